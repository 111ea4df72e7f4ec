"""Error covariances at the remote estimator (arXiv:2012.04896, eqs. 17-20) and their mean.

Remote estimate of sensor i with holding time ``tau_i`` (eq. 11):
``chi_hat_i = A_i^tau_i chi_hat_s_i(k - tau_i)``, error
``E_i = A_i^tau_i E_s_i(k - tau_i) + sum_{t<tau_i} A_i^t V_i' w_{k-t-1}``.

**Correction of eq. (18).**  The paper writes, for ``i != j``,
``P^(ij) = A_i^tau_i Gamma_ij A_j'^tau_j + sum_{t<min(tau_i,tau_j)} A_i^t Q_ij A_j'^t``,
which uses the *same-time* cross covariance ``Gamma_ij`` for local errors
taken at the different times ``k - tau_i`` and ``k - tau_j`` and drops the
correlation between the newer local error and the process noise the older
one is propagated through.  For ``tau_i >= tau_j`` and ``d = tau_i - tau_j``
the exact cross covariance is

    P^(ij) = A_i^tau_j [ A_i^d Gamma_ij F_j'^d + U_ij(d) ] A_j'^tau_j + S_ij(tau_j),
    U_ij(d) = sum_{r<d} A_i^r Q_ij G_j' F_j'^r,   S_ij(t) = sum_{s<t} A_i^s Q_ij A_j'^s,

with ``Q_ij = V_i' Q V_j`` and ``F_j, G_j`` from :mod:`.local_filters`.  It
agrees with (18) when ``tau_i = tau_j`` and, for ``i = j``, gives (17).
:func:`remote_error_covariance` also computes it by step-by-step propagation
of the joint error covariance (``method="propagation"``), an independent
route used to check the formula; ``proofs/fusion_cross_covariance.py`` shows
(18) as printed is wrong.

Sigma (eq. 20) is ``Diag(V_i) P Diag(V_i)'``; the mean of ``P`` over the
i.i.d. arrivals in steady state solves Stein equations (:func:`expected_remote_covariance`).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from scipy.linalg import block_diag

from .. import budget
from ..arguments import check_public, count, index
from ..errors import InputError
from .local_filters import LocalFilters

__all__ = ["HoldingTimeCovariance", "remote_error_covariance", "fusion_sigma", "unbiasedness_matrix",
           "stacked_bases", "expected_remote_covariance", "stein"]


def stacked_bases(lf: LocalFilters) -> np.ndarray:
    """``Diag(V_1,o, ..., V_N,o)`` (nN x sum n_i,o), the ``V`` of Appendix B."""
    return block_diag(*[loc.V for loc in lf.model.local])


def unbiasedness_matrix(lf: LocalFilters) -> np.ndarray:
    """``V_o = [V_1 V_1'; ...; V_N V_N']`` (nN x n), the constraint ``W' V_o = I`` of Problem 1."""
    return np.vstack([loc.V @ loc.V.T for loc in lf.model.local])


