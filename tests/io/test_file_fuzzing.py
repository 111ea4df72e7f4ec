"""Fuzzing the file reader and the CLI: broken input gives exit status 2 and one line, never a traceback.

Every broken file in ``tests/corpus/bad`` starts with ``# expect: TEXT``; the
message must name the file and contain TEXT (the key at fault).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from symkf.io import files
from symkf.errors import FileFormatError, SymkfError
from conftest import ROOT, run

CORPUS = sorted((ROOT / "tests" / "corpus" / "bad").glob("*.toml"))
FUZZ = settings(max_examples=40, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def expected(path: Path) -> str:
    return re.match(r"# expect: (.*)", path.read_text(encoding="utf-8", errors="replace")).group(1)


def assert_bad(status: int, out: str, err: str, path: Path) -> None:
    assert status == 2, err
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("symkf ") and "Traceback" not in err
    assert str(path) in err


# ------------------------------------------------------------------ the corpus

def test_corpus_is_substantial():
    assert len(CORPUS) >= 25


@pytest.mark.parametrize("path", CORPUS, ids=[p.stem for p in CORPUS])
def test_corpus(capsys, path):
    # every file through analyze, and through one of the other commands in turn
    other = ["critical", "verify", "simulate"][CORPUS.index(path) % 3]
    for argv in (["analyze"], [other] + (["--horizon", "5", "--paths", "10"] if other == "simulate" else [])):
        status, out, err = run(capsys, argv[0], path, *argv[1:])
        assert_bad(status, out, err, path)
        assert expected(path) in err


@pytest.mark.parametrize("path", CORPUS[:4], ids=[p.stem for p in CORPUS[:4]])
def test_corpus_subprocess_no_traceback(path):
    proc = subprocess.run([sys.executable, "-m", "symkf", "critical", str(path), "--json"],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert json.loads(proc.stdout)["error"]["exit_status"] == 2     # --json: the error as JSON too
    assert_bad(proc.returncode, "", proc.stderr, path)


def test_subprocess_bad_usage_no_traceback():
    proc = subprocess.run([sys.executable, "-m", "symkf", "simulate", "x.toml", "--horizon", "-3"],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 2 and proc.stdout == "" and proc.stderr.count("\n") == 1


def test_unreadable_paths(capsys, tmp_path):
    status, out, err = run(capsys, "analyze", tmp_path)                   # a directory
    assert_bad(status, out, err, tmp_path)
    missing = tmp_path / "missing.toml"
    status, out, err = run(capsys, "analyze", missing)
    assert_bad(status, out, err, missing)
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe\x00[system]")
    status, out, err = run(capsys, "analyze", binary)
    assert_bad(status, out, err, binary)


# ------------------------------------------------------------------ generated files

def toml_value(v) -> str:
    """A tiny TOML writer for the values generated here (strings, ints, floats, bools, lists)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float):
        return {float("inf"): "inf", float("-inf"): "-inf"}.get(v, "nan" if v != v else repr(v))
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return str(v)


def toml_text(doc: dict) -> str:
    lines = [f"{k} = {toml_value(v)}" for k, v in doc.items() if not isinstance(v, (dict, list)) or
             (isinstance(v, list) and not (v and all(isinstance(x, dict) for x in v)))]
    for k, v in doc.items():
        if isinstance(v, dict):
            lines.append(f"[{k}]")
            lines += [f"{kk} = {toml_value(vv)}" for kk, vv in v.items()]
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for item in v:
                lines.append(f"[[{k}]]")
                lines += [f"{kk} = {toml_value(vv)}" for kk, vv in item.items()]
    return "\n".join(lines) + "\n"


def valid_doc() -> dict:
    return {"system": {"A": [["0", "-2"], ["2", "0"]]},
            "sensors": [{"name": "s1", "C": [["1", "0"]]}, {"name": "s2", "C": [["1", "1"]]}],
            "loss": {"kind": "iid", "loss": ["1/20", "1/10"]}}


