"""The closed LQG loop over lossy networks (Schenato et al. 2007, Sections III-V): the control MARE,
the TCP-like and UDP-like loops, and the divergence verdict of E[x'Wx]."""

import itertools
import math
import os

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are

from symkf.errors import InputError, NumericalBreakdownError
from symkf.model.iid import IID
from symkf.model.system import Actuator, Sensor, System
from symkf.numeric.closed_loop import (LoopDivergence, LoopSimulation, control_riccati, loop_divergence, loop_plant,
                                       plant_of, simulate_loop)

#: the simulation seed; checked with SYMKF_TEST_SEED = 0..19 before landing
SEED = int(os.environ.get("SYMKF_TEST_SEED", "0"))

#: the scalar plant a = 2, b = c = 1, W = U = Q = R = P0 = 1
SCALAR = loop_plant([[2]], [[1]], [[1]])


def scalar_fixed_point(nu):
    """The positive root of the scalar control MARE ``S = a^2 S + W - nu a^2 b^2 S^2 / (b^2 S + U)``
    with a = 2, b = W = U = 1: multiplied out, ``(1 - a^2 + nu a^2) S^2 + (1 - a^2 - 1) S - 1 = 0``."""
    qa, qb, qc = 1 - 4 + 4 * nu, -4.0, -1.0
    return (-qb + math.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)


def test_control_riccati_is_scipys_dare_when_every_control_arrives():
    A = np.array([[1.1, 0.4], [-0.2, 0.9]])
    B = np.array([[1.0, 0.0], [0.5, 2.0]])
    W, U = np.array([[2.0, 0.3], [0.3, 1.0]]), np.array([[1.0, 0.0], [0.0, 3.0]])
    S, L = control_riccati(A, B, W, U, 1.0)
    X = solve_discrete_are(A, B, W, U)
    assert np.allclose(S, X, rtol=1e-9)
    assert np.allclose(L, np.linalg.solve(B.T @ X @ B + U, B.T @ X @ A), rtol=1e-9)


def test_control_riccati_is_the_root_of_the_scalar_quadratic_at_nu_0_9():
    S, L = control_riccati([[2]], [[1]], [[1]], [[1]], 0.9)
    s = scalar_fixed_point(0.9)                       # (4 + sqrt(18.4)) / 1.2
    assert S[0, 0] == pytest.approx(s, rel=1e-10)
    assert L[0, 0] == pytest.approx(2 * s / (s + 1), rel=1e-10)


def test_control_riccati_diverges_below_the_critical_control_rate():
    # 1 - 1/a^2 = 3/4: at nu = 0.6 the quadratic's leading coefficient 1 - 4 + 2.4 < 0, no fixed point
    with pytest.raises(NumericalBreakdownError, match="explicit gain"):
        control_riccati([[2]], [[1]], [[1]], [[1]], 0.6)


def test_per_actuator_riccati_is_the_expected_cost_to_go_by_enumeration():
    """S = W + E[(A - Gamma B L)' S (A - Gamma B L) + L' Gamma U Gamma L] and the gain is stationary
    in L, over the four reception patterns of two independent actuators (2 and 1 columns)."""
    A = np.array([[1.2, 0.3, 0.0], [0.0, 1.1, 0.2], [0.1, 0.0, 0.9]])
    B = np.array([[1.0, 0.0, 0.2], [0.0, 1.0, 0.0], [0.3, 0.0, 1.0]])
    W, U = np.eye(3), np.diag([1.0, 2.0, 0.5])
    rates, columns = [0.8, 0.6], [2, 1]
    S, L = control_riccati(A, B, W, U, rates, columns)
    expected, gradient = W.copy(), np.zeros_like(L)
    for pattern in itertools.product((0, 1), repeat=2):
        p = math.prod(r if g else 1 - r for g, r in zip(pattern, rates))
        G = np.diag(np.repeat(pattern, columns).astype(float))
        closed = A - B @ G @ L
        expected += p * (closed.T @ S @ closed + L.T @ G @ U @ G @ L)
        gradient += p * (G @ B.T @ S @ closed - G @ U @ G @ L)
    assert np.allclose(S, expected, rtol=1e-9)
    assert np.abs(gradient).max() < 1e-9 * np.abs(S).max()


def test_one_channel_is_one_actuator_with_every_column():
    A, B = np.array([[1.5, 1.0], [0.0, 1.2]]), np.eye(2)
    one = control_riccati(A, B, np.eye(2), np.eye(2), 0.9)
    grouped = control_riccati(A, B, np.eye(2), np.eye(2), [0.9], [2])
    assert all(np.allclose(a, b) for a, b in zip(one, grouped))


