"""Sinopoli, Schenato, Franceschetti, Poolla, Jordan, Sastry, "Kalman filtering with intermittent
observations", IEEE TAC 49(9), 2004: the two bounds on the critical arrival rate.

With ``lambda`` the arrival probability (``eps = 1 - lambda``), under ``(A, Q^(1/2))``
controllable and ``(A, C)`` detectable, they bracket the critical arrival rate,
``lambda_min <= lambda_c <= lambda_max``:

* ``lambda_min = 1 - 1/rho(A)^2`` (necessary: the all-lost pattern), so
  ``eps_c <= 1/rho(A)^2``;
* ``lambda_max`` is the least ``lambda`` for which the modified Riccati inequality
  ``X > phi_lambda(K, X)`` has a solution, i.e. (Theorem 5) for which the LMI
  ``Psi_lambda(Y, Z) > 0, 0 < Y <= I`` is feasible; the problem is quasi-convex and
  solved by bisection on ``lambda``, so ``eps_c >= 1 - lambda_max``;
* the two coincide when ``C`` is invertible.

Theorem numbers other than Theorem 5 (the LMI) are not given: they could not be checked here.

``Psi_lambda`` is, after the change of variables ``Z = Y K``, the one-sensor case of the
multi-sensor LMI that :mod:`symkf.capacity.convergence` decides with exact certificates (a
constant gain making ``(1 - lambda) A X A' + lambda (A + KC) X (A + KC)'`` contractive;
Yang et al.'s eq. 22 with one arrival rate per sensor).  Each bisection point is decided
there: a rational ``(Y, Z)`` with ``Psi > 0`` verified exactly (feasible) or a dual
``W > 0`` verified exactly (infeasible), so the threshold ``1 - lambda_max`` lies in a
certified bracket ``[lo, hi]``.  With several sensors the common-rate form is used (the
standard multi-sensor LMI, one arrival rate per sensor, all equal).
"""

from __future__ import annotations

from typing import Callable

import sympy as sp

from ..arguments import check_public
from ..capacity.convergence import mare_stabilizable, price_lmi
from ..errors import BudgetError, ExtraNotInstalledError
from ..model.iid import IID
from ..model.system import System
from ..engine.stability import stability
from ..exact.spectral import spectral_radius
from . import hypotheses as hyp
from .row import EXACT, NECESSARY, REFUSED, SUFFICIENT, VIOLATED, Hypothesis, Quantity, Row, compare_bracket, number, row

CITATION = ("B. Sinopoli, L. Schenato, M. Franceschetti, K. Poolla, M. I. Jordan, S. S. Sastry, "
            "\"Kalman filtering with intermittent observations\", IEEE Trans. Autom. Control 49(9), 2004")

#: bisection steps of the LMI threshold (each halves the bracket and solves and certifies one LMI)
LMI_STEPS = 8


def inverse_rho_squared(system: System, quantity: Quantity) -> Callable[[], tuple]:
    """The evaluation ``eps < 1/rho(A)^2`` of every row whose value is Sinopoli et al.'s bound."""
    v = 1 / spectral_radius(system.A).exact ** 2
    return lambda: (quantity.below(v), number(v))


def lower_bound(system: System, quantity: Quantity) -> Row:
    """The lower bound on the arrival rate: ``eps_c <= 1/rho(A)^2`` (necessary), one sensor."""
    hyps = [hyp.one_sensor(system), hyp.iid(quantity), hyp.unstable(system), hyp.controllable_noise(system),
            hyp.detectable(system)]
    return row("sinopoli-lower", "Sinopoli et al. 2004, lower bound", CITATION,
               "eps_c <= 1/rho(A)^2 (arrival lambda_c >= 1 - 1/rho(A)^2)", NECESSARY, hyps, quantity,
               inverse_rho_squared(system, quantity))


def invertible_c(system: System, quantity: Quantity) -> Row:
    """``C`` invertible: ``lambda_min = lambda_max``, so ``eps_c = 1/rho(A)^2``."""
    hyps = [hyp.one_sensor(system), hyp.iid(quantity), hyp.unstable(system), hyp.controllable_noise(system),
            hyp.invertible_C(system)]
    return row("sinopoli-invertible-c", "Sinopoli et al. 2004, C invertible", CITATION,
               "eps_c = 1/rho(A)^2 when C is invertible", EXACT, hyps, quantity, inverse_rho_squared(system, quantity))


