"""The square-root filter kernel's share of one core's floating-point peak, n = 2, 4, 8, 16 states.

The kernel is :func:`symkf.numeric.filters.log_traces` on receptions drawn beforehand (i.i.d. 0.3
losses, ``d`` single-row sensors, systems of ``bench_simulate.system``).  Work per path-step is
the kernel's own multiplications and additions (:func:`arithmetic_work`: ``d`` Carlson rows, the
time update with ``A`` lower Hessenberg and its short reflectors, the trace), each one flop; the
kernel fuses none (no FMA contraction), so it can reach at most half of an FMA peak.  For n <= 8
the count is checked against the operators of the generated source (:func:`source_arithmetic`);
the loop kernel beyond runs the same operations (and skips zero entries of ``A`` and ``H``).

Peak: derived from ``lscpu`` (FMA pipes x doubles per pipe x 2 flop x clock; AMD family 25,
Zen 3/4, has two 256-bit FMA pipes, AVX-512 is double-pumped; family 26, Zen 5, two 512-bit
pipes; family 23 before model 0x30, Zen and Zen+, two 128-bit pipes) and measured with a numba FMA loop
(``fastmath={"contract"}`` there only; the kernel has no contraction) just before each timed run of
the kernel, in its process: the share of peak is the median of those paired ratios (the machine is
shared; its speed drifts by a quarter between runs, and a peak measured once beforehand moved the
shares with it).  Division and
square-root throughput are measured the same way, on independent operands in [1, 2): each
path-step costs at least ``div / div-rate + sqrt / sqrt-rate`` (they share the divider: one of
each takes the sum, printed), which bounds the share of peak at small ``n``; that bound is
printed next to the measured share.  The counts are the compiled kernel's: the ``vdivpd`` and
``vsqrtpd`` of each loop body of the straight-line kernels (n <= 8), checked against the count
of the source (``divider_work``), which n = 16 uses.

``--main DIR``: the same cells timed with the checkout in ``DIR`` (e.g. ``/work/main``) in a
subprocess, for the same-run ratio against main's kernel: three rounds per cell, this checkout and
``DIR`` in turn, the speed-up the median of the three pairs' ratios (the machine is shared and its
speed drifts between runs).

    nice -n 10 python benchmarks/bench_kernel.py [--quick] [--main /work/main]
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import re
import subprocess
import sys
import time

import numpy as np
from numba import njit

from symkf.numeric.square_root import STRAIGHT_MAX
from timing import median_cpu, peak_rss_mb

HORIZON = 100
CELLS = [(n, d) for n in (2, 4, 8, 16) for d in (1, 3, 8)]

CASE = r"""
import json, sys, time
import numpy as np
import importlib.util
sys.path.insert(0, sys.argv[1])
spec = importlib.util.spec_from_file_location("kernel_peak", sys.argv[5])   # this checkout's FMA loop
peak = importlib.util.module_from_spec(spec)
spec.loader.exec_module(peak)
fma_rate = peak.fma_rate
from bench_simulate import system
from symkf.numeric.filters import log_traces, real_form
horizon, repeats, cells = int(sys.argv[2]), int(sys.argv[3]), json.loads(sys.argv[4])
out = []
for n, d, paths in cells:
    model = real_form(system(n, d))
    received = np.random.default_rng(0).random((horizon, paths, d)) >= 0.3
    log_traces(model, received[:2, :64])                    # compiled kernel loaded before timing
    fma_rate()
    times, peaks = [], []
    for r in range(repeats):
        peaks.append(fma_rate())
        t = time.process_time()
        log_traces(model, received)
        times.append(time.process_time() - t)
    out.append([times, peaks])
