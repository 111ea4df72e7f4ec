"""Convex programmes in floats (symkf.numeric.convex): a solver's failure is a status that the
callers decide on (undecided, or an AssumptionError naming what applies instead), never
cvxpy's exception; a solved programme gives cvxpy's own status and values."""

from __future__ import annotations

import numpy as np
import pytest

from symkf import IID, Sensor, System
from symkf.capacity import mare_stabilizable
from symkf.errors import AssumptionError
from symkf.fusion.weights import optimal_weights
from symkf.numeric import convex

cp = pytest.importorskip("cvxpy")


@pytest.fixture
def failing_solver(monkeypatch):
    """Every cvxpy solve stops with the SolverError Clarabel raises on a breakdown."""
    def fail(self, *args, **kwargs):
        raise cp.error.SolverError("Solver 'CLARABEL' failed. Try another solver")
    monkeypatch.setattr(cp.Problem, "solve", fail)


def test_a_solved_programme_gives_cvxpys_status_and_values():
    x = cp.Variable()
    assert convex.solve(cp.Problem(cp.Minimize(x), [x >= 3])) == "optimal" and abs(x.value - 3) < 1e-6


def test_a_failed_solve_is_a_status_with_no_values_left(failing_solver):
    x = cp.Variable()
    x.value = 1.0
    assert convex.solve(cp.Problem(cp.Minimize(x), [x >= 3])) == convex.FAILED and x.value is None


def test_the_lmi_of_theorem_4_is_undecided_when_the_solver_fails(failing_solver):
    # a^2 (1 - lambda) < 1 holds at loss 1/5 for a = 2 (the exact screen passes it to the LMI)
    verdict = mare_stabilizable(System(A=[[2]], sensors=[Sensor(C=[[1]])]), IID(["1/5"]))
    assert verdict.holds is None and "the SDP solver failed on the primal and dual" in verdict.certificate


def test_the_fusion_sdp_names_the_closed_form_when_the_solver_fails(failing_solver):
    Vo = np.vstack([np.eye(2), np.eye(2)])
    with pytest.raises(AssumptionError, match="'solver_error'.*closed-form"):
        optimal_weights(np.eye(4), Vo, "sdp")


def test_what_is_not_a_programme_is_refused_naming_it():
    from symkf.errors import InputError
    with pytest.raises(InputError, match="problem: expected a cvxpy Problem, got list"):
        convex.solve([[1]])
