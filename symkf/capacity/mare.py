"""The multi-sensor MARE g_lambda and the upper bound V_k (Yang et al., Section III-D, eqs. 18-21).

``g_lambda(X) = A X A' + Q - A X H' (W o (H X H' + I))^{-1} H X A'`` (eq. 18), with
``o`` the Hadamard product, ``H = col(R_i^{-1/2} C_i)`` and

    W = 1 1' + D_SNR^{-1} I_blk,   D_SNR = diag(q_i I_{p_i}),   I_blk = diag(1_{p_i} 1_{p_i}')   (19-20).

The printed form is the right one: ``E[Gamma X Gamma] = Lambda (W o X) Lambda``
because ``E[gamma_i gamma_j] = lambda_i lambda_j`` off the diagonal blocks and
``lambda_i = lambda_i^2 (1 + 1/q_i)`` on them; minimising the expected
``Phi(L, X, Gamma)`` of Theorem 3's proof over ``K = L Lambda`` gives eq. 18
(checked in tests/capacity/test_mare.py by enumeration of Gamma).  Since ``W`` is
constant on each sensor block and ``R^{-1/2}`` is block diagonal,
``W o (H X H' + I) = R^{-1/2} (W o (C X C' + R)) R^{-1/2}``, so

    g_lambda(X) = A X A' + Q - A X C' (W o (C X C' + R))^{-1} C X A'

(Remark 4 with S = 0) needs no matrix square root; that form is computed.  A
sensor with ``lambda_i = 0`` never reports and is left out (``1/q_i = oo``).
``V_1 = P_1^-``, ``V_{k+1} = g_lambda(V_k)`` bounds ``E[P_k^-]`` from above
(Theorem 3).  These are float computations (bounds to plot and compare);
whether ``V_k`` converges is decided by :mod:`symkf.capacity.convergence`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from ..arguments import check_public, count
from ..errors import AssumptionError, InputError
from ..model.iid import IID
from ..model.loss import LossModel
from ..model.system import System
from ..numeric.closed_loop import arrival_weight
from .quantities import _require_iid, initial_matrix, sequence_horizon


def hadamard_weight(loss: LossModel, dims: list[int]) -> sp.ImmutableMatrix:
    """``W = 1 1' + D_SNR^{-1} I_blk`` (eqs. 19-20), exact; blocks ``1`` off and ``1/lambda_i`` on the diagonal.

    ``dims`` are the measurement dimensions ``p_i``; every ``lambda_i`` must be positive.
    """
    arrival = [1 - e for e in _require_iid(loss)]
    if any(a == 0 for a in arrival):
        raise AssumptionError("a sensor with lambda_i = 0 has D_SNR^{-1} infinite",
                              assumption="lambda_i > 0 in W (Yang et al., eq. 19)",
                              applies_instead="leave the silent sensor out of the system")
    return sp.ImmutableMatrix(arrival_weight(arrival, dims))


class MARE:
    """``g_lambda`` of eq. 18 for one system and arrival rates, in floats (Remark 4 form, see module doc)."""

    def __init__(self, system: System, loss: LossModel):
        losses = _require_iid(loss)
        if len(losses) != system.d:
            raise AssumptionError(f"loss has {len(losses)} rates for {system.d} sensors",
                                  assumption="one arrival rate per sensor")
        live = [i for i, e in enumerate(losses) if e != 1]
        self.A = np.array(system.A.evalf(30), dtype=float)
        self.Q = np.array(system.Q.evalf(30), dtype=float)
        self.P1 = np.array(system.P0.evalf(30), dtype=float)
        if live:
            sensors = [system.sensors[i] for i in live]
            self.C = np.array(sp.Matrix.vstack(*[s.C for s in sensors]).evalf(30), dtype=float)
            self.R = np.array(sp.diag(*[s.R for s in sensors]).evalf(30), dtype=float)
            W = hadamard_weight(IID([losses[i] for i in live]), [s.m for s in sensors])
            self.W = np.array(W.evalf(30), dtype=float)
        else:
            self.C = np.zeros((0, system.n))

    def __call__(self, X: np.ndarray) -> np.ndarray:
        X = np.asarray(X, dtype=float)
        out = self.A @ X @ self.A.T + self.Q
        if self.C.shape[0]:
            AXC = self.A @ X @ self.C.T
            out = out - AXC @ np.linalg.solve(self.W * (self.C @ X @ self.C.T + self.R), AXC.T)
        return (out + out.T) / 2

    def sequence(self, horizon: int, V1: Any = None) -> list[np.ndarray]:
        """``[V_1, ..., V_horizon]`` with ``V_1 = P_1^-`` (Theorem 3).

        ``P_1^-`` defaults to the system's ``P0``, the covariance of the first
        prediction (``P_{0|-1}`` in :mod:`symkf.numeric.filters`; Yang et al. index it 1).
        """
        n = self.A.shape[0]
        horizon = sequence_horizon(horizon, n)
        V = self.P1 if V1 is None else initial_matrix(V1, n, "V1")
        out = [V]
        for _ in range(horizon - 1):
            V = self(V)
            out.append(V)
        return out

    def fixed_point(self, tol: float = 1e-12, max_iter: int = 100_000) -> np.ndarray:
        """``Vbar = g_lambda(Vbar)`` by the monotone iteration from ``0`` (Theorem 6, eq. 30).

        Raises :class:`AssumptionError` when the iteration grows without bound
        (no positive definite fixed point: Theorem 4's condition fails).
        """
        if not tol > 0:
            raise InputError(f"tol: expected a positive tolerance, got {tol!r}")
        V = np.zeros_like(self.Q)
        for _ in range(count(max_iter, "max_iter", 1)):
            nxt = self(V)
            if not np.all(np.isfinite(nxt)) or np.abs(nxt).max() > 1e14:
                break
            if np.abs(nxt - V).max() <= tol * max(1.0, np.abs(nxt).max()):
                return nxt
            V = nxt
        raise AssumptionError("the iteration V_{k+1} = g_lambda(V_k) from 0 does not converge",
                              assumption="Theorem 4's condition 1) (Yang et al.)",
                              applies_instead="convergence.mare_converges to decide it")

check_public(globals())