@pytest.mark.parametrize("protocol", ["tcp", "udp"])
def test_second_moment_after_one_step_by_hand(protocol):
    """x_1 = 2 x_0 - nu_0 L gamma_0 (x_0 + v_0) / 2 + w_0 (Kalman gain 1/2 from P0 = R = 1), so
    E[x_1^2] = 4 (1 - p) + p (2 - L/2)^2 + p L^2 / 4 + 1 with p = gamma nu = 0.81: 3.38 at L = 2."""
    r = simulate_loop(SCALAR, 0.9, 0.9, protocol=protocol, gain=[[2.0]], horizon=1, paths=200_000, seed=SEED)
    p = 0.81
    exact = 4 * (1 - p) + p * (2 - 1) ** 2 + p * 1 + 1
    assert exact == pytest.approx(3.38)
    assert abs(r.cost[1] - exact) < 5 * r.cost_rel_stderr[1] * r.cost[1]
    assert abs(r.cost[0] - 1) < 5 * r.cost_rel_stderr[0]            # x_0 ~ N(0, 1)


def test_udp_is_tcp_when_every_control_arrives():
    tcp, udp = (simulate_loop(SCALAR, 0.8, 1.0, protocol=p, gain=[[1.7]], horizon=40, paths=300, seed=SEED)
                for p in ("tcp", "udp"))
    assert np.array_equal(tcp.log_cost, udp.log_cost) and np.array_equal(tcp.log_norm, udp.log_norm)


def test_udp_departs_from_tcp_when_controls_are_lost():
    tcp, udp = (simulate_loop(SCALAR, 0.9, 0.9, protocol=p, gain=[[1.7]], horizon=10, paths=300, seed=SEED)
                for p in ("tcp", "udp"))
    assert tcp.log_cost[1] == udp.log_cost[1]          # x_1 does not depend on the estimator's prediction
    assert not np.array_equal(tcp.log_cost, udp.log_cost)


@pytest.mark.parametrize("protocol", ["tcp", "udp"])
def test_estimator_covariance_is_the_mean_square_of_its_error(protocol):
    """E[||x_k - x^_{k|k}||^2] = E[tr P_{k|k}] at every step: the Kalman filter's P (TCP-like) and
    the UDP-like P with its term B (V o u u') B' (without it the UDP error outgrows P, by 4 to 10
    standard errors at most steps from k = 2 on, seed 0)."""
    r = simulate_loop(SCALAR, 0.9, 0.8, protocol=protocol, gain=[[1.7]], horizon=20, paths=20_000, seed=SEED)
    error, trace = np.exp(r.log_error), np.exp(r.log_trace)
    z = (error - trace) / np.hypot(error * r.error_rel_stderr, trace * r.trace_rel_stderr)
    assert np.abs(z).max() < 5, z


def test_tcp_loop_at_nine_tenths_stays_below_the_hand_derived_bound():
    """gamma = nu = 0.9 > 1 - 1/a^2: with the MARE gain L and u = -L x^, x+ = (2 - nu L) x + nu L e + w,
    E[x e] = E[e^2] (x^ orthogonal to e) and E[e^2] = E[P_{k|k}] <= V = S (the estimation MARE is the
    same quadratic here), so E[x+^2] <= m E[x^2] + c V + 1 with m = 0.1 * 4 + 0.9 (2 - L)^2 and
    c = 0.9 (L^2 + 2 (2 - L) L): sup_k E[x_k^2] <= (c V + 1) / (1 - m) = 46.96."""
    S, L = control_riccati([[2]], [[1]], [[1]], [[1]], 0.9)
    s, g = S[0, 0], L[0, 0]
    m, c = 0.4 + 0.9 * (2 - g) ** 2, 0.9 * (g * g + 2 * (2 - g) * g)
    bound = (c * s + 1) / (1 - m)
    assert bound == pytest.approx(46.96, abs=0.01)
    r = simulate_loop(SCALAR, 0.9, 0.9, horizon=200, paths=2000, seed=SEED)
    assert np.allclose(r.gain, L)
    assert r.cost_interval(200)[1] < bound
    d = loop_divergence(SCALAR, 0.9, 0.9, horizon=120, paths=1000, seed=SEED)
    assert d.verdict == "stable"


@pytest.mark.parametrize("gain", [2.0, 1.5, 1.0])
def test_tcp_loop_below_the_control_threshold_diverges_for_any_gain(gain):
    """nu = 0.6 < 3/4: x+ = (2 - nu L) x + nu L e + w with e of bounded second moment (gamma = 0.9),
    so E[x^2] grows by exactly (1 - nu) a^2 + nu (a - L)^2 >= (1 - nu) a^2 = 1.6 per step."""
    d = loop_divergence(SCALAR, 0.9, 0.6, gain=[[gain]], horizon=120, paths=1000, seed=SEED)
    exact = 0.4 * 4 + 0.6 * (2 - gain) ** 2
    low, high = d.rate_interval
    assert d.verdict == "unstable"
    assert low <= exact <= high and high >= 1.6


