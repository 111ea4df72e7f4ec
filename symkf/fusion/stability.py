"""Stability of the remote fused estimate (arXiv:2012.04896, Proposition 1 and Assumption 2).

Proposition 1 claims ``lim_k tr E[P*_k] < infinity`` under Assumption 2 and
proves it with the bound (Appendix E)

    tr E[P*_k] <= m sum_i n_i,o { E[rho_i^(2 tau_i)] (tr Pbar_i - tr Q~_i / (1 - rho_i^2)) + tr Q~_i / (1 - rho_i^2) },

``rho_i = rho(A_i,o)``, ``m > sigma_max(W)^2`` for a fixed feasible ``W``.  Its
last step uses ``tr(A^t X A'^t) <= n rho(A)^(2t) tr X``, false for non-normal
``A`` (``proofs/fusion_proposition1.py`` gives a counterexample to the bound).

A valid bound follows from the same idea without that step: for any fixed
feasible ``W``, ``E[tr P*_k] <= tr(W' E[Sigma_k] W)``, and ``E[Sigma_k]`` in
steady state is exact (:func:`symkf.fusion.covariance.expected_remote_covariance`);
the best such ``W`` is the optimal weight for ``E[Sigma]``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arguments import check_public
from ..errors import AssumptionError
from .covariance import expected_remote_covariance, fusion_sigma, unbiasedness_matrix
from .local_filters import LocalFilters
from .weights import fused_covariance, optimal_weights

__all__ = ["Proposition1", "proposition1_bound"]


@dataclass(frozen=True)
class Proposition1:
    """``bound``: valid steady-state bound on ``tr E[P*_k]``; ``printed_bound``: the bound as printed, (E.1)."""

    bound: float
    printed_bound: float
    trace_expected_sigma: float
    weights: np.ndarray


def proposition1_bound(lf: LocalFilters) -> Proposition1:
    """Both bounds of Proposition 1 for the steady state (needs Assumption 2)."""
    a2 = lf.model.assumption2
    if not a2.holds:
        raise AssumptionError(f"(1 - min lambda) rho(A)^2 lies in [{float(a2.interval[0]):.6g}, "
                              f"{float(a2.interval[1]):.6g}], not below 1",
                              assumption="Assumption 2 (arXiv:2012.04896)")
    EP = expected_remote_covariance(lf)
    ES = fusion_sigma(lf, EP)
    W = optimal_weights(ES, unbiasedness_matrix(lf))
    bound = float(np.trace(fused_covariance(ES, W)))
    m = float(np.linalg.svd(W, compute_uv=False)[0] ** 2)
    total = 0.0
    for loc, f, lam in zip(lf.model.local, lf.filters, lf.model.arrival):
        lam = float(lam)
        rho2 = float(max(abs(np.linalg.eigvals(loc.A)))) ** 2
        e_rho = lam / (1 - (1 - lam) * rho2)
        stat = np.trace(loc.Q) / (1 - rho2)
        total += loc.n_o * (e_rho * (np.trace(f.P) - stat) + stat)
    return Proposition1(bound=bound, printed_bound=m * total, trace_expected_sigma=float(np.trace(ES)), weights=W)

check_public(globals())
