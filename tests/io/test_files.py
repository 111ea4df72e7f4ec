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

from conftest import ROOT, limited, one_line, refused_at_once, run

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


def _markov_file(path: Path, d: int) -> Path:
    """A system file of ``d`` scalar sensors and the joint chain on all ``2^d`` receival vectors,
    the probabilities of a row distinct (``k / (1 + 2 + ... + 2^d)``, k = 1..2^d)."""
    states = [[int(c) for c in format(k, f"0{d}b")] for k in range(2 ** d)]
    total = 2 ** d * (2 ** d + 1) // 2
    row = ", ".join(f'"{k}/{total}"' for k in range(1, 2 ** d + 1))
    path.write_text('[system]\nA = [["2"]]\n' + '[[sensors]]\nC = [["1"]]\n' * d +
                    f'[loss]\nkind = "markov"\nstates = {states}\nP = [\n' + ",\n".join([f"[{row}]"] * 2 ** d) + "]\n")
    return path


def test_a_joint_chain_too_large_is_refused_from_its_shape_in_a_second(tmp_path):
    # 8 sensors: 256 states, 65,536 probabilities (a 620 KB file) were all read, 44.7 s, before
    # max_markov_states refused the chain (timed from the read TOML: the reading is the file's size)
    path = _markov_file(tmp_path / "m8.toml", 8)
    assert path.stat().st_size > 500_000
    data = files.read_toml(path)
    code, err = limited(refused_at_once, lambda: files.parse(data, str(path)), "max_markov_states")
    assert code == 0 and f"{path}: [loss] key 'states'" in err and "is 256, above the cap 128" in err, err
    code, err = limited(cli.main, ["analyze", str(path)])
    assert code == 2 and "--max-markov-states" in one_line(err)


@pytest.mark.parametrize("table, cap", [
    ('[fusion]\nA = [["1"]]\nQ = [["1"]]\narrival = [' + '"1/2", ' * 100_000 + ']\n', "max_sensors"),
    ('[fusion]\nA = [' + '["1"], ' * 100_000 + ']\nQ = [["1"]]\narrival = ["1/2"]\n', "max_dimension"),
], ids=["arrival", "A"])
def test_fusion_lists_too_long_are_refused_before_a_number_is_read(tmp_path, table, cap):
    path = tmp_path / "f.toml"
    path.write_text(table + '[[sensors]]\nC = [["1"]]\n')
    data = files.read_toml(path)
    code, err = limited(refused_at_once, lambda: files.parse_fusion(data, str(path)), cap)
    assert code == 0, err


def test_a_design_rate_is_one_number(tmp_path):
    path = tmp_path / "d.toml"
    path.write_text('[system]\nA = [["2"]]\n[[sensors]]\nC = [["1"]]\n[design]\ncritical_rate = ["1/2", "1/3"]\n')
    with pytest.raises(sk.errors.FileFormatError, match=r"d.toml: \[design\] critical_rate: expected a number, got a list"):
        files.load_design(path)


def test_too_many_sensors_are_counted_before_one_is_read(tmp_path):
    # each sensor's C was converted before the system counted them: 40,000 in a 1 MB file, 12 s
    path = tmp_path / "many.toml"
    path.write_text('[system]\nA = [["2"]]\n' + '[[sensors]]\nC = [["1/3"]]\n' * 40_000)
    data = files.read_toml(path)
    code, err = limited(refused_at_once, lambda: files.parse(data, str(path)), "max_sensors")
    assert code == 0 and f"{path}: [[sensors]]: the number of sensors is 40000, above the cap 64" in err, err
