"""Speed of exact number fields: critical_loss_rate of (3/2) R(pi p/q) with C = [1, 0].

The engine builds Q(cos, sin) of the angle for the eigen-blocks and Q(cos, sin, exp(i pi p/q))
for the modal form (degree up to 20 for q = 11).  Each run starts from cold caches (symkf's
field, minimal-polynomial and adjunction caches cleared, a new System).  Prints the median
over repeats (target <= 1 s) and its ratio to the reference seconds in ``CASES``: the same call
through sympy's ``QQ.algebraic_field`` and ``from_sympy``, timed on the shared 2-core machine;
``--sympy`` also times sympy's construction and conversion of the modal field in this process.
"""

import statistics
import sys
import time

import sympy as sp

import symkf as sk
from symkf.exact import spectral
from symkf.exact import algebraic, embedding, field
from symkf.engine.stability import critical_loss_rate

CASES = [(2, 7, 4.4), (1, 9, None), (3, 11, 59.0), (1, 12, 2.7)]  # (p, q, reference seconds of the sympy fields' route)
R = sp.Rational(3, 2)


def rotation(p: int, q: int) -> sk.System:
    t = sp.pi * sp.Rational(p, q)
    return sk.System(A=[[R * sp.cos(t), -R * sp.sin(t)], [R * sp.sin(t), R * sp.cos(t)]],
                     sensors=[sk.Sensor(C=[[1, 0]])])


def clear_caches() -> None:
    for fn in (algebraic.root_of, field._integral, field._presentation, embedding.adjoin, embedding._roots,
               spectral._ratio_poly, spectral._abs_poly):
        fn.cache_clear()


def run(p: int, q: int) -> float:
    clear_caches()
    S = rotation(p, q)
    t = time.perf_counter()
    value = critical_loss_rate(S)
    elapsed = time.perf_counter() - t
    assert value == R ** sp.Rational(-2 * q, q - 1)  # hand-derived: alpha^(-2g/(g-1)), g = q
    return elapsed


def sympy_modal_field(p: int, q: int) -> float:
    t = sp.pi * sp.Rational(p, q)
    gens = [R * sp.cos(t), -R * sp.sin(t), R * sp.sin(t), R * sp.exp(sp.I * t), R * sp.exp(-sp.I * t)]
    start = time.perf_counter()
    K = sp.QQ.algebraic_field(*gens)
    for g in gens:
        K.from_sympy(g)
    return time.perf_counter() - start


def main(repeats: int = 5) -> None:
    with_sympy = "--sympy" in sys.argv
    for p, q, before in CASES:
        med = statistics.median(run(p, q) for _ in range(repeats))
        line = f"q = {q:2d} (angle {p}pi/{q}): median {med:.3f} s over {repeats} (target <= 1 s)"
        if before:
            line += f"; before {before:.1f} s, ratio {before / med:.0f}x"
        if with_sympy:
            base = sympy_modal_field(p, q)
            line += f"; sympy modal field alone in this process {base:.1f} s, ratio {base / med:.0f}x"
        print(line, flush=True)


if __name__ == "__main__":
    main()
