"""The examples of Quevedo et al. (symkf.network.reproduce): Example 3, the semi-Markov example
(exact part and simulation), the robot of Sec. VII and its critical growth, exact and by Theorem 2.
(The proofs in proofs/quevedo_*.py run in tests/test_proofs.py.)"""

from __future__ import annotations

import subprocess
import sys

import pytest
import sympy as sp

from symkf import stability
from symkf.io import files
from symkf.network import PeriodicDynamics, theorem2

from conftest import ROOT

R = sp.Rational


def test_reproduce_example3():
    from symkf.network.reproduce import reproduce_quevedo_example3
    out = reproduce_quevedo_example3()
    assert all(out["checks"].values()), out["checks"]
    assert out["results"]["configurations"][0] == [0, 1, 0, 1, 1] and len(out["results"]["configurations"]) == 9


def test_reproduce_semi_markov_exact_part():
    from symkf.network.reproduce import reproduce_quevedo_semi_markov
    out = reproduce_quevedo_semi_markov(simulate=False)
    assert all(out["checks"].values()), out["checks"]
    w = out["results"]["witness_q_half"]
    assert w["holds_as_printed"] is True and w["holds_corrected"] is False


@pytest.mark.full
def test_reproduce_robot_and_examples_scripts(tmp_path):
    from symkf.network.reproduce import reproduce_quevedo_robot
    out = reproduce_quevedo_robot(str(tmp_path))
    assert all(out["checks"].values()), out["checks"]
    # exact margins of the 21/20 and 1 blocks: Perron roots of the 560-state lifted chain restricted
    # to "S1 and S4 lost" and "S1, S3, S4 lost" (cross-checked against LAPACK in tests/exact/test_perron.py)
    exact = out["results"]["exact_verdict"]
    assert exact["stable"] is True and exact["margin_minpoly_degrees"] == [56, 56]
    assert [round(float(m[0]), 6) for m in exact["margins"]] == [0.153956, 0.091163]
    assert (tmp_path / "quevedo_robot.png").exists()
    for name in ("quevedo_example3", "quevedo_robot"):
        run = subprocess.run([sys.executable, str(ROOT / "examples" / f"{name}.py")], capture_output=True,
                             text=True, cwd=ROOT)
        assert run.returncode == 0, run.stderr


def test_simulation_bounded_where_theorem2_holds():
    pytest.importorskip("symkf.numeric.montecarlo")
    from symkf.network.reproduce import VIIC_A, VIIC_C1, viic_simulation
    results, bounded = viic_simulation(PeriodicDynamics(VIIC_A, [VIIC_C1]))
    assert bounded
    stable = results["phi = 19/20 (both states)"]
    assert stable["corrected_condition_holds"] and stable["mean_trace_k300_400"] < 10
    assert results["phi = 3/10 (both states)"]["corrected_condition_holds"] is False


def _robot_with_growth(tmp_path, a: str):
    text = (ROOT / "symkf/io/examples/systems/network/quevedo-robot.toml").read_text()
    path = tmp_path / "robot.toml"
    path.write_text(text.replace('A = [["21/20"', f'A = [["{a}"'))
    return files.load(path)


def test_robot_exact_critical_growth(tmp_path):
    # A = [[a, 1/10], [0, 1]]: the a-mode's eigenvector (1, 0) is seen by S1 and S4 only, for every
    # a != 1, so its rate rho_0 (chain restricted to "S1 and S4 lost", 560 lifted states) does not
    # depend on a and the filter is stable iff a^2 rho_0 < 1: a < rho_0^(-1/2) = 2.67603...
    # (the 1-mode's margin is 0.0912 or 0.1396, far below 1)
    system, loss = files.load(ROOT / "symkf/io/examples/systems/network/quevedo-robot.toml")
    rho0 = stability(system, loss).margins[0] / R(441, 400)
    assert 2.67602 < float(rho0) ** -0.5 < 2.67603
    assert stability(*_robot_with_growth(tmp_path, "267/100")).stable
    assert not stability(*_robot_with_growth(tmp_path, "268/100")).stable


@pytest.mark.full
def test_robot_theorem2_critical_growth(tmp_path):
    # Theorem 2 (corrected) on the same family: holds up to a = 2.17, fails from 2.18 (docs/quevedo.md)
    for a, holds in (("217/100", True), ("218/100", False)):
        system, loss = _robot_with_growth(tmp_path, a)
        dyn = PeriodicDynamics(system.A, [s.C for s in system.sensors])
        assert theorem2(loss, dyn).holds is holds