print(json.dumps(out))
"""


def paths_for(n: int, quick: bool) -> int:
    return max(2048, (2 ** 15 if quick else 2 ** 17) // n ** 2 // 128 * 128)


def derived_peak() -> tuple[float | None, str]:
    """GFLOP/s of one core from lscpu, with the derivation in words."""
    text = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    field = lambda name: (re.search(rf"^{name}:\s*(.+)$", text, re.M) or [None, None])[1]
    flags = set((field("Flags") or "").split())
    model, family = field("Model name"), field("CPU family")
    mhz = field("CPU max MHz")
    clock, clock_note = (float(mhz) / 1e3, "CPU max MHz") if mhz else (
        (float(field("BogoMIPS")) / 2e3, "BogoMIPS / 2 (the TSC base clock; no max MHz listed)") if field("BogoMIPS") else (None, ""))
    if "fma" not in flags or clock is None:
        return None, f"{model}: no FMA flag or no clock in lscpu"
    width = 512 if "avx512f" in flags else 256
    amd = "AMD" in (field("Vendor ID") or "")
    # AMD family 25 (Zen 3/4) runs AVX-512 double-pumped on 256-bit pipes (Zen 5, family 26, has
    # full 512-bit pipes: 94 GFLOP/s measured on a 2.6 GHz EPYC); family 23 before model 0x30
    # (Zen, Zen+) splits 256-bit operations over 128-bit pipes
    pipe = 256 if (amd and family == "25" and width == 512) else (
        128 if amd and family == "23" and int(field("Model") or 0) < 0x30 else width)
    lanes = pipe // 64
    peak = 2 * lanes * 2 * clock
    return peak, (f"{model} (family {family}), flags {'avx512f ' if 'avx512f' in flags else ''}avx2 fma: "
                  f"2 FMA pipes x {lanes} doubles ({pipe}-bit{' datapath, wider operations double-pumped' if pipe < width else ''})"
                  f" x 2 flop x {clock:.3f} GHz ({clock_note}) = {peak:.1f} GFLOP/s")


@njit(fastmath={"contract"}, error_model="numpy")
def _fma_loop(acc, iters, m, c):
    for _ in range(iters):
        for p in range(acc.size):
            x = acc[p]
            for _ in range(16):
                x = x * m + c
            acc[p] = x


@njit(error_model="numpy")
def _div_pass(x, y, iters, m):
    for _ in range(iters):
        for p in range(x.size):
            y[p] = m / x[p]


@njit(error_model="numpy")
def _sqrt_pass(x, y, iters):
    for _ in range(iters):
        for p in range(x.size):
            y[p] = np.sqrt(x[p])


@njit(error_model="numpy")
def _both_pass(x, y, iters, m):
    for _ in range(iters):
        for p in range(x.size):
            y[p] = m / x[p] + np.sqrt(x[p])


def fma_rate(iters: int = 20_000) -> float:
    """GFLOP/s of one core's FMAs over ``iters`` passes (20 000: about 4 ms, timed next to each kernel
    run, so that the share of peak is a ratio of the same moment: this machine is shared, its speed
    drifts by 25 % between runs, the FMA loop's and the kernel's alike)."""
    acc = np.full(256, 1.5)
    t = time.process_time()
    _fma_loop(acc, iters, 0.9999999, 1e-9)
    return 2 * 16 * 256 * iters / (time.process_time() - t) / 1e9


def measured_rates(repeats: int) -> tuple[float, float, float, float]:
    """(GFLOP/s of FMAs, G divisions/s, G square roots/s, ns of one division and one square root
    together) of one core.  Division and square root: independent operations on 512 operands in
    [1, 2) (throughput, not latency; the divider's time depends on the operand: ``sqrt(1.0)``,
    which a chained loop converges to, is about twice as fast as a general one)."""
    x = np.random.default_rng(0).random(512) + 1.0
    y = np.empty_like(x)
    fma_rate(1), _div_pass(x, y, 1, 3.0), _sqrt_pass(x, y, 1), _both_pass(x, y, 1, 3.0)
    fma = sorted(fma_rate(40_000) for _ in range(repeats))[repeats // 2]
    div = x.size * 40_000 / median_cpu(lambda r: _div_pass(x, y, 40_000, 3.0), repeats) / 1e9
    sqrt = x.size * 40_000 / median_cpu(lambda r: _sqrt_pass(x, y, 40_000), repeats) / 1e9
    both = median_cpu(lambda r: _both_pass(x, y, 40_000, 3.0), repeats) / (x.size * 40_000) * 1e9
    return fma, div, sqrt, both


def divider_work(n: int, rows: int) -> tuple[int, int]:
    """Divisions and square roots per path-step the kernel cannot avoid (:mod:`symkf.numeric.square_root`):
    per Carlson row and column ``sqrt(alpha_j)`` and ``1 / s_j``; per Householder column the norm,
    and but for the last column (never applied) ``1 / (|x| (|x| + |x_0|))``; the log of the trace,
    ``s = f / (2 + f)``."""
    return rows * n + n, rows * n + n


def arithmetic_work(n: int, rows: int) -> tuple[int, int]:
    """(multiplications, additions) per path-step of :mod:`symkf.numeric.square_root`'s kernel for a
    dense lower-Hessenberg ``A``: per Carlson row ``f = S^T h`` and, column by column from the last,
    ``alpha += f_j^2``, ``c`` and ``sn``, the diagonal entry and the rotation of the entries below it
    (and of ``v`` but for column 0); the time update's ``A S`` (entry ``(i, j)``, ``j <= i + 1``: the
    terms ``l = j..min(i + 1, n - 1)``), ``2^(-E/2) U_Q``, each column's reflector over its ``c + 3``
    rows (``c + 2`` for the last, never applied) and the trace's sum of squares."""
    mul = add = 0
    for j in range(n):                                  # a Carlson row
        below = n - 1 - j
        mul += (n - j) + 3 + (2 + 4 * below if j else 1 + 2 * below)
        add += (n - j - 1) + 1 + (2 * below if j else below)
    mul, add = rows * mul, rows * add
    for i in range(n):                                  # A S
        for j in range(min(i + 2, n)):
            terms = min(i + 1, n - 1) - j + 1
            mul, add = mul + terms, add + terms - 1
    mul += n * (n + 1) // 2                             # 2^(-E/2) U_Q
    for c in range(n):                                  # the reflectors
        rows_c = c + 3 if c < n - 1 else c + 2
        mul, add = mul + rows_c, add + rows_c - 1
        if c < n - 1:
            mul, add = mul + 1, add + 2
            later = n - 1 - c
            mul, add = mul + later * (2 * rows_c + 1), add + later * (2 * rows_c - 1)
    return mul + n * (n + 1) // 2, add + n * (n + 1) // 2 - 1


