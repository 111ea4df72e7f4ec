"""Issue 26, sections 5 and 7: bad input is exit 2 with one line naming the file and the key
(never exit 70), and reports name what they compute (the class period is not the governing
period)."""

from __future__ import annotations

import json

import pytest

import symkf as sk
from symkf import budget, cli, examples
from symkf.io import files
from symkf.errors import FileFormatError, InputError
from conftest import ROOT

GE = examples.system("ge-two-sensors")
FAMILY = examples.family("rotation-periods")
ROTATION = '[system]\nA = [["0", "-2"], ["2", "0"]]\n[[sensors]]\nname = "s1"\nC = [["1", "0"]]\n'


def run(capsys, *argv) -> tuple[int, str, str]:
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def one_line(err: str) -> str:
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


# -- section 5: exit 70 left --------------------------------------------------------------

def test_huge_rational_loss_is_exit_2_naming_file_and_key(capsys, tmp_path):
    """(1 - 1/10^6)^10000 has 60 001 digits: Python refused to print it (ValueError, exit 70).
    Now its height (10000 times the base's 20 bits) is estimated before it is evaluated and
    refused under max_bits."""
    path = tmp_path / "s.toml"
    path.write_text(ROTATION + '[loss]\nkind = "iid"\nloss = ["(1-1/10**6)**10000"]\n')
    status, out, err = run(capsys, "analyze", path)
    assert status == 2 and out == ""
    assert f"{path}: [loss] loss[0]" in one_line(err) and "above the cap 768" in err and "--max-bits" in err


def test_digits_beyond_python_are_a_usage_error(capsys, tmp_path):
    """--max-digits 10^15 made Python's int-to-text limit overflow a C int (OverflowError, exit 70)."""
    path = tmp_path / "s.toml"
    path.write_text(ROTATION)
    status, _, err = run(capsys, "critical", path, "--digits", "1000000000", "--max-digits", "1000000000000000")
    assert status == 2 and "--max-digits" in one_line(err) and str(budget.MAX_DIGITS_CAP) in err
    with pytest.raises(InputError, match="max_digits: 1000000000000000 is above"):
        with budget.limits(max_digits=10 ** 15):
            pass
    with pytest.raises(InputError, match="unknown cap"):
        with budget.limits(max_degre=3):
            pass


def test_too_long_output_name_is_exit_2(capsys, tmp_path):
    """A 300-character file name: OSError (File name too long) in output.plan was exit 70."""
    target = tmp_path / ("a" * 300 + ".tex")
    status, out, err = run(capsys, "table", FAMILY, "--latex", target)
    assert status == 2 and out == ""
    assert "--latex" in one_line(err) and "above the file system's limit" in err


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


# -- section 7: reports that say what they compute --------------------------------------------

#: an aperiodic block: eigenvalues (6 +- 8i)/5 = 2 e^(+-i t), cos t = 3/5, t not a rational multiple of pi
APERIODIC = [["6/5", "-8/5"], ["8/5", "6/5"]]


def test_aperiodic_block_reports_its_class_period_not_a_governing_period(capsys, tmp_path):
    """The ratio of the eigenvalues e^(2it) is not a root of unity: two classes of one eigenvalue
    each, so the rows are grouped over the class period 1 while the governing period is None.
    The certificate and the verdict said "g = 1" under the name governing period."""
    S = sk.System(A=APERIODIC, sensors=[sk.Sensor(C=[[1, 0]])])
    block = sk.eigen_blocks(S.A)[0]
    assert block.governing_period is None and block.period is None and block.class_period == 1
    v = sk.stability(S, sk.IID(["1/10"]))
    assert v.certificate[0].class_period == 1 and not hasattr(v.certificate[0], "governing_period")
    assert "class period g = 1" in str(v) and "governing" not in str(v)
    path = tmp_path / "aperiodic.toml"
    path.write_text('[system]\nA = [["6/5", "-8/5"], ["8/5", "6/5"]]\n[[sensors]]\nC = [["1", "0"]]\n'
                    '[loss]\nkind = "iid"\nloss = ["1/10"]\n')
    status, out, _ = run(capsys, "analyze", path, "--json")
    doc = json.loads(out)
    assert status == 0 and doc["blocks"][0]["governing_period"] is None
    assert doc["verdict"]["certificate"][0]["class_period"] == 1
    assert "governing_period" not in doc["verdict"]["certificate"][0]
    status, out, _ = run(capsys, "analyze", path)
    assert "governing period = None" in out and "class period g = 1" in out


def test_periodic_block_class_period_is_its_governing_period():
    """2R(pi/2): A^2 = -4I, governing period 2 = class period (one class)."""
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    assert sk.eigen_blocks(S.A)[0].governing_period == 2
    assert sk.stability(S, sk.IID(["1/20"])).certificate[0].class_period == 2


def test_loss_table_without_kind_is_refused(capsys, tmp_path):
    """docs/formats.md says kind is required; it was read as iid."""
    path = tmp_path / "nokind.toml"
    path.write_text(ROTATION + '[loss]\nloss = ["1/10"]\n')
    with pytest.raises(FileFormatError, match=r"\[loss\]: key 'kind' missing"):
        files.load(path)
    status, _, err = run(capsys, "analyze", path)
    assert status == 2 and f"{path}: [loss]: key 'kind' missing" in one_line(err)


def test_toml_decimals_are_exact_without_rationalize(tmp_path):
    """docs/formats.md said a TOML float is refused without rationalize = true; it is read
    exactly as written (the docs now say so)."""
    path = tmp_path / "dec.toml"
    path.write_text('[system]\nA = [[0.1, -2], [2, 1e-3]]\n[[sensors]]\nC = [[1, 0]]\n')
    system, _ = files.load(path)
    assert system.A[0, 0] == sk.exact.numbers.parse_exact("1/10", "x") and system.A[1, 1] * 1000 == 1
    text = (ROOT / "docs" / "formats.md").read_text()
    assert "is refused with an error naming the entry" not in text and "read exactly as written" in text
