"""Kalman decomposition of each sensor (arXiv:2012.04896, eqs. 3-5, Remark 2).

The observable subspace of ``(A, C_i)`` is the row space of the observability
matrix ``O_i = [C_i; C_i A; ...; C_i A^{n-1}]``, the orthogonal complement of
the unobservable subspace.  It is computed **exactly** (sympy, rational or
algebraic entries) and its dimension ``n_{i,o}`` is the exact rank
(:func:`symkf.exact.linalg.rank`).  The orthonormal basis ``V_{i,o}`` that
eqs. (3)-(5) need is then taken in floating point (a QR factorisation of the
exact basis): orthonormalising exactly would bring nested square roots into
every later step while deciding nothing.

With the orthonormal ``T_i = [V_{i,o} V_{i,ō}]'`` the transformed matrix
``T_i A T_i'`` is block **lower** triangular (``V_{i,o}' A V_{i,ō} = 0``
because the unobservable subspace is A-invariant); this is what makes the
local model (4) autonomous.  The paper prints the block upper triangular form
of a controllability decomposition in (3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..arguments import check_public
from ..errors import AssumptionError, ShapeError
from ..exact.linalg import rank
from ..exact.numbers import as_matrix

__all__ = ["observability_matrix", "observable_subspace", "orthonormal_basis",
           "check_collective_observability", "check_reachability", "LocalModel", "local_model"]


def observability_matrix(A: sp.MatrixBase, C: sp.MatrixBase) -> sp.Matrix:
    """``O = [C; CA; ...; CA^{n-1}]`` (exact)."""
    A, C = as_matrix(A, "A"), as_matrix(C, "C")
    if A.shape[0] != A.shape[1] or C.shape[1] != A.shape[0]:
        raise ShapeError(f"C: has {C.shape[1]} columns, A is {A.shape[0]}x{A.shape[1]}")
    blocks, M = [], C
    for _ in range(A.shape[0]):
        blocks.append(M)
        M = M * A
    return sp.Matrix.vstack(*blocks)


def observable_subspace(A: sp.MatrixBase, C: sp.MatrixBase) -> sp.Matrix:
    """Exact basis (as columns) of the observable subspace of ``(A, C)``.

    The columns span the row space of ``O``; their number is the exact rank
    ``n_{i,o}`` of eq. (3).
    """
    O = observability_matrix(A, C)
    r = rank(O)
    rows = O.rowspace()
    if len(rows) != r:
        raise AssumptionError(f"sympy's row space has {len(rows)} rows but the exact rank is {r}",
                              assumption="exact observable subspace")
    if r == 0:
        return sp.zeros(A.shape[0], 0)
    return sp.Matrix.hstack(*[row.T for row in rows])


def orthonormal_basis(basis: sp.MatrixBase) -> np.ndarray:
    """Float orthonormal basis ``V_{i,o}`` of the exact column space (QR)."""
    B = np.array(as_matrix(basis, "basis").evalf(30).tolist(), dtype=float)
    Q, _ = np.linalg.qr(B)
    return Q


def check_collective_observability(A: sp.MatrixBase, Cs: list[sp.MatrixBase]) -> None:
    """Assumption 1 (arXiv:2012.04896): ``(A, [C_1' ... C_N']')`` observable, decided by exact rank."""
    O = observability_matrix(A, sp.Matrix.vstack(*Cs))
    r = rank(O)
    if r < A.shape[0]:
        raise AssumptionError(
            f"the stacked observability matrix has rank {r} < n = {A.shape[0]}; the sensors "
            "together do not see the whole state, so W'V_o = I has no solution",
            assumption="Assumption 1 (arXiv:2012.04896): collective observability",
            applies_instead="a sensor set whose stacked C makes (A, C) observable")


def check_reachability(A: sp.MatrixBase, G: sp.MatrixBase) -> None:
    """Lemma 1's premise when ``Q`` is singular: ``(A, G)`` controllable, ``range G = range Q``.

    Assumption 1 asks ``Q > 0`` only so that every projected pair
    ``(A_{i,o}, Q_{i,o}^{1/2})`` is controllable (Remark 1).  Controllability
    of ``(A, Q^{1/2})`` already gives that, because ``(A_{i,o}, V_{i,o}' Q^{1/2})``
    is the quotient of ``(A, Q^{1/2})`` by the A-invariant unobservable subspace.
    """
    A, G = as_matrix(A, "A"), as_matrix(G, "G")
    blocks, M = [], G
    for _ in range(A.shape[0]):
        blocks.append(M)
        M = A * M
    r = rank(sp.Matrix.hstack(*blocks))
    if r < A.shape[0]:
        raise AssumptionError(
            f"Q is singular and (A, Q^(1/2)) has a reachable subspace of dimension {r} < {A.shape[0]}; "
            "the local Riccati equations need not have stabilising positive definite solutions",
            assumption="Assumption 1 (arXiv:2012.04896): Q > 0 (or at least (A, Q^(1/2)) controllable, Remark 1)")


@dataclass(frozen=True)
class LocalModel:
    """The model (4)-(5) of one sensor on its observable subspace.

    ``V`` is ``V_{i,o}`` (n x n_o, orthonormal columns), ``A = V' A V``,
    ``C = C_i V`` (the paper's C̃_i), ``Q = V' Q V`` (Q̃_{i,o}), ``R = R_i``.
    ``exact_basis`` spans the same subspace exactly.
    """

    name: str
    exact_basis: sp.Matrix
    V: np.ndarray
    A: np.ndarray
    C: np.ndarray
    Q: np.ndarray
    R: np.ndarray

    @property
    def n_o(self) -> int:
        return self.V.shape[1]


def local_model(name: str, A_exact: sp.MatrixBase, A: np.ndarray, Q: np.ndarray,
                C: sp.MatrixBase, R: np.ndarray) -> LocalModel:
    """Kalman decomposition of sensor ``name`` (eqs. 3-5).

    ``A_exact`` decides the observable subspace; ``A`` (float) is the matrix
    the filters run on.  They are the same matrix for a discrete-time model
    and ``A_c``, ``exp(A_c T_s)`` for a sampled one (see
    :meth:`symkf.fusion.model.FusionModel.zoh`).
    """
    A_exact, C = as_matrix(A_exact, "A_exact"), as_matrix(C, f"sensor {name!r} C")
    basis = observable_subspace(A_exact, C)
    V = orthonormal_basis(basis)
    Cf = np.array(sp.Matrix(C).evalf(30).tolist(), dtype=float)
    return LocalModel(name=name, exact_basis=basis, V=V, A=V.T @ A @ V, C=Cf @ V,
                      Q=V.T @ Q @ V, R=np.atleast_2d(np.asarray(R, dtype=float)))

check_public(globals())
