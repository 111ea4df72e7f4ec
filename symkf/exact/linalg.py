"""Exact linear algebra over Q and number fields.

``rank`` is the workhorse of the regression-matrix analysis (eqs. 14-17 of
Sui-You-Fu).  Over Q it is ``fmpq_mat.rank``.  Over a number field K it is
Gaussian elimination in K, row by row with an early exit at full rank (elements
are ``fmpq_poly`` reduced modulo the minimal polynomial).
"""

from __future__ import annotations

import itertools
import operator
from typing import Sequence

import flint
import sympy as sp

from .. import budget
from ..errors import InputError, ShapeError
from ..arguments import check_public
from typing import Any

from .algebraic import with_prec
from .field import Elem, NumberField, QQ_FIELD, rational_value
from .numbers import as_matrix, sympify


def field_of(*matrices: sp.MatrixBase) -> NumberField:
    """The smallest number field holding every entry."""
    gens: list[sp.Expr] = []
    for M in matrices:
        for v in M:
            v = sympify(v, "entry")
            if not v.is_Rational and v not in gens:
                gens.append(v)
    return NumberField(gens) if gens else QQ_FIELD


def rank_rows(K: NumberField, rows: Sequence[Sequence[Elem]], ncols: int | None = None) -> int:
    """Exact rank over ``K`` of the matrix with the given rows (entries in ``K``)."""
    rows = [r for r in rows]
    if not rows:
        return 0
    ncols = len(rows[0]) if ncols is None else ncols
    if K.is_rational:
        return flint.fmpq_mat([[rational_value(a) for a in r] for r in rows]).rank()
    return len(_echelon(K, rows, ncols)[1])


def rank(M: sp.MatrixBase, K: NumberField | None = None) -> int:
    """Exact rank of a sympy matrix with algebraic entries."""
    M = as_matrix(M, "M")
    if M.shape[0] == 0 or M.shape[1] == 0:
        return 0
    K = K or field_of(M)
    return rank_rows(K, K.matrix(M), M.shape[1])


def krylov_rank(A: sp.MatrixBase, C: sp.MatrixBase) -> int:
    """Exact rank of ``col{C, CA, ..., CA^(n-1)}`` (the observability matrix; with ``A'``, ``Q'`` it is
    the controllability rank of ``(A, Q)``) for ``A`` (n x n) and ``C`` with algebraic entries.

    Each block ``C A^(k+1) = (C A^k) A`` is computed from the last: in flint's rational matrices when
    every entry is rational (sympy's powers ``A^k``, one per k, cost far more at n = 48), otherwise in
    the field of A's and C's entries (the entries of ``A^k`` would each be a new generator), which is
    first priced by its degree (``max_cyclotomic_degree``); the stacked rows are ranked at once."""
    A, C = as_matrix(A, "A"), as_matrix(C, "C")
    n = A.shape[0]
    if n == 0 or C.shape[0] == 0:
        return 0
    K = field_of(A, C)
    if K.is_rational:
        to_q = lambda M: flint.fmpq_mat([[rational_value(QQ_FIELD.convert(v)) for v in M.row(i)]  # noqa: E731
                                         for i in range(M.shape[0])])
        Aq, block = to_q(A), to_q(C)
        rows = []
        for _ in range(n):
            rows.extend(block.tolist())
            block = block * Aq
        return flint.fmpq_mat(rows).rank()
    budget.check("max_cyclotomic_degree", K.degree, "A", "the degree of the field of A's and C's entries, in which "
                 "the Krylov rank is computed")
    Ak = K.matrix(A)
    rows, kblock = [], K.matrix(C)
    for _ in range(n):
        rows += kblock
        kblock = [K.vecmat(row, Ak) for row in kblock]
    return rank_rows(K, rows, n)


def _echelon(K: NumberField, rows: Sequence[Sequence[Elem]], ncols: int) -> tuple[list[list[Elem]], list[int]]:
    """Reduced row echelon form over ``K``: the normalised pivot rows and their pivot columns."""
    basis = echelon_extended(K, {}, rows, ncols)
    pivots = sorted(basis)
    return [basis[c] for c in pivots], pivots


def echelon_extended(K: NumberField, basis: dict[int, list[Elem]], rows: Sequence[Sequence[Elem]],
                     ncols: int) -> dict[int, list[Elem]]:
    """The reduced echelon basis (pivot column -> normalised row) of the span of ``basis`` and
    ``rows``, a new dict (``basis`` is left as it was): a span grown one block of rows at a time.

    Rows are reduced one at a time against the pivot rows found so far, touching only
    the non-pivot columns (pivot columns become exactly zero), as sympy's sparse rref does.
    """
    zero = flint.fmpq_poly([])
    mul = operator.mul if K.is_rational else K.mul   # rationals: flint's product, no reduction needed
    basis = dict(basis)
    for row in rows:
        if len(basis) == ncols:
            break
        coef = [(pc, row[pc]) for pc in basis if not row[pc].is_zero()]
        r = [zero if c in basis else
             (row[c] - sum((mul(f, basis[pc][c]) for pc, f in coef), zero)) % K.modulus
             for c in range(ncols)]
        piv = next((c for c in range(ncols) if not r[c].is_zero()), None)
        if piv is None:
            continue
        inv = K.inv(r[piv])
        r = [mul(a, inv) for a in r]
        for pc, b in basis.items():
            f = b[piv]
            if not f.is_zero():
                basis[pc] = [(x - mul(f, y)) % K.modulus for x, y in zip(b, r)]
        basis[piv] = r
    return basis


