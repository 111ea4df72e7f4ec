"""Exact enumeration, Monte Carlo and importance sampling of E[tr P_k], and divergence verdicts."""

import math
import os
import time
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf.model import strategies as sks
import symkf as sk
from symkf.errors import BudgetError, InputError
from symkf.numeric import montecarlo
from symkf.numeric.filters import receival_table
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.model.markov import MarkovLoss
from symkf.model.system import Sensor, System
from symkf.numeric.montecarlo import (BurstPlan, burst_pattern, burst_plan, divergence_test, estimate_mean_trace,
                                      exact_mean_covariances, exact_mean_trace, log_mean_trace, loss_factors,
                                      float_horizon, pattern_probabilities, simulate_traces, verdict_plan, _patterns)
from symkf.engine.stability import stability

TRI = System(A=[["5/4", 0], [1, "11/10"]], sensors=[Sensor(C=[[1, 1]])])     # eps_c = 16/25
ROT = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])])               # eps_c = 1/16
#: the property tests' simulation seed; checked with SYMKF_TEST_SEED = 0..19 before landing
SEED = int(os.environ.get("SYMKF_TEST_SEED", "0"))
COMPLEX = System(A=[["2*exp(I*pi/3)", 0], [0, "1/2"]], sensors=[Sensor(C=[[1, 1]])])


@pytest.mark.parametrize("system, loss, horizon", [
    (TRI, IID(["1/2"]), 6),
    (TRI, GilbertElliott(["1/5"], ["1/2"]), 5),
    (COMPLEX, IID(["1/3"]), 4),
    (System(A=[["3/2", 0], [0, "1/2"]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[1, 1]])]),
     MarkovLoss({(1, 1): {(1, 1): "1/2", (0, 1): "1/2"}, (0, 1): {(0, 0): "1/3", (1, 1): "2/3"},
                 (1, 0): {(1, 1): 1}, (0, 0): {(1, 0): "1/4", (0, 1): "3/4"}}), 3),
], ids=["iid", "gilbert-elliott", "complex", "markov"])
def test_enumeration_matches_exact_arithmetic(system, loss, horizon):
    exact = exact_mean_covariances(system, loss, horizon, exact=True)
    approx = exact_mean_covariances(system, loss, horizon)
    for E, F in zip(exact, approx):
        np.testing.assert_allclose(F, np.array(sp.N(E).tolist(), dtype=complex), rtol=1e-12, atol=1e-12)


def test_forward_recursion_matches_sequence_probability():
    loss = GilbertElliott(["1/5", "1/3"], ["1/2", "1/4"])
    codes = _patterns(2, 3)
    table = [(1 & (c >> 0), 1 & (c >> 1)) for c in range(4)]
    p = pattern_probabilities(loss, codes)
    assert p.sum() == pytest.approx(1.0)
    for col in (0, 17, 63):
        seq = [table[c] for c in codes[:, col]]
        assert p[col] == pytest.approx(float(loss.chain.sequence_probability(seq)), rel=1e-12)


def test_single_sensor_closed_form():
    # A = a, C = 1, Q = P0 = R = 1: P_{1|0} = a^2 (1 - gamma/2) + 1 exactly.
    S = System(A=[[3]], sensors=[Sensor(C=[[1]])])
    assert exact_mean_trace(S, IID(["1/4"]), 2)[1] == pytest.approx(9 * (1 - sp.Rational(3, 8)) + 1)


def _coverage(estimates, exact):
    return np.mean([e.low[-1] <= exact <= e.high[-1] for e in estimates])


LOSS = IID(["1/2"])
EXACT9 = exact_mean_trace(TRI, LOSS, 9)


def test_plain_monte_carlo_coverage():
    cov = _coverage([estimate_mean_trace(TRI, LOSS, 9, 1000, seed=s) for s in range(200 * SEED, 200 * SEED + 200)],
                    EXACT9[-1])
    assert 0.88 <= cov <= 0.99