def source_arithmetic(n: int, rows: int) -> tuple[int, int]:
    """(multiplications, additions) per path-step read off the straight-line kernel's source for ``n``
    states: the operators of the lane loop of a Carlson row (``rows`` times) and of the time update's
    lane loops for the logs (the copy for the traces themselves skipped), indices and the
    power-of-two scaling left out."""
    from symkf.numeric.square_root import _straight_source
    lines = _straight_source(n).splitlines()
    loops, skip = [], False
    for i, line in enumerate(lines):
        if line.strip() == "if linear:":
            skip = True
        elif line.strip() == "else:":
            skip = False
        if re.match(r"\s*for p in range\(", line) and not skip:
            depth = len(line) - len(line.lstrip())
            body = list(itertools.takewhile(lambda l: len(l) - len(l.lstrip()) > depth, lines[i + 1:]))
            loops.append("\n".join(body))

    def count(text: str) -> tuple[int, int]:
        text = re.sub(r"\[[^\]]*\]|_pow2\([^)]*\)|_float_bits\([^)]*\)", "", text)
        return (len(re.findall(r"(?<![*])\*(?![*])", text)),
                len(re.findall(r" [-+] ", text)) + len(re.findall(r"[-+]= ", text)))

    carlson = [count(b) for b in loops if "sprev" in b]
    update = [count(b) for b in loops if "root = half[p]" in b]
    trace = [count(b) for b in loops if "tp +=" in b and "root = half[p]" not in b and "scale" not in b]
    mul = rows * carlson[0][0] + sum(m for m, _ in update + trace)
    add = rows * carlson[0][1] + sum(a for _, a in update + trace)
    return mul, add