def span_key(basis: dict[int, list[Elem]]) -> tuple:
    """A hashable key of the span whose reduced echelon basis is ``basis`` (:func:`echelon_extended`):
    equal spans, equal keys (the reduced echelon form is unique).  Integers: they hash fast, flint's
    rationals go through Fraction."""
    return tuple((c, tuple((int(e.denom()), *map(int, e.numer().coeffs())) for e in basis[c])) for c in sorted(basis))


def nullspace_rows(K: NumberField, rows: Sequence[Sequence[Elem]], ncols: int) -> list[list[Elem]]:
    """A basis of ``{h : row . h = 0 for every row}`` over ``K`` (Gaussian elimination in K)."""
    A, pivots = _echelon(K, rows, ncols)
    free = [c for c in range(ncols) if c not in pivots]
    basis = []
    for fc in free:
        h = [flint.fmpq_poly([]) for _ in range(ncols)]
        h[fc] = flint.fmpq_poly([1])
        for i, pc in enumerate(pivots):
            h[pc] = -A[i][fc]
        basis.append(h)
    return basis

#: the largest ``n`` :func:`normal_of` expands by minors (``n 2^(n-1)`` products in K); beyond, an
#: echelon form (about ``n^3`` products and ``n`` inverses)
MINORS_MAX = 8


def normal_of(K: NumberField, rows: Sequence[Sequence[Elem]], ncols: int) -> list[Elem]:
    """A vector orthogonal to ``ncols - 1`` rows: their signed maximal minors ``h_j = (-1)^j
    det(rows without column j)`` (the generalized cross product), nonzero iff the rows are
    independent.  Up to :data:`MINORS_MAX` columns the minors share their sub-minors (each row's
    expansion over the column sets of the rows below it) and need no inverse in K, where an inverse
    costs as much as hundreds of products at high degree (a Markov screen's exact check on
    2R(2 pi/5) + 2R(2 pi/7) + 2R(2 pi/9), degree 288: docs/performance.md).  Beyond, and over
    Q (whose inverses are cheap), the nullspace of an echelon form (:func:`nullspace_rows`; the zero
    vector for dependent rows)."""
    if len(rows) != ncols - 1:
        raise ShapeError(f"normal_of: {ncols - 1} rows expected for {ncols} columns, got {len(rows)}")
    if ncols > MINORS_MAX or K.is_rational:
        basis = nullspace_rows(K, rows, ncols)
        return basis[0] if len(basis) == 1 else [flint.fmpq_poly([]) for _ in range(ncols)]
    minors = {(): flint.fmpq_poly([1])}          # det(rows i.. on columns T), |T| = the rows' count
    for i in range(len(rows) - 1, -1, -1):
        below, minors = minors, {}
        for T in itertools.combinations(range(ncols), len(rows) - i):
            acc = flint.fmpq_poly([])
            for k, c in enumerate(T):
                if not rows[i][c].is_zero():
                    term = rows[i][c] * below[T[:k] + T[k + 1:]]
                    acc = acc - term if k % 2 else acc + term
            minors[T] = acc % K.modulus
    every = tuple(range(ncols))
    return [minors[every[:j] + every[j + 1:]] * (-1 if j % 2 else 1) for j in range(ncols)]


def solve_rows(K: NumberField, rows: Sequence[Sequence[Elem]], rhs: Sequence[Elem]) -> list[Elem]:
    """The solution ``x`` over ``K`` of ``rows x = rhs`` (a square, invertible system), through the
    regular representation: ``a x`` is ``M_a`` times ``x``'s coordinates in the power basis of
    ``theta``, so the system is a rational one of ``deg K`` times the size, solved by flint's
    ``fmpq_mat.solve`` (multimodular: Gaussian elimination in K lets the rationals of a large Gram
    system grow).  Raises ZeroDivisionError when the system is singular."""
    N, D = len(rows), K.degree
    if K.is_rational:
        x = flint.fmpq_mat([[rational_value(a) for a in r] for r in rows]).solve(
            flint.fmpq_mat([[rational_value(b)] for b in rhs]))
        return [flint.fmpq_poly([x[i, 0]]) for i in range(N)]
    powers = [flint.fmpq_poly([0] * t + [1]) for t in range(D)]
    big = flint.fmpq_mat(N * D, N * D)
    for i, row in enumerate(rows):
        for j, a in enumerate(row):
            if a.is_zero():
                continue
            for t, th in enumerate(powers):   # column t of M_a: a theta^t in the power basis
                for u, c in enumerate(K.mul(a, th).coeffs()):
                    big[i * D + u, j * D + t] = c
    b = flint.fmpq_mat(N * D, 1)
    for i, e in enumerate(rhs):
        for u, c in enumerate(e.coeffs()):
            b[i * D + u, 0] = c
    x = big.solve(b)
    return [flint.fmpq_poly([x[j * D + t, 0] for t in range(D)]) for j in range(N)]