def test_simulate_traces_shape_and_seed():
    a = simulate_traces(TRI, LOSS, 7, 3, seed=5)
    assert a.shape == (3, 7) and np.all(a[:, 0] == 2)
    np.testing.assert_array_equal(a, simulate_traces(TRI, LOSS, 7, 3, seed=5))


def test_simulated_traces_are_a_row_per_step_in_memory_and_chunks_fill_their_own_paths(monkeypatch):
    # simulate_traces returns the transposed view of a (horizon, paths) buffer that the kernel fills
    # step by step; chunks of 64 paths (the last partial) write their own columns: each path's traces
    # are those of log_traces on the same receptions (drawn chunk by chunk from the same generator)
    from symkf.numeric import receptions
    from symkf.numeric.filters import log_traces, real_form
    monkeypatch.setattr(montecarlo, "CHUNK", 64)
    horizon, paths = 9, 150
    a = simulate_traces(TRI, LOSS, horizon, paths, seed=3)
    assert a.shape == (paths, horizon) and a.T.flags.c_contiguous and a.flags.f_contiguous
    rng = np.random.default_rng(3)
    for start in range(0, paths, 64):
        received = receptions.sample(loss_factors(LOSS, 1), horizon, min(64, paths - start), 1, rng)
        np.testing.assert_allclose(a[start:start + 64], np.exp(log_traces(real_form(TRI), received)[:, :horizon]),
                                   rtol=1e-14)


def test_burst_pattern_from_the_engine():
    phases, growth = burst_pattern(TRI, stability(TRI, LOSS))
    assert phases == ((0,),) and growth == sp.Rational(25, 16)
    # governing period 2: losing the sensor at one phase of two already blinds the filter
    phases, growth = burst_pattern(ROT, stability(ROT, IID(["1/20"])))
    assert sorted(phases) == [(), (0,)] and growth == 16


def test_bad_arguments():
    with pytest.raises(InputError, match="horizon"):
        exact_mean_covariances(TRI, LOSS, 40)
    with pytest.raises(InputError, match="sensor"):
        estimate_mean_trace(TRI, IID(["1/2", "1/2"]), 3, 10)
    with pytest.raises(InputError, match="pattern"):
        burst_plan(TRI, [3], 2)
    with pytest.raises(InputError, match="growth"):
        burst_plan(TRI, [0], 0)


# --------------------------------------------------------- theory against simulation

def _verdict(system, eps, seed, **kw):
    return divergence_test(system, IID([eps] * system.d), seed=seed, **kw)


SETTINGS = settings(max_examples=4, deadline=None)


@SETTINGS
@given(case=sks.rotation_systems(scale="3/2", max_denominator=4).flatmap(
    lambda rot: st.tuples(st.just(rot), st.sampled_from(["below", "above"]),
                          sks.loss_rates_near(rot.critical_loss_rate(), "1/4", side="below"),
                          sks.loss_rates_near(rot.critical_loss_rate(), "1/4", side="above"))))
def test_rotations_classified_on_both_sides(case):
    _check_rotation(case, seed=SEED)


def _check_rotation(case, seed):
    rot, side, below, above = case
    q = rot.angle.denominator
    pattern, growth = [[0]] * (q - 1) + [[]], rot.scale ** (2 * q)
    assert _verdict(rot.system, below, seed, pattern=pattern, growth=growth).verdict == "stable"
    assert _verdict(rot.system, above, seed, pattern=pattern, growth=growth).verdict == "unstable"


@SETTINGS
@given(case=st.tuples(st.sampled_from(["3/2", "5/4", "2"]), st.sampled_from(["6/5", "1/2", "-1"]),
                      st.integers(-1, 1)).flatmap(
    lambda t: st.tuples(st.just(t), sks.loss_rates_near(1 / sp.Rational(t[0]) ** 2, "1/4", side="below"),
                        sks.loss_rates_near(1 / sp.Rational(t[0]) ** 2, "1/4", side="above"))))
