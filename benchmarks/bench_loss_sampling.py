"""``simulate_traces`` under Gilbert-Elliott losses for many sensors: receptions drawn per sensor.

The system is the 4-dimensional block ``diag(2R(pi/6), 2R(pi/4))`` (modulus 2) with ``d``
integer sensor rows drawn from -2..2; every sensor is a Gilbert-Elliott channel with fail 1/10,
recover 1/2.  Each case runs in a fresh process (its peak RSS is its own):

* ``simulate``: :func:`symkf.numeric.montecarlo.simulate_traces` (receptions sampled per factor of the
  loss model, :meth:`symkf.model.loss.LossModel.sample`, then the compiled square-root filter);
* ``kernel``: the filter kernel alone, :func:`symkf.numeric.filters.traces_into` (what
  ``simulate_traces`` runs after drawing the receptions), on receptions drawn
  beforehand with plain NumPy (not timed): the floor ``simulate`` is compared with, timed
  alternately with ``simulate`` in one process (the ratio is the median of the pairs: on a
  loaded machine separate processes see different loads);
* ``main``: ``simulate_traces`` of main (``--main PYTHON``, the interpreter of a checkout
  of main), which samples from the joint ``2^d``-state chain: feasible up to about d = 12
  (d = 16 needs a 34 GB matrix), so it is run at d = 8 and 12 for the same-run ratio.

Printed: CPU seconds (``resource`` user + system of the child, medians over repeats, the
compiled kernel loaded before timing), peak RSS (MB) and the ratios.  Targets:
d = 16 and 64 in <= 500 MB and within 1.5x of the kernel alone.

    nice -n 10 python benchmarks/bench_loss_sampling.py [--quick] [--main /work/wt/main-ref/.venv/bin/python]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

CASE = r"""
import json, resource, sys, time
import numpy as np, sympy as sp
from symkf.numeric.filters import real_form, traces_into
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.system import Sensor, System
from symkf.numeric.montecarlo import simulate_traces

mode, d, horizon, paths, repeats = sys.argv[1], *map(int, sys.argv[2:6])
R = lambda t: sp.Matrix([[sp.cos(t), -sp.sin(t)], [sp.sin(t), sp.cos(t)]])
A = sp.diag(2 * R(sp.pi / 6), 2 * R(sp.pi / 4))
rows = np.random.default_rng(d).integers(-2, 3, (d, 4))
rows[np.all(rows == 0, axis=1), 0] = 1
S = System(A=A, sensors=[Sensor(C=[[int(x) for x in r]]) for r in rows])
loss = GilbertElliott(["1/10"] * d, ["1/2"] * d)
model = real_form(S)
simulate_traces(S, GilbertElliott(["1/10"], ["1/2"]) if d == 1 else loss, 2, 64, seed=0)  # load the kernel
kernel, simulate = [], []
for r in range(repeats):   # "both": alternately, so that both see the same machine load
    if mode != "simulate":   # Gilbert-Elliott receptions drawn beforehand, per sensor, plain NumPy
        rng = np.random.default_rng(r)
        received = np.empty((horizon, paths, d), bool)
        received[0] = rng.random((paths, d)) < 5 / 6
        for k in range(1, horizon):
            u = rng.random((paths, d))
            received[k] = np.where(received[k - 1], u >= 1 / 10, u < 1 / 2)
        t = time.process_time()
        traces_into(model, received, np.empty((horizon, paths)).T)
        kernel.append(time.process_time() - t)
        del received, u
    if mode != "kernel":
        t = time.process_time()
        simulate_traces(S, loss, horizon, paths, seed=r)
        simulate.append(time.process_time() - t)
median = lambda xs: sorted(xs)[len(xs) // 2] if xs else None
ratio = median([s / k for s, k in zip(simulate, kernel)]) if kernel and simulate else None
print(json.dumps({"kernel": median(kernel), "simulate": median(simulate), "ratio": ratio,
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def run(python: str, mode: str, d: int, horizon: int, paths: int, repeats: int, memory_mb: int) -> dict | None:
    """One case in a fresh process under ``ulimit -v``; None when it fails (e.g. out of memory)."""
    cmd = f"ulimit -v {memory_mb * 1024}; exec {python} -c \"$0\" {mode} {d} {horizon} {paths} {repeats}"
    out = subprocess.run(["bash", "-c", cmd, CASE], capture_output=True, text=True, cwd="/tmp")
    if out.returncode:
        return None
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer paths and repeats")
    ap.add_argument("--main", default=None, metavar="PYTHON", help="interpreter of a checkout of main")
    args = ap.parse_args()
    horizon, paths, repeats = (50, 2048, 1) if args.quick else (100, 16384, 7)
    print(f"n = 4, Gilbert-Elliott (fail 1/10, recover 1/2) per sensor; horizon {horizon}, {paths} paths; "
          f"CPU s (medians of {repeats}) and peak RSS per fresh process")
    print(f"{'d':>3} {'case':<34} {'CPU s':>8} {'RSS MB':>8} {'ratio':>7}")
    for d in (8, 12, 16, 64):
        both = run(sys.executable, "both", d, horizon, paths, repeats, 4000)
        new = run(sys.executable, "simulate", d, horizon, paths, repeats, 4000)
        print(f"{d:>3} {'kernel alone (pre-drawn receptions)':<34} {both['kernel']:>8.3f}")
        print(f"{d:>3} {'simulate_traces (per factor)':<34} {both['simulate']:>8.3f} {new['rss_mb']:>8.0f} "
              f"{both['ratio']:>7.2f}  (simulate / kernel, median of same-process pairs)", flush=True)
        if args.main and d <= 12:
            old = run(args.main, "simulate", d, horizon, paths, repeats, 8000)
            if old is None:
                print(f"{d:>3} {'simulate_traces, main':<34} failed under 8 GB")
            else:
                print(f"{d:>3} {'simulate_traces, main (joint chain)':<34} {old['simulate']:>8.3f} {old['rss_mb']:>8.0f} "
                      f"{old['simulate'] / new['simulate']:>7.2f}  (main / new)", flush=True)
        elif args.main:
            print(f"{d:>3} {'simulate_traces, main':<34} not run: the joint chain has 4^{d} float64 entries")

if __name__ == "__main__":
    main()
