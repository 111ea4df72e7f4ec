"""The lower bound of E[P_k^-]: m(X), G_k, its limit, and Remark 3's F_k (Yang et al., Section III-C).

With ``c = prod_i (1 - lambda_i)`` (the probability that every packet is lost),

* ``m(X) = c A X A' + Q`` (eq. 13), ``G_1 = 0``, ``G_{k+1} = m(G_k)`` and
  ``G_k <= E[P_k^-]`` (Proposition 1);
* Theorem 1: with ``(A, sqrt(Q))`` controllable, ``G_k`` converges iff
  ``c rho(A)^2 < 1``, i.e. iff ``C > ln rho(A)`` (eq. 14); the limit is the
  solution ``Gbar`` of the Stein equation ``X = c A X A' + Q``, which is
  rational for rational data and is computed exactly here;
* Theorem 2: ``C <= ln rho(A)`` makes ``E[P_k^-]`` diverge, otherwise
  ``liminf E[P_k^-] >= Gbar`` (eq. 17);
* Remark 3: ``F_1 = P_1^-``, ``F_{k+1} = A (F_k^{-1} + sum_i lambda_i S_i)^{-1} A' + Q``
  with ``S_i = C_i' R_i^{-1} C_i`` is another lower bound.  The paper justifies
  it by the convexity of ``gbar(X; S)`` in ``S`` alone, which does not suffice
  (``gbar`` is concave in ``X``); the bound holds because ``P_k`` is jointly
  convex in ``(S_1, ..., S_{k-1})`` (proofs/yang_remark3_lower_bound.py).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from ..arguments import check_public
from ..errors import AssumptionError
from ..exact.linalg import rank
from ..model.loss import LossModel
from ..model.system import System
from .quantities import _require_iid, capacity_exceeds, initial_matrix, sequence_horizon, spectral_radius


def loss_product(loss: LossModel) -> sp.Expr:
    """``c = prod_i (1 - lambda_i)``, the probability that all packets of one step are lost."""
    return sp.Mul(*_require_iid(loss))


def _m(X: Any, c: Any, A: Any, Q: Any) -> Any:
    # one formula for exact (sympy) and float (numpy) matrices
    return c * (A @ X @ A.T) + Q


def lower_bound_sequence(system: System, loss: LossModel, horizon: int, *, exact: bool = False) -> list[Any]:
    """``[G_1, ..., G_horizon]`` with ``G_1 = 0``, ``G_{k+1} = m(G_k)`` (Proposition 1, eq. 13).

    Exact sympy matrices when ``exact``, else float numpy arrays.
    """
    horizon = sequence_horizon(horizon, system.n)
    c = loss_product(loss)
    if exact:
        A, Q, G = system.A, system.Q, sp.zeros(system.n, system.n)
    else:
        A, Q = np.array(system.A.evalf(30), dtype=float), np.array(system.Q.evalf(30), dtype=float)
        c, G = float(c), np.zeros((system.n, system.n))
    out = [G]
    for _ in range(horizon - 1):
        G = _m(G, c, A, Q)
        out.append(G)
    return out


def require_controllable(system: System) -> None:
    """Raise unless ``(A, sqrt(Q))`` is controllable (Theorems 1 and 2); ``Q > 0`` always is."""
    A, Q = sp.Matrix(system.A), sp.Matrix(system.Q)
    blocks = [Q]
    for _ in range(system.n - 1):
        blocks.append(A * blocks[-1])
    if rank(sp.Matrix.hstack(*blocks)) < system.n:
        raise AssumptionError("[Q, AQ, ..., A^(n-1) Q] is rank deficient",
                              assumption="(A, sqrt(Q)) controllable (Yang et al., Theorems 1-2)")


def lower_bound_converges(system: System, loss: LossModel) -> bool:
    """Theorem 1, exactly: ``G_k`` converges iff ``C > ln rho(A)`` (eq. 14).

    The proof does not use that ``A`` is unstable (for stable ``A`` both sides
    hold), so only controllability of ``(A, sqrt(Q))`` is required.
    """
    require_controllable(system)
    return capacity_exceeds(loss, spectral_radius(system.A))


def lower_bound_limit(system: System, loss: LossModel) -> sp.ImmutableMatrix:
    """``Gbar = lim G_k``, the solution of the Stein equation ``X = c A X A' + Q`` (Theorem 1), exact.

    Solved as ``(I - c A (x) A) vec X = vec Q``.  Raises :class:`AssumptionError`
    when ``C <= ln rho(A)`` (then ``G_k`` diverges and no positive solution exists).
    """
    if not lower_bound_converges(system, loss):
        raise AssumptionError("C <= ln rho(A), so G_k diverges (Theorem 1)",
                              assumption="C > ln rho(A) (Yang et al., eq. 14)",
                              applies_instead="lower_bound_sequence for the finite-horizon bound")
    n, c = system.n, loss_product(loss)
    A = sp.Matrix(system.A)
    K = sp.eye(n * n) - c * sp.kronecker_product(A, A)
    vec = K.LUsolve(sp.Matrix(system.Q).reshape(n * n, 1))
    return sp.ImmutableMatrix(vec.reshape(n, n).applyfunc(sp.radsimp))


def theorem2(system: System, loss: LossModel) -> dict[str, Any]:
    """Theorem 2: ``{"diverges": C <= ln rho(A), "Gbar": Gbar or None}`` (eqs. 16-17), exact."""
    if lower_bound_converges(system, loss):
        return {"diverges": False, "Gbar": lower_bound_limit(system, loss)}
    return {"diverges": True, "Gbar": None}


def information_lower_bound_sequence(system: System, loss: LossModel, horizon: int,
                                     P1: Any = None) -> list[np.ndarray]:
    """Remark 3's ``[F_1, ..., F_horizon]`` (floats): ``F_{k+1} = A (F_k^{-1} + sum lambda_i S_i)^{-1} A' + Q``.

    ``F_1 = P_1^-`` defaults to the system's ``P0`` (the first prediction, as in :class:`MARE`).
    """
    horizon = sequence_horizon(horizon, system.n)
    A = np.array(system.A.evalf(30), dtype=float)
    Q = np.array(system.Q.evalf(30), dtype=float)
    S = sum(float(1 - e) * np.array((s.C.T * s.R.inv() * s.C).evalf(30), dtype=float)
            for s, e in zip(system.sensors, _require_iid(loss)))
    F = np.array(system.P0.evalf(30), dtype=float) if P1 is None else initial_matrix(P1, system.n, "P1")
    out = [F]
    for _ in range(horizon - 1):
        F = A @ np.linalg.solve(np.linalg.inv(F) + S, A.T) + Q
        out.append(F)
    return out

check_public(globals())
