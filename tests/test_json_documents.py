"""One name per concept in code and JSON (issue 15, item 3): tau and governing_period, schema_version,
losses as structured objects."""

from __future__ import annotations

import json
from typing import Any

import pytest

import symkf as sk
from symkf import cli, examples
from symkf.exact.spectral import eigen_blocks

SYSTEMS = examples.directory() / "systems"
DESIGN = SYSTEMS / "design-rotation.toml"       # A = 2 R(pi/2), C = [1 0], i.i.d. loss 1/20
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


def test_eigen_block_tau_and_governing_period() -> None:
    # A = 2 R(pi/2): eigenvalues +-2i, lambda/|lambda| = i has order 4 (tau = 4); A^2 = -4 I (g = 2)
    [block] = eigen_blocks(sk.System([[0, -2], [2, 0]], [sk.Sensor([[1, 0]])]).A)
    assert (block.tau, block.period, block.governing_period) == (4, 4, 2)
    assert "tau=4, governing_period=2" in repr(block)


def test_analyze_json_has_one_name_per_period(capsys) -> None:
    """The issue's report: blocks[0].period = 4 next to certificate[0].period = 2."""
    doc = json_of(capsys, "analyze", DESIGN)
    assert doc["schema_version"] == cli.SCHEMA_VERSION == 1
    assert "period" not in keys(doc)
    assert (doc["blocks"][0]["tau"], doc["blocks"][0]["governing_period"]) == (4, 2)
    assert doc["verdict"]["certificate"][0]["class_period"] == 2  # one class: the governing period
    assert doc["loss"] == {"kind": "iid", "loss": ["1/20"]}


def test_certificate_and_verdict_text_use_the_class_period() -> None:
    S = sk.System([[0, -2], [2, 0]], [sk.Sensor([[1, 0]])])
    v = sk.stability(S, sk.IID(["1/20"]))
    assert v.certificate[0].class_period == 2 and not hasattr(v.certificate[0], "period")
    assert "class period g = 2" in str(v) and "alpha^4 * rho^2" in str(v)


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


@pytest.mark.parametrize("argv", [("demo",), ("critical", DESIGN), ("reproduce", "--list")])
def test_every_document_carries_schema_version(capsys, argv) -> None:
    doc = json_of(capsys, *argv)
    assert doc["schema_version"] == cli.SCHEMA_VERSION
    assert "period" not in keys(doc)
