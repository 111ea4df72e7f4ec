"""The hypotheses of the published results, each decided exactly on a :class:`~symkf.model.system.System`.

Each function returns a :class:`~symkf.bounds.row.Hypothesis` naming what was checked and,
when it fails, the offending data.
"""

from __future__ import annotations

import functools
from typing import Callable

import sympy as sp

from ..arguments import check_public
from ..errors import BudgetError
from ..exact.linalg import krylov_rank, nullspace_rows, rank
from ..model.system import System
from ..engine.rows import modal_form
from .row import Hypothesis, Quantity
from ..exact.spectral import spectral_radius




def _refusable(name: str) -> Callable[[Callable[..., Hypothesis]], Callable[..., Hypothesis]]:
    """The hypothesis ``name`` checked by the decorated function, or, when a cap refuses its exact
    check (a rank over the compositum of many cyclotomic fields), the refusal as the hypothesis's
    detail: the row is refused, naming the cap, and the rest of the atlas is read."""
    def wrap(check: Callable[..., Hypothesis]) -> Callable[..., Hypothesis]:
        @functools.wraps(check)
        def checked(*args: object) -> Hypothesis:
            try:
                return check(*args)
            except BudgetError as exc:
                return Hypothesis(name, False, str(exc), refused=True)
        return checked
    return wrap


def one_sensor(system: System) -> Hypothesis:
    return Hypothesis("one sensor", system.d == 1, "" if system.d == 1 else
                      f"{system.d} sensors; the result is stated for a single sensor (one channel)")


def iid(quantity: Quantity) -> Hypothesis:
    return Hypothesis("i.i.d. losses", quantity.iid,
                      "" if quantity.iid else "the loss model is Gilbert-Elliott")


def gilbert_elliott(quantity: Quantity) -> Hypothesis:
    ok = quantity.kind == "gilbert-elliott"
    return Hypothesis("Gilbert-Elliott losses", ok,
                      "" if ok else "the loss model is i.i.d.; the result is stated for Markov losses")


@_refusable("A unstable")
def unstable(system: System) -> Hypothesis:
    rho = spectral_radius(system.A)
    return Hypothesis("A unstable", rho >= 1,
                      f"rho(A) = {rho.exact}" + ("" if rho >= 1 else ": every loss rate is stable"))


@_refusable("(A, Q^(1/2)) controllable")
def controllable_noise(system: System) -> Hypothesis:
    """``(A, Q^(1/2))`` controllable: ``range Q^(1/2) = range Q``, Krylov rank."""
    A, Q = sp.Matrix(system.A), sp.Matrix(system.Q)
    definite = rank(Q) == system.n
    r = system.n if definite else krylov_rank(A.T, Q.T)
    detail = "Q > 0" if definite else f"rank [Q, AQ, ...] = {r}, n = {system.n}"
    return Hypothesis("(A, Q^(1/2)) controllable", r == system.n, detail)


def detectable(system: System) -> Hypothesis:
    """Checked when the :class:`System` was built (PBH on ``|lambda| >= 1``); recorded here."""
    return Hypothesis("(A, C) detectable", True, "PBH test on |lambda| >= 1 (System)")


@_refusable("A diagonalizable")
def diagonalizable(system: System) -> Hypothesis:
    chains = [str(e.expr) for b in system.eigen_blocks() for e in b.members if e.defective]
    return Hypothesis("A diagonalizable", not chains, f"Jordan chains at {', '.join(chains)}" if chains else "")


@_refusable("no unit-circle Jordan chain")
def no_defective_unit_circle_eigenvalue(system: System) -> Hypothesis:
    bad = [str(e.expr) for b in system.eigen_blocks() if b.modulus == 1 for e in b.members if e.defective]
    return Hypothesis("no unit-circle Jordan chain", not bad,
                      f"Jordan chains at {', '.join(bad)}" if bad else "")


@_refusable("one-step observable")
def one_step_observable(system: System) -> Hypothesis:
    """``C`` of full column rank (the state is recovered from one measurement)."""
    r = rank(sp.Matrix(system.C))
    return Hypothesis("one-step observable", r == system.n, f"C of full column rank: rank C = {r}, n = {system.n}")


@_refusable("C invertible")
def invertible_C(system: System) -> Hypothesis:
    C = system.C
    ok = C.shape[0] == C.shape[1] and rank(sp.Matrix(C)) == system.n
    return Hypothesis("C invertible", ok, "" if ok else f"C is {C.shape[0]}x{C.shape[1]} of rank {rank(sp.Matrix(C))}")


@_refusable("C_o invertible")
def invertible_on_observable_subspace(system: System) -> Hypothesis:
    """Plarre-Bullo: in the observability decomposition ``C = [C_o, 0]``, ``C_o`` invertible.

    Read as: ``rank C`` equals the dimension ``n_o`` of the observable part, i.e. ``C_o`` is
    injective (redundant rows of ``C`` are dropped, which changes no covariance bound)."""
    A, C = sp.Matrix(system.A), sp.Matrix(system.C)
    n_o = krylov_rank(A, C)
    r = rank(C)
    return Hypothesis("C_o invertible", r == n_o,
                      f"C = [C_o, 0] in the observability decomposition: rank C = {r}, "
                      f"observable part of dimension {n_o}")


@_refusable("non-degenerate")
def non_degenerate(system: System) -> Hypothesis:
    """Mo-Sinopoli: every equiblock (eigenvalues of one modulus) is one-step observable.

    With ``T_I`` the eigenvectors of the block (exact, over its number field), ``C T_I`` must
    have full column rank ``|I|``."""
    for block in system.eigen_blocks():
        K, T, _ = modal_form(system.A, block, [system.C])
        rows = [K.vecmat(K.matrix(system.C)[r], T) for r in range(system.C.shape[0])]
        deficiency = len(nullspace_rows(K, rows, block.size))
        if deficiency:
            return Hypothesis("non-degenerate", False,
                              "not every equiblock is one-step observable: the equiblock "
                              f"|lambda| = {block.modulus.exact} (eigenvalues "
                              f"{', '.join(map(str, block.eigenvalues))}) has rank C T = "
                              f"{block.size - deficiency} < {block.size}")
    return Hypothesis("non-degenerate", True)


def second_order(system: System) -> Hypothesis:
    return Hypothesis("second order", system.n == 2, f"n = {system.n}")


check_public(globals())