#: entries that are never an exact number: non-finite floats (TOML decimals are exact), symbols,
#: junk, huge powers, transcendental numbers, bools, nested lists, empty strings, code
BAD_NUMBERS = st.one_of(
    st.sampled_from([float("inf"), float("-inf"), float("nan")]), st.sampled_from(["x", "eps", "a*b", "lambda"]),
    st.sampled_from(["9^9^9", "2^(10^6)", "(1/3)^-99999", "10^5000", "exp(1)", "pi", "1/0", "0^-1",
                     "cos(1)", "5/", "1.5.2", "0x10", "1e9999", "__import__('os')", "", "   ", "sqrt(",
                     "2**2**2**2**2"]),
    st.booleans(), st.lists(st.integers(), max_size=2), st.integers(min_value=10 ** 1200, max_value=10 ** 1300))

#: loss values that are never a probability
BAD_PROBABILITIES = st.one_of(BAD_NUMBERS, st.integers(min_value=2, max_value=10 ** 30),
                              st.integers(max_value=-1), st.sampled_from(["-1/10", "11/10", "sqrt(2)", "I"]))


def mutate(doc: dict, data: st.DataObject) -> dict:
    """Break one thing in a valid document."""
    kind = data.draw(st.sampled_from(
        ["A-entry", "C-entry", "R-entry", "Q-entry", "loss-entry", "A-shape", "C-shape", "R-shape",
         "no-sensors", "loss-kind", "loss-length", "missing", "unknown-key", "table-type", "names"]))
    system, sensors, loss = doc["system"], doc["sensors"], doc["loss"]
    i, j = data.draw(st.integers(0, 1)), data.draw(st.integers(0, 1))
    if kind == "A-entry":
        system["A"][i][j] = data.draw(BAD_NUMBERS)
    elif kind == "C-entry":
        sensors[i]["C"][0][j] = data.draw(BAD_NUMBERS)
    elif kind == "R-entry":
        sensors[i]["R"] = [[data.draw(st.one_of(BAD_NUMBERS, st.sampled_from(["0", "-1", "-5/2"]),
                                                st.integers(max_value=0)))]]
    elif kind == "Q-entry":
        # (a zero is no break: Q = diag(1, 0) is singular, but (A, Q^(1/2)) stays controllable under the rotation)
        system["Q"] = [["1", "0"], ["0", data.draw(st.one_of(BAD_NUMBERS, st.sampled_from(["-1", "-1/3"])))]]
    elif kind == "loss-entry":
        loss["loss"][i] = data.draw(BAD_PROBABILITIES)
    elif kind == "A-shape":
        system["A"] = data.draw(st.sampled_from([[["1", "0"]], [["1"]], [["1", "0"], ["1"]], [], [[]], "2",
                                                 [["1", "0", "0"]] * 3, [[["1"]]]]))
    elif kind == "C-shape":
        sensors[i]["C"] = data.draw(st.sampled_from([[["1"]], [["1", "0", "0"]], [], "1", [[]], [["1", "0"], ["1"]]]))
    elif kind == "R-shape":
        sensors[i]["R"] = data.draw(st.sampled_from([[["1", "0"], ["0", "1"]], [], [["1"], ["1"]], "1"]))
    elif kind == "no-sensors":
        doc["sensors"] = data.draw(st.sampled_from([[], [1], "s1", [[]]]))
    elif kind == "loss-kind":
        loss["kind"] = data.draw(st.one_of(st.sampled_from(["markov", "IID", "", "gilbert"]), st.integers()))
    elif kind == "loss-length":
        # (one number, "1/2" or 0, is every sensor's: a common rate, not a broken file)
        loss["loss"] = data.draw(st.sampled_from([[], ["1/2"], ["1/2"] * 3, {"p": "1/2"}]))
    elif kind == "missing":
        where, key = data.draw(st.sampled_from([(doc, "system"), (doc, "sensors"), (system, "A"),
                                                (sensors[i], "C"), (loss, "loss")]))
        del where[key]
    elif kind == "unknown-key":
        target = data.draw(st.sampled_from([doc, system, sensors[i], loss]))
        target[data.draw(st.sampled_from(["B", "P_0", "q", "losses", "network"]))] = "1"
    elif kind == "table-type":
        doc[data.draw(st.sampled_from(["system", "loss"]))] = data.draw(st.sampled_from(["x", 3, [1, 2]]))
    elif kind == "names":
        sensors[1]["name"] = data.draw(st.sampled_from(["s1", 5, "", True]))
    return doc


