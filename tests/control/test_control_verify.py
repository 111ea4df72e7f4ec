"""The closed loop's exact verdicts against simulation, on both sides of every threshold."""

from __future__ import annotations

import pytest
import sympy as sp

import symkf as sk
from symkf.control.verify import verify_loop

R = sp.Rational


def _plant(A, B, C, name):
    return sk.System(A=A, sensors=[sk.Sensor(C=C)], actuators=[sk.Actuator(B=B)], name=name)


#: ten plants of our own: one input, invertible B, two inputs on three modes (certified brackets),
#: rotations, a Jordan block, a partly observed plant
PLANTS = [
    _plant([[2]], [[1]], [[1]], "scalar 2"),
    _plant([[R(6, 5)]], [[1]], [[1]], "scalar 6/5"),
    _plant([[2, 1], [0, 3]], [[0], [1]], [[1, 0]], "two modes, one input, one sensor"),
    _plant([[2, 1], [0, 3]], [[1, 0], [0, 1]], [[1, 0], [0, 1]], "two modes, B invertible"),
    _plant([[0, -2], [2, 0]], [[0], [1]], [[1, 0]], "2R(pi/2), one input"),
    _plant([[R(3, 2), 1], [0, R(3, 2)]], [[0], [1]], [[1, 0]], "Jordan block 3/2"),
    _plant([[2, 0, 0], [0, 3, 0], [0, 0, 5]], [[1, 0], [0, 1], [1, 1]], sp.eye(3), "two inputs, three modes"),
    _plant([[2, 0, 0], [0, R(1, 2), 0], [0, 0, 3]], [[1], [1], [1]], [[1, 1, 1]], "a stable mode beside two"),
    _plant([[1, 1], [-1, 2]], [[1], [0]], [[0, 1]], "complex pair, one input"),
    _plant([[R(5, 4), 1], [0, R(11, 10)]], [[0], [1]], [[1, 0]], "the shipped lqg-two-modes plant"),
]


def _sides(S):
    """(gamma, nu) just below and just above each TCP threshold, the other rate 1."""
    gamma_c = 1 - sk.critical_loss_rate(S).exact
    nu_c = sk.control.critical_arrival_rate(S).lower.exact
    out = []
    for threshold, at in ((gamma_c, lambda x: (x, 1)), (nu_c, lambda x: (1, x))):
        gap = min(R(1, 25), (1 - threshold) / 2)
        low = max(R(1, 100), threshold - gap)
        out += [(at(low), False),
                (at(min(R(1), threshold + gap)), True)]
    return out


def test_scalar_loop_agrees_with_the_simulation_on_both_sides_of_both_thresholds():
    S = PLANTS[0]
    for (g, v), bounded in _sides(S):
        r = verify_loop(S, g, v, paths=8000)
        assert r.theory is bounded and r.outcome == "consistent", r


@pytest.mark.full
@pytest.mark.parametrize("S", PLANTS, ids=[S.name for S in PLANTS])
def test_loop_agrees_with_the_simulation_on_both_sides_of_both_thresholds(S):
    for (g, v), bounded in _sides(S):
        r = verify_loop(S, g, v)
        assert r.theory is bounded and r.outcome == "consistent", r
