"""Local steady-state Kalman filters and their joint error covariance (arXiv:2012.04896, Lemmas 1-2).

Each smart sensor runs the Kalman filter (6) on its observable subspace.  In
steady state (Lemma 1) the prediction covariance ``P*`` solves the DARE
``X = h_i(g~_i(X))`` (eqs. 7-8), the gain is ``K_i = P* C~' (C~ P* C~' + R)^{-1}``
and the filtered covariance ``Pbar = (I - K_i C~_i) P*``.

The local errors ``E_i`` obey ``E_i+ = F_i E_i + G_i V_i' w - K_i v_i`` with
``F_i = (I - K_i C~_i) A_{i,o}`` and ``G_i = I - K_i C~_i`` (proof of Lemma 2).
Their joint steady covariance ``Pi = [Gamma_ij]`` therefore solves one Stein
(discrete Lyapunov) equation

    Pi = F Pi F' + G V' Q V G' + K R K',   F = Diag(F_i), G = Diag(G_i), K = Diag(K_i),

whose diagonal blocks are the ``Pbar_i`` of Lemma 1 and whose off-diagonal
blocks are the fixed points ``Gamma_ij`` of the maps ``T_ij`` of Lemma 2.  It
is solved directly (Bartels-Stewart, :func:`scipy.linalg.solve_discrete_lyapunov`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import block_diag, solve_discrete_are, solve_discrete_lyapunov
from threadpoolctl import threadpool_limits

from .. import budget
from ..arguments import check_public, index
from ..errors import AssumptionError
from .decomposition import LocalModel
from .model import FusionModel

__all__ = ["SteadyFilter", "steady_filter", "LocalFilters", "local_filters", "lemma2_iteration"]


@dataclass(frozen=True)
class SteadyFilter:
    """Steady state of the local filter (6) of one sensor (Lemma 1)."""

    P_pred: np.ndarray   # P*(i,o)
    K: np.ndarray        # K*_i
    P: np.ndarray        # Pbar(i,o) = g~_i(P*)
    F: np.ndarray        # (I - K C~) A_{i,o}, the error transition
    G: np.ndarray        # I - K C~


def steady_filter(loc: LocalModel) -> SteadyFilter:
    """Solve the DARE of Lemma 1 for one sensor and check the gain is stabilising."""
    P_pred = solve_discrete_are(loc.A.T, loc.C.T, loc.Q, loc.R)
    P_pred = (P_pred + P_pred.T) / 2
    K = P_pred @ loc.C.T @ np.linalg.inv(loc.C @ P_pred @ loc.C.T + loc.R)
    G = np.eye(loc.n_o) - K @ loc.C
    F = G @ loc.A
    radius = max(abs(np.linalg.eigvals(F)))
    if radius >= 1:
        raise AssumptionError(f"sensor {loc.name!r}: the steady gain leaves rho(F) = {radius:.6g} >= 1",
                              assumption="Lemma 1 (arXiv:2012.04896): stabilising DARE solution")
    P = G @ P_pred
    return SteadyFilter(P_pred=P_pred, K=K, P=(P + P.T) / 2, F=F, G=G)


@dataclass(frozen=True)
class LocalFilters:
    """All local steady filters and the joint covariance ``Pi`` of their errors."""

    model: FusionModel
    filters: tuple[SteadyFilter, ...]
    Pi: np.ndarray
    offsets: tuple[int, ...]

    def block(self, i: int, j: int) -> np.ndarray:
        """``Gamma_ij`` (``Pbar_i`` when ``i == j``)."""
        N = len(self.filters)
        i, j, o = index(i, N, "i"), index(j, N, "j"), self.offsets
        return self.Pi[o[i]:o[i + 1], o[j]:o[j + 1]]


def local_filters(model: FusionModel) -> LocalFilters:
    """Lemma 1 for every sensor and the joint Stein equation for ``[Gamma_ij]``."""
    size = sum(loc.n_o for loc in model.local)
    budget.price("symkf.fusion.local_filters",
                 lambda: f"{model.N} local Riccati equations and the joint Stein equation of size {size}",
                 local_filter=model.N, float_cube=size ** 3)
    # one BLAS thread, as priced: beside other work BLAS's threads spin, and the Stein solve of size
    # 192 cost four times its CPU (the small Riccati solves, 256 triangular solves at 128 sensors,
    # up to five times)
    with threadpool_limits(1):
        filters = tuple(steady_filter(loc) for loc in model.local)
        F = block_diag(*[f.F for f in filters])
        G = block_diag(*[f.G for f in filters])
        K = block_diag(*[f.K for f in filters])
        Vt = np.vstack([loc.V.T for loc in model.local])
        Pi = solve_discrete_lyapunov(F, G @ Vt @ model.Q @ Vt.T @ G.T + K @ model.R @ K.T)
    offsets = tuple(np.concatenate([[0], np.cumsum([loc.n_o for loc in model.local])]).tolist())
    return LocalFilters(model=model, filters=filters, Pi=(Pi + Pi.T) / 2, offsets=offsets)


def lemma2_iteration(lf: LocalFilters, i: int, j: int, steps: int) -> np.ndarray:
    """``T_ij^steps(0)``: the recursion (14) of Lemma 2, from zero (for cross-checks)."""
    li, lj = lf.model.local[i], lf.model.local[j]
    fi, fj = lf.filters[i], lf.filters[j]
    Qij = li.V.T @ lf.model.Q @ lj.V
    X = np.zeros((li.n_o, lj.n_o))
    for _ in range(steps):
        X = fi.G @ (li.A @ X @ lj.A.T + Qij) @ fj.G.T
    return X

check_public(globals())