def test_invertible_sensor_classified_on_both_sides(case):
    seed = SEED
    # one sensor with invertible C: eps_c = 1 / rho(A)^2
    (a, b, c), below, above = case
    S = System(A=[[a, c], [0, b]], sensors=[Sensor(C=[[1, 0], [0, 1]])])
    assert _verdict(S, below, seed).verdict == "stable"
    assert _verdict(S, above, seed).verdict == "unstable"


@pytest.mark.full
@SETTINGS
@given(case=st.tuples(st.sampled_from(["3/2", "5/4"]), st.sampled_from(["6/5", "1/2", "11/10"])).flatmap(
    lambda t: st.tuples(st.just(t), sks.loss_rates_near(1 / sp.Rational(t[0]) ** 2, "1/4", side="below"),
                        sks.loss_rates_near(1 / sp.Rational(t[0]) ** 2, "1/4", side="above"))))
def test_diagonal_one_sensor_per_mode(case):
    seed = SEED
    # common loss eps for both sensors: eps_c = 1 / max a_i^2
    (a, b), below, above = case
    S = System(A=[[a, 0], [0, b]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])])
    assert _verdict(S, below, seed).verdict == "stable"
    assert _verdict(S, above, seed).verdict == "unstable"


def test_quarter_turn_rate_matches_exact():
    for eps, verdict in (("3/64", "stable"), ("5/64", "unstable")):
        r = _verdict(ROT, eps, SEED, pattern=[[0], []], growth=16, exact_rate=4 * sp.sqrt(sp.Rational(eps)))
        # the margin 4 sqrt(eps) (hand-derived: period-2 bursts lose one phase) inside the margin
        # interval: always resolved when unstable, and when resolved below the threshold too
        assert r.verdict == verdict and (r.rate is not None or verdict == "stable")
        if r.rate is not None:
            assert r.rate_low <= r.exact_rate <= r.rate_high


@pytest.mark.full
@pytest.mark.parametrize("seed", range(20))
def test_verdicts_over_seeds(seed):
    _check_rotation((sks.Rotation(ROT, sp.Integer(2), Fraction(1, 2)), "below",
                     sp.Rational(3, 64), sp.Rational(5, 64)), seed)
    for A, sensors in (([["3/2", 1], [0, "1/2"]], [Sensor(C=[[1, 0], [0, 1]])]),
                       ([["5/4", 0], [0, "6/5"]], [Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])])):
        S = System(A=A, sensors=sensors)
        eps_c = 1 / S.A[0, 0] ** 2
        assert _verdict(S, eps_c * sp.Rational(3, 4), seed).verdict == "stable"
        assert _verdict(S, eps_c * sp.Rational(5, 4), seed).verdict == "unstable"


# ------------------------------------------------- final-burst sampling, every loss model


def _example(name):
    from symkf import examples
    from symkf.io import files
    return files.load(examples.directory() / "systems" / name)


@pytest.mark.parametrize("name, horizon", [("design-rotation.toml", 6), ("ge-two-sensors.toml", 5),
                                           ("network/markov-shared-channel.toml", 5),
                                           ("network/quevedo-example3.toml", 3)],
                         ids=["iid", "gilbert-elliott", "joint-markov", "network"])
def test_burst_sampling_is_unbiased_for_every_loss_model(name, horizon):
    # 24 independent runs steered by the exact verdict's decisive pattern, pooled: the mean of
    # E-hat must match exact enumeration (Sui-You-Fu eq. 9 over every receival sequence).
    # 24 runs, not 12: the runs' means are skewed (importance weights), and the 4-sigma check
    # with 12 failed once in 80 (seed 4, network: -4.0 sigma, +-1.1 sigma with 40 runs of 4000)
    system, loss = _example(name)
    plan = verdict_plan(system, stability(system, loss), loss)
    exact = exact_mean_trace(system, loss, horizon + 1)[horizon]
    runs = np.array([np.exp(log_mean_trace(system, loss, horizon, 1000, seed=s, plan=plan).log_mean)
                     for s in range(24 * SEED, 24 * SEED + 24)])
    assert abs(runs.mean() - exact) < 4 * runs.std(ddof=1) / np.sqrt(len(runs))
    # and the spread is small enough for that check to mean something (pooled stderr ~1.5 %)
    assert abs(runs.mean() / exact - 1) < 0.06


