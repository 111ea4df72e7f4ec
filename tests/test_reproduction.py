"""Reproduce reports (symkf.reproduction) say exactly what was checked: ``checks`` all hold,
``discrepancies`` give the paper's printed value beside the computed one."""

from __future__ import annotations

import importlib
import json
import time

import pytest
import sympy as sp

from symkf.exact.numbers import sympify as exact
import symkf as sk
from symkf import cli
from symkf.reproduction import discrepancy, reproduction


def reproduce_json(capsys, name: str) -> dict:
    status = cli.main(["reproduce", name, "--quick", "--json"])
    out, err = capsys.readouterr()
    assert status == 0, err
    return json.loads(out)


def test_report_shape() -> None:
    rep = reproduction("x", "seed", {"r": 1}, {"a claim": sp.true},
                       [discrepancy("eq. (1)", "0.5 x 1.00042", sp.Rational(1, 2), "misprint")])
    assert rep["checks"] == {"a claim": True} and type(rep["checks"]["a claim"]) is bool
    assert rep["discrepancies"] == [{"claim": "eq. (1)", "printed": "0.5 x 1.00042", "computed": "1/2",
                                     "note": "misprint"}]


def test_sui_theorem12_refutation_is_a_list_of_discrepancies(capsys) -> None:
    doc = reproduce_json(capsys, "sui-theorem12")
    assert doc["schema_version"] == cli.SCHEMA_VERSION
    assert doc["checks"] and all(v is True for v in doc["checks"].values())
    by_claim = {d["claim"]: d for d in doc["discrepancies"]}
    assert len(by_claim) == 15  # four counterexamples and 2R(pi/g), g = 2..12
    # g = 3: printed 2^(-4g/(2g-1)) = 2^(-12/5), corrected and exact 2^(-2g/(g-1)) = 1/8
    d = next(d for claim, d in by_claim.items() if claim.endswith("g = 3, tau = 6"))
    assert exact(d["printed"]) == 2 ** sp.Rational(-12, 5) and d["computed"] == "1/8"


def test_a_report_with_nothing_to_dispute(capsys) -> None:
    doc = reproduce_json(capsys, "quevedo-example3")
    assert all(doc["checks"].values()) and doc["discrepancies"] == []


@pytest.mark.parametrize("module, name", [
    ("symkf.network.reproduce", "reproduce_quevedo_semi_markov"), ("symkf.network.reproduce", "reproduce_quevedo_robot"),
    ("symkf.network.reproduce", "reproduce_quevedo_example3"), ("symkf.engine.second_order", "reproduce_sui_theorem12"),
    ("symkf.capacity.example1", "reproduce_yang_example1"), ("symkf.fusion.pendulum", "reproduce_fusion_pendulum"),
    ("symkf.control.reproduce", "reproduce_schenato_claims")])
def test_a_reproduction_refuses_its_output_directory_before_the_work(module, name, tmp_path):
    fn = getattr(importlib.import_module(module), name)
    afile = tmp_path / "a-file"
    afile.write_text("x")
    for bad in ("", afile, "\0"):
        start = time.process_time()
        with pytest.raises(sk.errors.SymkfError, match="outdir"):
            fn(outdir=bad)
        assert time.process_time() - start < 0.5
