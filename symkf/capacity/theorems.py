"""Capacity conditions for the upper bound: Theorems 5-7, Corollaries 1-2, Lemma 2 (Yang et al., III-D, III-E).

**Wonham decomposition (eq. 26).**  Rows ``h_1, h_2, ...`` of the sensors are
taken in order; ``U_k`` is the unobservable subspace of ``(col(h_1..h_k), A)``
(A-invariant, ``U_0 = R^n``).  A row with ``dim U_{k-1} > dim U_k`` opens a
block ``A_k``: the map ``A`` induces on ``U_{k-1} / U_k``.  In the basis
``T = [V_1, V_2, ...]`` (``V_k`` completing a basis of ``U_k`` to one of
``U_{k-1}``) ``T^{-1} A T`` is block lower triangular with diagonal blocks
``A_k``; rows that enlarge nothing open no block.  Yang et al. draw the
transformed ``H`` block diagonal; in general it is block lower triangular
(row ``k`` sees blocks ``1..k``), which changes nothing in (27): only the
Mahler measures ``M(A_k)`` enter.  Condition 1) of Theorem 4 depends on each
sensor's row space only (``L_i H_i = (L_i T^{-1})(T H_i)``), so the rows of
``C_i`` are used instead of those of ``H_i = R_i^{-1/2} C_i``.

**Theorem 5** (as proved in the appendix): if every sensor has
``C_i > r_i = max_j h(A_ij)`` then ``V_k`` converges for these rates; hence
a capacity budget ``C > sum_i r_i`` (27), in particular ``C > h(A)`` (28,
because ``sum_i r_i <= h(A)``; the appendix's strict ``>`` is a slip), can be
*allocated* so that ``V_k`` converges (Theorem 6).  The sentence "if (28),
``{V_k}`` converges" is false read for the given rates: two scalar sensors
``c = 1`` on ``a = 2`` with ``lambda_1 = lambda_2 = 11/20`` have ``C > ln 2 = h(A)``
but ``V_k`` diverges (``a^2 < 1 + q_1 + q_2`` is needed); see
``proofs/yang_theorem5_reading.py``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .. import budget
from ..arguments import check_public
from ..errors import AssumptionError, InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.linalg import field_of, rank
from ..exact.numbers import to_exact_matrix
from ..model.iid import IID
from ..model.loss import LossModel
from ..model.system import System
from ..exact.spectral import eigenvalues
from .quantities import _require_iid, mahler_measure, spectral_radius


@dataclass(frozen=True)
class WonhamDecomposition:
    """``T^{-1} A T`` block lower triangular; ``blocks[k] = (sensor, row, A_k)`` (eq. 26)."""

    T: sp.ImmutableMatrix
    A_tilde: sp.ImmutableMatrix
    blocks: tuple[tuple[int, int, sp.ImmutableMatrix], ...]

    def requirement(self, sensor: int) -> AlgebraicNumber:
        """``exp(r_i) = max_j M(A_ij)`` over the blocks of ``sensor`` (1 if it opens none)."""
        return max([mahler_measure(B) for s, _, B in self.blocks if s == sensor] + [AlgebraicNumber.from_expr(1)])


def _unobservable(rows: list[sp.Matrix], A: sp.Matrix) -> list[sp.Matrix]:
    n = A.shape[0]
    obs = sp.Matrix.vstack(*[r * A ** k for r in rows for k in range(n)])
    return obs.nullspace()


def wonham_decomposition(system: System, order: list[tuple[int, int]] | None = None) -> WonhamDecomposition:
    """The decomposition of eq. 26 with rows taken in ``order`` ((sensor, row) pairs; default: all, in order).

    Raises :class:`AssumptionError` when the chosen rows leave ``(H, A)`` unobservable.
    """
    A = sp.Matrix(system.A)
    n = system.n
    # computed with sympy's linear algebra on the entries (rref, inverses), whose cost explodes with
    # the degree of their field as a generic field's does: priced by max_degree (four cyclotomic
    # fields, degree 1440, did not end)
    budget.check("max_degree", field_of(system.A, system.C).degree, "A", "the degree of the field of A's and C's "
                 "entries, in which the decomposition is computed")
    order = order or [(i, r) for i, s in enumerate(system.sensors) for r in range(s.m)]
    rows: list[sp.Matrix] = []
    U = [sp.eye(n)[:, k] for k in range(n)]
    V_all, blocks = [], []
    for i, r in order:
        if not U:   # observable: no later row opens a block (an exact nullspace for each row to the
            break   # last would be wasted work, and costly at many sensors)
        rows.append(system.sensors[i].C[r, :])
        new = _unobservable(rows, A)
        if len(new) == len(U):
            continue
        V = []  # complete a basis of U_k to one of U_{k-1}
        for u in U:
            if rank(sp.Matrix.hstack(*(new + V + [u]))) > len(new) + len(V):
                V.append(u)
        B = sp.Matrix.hstack(*(V + new))
        M = (B.T * B).inv() * B.T * A * B
        blocks.append((i, r, sp.ImmutableMatrix(M[:len(V), :len(V)])))
        V_all += V
        U = new
    if U:
        raise AssumptionError("the chosen rows leave an unobservable subspace of dimension "
                              f"{len(U)}", assumption="(H, A) observable (Yang et al., Theorem 5)")
    T = sp.Matrix.hstack(*V_all)
    return WonhamDecomposition(sp.ImmutableMatrix(T), sp.ImmutableMatrix(T.inv() * A * T), tuple(blocks))


def theorem5_requirements(system: System, order: list[tuple[int, int]] | None = None) -> tuple[sp.Expr, ...]:
    """``r_i = max_j h(A_ij)`` per sensor (exact logs): ``C_i > r_i`` for all ``i`` makes ``V_k`` converge."""
    dec = wonham_decomposition(system, order)
    return tuple(sp.log(dec.requirement(i).exact) for i in range(system.d))


def theorem5_sufficient(system: System, loss: LossModel, order: list[tuple[int, int]] | None = None) -> bool:
    """Exactly whether ``C_i > max_j h(A_ij)`` for every sensor (the appendix's hypothesis): then ``V_k`` converges.

    ``C_i > ln x`` iff ``1 / loss_i > x^2``.
    """
    losses = _require_iid(loss)
    dec = wonham_decomposition(system, order)
    return all(e == 0 or AlgebraicNumber.from_expr(1 / e) > AlgebraicNumber.from_expr(dec.requirement(i).exact ** 2)
               for i, e in enumerate(losses))


def theorem6_allocation(system: System, exp_capacity: Any, order: list[tuple[int, int]] | None = None) -> IID:
    """Theorem 6, constructively: rates with overall capacity ``C = ln(exp_capacity)`` and ``C_i > r_i``.

    Needs ``C > sum_i r_i`` (27), implied by ``C > h(A)`` (28).  The excess is
    shared equally: ``loss_i = exp(-2 r_i) * (prod_j exp(r_j))^{2/N} * exp_capacity^{-2/N}``.
    """
    u = AlgebraicNumber.from_expr(exp_capacity)
    dec = wonham_decomposition(system, order)
    req = [dec.requirement(i) for i in range(system.d)]
    total = sp.Mul(*[m.exact for m in req])
    if not u > AlgebraicNumber.from_expr(total):
        raise AssumptionError(f"C = ln({u.exact}) is not above sum_i max_j h(A_ij) = ln({total})",
                              assumption="condition (27) (Yang et al., Theorem 5)")
    N = system.d
    return IID([sp.radsimp(total ** sp.Rational(2, N) / (m.exact ** 2 * u.exact ** sp.Rational(2, N))) for m in req])


def theorem7_necessary(system: System, loss: LossModel) -> bool:
    """Theorem 7's necessary condition ``sum_i p_i C_i > ln |det A|`` (eq. 31), exactly.

    (The paper prints ``ln det(A)``; ``|det A|`` is meant.)  Requires ``A``
    without zero eigenvalues.  Decided as ``prod_i loss_i^{-p_i} > det(A)^2``.
    """
    det = sp.Matrix(system.A).det()
    if det == 0:
        raise AssumptionError("A has a zero eigenvalue", assumption="A invertible (Yang et al., Theorem 7)")
    losses = _require_iid(loss)
    if any(e == 0 for e in losses):
        return True
    lhs = sp.Mul(*[e ** -s.m for e, s in zip(losses, system.sensors)])
    return AlgebraicNumber.from_expr(lhs) > AlgebraicNumber.from_expr(sp.expand(det ** 2))


def corollary1_critical_capacity(system: System) -> sp.Expr:
    """Corollary 1: all eigenvalues unstable, scalar measurements: some rates of capacity ``C`` make ``V_k``
    converge iff ``C > h(A)``; returns ``h(A)`` after checking the hypotheses exactly."""
    if any(s.m != 1 for s in system.sensors):
        raise AssumptionError("a sensor has a vector measurement",
                              assumption="scalar measurements (Yang et al., Corollary 1)",
                              applies_instead="theorem5_requirements (sufficient) and theorem7_necessary")
    if any(ev.modulus <= 1 for ev in eigenvalues(system.A)):
        raise AssumptionError("A has an eigenvalue of modulus <= 1",
                              assumption="all eigenvalues unstable (Yang et al., Corollary 1)",
                              applies_instead="theorem5_requirements (sufficient) and theorem7_necessary")
    return sp.log(mahler_measure(system.A).exact)


def unstable_count(A: Any) -> int:
    """Number of eigenvalues with ``|lambda| > 1``, counted with algebraic multiplicity."""
    return sum(ev.multiplicity for ev in eigenvalues(A) if ev.modulus > 1)


def capacity_bounds_meet(A: Any) -> bool:
    """Exactly whether the two critical capacities coincide, ``ln rho(A) = h(A)`` (Lemma 2, Corollary 2).

    This holds iff ``A`` has exactly one eigenvalue outside the unit disc
    counted with multiplicity, or ``rho(A) = 1``.  Lemma 2's "only one
    unstable eigenvalue" must count multiplicity: ``A = 2 I`` has one distinct
    unstable eigenvalue and ``ln 2 < ln 4`` (proofs/yang_lemma2.py).
    """
    A = to_exact_matrix(A, "A")
    return spectral_radius(A) == mahler_measure(A)


def single_sensor_rates(A: Any) -> tuple[AlgebraicNumber, AlgebraicNumber]:
    """Single sensor (N = 1): ``(1 - 1/rho(A)^2, 1 - 1/M(A)^2)``, exact.

    Below the first (Sinopoli et al.'s lower bound) ``E[P_k^-]`` diverges
    (Theorem 2); above the second ``V_k`` converges when the pair is observable
    (Theorem 5 with ``N = 1``: ``max_j M(A_1j) <= M(A)``), the closed form the
    paper states after eq. 32.  For scalar measurements it is exactly the
    threshold of Theorem 4 (Corollary 1 / Elia).
    """
    A = to_exact_matrix(A, "A")
    rho, M = spectral_radius(A), mahler_measure(A)
    if rho == 0:
        raise InputError("A is nilpotent: every arrival rate works, 1 - 1/rho^2 is undefined")
    return (AlgebraicNumber.from_expr(sp.radsimp(1 - 1 / rho.exact ** 2)),
            AlgebraicNumber.from_expr(sp.radsimp(1 - 1 / M.exact ** 2)))

check_public(globals())