def test_tcp_loop_below_the_observation_threshold_diverges():
    """gamma = 0.6 < 3/4: the error grows through bursts of lost observations, E[P] by
    (1 - gamma) a^2 = 1.6 per step (Sui-You-Fu's margin alpha^2 rho), and E[x^2] with it."""
    d = loop_divergence(SCALAR, 0.6, 0.95, horizon=120, paths=1000, seed=SEED)
    low, high = d.rate_interval
    assert d.verdict == "unstable" and low <= 1.6 <= high


def test_per_sensor_and_per_actuator_loss_models_drive_their_channels():
    plant = loop_plant([[1.2, 0.3], [0.0, 1.1]], np.eye(2), np.eye(2), sensor_rows=[1, 1], actuator_columns=[1, 1])
    gamma, nu = IID(["1/10", "1/5"]), IID(["1/5", "1/10"])
    r = simulate_loop(plant, gamma, nu, horizon=30, paths=500, seed=SEED)
    L = control_riccati(plant.A, plant.B, plant.W, plant.U, [0.8, 0.9], [1, 1])[1]
    assert np.allclose(r.gain, L)
    assert isinstance(r, LoopSimulation) and r.log_cost.shape == (31,)
    assert loop_divergence(plant, gamma, nu, horizon=60, paths=500, seed=SEED).verdict == "stable"
    # an actuator that never receives its controls leaves the open loop: E[x'Wx] grows
    lost = loop_divergence(plant, gamma, IID(["1", "1"]), gain=L, horizon=60, paths=500, seed=SEED)
    assert lost.verdict == "unstable"


def test_results_are_json_documents_with_short_reprs():
    r = simulate_loop(SCALAR, 0.9, 0.9, horizon=10, paths=100, seed=1)
    d = loop_divergence(SCALAR, 0.9, 0.6, gain=[[2.0]], horizon=24, paths=200, seed=1)
    assert isinstance(d, LoopDivergence)
    for obj in (r, d, SCALAR):
        assert len(repr(obj).splitlines()) <= 10
        assert obj.to_json()
    assert r.to_dict()["horizon"] == 10 and len(r.to_dict()["log_cost"]) == 11
    assert d.to_dict()["horizons"] == [8, 16, 24]
    same = simulate_loop(SCALAR, 0.9, 0.9, horizon=10, paths=100, seed=1)
    assert np.array_equal(r.log_cost, same.log_cost)                     # deterministic for a seed


def test_udp_needs_an_explicit_gain_and_bernoulli_controls():
    with pytest.raises(InputError, match="explicit gain"):
        simulate_loop(SCALAR, 0.9, 0.9, protocol="udp", horizon=5, paths=10)
    with pytest.raises(InputError, match="protocol"):
        simulate_loop(SCALAR, 0.9, 0.9, protocol="ip", horizon=5, paths=10)
    with pytest.raises(InputError, match="nu"):
        simulate_loop(SCALAR, 0.9, 1.5, horizon=5, paths=10)


def test_plant_of_reads_the_systems_actuators_and_cost_weights():
    S = System(A=[[2, 0], [1, 1]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]], R=[[2]])],
               actuators=[Actuator(B=[[1], [0]], U=[[3]]), Actuator(B=[[0], [1]])], W=[[2, 0], [0, 1]])
    p = plant_of(S)
    assert p.sensor_rows == (1, 1) and p.actuator_columns == (1, 1)
    assert np.array_equal(p.B, np.eye(2)) and np.array_equal(p.U, np.diag([3.0, 1.0]))
    assert np.array_equal(p.W, np.diag([2.0, 1.0])) and np.array_equal(p.R, np.diag([1.0, 2.0]))
    r = simulate_loop(S, IID(["1/10", "1/10"]), IID(["1/10", "1/5"]), horizon=5, paths=10, seed=SEED)
    assert np.allclose(r.gain, control_riccati(p.A, p.B, p.W, p.U, [0.9, 0.8], [1, 1])[1])


def test_a_system_without_an_input_matrix_is_refused_by_name():
    S = System(A=[[2]], sensors=[Sensor(C=[[1]])])
    with pytest.raises(InputError, match="system.B"):
        plant_of(S)


@pytest.mark.full
@pytest.mark.parametrize("seed", range(5))
def test_long_runs_find_the_hand_derived_growth_of_the_scalar_loop(seed):
    """Longer horizons and more paths than the fast tier: the interval contains the exact margin
    (1 - nu) a^2 + nu (a - L)^2 of the control side, or (1 - gamma) a^2 of the observation side."""
    for gamma, nu, gain, exact in [(0.9, 0.6, 2.0, 1.6), (0.9, 0.7, 1.0, 0.3 * 4 + 0.7), (0.6, 0.95, None, 1.6)]:
        d = loop_divergence(SCALAR, gamma, nu, gain=None if gain is None else [[gain]], horizon=240,
                            paths=2000, seed=100 * seed)
        low, high = d.rate_interval
        assert d.verdict == "unstable" and low <= exact <= high, (gamma, nu, gain, d)