def test_loss_factors_reproduce_the_joint_chain():
    # independent Gilbert-Elliott sensors: the product of the per-sensor chains is LossChain.P
    loss = GilbertElliott(["1/4", "1/3"], ["1/2", "1/5"])
    f0, f1 = loss_factors(loss, 2)
    P, init, emit = loss.chain.numeric()
    code = {tuple(v): i for i, v in enumerate(emit.astype(int).tolist())}
    for a, b, c, e in np.ndindex(2, 2, 2, 2):
        src, dst = code[(1 - a, 1 - b)], code[(1 - c, 1 - e)]
        assert P[src, dst] == pytest.approx(f0.P[a, c] * f1.P[b, e])
    assert init[code[(1, 0)]] == pytest.approx(f0.init[0] * f1.init[1])


def test_gilbert_elliott_growth_found_where_plain_monte_carlo_misses_it():
    # ge-two-sensors: exact margin sqrt(6)/2; plain Monte Carlo saw 0.947 (it never samples the
    # bursts of probability ~0.3^k that carry E[tr P_k]); the burst estimate's margin interval
    # (difference ratio at 24, 48, 72: the bounded part of E_k cancels) brackets sqrt(6)/2
    from symkf.numeric.verify import judge, simulated_verdict
    system, loss = _example("ge-two-sensors.toml")
    v = stability(system, loss)
    sim = simulated_verdict(system, loss, v, seed=SEED, horizon=72, paths=4000)
    assert sim["verdict"] == "unstable" and judge(v, sim)["outcome"] == "consistent"
    r = divergence_test(system, loss, seed=SEED, horizon=72, paths=4000)
    assert r.rate_low <= 6 ** 0.5 / 2 <= r.rate_high and abs(r.rate / (6 ** 0.5 / 2) - 1) < 0.02
    plain = divergence_test(system, loss, seed=SEED, horizon=72, paths=4000, confidence=0.99,
                            plan=BurstPlan(np.ones((1, 1, 2), bool), 1.0))
    assert plain.growth_high < 6 ** 0.5 / 2 - 0.1     # nothing to steer: the rare bursts are missed


def test_tie_search_is_capped_by_max_tie_search():
    # ge-two-sensors: the limiting block has 4 hyperplanes; the decisive pattern has 2 shifts and
    # the tie search adds the 2 tied patterns through the other sensor; with fewer hyperplanes
    # allowed than the block has, the plan is the decisive pattern's shifts alone
    from symkf import budget
    system, loss = _example("ge-two-sensors.toml")
    v = stability(system, loss)
    shifts = verdict_plan(system, v).allowed
    assert shifts.shape == (2, 2, 2) and verdict_plan(system, v, loss).allowed.shape == (4, 2, 2)
    with budget.limits(max_tie_search=4):
        assert verdict_plan(system, v, loss).allowed.shape == (4, 2, 2)
    with budget.limits(max_tie_search=3):
        assert np.array_equal(verdict_plan(system, v, loss).allowed, shifts)


