"""The closed loop's exact verdicts against simulation, on both sides of every threshold."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.control.threshold import critical_arrival_rate
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
    """Short rationals (gamma, nu) below and above each TCP threshold, the other rate halfway between
    its own threshold and 1: below by ``min(1/25, ...)``, above halfway to 1."""
    thresholds = [1 - sk.critical_loss_rate(S), sk.control.critical_arrival_rate(S).lower]
    ends = [[R(*q.as_integer_ratio()) for q in t.interval] for t in thresholds]
    safe = [R(int((hi + (1 - hi) / 2) * 1000) + 1, 1000) for _, hi in ends]
    out = []
    for k, (lo, hi) in enumerate(ends):
        below = R(int(max(R(1, 100), lo - min(R(1, 25), (1 - hi) / 2)) * 1000), 1000)
        for x, bounded in ((below, False), (safe[k], True)):
            point = (x, safe[1]) if k == 0 else (safe[0], x)
            out.append((point, bounded))
    return out


def _points(S):
    """The distinct points of :func:`_sides` (the bounded point is the same for both thresholds)."""
    return dict(_sides(S))


def test_scalar_loop_agrees_with_the_simulation_on_both_sides_of_both_thresholds():
    S = PLANTS[0]
    for (g, v), bounded in _points(S).items():
        r = verify_loop(S, g, v, paths=1000, horizon=60)
        assert r.theory is bounded and r.outcome == "consistent", r


#: the point the simulation leaves undecided at seed 0 (4000 paths, horizon 90), with the reason:
#: the bounded loop of two modes with one sensor, whose estimate sits on the filter's heavy tail
#: ((1 - gamma) 3^4 = 4.5 > 1: relative standard errors 0.1-0.5)
UNDECIDED = {("two modes, one input, one sensor", R(189, 200), R(987, 1000))}


@pytest.mark.full
@pytest.mark.parametrize("S", PLANTS, ids=[S.name for S in PLANTS])
def test_simulation_decides_the_loop_theory_on_both_sides_of_both_thresholds(S):
    """Both sides of both TCP thresholds: the simulation decides the theory's verdict (consistent)
    at every point but the one of :data:`UNDECIDED`, which it leaves undecided; never a contradiction."""
    for (g, v), bounded in _points(S).items():
        r = verify_loop(S, g, v, paths=4000, horizon=90)
        assert r.theory is bounded, r
        assert r.outcome == ("undecided" if (S.name, g, v) in UNDECIDED else "consistent"), r


@pytest.mark.full
def test_jordan_block_loop_below_the_control_threshold_is_seen_diverging():
    """Below nu_c = 65/81 the Jordan block's loop with the certificate gain L grows, its estimator
    being stable, as the controls' jump linear system: E[x x'] by X -> nu F X F' + (1 - nu) A X A',
    F = A - B L, whose spectral radius (1.107) the margin's interval holds."""
    S = next(S for S in PLANTS if S.name == "Jordan block 3/2")
    nu = R(381, 500)
    r = verify_loop(S, R(389, 500), nu, paths=4000, horizon=90)
    A = np.array(S.A.tolist(), dtype=float)
    F = A - np.array(S.B.tolist(), dtype=float) @ -np.array(critical_arrival_rate(S).gain.tolist(), dtype=float)
    growth = max(abs(np.linalg.eigvals(float(nu) * np.kron(F, F) + (1 - float(nu)) * np.kron(A, A))))
    assert r.theory is False and r.outcome == "consistent", r
    low, high = r.simulation.rate_interval
    assert growth == pytest.approx(1.107, abs=1e-3) and low <= growth <= high and low > 1.05, r