def positive_definite(K: NumberField, M: list[list[Elem]]) -> bool:
    """Exact: Sylvester's criterion on a symmetric matrix over ``K``, decided by the pivots of
    elimination without row exchanges (the leading minors are their running products) on certified
    balls at 256 bits, then 1024 and 4096 (the terms of an element of Q(cos 2 pi/401), degree 400,
    cancel by 10^500); when a ball's sign stays open, on the exact pivots (:func:`pivots_positive`
    over Q, :func:`_field_pivots_positive` over K: not sympy's determinants and minimal
    polynomials, far too slow at degree 400)."""
    _square_of(M, (flint.fmpq_poly,), "M")
    for prec in (256, 1024, 4096):
        decided = with_prec(prec, lambda: schur_positive(K.real_balls(M, prec)))
        if decided is not None:
            return decided
        if K.is_rational:
            return pivots_positive([[a[0] for a in row] for row in M])
    return _field_pivots_positive(K, M)


def _field_pivots_positive(K: NumberField, M: list[list[Elem]]) -> bool:
    """Sylvester's criterion by exact elimination over K without row exchanges: every pivot must be
    positive (a zero pivot is a zero leading minor); a nonzero pivot's sign comes from its certified
    ball at rising precision (one correct bit excludes 0, the pivot being exactly nonzero)."""
    A = [list(row) for row in M]
    for k in range(len(A)):
        pivot = A[k][k]
        if pivot.is_zero() or K.real_balls([[pivot]], 256, accuracy=1)[0][0] < 0:
            return False
        inv = K.inv(pivot)
        for i in range(k + 1, len(A)):
            f = K.mul(A[i][k], inv)
            for j in range(k + 1, len(A)):
                A[i][j] = (A[i][j] - K.mul(f, A[k][j])) % K.modulus
    return True


def _square_of(rows: Any, kinds: tuple[type, ...], entry: str) -> None:
    """Refuse anything but a square list of lists of ``kinds`` (python-flint numbers)."""
    if not (isinstance(rows, list) and all(isinstance(r, list) and len(r) == len(rows) for r in rows)
            and all(isinstance(v, kinds) for r in rows for v in r)):
        names = " or ".join(k.__name__ for k in kinds)
        raise InputError(f"{entry}: expected a square list of lists of python-flint {names}")


#: below this size :func:`schur_positive` eliminates entry by entry (:func:`pivots_positive`)
SCHUR_BLOCK = 48


def schur_positive(a: list[list[flint.arb]]) -> bool | None:
    """:func:`pivots_positive` on balls, by halves: the pivots of elimination without row exchanges
    are those of the leading block ``A11`` followed by those of its Schur complement ``A22 - A21
    A11^-1 A12``, whose balls (enclosing the exact complement) flint's certified solve and product
    give in C, where an entry-by-entry elimination runs in Python (docs/performance.md).  Not for
    rationals: an exact ``fmpq_mat`` solve swells."""
    _square_of(a, (flint.arb,), "a")
    k = len(a)
    if k <= SCHUR_BLOCK:
        return pivots_positive(a)
    h = k // 2
    leading = schur_positive([row[:h] for row in a[:h]])
    if leading is not True:
        return leading
    try:
        X = flint.arb_mat([row[:h] for row in a[:h]]).solve(flint.arb_mat([row[h:] for row in a[:h]]))
    except ZeroDivisionError:   # a ball of A11 too wide to certify it invertible
        return None
    return schur_positive((flint.arb_mat([row[h:] for row in a[h:]])
                            - flint.arb_mat([row[:h] for row in a[h:]]) * X).tolist())


def pivots_positive(a: list[list[Any]]) -> bool | None:
    """Whether every pivot of elimination without row exchanges is positive, in exact rationals
    (``fmpq``) or certified balls (``arb``, at their precision): a negative pivot decides False, a
    ball around zero leaves the answer open (None).  One elimination, not ``k`` determinants (the
    leading minors of a large certificate, each a determinant of its own, repeat that work ``k``
    times)."""
    _square_of(a, (flint.fmpq, flint.arb), "a")
    k = len(a)
    for i in range(k):
        pivot = a[i][i]
        if not pivot > 0:
            return False if pivot < 0 else None
        for r in range(i + 1, k):
            f = a[r][i] / pivot
            if f == 0:
                continue
            row, top = a[r], a[i]
            for j in range(i + 1, k):
                row[j] -= f * top[j]
    return True


check_public(globals())
