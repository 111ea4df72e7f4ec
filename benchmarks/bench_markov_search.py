"""Markov-loss, ray and per-sensor queries without listing every hyperplane.

The 4-dim eigen-block diag(2R(pi/6), 2R(pi/4)) (modulus 2, governing period 24) with d integer
sensor rows drawn from -2..2 (fixed seed); rows and targets:

* Gilbert-Elliott (fail 1/10, recover 1/2 per sensor), ``stability``, d = 8 / 16: <= 5 / 20 CPU-s;
* ``critical_recovery_rate``, Gilbert-Elliott (fail 1/10), d = 8: <= 10 CPU-s; the same with only
  sensor s1's rate varying (the others recover at 1/2; main lists every hyperplane and is refused);
* a joint Markov chain over two correlated sensor pairs (d = 4, 16 receival vectors): <= 5 CPU-s;
* ``critical_loss_rate(ray=...)`` and ``(sensor=..., others=...)``, d = 16: <= 2x the common query,
  also with ray weights 0 and above 1 and others of loss 0 (main lists every hyperplane: refused);
  a ray of three weights 1, 2, 3 is measured beside them (no target);
* peak memory of every row <= 500 MB;
* ``critical_recovery_rate`` (fail 1/10) with rows from seed 1000 + d, d = 16 / 32 / 64 (d = 64 <= 30
  CPU-s); on the 6-dim block (3/2) diag(R(pi/2), R(pi/3), R(2 pi/3)) with three sensors in general
  position, fail (1/2, 1/2, 3/10) (main refuses it by max_hyperplanes); with four sensors failing at
  (3/5, 1/2, 3/5, 9/10), whose q_c lies above 1 - max fail (every hyperplane listed);
* joint chains of 2 / 3 / 4 correlated pairs (16 / 64 / 256 states) with rows from seed 1000 + d
  (four pairs <= 10 CPU-s; main refuses 256 states by max_markov_states).

Beside them (no target), a block in general position: 2R(2 pi/7) + 2R(2 pi/11) with two sensors
on Gilbert-Elliott channels, whose C(154, 3) hyperplanes cost 40 CPU-s to list, decided by its
special hyperplanes and the best rate of any three elements (symkf.engine.generic_hyperplanes); and the
same by the list (``search.LIST_BELOW`` raised; on main ``max_hyperplanes``), the reference in the same run.

Many sensors (``--rows many``), at the default caps: the same block with d = 128 ... 1024 integer
rows from the seed 1000 + d, the common critical loss rate (d = 1024: <= 60 CPU-s) and
Gilbert-Elliott stability (fail 1/10, recover 1/2; d = 1024: answered in <= 60 or refused in <= 5
CPU-s, the refusal time printed; d = 2048: refused in <= 5), each with the work priced before its heavy steps (``budget.price``)
beside what it cost; the system's construction is inside their timing.  Main refuses them by its
sensor count (64), so its baseline runs with its caps raised (``max_sensors``, ``max_hyperplanes``,
``max_screen_work``), for the digest.

Each measurement is a fresh interpreter (cold caches) printing the CPU seconds of the computation
(``time.process_time``), its peak RSS and a digest of the exact result.  The baseline is
``main`` from a separate checkout (``--main``, default /work/main, run by ``--main-python``,
default that checkout's .venv/bin/python), run once per row in the same run under a time limit
(``--limit``, reported as ``> limit``) and an address-space cap of 4 GB (``> 4 GB``).  Medians over
REPEATS runs of this checkout.

Usage: python bench_markov_search.py [REPEATS] [--main PATH] [--main-python PYTHON] [--limit SECONDS] [--rows A|B]
Child mode: python bench_markov_search.py --child ROW
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
MEMORY_CAP = 4 * 1024 ** 3

ROWS = {  # name: (what, d, target CPU-s or None)
    "G-E stability, d = 8": ("ge", 8, 5),
    "G-E stability, d = 16": ("ge", 16, 20),
    "G-E critical_recovery_rate, d = 8": ("recovery", 8, 10),
    "G-E critical_recovery_rate(sensor=s1), d = 8": ("recovery-sensor", 8, 10),
    "joint chain, two correlated pairs, d = 4": ("pairs", 4, 5),
    "common critical_loss_rate, d = 8": ("common", 8, None),
    "critical_loss_rate(ray=w), d = 8": ("ray", 8, None),
    "critical_loss_rate(sensor=s1, others), d = 8": ("sensor", 8, None),
    "common critical_loss_rate, d = 16": ("common", 16, None),
    "critical_loss_rate(ray=w), d = 16": ("ray", 16, "2x common"),
    "critical_loss_rate(sensor=s1, others), d = 16": ("sensor", 16, "2x common"),
    "critical_loss_rate(ray=w, w in {0, 2, 9/10}), d = 16": ("ray-extremes", 16, "2x common"),
    "critical_loss_rate(sensor=s1, others with 0), d = 16": ("sensor-zero", 16, "2x common"),
    "critical_loss_rate(ray=w, w in {1, 2, 3}), d = 16": ("ray-three", 16, None),
    "G-E critical_recovery_rate, rows of seed 1000 + d, d = 16": ("recovery-seeded", 16, None),
    "G-E critical_recovery_rate, rows of seed 1000 + d, d = 32": ("recovery-seeded", 32, None),
    "G-E critical_recovery_rate, rows of seed 1000 + d, d = 64": ("recovery-seeded", 64, 30),
    "critical_recovery_rate, 6-dim block in general position": ("recovery-six", 3, None),
    "critical_recovery_rate, fail (3/5, 1/2, 3/5, 9/10), d = 4": ("recovery-above", 4, None),
    "joint chain, pairs, rows of seed 1000 + d, d = 4": ("pairs-seeded", 4, None),
    "joint chain, pairs, rows of seed 1000 + d, d = 6": ("pairs-seeded", 6, None),
    "joint chain, pairs, rows of seed 1000 + d, d = 8": ("pairs-seeded", 8, 10),
    "G-E stability, 2R(2pi/7) + 2R(2pi/11), d = 2": ("general", 2, None),
    "the same by the list (max_hyperplanes 10^6)": ("general-listed", 2, None),
    "many: common critical_loss_rate, d = 128": ("many-common", 128, None),
    "many: common critical_loss_rate, d = 256": ("many-common", 256, None),
    "many: common critical_loss_rate, d = 512": ("many-common", 512, None),
    "many: common critical_loss_rate, d = 1024": ("many-common", 1024, 60),
    "many: G-E stability, d = 128": ("many-ge", 128, None),
    "many: G-E stability, d = 512": ("many-ge", 512, None),
    "many: G-E stability, d = 1024": ("many-ge", 1024, 60),
    "many: G-E stability, d = 2048": ("many-ge", 2048, 5),
}

#: the caps a baseline without work pricing needs raised to run the many-sensor rows (names that
#: this tree's budget does not know are left out)
MAIN_RAISED = {"max_sensors": 4096, "max_hyperplanes": 10 ** 12, "max_screen_work": 10 ** 15}

#: a correlated channel of two sensors on (received, received), (received, lost), ...
PAIR = {(1, 1): {(1, 1): Fraction(4, 5), (1, 0): Fraction(1, 20), (0, 1): Fraction(1, 20), (0, 0): Fraction(1, 10)},
        (1, 0): {(1, 1): Fraction(1, 2), (1, 0): Fraction(1, 5), (0, 1): Fraction(1, 10), (0, 0): Fraction(1, 5)},
        (0, 1): {(1, 1): Fraction(1, 2), (1, 0): Fraction(1, 10), (0, 1): Fraction(1, 5), (0, 0): Fraction(1, 5)},
        (0, 0): {(1, 1): Fraction(2, 5), (1, 0): Fraction(1, 10), (0, 1): Fraction(1, 10), (0, 0): Fraction(2, 5)}}


def system(d: int, seed: int = 0):
    import numpy as np
    import sympy as sp
    import symkf as sk

    def rotation(angle):
        return 2 * sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])
    rng = np.random.default_rng(seed)
    rows = []
    while len(rows) < d:
        r = [int(v) for v in rng.integers(-2, 3, 4)]
        if any(r):
            rows.append(r)
    return sk.System(A=sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)),
                     sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)])


def seeded(d: int):
    """The same block with d integer rows from seed 1000 + d (a zero row gets a 1 first)."""
    import numpy as np
    import symkf as sk
    rows = np.random.default_rng(1000 + d).integers(-2, 3, (d, 4))
    rows[np.all(rows == 0, axis=1), 0] = 1
    return sk.System(A=system(1).A, sensors=[sk.Sensor(C=[[int(v) for v in r]], name=f"s{j + 1}")
                                             for j, r in enumerate(rows)])


def six():
    """(3/2) diag(R(pi/2), R(pi/3), R(2 pi/3)) seen by three sensors in general position."""
    import sympy as sp
    import symkf as sk

    def rotation(angle):
        return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])
    rows = [[-2, -2, -2, 0, -1, 0], [0, 2, -1, 2, -2, 2], [-1, 1, 1, 2, 0, 2]]
    return sk.System(A=sp.Rational(3, 2) * sp.diag(rotation(sp.pi / 2), rotation(sp.pi / 3), rotation(2 * sp.pi / 3)),
                     sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)])


def pairs(k: int):
    """The joint MarkovLoss of k independent correlated pairs (d = 2k sensors, 4^k receival vectors)."""
    import symkf as sk
    table = {}
    for hist in itertools.product(PAIR, repeat=k):
        table[sum(hist, ())] = {sum(nxt, ()): _product(PAIR[h][n] for h, n in zip(hist, nxt))
                                for nxt in itertools.product(PAIR, repeat=k)}
    return sk.MarkovLoss(table)


def _product(values) -> Fraction:
    out = Fraction(1)
    for v in values:
        out *= v
    return out


def general():
    """2R(2 pi/7) + 2R(2 pi/11) seen by two sensors in general position."""
    import sympy as sp
    import symkf as sk

    def rotation(q):
        return 2 * sp.Matrix([[sp.cos(2 * sp.pi / q), -sp.sin(2 * sp.pi / q)], [sp.sin(2 * sp.pi / q), sp.cos(2 * sp.pi / q)]])
    return sk.System(A=sp.diag(rotation(7), rotation(11)),
                     sensors=[sk.Sensor(C=[[2, 1, 0, -1]], name="s1"), sk.Sensor(C=[[-2, -2, 2, 1]], name="s2")])


def _compute(what: str, d: int) -> str:
    import symkf as sk
    from symkf import budget
    if what.startswith("general"):
        from symkf.engine import search
        if what == "general":
            v = sk.stability(general(), sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))
        elif "max_hyperplanes" in budget.OPTIONS:   # a baseline that lists up to that cap
            with budget.limits(max_hyperplanes=10 ** 6):
                v = sk.stability(general(), sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))
        else:
            search.LIST_BELOW = float("inf")   # the list chosen whatever its estimate (a child of its own)
            v = sk.stability(general(), sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))
        return f"{v.stable} {[str(m.exact) for m in v.margins]}"
    if what.startswith("many"):
        S = system(d, 1000 + d)
        if what == "many-common":
            return str(sk.critical_loss_rate(S).exact)
        v = sk.stability(S, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))
        return f"{v.stable} {[str(m.exact) for m in v.margins]}"
    if what == "recovery-six":
        return str(sk.critical_recovery_rate(six(), fail=["1/2", "1/2", "3/10"]).exact)
    if what == "recovery-seeded":
        return str(sk.critical_recovery_rate(seeded(d), fail=["1/10"] * d).exact)
    if what == "recovery-above":   # q_c above 1 - max fail: every hyperplane is listed
        return str(sk.critical_recovery_rate(system(d), fail=["3/5", "1/2", "3/5", "9/10"]).exact)
    if what == "pairs-seeded":
        v = sk.stability(seeded(d), pairs(d // 2))
        return f"{v.stable} {[str(m.exact) for m in v.margins]}"
    S = system(d)
    if what == "ge":
        v = sk.stability(S, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))
        return f"{v.stable} {[str(m.exact) for m in v.margins]}"
    if what == "pairs":
        v = sk.stability(S, pairs(d // 2))
        return f"{v.stable} {[str(m.exact) for m in v.margins]}"
    if what == "recovery":
        return str(sk.critical_recovery_rate(S, fail=["1/10"] * d).exact)
    if what == "recovery-sensor":
        return str(sk.critical_recovery_rate(S, fail=["1/10"] * d, recover=["1/2"] * d, sensor="s1").exact)
    if what == "ray-extremes":
        return str(sk.critical_loss_rate(S, ray=(["2", "0", "9/10"] * d)[:d]).exact)
    if what == "sensor-zero":
        return str(sk.critical_loss_rate(S, "s1", others=(["9/10", "0", "1/2"] * d)[:d]).exact)
    if what == "common":
        return str(sk.critical_loss_rate(S).exact)
    if what == "ray":
        return str(sk.critical_loss_rate(S, ray=(["1", "9/10"] * d)[:d]).exact)
    if what == "ray-three":   # three weights: many more candidate bounds, each x^k W - 1 of degree ~300
        return str(sk.critical_loss_rate(S, ray=(["1", "2", "3"] * d)[:d]).exact)
    return str(sk.critical_loss_rate(S, "s1", others=["9/10"] * d).exact)


def _child(row: str, raised: bool = False) -> None:
    from symkf import budget
    what, d, _ = ROWS[row]
    caps = {k: v for k, v in MAIN_RAISED.items() if k in budget.OPTIONS} if raised else {}
    with budget.limits(**caps):
        _timed(what, d)


def _timed(what: str, d: int) -> None:
    from symkf import budget
    system(d)  # imports and field set-up outside the timing, as in every row
    estimates = []   # the work priced before each heavy step that ran (a tree with budget.price)
    if hasattr(budget, "price"):
        price = budget.price
        budget.price = lambda *names, **units: estimates.append(price(*names, **units)) or estimates[-1]
    start = time.process_time()
    try:
        result, error = _compute(what, d), None
    except Exception as exc:  # a refusal (BudgetError) is a result of the row
        result, error = "", f"{type(exc).__name__}: {str(exc)[:160]}"
    cpu = time.process_time() - start
    print(json.dumps({"cpu": cpu, "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                      "digest": hashlib.sha1(result.encode()).hexdigest()[:12], "error": error,
                      "estimate": sum(estimates)}))


def _cap() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP, MEMORY_CAP))


def _run(tree: Path, row: str, limit: float, python: str = sys.executable, raised: bool = False) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree), "OPENBLAS_NUM_THREADS": "1"}
    try:
        proc = subprocess.run([python, __file__, "--child" + ("-raised" if raised else ""), row], env=env, capture_output=True, text=True,
                              timeout=limit, cwd=tree, preexec_fn=_cap)
    except subprocess.TimeoutExpired:
        return {"cpu": None, "why": f"> {limit:.0f} s"}
    if proc.returncode != 0 or not proc.stdout.strip():
        memory = "MemoryError" in proc.stderr or proc.returncode < 0
        return {"cpu": None, "why": "> 4 GB" if memory else f"failed: {proc.stderr.strip()[-120:]}"}
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    if out["error"] and "MemoryError" in out["error"]:
        return {"cpu": None, "why": "> 4 GB"}
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("repeats", nargs="?", type=int, default=3)
    ap.add_argument("--main", default="/work/main", type=Path)
    ap.add_argument("--main-python", default=None, help="default: MAIN/.venv/bin/python")
    ap.add_argument("--limit", default=120.0, type=float)
    ap.add_argument("--rows", default=None, help="substrings selecting rows, separated by |")
    args = ap.parse_args()
    rows = [r for r in ROWS if args.rows is None or any(k in r for k in args.rows.split("|"))]
    print(f"{__doc__.splitlines()[0]}\nCPU seconds (medians of {args.repeats}, fresh interpreter each), peak RSS; "
          f"main = {args.main} (once, limit {args.limit:.0f} s, 4 GB); load {os.getloadavg()[0]:.1f}")
    print(f"  {'row':52s} {'this CPU-s':>10s} {'RSS MB':>7s} {'main CPU-s':>11s} {'main MB':>8s} "
          f"{'ratio':>8s}  target")
    common = {}
    for row in rows:
        what, d, target = ROWS[row]
        runs = [_run(ROOT, row, 600) for _ in range(args.repeats)]
        if any(r["cpu"] is None or r["error"] for r in runs):
            bad = next(r for r in runs if r["cpu"] is None or r["error"])
            refused = (bad.get("error") or "").startswith("BudgetError") and all(r["cpu"] is not None for r in runs)
            spent = statistics.median(r["cpu"] for r in runs) if refused else None
            when = f"refused in {spent:.2f} CPU-s: " if refused else ""
            goal = f"  (a refusal <= 5 CPU-s: {'met' if spent <= 5 else 'NOT met'})" if refused and target else ""
            print(f"  {row:52s} {when}{(bad.get('error') or bad.get('why'))[:150]}{goal}")
            continue
        new = statistics.median(r["cpu"] for r in runs)
        rss = max(r["rss_mb"] for r in runs)
        base = _run(args.main, row, args.limit, args.main_python or str(args.main / ".venv" / "bin" / "python"),
                    raised=what.startswith("many"))
        if base["cpu"] is None or base.get("error"):
            refused = (base.get("error") or "").startswith("BudgetError")
            old, old_rss = "refused" if refused else base.get("why") or base["error"][:30], ""
            ratio = "(cap)" if refused else f"> {args.limit / new:.1f}x"
        else:
            same = base["digest"] == runs[0]["digest"]
            old, old_rss = f"{base['cpu']:.2f}", f"{base['rss_mb']:.0f}"
            ratio = f"{base['cpu'] / new:.1f}x" + ("" if same else " (RESULT DIFFERS)")
        if what == "common":
            common[d] = new
        if target == "2x common" and d in common:
            goal = f"<= 2x common ({new / common[d]:.2f}x): {'met' if new <= 2 * common[d] else 'NOT met'}"
        elif target is not None:
            goal = f"<= {target}: {'met' if new <= target else 'NOT met'}"
        else:
            goal = "(reference)"
        memory = "" if rss <= 500 else "  RSS above 500 MB"
        if what.startswith("many"):   # the work priced against max_work, beside what it cost
            goal += f"  (priced {statistics.median(r['estimate'] for r in runs):.1f} CPU-s)"
        print(f"  {row:52s} {new:10.2f} {rss:7.0f} {old:>11s} {old_rss:>8s} {ratio:>8s}  {goal}{memory}")


if __name__ == "__main__":
    if sys.argv[1:2] in (["--child"], ["--child-raised"]):
        _child(sys.argv[2], sys.argv[1] == "--child-raised")
    else:
        main()