class HoldingTimeCovariance:
    """``P_k`` (stacked remote errors, sum n_i,o square) as a function of the holding times.

    Blocks are cached by ``(i, j, tau_i, tau_j)``: holding times are short
    (geometric), so a simulation reuses them.
    """

    def __init__(self, lf: LocalFilters):
        self.lf = lf
        m = lf.model
        self._A = [loc.A for loc in m.local]
        self._Qij = {(i, j): m.local[i].V.T @ m.Q @ m.local[j].V for i in range(m.N) for j in range(m.N)}
        self._pow: dict[tuple[str, int, int], np.ndarray] = {}
        self._S: dict[tuple[int, int, int], np.ndarray] = {}
        self._U: dict[tuple[int, int, int], np.ndarray] = {}
        self._blocks: dict[tuple[int, int, int, int], np.ndarray] = {}

    def _power(self, kind: str, i: int, t: int) -> np.ndarray:
        key = (kind, i, t)
        if key not in self._pow:
            base = self._A[i] if kind == "A" else self.lf.filters[i].F
            self._pow[key] = np.eye(base.shape[0]) if t == 0 else self._power(kind, i, t - 1) @ base
        return self._pow[key]

    def _sum_S(self, i: int, j: int, t: int) -> np.ndarray:
        """``S_ij(t) = sum_{s<t} A_i^s Q_ij A_j'^s``."""
        key = (i, j, t)
        if key not in self._S:
            self._S[key] = np.zeros_like(self._Qij[i, j]) if t == 0 else (
                self._sum_S(i, j, t - 1) + self._power("A", i, t - 1) @ self._Qij[i, j] @ self._power("A", j, t - 1).T)
        return self._S[key]

    def _sum_U(self, i: int, j: int, d: int) -> np.ndarray:
        """``U_ij(d) = sum_{r<d} A_i^r Q_ij G_j' F_j'^r``."""
        key = (i, j, d)
        if key not in self._U:
            G = self.lf.filters[j].G
            self._U[key] = np.zeros_like(self._Qij[i, j]) if d == 0 else (
                self._sum_U(i, j, d - 1)
                + self._power("A", i, d - 1) @ self._Qij[i, j] @ G.T @ self._power("F", j, d - 1).T)
        return self._U[key]

    def block(self, i: int, j: int, ti: int, tj: int) -> np.ndarray:
        """``P^(ij)`` for holding times ``tau_i = ti``, ``tau_j = tj`` (corrected eq. 18; eq. 17 if i = j)."""
        N = self.lf.model.N
        return self._block(index(i, N, "i"), index(j, N, "j"), _holding(ti, "ti"), _holding(tj, "tj"))

    def _block(self, i: int, j: int, ti: int, tj: int) -> np.ndarray:
        """:meth:`block` of checked indices and holding times."""
        if ti < tj:
            return self._block(j, i, tj, ti).T
        key = (i, j, ti, tj)
        if key not in self._blocks:
            d = ti - tj
            inner = self._power("A", i, d) @ self.lf.block(i, j) @ self._power("F", j, d).T + self._sum_U(i, j, d)
            self._blocks[key] = (self._power("A", i, tj) @ inner @ self._power("A", j, tj).T
                                 + self._sum_S(i, j, tj))
        return self._blocks[key]

    def matrix(self, tau: Sequence[int]) -> np.ndarray:
        """The joint covariance ``[P^(ij)]`` for the holding times ``tau`` (eq. 18 blocks)."""
        return self._checked_matrix(holding_times(self.lf, tau))

    def _checked_matrix(self, tau: list[int]) -> np.ndarray:
        """:meth:`matrix` of holding times already checked by :func:`holding_times` (a simulation
        asks for one per path and step: the blocks are written in place, once each)."""
        o = self.lf.offsets
        P = np.empty((o[-1], o[-1]))
        for i, ti in enumerate(tau):
            for j, tj in enumerate(tau):
                P[o[i]:o[i + 1], o[j]:o[j + 1]] = self._block(i, j, ti, tj)
        return P


def holding_times(lf: LocalFilters, tau: Sequence[int]) -> list[int]:
    """``tau`` checked as one holding time per sensor (eq. 10), each within the cap on exponents."""
    tau = list(tau)
    if len(tau) != lf.model.N:
        raise InputError(f"tau: expected {lf.model.N} non-negative integer holding times (eq. 10), got {len(tau)}")
    return [_holding(t, f"tau[{i}]") for i, t in enumerate(tau)]


def _holding(t: Any, entry: str) -> int:
    """A holding time (eq. 10): an integer from 0 to the cap on exponents (its powers of A are computed)."""
    t = count(t, entry)
    budget.check("max_exponent", t, entry, "the holding time (the power of A it takes)")
    return t


def _by_propagation(lf: LocalFilters, tau: list[int]) -> np.ndarray:
    """Propagate the joint error covariance from time ``k - max tau`` to ``k``.

    Sensor i's error is the local filter error (closed loop) until ``k - tau_i``
    and is then predicted open loop; the covariance update is exact.
    """
    m, T = lf.model, max(tau)
    Vt = np.vstack([loc.V.T for loc in m.local])
    C = lf.Pi.copy()
    for step in range(1, T + 1):
        closed = [step <= T - t for t in tau]
        Phi = block_diag(*[f.F if c else loc.A for f, loc, c in zip(lf.filters, m.local, closed)])
        Gw = block_diag(*[f.G if c else np.eye(loc.n_o) for f, loc, c in zip(lf.filters, m.local, closed)]) @ Vt
        Kv = block_diag(*[f.K if c else np.zeros_like(f.K) for f, c in zip(lf.filters, closed)])
        C = Phi @ C @ Phi.T + Gw @ m.Q @ Gw.T + Kv @ m.R @ Kv.T
    return (C + C.T) / 2


