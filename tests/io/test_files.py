"""System files (symkf.io.files): TOML decimals read exactly as written, the control loop's tables
([[actuators]], W, [actuator_loss]) read and written back, and files that cannot be read
(unreadable, a FIFO, a directory, a device) refused in one line with exit status 2.
(Broken files: tests/io/test_file_fuzzing.py; network and fusion files:
tests/io/test_network_and_fusion_files.py.)"""

from __future__ import annotations

import json
import os
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

import symkf as sk
from symkf import budget, cli, examples
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
    # 9 sensors: 512 states, 262,144 probabilities (a 2.9 MB file; at 8 sensors, 65,536 were all read,
    # 44.7 s, before max_markov_states refused the chain): timed from the read TOML, the reading is
    # the file's size
    path = _markov_file(tmp_path / "m9.toml", 9)
    assert path.stat().st_size > 2_000_000
    with budget.limits(max_file_size=2 ** 22):
        data = files.read_toml(path)
    code, err = limited(refused_at_once, lambda: files.parse(data, str(path)), "max_markov_states")
    assert code == 0 and f"{path}: [loss] key 'states'" in err and "is 512, above the cap 256" in err, err
    code, err = limited(cli.main, ["analyze", str(path), "--max-file-size", str(2 ** 22)])
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


@pytest.mark.parametrize("key, table, count", [("sensors", 'C = [["1/3"]]', 40_000), ("actuators", 'B = [["1/3"]]', 30_000)])
def test_too_many_sensors_or_actuators_are_counted_before_one_is_read(tmp_path, key, table, count):
    # each sensor's C was converted before the system counted them: 40,000 in a 1 MB file, 12 s;
    # actuators count against the same cap
    path = tmp_path / "many.toml"
    first = "" if key == "sensors" else '[[sensors]]\nC = [["1"]]\n'
    path.write_text('[system]\nA = [["2"]]\n' + first + f"[[{key}]]\n{table}\n" * count)
    data = files.read_toml(path)
    code, err = limited(refused_at_once, lambda: files.parse(data, str(path)), "max_sensors")
    assert code == 0 and f"{path}: [[{key}]]: the number of {key} is {count}, above the cap 16384" in err, err


# -- the control loop: [[actuators]], W and [actuator_loss] -----------------------------------------

def _toml(doc: dict) -> str:
    """A system document (System.to_dict) as TOML: its strings and lists of them are JSON's."""
    lines = ["[system]", *(f"{k} = {json.dumps(v)}" for k, v in doc["system"].items())]
    for key in ("sensors", "actuators"):
        for table in doc.get(key, []):
            lines += [f"[[{key}]]", *(f"{k} = {json.dumps(v)}" for k, v in table.items())]
    return "\n".join(lines) + "\n"


def test_load_loop_reads_the_system_and_both_loss_models():
    system, loss, actuator_loss = files.load_loop(examples.system("lqg-two-modes"))
    assert system.actuator_names == ("u",) and system.B == sp.Matrix([[0], [1]]) and system.U == sp.eye(1)
    assert system.W == sp.eye(2) and system.stabilizable and system.controllable
    assert loss.loss == (R(1, 5),) and actuator_loss.loss == (R(1, 10),)
    read, sensor_loss = files.load(examples.system("lqg-two-modes"))        # load: the sensors' loss only
    assert read == system and sensor_loss.loss == loss.loss
    assert files.load_loop(examples.system("ge-two-sensors"))[2] is None


def test_a_file_with_actuators_reads_back_from_its_written_dict(tmp_path):
    text = """[system]
A = [["5/4", "1"], ["0", "11/10"]]
W = [["2", "0"], ["0", "0"]]
name = "loop"
[[sensors]]
name = "y"
C = [["1", "0"]]
[[actuators]]
B = [["0"], ["1"]]
U = [["1/2"]]
[[actuators]]
name = "pair"
B = [["1", "0"], ["0", "sqrt(2)"]]
"""
    (tmp_path / "a.toml").write_text(text)
    system, _ = files.load(tmp_path / "a.toml")
    assert system.actuator_names == ("a1", "pair") and system.W == sp.diag(2, 0)
    assert system.U == sp.diag(R(1, 2), 1, 1) and system.B[1, 2] == sp.sqrt(2)
    (tmp_path / "b.toml").write_text(_toml(system.to_dict()))
    again, _ = files.load(tmp_path / "b.toml")
    assert again == system
    shipped, _ = files.load(examples.system("lqg-two-modes"))
    (tmp_path / "lqg-two-modes.toml").write_text(_toml(shipped.to_dict()))
    assert files.load(tmp_path / "lqg-two-modes.toml")[0] == shipped


@pytest.mark.parametrize("top, tail, message", [
    ("", '[[actuators]]\nC = [["1"]]\n', "x.toml: actuators[0]: unknown key 'C' (allowed: B, U, name)"),
    ("", '[[actuators]]\nU = [["1"]]\n', "x.toml: actuators[0]: missing key 'B'"),
    ("", '[[actuators]]\nB = [["1"], ["0"]]\n', "x.toml: actuators[0].B: has 2 rows, A is 1x1"),
    ("", '[[actuators]]\nname = "y"\nB = [["1"]]\n', "actuators: the name 'y' is also a sensor's"),
    ("", '[[actuators]]\nB = [["1"]]\nU = [["-1"]]\n', "x.toml: actuators[0]: actuator U: not positive definite"),
    ('actuators = "u"\n', "", "x.toml: [[actuators]] must list tables, one per actuator"),
    ("", '[actuator_loss]\nkind = "iid"\nloss = ["1/2"]\n',
     "x.toml: [actuator_loss] gives the losses of the actuators' channels, and the file has no [[actuators]]"),
    ("", '[[actuators]]\nB = [["1"]]\n[actuator_loss]\nkind = "iid"\nloss = ["1/2", "1/3"]\n',
     "x.toml: [actuator_loss] gives 2 value(s) for 1 actuator(s)"),
    ("", '[[actuators]]\nB = [["1"]]\n[actuator_loss]\nkind = "bursty"\n',
     "x.toml: [actuator_loss] kind 'bursty' is not one of"),
])
def test_a_bad_control_table_is_named_in_one_line(capsys, tmp_path, top, tail, message):
    path = tmp_path / "x.toml"
    path.write_text(top + '[system]\nA = [["2"]]\n[[sensors]]\nname = "y"\nC = [["1"]]\n' + tail)
    with pytest.raises(sk.errors.SymkfError) as info:
        files.load_loop(path)
    assert message in str(info.value), str(info.value)
    status, out, err = run(capsys, "analyze", str(path))
    assert status == 2 and out == "" and message in one_line(err)


def test_analyze_reads_a_file_with_actuators_as_an_estimation_problem(capsys):
    status, out, _ = run(capsys, "analyze", "lqg-two-modes", "--json")
    verdict = json.loads(out)["verdict"]
    # one sensor, loss 1/5: the limiting margin is (5/4)^2 * 1/5 = 5/16
    assert status == 0 and verdict["stable"] and verdict["margins"][0]["exact"] == "5/16"
