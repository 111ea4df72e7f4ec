"""The remote estimator over i.i.d. lossy channels and its simulation (arXiv:2012.04896, eqs. 9-12).

Each channel delivers the local estimate with probability ``lambda_i``; the
remote estimator predicts the last one it received open loop,
``chi_hat_i = A_i^tau_i chi_hat_s_i(k - tau_i)`` (eq. 11, ``tau_i`` the holding
time, eq. 10), and fuses ``x_hat = sum_i W_i V_i chi_hat_i`` (eq. 12) with the
optimal weights for the current holding times.

The weights are computed in the reduced coordinates ``U = Diag(V_i)' W``:
since ``Sigma = Diag(V_i) P Diag(V_i)'`` and ``V_o = Diag(V_i) H`` with
``H = [V_1'; ...; V_N']``, Problem 1 is the same problem for ``(P, H)``, and
``W = Diag(V_i) U`` is one of its minimisers (tests check it against all three
methods of :func:`symkf.fusion.optimal_weights` on ``Sigma``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_discrete_are
from threadpoolctl import threadpool_limits

from .. import budget
from ..arguments import check_public
from ..errors import InputError
from .covariance import HoldingTimeCovariance, holding_times
from .local_filters import LocalFilters
from .weights import _ClosedForm, _validate
from ..numeric.receptions import draw

__all__ = ["RemoteFusion", "FusionRun", "simulate_fusion", "centralized_filter"]


class RemoteFusion:
    """Optimal fusion weights as a function of the holding times, cached."""

    def __init__(self, lf: LocalFilters):
        self.lf = lf
        self.cov = HoldingTimeCovariance(lf)
        self.H = np.vstack([loc.V.T for loc in lf.model.local])
        self._closed_form = _ClosedForm(_validate(self.cov.matrix([0] * lf.model.N), self.H)[1])
        self._cache: dict[tuple[int, ...], tuple[np.ndarray, float]] = {}

    def weights(self, tau: tuple[int, ...]) -> tuple[np.ndarray, float]:
        """``(U, tr P*)``: reduced weights (sum n_i,o x n) and the optimal trace of eq. (19)."""
        return self._weights(tuple(holding_times(self.cov.lf, tau)))

    def _weights(self, tau: tuple[int, ...]) -> tuple[np.ndarray, float]:
        """:meth:`weights` of holding times the simulation built (Python ints), cached."""
        if tau not in self._cache:
            P = self.cov._checked_matrix(list(tau))
            U = self._closed_form(_validate(P, self.H)[0])
            self._cache[tau] = (U, float(np.trace(U.T @ P @ U)))
        return self._cache[tau]


def centralized_filter(lf: LocalFilters) -> tuple[np.ndarray, np.ndarray]:
    """Steady gain and filtered covariance of the centralized Kalman filter with perfect channels."""
    m = lf.model
    C, R = m.C, m.R
    P_pred = solve_discrete_are(m.A.T, C.T, m.Q, R)
    K = P_pred @ C.T @ np.linalg.inv(C @ P_pred @ C.T + R)
    P = (np.eye(m.n) - K @ C) @ P_pred
    return K, (P + P.T) / 2


def _sqrt_psd(M: np.ndarray) -> np.ndarray:
    s, U = np.linalg.eigh((M + M.T) / 2)
    return U * np.sqrt(np.clip(s, 0, None))


@dataclass(frozen=True)
class FusionRun:
    """Errors of ``paths`` sample paths over ``horizon`` steps (index 0 = time 0).

    ``fused`` (paths, K+1, n): ``x_k - x_hat_k``; ``centralized`` likewise for the
    centralized filter with perfect channels; ``single`` (paths, K+1, N, n):
    ``x_k - V_i chi_hat_i`` for each sensor's remote estimate alone;
    ``trace_P`` (paths, K+1): ``tr P*_k`` of the optimal fusion given the holding times.
    """

    fused: np.ndarray
    centralized: np.ndarray
    single: np.ndarray
    trace_P: np.ndarray
    seed: int


def simulate_fusion(lf: LocalFilters, horizon: int, paths: int, seed: int) -> FusionRun:
    """Simulate process, local steady filters, lossy channels and the three kinds of estimators.

    At time 0: ``x_0 = 0``, local and centralized filters in steady state
    (errors drawn from their steady covariances, jointly for the local ones,
    as the paper assumes after Lemma 1), every packet received (``tau = 0``).
    The state itself is simulated, so for unstable ``A`` keep ``rho(A)^horizon``
    well below ``1/eps``: the errors are differences of numbers of the size of ``x``.
    """
    if horizon < 1 or paths < 1:
        raise InputError(f"horizon, paths: must be positive, got {horizon}, {paths}")
    m = lf.model
    n, N = m.n, m.N
    # the error records (floats) and the arrivals (bytes) it returns and draws
    budget.check("max_memory", 8 * (horizon + 1) * paths * (2 * n + N * n + 1) + horizon * paths * N,
                 "symkf.fusion.simulate_fusion", f"the bytes (estimate) of {paths} paths x {horizon} steps of "
                 f"{N} sensors' errors")
    size = lf.Pi.shape[0]
    budget.price("symkf.fusion.simulate_fusion", f"the first fusion weights ({N * N} blocks of a {size} x {size} "
                 "covariance and its solve)", fusion_block=N * N, weights_cube=size ** 3)
    # each path's step solves the weights of its holding times unless they were met before (cached):
    # their cost is known only as the cache fills, so the (step, path) rounds are metered
    meter = budget.Meter("symkf.fusion.simulate_fusion", f"the fusion weights of {paths} paths x {horizon + 1} "
                         f"steps (a {size} x {size} solve for each new holding time)", rounds=(horizon + 1) * paths)
    with threadpool_limits(1):   # one BLAS thread, as priced (see symkf.fusion.optimal_weights)
        return _simulate(lf, horizon, paths, seed, meter)


def _simulate(lf: LocalFilters, horizon: int, paths: int, seed: int, meter: budget.Meter) -> FusionRun:
    """:func:`simulate_fusion` of checked and priced arguments, its rounds counted by ``meter``."""
    m = lf.model
    n, N = m.n, m.N
    rng = np.random.default_rng(seed)
    fusion = RemoteFusion(lf)
    Kc, Pc = centralized_filter(lf)
    Cc, Rc = m.C, m.R
    sq_Q, sq_Rc = _sqrt_psd(m.Q), _sqrt_psd(Rc)
    rows = np.cumsum([0] + [s.m for s in m.sensors])
    arrivals = draw(m.loss, horizon, paths, rng)     # (horizon, paths, N), drawn per sensor
    locs, filt, off = m.local, lf.filters, lf.offsets

    x = np.zeros((paths, n))
    E0 = rng.standard_normal((paths, lf.Pi.shape[0])) @ _sqrt_psd(lf.Pi).T
    local = [x @ loc.V - E0[:, off[i]:off[i + 1]] for i, loc in enumerate(locs)]
    remote = [c.copy() for c in local]
    xc = x - rng.standard_normal((paths, n)) @ _sqrt_psd(Pc).T
    tau = np.zeros((paths, N), dtype=int)

    fused_err = np.zeros((horizon + 1, paths, n))
    central_err = np.zeros((horizon + 1, paths, n))
    single_err = np.zeros((horizon + 1, paths, N, n))
    trace_P = np.zeros((horizon + 1, paths))

    def record(k: int) -> None:
        r = np.concatenate(remote, axis=1)
        for p in range(paths):
            meter.round()
            U, tr = fusion._weights(tuple(tau[p].tolist()))
            fused_err[k, p] = x[p] - U.T @ r[p]
            trace_P[k, p] = tr
        central_err[k] = x - xc
        for i, loc in enumerate(locs):
            single_err[k, :, i] = x - remote[i] @ loc.V.T

    record(0)
    for k in range(1, horizon + 1):
        x = x @ m.A.T + rng.standard_normal((paths, n)) @ sq_Q.T
        y = x @ Cc.T + rng.standard_normal((paths, Rc.shape[0])) @ sq_Rc.T
        for i, (loc, f) in enumerate(zip(locs, filt)):
            pred = local[i] @ loc.A.T
            local[i] = pred + (y[:, rows[i]:rows[i + 1]] - pred @ loc.C.T) @ f.K.T
        pred = xc @ m.A.T
        xc = pred + (y - pred @ Cc.T) @ Kc.T
        arrived = arrivals[k - 1]
        tau = np.where(arrived, 0, tau + 1)
        for i, loc in enumerate(locs):
            remote[i] = np.where(arrived[:, [i]], local[i], remote[i] @ loc.A.T)
        record(k)
    swap = lambda a: np.swapaxes(a, 0, 1)
    return FusionRun(fused=swap(fused_err), centralized=swap(central_err), single=swap(single_err),
                     trace_P=swap(trace_P), seed=seed)

check_public(globals())
