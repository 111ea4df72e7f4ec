"""The critical control-packet arrival rate of TCP-like LQG control, exact where proved, else certified.

Schenato, Sinopoli, Franceschetti, Poolla and Sastry, "Foundations of control and estimation over
lossy networks", Proc. IEEE 95(1), 2007, Section IV: with acknowledged control packets arriving
i.i.d. with probability ``nu`` (one channel carrying all inputs), the optimal cost stays bounded
iff the control MARE::

    S = A'SA + W - nu A'SB (B'SB + U)^{-1} B'SA

has a fixed point, i.e. iff ``nu > nu_c``.  The paper gives ``nu_c`` in closed form for one input
(``1 - 1/prod |lambda_u|^2``, after Elia 2005) and for square invertible ``B`` (``1 - 1/rho(A)^2``),
otherwise as a quasi-convex LMI problem.  ``W`` and ``U`` do not move ``nu_c`` (``W > 0`` assumed,
``U > 0``): it is the mean-square stabilizability threshold of ``x+ = A x + nu_k B u``.

**Lower side: the quotient bound (exact).**  For every ``A``-invariant subspace ``V`` the quotient
``(A_Q, B_Q)`` on ``R^n / V`` must be stabilizable too, and at a positive definite fixed point
``S`` of its MARE ``S > A_Q' S^(1/2) (I - nu Pi) S^(1/2) A_Q`` with ``Pi`` an orthogonal projection
of rank ``r = rank B_Q``; taking determinants, ``(1 - nu)^r |det A_Q|^2 < 1``.  So::

    nu_c >= max_Q 1 - |det A_Q|^(-2/r_Q)

over the quotients by sums of generalised eigenspaces (``proofs/control_quotient_bound.py``).  The
determinants are exact products of conjugate eigenvalues
(:func:`symkf.exact.algebraic.subset_product`); ``r_Q`` is the exact rank of ``h(A) B`` (``h`` the
characteristic polynomial's cofactor of the quotient) when the quotient is rational, and
``min(dim Q, rank B) >= r_Q`` otherwise (a larger rank only weakens the bound, so it stays sound).
One input gives ``r_Q = 1`` and the whole unstable part, ``1 - 1/prod |lambda_u|^2``; invertible
``B`` gives ``r_Q = dim Q`` and the top eigenvalue, ``1 - 1/rho(A)^2``: the paper's closed forms.

**Upper side: a rational gain, verified exactly.**  At a rational ``nu`` a rational gain ``K``
makes the loop mean-square stable iff the positive map ``T(S) = (1 - nu) A'SA + nu (A+BK)'S(A+BK)``
has spectral radius below one, iff ``S - T(S) = I`` has a positive definite solution: one exact
linear solve in the number field of ``A`` and ``B`` (:func:`stein_certificate`) and exact pivots.  The gain is the optimal one
at that ``nu``, from policy iteration (Hewer's algorithm, the policy-evaluation/improvement form
of the MARE) continued from ``nu = 1`` towards the quotient bound in 256-bit arithmetic (floats
only choose the gain; the verdict is the exact solve).  Whenever the certificate verifies at the
quotient bound plus the tolerance, the bracket is that narrow.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import flint
import sympy as sp

from .. import budget
from ..arguments import check_public
from ..errors import AssumptionError, InputError, NumericalBreakdownError, ShapeError
from ..exact.algebraic import AlgebraicNumber, subset_product, terminating_decimal, with_prec
from ..exact.linalg import field_of, positive_definite, rank, solve_rows
from ..exact.numbers import to_exact_matrix, to_rational
from ..exact.spectral import Eigenvalue, eigenvalues
from ..exact.text import algebraic_text
from ..model.system import System
from ..output import JsonDocument

#: bits of the arithmetic that computes the gain (not the verdict, which is exact)
_PREC = 256


@dataclass(frozen=True)
class Quotient:
    """A quotient of the plant by a sum of generalised eigenspaces, kept by the bound: the kept
    eigenvalues (with multiplicity), ``|det A_Q|^2`` exactly, the rank ``r`` of ``B_Q`` used and
    whether that rank is exact (a rational quotient) or the upper bound ``min(dim Q, rank B)``."""

    eigenvalues: tuple[Eigenvalue, ...]
    det2: AlgebraicNumber
    rank: int
    rank_exact: bool

    @property
    def dimension(self) -> int:
        return sum(e.multiplicity for e in self.eigenvalues)

    @property
    def bound(self) -> AlgebraicNumber:
        """``1 - |det A_Q|^(-2/r)``, exact."""
        return AlgebraicNumber.from_expr(1 - 1 / sp.root(self.det2.exact, self.rank))

    def words(self) -> str:
        shown = ", ".join(e.label + (f" (x{e.multiplicity})" if e.multiplicity > 1 else "") for e in self.eigenvalues)
        how = "exact" if self.rank_exact else "at most"
        return f"quotient on the eigenvalues {{{shown}}}, |det A_Q|^2 = {algebraic_text(self.det2)}, rank B_Q {how} {self.rank}"


def _modes(A: sp.MatrixBase) -> list[list[Eigenvalue]]:
    """The eigenvalues of modulus above one, a real one alone and a complex one with its conjugate
    (a real quotient keeps both)."""
    unstable = [e for e in eigenvalues(A) if e.modulus > 1]
    modes, seen = [], set()
    for e in unstable:
        if e.key in seen:
            continue
        if e.is_real:
            modes.append([e])
            seen.add(e.key)
            continue
        conj = next(o for o in unstable if o.key not in seen and o.key != e.key and o.minpoly == e.minpoly
                    and o.multiplicity == e.multiplicity and _conjugate(o, e))
        modes.append([e, conj])
        seen.update({e.key, conj.key})
    return modes


def _conjugate(a: Eigenvalue, b: Eigenvalue) -> bool:
    x, y = a.ball(128), b.ball(128)
    return bool((x.real - y.real).contains(0) and (x.imag + y.imag).contains(0))


def _det2(members: list[Eigenvalue]) -> AlgebraicNumber:
    """``prod |lambda|^(2 mult)`` over ``members`` (closed under conjugation), exact: per minimal
    polynomial the product of the chosen conjugates, squared."""
    out = AlgebraicNumber.from_expr(1)
    by_poly: dict[tuple[int, ...], list[Eigenvalue]] = {}
    for e in members:
        by_poly.setdefault(e.key[0], []).append(e)
    for group in by_poly.values():
        mult = group[0].multiplicity
        product = subset_product(group[0].minpoly, [e.root_index for e in group])
        out = out * product ** (2 * mult)
    return out


def _cofactor(A: sp.MatrixBase, members: list[Eigenvalue]) -> sp.Matrix | None:
    """``h(A)``, ``h`` the characteristic polynomial without the kept factors, when the quotient is
    rational (every conjugate of a kept eigenvalue kept), else None: ``h(A)`` has the kept
    generalised eigenspace as range and ``V`` as kernel, so ``B_Q`` is ``B`` seen through it."""
    polys = {e.key[0]: e for e in members}
    if any(sum(1 for m in members if m.key[0] == k) != e.minpoly.degree() for k, e in polys.items()):
        return None
    x = sp.Symbol("x")
    kept = sp.Mul(*[sp.Poly(list(reversed([int(c) for c in e.minpoly.coeffs()])), x).as_expr() ** e.multiplicity
                    for e in polys.values()])
    h = sp.Poly(sp.quo(A.charpoly(x).as_expr(), kept, x), x)
    H = sp.zeros(*A.shape)
    for c in h.all_coeffs():
        H = H * A + c * sp.eye(A.shape[0])
    return H


def _quotient_rank(H: sp.Matrix | None, B: sp.MatrixBase, dimension: int) -> tuple[int, bool]:
    """``rank B_Q`` and whether it is exact: ``rank h(A) B`` for a rational quotient (``H`` from
    :func:`_quotients`), else the upper bound ``min(dim Q, rank B)`` (sound: a larger rank weakens
    the bound)."""
    if H is None:
        return min(dimension, rank(B)), False
    return rank(H * B), True


def _quotients(A: sp.Matrix) -> list[tuple[list[Eigenvalue], AlgebraicNumber, sp.Matrix | None]]:
    """Every quotient by a sum of generalised eigenspaces that keeps only eigenvalues of modulus
    above one: its eigenvalues, ``|det A_Q|^2`` exactly and ``h(A)`` when rational (else None).
    ``2^u`` of them for ``u`` unstable modes (a real eigenvalue or a conjugate pair), capped by
    ``max_patterns``."""
    modes = _modes(A)
    budget.check_power("max_patterns", 2, len(modes), "A", f"the number 2^{len(modes)} of quotients of "
                       f"{len(modes)} unstable modes searched by the quotient bound")
    budget.price("symkf.control.quotient_bound",
                 lambda: f"the quotient bound's {2 ** len(modes) - 1} quotients of {len(modes)} unstable modes (each an "
                         f"exact product of conjugate eigenvalues, of its compound degree, and a cofactor h(A), "
                         f"{A.rows} x {A.rows})",
                 quotient_degree=_compound_degrees(modes), quotient_entry=(2 ** len(modes) - 1) * A.rows ** 2)
    out = []
    for k in range(1, len(modes) + 1):
        for chosen in itertools.combinations(modes, k):
            members = [e for mode in chosen for e in mode]
            out.append((members, _det2(members), _cofactor(A, members)))
    return out


def _compound_degrees(modes: list[list[Eigenvalue]]) -> float:
    """The sum over every quotient of :func:`_quotients` of ``C(D, k)^1.5`` for its products of ``k``
    of the ``D`` conjugates of a minimal polynomial (:func:`_det2`: isolating the roots of a product
    of degree ``C(D, k)`` costs about so, measured on dense plants of 8 to 12 states), counted
    without listing the quotients: per minimal polynomial, the number of its mode sets keeping ``k``
    roots is the coefficient of ``x^k`` in ``prod (1 + x^size)`` over its modes, and each goes with
    every set of the other modes."""
    groups: dict[tuple[int, ...], list[list[Eigenvalue]]] = {}
    for mode in modes:
        groups.setdefault(mode[0].key[0], []).append(mode)
    total = 0.0
    for group in groups.values():
        counts = [1]
        for mode in group:
            size = len(mode)
            counts = [a + (counts[k - size] if k >= size else 0) for k, a in enumerate(counts + [0] * size)]
        degree = group[0][0].minpoly.degree()
        total += sum(c * math.comb(degree, k) ** 1.5 for k, c in enumerate(counts) if k) * 2.0 ** (len(modes) - len(group))
    return total


def quotient_bound(A: Any, B: Any) -> Quotient | None:
    """The quotient whose bound ``1 - |det A_Q|^(-2/r_Q)`` is largest (module doc), or None when
    ``A`` has no eigenvalue of modulus above one (``nu_c = 0``).

    >>> quotient_bound([[2, 0], [0, 3]], [[1], [1]]).bound.exact     # one input: 1 - 1/(2 * 3)^2
    35/36
    """
    A, B = _plant_matrices(A, B)
    best: Quotient | None = None
    for members, det2, H in _quotients(A):
        r, exact = _quotient_rank(H, B, sum(e.multiplicity for e in members))
        if r == 0:
            continue   # an unreachable unstable quotient: refused by stabilizability
        # compare det2^(1/r) exactly: a^(1/r) > b^(1/s) iff a^s > b^r
        if best is None or det2 ** best.rank > best.det2 ** r:
            best = Quotient(tuple(members), det2, r, exact)
    return best


# -- the upper side: a gain from policy iteration, verified in exact rationals ----------------

def _plant_matrices(A: Any, B: Any) -> tuple[sp.Matrix, sp.Matrix]:
    """``A`` (square) and ``B`` (as many rows) as exact matrices, or the entry that breaks them."""
    A, B = sp.Matrix(to_exact_matrix(A, "A")), sp.Matrix(to_exact_matrix(B, "B"))
    if A.rows != A.cols or A.rows == 0:
        raise ShapeError(f"A: must be square and non-empty, got {A.rows}x{A.cols}")
    if B.rows != A.rows or B.cols == 0:
        raise ShapeError(f"B: must have {A.rows} rows (A is {A.rows}x{A.rows}) and a column, got {B.rows}x{B.cols}")
    return A, B


def _arb_matrix(M: sp.MatrixBase) -> flint.arb_mat:
    return flint.arb_mat([[flint.arb(str(sp.N(v, _PREC // 3))) for v in M.row(i)] for i in range(M.rows)])


def _mid(M: flint.arb_mat) -> flint.arb_mat:
    return M.mid()


def _eye(n: int) -> flint.arb_mat:
    out = flint.arb_mat(n, n)
    for i in range(n):
        out[i, i] = 1
    return out


def _kron(X: flint.arb_mat, Y: flint.arb_mat) -> flint.arb_mat:
    n, m = X.nrows(), Y.nrows()
    out = flint.arb_mat(n * m, n * m)
    for i in range(n):
        for j in range(n):
            x = X[i, j]
            if x == 0:
                continue
            for k in range(m):
                for l in range(m):
                    out[i * m + k, j * m + l] = x * Y[k, l]
    return out


def _vec(S: flint.arb_mat) -> flint.arb_mat:
    n = S.nrows()
    return flint.arb_mat([[S[i, j]] for j in range(n) for i in range(n)])


def _unvec(v: flint.arb_mat, n: int) -> flint.arb_mat:
    return flint.arb_mat([[v[j * n + i, 0] for j in range(n)] for i in range(n)])


class _Plant:
    """``A, B, W, U`` at 256 bits, with the policy evaluation and improvement of Hewer's algorithm."""

    def __init__(self, A: sp.MatrixBase, B: sp.MatrixBase, W: sp.MatrixBase, U: sp.MatrixBase):
        self.n = A.rows
        self.A, self.B, self.W, self.U = (_arb_matrix(M) for M in (A, B, W, U))
        self.AtA = _kron(self.A.transpose(), self.A.transpose())

    def evaluate(self, K: flint.arb_mat, nu: flint.arb) -> flint.arb_mat | None:
        """The cost matrix ``S = W + nu K'UK + (1 - nu) A'SA + nu (A+BK)'S(A+BK)`` of the gain ``K``,
        or None when the loop is not mean-square stable (no positive definite ``S``)."""
        Acl = self.A + self.B * K
        n = self.n
        M = _eye(n * n) - (1 - nu) * self.AtA - nu * _kron(Acl.transpose(), Acl.transpose())
        rhs = _vec(self.W + nu * K.transpose() * self.U * K)
        try:
            S = _mid(_unvec(_mid(M).solve(rhs), n))
        except ZeroDivisionError:
            return None
        return S if _positive_float(S) else None

    def improve(self, S: flint.arb_mat) -> flint.arb_mat | None:
        """``K = -(B'SB + U)^{-1} B'SA``; None when the working precision cannot solve it (a cost
        matrix of a barely stabilizing gain, whose entries span more than its 256 bits)."""
        Bt = self.B.transpose()
        try:
            return _mid(-(Bt * S * self.B + self.U).solve(Bt * S * self.A))
        except ZeroDivisionError:
            return None

    def optimal(self, K: flint.arb_mat, nu: flint.arb) -> flint.arb_mat | None:
        """Policy iteration from the stabilizing ``K`` to the optimal gain at ``nu`` (None: ``K`` does
        not stabilize at ``nu``)."""
        return self.iterate(K, lambda gain: self.evaluate(gain, nu))

    def iterate(self, K: flint.arb_mat, cost: Any) -> flint.arb_mat | None:
        """Hewer's policy iteration: ``K <- -(B'SB + U)^{-1} B'SA`` with ``S = cost(K)`` (the cost
        matrix the next command sees, None when ``K`` does not stabilize), to a fixed point."""
        for _ in range(60):
            S = cost(K)
            new = None if S is None else self.improve(S)
            if new is None:
                return None
            change = max(abs(float((new[i, j] - K[i, j]).mid())) for i in range(K.nrows()) for j in range(K.ncols()))
            K = new
            if change < 2.0 ** (-_PREC // 2):
                break
        return K


def _positive_float(S: flint.arb_mat) -> bool:
    import numpy as np
    F = np.array([[float(S[i, j].mid()) for j in range(S.ncols())] for i in range(S.nrows())])
    if not np.all(np.isfinite(F)):
        return False
    return bool(np.linalg.eigvalsh((F + F.T) / 2)[0] > 0)


def _lqr_gain(plant: _Plant) -> flint.arb_mat:
    """A stabilizing gain at ``nu = 1``: the Riccati difference equation from ``S = W`` (value
    iteration converges for a stabilizable plant with ``W > 0``), then polished by policy iteration."""
    S = plant.W
    for _ in range(5000):
        K = plant.improve(S)
        if K is None:
            break
        Acl = plant.A + plant.B * K
        new = _mid(plant.W + K.transpose() * plant.U * K + Acl.transpose() * S * Acl)
        if plant.evaluate(K, flint.arb(1)) is not None:
            polished = plant.optimal(K, flint.arb(1))
            if polished is not None:
                return polished
        S = new
    raise NumericalBreakdownError("the Riccati difference equation found no stabilizing gain at nu = 1 "
                                  "in 5000 steps")


def _dyadic(M: flint.arb_mat, bits: int = 160) -> sp.ImmutableMatrix:
    """The midpoints of ``M`` rounded down to multiples of ``2^-bits``: the certificate's rational gain."""
    return sp.ImmutableMatrix([[_round(M[i, j], bits) for j in range(M.ncols())] for i in range(M.nrows())])


def _round(x: flint.arb, bits: int) -> sp.Rational:
    scaled = (x.mid() * flint.arb(2) ** bits).floor().mid()
    return sp.Rational(int(scaled.unique_fmpz()), 2 ** bits)


def stein_certificate(equations: list[list[tuple[int, Any, sp.MatrixBase]]], n: int
                      ) -> list[sp.ImmutableMatrix] | None:
    """Exact: matrices ``S_i > 0`` solving ``S_i - sum_(j, c, M) c M' S_j M = I`` for every ``i``
    (``equations[i]`` lists the terms ``(j, c, M)``: rational ``c``, ``n x n`` exact ``M``), over the
    number field of the ``M``'s entries; None when the solution is not positive definite or the
    system is singular.  A positive map ``S -> (sum_j c M' S_j M)_i`` with such a solution has spectral
    radius below one: the second moments of the loop it describes decay."""
    budget.check("max_dimension", n * len(equations), "A", "the size of the certificate's matrices (an "
                 "(n k)^2 x (n k)^2 exact solve for k coupled matrices)")
    field = field_of(*[M for terms in equations for _, _, M in terms])
    budget.check("max_cyclotomic_degree", field.degree, "A", "the degree of the field of the plant's entries, in "
                 "which the certificate is solved")
    k, one = len(equations), flint.fmpq_poly([1])
    size = k * n * n
    rows = [[flint.fmpq_poly([]) for _ in range(size)] for _ in range(size)]
    for i, terms in enumerate(equations):
        for t in range(n * n):
            rows[i * n * n + t][i * n * n + t] += one
        for j, c, M in terms:
            E = field.matrix(sp.Matrix(M))
            coef = field.convert(c)
            for a in range(n):
                for e in range(n):
                    row = rows[i * n * n + a * n + e]
                    for b in range(n):
                        if E[b][a].is_zero():
                            continue
                        left = field.mul(coef, E[b][a])
                        for d in range(n):
                            if not E[d][e].is_zero():
                                row[j * n * n + b * n + d] -= field.mul(left, E[d][e])
    rhs = [one if (t // n == t % n) else flint.fmpq_poly([]) for _ in range(k) for t in range(n * n)]
    try:
        x = solve_rows(field, rows, rhs)
    except ZeroDivisionError:
        return None
    blocks = [[[x[i * n * n + a * n + e] % field.modulus for e in range(n)] for a in range(n)] for i in range(k)]
    if not all(positive_definite(field, S) for S in blocks):
        return None
    return [sp.ImmutableMatrix([[field.to_sympy(v) for v in row] for row in S]) for S in blocks]


def lyapunov_certificate(A: Any, B: Any, K: Any, nu: Any) -> sp.ImmutableMatrix | None:
    """Exact: the solution ``S`` of ``S - (1 - nu) A'SA - nu (A+BK)'S(A+BK) = I`` when it is positive
    definite (then the loop ``x+ = (A + nu_k B K) x`` is mean-square stable at arrival rate ``nu``:
    the positive map has spectral radius below one), else None (:func:`stein_certificate`).

    >>> lyapunov_certificate([[2]], [[1]], [[-2]], "4/5")     # (1 - 4/5) 4 = 4/5 < 1: S = 1/(1 - 4/5)
    Matrix([[5]])
    """
    A, B = _plant_matrices(A, B)
    K = sp.Matrix(to_exact_matrix(K, "K"))
    if K.shape != (B.cols, A.rows):
        raise ShapeError(f"K: must be {B.cols}x{A.rows} (inputs x states), got {K.rows}x{K.cols}")
    nu = to_rational(nu, "nu")
    if not 0 <= nu <= 1:
        raise InputError(f"nu: an arrival rate lies in [0, 1], got {nu}")
    found = stein_certificate([[(0, 1 - nu, A), (0, nu, A + B * K)]], A.rows)
    return None if found is None else found[0]


def _certified_upper(A: sp.MatrixBase, B: sp.MatrixBase, W: sp.MatrixBase, U: sp.MatrixBase,
                     lower: AlgebraicNumber, tolerance: Fraction
                     ) -> tuple[Fraction, sp.ImmutableMatrix, sp.ImmutableMatrix]:
    """The least rational ``nu`` found, at most ``lower + tolerance`` when the bound is tight, with a
    rational gain whose loop is verified mean-square stable there (:func:`lyapunov_certificate`) and
    the certificate ``S``.  Continuation: ``nu`` falls from 1 towards ``lower + tolerance / 2``, the
    gap shrinking fourfold per step and halved back when the previous gain no longer stabilizes;
    a gap that stops shrinking means ``nu_c`` lies above the bound."""
    return with_prec(_PREC, lambda: _continued(A, B, W, U, lower, tolerance))


def _continued(A, B, W, U, lower: AlgebraicNumber, tolerance: Fraction):
    plant = _Plant(A, B, W, U)
    K = _lqr_gain(plant)
    low = Fraction(lower.interval[1])
    target = low + tolerance / 2
    nu = Fraction(1)
    certified = _verified(A, B, K, nu)
    if certified is None:
        raise NumericalBreakdownError("the gain of the deterministic Riccati equation failed its exact check at nu = 1")
    best = (nu, *certified)
    while nu > target:
        step = max((nu - low) * 3 / 4, nu - target) if nu - target > 0 else Fraction(0)
        step = min(step, nu - target)
        for _ in range(40):
            trial = nu - step
            found = plant.optimal(K, flint.arb(trial.numerator) / trial.denominator)
            if found is not None:
                break
            step /= 2
        else:
            break   # the gap stopped shrinking: nu_c is above the bound
        nu, K = trial, found
        certified = _verified(A, B, K, _nice_above(nu, low, tolerance))
        if certified is not None:
            best = (_nice_above(nu, low, tolerance), *certified)
    return best


def _nice_above(nu: Fraction, low: Fraction, tolerance: Fraction) -> Fraction:
    """A short rational in ``[nu, nu + (nu - low) / 8]``: the certificate's rate (a decimal reads well)."""
    slack = max((nu - low) / 8, tolerance / 16)
    digits = max(1, -math.floor(math.log10(slack)) + 1)
    return Fraction(math.ceil(nu * 10 ** digits), 10 ** digits)


def _verified(A, B, K: flint.arb_mat, nu: Fraction) -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix] | None:
    Kq = _dyadic(K)
    S = lyapunov_certificate(A, B, Kq, sp.Rational(nu.numerator, nu.denominator))
    return None if S is None else (Kq, S)


def _decimal(q: Fraction) -> str:
    """A rational rate as people read it: its exact decimal when it has one (the certificate's rates
    do), else the fraction."""
    d = terminating_decimal(q)
    return str(q) if d is None else str(d)


CLOSED_FORMS = {
    "one input": "rank B = 1: nu_c = 1 - 1/prod|lambda_u|^2 (Elia 2005; Schenato et al. 2007, Section IV)",
    "B invertible": "B square invertible: nu_c = 1 - 1/rho(A)^2 (Schenato et al. 2007, Section IV)",
}


@dataclass(frozen=True, repr=False)
class ControlThreshold(JsonDocument):
    """The critical arrival rate ``nu_c`` of the control packets (TCP-like, one channel for all inputs).

    ``lower`` is the quotient bound (exact, proved: module doc), attained by ``quotient``;
    ``upper`` a rational rate at which the rational ``gain`` is verified to stabilize the loop in
    mean square (``certificate`` is the exact ``S > 0`` with ``S - T(S) = I``), so
    ``lower <= nu_c < upper``.  ``closed_form`` names the paper's closed form when it applies; then
    ``nu_c = lower`` is ``exact``.  ``reached`` says whether ``upper - lower <= tolerance``."""

    lower: AlgebraicNumber
    upper: Fraction
    quotient: Quotient | None
    gain: sp.ImmutableMatrix
    certificate: sp.ImmutableMatrix = field(compare=False)
    tolerance: Fraction
    closed_form: str | None = None
    A: sp.ImmutableMatrix = field(default=None, compare=False)
    B: sp.ImmutableMatrix = field(default=None, compare=False)

    @property
    def exact(self) -> AlgebraicNumber | None:
        """``nu_c`` exactly when a proved closed form applies (it equals the quotient bound), else None."""
        return self.lower if self.closed_form else None

    @property
    def width(self) -> Fraction:
        """``upper`` minus the lower end of ``lower``'s exact rational interval (an upper bound on the
        bracket's width)."""
        return self.upper - Fraction(self.lower.interval[0])

    @property
    def reached(self) -> bool:
        return self.width <= self.tolerance

    @property
    def critical_loss_rate(self) -> AlgebraicNumber | None:
        """``1 - nu_c`` (the control channel's critical loss probability) when exact."""
        return None if self.exact is None else 1 - self.exact

    def decides(self, nu: Any) -> bool | None:
        """Whether the loop is stabilizable at arrival rate ``nu``, exactly: False at or below the
        bound, True from ``upper`` on or, when ``nu_c`` is exact, anywhere above it; None inside an
        open bracket."""
        v = to_rational(nu, "nu")
        if not 0 <= v <= 1:
            raise InputError(f"nu: an arrival rate lies in [0, 1], got {v}")
        if not self.lower < v:
            return False
        if self.exact is not None or Fraction(int(v.p), int(v.q)) >= self.upper:
            return True
        return None

    def check(self) -> bool:
        """Re-verify the certificate exactly: ``S > 0`` and ``S - T(S) = I`` at ``upper`` (the map of the
        module doc with this gain); False if either fails."""
        S = lyapunov_certificate(self.A, self.B, self.gain, sp.Rational(self.upper.numerator, self.upper.denominator))
        return S is not None and S == self.certificate

    def __str__(self) -> str:
        low, up = algebraic_text(self.lower), _decimal(self.upper)
        if self.exact is not None:
            return f"nu_c = {low} exactly ({self.closed_form}); certified: loop stable at nu = {up}"
        state = (f"width {float(self.width):.2g} <= tolerance {float(self.tolerance):.2g}" if self.reached else
                 f"width {float(self.width):.3g} above the tolerance {float(self.tolerance):.2g}: no gain found "
                 f"closer to the bound")
        return f"nu_c in [{low}, {up}] ({state})"

    __repr__ = __str__

    def to_dict(self) -> dict[str, Any]:
        return {"quantity": "critical control-packet arrival rate nu_c (TCP-like, one channel)",
                "lower": self.lower.to_dict(), "upper": str(self.upper), "width_at_most": str(self.width),
                "tolerance": str(self.tolerance), "reached": self.reached,
                "exact": None if self.exact is None else self.exact.to_dict(),
                "closed_form": self.closed_form,
                "quotient": None if self.quotient is None else self.quotient.words(),
                "gain": [[str(v) for v in self.gain.row(i)] for i in range(self.gain.rows)]}

    def _repr_latex_(self) -> str:
        if self.exact is not None:
            return rf"$\nu_c = {sp.latex(self.lower.exact)}$"
        return rf"$\nu_c \in [{sp.latex(self.lower.exact)},\ {sp.latex(sp.Rational(self.upper.numerator, self.upper.denominator))}]$"


def critical_arrival_rate(system: System, tolerance: Any = "1e-12") -> ControlThreshold:
    """``nu_c`` of TCP-like LQG control with every input on one lossy channel (Schenato et al. 2007,
    Section IV): exact when a closed form is proved (one input; ``B`` square invertible), otherwise a
    certified bracket ``[lower, upper)`` (module doc) aimed at width ``tolerance``.

    Parameters
    ----------
    system : System
        With actuators (``system.B``); ``(A, B)`` must be stabilizable.
    tolerance : exact number in (0, 1), default ``1e-12``
        The bracket's aimed width; the result says whether it was reached (``.reached``).

    Raises
    ------
    UncontrollableError
        An eigenvalue of modulus at least one that no actuator reaches (no rate stabilizes).
    BudgetError
        The plant's dimension or its entries' field is above its cap (the certificate's exact solve).

    Examples
    --------
    A scalar plant ``a = 2`` with one input: ``nu_c = 1 - 1/a^2 = 3/4``:

    >>> import symkf as sk
    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])
    >>> t = sk.control.critical_arrival_rate(S)
    >>> t.exact.exact, t.reached, t.check()
    (3/4, True, True)
    """
    tol = to_rational(tolerance, "tolerance")
    if not 0 < tol < 1:
        raise InputError(f"tolerance: must lie in (0, 1), got {tol}")
    if not system.actuators:
        raise InputError("system: has no actuators; give System(..., actuators=[Actuator(B=...)])")
    key = ("control_threshold", tol)
    if key not in system._cache:   # analyze asks once for the threshold and once for the loop's verdict
        system._cache[key] = _threshold(system, Fraction(int(tol.p), int(tol.q)))
    return system._cache[key]


def exact_plant(system: System) -> tuple[sp.ImmutableMatrix, sp.ImmutableMatrix]:
    """``(A, B)`` of a plant with actuators, stabilizable (:meth:`System.check_stabilizable`)."""
    system.check_stabilizable()
    return sp.ImmutableMatrix(system.A), sp.ImmutableMatrix(system.B)


#: the exact certificates (:func:`lyapunov_certificate`) and policy evaluations (:class:`_Plant`, a
#: solve of the n^2 coordinates of S in 256-bit balls) a continuation is priced at: it verifies one
#: gain per step of a gap shrinking about fourfold, and evaluates a few policies per step (2 to 21
#: certificates and up to 126 evaluations on plants of 4 to 12 states)
VERIFICATIONS, EVALUATIONS = 16, 128


def _threshold(system: System, tol: Fraction) -> ControlThreshold:
    A, B = exact_plant(system)
    n, degree = A.rows, field_of(A, B).degree
    # each is a dense system in the n^2 entries of S: (n^2)^3, over a field of degree D (D^2)
    budget.price("symkf.control.critical_arrival_rate",
                 lambda: f"the continuation towards the quotient bound ({VERIFICATIONS} exact certificates over a "
                         f"field of degree {degree} and {EVALUATIONS} policy evaluations, each a solve in the n^2 = "
                         f"{n * n} entries of S)",
                 stein_entry=VERIFICATIONS * (n * n * degree) ** 2 * n * n, policy_entry=EVALUATIONS * n ** 6)
    quotient = quotient_bound(A, B)
    lower = AlgebraicNumber.from_expr(0) if quotient is None else quotient.bound
    upper, gain, certificate = _certified_upper(A, B, sp.Matrix(system.W), sp.Matrix(system.U), lower, tol)
    rank_B = rank(B)
    closed = (CLOSED_FORMS["one input"] if rank_B == 1 else
              CLOSED_FORMS["B invertible"] if B.rows == B.cols == rank_B else None)
    return ControlThreshold(lower, upper, quotient, gain, certificate, tol, closed, A, B)


check_public(globals())
