"""Plant data for the network conditions: ``A(k)`` as a periodic sequence, ``C_m``, norms (Quevedo et al.).

``A(k)`` is given as one matrix (LTI) or a finite list ``A(0), ..., A(T-1)``
repeated periodically (eq. 1 with deterministic bounded ``A(k)``).
``Phi(l, k) = A(l-1) ... A(k)`` (Sec. VII-B).  Spectral norms are exact real
algebraic numbers: ``||M||^2`` is the largest eigenvalue of ``M^T M``.
"""

from __future__ import annotations

import numbers
from fractions import Fraction
from typing import Any, Sequence

import sympy as sp

from .. import budget
from ..arguments import check_public, described
from ..errors import InputError, ShapeError
from ..exact.algebraic import AlgebraicNumber, real_from_ball, sign
from ..exact.numbers import as_matrix, to_exact_matrix
from ..model.system import System
from ..exact.spectral import eigenvalues


class PeriodicDynamics:
    """``A(k) = A[k mod T]`` and the sensor blocks ``C_1..C_M`` (relays: all-zero ``C``)."""

    def __init__(self, A: Any, C: Sequence[Any]):
        A = [A] if _is_matrix(A) else A
        if isinstance(A, (str, bytes)) or not isinstance(A, Sequence) or not A:
            raise InputError("A: expected a square matrix or a non-empty list of them (one period of A(k))")
        self.A = tuple(to_exact_matrix(a, f"A({k})") for k, a in enumerate(A))
        n = self.A[0].shape[0]
        for k, a in enumerate(self.A):
            if a.shape != (n, n):
                raise ShapeError(f"A({k}): expected {n}x{n}, got {a.shape[0]}x{a.shape[1]}")
        self.n, self.T = n, len(self.A)
        if isinstance(C, (str, bytes)) or not isinstance(C, Sequence) or not C:
            raise InputError("C: expected one observation matrix per sensor node")
        self.C = tuple(to_exact_matrix(c, f"C_{m}") for m, c in enumerate(C, start=1))
        for m, c in enumerate(self.C, start=1):
            if c.shape[1] != n:
                raise ShapeError(f"C_{m}: has {c.shape[1]} columns, A(k) is {n}x{n}")

    @classmethod
    def from_system(cls, system: System, A: Any = None) -> "PeriodicDynamics":
        """The sensors' ``C_m`` of a :class:`~symkf.model.system.System`; ``A`` defaults to ``system.A``."""
        return cls(system.A if A is None else A, [s.C for s in system.sensors])

    @property
    def M(self) -> int:
        """Number of sensor nodes ``M``."""
        return len(self.C)

    def A_at(self, k: int) -> sp.ImmutableMatrix:
        """``A(k)``: the periodic system matrix at time ``k``."""
        return self.A[k % self.T]

    def Phi(self, l: int, k: int) -> sp.ImmutableMatrix:
        """``Phi(l, k) = A(l-1) A(l-2) ... A(k)``, ``Phi(k, k) = I``."""
        if not isinstance(l, numbers.Integral) or not isinstance(k, numbers.Integral) or l < k:
            raise InputError(f"Phi(l, k): expected integers l >= k, got {described(l)} and {described(k)}")
        budget.check("max_exponent", l - k, "l - k", "the number of factors A(t) of Phi(l, k)")
        out = sp.eye(self.n)
        for t in range(k, l):
            out = self.A_at(t) * out
        return sp.ImmutableMatrix(out)

    def C_of(self, theta: Sequence[int]) -> sp.Matrix:
        """``C(k) = col(theta_1 C_1, ..., theta_M C_M)`` (eq. 14)."""
        return sp.Matrix.vstack(*[c if t else sp.zeros(*c.shape) for c, t in zip(self.C, theta)])


def _is_matrix(A: Any) -> bool:
    """One matrix (sympy, or a list of rows of numbers) rather than a list of matrices."""
    if isinstance(A, sp.MatrixBase):
        return True
    return (isinstance(A, Sequence) and bool(A) and isinstance(A[0], Sequence)
            and not isinstance(A[0], str) and bool(A[0])
            and (isinstance(A[0][0], str) or not isinstance(A[0][0], Sequence)))


def spectral_norm_squared(M: sp.MatrixBase) -> AlgebraicNumber:
    """``||M||^2``, the largest eigenvalue of ``M^T M`` (all real: the matrix is symmetric), as an
    exact algebraic number (the engine's eigenvalues: flint's characteristic polynomial over the
    entries' field, not sympy's charpoly, which simplifies every coefficient, slow even for a 2x2
    rotation by 2 pi/11)."""
    M = as_matrix(M, "M")
    return max(real_from_ball(e.minpoly, e.root_index) for e in eigenvalues(M.T * M))


def certified_less_than_one(coeffs: Sequence[sp.Expr], values: Sequence[AlgebraicNumber],
                            width: Fraction = Fraction(1, 10 ** 60)) -> bool:
    """Decide ``sum_i c_i v_i < 1`` exactly for rationals ``c_i >= 0`` and algebraic ``v_i >= 0``.

    Interval sums separate the sum from 1 unless it equals 1 to within
    ``width``; then the exact sign of the sympy expression decides.
    """
    step = Fraction(1, 1000)
    while True:
        lo = sum(Fraction(int(c.p), int(c.q)) * v.refine(step).interval[0] for c, v in zip(coeffs, values))
        hi = sum(Fraction(int(c.p), int(c.q)) * v.interval[1] for c, v in zip(coeffs, values))
        if hi < 1:
            return True
        if lo >= 1:
            return False
        if step < width:
            return sign(sum(c * v.exact for c, v in zip(coeffs, values)) - 1) < 0
        step /= 10 ** 6


def interval_sum(coeffs: Sequence[sp.Expr], values: Sequence[AlgebraicNumber],
                 step: Fraction = Fraction(1, 10 ** 20)) -> tuple[Fraction, Fraction]:
    """Exact rational bounds on ``sum_i c_i v_i`` (``c_i >= 0`` rational)."""
    lo = sum((Fraction(int(c.p), int(c.q)) * v.refine(step).interval[0] for c, v in zip(coeffs, values)),
             Fraction(0))
    hi = sum((Fraction(int(c.p), int(c.q)) * v.interval[1] for c, v in zip(coeffs, values)), Fraction(0))
    return lo, hi

check_public(globals())
