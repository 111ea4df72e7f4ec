"""TCP-like control over one Gilbert-Elliott channel: exact verdicts where a certificate decides.

With acknowledged packets the controller knows whether the previous command arrived, which is
the channel's state (Gilbert-Elliott: ``P(lost | received last) = f``, ``P(received | lost last) =
q``).  The cost-to-go ``x'S_i x`` depends on that state ``i`` (0 lost, 1 received) and the LQ
recursion of Schenato et al. 2007, Section IV, becomes the coupled pair (a Markov jump linear
system with the mode seen one step late; Costa, Fragoso and Marques, *Discrete-time Markov jump
linear systems*, 2005)::

    S_i = W + A'(p_i0 S_0 + p_i1 S_1)A - p_i1 A'S_1 B (B'S_1 B + U)^{-1} B'S_1 A,

``p_01 = q``, ``p_11 = 1 - f``, whose optimal gain ``K = -(B'S_1B + U)^{-1} B'S_1 A`` is the same in
both states.  Decided exactly:

* **stable** when a rational gain passes the coupled Lyapunov test: ``S_i - sum_j p_ij M_j' S_j M_j
  = I`` (``M_0 = A``, ``M_1 = A + BK``) has a positive definite solution, one exact rational solve
  (the second-moment operator of the loop then has spectral radius below one);
* **unstable** when a loss burst alone diverges: ``(1 - q) rho(A)^2 >= 1`` (the operator dominates
  its lost-to-lost term ``(1 - q) A (.) A'``);
* otherwise **undecided**, with both numbers.  For one input the i.i.d. threshold's argument
  (:mod:`.threshold`) suggests ``(1 - q) prod |lambda_u|^2 < 1``; it is not proved here for
  Markov channels (the determinant argument needs one Riccati matrix, the channel gives two), so
  symkf does not use it.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import flint
import sympy as sp

from ..exact.algebraic import AlgebraicNumber, with_prec
from ..exact.text import algebraic_text
from ..exact.spectral import eigenvalues
from .threshold import _PREC, _Plant, _dyadic, _kron, _mid, _positive_float, _unvec, _vec, stein_certificate


def _evaluate(plant: _Plant, K: flint.arb_mat, p: list[list[flint.arb]]) -> tuple[flint.arb_mat, flint.arb_mat] | None:
    """The coupled cost ``S_i = W + p_i1 K'UK + sum_j p_ij M_j' S_j M_j`` of the gain ``K``, or None
    when the loop is not mean-square stable."""
    n = plant.n
    M = [plant.A, plant.A + plant.B * K]
    blocks = [_kron(Mj.transpose(), Mj.transpose()) for Mj in M]
    size = 2 * n * n
    L = flint.arb_mat(size, size)
    for i in range(2):
        for k in range(n * n):
            L[i * n * n + k, i * n * n + k] = 1
        for j in range(2):
            for a in range(n * n):
                for b in range(n * n):
                    L[i * n * n + a, j * n * n + b] -= p[i][j] * blocks[j][a, b]
    rhs = flint.arb_mat(size, 1)
    for i in range(2):
        v = _vec(plant.W + p[i][1] * K.transpose() * plant.U * K)
        for a in range(n * n):
            rhs[i * n * n + a, 0] = v[a, 0]
    try:
        x = _mid(L).solve(rhs)
    except ZeroDivisionError:
        return None
    S = [_mid(_unvec(flint.arb_mat([[x[i * n * n + a, 0]] for a in range(n * n)]), n)) for i in range(2)]
    return (S[0], S[1]) if all(_positive_float(Si) for Si in S) else None


def _optimal(plant: _Plant, K: flint.arb_mat, p) -> flint.arb_mat | None:
    """Policy iteration on the coupled pair: the next command sees ``S_1`` (module doc)."""
    def cost(gain: flint.arb_mat) -> flint.arb_mat | None:
        S = _evaluate(plant, gain, p)
        return None if S is None else S[1]
    return plant.iterate(K, cost)


def _gain(plant: _Plant, f: Fraction, q: Fraction) -> flint.arb_mat | None:
    """The optimal gain at ``(f, q)``, continued from the lossless channel ``(0, 1)`` along
    ``(t f, 1 - t (1 - q))``, the step halved when the previous gain no longer stabilizes."""
    from .threshold import _lqr_gain
    K = _lqr_gain(plant)
    t, step = Fraction(0), Fraction(1, 4)
    while t < 1:
        trial = min(Fraction(1), t + step)
        ft, qt = trial * f, 1 - trial * (1 - q)
        p = [[1 - _arb(qt), _arb(qt)], [_arb(ft), 1 - _arb(ft)]]
        found = _optimal(plant, K, p)
        if found is None:
            step /= 2
            if step < Fraction(1, 2 ** 30):
                return None
            continue
        t, K, step = trial, found, min(step * 2, Fraction(1, 2))
    return K


def _arb(q: Fraction) -> flint.arb:
    return flint.arb(q.numerator) / q.denominator


def _coupled_certificate(A: sp.MatrixBase, B: sp.MatrixBase, K: sp.MatrixBase, f: Fraction, q: Fraction
                         ) -> list[sp.ImmutableMatrix] | None:
    """Exact: ``(S_0, S_1) > 0`` solving ``S_i - sum_j p_ij M_j' S_j M_j = I`` (module doc), or None."""
    M = [A, A + B * K]
    p = [[1 - _rational(q), _rational(q)], [_rational(f), 1 - _rational(f)]]
    return stein_certificate([[(j, p[i][j], M[j]) for j in range(2)] for i in range(2)], A.rows)


def _rational(x: Fraction) -> sp.Rational:
    return sp.Rational(x.numerator, x.denominator)


def _gilbert_elliott_stabilizable(A: sp.MatrixBase, B: sp.MatrixBase, W: sp.MatrixBase, U: sp.MatrixBase,
                                 fail: Any, recover: Any) -> tuple[bool | None, str]:
    """The verdict of the module doc, with its reason (``(A, B)`` stabilizable)."""
    f, q = Fraction(str(sp.Rational(fail))), Fraction(str(sp.Rational(recover)))
    rho2 = max((e.modulus for e in eigenvalues(A)), default=None) ** 2
    burst = AlgebraicNumber.from_expr(rho2.exact * (1 - sp.Rational(q.numerator, q.denominator)))
    if not burst < 1:
        return False, (f"a burst of lost commands diverges: (1 - recover) rho(A)^2 = {algebraic_text(burst)} >= 1")
    K = with_prec(_PREC, lambda: _gain(_Plant(A, B, W, U), f, q))
    if K is not None:
        Kq = _dyadic(K)
        if _coupled_certificate(A, B, Kq, f, q) is not None:
            return True, ("a rational gain passes the coupled Lyapunov test exactly (coupled second moments of the "
                          "Markov jump linear system)")
    return None, (f"undecided: no gain found stabilizing the coupled recursion, and (1 - recover) rho(A)^2 = "
                  f"{algebraic_text(burst)} < 1 does not rule one out")
