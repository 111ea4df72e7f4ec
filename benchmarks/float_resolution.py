"""How far float64 follows the sampled paths of ``divergence_test``: the kernel against exact arithmetic.

For ``symkf/io/examples/systems/ge-two-sensors.toml`` with recovery ``--recover`` (the member of
``ge-recovery.toml``), draws the final-burst importance sample of ``log E[tr P_k]`` at ``k = h,
2h, 3h`` (seeds ``seed``, ``seed + 1``, ``seed + 2``, as ``divergence_test``), recomputes
``log tr P_{k|k-1}`` of every path by the exact rational Riccati recursion (python-flint
``fmpq_mat``; the system is integer, ``Q = P0 = I``, ``R = 1``), and prints per horizon the
paths the float kernel misses, ``log E`` float and exact, and the margin estimate
``((E_3h - E_2h) / (E_2h - E_h))^(1/h)`` both ways against the exact margin.

    nice -n 10 python benchmarks/float_resolution.py [--recover 1/4] [--h 40] [--paths 15000] [--seed 1]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from flint import fmpq_mat

import symkf.numeric.montecarlo as mc
from symkf import GilbertElliott, Sensor, System


def exact_log_trace(received: np.ndarray) -> float:
    """``log tr P_{K|K-1}`` for one path's receptions (K, 2), exact (covariance form, eq. 9)."""
    A, I = fmpq_mat([[0, -2], [2, 0]]), fmpq_mat([[1, 0], [0, 1]])
    C = [fmpq_mat([[1, 0]]), fmpq_mat([[1, 1]])]
    P = I
    for row in received:
        for c, got in zip(C, row):
            if got:
                Pc = P * c.transpose()
                P = P - Pc * Pc.transpose() * (1 / ((c * Pc)[0, 0] + 1))
        P = A * P * A.transpose() + I
    t = P[0, 0] + P[1, 1]
    return math.log(int(t.p)) - math.log(int(t.q))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--recover", default="1/4")
    ap.add_argument("--h", type=int, default=40)
    ap.add_argument("--paths", type=int, default=15000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    system = System([[0, -2], [2, 0]], [Sensor([[1, 0]], name="s1"), Sensor([[1, 1]], name="s2")])
    loss = GilbertElliott(["1/4", "1/4"], [args.recover] * 2)
    verdict = mc._verdict(system, loss)
    plan = mc.verdict_plan(system, verdict, loss)
    seen = []
    kernel = mc.log_traces

    def keep(model, received):          # burst_sample does not return the receptions: keep them
        seen.append(received.copy())
        return kernel(model, received)

    mc.log_traces = keep
    logE = {"float": [], "exact": []}
    for j, k in enumerate((args.h, 2 * args.h, 3 * args.h)):
        seen.clear()
        start = time.process_time()
        logtr, logw = mc.burst_sample(system, loss, k, args.paths, args.seed + j, plan)
        exact = np.array([exact_log_trace(seen[0][:, p]) for p in range(args.paths)])
        err = logtr - exact
        y = exact + logw
        share = np.exp(y - y.max())
        bad = np.abs(err) > 1e-3
        for name, v in (("float", logtr), ("exact", exact)):
            z = v + logw
            logE[name].append(z.max() + math.log(np.mean(np.exp(z - z.max()))))
        print(f"k = {k}: float misses log tr P by > 1e-3 on {bad.sum()} of {args.paths} paths "
              f"(float - exact in [{err.min():.3g}, {err.max():.3g}]), carrying {share[bad].sum() / share.sum():.3f} "
              f"of the exact mean; log E float {logE['float'][-1]:.5f}, exact {logE['exact'][-1]:.5f} "
              f"({time.process_time() - start:.1f} CPU-s)")
    margin = float(mc.exact_growth_rate(verdict).exact.evalf(12))
    for name, v in logE.items():
        e = [math.exp(x - max(v)) for x in v]
        m = ((e[2] - e[1]) / (e[1] - e[0])) ** (1 / args.h)
        print(f"margin estimate, {name} log tr P: {m:.5f} ({100 * (m / margin - 1):+.3f} % against {margin:.5f})")


if __name__ == "__main__":
    main()
