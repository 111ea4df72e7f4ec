"""Exact linear algebra over Q and number fields.

``rank`` is the workhorse of the regression-matrix analysis (eqs. 14-17 of
Sui-You-Fu).  Over Q it is ``fmpq_mat.rank``.  Over a number field K it first
reduces modulo a prime ideal of degree one (``theta -> r mod p``): reduction
can only lower the rank, so a full rank modulo ``p`` proves full rank over K.
Otherwise the exact rank is computed from the Q-realification of the rows
(rank over Q = [K:Q] * rank over K).
"""

from __future__ import annotations

from typing import Sequence

import flint
import sympy as sp

from .field import Elem, NumberField, QQ_FIELD


def field_of(*matrices: sp.MatrixBase) -> NumberField:
    """The smallest number field holding every entry."""
    gens: list[sp.Expr] = []
    for M in matrices:
        for v in M:
            v = sp.sympify(v)
            if not v.is_Rational and v not in gens:
                gens.append(v)
    return NumberField(gens) if gens else QQ_FIELD


def rank_rows(K: NumberField, rows: Sequence[Sequence[Elem]], ncols: int | None = None) -> int:
    """Exact rank over ``K`` of the matrix with the given rows (entries in ``K``)."""
    rows = [r for r in rows]
    if not rows:
        return 0
    ncols = len(rows[0]) if ncols is None else ncols
    full = min(len(rows), ncols)
    if K.is_rational:
        return flint.fmpq_mat([[a[0] if a.length() else 0 for a in r] for r in rows]).rank()
    p, _ = K._prime_embedding
    reduced = [[K.reduce(a) for a in r] for r in rows]
    if all(v is not None for r in reduced for v in r):
        if flint.nmod_mat(reduced, p).rank() == full:
            return full
    return K.realify(rows).rank() // K.degree


def rank(M: sp.MatrixBase, K: NumberField | None = None) -> int:
    """Exact rank of a sympy matrix with algebraic entries."""
    M = sp.Matrix(M)
    if M.shape[0] == 0 or M.shape[1] == 0:
        return 0
    K = K or field_of(M)
    return rank_rows(K, K.matrix(M), M.shape[1])


def nullspace_rows(K: NumberField, rows: Sequence[Sequence[Elem]], ncols: int) -> list[list[Elem]]:
    """A basis of ``{h : row . h = 0 for every row}`` over ``K`` (Gaussian elimination in K)."""
    A = [list(r) for r in rows]
    pivots: list[int] = []
    r = 0
    for c in range(ncols):
        piv = next((i for i in range(r, len(A)) if not A[i][c].is_zero()), None)
        if piv is None:
            continue
        A[r], A[piv] = A[piv], A[r]
        inv = K.inv(A[r][c])
        A[r] = [K.mul(a, inv) for a in A[r]]
        for i in range(len(A)):
            if i != r and not A[i][c].is_zero():
                f = A[i][c]
                A[i] = [(a - K.mul(f, b)) % K.modulus for a, b in zip(A[i], A[r])]
        pivots.append(c)
        r += 1
        if r == len(A):
            break
    free = [c for c in range(ncols) if c not in pivots]
    basis = []
    for fc in free:
        h = [flint.fmpq_poly([]) for _ in range(ncols)]
        h[fc] = flint.fmpq_poly([1])
        for i, pc in enumerate(pivots):
            h[pc] = -A[i][fc]
        basis.append(h)
    return basis