def lmi_bracket(system: System, steps: int = LMI_STEPS) -> tuple[sp.Expr, sp.Expr, tuple[str, ...]]:
    """A certified bracket ``[lo, hi]`` of the largest common loss at which the LMI is feasible.

    ``lo`` carries an exact feasibility certificate (0 when ``(A, C)`` is detectable),
    ``hi`` an exact infeasibility certificate (at first ``rho(A)^(-2/d)``, where the all-lost
    pattern alone rules feasibility out).  A bisection point where neither certificate
    verifies (too close to the boundary) ends the bisection."""
    d = system.d
    price_lmi(system, d, 1 + steps, "symkf.bounds.sinopoli.lmi_bracket (the atlas's LMI row)")
    hi = sp.radsimp(spectral_radius(system.A).exact ** sp.Rational(-2, d))
    hi = hi if number(hi) < 1 else sp.Integer(1)
    lo = sp.Integer(0)
    notes = [f"infeasible at eps = {hi}: the all-lost pattern (capacity <= ln rho(A))"]
    start = mare_stabilizable(system, IID([lo] * d))
    if not start.holds:
        return lo, lo, (f"eps = 0: {start.certificate}",)
    for _ in range(steps):
        for share in (sp.Rational(1, 2), sp.Rational(3, 7), sp.Rational(4, 7)):
            point = _between(lo, hi, share)
            verdict = mare_stabilizable(system, IID([point] * d))
            if verdict.holds is not None:
                break
            notes.append(f"eps = {point}: {verdict.certificate}")
        if verdict.holds is None:
            break
        lo, hi = (point, hi) if verdict.holds else (lo, point)
    return lo, hi, (*notes, f"feasible at eps = {lo}: F(Y, Z) > 0 verified exactly",
                    f"infeasible at eps = {hi}: certificate verified exactly")


def _between(lo: sp.Expr, hi: sp.Expr, share: sp.Rational) -> sp.Rational:
    """The rational ``lo + share (hi - lo)`` (``hi`` rounded down to a rational when irrational)."""
    top = hi if hi.is_Rational else sp.Rational(number(hi).interval[0])
    return lo + share * (top - lo)


def lmi(system: System, quantity: Quantity, steps: int = LMI_STEPS) -> Row:
    """Theorem 5: ``eps_c >= 1 - lambda_max``, ``lambda_max`` by bisection on the LMI (certified bracket)."""
    base = dict(key="sinopoli-lmi", result="Sinopoli et al. 2004, LMI (Thm. 5)", citation=CITATION,
                statement="eps_c >= 1 - lambda_max, lambda_max the least arrival rate with Psi_lambda(Y, Z) > 0, "
                          "0 < Y <= I feasible" + (" (multi-sensor form, common rate)" if system.d > 1 else ""),
                claim=SUFFICIENT)
    hyps = (hyp.iid(quantity), hyp.unstable(system), hyp.controllable_noise(system), hyp.detectable(system))
    if not all(h.holds for h in hyps):
        return Row(**base, hypotheses=hyps)
    try:
        lo, hi, notes = lmi_bracket(system, steps)
        relation, gap = compare_bracket(lo, hi, quantity.critical)
        note = "the threshold lies in the certified bracket"
        if quantity.rates:
            at, relation = at_rates(system, quantity.rates, relation)
            note += "; " + at
    except ExtraNotInstalledError as exc:  # the LMI needs cvxpy (the sdp extra); the other rows do not
        return Row(**base, hypotheses=hyps + (Hypothesis("the sdp extra installed", False, str(exc)),))
    except BudgetError as exc:   # a cap refuses the bisection, not the atlas: its message is the row's note
        return Row(**base, hypotheses=hyps, relation=REFUSED, note=str(exc))
    return Row(**base, hypotheses=hyps, bracket=(lo, hi), relation=relation, gap=gap, certificate=notes,
               stable=quantity.below(lo), note=note)


def at_rates(system: System, rates: tuple, relation: str) -> tuple[str, str]:
    """The multi-sensor LMI at the model's own per-sensor rates beside the exact verdict.

    Feasible (certified) where the engine says unstable would be a violation."""
    verdict = mare_stabilizable(system, IID(list(rates)))
    exact = stability(system, IID(list(rates))).stable
    words = {True: "feasible (stable certified)", False: "infeasible", None: "undecided"}[verdict.holds]
    if verdict.holds and not exact:
        relation = VIOLATED
    return (f"at the model's rates {[str(r) for r in rates]}: LMI {words}, exact verdict "
            f"{'stable' if exact else 'unstable'}"), relation


check_public(globals())
# after the wrapping: atlas recognises the LMI row by identity (it takes the bisection steps)
ROWS = (lower_bound, lmi, invertible_c)
