"""The JSON documents of the command line: one name per concept (tau, governing_period and
class_period, never a bare "period"), schema_version in every document, losses as structured
objects, and errors as JSON on stdout too."""

from __future__ import annotations

import json
from typing import Any

import pytest

from conftest import run
from symkf import cli, examples

SYSTEMS = examples.directory() / "systems"
QUARTER_TURN = SYSTEMS / "design-rotation.toml"       # A = 2 R(pi/2), C = [1 0], i.i.d. loss 1/20
GE = SYSTEMS / "ge-two-sensors.toml"
MARKOV = SYSTEMS / "network" / "markov-shared-channel.toml"


def json_of(capsys, *argv: Any) -> dict:
    status = cli.main([str(a) for a in argv] + ["--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    return json.loads(out)


def keys(doc: Any) -> set[str]:
    """Every key of every object in a JSON document."""
    if isinstance(doc, dict):
        return set(doc) | {k for v in doc.values() for k in keys(v)}
    if isinstance(doc, list):
        return {k for v in doc for k in keys(v)}
    return set()


def test_analyze_json_has_one_name_per_period(capsys) -> None:
    """One name per period: the document once had blocks[0].period = 4 (tau) next to
    certificate[0].period = 2 (the class period)."""
    doc = json_of(capsys, "analyze", QUARTER_TURN)
    assert doc["schema_version"] == cli.SCHEMA_VERSION == 1
    assert "period" not in keys(doc)
    assert (doc["blocks"][0]["tau"], doc["blocks"][0]["governing_period"]) == (4, 2)
    assert doc["verdict"]["certificate"][0]["class_period"] == 2  # one class: the governing period
    assert doc["loss"] == {"kind": "iid", "loss": ["1/20"]}


def test_losses_are_structured_objects(capsys) -> None:
    ge = json_of(capsys, "analyze", GE)["loss"]
    assert ge == {"kind": "gilbert-elliott", "fail": ["1/4", "1/4"], "recover": ["1/2", "1/2"]}
    markov = json_of(capsys, "analyze", MARKOV)["loss"]
    assert markov["kind"] == "markov" and markov["order"] == 1
    chain = markov["chain"]
    n = len(chain["states"])
    assert len(chain["P"]) == n and all(len(row) == n for row in chain["P"]) and len(chain["initial"]) == n
    assert all(isinstance(p, str) for row in chain["P"] for p in row)  # exact strings, not floats
    assert all(len(v) == 2 for v in chain["emit"])


@pytest.mark.parametrize("argv", [("demo",), ("critical", QUARTER_TURN), ("reproduce", "--list"),
                                  ("analyze", SYSTEMS / "lqg-two-modes.toml"), ("critical", SYSTEMS / "lqg-two-modes.toml")])
def test_every_document_carries_schema_version(capsys, argv) -> None:
    doc = json_of(capsys, *argv)
    assert doc["schema_version"] == cli.SCHEMA_VERSION
    assert "period" not in keys(doc)


def test_json_errors_go_to_stdout_too(capsys, tmp_path):
    status, out, err = run(capsys, "analyze", tmp_path / "missing.toml", "--json")
    doc = json.loads(out)
    assert status == 2 and doc["error"]["type"] == "UsageError" and doc["error"]["exit_status"] == 2
    assert doc["schema_version"] == cli.SCHEMA_VERSION and err.count("\n") == 1
    unseen = tmp_path / "unseen.toml"   # the mode 3 is unstable and no sensor sees it
    unseen.write_text('[system]\nA = [["2", "0"], ["0", "3"]]\n[[sensors]]\nC = [["1", "0"]]\n'
                      '[loss]\nkind = "iid"\nloss = ["1/10"]\n')
    status, out, _ = run(capsys, "analyze", unseen, "--json")
    assert status == 3 and json.loads(out)["error"]["exit_status"] == 3
    status, out, err = run(capsys, "simulate", unseen, "--paths", "5", "--json")    # no --horizon
    assert status == 2 and json.loads(out)["error"]["message"] == err.strip() and "--horizon" in err