def test_plan_of_a_dense_system_takes_the_engines_growth():
    """A dense random integer A (entries -3..3, n = 8): the limiting block's alpha^2 is a root of a
    degree-28 polynomial whose sympy form is above the input cap max_bits; the plan's growth comes
    from the engine, not from a user, and is taken as its float (verify refused it before)."""
    rng = np.random.default_rng(0)
    A = [[int(v) for v in row] for row in rng.integers(-3, 4, (8, 8))]
    system = System(A=A, sensors=[Sensor(C=[[int(v) for v in rng.integers(-2, 3, 8)]]) for _ in range(2)])
    loss = GilbertElliott(["1/10"] * 2, ["1/2"] * 2)
    v = stability(system, loss)
    growth = burst_pattern(system, v)[1]
    plan = verdict_plan(system, v, loss)
    assert plan.growth == pytest.approx(float(growth), rel=1e-12) and plan.growth > 1


def test_long_bursts_are_sampled_to_the_horizon():
    # ge-two-sensors, 2000 paths: log E[tr P_k] must keep growing like k ln(sqrt(6)/2) out to
    # k = 200 (with 5 % of the loss law mixed in at every burst step, almost no path held the
    # pattern for 196 steps and log10 E_200 came out 7.5 instead of ~19)
    system, loss = _example("ge-two-sensors.toml")
    plan = verdict_plan(system, stability(system, loss), loss)
    first, last = (log_mean_trace(system, loss, k, 2000, seed=2 * SEED + j, plan=plan) for j, k in enumerate((100, 200)))
    assert abs((last.log_mean - first.log_mean) / (100 * np.log(np.sqrt(6) / 2)) - 1) < 0.05


def test_float_horizon_caps_bursts_float64_cannot_follow():
    # A = 2 R(2 pi/3) (entries -1, +-sqrt(3)), C = [1 0]: the decisive pattern receives one
    # phase in 3, C A^(3k) = 8^k C exactly but only to 1e-16 in float64, so a burst saturates
    # near log tr P ~ 75 (P grows 4x per step: ~55 steps).  Uncapped, verify at loss 3/20
    # (exact rate 4 (3/20)^(2/3) ~ 1.129) saw ~1.0 and called it a contradiction.
    system = System(A=[[-1, "-sqrt(3)"], ["sqrt(3)", -1]], sensors=[Sensor(C=[[1, 0]])])
    loss = IID(["3/20"])
    plan = verdict_plan(system, stability(system, loss))
    cap = float_horizon(system, plan)
    assert cap is not None and 30 <= cap <= 55
    r = divergence_test(system, loss, seed=SEED, horizon=120, paths=4000)
    assert r.horizons[-1] <= cap and r.verdict == "unstable" and r.rate > 1.1
    assert r.rate_low <= 4 * 0.15 ** (2 / 3) <= r.rate_high
    # integer A = 2 R(pi/2): exact in float64, its pure burst has no cap; the sampled paths do: after
    # L lost steps P spans scales 4^L, and a reception leaves a direction of size 1 carried with an
    # error 2^-53 2^L, so the resolution cap is RESOLUTION_BITS ln 2 / ln alpha = 40 steps (alpha = 2)
    ge_system, ge_loss = _example("ge-two-sensors.toml")
    assert float_horizon(ge_system, verdict_plan(ge_system, stability(ge_system, ge_loss))) == 40


def test_traces_too_large_for_memory_are_refused_before_allocation():
    from symkf.errors import BudgetError
    S = System(A=[[2]], sensors=[Sensor(C=[[1]])])
    with pytest.raises(BudgetError, match=r"paths x horizon: the bytes .* above the cap .*--max-memory"):
        simulate_traces(S, IID(["1/2"]), horizon=10 ** 5, paths=10 ** 6, seed=0)


# ------------------------------------------------- the margin from three horizons

def _estimates(values, rel, horizons):
    from symkf.numeric.montecarlo import LogMeanEstimate
    return [LogMeanEstimate(float(np.log(v)), rel, 1000.0, 1000, k, None, "synthetic")
            for v, k in zip(values, horizons)]


