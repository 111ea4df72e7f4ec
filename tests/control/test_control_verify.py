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


def test_scalar_loop_agrees_with_the_simulation_on_both_sides_of_both_thresholds():
    S = PLANTS[0]
    for (g, v), bounded in _sides(S):
        r = verify_loop(S, g, v, paths=8000)
        assert r.theory is bounded and r.outcome == "consistent", r


@pytest.mark.full
def test_no_simulation_contradicts_the_loop_theory_on_ten_plants():
    """Both sides of both TCP thresholds of ten plants: never a contradiction; the simulation
    decides (consistent) on most points and says why where it does not (undecided)."""
    outcomes = []
    for S in PLANTS:
        for (g, v), bounded in _sides(S):
            r = verify_loop(S, g, v, paths=8000, horizon=90)
            assert r.theory is bounded and r.outcome != "contradiction", r
            outcomes.append(r.outcome)
    print(f"consistent {outcomes.count('consistent')} of {len(outcomes)}")
    assert len(outcomes) == 40 and outcomes.count("consistent") >= 20, outcomes


@pytest.mark.full
@pytest.mark.xfail(strict=True, reason="known limit of the loop sampler: below nu_c = 65/81 the Jordan block's "
                   "loop with the certificate gain grows by rho = 1.107 per step (exact second moments), and "
                   "the final-burst sampler leaves it undecided")
def test_jordan_block_loop_below_the_control_threshold_is_seen_diverging():
    S = next(S for S in PLANTS if S.name == "Jordan block 3/2")
    r = verify_loop(S, R(389, 500), R(381, 500), paths=8000, horizon=90)
    assert r.theory is False and r.outcome == "consistent", r
