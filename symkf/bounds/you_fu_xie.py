"""You, Fu, Xie, "Mean square stability for Kalman filtering with Markovian packet losses",
Automatica 47(12), 2011: a necessary and sufficient condition for second-order systems.

The condition, in the form derived here (one sensor, Gilbert-Elliott channel with
``f = P(lost | received last)`` and ``q = P(received | lost last)``):

* if ``A`` has two simple eigenvalues of modulus ``r`` whose ratio is a primitive ``p``-th
  root of unity and ``C`` has one independent row, the estimate stays singular iff every
  reception falls on one residue mod ``p``; over one period the chain's transfer restricted to
  those patterns has rank one and spectral radius ``(1 - q)^(p - 2) ((1 - q)^2 + f q)``, so the
  filter is stable iff ``r^(2p) (1 - q)^(p - 2) ((1 - q)^2 + f q) < 1``;
* otherwise (distinct moduli, an aperiodic ratio, Jordan chains, or ``C`` of rank 2) two
  receptions at distinct times already observe the unstable modes: stable iff
  ``(1 - q) rho(A)^2 < 1``.

With i.i.d. losses (``f = eps``, ``q = 1 - eps``) the first reads ``eps < r^(-2p/(p-1))``
(their Theorem 7, the single-sensor case of Sui-You-Fu's Theorem 12, Remark 13) and the
second ``eps < 1/rho(A)^2``.  The set of stable ``q`` need not be an interval: for
``A = (sqrt 6/2) R(pi/2)``, ``C = [1 0]``, ``f = 1/2`` it is ``2/3 < q < 5/6``, the
engine's finding in ``proofs/sui_engine_ge_recovery_nonmonotone.py``.
"""

from __future__ import annotations

import sympy as sp

from ..arguments import check_public
from ..model.system import System
from ..engine.region import stable_intervals
from ..exact.spectral import spectral_radius
from . import hypotheses as hyp
from .mo_sinopoli import degenerate_pair, ratio_order
from .row import EXACT, Quantity, Row, number, row

CITATION = ("K. You, M. Fu, L. Xie, \"Mean square stability for Kalman filtering with Markovian packet "
            "losses\", Automatica 47(12), 2011")

q = sp.Symbol("q", positive=True)


def period(system: System) -> int | None:
    """``p`` when the degenerate periodic case applies, else None (the one-step case)."""
    if not all(h.holds for h in degenerate_pair(system)):
        return None
    return ratio_order(system)


def margin(system: System, fail: sp.Expr) -> sp.Expr:
    """The left-hand side of the condition (module docstring) as a polynomial in ``q``."""
    r2 = spectral_radius(system.A).exact ** 2
    p = period(system)
    if p is None:
        return sp.expand(r2 * (1 - q))
    return sp.expand(r2 ** p * (1 - q) ** (p - 2) * ((1 - q) ** 2 + fail * q))


def critical_loss(system: System) -> sp.Expr:
    """The i.i.d. form: ``r^(-2p/(p-1))``, or ``1/rho(A)^2`` in the one-step case."""
    r = spectral_radius(system.A).exact
    p = period(system)
    return sp.radsimp(r ** -2 if p is None else r ** sp.Rational(-2 * p, p - 1))


def second_order(system: System, quantity: Quantity) -> Row:
    """The necessary and sufficient condition for ``n = 2`` (module docstring), i.i.d. or Gilbert-Elliott."""
    hyps = [hyp.one_sensor(system), hyp.second_order(system), hyp.unstable(system)]

    def value() -> tuple:
        if quantity.iid:
            v = critical_loss(system)
            return quantity.below(v), number(v)
        stable = stable_intervals([margin(system, quantity.fail[0])], q)
        one = len(stable) == 1 and stable[0][1] == 1
        return stable, stable[0][0] if one else None

    statement = ("stable iff r^(2p) (1-q)^(p-2) ((1-q)^2 + f q) < 1 (degenerate, period p), "
                 "else (1-q) rho(A)^2 < 1; i.i.d.: eps_c = r^(-2p/(p-1)) or 1/rho(A)^2")
    return row("you-fu-xie", "You, Fu, Xie 2011, 2nd order", CITATION, statement, EXACT, hyps, quantity, value)


ROWS = (second_order,)


check_public(globals())
