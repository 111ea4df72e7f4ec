"""The engine against the oracle (symkf.engine.oracle), which ranks the raw regression matrix O_N
built from A and C without any of the engine's code.

Systems outside the papers' class: detectable, singular, defective and marginal A, aperiodic
blocks under Markov losses, delayed and multi-rate sensors, drawn Jordan chains.  Every case has
its exact probability of rank deficiency and critical value derived by hand in the test, and the
slope of the oracle's least lost weight equals the engine's exponent."""

from fractions import Fraction
from math import lcm

import pytest
import sympy as sp
from hypothesis import given, settings

import symkf as sk
from symkf import examples
from symkf.engine.blocks import block_rows
from symkf.engine.oracle import RawRegression, decay_slope, iid_probability
from symkf.engine.search import outside_counts
from symkf.engine.recovery import critical_recovery_rate
from symkf.engine.stability import critical_loss_rate, stability
from symkf.io.files import load
from symkf.model import strategies as sks

from conftest import limited, refused_at_once

R = sp.Rational
EXAMPLES = examples.directory() / "systems"


def system(A, *Cs):
    return sk.System(A=A, sensors=[sk.Sensor(C=C) for C in Cs])


def engine_exponent(S, weights):
    """Per-step exponent e of the slowest unstable block, rho = x^e for losses eps_j = x^(w_j):
    min over blocks with alpha >= 1 and hyperplanes H of sum_j w_j k_j(H) / g."""
    return min(Fraction(sum(w * k for w, k in zip(weights, ks)), br.class_period)
               for br in block_rows(S) if not br.block.is_stable for ks in outside_counts(br))


def assert_oracle_agrees(S, subspace=None, weights=(1,), N=None):
    """The oracle's slope of the least lost weight L(N) equals the engine's exponent."""
    G = lcm(*(br.class_period for br in block_rows(S) if not br.block.is_stable))
    N = N or 2 * S.n + 1
    e = engine_exponent(S, weights)
    Cs = [s.C for s in S.sensors]
    assert decay_slope(S.A, Cs, weights, N, G, subspace) == (G * e, G * e)


eps = sp.Symbol("eps", positive=True)


def at_most_one_reception(N):
    # P(fewer than 2 of N packets arrive) = eps^N + N (1 - eps) eps^(N - 1): rate eps, factor N
    return sp.expand(eps ** N + N * (1 - eps) * eps ** (N - 1))


def test_quarter_turn_rotation_against_oracle():
    # A = 2 R(pi/2), C = [1 0]: rows C A^k are multiples of [1, 0] at even k and of
    # [0, 1] at odd k, so O_6 is deficient iff every reception has one parity:
    # P(R_6) = 2 eps^3 - eps^6.  Slope of L(N): 1 lost packet per 2 steps, rho = eps^(1/2),
    # margin 4 eps^(1/2) < 1 iff eps < 1/16 (the README's claim points here).
    S = system([[0, -2], [2, 0]], [[1, 0]])
    assert RawRegression(S.A, [S.sensors[0].C], 6).probability(iid_probability([eps])) == 2 * eps ** 3 - eps ** 6
    assert critical_loss_rate(S) == R(1, 16)
    assert_oracle_agrees(S)


def test_constant_velocity_is_stable_for_every_loss():
    # rows C A^k = [1, k]: any two receptions are independent, so R_N = {at most one reception},
    # P(R_N) ~ N eps^N, rho = eps and alpha = 1: margin eps < 1 for every eps < 1.
    S = system([[1, 1], [0, 1]], [[1, 0]])
    assert RawRegression(S.A, [S.sensors[0].C], 7).probability(iid_probability([eps])) == at_most_one_reception(7)
    assert critical_loss_rate(S) == 1
    v = stability(S, sk.IID(["99/100"]))
    assert v.stable and v.margins[0] == R(99, 100) and "Jordan chains" in v.assumptions[0]
    assert_oracle_agrees(S)


def test_unstable_jordan_block_critical_25_36():
    # rows C A^k = (6/5)^k [1, 5k/6]: as for constant velocity R_N = {at most one reception}, so
    # rho = eps (the factor N does not change the rate) and the margin is (36/25) eps:
    # eps_c = 25/36.  At eps = 1/2 the margin is 18/25; at 7/10 it is 126/125 > 1.
    S = system([[R(6, 5), 1], [0, R(6, 5)]], [[1, 0]])
    assert RawRegression(S.A, [S.sensors[0].C], 7).probability(iid_probability([eps])) == at_most_one_reception(7)
    assert critical_loss_rate(S) == R(25, 36)
    assert stability(S, sk.IID(["1/2"])).margins[0] == R(18, 25)
    assert not stability(S, sk.IID(["7/10"])).stable
    # at the boundary the margin is exactly 1: not stable (docs/sui.md, "At the boundary")
    assert stability(S, sk.IID(["25/36"])).margins[0] == 1 and not stability(S, sk.IID(["25/36"])).stable
    assert_oracle_agrees(S)


