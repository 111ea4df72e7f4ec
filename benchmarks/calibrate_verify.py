"""Calibration of ``verify``: theory against simulation at known distances from the threshold.

Systems come from :mod:`symkf.model.strategies` (rotations, complex diagonal, diagonalizable with
two sensors), drawn deterministically (hypothesis, ``derandomize=True``).  Each system gets
three loss families with one scalar parameter ``t``:

* i.i.d.: common loss ``t``; threshold ``critical_loss_rate`` (exact);
* Gilbert-Elliott: fail 1/4, common recovery ``t``; threshold ``critical_recovery_rate`` (exact);
* joint Markov (``MarkovLoss``, the joint-chain code path): from the all-lost vector the
  chain stays all-lost with probability ``t``, from any other vector it goes there with
  ``t / 4``, the rest spread evenly; threshold ``t_c`` by bisection on the exact margin.

Points: ``t = t_c (1 +- delta)`` for ``delta`` in 2 %, 5 %, 20 % (rounded to 6 digits; the
exact verdict and rate are recomputed at the rounded point).  Each point runs
:func:`symkf.numeric.verify.verify` with a fixed budget (``--paths`` per run at the horizons ``h, 2h,
3h`` of ``--horizon``: 15 000 x (40 + 80 + 120) path-steps) and a seed fixed by its index.
Printed: per distance and side the fraction decided (consistent), per loss kind, and the contradictions; the coverage of the
exact margin by the margin intervals at verify's confidence, 99.9 % (with the allowance, and Fieller's alone) where
they are resolved; CPU seconds.

    nice -n 10 python benchmarks/calibrate_verify.py [--paths 15000] [--horizon 120] [--out results.json]
"""

from __future__ import annotations

import argparse
import inspect
import json
import time
from fractions import Fraction

import sympy as sp
from hypothesis import given, settings, HealthCheck

from symkf.model import strategies as sks
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.model.markov import MarkovLoss
from symkf.engine.stability import critical_loss_rate, stability
from symkf.engine.recovery import critical_recovery_rate
from symkf.numeric.verify import verify

DISTANCES = (Fraction(2, 100), Fraction(5, 100), Fraction(20, 100))
KINDS = ("iid", "gilbert-elliott", "markov")
FAIL = sp.Rational(1, 4)
#: verify's default confidence, the level of the intervals whose coverage is measured
CONFIDENCE = inspect.signature(verify).parameters["confidence"].default


