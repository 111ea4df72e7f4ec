"""Convex programmes solved in floating point (cvxpy with Clarabel), whose answers the callers then
certify exactly or check (the LMI of Yang et al.'s Theorem 4 in :mod:`symkf.capacity.convergence`,
the fusion SDP in :mod:`symkf.fusion.weights`): one place that turns a solver's failure into a
status the caller decides on, never an exception of cvxpy's."""

from __future__ import annotations

import warnings
from typing import Any

from ..arguments import check_public
from ..errors import InputError, require_extra

#: the status :func:`solve` gives when the solver itself failed (cvxpy's own statuses are the others)
FAILED = "solver_error"


def solve(problem: Any, **options: Any) -> str:
    """Solve the cvxpy ``problem`` with Clarabel (``options`` are Clarabel's) and return its
    status, :data:`FAILED` when the solver stopped with an error (cvxpy's ``SolverError``:
    a numerical breakdown on an ill-conditioned programme), after which its variables hold no value.
    cvxpy's warning that a solution "may be inaccurate" is not shown: the callers certify or check."""
    cp = require_extra("cvxpy", "sdp", "a convex programme")
    if not isinstance(problem, cp.Problem):
        raise InputError(f"problem: expected a cvxpy Problem, got {type(problem).__name__}")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Solution may be inaccurate", category=UserWarning)
        try:
            problem.solve(solver=cp.CLARABEL, **options)
        except cp.error.SolverError:
            for variable in problem.variables():
                variable.value = None
            return FAILED
    return problem.status


check_public(globals())
