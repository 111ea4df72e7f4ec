"""Calibration of the closed loop's simulated verdicts against the exact ones: right, undecided, wrong.

:func:`symkf.control.verify.verify_loop` on the points of ``tests/control/test_control_verify.py``
(ten plants, below and above each TCP-like threshold; the bounded point is the same for both
thresholds, so three distinct points per plant) and on UDP-like scalar noiseless points (a = 2,
6/5; gamma = 9/10, 19/20; nu = nu_udp(gamma) +- 1/25), over seeds ``0, 3, 6, ..`` (each
verdict uses three consecutive seeds).  A verdict is right when the outcome is "consistent",
wrong on "contradiction".  Prints one line per point and seed, then the counts per protocol, the
CPU seconds and the peak RSS.

    nice -n 10 python benchmarks/calibrate_loop_verify.py [--seeds 20] [--first 0] [--paths 4000] [--horizon 90]
        [--udp] [--tcp] [--no-filter-points]

Measured on 2026-12-06 (4000 paths, horizon 90, the loop points only: ``--no-filter-points``),
9 complete seeds (0, 3, 6, 21, 24, 27, 42, 45, 48; the run over 20 was stopped at the deadline of
a loaded machine): TCP-like right 170, undecided 10, wrong 0 of 180; UDP-like right 72, undecided
0, wrong 0 of 72; 829 CPU-s (about 3.3 CPU-s a point), peak RSS about 110 MB.  The undecided: two
modes with one sensor, bounded (5 of 9) and below nu_c (2 of 9); a stable mode beside two,
bounded (2 of 9) and below nu_c (1 of 9): plants where (1 - gamma) 3^4 > 1, the filter's heavy tail.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time

import sympy as sp

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests" / "control"), str(pathlib.Path(__file__).resolve().parent)]

import symkf as sk  # noqa: E402
from symkf.control.udp import udp_threshold  # noqa: E402
from symkf.control.verify import verify_loop  # noqa: E402
from test_control_verify import PLANTS, _sides  # noqa: E402
from timing import peak_rss_mb  # noqa: E402


def tcp_points(filter_points: bool):
    for S in PLANTS:
        sides = _sides(S)
        for (g, v), bounded in (sides[:3] if filter_points else sides[1:3]):
            yield S, g, v, "tcp", False


def udp_points():
    R = sp.Rational
    for a in (sp.Integer(2), R(6, 5)):
        S = sk.System(A=[[a]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])], name=f"UDP a = {a}")
        for g in (R(9, 10), R(19, 20)):
            star = udp_threshold(a, g)
            for v in (min(R(1), star + R(1, 25)), star - R(1, 25)):
                yield S, g, R(int(v * 1000), 1000), "udp", True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first", type=int, default=0, help="index of the first seed (seed = 3 * index)")
    ap.add_argument("--paths", type=int, default=4000)
    ap.add_argument("--horizon", type=int, default=90)
    ap.add_argument("--tcp", action="store_true")
    ap.add_argument("--udp", action="store_true")
    ap.add_argument("--no-filter-points", action="store_true",
                    help="leave out the points below the observation threshold (witnessed by symkf.verify)")
    args = ap.parse_args()
    both = not (args.tcp or args.udp)
    points = ([*tcp_points(not args.no_filter_points)] if args.tcp or both else []) + ([*udp_points()] if args.udp or both else [])
    counts = {"tcp": [0, 0, 0], "udp": [0, 0, 0]}
    start = time.process_time()
    for i in range(args.first, args.first + args.seeds):
        for S, g, v, protocol, noiseless in points:
            t = time.process_time()
            r = verify_loop(S, g, v, protocol=protocol, noiseless=noiseless, seed=3 * i, paths=args.paths,
                            horizon=args.horizon)
            counts[protocol][OUTCOMES.index(r.outcome)] += 1
            print(f"seed {3 * i:3d} {protocol} {S.name[:30]:30s} {str(g):9s} {str(v):9s} "
                  f"{'bounded' if r.theory else 'unbounded':9s} {r.outcome:13s} {r.simulated_verdict or '-':9s} "
                  f"{time.process_time() - t:5.1f} CPU-s", flush=True)
    for protocol, (right, wrong, undecided) in counts.items():
        if right + wrong + undecided:
            print(f"{protocol.upper()}-like: right {right}, undecided {undecided}, wrong {wrong} "
                  f"of {right + wrong + undecided}")
    print(f"CPU {time.process_time() - start:.1f} s, peak RSS {peak_rss_mb():.0f} MB")


OUTCOMES = ("consistent", "contradiction", "undecided")

if __name__ == "__main__":
    main()
