"""Errors (symkf.errors) and exit statuses: bad input is exit 2 with one line naming the file and
the key (never exit 70, an untranslated exception), a failed assumption is exit 3 naming the
assumption, and every error is a SymkfError."""

from __future__ import annotations

import pytest

from conftest import ROTATION, one_line, run
from symkf import examples
from symkf.errors import BudgetError, SymkfError

GE = examples.system("ge-two-sensors")


def test_huge_rational_loss_is_exit_2_naming_file_and_key(capsys, tmp_path):
    """(1 - 1/10^6)^10000 has 60 001 digits: Python refused to print it (ValueError, exit 70).
    Now its height (10000 times the base's 20 bits) is estimated before it is evaluated and
    refused under max_bits."""
    path = tmp_path / "s.toml"
    path.write_text(ROTATION + '[loss]\nkind = "iid"\nloss = ["(1-1/10**6)**10000"]\n')
    status, out, err = run(capsys, "analyze", path)
    assert status == 2 and out == ""
    assert f"{path}: [loss] loss[0]" in one_line(err) and "above the cap 768" in err and "--max-bits" in err


def test_number_field_failure_names_the_file_and_elides_digits(capsys, tmp_path):
    """A = [[1e400, -2], [2, 0]]: the refusal named no file and printed 2 900 digits.  Now its
    1329-bit height is refused before any field is built, naming the file, the entry and the cap,
    with the literal elided."""
    path = tmp_path / "big.toml"
    path.write_text(ROTATION.replace('"0", "-2"', '"1e400", "-2"'))
    status, _, err = run(capsys, "critical", path)
    assert status == 2 and one_line(err).startswith(f"symkf critical: {path}: ")
    assert f"{path}: A[0][0]" in err and "above the cap 768" in err and "0" * 40 not in err


@pytest.mark.parametrize("change, key, transition", [
    (('fail = ["1/4", "1/4"]', 'fail = ["0", "1/4"]'), "fail[0] = 0", "P(next lost | received) = 0"),
    (('recover = ["1/2", "1/2"]', 'recover = ["1/2", "1"]'), "recover[1] = 1", "P(next lost | lost) = 0"),
])
def test_gilbert_elliott_assumption2_names_file_and_key(capsys, tmp_path, change, key, transition):
    path = tmp_path / "ge.toml"
    path.write_text(GE.read_text().replace(*change))
    status, _, err = run(capsys, "analyze", path)
    assert status == 3
    assert one_line(err).startswith(f"symkf analyze: {path}: Assumption 2 (Sui-You-Fu) fails: {key}")
    assert transition in err


def test_symbol_errors_are_symkf_errors():
    assert issubclass(BudgetError, SymkfError)
