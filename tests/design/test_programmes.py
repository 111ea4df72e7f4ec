"""The covering and linear programmes (symkf.design.programmes): HiGHS, the pure-Python branch
and bound and SymPy's exact simplex against enumeration and against each other."""

import itertools
import random
from fractions import Fraction

import pytest
from hypothesis import given, settings, strategies as st

from symkf.design.programmes import cheapest_cover, cheapest_point


def enumerated(costs, rows, needs):
    best = None
    for r in range(len(costs) + 1):
        for T in itertools.combinations(range(len(costs)), r):
            if all(sum(w[j] for j in T) >= n for w, n in zip(rows, needs)):
                c = sum(costs[j] for j in T)
                best = c if best is None or c < best else best
    return best


@settings(max_examples=40)
@given(st.integers(0, 10 ** 6))
def test_both_covering_solvers_find_the_enumerated_optimum(seed):
    rng = random.Random(seed)
    d, m = rng.randint(1, 8), rng.randint(0, 5)
    costs = [rng.randint(0, 6) for _ in range(d)]
    rows = [[rng.choice([0, 0, 1, 2, 3.5, float("inf")]) for _ in range(d)] for _ in range(m)]
    needs = [rng.choice([1, 2, 4, 7]) for _ in range(m)]
    best = enumerated(costs, [[min(x, n + 1) for x in w] for w, n in zip(rows, needs)], needs)
    for solver in ("highs", "python"):
        T = cheapest_cover(costs, rows, needs, 1e-9, solver)
        assert (None if T is None else sum(costs[j] for j in T)) == best, solver


def test_linear_programme_solvers_agree_and_the_bound_holds():
    costs = [Fraction(1), Fraction(3), Fraction(2)]
    rows = [[1, 2, 0], [2, 1, 1], [0, 1, 3]]
    needs = [Fraction(4), Fraction(5), Fraction(3)]
    x_h, bound_h = cheapest_point(costs, rows, needs, "highs")
    x_p, exact = cheapest_point(costs, rows, needs, "python")
    value = sum(float(c) * v for c, v in zip(costs, x_h))
    assert float(exact) == pytest.approx(value, rel=1e-9) and bound_h <= exact
    assert float(bound_h) == pytest.approx(float(exact), rel=1e-9)
    assert all(sum(k * v for k, v in zip(r, x_p)) >= float(n) - 1e-12 for r, n in zip(rows, needs))
