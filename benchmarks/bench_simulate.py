"""Monte Carlo throughput against a per-path float64 loop, for n = 2, 4, 8 and d = 1, 3, 8, 16.

The batched engine is :func:`symkf.numeric.montecarlo.burst_sample` (the compiled square-root
filter with a log-scale, :mod:`symkf.numeric.square_root`; receptions sampled per independent
sensor), plain (i.i.d. and Gilbert-Elliott losses) and with final-burst importance
sampling (Gilbert-Elliott, a pattern losing sensor 1).  The baseline is the textbook loop,
one path and one step at a time (eq. 9 with the stacked received rows, ``np.linalg.inv``),
measured in the same process.  Printed: CPU seconds (time.process_time, medians),
path-steps per CPU second, the ratio, the set-up cost of one call (paths = 2, horizon = 1)
and, for ``jobs = 2``, wall and CPU (with the workers') against ``jobs = 1``.

Second, ``simulate_traces`` (receptions sampled per sensor, then the kernel) against the
vectorised NumPy covariance-form filter over all paths at once (``batch_filter.py``, BLAS on
one thread, drawing its own receptions), for n = 2, 4, 8, 16 x d = 1, 3, 8 under i.i.d. and
Gilbert-Elliott losses, and against the kernel alone (:func:`symkf.numeric.filters.traces_into`, what
``simulate_traces`` runs after drawing the receptions, on receptions drawn beforehand): CPU seconds (medians), the ratios of the same run,
and the process's peak RSS (per fresh process for many sensors: ``bench_loss_sampling.py``).
Yardsticks: baseline / simulate >= 2 in every cell; simulate / kernel is the cost of drawing the receptions
(about 0.7 ns per sensor-step, rng.random: 1.6-1.8 at n = 2 with 3 and 8 sensors, where the kernel is fastest).
Set-up of the compiled kernel: a fresh process's first call with numba's
cache present, and with an empty cache (``NUMBA_CACHE_DIR``: the first call ever).
Targets: ratio >= 100 at every size, >= 1e7 path-steps/s at n = 2, d = 3,
set-up <= 1 s, both cores used with jobs = 2.

    nice -n 10 python benchmarks/bench_simulate.py [--quick] [--grid]
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):   # before numpy: one BLAS thread
    os.environ[_var] = "1"

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import sympy as sp

from symkf.numeric.filters import real_form, sample_receptions, traces_into
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.model.system import Sensor, System
from symkf.numeric.montecarlo import BurstPlan, burst_sample, simulate_traces

from batch_filter import trace_batch
from timing import median_cpu as cpu, peak_rss_mb

HORIZON = 100


def system(n: int, d: int) -> System:
    """Rotation blocks of modulus 21/20 (n/2 of them, angles pi/3, pi/4, ...), d integer sensor rows."""
    A = sp.zeros(n, n)
    for b in range(n // 2):
        c, s = sp.cos(sp.pi / (3 + b)), sp.sin(sp.pi / (3 + b))
        A[2 * b:2 * b + 2, 2 * b:2 * b + 2] = sp.Rational(21, 20) * sp.Matrix([[c, -s], [s, c]])
    rng = np.random.default_rng(n * 100 + d)
    rows = rng.integers(-2, 3, (d, n))
    rows[np.all(rows == 0, axis=1), 0] = 1
    return System(A=A, sensors=[Sensor(C=[[int(x) for x in r]]) for r in rows])


def naive(S: System, eps: float, paths: int, seed: int) -> None:
    """The textbook loop: one path at a time, eq. (9) with the stacked received rows."""
    A = np.array(S.A.evalf().tolist(), dtype=float)
    C = np.array(S.C.tolist(), dtype=float)
    n, d = A.shape[0], C.shape[0]
    rng = np.random.default_rng(seed)
    for _ in range(paths):
        P = np.eye(n)
        for _ in range(HORIZON):
            np.trace(P)
            got = rng.random(d) >= eps
            if got.any():
                H = C[got]
                K = P @ H.T @ np.linalg.inv(H @ P @ H.T + np.eye(int(got.sum())))
                P = P - K @ H @ P
            P = A @ P @ A.T + np.eye(n)


GRID_PATHS = {2: 16384, 4: 8192, 8: 2048, 16: 1024}


def numpy_grid(repeats: int, quick: bool) -> None:
    """simulate_traces against the NumPy batch filter and against the kernel alone, n x d x losses:
    the three timed in turn, ``repeats`` rounds, the ratios the medians of each round's (the machine
    is shared: separate medians of separately timed runs moved a ratio by a fifth between runs)."""
    print(f"{'n':>2} {'d':>2} {'losses':<16} {'paths':>6} {'simulate s':>10} {'numpy s':>8} {'numpy/sim':>9} "
          f"{'kernel s':>8} {'sim/kernel':>10}")
    for n in (2, 4, 8, 16):
        for d in (1, 3, 8):
            S = system(n, d)
            model = real_form(S)
            paths = GRID_PATHS[n] // (4 if quick else 1)
            for name, loss, stay, back in (("i.i.d. 0.3", IID(["3/10"] * d), 0.7, 0.7),
                                           ("Gilbert-Elliott", GilbertElliott(["1/4"] * d, ["1/2"] * d), 0.75, 0.5)):
                law = [np.full(d, x) for x in (stay, back, stay)]
                simulate_traces(S, loss, 2, 64, seed=0)                  # compiled kernel loaded
                gamma = sample_receptions(loss, HORIZON, paths, np.random.default_rng(0))   # (paths, horizon, d)
                received = np.ascontiguousarray(gamma.transpose(1, 0, 2))
                out = np.empty((HORIZON, paths)).T   # Fortran order, as simulate_traces's
                runs = {"sim": lambda r: simulate_traces(S, loss, HORIZON, paths, seed=r),
                        "base": lambda r: trace_batch(model.A, model.Q, model.P0, model.H, model.row_sensor,
                                                      HORIZON, paths, *law, r),
                        "kern": lambda r: traces_into(model, received, out)}
                times = {key: [] for key in runs}
                for r in range(repeats):   # in turn: each ratio is of one round, under one machine load
                    for key, run in runs.items():
                        times[key].append(cpu(lambda _: run(r), 1))
                med = statistics.median
                sim, base, kern = (med(times[key]) for key in runs)
                over = med([b / a for a, b in zip(times["sim"], times["base"])])
                floor = med([a / k for a, k in zip(times["sim"], times["kern"])])
                print(f"{n:>2} {d:>2} {name:<16} {paths:>6} {sim:>10.4f} {base:>8.4f} {over:>9.2f} "
                      f"{kern:>8.4f} {floor:>10.2f}", flush=True)
    print(f"peak RSS of this process {peak_rss_mb():.0f} MB")


SETUP = ("import time, numpy as np, sympy as sp; from symkf.model.iid import IID; from symkf.model.system import Sensor, System; "
         "from symkf.numeric.montecarlo import burst_sample; S = System(A=sp.Matrix([[1, 1], [0, 1]]), "
         "sensors=[Sensor(C=[[1, 0]])]); t = time.process_time(); burst_sample(S, IID(['3/10']), 1, 2, 0, None); "
         "print(time.process_time() - t)")


def compiled_setup() -> None:
    """CPU seconds of the first call in a fresh process: numba cache empty, then present."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label in ("first call ever (empty numba cache)", "fresh process, numba cache present"):
            out = subprocess.run([sys.executable, "-c", SETUP], env=env, capture_output=True, text=True, check=True)
            print(f"set-up, {label}: {float(out.stdout):.3f} CPU s", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer paths and repeats")
    ap.add_argument("--grid", action="store_true", help="only the set-up and the grid against NumPy")
    args = ap.parse_args()
    paths, loop_paths, repeats = (4096, 10, 1) if args.quick else (16384, 20, 3)
    grid_repeats = 3 if args.quick else 7
    print(f"horizon {HORIZON}; batched {paths} paths, loop {loop_paths} paths; CPU seconds, medians of {repeats} "
          f"({grid_repeats} rounds in the grid, its ratios the medians of the rounds' ratios)")
    compiled_setup()
    burst_sample(system(2, 1), IID(["3/10"]), 1, 2, 0, None)   # this process loads the compiled kernel once
    numpy_grid(grid_repeats, args.quick)
    if args.grid:
        return
    print(f"{'n':>2} {'d':>3} {'losses':<22} {'set-up s':>8} {'batched CPU s':>13} {'path-steps/s':>12} "
          f"{'loop path-steps/s':>17} {'ratio':>6}")
    for n in (2, 4, 8):
        for d in (1, 3, 8, 16):
            S = system(n, d)
            cases = [("i.i.d. 0.3", IID(["3/10"] * d), None),
                     ("Gilbert-Elliott", GilbertElliott(["1/4"] * d, ["1/2"] * d), None),
                     ("G-E, final bursts", GilbertElliott(["1/4"] * d, ["1/2"] * d),
                      BurstPlan(np.array([[[j != 0 for j in range(d)]]]), float(sp.Rational(21, 20) ** 2)))]
            loop = loop_paths * HORIZON / cpu(lambda r: naive(S, 0.3, loop_paths, r), repeats)
            for name, loss, plan in cases:
                setup = cpu(lambda r: burst_sample(S, loss, 1, 2, r, plan), 1)
                batched = paths * HORIZON / cpu(lambda r: burst_sample(S, loss, HORIZON, paths, r, plan), repeats)
                print(f"{n:>2} {d:>3} {name:<22} {setup:>8.3f} {paths * HORIZON / batched:>13.3f} "
                      f"{batched:>12.3e} {loop:>17.3e} {batched / loop:>6.0f}", flush=True)
    S, loss = system(8, 3), IID(["3/10"] * 3)
    results = []
    for jobs in (1, 2):   # 4 x paths = 2 chunks of 32768: the workers get one each
        wall, t = time.perf_counter(), time.process_time()
        children = resource.getrusage(resource.RUSAGE_CHILDREN)
        results.append(burst_sample(S, loss, HORIZON, 4 * paths, 0, None, jobs)[0])
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        workers = (after.ru_utime + after.ru_stime) - (children.ru_utime + children.ru_stime)
        print(f"jobs = {jobs}: n = 8, d = 3, {4 * paths} paths: wall {time.perf_counter() - wall:.2f} s, "
              f"CPU {time.process_time() - t:.2f} s in this process + {workers:.2f} s in workers", flush=True)
    print(f"same result with jobs = 1 and 2: {np.array_equal(*results)}")


if __name__ == "__main__":
    main()