@FUZZ
@given(data=st.data(), command=st.sampled_from(["analyze", "critical", "verify"]))
def test_broken_files(capsys, tmp_path_factory, data, command):
    doc = mutate(valid_doc(), data)
    path = tmp_path_factory.mktemp("fuzz") / "broken.toml"
    path.write_text(toml_text(doc), encoding="utf-8")
    status, out, err = run(capsys, command, path, "--paths", "10", "--horizon", "8") if command == "verify" \
        else run(capsys, command, path)
    assert_bad(status, out, err, path)
    with pytest.raises(SymkfError):
        files.load(path)


@FUZZ
@given(text=st.one_of(st.text(max_size=200),
                      st.lists(st.sampled_from(["[system]", "[[sensors]]", "[loss]", "A = [[\"2\"]]", "C = [[1]]",
                                                "loss = [\"1/2\"]", "kind = \"iid\"", "R = [[0]]", "A = 2",
                                                "rationalize = true", "A = [[2.5]]", "x = ", "[[sensors]", "]]"]),
                               max_size=8).map("\n".join)))
def test_malformed_toml(capsys, tmp_path_factory, text):
    path = tmp_path_factory.mktemp("fuzz") / "malformed.toml"
    path.write_text(text, encoding="utf-8")
    try:
        system, _ = files.load(path)
    except FileFormatError:
        pass
    except SymkfError as exc:
        assert str(path) in str(exc)
    else:   # the fragments can make a valid file; then the command must succeed
        assert system.n == 1
    status, out, err = run(capsys, "analyze", path)
    if status != 0:
        assert_bad(status, out, err, path)


# ------------------------------------------------------------------ never a wrong answer

@FUZZ
@given(a=st.fractions(min_value=-5, max_value=5, max_denominator=7).filter(lambda x: x != 0),
       b=st.fractions(min_value=-5, max_value=5, max_denominator=7).filter(lambda x: x != 0),
       c=st.integers(-3, 3), rationalize=st.booleans())
def test_valid_files_give_the_hand_derived_value(capsys, tmp_path_factory, a, b, c, rationalize):
    # one sensor measuring the whole state (C = I): eps_c = 1 / rho(A)^2, capped at 1
    path = tmp_path_factory.mktemp("fuzz") / "valid.toml"
    entry = (lambda x: float(x) if x.denominator in (1, 2, 4) else f"{x}") if rationalize else str
    path.write_text(toml_text({"rationalize": rationalize,
                               "system": {"A": [[entry(a), c], [0, entry(b)]]},
                               "sensors": [{"C": [[1, 0], [0, 1]]}]}), encoding="utf-8")
    status, out, err = run(capsys, "critical", path, "--json", "--digits", "6")
    # a == b, c != 0 is a Jordan block, decided too: C = I sees the state at any
    # single reception, so rho = eps and the margin is a^2 eps either way
    assert status == 0, err
    rho = max(abs(sp.Rational(a.numerator, a.denominator)), abs(sp.Rational(b.numerator, b.denominator)))
    assert sp.Rational(json.loads(out)["critical_loss_rate"]["exact"]) == min(1 / rho ** 2, 1)