def loop_divider_work(n: int) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """(divisions, square roots) per path of each lane loop of the straight-line kernel that has
    any, and of those a step runs for the logs at d = 1.  A Carlson row (one loop); the time update,
    one loop per Householder column from ``PHASED_MIN`` to ``PHASED_MAX`` states (the last column
    only its norm), else one loop; up to ``TRACED_MAX`` its last loop written twice, once with the
    log of the traces (one division more); the log's own loop (the last step, and every step
    beyond ``TRACED_MAX``)."""
    from symkf.numeric.square_root import PHASED_MAX, PHASED_MIN, TRACED_MAX
    carlson = [(n, n)]
    columns = [(1, 1)] * (n - 1) + [(0, 1)] if PHASED_MIN <= n <= PHASED_MAX else [(n - 1, n)]
    if n > TRACED_MAX:
        return carlson + columns + [(1, 0)], carlson + columns + [(1, 0)]
    with_log = (columns[-1][0] + 1, columns[-1][1])
    return carlson + columns + [with_log, (1, 0)], carlson + columns[:-1] + [with_log]


def asm_divider_work(n: int) -> tuple[list[tuple[int, int]], str]:
    """(vdivpd, vsqrtpd) on vector registers of the widest width the compiler used (xmm, ymm or zmm:
    2, 4 or 8 paths each) per loop body of the compiled straight-line kernel for ``n`` states, the
    bodies that have any (compiled here without numba's cache, whose code cannot be inspected), per
    vector; and that width's name.  A body the compiler unrolled (2, 4, 8 or 16 vectors at once: up to
    the whole lane loop) holds that multiple of one of :func:`loop_divider_work`'s counts and is
    divided by it; a body matching none is kept whole, and the bodies then differ from the source's."""
    from symkf.numeric import straight_kernels
    from symkf.numeric.square_root import lanes
    kernel = njit(error_model="numpy")(getattr(straight_kernels, f"_paths_{n}"))
    kernel(np.eye(n), np.eye(n), np.ones((1, n)), np.zeros(1, np.int64), np.eye(n), np.ones((1, lanes(n), 1), bool),
           np.empty((1, lanes(n))), 0, True)
    asm = "\n".join(kernel.inspect_asm().values())
    register = next(r for r in ("zmm", "ymm", "xmm") if re.search(rf"^\s*v(div|sqrt)pd\s.*%{r}", asm, re.M))
    bodies = re.split(r"^\.LBB\w+:", asm, flags=re.M)
    counts = [(len(re.findall(rf"^\s*vdivpd\s.*%{register}", b, re.M)),
               len(re.findall(rf"^\s*vsqrtpd\s.*%{register}", b, re.M))) for b in bodies]
    written = loop_divider_work(n)[0]
    # each body's readings as the source's counts (a (2, 2) is one loop with 2 of each, or a
    # (1, 1) loop unrolled twice): the first assignment that gives the source's bodies, if any
    readings = [[tuple(x // u for x in c) for u in (1, 2, 4, 8, 16)
                 if all(x % u == 0 for x in c) and tuple(x // u for x in c) in written] or [c]
                for c in counts if any(c)]
    matching = (list(b) for b in itertools.product(*readings) if sorted(b) == sorted(written))
    return next(matching, [r[0] for r in readings]), register


def run_cells(python: str, root: str, horizon: int, repeats: int, cells: list, env: dict) \
        -> list[list[tuple[float, float]]]:
    """Per cell, ``repeats`` pairs (CPU seconds of ``log_traces``, GFLOP/s of :func:`fma_rate` just
    before it), timed in a subprocess with the checkout ``root``'s benchmarks (``""``: this one's)."""
    here = os.path.join(os.path.abspath(root), "benchmarks") if root else os.path.dirname(os.path.abspath(__file__))
    out = subprocess.run([python, "-c", CASE, here, str(horizon), str(repeats), json.dumps(cells),
                          os.path.abspath(__file__)], capture_output=True, text=True, cwd="/tmp", env=env, check=True)
    return [list(zip(times, peaks)) for times, peaks in json.loads(out.stdout.strip().splitlines()[-1])]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer paths and repeats")
    ap.add_argument("--main", default=None, metavar="DIR", help="a checkout of main, timed in a subprocess")
    args = ap.parse_args()
    repeats = 3 if args.quick else 5
    peak, how = derived_peak()
    fma, div, sqrt, both = measured_rates(repeats)
    print(f"peak (lscpu): {how}")
    print(f"peak (measured, numba FMA loop, one core): {fma:.1f} GFLOP/s; vector division {div:.2f} G/s, "
          f"square root {sqrt:.2f} G/s, one of each {both:.2f} ns (1/div + 1/sqrt = {1 / div + 1 / sqrt:.2f} ns: "
          f"one divider) (CPU seconds, medians of {repeats})")
    for n in sorted({n for n, _ in CELLS if n <= STRAIGHT_MAX}):
        bodies, register = asm_divider_work(n)
        written, step = loop_divider_work(n)
        total = tuple(map(sum, zip(*step)))
        width = {"xmm": 2, "ymm": 4, "zmm": 8}[register]
        same = sorted(bodies) == sorted(written)
        print(f"compiled kernel n = {n}: {register} vdivpd, vsqrtpd per loop body ({width} paths) {bodies}"
              f"{', as the source' if same else ' DIFFERS from the source ' + str(written)}; a step for the logs "
              f"at d = 1 runs {step}: {total} per path-step, the yardstick's {divider_work(n, 1)}"
              f"{'' if total == divider_work(n, 1) else ' DIFFERS'}; each further row adds {(n, n)}")
        for d in sorted({d for m, d in CELLS if m == n}):
            counted, read = arithmetic_work(n, d), source_arithmetic(n, d)
            print(f"  d = {d}: multiplications, additions per path-step {counted}"
                  f"{', as the source' if counted == read else ' DIFFER from the source ' + str(read)}")
    cells = [(n, d, paths_for(n, args.quick)) for n, d in CELLS]
    rounds = 3 if args.main else 1
    here, old = [[] for _ in cells], [[] for _ in cells]
    for j, cell in enumerate(cells):       # this checkout and main in turn, cell by cell: the ratio of each pair
        for _ in range(rounds):
            here[j] += run_cells(sys.executable, "", HORIZON, repeats, [cell], dict(os.environ))[0]
            if args.main:
                env = dict(os.environ, PYTHONPATH=os.path.abspath(args.main))
                old[j] += run_cells(sys.executable, args.main, HORIZON, repeats, [cell], env)[0]
    median = lambda v: sorted(v)[len(v) // 2]
    ratio = [median([b[0] / a[0] for a, b in zip(h, o)]) for h, o in zip(here, old)] if args.main else None
    print(f"horizon {HORIZON}; flop: the kernel's multiplications and additions (arithmetic_work); % peak: the median over {len(here[0])} runs "
          f"of each run's GFLOP/s over the FMA loop's just before it (peak: that loop's median) and, in "
          f"brackets, of the lscpu peak ({peak:.1f}); bound: the divider's limit on that share")
    print(f"{'n':>3} {'d':>2} {'paths':>6} {'CPU s':>7} {'path-steps/s':>12} {'GFLOP/s':>8} {'peak':>5} {'% peak':>13} "
          f"{'bound %':>8}" + (f" {'main CPU s':>10} {'speed-up':>8}" if args.main else ""))
    for j, (n, d, paths) in enumerate(cells):
        work = sum(arithmetic_work(n, d))
        flop = work * paths * HORIZON
        t, paired = median([t for t, _ in here[j]]), median([p for _, p in here[j]])
        share = median([flop / t_r / 1e9 / p_r * 100 for t_r, p_r in here[j]])
        ndiv, nsqrt = divider_work(n, d)
        floor = ndiv / div + nsqrt / sqrt                      # ns per path-step
        bound = work / floor / paired * 100
        line = (f"{n:>3} {d:>2} {paths:>6} {t:>7.3f} {paths * HORIZON / t:>12.3e} {flop / t / 1e9:>8.2f} {paired:>5.1f} "
                f"{share:>5.1f} ({flop / t / 1e9 / peak * 100:>5.1f}) {min(bound, 100):>8.1f}")
        if args.main:
            line += f" {median([o for o, _ in old[j]]):>10.3f} {ratio[j]:>8.2f}"
        print(line, flush=True)
    ndiv, nsqrt = divider_work(2, 1)
    floor = ndiv / div + nsqrt / sqrt
    print(f"division/square-root floor at n = 2, d = 1: {ndiv} divisions + {nsqrt} square roots per path-step "
          f"= {floor:.2f} ns, i.e. at most {sum(arithmetic_work(2, 1)) / floor / fma * 100:.1f} % of the measured peak")
    print(f"peak RSS of this process {peak_rss_mb():.0f} MB")


if __name__ == "__main__":
    main()
