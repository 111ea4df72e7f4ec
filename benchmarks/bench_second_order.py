"""Closed form (symkf.second_order.critical_loss_rate) against the engine (symkf.critical_loss_rate).

Second-order systems with 2 sensors: ``2 R(2 pi/m)`` for m = 4, 6, 7, 9 and the
complex-diagonal ``2 diag(e^(2 pi i/12), e^(2 pi i 7/12))``.  Each timed call
gets a freshly built System (both methods cache per System), so every run
includes eigen-blocks and number-field set-up.  Baseline: the engine, run in
this process on the same systems.  Prints per-system medians and the ratio
closed form / engine.
"""

import statistics
import time

import sympy as sp

import symkf as sk
from symkf import second_order as so


def rotation(m):
    th = 2 * sp.pi / m
    return sp.Matrix([[2 * sp.cos(th), -2 * sp.sin(th)], [2 * sp.sin(th), 2 * sp.cos(th)]])


CASES = [(f"2R(2pi/{m})", rotation(m)) for m in (4, 6, 7, 9)]
CASES.append(("2diag(e^(i pi/6), e^(7 i pi/6))", sp.diag(2 * sp.exp(sp.I * sp.pi / 6), 2 * sp.exp(7 * sp.I * sp.pi / 6))))
ROWS = ([[1, 2]], [[3, -1]])


def median_time(fn, A, repeats=3):
    times = []
    for _ in range(repeats):
        S = sk.System(A=A, sensors=[sk.Sensor(C=c) for c in ROWS])
        t = time.perf_counter()
        fn(S)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    print(f"{'system':34s} {'closed form':>12s} {'engine':>10s} {'ratio':>7s}")
    for label, A in CASES:
        a = median_time(so.critical_loss_rate, A)
        b = median_time(sk.critical_loss_rate, A)
        print(f"{label:34s} {a:11.3f}s {b:9.3f}s {a / b:7.2f}")


if __name__ == "__main__":
    main()