@pytest.mark.parametrize("m, a, b", [(1.02, 60.0, -50.0), (1.05, 1.0, 30.0), (0.97, -40.0, 41.0), (0.9, 5.0, 2.0)])
def test_difference_ratio_removes_the_bounded_part(m, a, b):
    # E_k = a m^k + b exactly (unstable: b < 0 is the geometric tail of shorter bursts; stable:
    # E_k rising to its limit b): the difference ratio gives m to rounding, the finite-horizon
    # rate (E_3h / E_h)^(1/2h) does not
    from symkf.numeric.montecarlo import margin_interval, rate_interval
    ks = (40, 80, 120)
    runs = _estimates([a * m ** k + b for k in ks], 1e-12, ks)
    rate, low, high = margin_interval(runs, 0.99)
    assert rate == pytest.approx(m, rel=1e-9) and low <= m * (1 + 1e-9) and m <= high * (1 + 1e-9)
    assert high - low < 1e-6
    assert abs(rate_interval(runs[0], runs[2], 0.99)[0] - m) > 1e-3


def test_margin_not_resolved_when_noise_hides_the_change():
    from symkf.numeric.montecarlo import margin_interval
    runs = _estimates([10.0, 10.01, 10.02], 0.01, (40, 80, 120))     # D_1 = 0.01 against sd 0.14
    assert margin_interval(runs, 0.99) is None


def test_fieller_interval_covers_at_the_nominal_level():
    # independent normal E_k around a m^k + b with the stated standard deviations: the 99 %
    # interval must cover m in 99 % of 4000 draws (binomial sd 0.16 %: 98.4 % is 4 sd below)
    from symkf.numeric.montecarlo import margin_interval
    rng = np.random.default_rng(12345 + SEED)
    ks, m, rel = (24, 48, 72), 1.01, 0.01
    true = np.array([10 * m ** k - 3 for k in ks])
    hits = resolved = 0
    for _ in range(4000):
        draw = true * (1 + rel * rng.standard_normal(3))
        r = margin_interval(_estimates(draw, rel, ks), 0.99)
        if r is not None:
            resolved += 1
            hits += r[1] <= m <= r[2]
    assert resolved > 3900 and hits / resolved > 0.984


@pytest.mark.parametrize("m", [1.001, 1.02, 1.3, 3.0])
@pytest.mark.parametrize("k, h", [(40, 40), (24, 24), (60, 30)])
@pytest.mark.parametrize("degree", [1, 3])
def test_factors_k_move_the_ratio_by_at_most_the_allowance(m, k, h, degree):
    # E_k = sum_{i <= p} c_i k^i m^k + b with c_i >= 0 (polynomial_allowance's derivation): the
    # ratio's log m lies in [ln m, ln m + allowance]; brute force over weights, the pure k^p m^k
    # term included (it comes closest to the upper end)
    from symkf.numeric.montecarlo import polynomial_allowance
    allowance = polynomial_allowance((k, k + h, k + 2 * h), degree)
    rng = np.random.default_rng(7)
    weights = [np.eye(degree + 1)[i] for i in range(degree + 1)] + list(rng.random((20, degree + 1)))
    for c in weights:
        E = [sum(ci * j ** i for i, ci in enumerate(c)) * m ** j - 7 for j in (k, k + h, k + 2 * h)]
        log_ratio = np.log((E[2] - E[1]) / (E[1] - E[0])) / h
        assert np.log(m) - 1e-12 <= log_ratio <= np.log(m) + allowance + 1e-12


def test_polynomial_degree_from_the_limiting_block():
    from symkf.numeric.montecarlo import polynomial_degree
    # diagonalizable: one factor k; a Jordan chain of length 2 (A = [[6/5, 1], [0, 6/5]]): P grows
    # like k^2 (6/5)^(2k) in a burst, plus that factor: 3
    assert polynomial_degree(ROT, stability(ROT, IID(["1/20"]))) == 1
    jordan = System(A=[["6/5", 1], [0, "6/5"]], sensors=[Sensor(C=[[1, 0]])])
    assert polynomial_degree(jordan, stability(jordan, IID(["19/25"]))) == 3


