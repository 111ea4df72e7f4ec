"""Yang et al., Example 1 (Section IV, Fig. 2): G_k <= E[P_k^-] <= V_k on a random n = 2, N = 8 system."""

from __future__ import annotations

import os
from fractions import Fraction
from typing import Any

import numpy as np
import sympy as sp

from .. import budget, output
from ..arguments import check_public, count
from ..errors import InputError
from ..model.iid import IID
from ..model.system import Sensor, System
from ..reproduction import reproduction
from .convergence import mare_stabilizable, unit_circle_condition
from .lower import lower_bound_converges, lower_bound_limit, lower_bound_sequence
from .mare import MARE
from .quantities import critical_capacities, transmission_capacity

SOURCE = "Yang et al., Multi-sensor Kalman filtering with intermittent measurements, Section IV, Example 1, Fig. 2"

_A = [["-0.82", "0.53"], ["0.34", "0.78"]]
_Q = [["0.53", "0.21"], ["0.21", "0.50"]]
_H = [[["-0.69", "0.67"]], [["1.18", "-0.36"], ["0.70", "-0.38"]], [["-1.58", "1.43"]], [["-1.71", "-2.12"]],
      [["-0.65", "0.49"], ["-2.01", "0.46"]], [["1.79", "2.2"], ["0.59", "0.31"]],
      [["1.28", "2.07"], ["-1.00", "-0.92"]], [["0.18", "0.21"], ["2.04", "0.91"]]]
_LAMBDA = ["0.2443", "0.4572", "0.7435", "0.6174", "0.1747", "0.6024", "0.8031", "0.3663"]


def _exact(rows: Any) -> Any:
    return [[Fraction(v) for v in r] for r in rows] if isinstance(rows[0], list) else [Fraction(v) for v in rows]


def example1_system() -> tuple[System, IID]:
    """The printed data, decimals taken exactly; ``H_i`` are the whitened ``C_i`` (``R_i = I``).

    The paper gives no ``Pi``; ``P_1^- = I`` is used.
    """
    sensors = [Sensor(C=_exact(H), name=f"s{i + 1}") for i, H in enumerate(_H)]
    return System(A=_exact(_A), sensors=sensors, Q=_exact(_Q)), IID([1 - Fraction(v) for v in _LAMBDA])


def _loewner_gap(lower: np.ndarray, samples: np.ndarray) -> tuple[float, float]:
    """Smallest eigenvalue of ``mean(samples) - lower`` and the Monte Carlo standard error along its eigenvector."""
    diff = samples.mean(axis=0) - lower
    w, U = np.linalg.eigh((diff + diff.T) / 2)
    u = U[:, 0]
    proj = np.einsum("i,pij,j->p", u, samples, u)
    return float(w[0]), float(proj.std(ddof=1) / np.sqrt(len(proj)))


def reproduce_yang_example1(outdir: str | None = None, *, horizon: int = 40, paths: int = 20_000,
                            seed: int = 2017, z: float = 4.0) -> dict:
    """G_k, V_k and a Monte Carlo ``E[P_k^-]`` (``paths`` runs of :mod:`symkf.numeric.filters`, fixed ``seed``).

    The Loewner claims are checked at every ``k``: the smallest eigenvalue of
    ``Ehat[P_k] - G_k`` (and of ``V_k - Ehat[P_k]``) must not be below ``-z``
    Monte Carlo standard errors.  A PNG like Fig. 2 (traces, 95% band) is
    written to ``outdir`` when given.
    """
    if outdir is not None:   # refused before the work, not after it
        output.plan_directory(outdir, "outdir")
    from ..numeric.filters import predicted_covariances, sample_receptions

    horizon, paths, seed = count(horizon, "horizon", 1), count(paths, "paths", 1), count(seed, "seed")
    if not z > 0:
        raise InputError(f"z: expected a positive number of standard errors, got {z!r}")
    system, loss = example1_system()
    budget.check("max_memory", 8 * paths * horizon * system.n ** 2, "paths x horizon",
                 "the bytes of the predicted covariances of every path and step")
    G = lower_bound_sequence(system, loss, horizon)
    V = MARE(system, loss).sequence(horizon)
    gamma = sample_receptions(loss, horizon, paths, np.random.default_rng(seed))   # per sensor
    P = predicted_covariances(system, gamma, keep="all")  # (paths, K, n, n): P_{k|k-1}
    lower_gaps = [_loewner_gap(G[k], P[:, k]) for k in range(horizon)]
    upper_gaps = [_loewner_gap(-V[k], -P[:, k]) for k in range(horizon)]
    tr_P = np.trace(P, axis1=2, axis2=3)
    mean, se = tr_P.mean(axis=0), tr_P.std(axis=0, ddof=1) / np.sqrt(paths)
    lmi = mare_stabilizable(system, loss)
    ln_rho, h = critical_capacities(system.A)
    Gbar = lower_bound_limit(system, loss)
    Vbar = MARE(system, loss).fixed_point()
    results = {
        "capacity": {"exact": str(transmission_capacity(loss)), "decimal": float(transmission_capacity(loss))},
        "ln_rho": float(ln_rho), "entropy_h": float(h),
        "horizon": horizon, "paths": paths, "seed": seed,
        "trace_G": [float(np.trace(g)) for g in G], "trace_V": [float(np.trace(v)) for v in V],
        "trace_EP": mean.tolist(), "trace_EP_se": se.tolist(),
        "min_eig_EP_minus_G": [g for g, _ in lower_gaps], "min_eig_V_minus_EP": [g for g, _ in upper_gaps],
        "Gbar": [[str(sp.Float(v, 12)) for v in row] for row in Gbar.tolist()],
        "trace_Gbar": float(Gbar.trace()), "trace_Vbar": float(np.trace(Vbar)),
        "theorem4_certificate": lmi.certificate,
    }
    checks = {
        "Proposition 1: G_k <= E[P_k^-] for every k (Loewner, within MC error)":
            all(g >= -z * s for g, s in lower_gaps),
        "Theorem 3: E[P_k^-] <= V_k for every k (Loewner, within MC error)":
            all(g >= -z * s for g, s in upper_gaps),
        "Theorem 1: G_k converges (C > ln rho(A))": lower_bound_converges(system, loss),
        "Theorem 4: V_k converges (condition 1 certified, condition 2 exact)":
            bool(lmi.holds) and unit_circle_condition(system),
        "Fig. 2: the two bounds are not tight (at k = horizon, tr E[P_k^-] is more than z standard errors "
        "inside both bounds)": bool(mean[-1] - results["trace_G"][-1] > z * se[-1]
                                    and results["trace_V"][-1] - mean[-1] > z * se[-1]),
    }
    if outdir is not None:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        k = np.arange(1, horizon + 1)
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(k, results["trace_V"], label="upper bound tr $V_k$ (Theorem 3)")
        ax.plot(k, mean, label=f"tr $E[P_k^-]$, Monte Carlo ({paths} runs)")
        ax.fill_between(k, mean - 1.96 * se, mean + 1.96 * se, alpha=0.3, label="95% band")
        ax.plot(k, results["trace_G"], label="lower bound tr $G_k$ (Proposition 1)")
        ax.set_xlabel("k")
        ax.set_ylabel("trace")
        ax.set_title("Yang et al. Example 1 (Fig. 2)")
        ax.legend()
        fig.tight_layout()
        path = os.path.join(output.plan_directory(outdir, "outdir"), "yang_example1.png")
        results["figure"] = str(output.save_figure(fig, path, "outdir", dpi=120))
        plt.close(fig)
    return reproduction("yang-example1", SOURCE, results, checks)

check_public(globals())
