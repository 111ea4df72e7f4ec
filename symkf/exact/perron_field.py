"""Exact Perron roots of non-negative matrices with entries in a number field K (Perron-Frobenius).

The root is an eigenvalue of ``M``, so a root of ``chi_M`` in ``K[x]`` and of its norm
``N(x) = prod_sigma sigma(chi_M)(x)`` in ``Q[x]``.  ``N`` is the characteristic polynomial of
the rational ``nd x nd`` matrix of ``v -> M v`` on ``K^n = Q^(nd)`` (each entry ``a`` replaced
by the matrix of multiplication by ``a`` on the basis ``1, theta, ..., theta^(d-1)``): the
determinant over Q of a K-linear map is the norm of its determinant over K.  flint computes
and factors it over Q, orders of magnitude faster than sympy's characteristic polynomial over
an algebraic extension and its norm (6 x 6 matrices over ``Q(sqrt 2, sqrt 3, sqrt 5)``:
docs/performance.md).

``N`` also has the eigenvalues of the conjugate matrices ``sigma(M)``, whose entries may be
negative and whose real eigenvalues may exceed ``rho(M)``.  The right root is the one in a
certified enclosure of ``rho(M)``: for a non-negative ``M`` and any positive vector ``v``,
``min_i (M v)_i / v_i <= rho(M) <= max_i (M v)_i / v_i`` (Collatz-Wielandt), evaluated in
ball arithmetic with the entries' certified values and ``v`` a float Perron vector (exact
binary rationals).  When exactly one real root of ``N`` can lie in the enclosure, it is
``rho(M)``; otherwise (roots of ``N`` closer than the enclosure's width, or no positive
float Perron vector) the caller falls back to the exact comparison of every real root.

The rational matrix has ``n d`` rows; the cost of its characteristic polynomial grows like
``(n d)^4`` (the dimension cubed, times the bits of its coefficients, which grow like ``n d``),
so ``n d`` is capped by ``budget.Limits.max_norm_dimension`` before the matrix is built; the
fallback over ``K`` (sympy's characteristic polynomial and norm) costs more still, so a block
above the cap is refused, not passed on.
"""

from __future__ import annotations

from fractions import Fraction

import flint
import numpy as np  # the float Perron vector only: the enclosure around it is certified
import sympy as sp

from .. import budget
from .algebraic import AlgebraicNumber, _arb_interval, _real_roots, with_prec
from ..arguments import check_public
from .field import NumberField
from .linalg import field_of

_PREC = 128


def _multiplication(K: NumberField, a: flint.fmpq_poly) -> list[list[flint.fmpq]]:
    """The d x d rational matrix of ``y -> a y`` on the basis ``theta^k`` (column k: ``a theta^k``)."""
    d = K.degree
    cols = []
    t = flint.fmpq_poly([1])
    for _ in range(d):
        c = K.mul(a, t).coeffs()
        cols.append(c + [flint.fmpq(0)] * (d - len(c)))
        t = K.mul(t, flint.fmpq_poly([0, 1]))
    return [[cols[k][i] for k in range(d)] for i in range(d)]


def norm_charpoly(K: NumberField, M: list[list[flint.fmpq_poly]]) -> flint.fmpz_poly:
    """``N(x) = Norm_(K/Q) det(x I - M)`` as a primitive integer polynomial (degree ``n d``)."""
    n, d = len(M), K.degree
    big = [[flint.fmpq(0)] * (n * d) for _ in range(n * d)]
    for r in range(n):
        for c in range(n):
            if M[r][c].is_zero():
                continue
            block = _multiplication(K, M[r][c])
            for i in range(d):
                big[r * d + i][c * d:(c + 1) * d] = block[i]
    chi = flint.fmpq_mat(big).charpoly()
    return flint.fmpz_poly([int(c) for c in (chi * chi.denom()).coeffs()])


def _enclosure(B: list[list[flint.arb]]) -> tuple[Fraction, Fraction] | None:
    """Collatz-Wielandt bounds ``[lo, hi]`` of ``rho`` around a float Perron vector, or None when
    that vector is not positive (the bounds need ``v > 0``)."""
    F = np.array([[float(b.mid()) for b in row] for row in B])
    w, V = np.linalg.eig(F)
    v = np.abs(V[:, int(np.argmax(w.real))].real)
    if not np.all(v > 1e-12 * v.max()):
        return None
    vq = [flint.arb(flint.fmpq(*Fraction(float(c)).as_integer_ratio())) for c in v]

    ratios = with_prec(_PREC, lambda: [sum((b * x for b, x in zip(row, vq)), flint.arb(0)) / vi
                                        for row, vi in zip(B, vq)])
    ends = [_arb_interval(r) for r in ratios]
    return min(Fraction(int(a.p), int(a.q)) for a, _ in ends), max(Fraction(int(b.p), int(b.q)) for _, b in ends)


def field_perron_root(M: sp.MatrixBase) -> AlgebraicNumber | None:
    """``rho(M)`` of a non-negative square sympy matrix with algebraic entries, or None when the
    enclosure does not single out one root of the norm (then compare every real root exactly).

    Refused (:class:`~symkf.errors.BudgetError`) when ``n d`` (``n`` rows, ``d`` the degree of
    the entries' field) is above ``budget.Limits.max_norm_dimension``."""
    K = field_of(M)
    budget.check("max_norm_dimension", M.rows * K.degree, f"an irreducible block of {M.rows} chain states",
                 f"the size n d of the rational matrix of its norm (n = {M.rows} states, entries in a field "
                 f"of degree d = {K.degree})")
    E = K.matrix(M)
    B = K.real_balls(E, _PREC)
    if any(not (b == 0 or b > 0) for row in B for b in row):  # M >= 0 is what the bounds need
        return None
    box = _enclosure(B)
    if box is None:
        return None
    lo, hi = box
    if hi <= 0:
        return AlgebraicNumber.from_expr(0)
    inside = []
    for r in _real_roots(norm_charpoly(K, E)):
        a, b = r.interval
        if a <= hi and b >= lo:
            r.refine(max(hi - lo, Fraction(1, 10 ** 40)) / 4)
            a, b = r.interval
            if a <= hi and b >= lo:
                inside.append(r)
    return inside[0] if len(inside) == 1 else None


check_public(globals())