@pytest.mark.parametrize("A, C, U, aside", [
    # diag(2, 1/2), C = [1 0]: the mode 1/2 is unseen but stable (detectable); rows on the
    # unstable mode e1 are 2^k, deficient only if nothing arrives: rho = eps, eps_c = 1/4
    ([[2, 0], [0, R(1, 2)]], [[1, 0]], [[1], [0]], "1/2"),
    # delayed output [[2, 0], [1, 0]]: unstable eigenvector (2, 1), C A^k (2, 1) = 2^(k+1) != 0
    ([[2, 0], [1, 0]], [[1, 0]], [[2], [1]], "0"),
    # diag(2, 0), C = [1 1] (crashed with max() of an empty sequence): rows on e1 are 2^k
    ([[2, 0], [0, 0]], [[1, 1]], [[1], [0]], "0"),
    # a stable Jordan chain of 1/2 beside the unstable mode 2: rows on e1 are 2^k
    ([[2, 0, 0], [0, R(1, 2), 1], [0, 0, R(1, 2)]], [[1, 1, 0]], [[1], [0], [0]], "1/2"),
])
def test_set_aside_stable_part_critical_1_4(A, C, U, aside):
    # P(R_N) = eps^N (only "nothing received" is deficient), margin 4 eps: eps_c = 1/4
    S = system(A, C)
    assert RawRegression(S.A, [S.sensors[0].C], 6, U).probability(iid_probability([eps])) == eps ** 6
    assert critical_loss_rate(S) == R(1, 4)
    v = stability(S, sk.IID(["1/5"]))
    assert v.stable and v.margins == (R(4, 5),)
    assert [e for e, _ in v.set_aside] == [(aside,)]
    assert_oracle_agrees(S, U)


def test_aperiodic_rotation_under_gilbert_elliott_oracle():
    # A = (3/2) R(theta), cos theta = 3/5: theta/pi irrational, so any two rows C A^k, C A^l
    # (k != l) are independent (sin((l - k) theta) != 0) and R_N = {at most one reception}:
    # exactly what the raw-O_N oracle finds.  Under Gilbert-Elliott the rate is P(stay lost) =
    # 1 - recover: margin (9/4)(1 - q) < 1 iff q > 5/9 (checked in tests/engine/test_stability.py too).
    S = system([["9/10", "-6/5"], ["6/5", "9/10"]], [[1, 0]])
    sets = RawRegression(S.A, [S.sensors[0].C], 7).deficient_sets
    assert sorted(map(len, sets)) == [0] + [1] * 7
    assert critical_recovery_rate(S, ["1/4"]) == R(5, 9)
    assert stability(S, sk.GilbertElliott(["1/4"], ["3/5"])).margins[0] == R(9, 10)


def test_delayed_sensor_against_oracle():
    # unstable part of z = (x_k, x_{k-1}): columns (I, A0^{-1}), A0 = 2 R(pi/2); with losses
    # eps_now = x, eps_late = x^2 each line leaves one element of each sensor: slope (1 + 2) per 2 steps
    S, _ = load(EXAMPLES / "delayed-sensor.toml")
    U = sp.Matrix([[1, 0], [0, 1], [0, R(1, 2)], [R(-1, 2), 0]])
    assert S.A * U == U * sp.Matrix([[0, -2], [2, 0]])
    assert_oracle_agrees(S, U, weights=(1, 2), N=6)


def test_cv_three_sensors_against_oracle():
    S, _ = load(EXAMPLES / "cv-three-sensors.toml")
    assert_oracle_agrees(S, weights=(1, 1, 2), N=3)


CHAINS = [
    ([(2, 2)], 1),                        # unstable Jordan chain
    ([(1, 2)], 2),                        # constant velocity, similar to it, two sensors
    ([(1, 3)], 1),                        # constant acceleration
    ([(-2, 2), (R(1, 2), 1)], 1),         # defective, beside a stable mode
    ([(R(3, 2), 1), (R(1, 2), 2)], 2),    # stable Jordan chain beside an unstable mode
    ([(2, 1), (0, 2)], 1),                # singular: a nilpotent chain
    ([(2, 1), (-2, 1), (0, 1)], 2),       # period-2 block and a zero eigenvalue
    ([(R(3, 2), 2), (1, 1)], 1),          # two unstable blocks, one defective
]


def compare_drawn(chains, sensors, examples):
    """Engine against the raw-O_N oracle on ``examples`` systems drawn by sks.jordan_systems;
    returns how many were compared."""
    seen = []

    @settings(max_examples=examples, deadline=None, database=None)
    @given(sks.jordan_systems(chains, sensors))
    def check(drawn):
        assert_oracle_agrees(drawn.system, drawn.unstable_basis, weights=(1, 2)[:sensors])
        seen.append(drawn)
    check()
    return len(seen)


@pytest.mark.parametrize("chains, sensors", CHAINS)
def test_engine_against_oracle_on_drawn_systems(chains, sensors):
    assert compare_drawn(chains, sensors, 3) >= 1


@pytest.mark.full
@pytest.mark.parametrize("chains, sensors", CHAINS)
def test_engine_against_oracle_on_drawn_systems_full(chains, sensors):
    assert compare_drawn(chains, sensors, 12) >= 1


def test_a_million_losses_are_refused_before_one_is_read():
    # each loss went through the number parser before the pattern law could be refused
    code, err = limited(refused_at_once, lambda: iid_probability(["1/10"] * 10 ** 6), "max_sensors")
    assert code == 0, err
