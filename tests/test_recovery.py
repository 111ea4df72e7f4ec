"""The monotone critical recovery rate (symkf.recovery) against the listing of every hyperplane
(``stable_recovery_intervals``): the same exact algebraic number on small systems (periods 2-24,
unequal fail rates, tied sensors), and the hand-checkable two-sensor example."""

import pytest
import sympy as sp

import symkf as sk
from symkf.files import load
from symkf.recovery import monotone_critical_recovery
from symkf.stability import stable_recovery_intervals


def _rotation(angle, scale=2):
    c, s = sp.cos(angle), sp.sin(angle)
    return scale * sp.Matrix([[c, -s], [s, c]])


def _system(A, rows):
    return sk.System(A=A, sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)])


def _listed(S, fail):
    (lo, hi), = stable_recovery_intervals(S, fail)
    assert hi == 1
    return lo


def test_two_sensor_example():
    S, loss = load(sk.examples.system("ge-two-sensors"))
    expected = sp.CRootOf(16 * sp.Symbol("x") ** 4 - 60 * sp.Symbol("x") ** 3 + 88 * sp.Symbol("x") ** 2
                          - 60 * sp.Symbol("x") + 15, 0)
    fast = monotone_critical_recovery(S, loss.fail)
    assert fast is not None and fast == _listed(S, loss.fail)
    assert fast.minpoly.as_expr() == 16 * sp.Symbol("x") ** 4 - 60 * sp.Symbol("x") ** 3 + 88 * sp.Symbol("x") ** 2 \
        - 60 * sp.Symbol("x") + 15
    assert abs(float(fast) - float(expected)) < 1e-14
    assert sk.critical_recovery_rate(S, fail=["1/4", "1/4"]) == fast


CASES = [  # (A, rows, fail): periods 2, 3, 4, 6 and 24, tied and unequal channels
    (_rotation(sp.pi / 2), [[1, 0], [1, 1]], ["1/4", "1/4"]),
    (_rotation(sp.pi / 2), [[1, 0], [1, 0]], ["1/5", "1/5"]),          # parallel rows: ties
    (_rotation(sp.pi / 2), [[1, 0], [0, 1], [1, 1]], ["1/10", "1/5", "1/8"]),
    (_rotation(2 * sp.pi / 3), [[1, 0], [1, 2]], ["1/6", "1/3"]),
    (_rotation(sp.pi / 4), [[1, 0]], ["1/10"]),
    (_rotation(sp.pi / 3), [[1, 0], [2, -1]], ["1/7", "1/10"]),
    (sp.diag(_rotation(sp.pi / 6), _rotation(sp.pi / 4)), [[1, 0, -1, 2]], ["1/10"]),
]


@pytest.mark.parametrize("A, rows, fail", CASES)
def test_equals_listing(A, rows, fail):
    S = _system(A, rows)
    fail = [sp.Rational(f) for f in fail]
    fast = monotone_critical_recovery(S, fail)
    assert fast is not None
    assert fast == _listed(S, fail)
    assert fast.minpoly == _listed(S, fail).minpoly


@pytest.mark.full
def test_equals_listing_benchmark_block():
    import numpy as np
    rng = np.random.default_rng(0)
    rows = []
    while len(rows) < 3:
        r = [int(v) for v in rng.integers(-2, 3, 4)]
        if any(r):
            rows.append(r)
    S = _system(sp.diag(_rotation(sp.pi / 6), _rotation(sp.pi / 4)), rows)
    for d in (1, 2, 3):
        sub = _system(S.A, rows[:d])
        fail = [sp.Rational(1, 10)] * d
        assert monotone_critical_recovery(sub, fail) == _listed(sub, fail)