def draw(strategy, count: int) -> list:
    """``count`` deterministic examples of a hypothesis strategy."""
    out: list = []

    @settings(derandomize=True, max_examples=count * 3, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(strategy)
    def collect(x):
        if len(out) < count and all(str(x) != str(y) for y in out):
            out.append(x)
    collect()
    return out


def systems(per_family: int) -> list:
    rot = [r.system for r in draw(sks.rotation_systems(scale="3/2", max_denominator=6), per_family)]
    rot += [r.system for r in draw(sks.rotation_systems(scale="2", max_denominator=6), per_family)]
    cplx = draw(sks.complex_diagonal_systems(n=2, moduli=("3/2", "5/4"), max_denominator=6), per_family)
    diag = draw(sks.diagonalizable_systems(blocks=[("3/2", 2)], sensors=2), per_family)
    return rot + cplx + diag


def markov(d: int, t) -> MarkovLoss:
    vecs = [tuple(1 - ((c >> j) & 1) for j in range(d)) for c in range(2 ** d)]   # vecs[-1] all lost
    lost = vecs[-1]
    table = {}
    for v in vecs:
        stay = t if v == lost else t / 4
        table[v] = {w: (stay if w == lost else (1 - stay) / (len(vecs) - 1)) for w in vecs}
    return MarkovLoss(table)


def margin(system, loss) -> float:
    return float(max(stability(system, loss).margins))


def markov_threshold(system) -> Fraction | None:
    """``t_c`` with margin 1, by bisection on the exact margin (float comparisons of exact values)."""
    lo, hi = Fraction(1, 1000), Fraction(999, 1000)
    if margin(system, markov(system.d, sp.Rational(hi.numerator, hi.denominator))) < 1:
        return None
    if margin(system, markov(system.d, sp.Rational(lo.numerator, lo.denominator))) > 1:
        return None
    for _ in range(24):
        mid = (lo + hi) / 2
        if margin(system, markov(system.d, sp.Rational(mid.numerator, mid.denominator))) < 1:
            lo = mid
        else:
            hi = mid
    return (lo + hi) / 2


def points(system) -> list[tuple[str, Fraction, object]]:
    """(kind, relative offset, loss) for the three loss families at the six distances."""
    out = []
    eps_c = critical_loss_rate(system)
    q_c = critical_recovery_rate(system, [FAIL] * system.d)
    t_c = markov_threshold(system)
    centres = {"iid": Fraction(str(eps_c.evalf(20))), "gilbert-elliott": Fraction(str(q_c.evalf(20))),
               "markov": t_c}
    make = {"iid": lambda t: IID([t] * system.d),
            "gilbert-elliott": lambda t: GilbertElliott([FAIL] * system.d, [t] * system.d),
            "markov": lambda t: markov(system.d, t)}
    for kind, c in centres.items():
        if c is None or not 0 < c < 1:
            continue
        ts = [(s * dist, (c * (1 + s * dist)).limit_denominator(10 ** 6)) for dist in DISTANCES for s in (-1, 1)]
        if all(0 < t < 1 for _, t in ts):
            out += [(kind, off, make[kind](sp.Rational(t.numerator, t.denominator))) for off, t in ts]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--paths", type=int, default=15_000)
    ap.add_argument("--horizon", type=int, default=120)
    ap.add_argument("--per-family", type=int, default=4, help="systems drawn per strategy")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    t0 = time.process_time()
    cases = [(s, *p) for s in systems(args.per_family) for p in points(s)]
    setup = time.process_time() - t0
    rows = []
    for i, (system, kind, off, loss) in enumerate(cases):
        t = time.process_time()
        rep = verify(system, loss, seed=1000 + 3 * i, paths=args.paths, horizon=args.horizon).to_dict()
        sim = rep["simulation"]
        m = float(max(float(x["decimal"]) for x in rep["theory"]["margins"]))
        interval = sim["rate_interval"]
        rows.append({"index": i, "system": str(system.A.tolist()), "sensors": system.d, "kind": kind,
                     "offset": str(off), "loss": repr(loss), "stable": rep["theory"]["stable"], "margin": m,
                     "rate": sim["rate"], "interval": interval, "growth": sim["growth_interval"],
                     "horizons": sim["horizons"], "outcome": rep["outcome"],
                     "covered": None if interval is None else interval[0] <= m <= interval[1],
                     "fieller": sim["fieller_interval"], "allowance": sim["allowance"],
                     "covered_fieller": None if interval is None else
                     sim["fieller_interval"][0] <= m <= sim["fieller_interval"][1],
                     "cpu": time.process_time() - t})
        shown = "not resolved" if interval is None else f"{sim['rate']:.5f} [{interval[0]:.5f}, {interval[1]:.5f}]"
        print(f"{i:4d} {kind:16s} {str(off):>6s} A = {system.A.tolist()} margin {m:.5f} estimate {shown} "
              f"horizons {sim['horizons']} {rep['outcome']}", flush=True)
    total = time.process_time() - t0
    print(f"\n{len(rows)} points, budget {args.paths} paths x horizon {args.horizon} (capped by float_horizon where "
          f"needed); set-up {setup:.0f} CPU-s, total {total:.0f} CPU-s")
    for dist in DISTANCES:
        for side in ("stable", "unstable"):
            sel = [r for r in rows if abs(Fraction(r["offset"])) == dist and r["stable"] == (side == "stable")]
            if not sel:
                continue
            dec = {k: sum(r["outcome"] == "consistent" for r in sel if r["kind"] == k) for k in KINDS}
            tot = {k: sum(r["kind"] == k for r in sel) for k in KINDS}
            con = sum(r["outcome"] == "contradiction" for r in sel)
            res = [r for r in sel if r["covered"] is not None]
            print(f"distance {float(dist):4.0%} theory {side:8s}: {len(sel):3d} points, decided "
                  f"{sum(dec.values())}/{len(sel)} = {sum(dec.values()) / len(sel):6.1%} ("
                  + ", ".join(f"{k} {dec[k]}/{tot[k]}" for k in KINDS) + f"), contradictions {con}; margin "
                  f"interval resolved at {len(res)}, covers the exact margin at {sum(r['covered'] for r in res)}")
    res = [r for r in rows if r["covered"] is not None]
    for side in ("stable", "unstable"):
        sel = [r for r in res if r["stable"] == (side == "stable")]
        if sel:
            print(f"coverage of the exact margin by the {len(sel)} resolved {100 * CONFIDENCE:g}% intervals, theory {side}: "
                  f"{sum(r['covered'] for r in sel) / len(sel):.1%} (Fieller interval alone "
                  f"{sum(r['covered_fieller'] for r in sel) / len(sel):.1%})")
            for dist in DISTANCES:
                sub = [r for r in sel if abs(Fraction(r["offset"])) == dist]
                print(f"  distance {float(dist):4.0%}: {sum(r['covered'] for r in sub)}/{len(sub)} "
                      f"(Fieller alone {sum(r['covered_fieller'] for r in sub)}/{len(sub)})")
    print(f"contradictions: {sum(r['outcome'] == 'contradiction' for r in rows)} of {len(rows)}")
    if args.out:
        with open(args.out, "w", encoding="utf-8") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
