"""Closed form (symkf.engine.second_order.critical_loss_rate) against the engine (symkf.critical_loss_rate).

Second-order systems with 2 sensors (rows [1, 2], [3, -1]): ``2 R(2 pi/m)`` for
m = 4, 6, 7, 9, 11 and the complex-diagonal ``2 diag(e^(i pi/6), e^(7 i pi/6))``.

* cold: the first call in a fresh interpreter (eigen-blocks, number field and
  all caches built from scratch), median of 3 subprocesses per method;
* warm: a freshly built System in a process that has already analysed the same
  ``A`` (module-level caches warm, per-System caches empty), median of 5.

Baseline: the engine, timed the same way on the same systems.  Prints medians
and the ratio closed form / engine.
"""

import statistics
import subprocess
import sys
import time

import sympy as sp

import symkf as sk
from symkf import second_order as so

CASES = {f"2R(2pi/{m})": f"rotation({m})" for m in (4, 6, 7, 9, 11)}
CASES["2diag(e^(i pi/6), e^(7 i pi/6))"] = "sp.diag(2 * sp.exp(sp.I * sp.pi / 6), 2 * sp.exp(7 * sp.I * sp.pi / 6))"
SETUP = """
import time, sympy as sp, symkf as sk
from symkf import second_order as so
def rotation(m):
    th = 2 * sp.pi / m
    return sp.Matrix([[2 * sp.cos(th), -2 * sp.sin(th)], [2 * sp.sin(th), 2 * sp.cos(th)]])
"""
FUNCS = {"closed form": "so.critical_loss_rate", "engine": "sk.critical_loss_rate"}


def build(expr: str) -> sk.System:
    env: dict = {"sp": sp}
    exec(SETUP, env)
    A = eval(expr, env)
    return sk.System(A=A, sensors=[sk.Sensor(C=[[1, 2]]), sk.Sensor(C=[[3, -1]])])


def cold(func: str, expr: str) -> float:
    code = SETUP + f"""
S = sk.System(A={expr}, sensors=[sk.Sensor(C=[[1, 2]]), sk.Sensor(C=[[3, -1]])])
t = time.perf_counter(); {func}(S); print(time.perf_counter() - t)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.strip())


def warm(func, expr: str) -> float:
    func(build(expr))
    times = []
    for _ in range(5):
        S = build(expr)
        t = time.perf_counter()
        func(S)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    print(f"{'system':34s} {'cold: closed':>13s} {'engine':>8s} {'ratio':>6s}   "
          f"{'warm: closed':>13s} {'engine':>8s} {'ratio':>6s}")
    for label, expr in CASES.items():
        c = {name: statistics.median(cold(f, expr) for _ in range(3)) for name, f in FUNCS.items()}
        w = {"closed form": warm(so.critical_loss_rate, expr), "engine": warm(sk.critical_loss_rate, expr)}
        print(f"{label:34s} {c['closed form']:12.3f}s {c['engine']:7.3f}s {c['closed form'] / c['engine']:6.2f}   "
              f"{w['closed form']:12.4f}s {w['engine']:7.4f}s {w['closed form'] / w['engine']:6.2f}")


if __name__ == "__main__":
    main()