def _sampled_paths(monkeypatch, system, loss, horizon, paths, seed):
    """``burst_sample``'s paths with the receptions it drew (kept on their way to the kernel)."""
    import symkf.numeric.montecarlo as mc
    seen = []
    kernel = mc.log_traces
    monkeypatch.setattr(mc, "log_traces", lambda model, received: (seen.append(received.copy()),
                                                                   kernel(model, received))[1])
    plan = mc.verdict_plan(system, mc._verdict(system, loss), loss)
    logtr, logw = mc.burst_sample(system, loss, horizon, paths, seed, plan)
    return logtr, logw, seen[0]


@pytest.mark.parametrize("seed", [0, 1])
def test_kernel_is_exact_on_sampled_bursts_within_float_resolution(monkeypatch, seed):
    # ge-recovery.toml's member recover = 1/4 (m = 2.3717), horizon 40 = divergence_test's h: the
    # paths of the final-burst sample against the exact rational Riccati recursion (eq. 9,
    # exact_covariances). Within 40 steps the scales of P stay resolvable and the kernel agrees
    # to 1e-3 in log tr P (measured on 15 000 paths: within 2e-4); from k = 80 on it misses
    # thousands (benchmarks/float_resolution.py), which is what biases the margin down.
    system = System([[0, -2], [2, 0]], [Sensor([[1, 0]]), Sensor([[1, 1]])])
    loss = GilbertElliott(["1/4", "1/4"], ["1/4", "1/4"])
    logtr, logw, received = _sampled_paths(monkeypatch, system, loss, 40, 256, seed)
    from symkf.numeric.filters import exact_covariances
    heaviest = np.argsort(-(logtr + logw))[:16]
    others = np.random.default_rng(seed).choice(np.setdiff1d(np.arange(256), heaviest), 16, replace=False)
    for p in np.concatenate([heaviest, others]):
        trace = sp.Rational(exact_covariances(system, received[:, p].astype(int).tolist())[-1].trace())
        exact = math.log(trace.p) - math.log(trace.q)      # big integers: math.log, not float()
        assert abs(logtr[p] - exact) < 1e-3, (p, logtr[p], exact)


def test_enumeration_is_capped_by_max_patterns():
    """2^(d (horizon - 1)) receival sequences: d = 2, horizon 11 gives 2^20, the default cap;
    one more step is refused naming the cap, and raising it lets a small case through."""
    from symkf import budget
    from symkf.errors import BudgetError
    S = System(A=[[2]], sensors=[Sensor(C=[[1]]), Sensor(C=[[1]])], Q=[[1]])
    with pytest.raises(BudgetError, match=r"2\^\(d \(horizon-1\)\).*is 4194304, above the cap 1048576.*--max-patterns"):
        exact_mean_trace(S, IID(["1/10"] * 2), 12)
    with budget.limits(max_patterns=8), pytest.raises(BudgetError, match="is 16, above the cap 8"):
        exact_mean_trace(S, IID(["1/10"] * 2), 3)
    with budget.limits(max_patterns=16):
        assert len(exact_mean_trace(S, IID(["1/10"] * 2), 3)) == 3


@pytest.mark.parametrize("horizon", [10 ** 9, 10 ** 10, 10 ** 30])
def test_the_exact_mean_is_refused_from_the_exponent_not_the_count(horizon):
    # 2^(d (h - 1)) compared in logarithms: building it took 18 s and 0.9 GB at 10^9, hung at 10^30
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    start = time.process_time()
    with pytest.raises(BudgetError, match=r"is 2\^\d+, above the cap"):
        montecarlo.exact_mean_trace(S, sk.IID(["1/10"]), horizon)
    with pytest.raises(BudgetError, match=r"is 2\^\d+, above the cap"):
        receival_table(10 ** 6)
    assert time.process_time() - start < 0.5