def remote_error_covariance(lf: LocalFilters, tau: Sequence[int], method: str = "closed-form",
                            cache: HoldingTimeCovariance | None = None) -> np.ndarray:
    """``P_k = [P^(ij)_k]`` for holding times ``tau`` (eqs. 17-18 corrected, see module docstring).

    ``method="closed-form"`` uses the block formula, ``"propagation"`` the
    joint covariance recursion; they agree to rounding.
    """
    tau = holding_times(lf, tau)
    if method == "closed-form":
        return (cache or HoldingTimeCovariance(lf)).matrix(tau)
    if method == "propagation":
        return _by_propagation(lf, tau)
    raise InputError(f"method: expected 'closed-form' or 'propagation', got {method!r}")


def fusion_sigma(lf: LocalFilters, P: np.ndarray) -> np.ndarray:
    """Sigma of eq. (20): ``Diag(V_i) P Diag(V_i)'`` (nN x nN)."""
    V = stacked_bases(lf)
    S = V @ P @ V.T
    return (S + S.T) / 2


def stein(c: float, A: np.ndarray, B: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve ``X = c A X B' + rhs`` (vectorised: ``(I - c B kron A) vec X = vec rhs``)."""
    n, m = rhs.shape
    M = np.eye(n * m) - c * np.kron(B, A)
    return np.linalg.solve(M, rhs.reshape(-1, order="F")).reshape((n, m), order="F")


def expected_remote_covariance(lf: LocalFilters) -> np.ndarray:
    """``lim_k E[P_k]`` over i.i.d. arrivals (``P(gamma_i = 1) = lambda_i``), by Stein equations.

    With ``R_i`` the remote error and ``S_i`` the local error of sensor i,
    ``R_i+ = S_i+`` if the packet arrives, ``A_i R_i + V_i' w`` otherwise.  Then
    ``X_ij = E[R_i S_j']`` and ``Y_ij = E[R_i R_j']`` solve::

        X_ij = l_i Pi_ij + (1 - l_i) (A_i X_ij F_j' + Q_ij G_j'),
        Y_ii = l_i Pi_ii + (1 - l_i) (A_i Y_ii A_i' + Q_ii),
        Y_ij = l_i l_j Pi_ij + l_i (1 - l_j) (F_i X_ji' A_j' + G_i Q_ij)
               + (1 - l_i) l_j (A_i X_ij F_j' + Q_ij G_j') + (1 - l_i)(1 - l_j)(A_i Y_ij A_j' + Q_ij).

    They have unique solutions under Assumption 2.
    """
    m = lf.model
    N = m.N
    cubes = sum(loc.n_o ** 3 for loc in m.local)
    # N^2 Stein equations X_ij and N (N + 1)/2 Y_ij, each solved as a dense system of n_i n_j unknowns
    budget.price("symkf.fusion.expected_remote_covariance",
                 lambda: f"{N * N + N * (N + 1) // 2} Stein equations of {N} sensors' observable parts",
                 fusion_pair=N * N + N * (N + 1) // 2, stein_float=3 * cubes * cubes // 2)
    lam = [float(x) for x in m.arrival]
    A = [loc.A for loc in m.local]
    F = [f.F for f in lf.filters]
    G = [f.G for f in lf.filters]
    Qij = {(i, j): m.local[i].V.T @ m.Q @ m.local[j].V for i in range(N) for j in range(N)}
    X = {(i, j): stein(1 - lam[i], A[i], F[j], lam[i] * lf.block(i, j) + (1 - lam[i]) * Qij[i, j] @ G[j].T)
         for i in range(N) for j in range(N)}
    Y = {}
    for i in range(N):
        Y[i, i] = stein(1 - lam[i], A[i], A[i], lam[i] * lf.block(i, i) + (1 - lam[i]) * Qij[i, i])
        for j in range(i + 1, N):
            li, lj = lam[i], lam[j]
            rhs = (li * lj * lf.block(i, j)
                   + li * (1 - lj) * (F[i] @ X[j, i].T @ A[j].T + G[i] @ Qij[i, j])
                   + (1 - li) * lj * (A[i] @ X[i, j] @ F[j].T + Qij[i, j] @ G[j].T)
                   + (1 - li) * (1 - lj) * Qij[i, j])
            Y[i, j] = stein((1 - li) * (1 - lj), A[i], A[j], rhs)
            Y[j, i] = Y[i, j].T
    P = np.block([[Y[i, j] for j in range(N)] for i in range(N)])
    return (P + P.T) / 2

check_public(globals())
