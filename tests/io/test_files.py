"""System files (symkf.io.files): TOML decimals read exactly as written, and files that cannot be
read (unreadable, a FIFO, a directory, a device) refused in one line with exit status 2.
(Broken files: tests/io/test_file_fuzzing.py; network and fusion files:
tests/io/test_network_and_fusion_files.py.)"""

from __future__ import annotations

import os
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

import symkf as sk
from symkf import cli
from symkf.exact.numbers import to_exact
from symkf.io import files

from conftest import ROOT, limited, run

R = sp.Rational


def test_toml_decimal_is_exact(tmp_path):
    """tomllib reads 0.1 with parse_float=Decimal: exactly 1/10, no float in between."""
    path = tmp_path / "s.toml"
    path.write_text('[system]\nA = [[0, -2], [2, 0]]\n[[sensors]]\nC = [[1, 0]]\n[loss]\nkind = "iid"\nloss = [0.1]\n')
    system, loss = files.load(path)
    assert loss.loss == (R(1, 10),)
    assert to_exact(Decimal("0.1"), "x") == R(1, 10) and to_exact(Fraction(1, 10), "x") == R(1, 10)


def test_toml_decimals_are_exact_without_rationalize(tmp_path):
    """docs/formats.md said a TOML float is refused without rationalize = true; it is read
    exactly as written (the docs now say so)."""
    path = tmp_path / "dec.toml"
    path.write_text('[system]\nA = [[0.1, -2], [2, 1e-3]]\n[[sensors]]\nC = [[1, 0]]\n')
    system, _ = files.load(path)
    assert system.A[0, 0] == sk.exact.numbers.parse_exact("1/10", "x") and system.A[1, 1] * 1000 == 1
    text = (ROOT / "docs" / "formats.md").read_text()
    assert "is refused with an error naming the entry" not in text and "read exactly as written" in text


@pytest.mark.parametrize("kind", ["fifo", "directory", "device"])
def test_non_regular_input_files_refused(tmp_path, kind):
    """A FIFO with no writer used to block forever; a directory or device is refused the same way."""
    path = {"directory": tmp_path, "device": "/dev/zero"}.get(kind, tmp_path / "fifo")
    if kind == "fifo":
        os.mkfifo(path)
    what = {"fifo": "is a FIFO", "directory": "is a directory", "device": "is a device"}[kind]
    for command in ("analyze", "critical"):
        code, err = limited(cli.main, [command, str(path)])
        assert code == 2 and err.count("\n") == 1 and f"{path}: {what}" in err, err


@pytest.fixture
def family(tmp_path):
    """A small family (two members, a fraction of a second); its LaTeX table is about 1 kB."""
    path = tmp_path / "fam.toml"
    path.write_text('[family]\n[grid]\na = ["2", "3"]\n[system]\nA = [["a", "0"], ["0", "a/2"]]\n'
                    '[[sensors]]\nC = [["1", "1"]]\n')
    return path


@pytest.mark.parametrize("command", ["table", "analyze", "verify"])
def test_unreadable_input_is_exit_2(capsys, monkeypatch, family, command):
    """An unreadable file (PermissionError; simulated, the tests may run as root) was exit 70 in
    ``table``: every reader goes through files.read_toml."""
    real_open = Path.open

    def deny(self, *args, **kwargs):
        if self == family:
            raise PermissionError(13, "Permission denied")
        return real_open(self, *args, **kwargs)
    monkeypatch.setattr(Path, "open", deny)
    status, out, err = run(capsys, command, family)
    assert status == 2 and out == "" and "cannot read (Permission denied)" in err and err.count("\n") == 1


def test_a_family_file_given_where_a_system_file_is_read_points_to_symkf_table(tmp_path):
    from symkf import examples
    from symkf.io import files
    family = examples.family("rotation-periods")
    with pytest.raises(sk.SymkfError, match="a family file .*`symkf table` and `symkf verify` read it"):
        files.load(family)
