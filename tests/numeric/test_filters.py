"""The batched float filter (symkf.numeric.filters; Sui-You-Fu Theorem 1, eqs. 8-9) against the exact
covariances of eq. (9) and against its own simulation; the square-root, log-scale traces
(log_traces) against the exact oracle, mpmath and the float64 covariance form, through thousands of
unstable steps and past float64's range."""


import numpy as np
import pytest
import sympy as sp

from symkf import budget
from symkf.errors import InputError, ShapeError
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.model.system import Sensor, System
from symkf.numeric.filters import (
    FloatSystem,
    exact_covariances,
    log_traces,
    predicted_covariances,
    real_form,
    sample_receptions,
    simulate_trajectories,
    traces_into,
)

TRI = System(A=[["5/4", 0], [1, "11/10"]], sensors=[Sensor(C=[[1, 1]], R=[[2]]),
                                                    Sensor(C=[[1, 0], [0, 1]], R=[[2, 1], [1, 3]])])
CUBIC = System(A=[["5/4", 0, 0], [1, "11/10", 0], [0, 1, "-1/2"]],
               sensors=[Sensor(C=[[1, 1, 0]], R=[[2]]), Sensor(C=[[1, 0, 0], [0, 0, 1]])])
COMPLEX = System(A=[["2*exp(I*pi/3)", 0], [0, "3/2"]], sensors=[Sensor(C=[[1, "I"]]), Sensor(C=[[0, 1]])])


@pytest.mark.parametrize("system", [TRI, CUBIC, COMPLEX], ids=["n2", "n3", "complex"])
def test_float_filter_matches_exact_oracle(system):
    rng = np.random.default_rng(7)
    seqs = rng.integers(0, 2, (4, 6, system.d))
    float_P = predicted_covariances(system, np.concatenate([seqs, seqs[:, :1]], axis=1), keep="all")
    for seq, Pf in zip(seqs, float_P):
        exact = exact_covariances(system, [tuple(int(g) for g in v) for v in seq])
        for k, Pk in enumerate(exact):
            target = np.array(sp.N(Pk).tolist(), dtype=complex)
            if system is COMPLEX:   # the float filter runs the real form: tr is preserved
                assert Pf[k].trace() == pytest.approx(target.trace().real, rel=1e-12)
            else:
                np.testing.assert_allclose(Pf[k], target.real, rtol=1e-12, atol=1e-12)


def test_trace_keep_modes_agree():
    g = sample_receptions(IID(["1/3", "1/2"]), 20, 5, np.random.default_rng(1))
    allP = predicted_covariances(TRI, g, keep="all")
    np.testing.assert_allclose(predicted_covariances(TRI, g), np.trace(allP, axis1=2, axis2=3))
    np.testing.assert_allclose(predicted_covariances(TRI, g[:, :-1], keep="last"),
                               allP[:, -1], rtol=1e-12)


def test_estimation_error_covariance_matches_filter():
    # MMSE: E[e e^T | receivals] = P_{k|k-1}; so E|e_k|^2 = E[tr P_{k|k-1}] over paths.
    run = simulate_trajectories(TRI, GilbertElliott(["1/5", "1/3"], ["1/2", "2/3"]), 12, 40000, seed=3)
    err = run.x - run.x_pred
    sq = (err ** 2).sum(axis=2)
    tr = np.trace(run.P_pred, axis1=2, axis2=3)
    for k in (0, 5, 11):
        se = sq[:, k].std() / np.sqrt(len(sq))
        assert abs(sq[:, k].mean() - tr[:, k].mean()) < 5 * se
    ferr = ((run.x - run.x_filt) ** 2).sum(axis=2)[:, 11]
    assert abs(ferr.mean() - np.trace(run.P_filt[:, 11], axis1=1, axis2=2).mean()) < 5 * ferr.std() / 200


def test_receival_frequencies():
    g = sample_receptions(IID(["1/10", "1/2"]), 50, 4000, np.random.default_rng(2))
    assert g.shape == (4000, 50, 2)
    np.testing.assert_allclose(1 - g.mean(axis=(0, 1)), [0.1, 0.5], atol=0.01)
    ge = sample_receptions(GilbertElliott(["1/10"], ["1/4"]), 200, 2000, np.random.default_rng(3))[:, :, 0]
    after_loss = ge[:, 1:][~ge[:, :-1]]
    assert after_loss.mean() == pytest.approx(0.25, abs=0.01)   # P(received | lost last) = recover


def test_real_form_is_evaluated_once_per_system():
    # equal systems share one FloatSystem (the sympy evaluation is the cost), whose arrays cannot
    # be changed behind the cache's back; the complex system's real form is twice its size
    twin = System(A=COMPLEX.A, sensors=COMPLEX.sensors, Q=COMPLEX.Q, P0=COMPLEX.P0)
    assert twin == COMPLEX and twin is not COMPLEX and real_form(twin) is real_form(COMPLEX)
    model = real_form(COMPLEX)
    assert model.n == 2 * COMPLEX.n
    with pytest.raises(ValueError, match="read-only"):
        model.A[0, 0] = 1.0


def test_bad_receptions_are_refused():
    with pytest.raises(ShapeError, match="receptions"):
        predicted_covariances(TRI, np.ones((2, 3, 3)))
    with pytest.raises(InputError, match="0 \\(lost\\) or 1"):
        predicted_covariances(TRI, np.full((2, 3, 2), 2))
    with pytest.raises(ShapeError, match="loss"):
        sample_receptions(IID(["1/2"]), 3, 2, np.random.default_rng(0), d=2)
    with pytest.raises(InputError, match="receptions\\[0\\]"):
        exact_covariances(TRI, [(1, 2)])


# -- log-scale traces -------------------------------------------------------------------------------

@pytest.mark.parametrize("system", [TRI, CUBIC, COMPLEX], ids=["n2", "n3", "complex"])
def test_log_traces_match_the_exact_oracle(system):
    # the square-root, log-scale filter against eq. (9) in exact arithmetic
    rng = np.random.default_rng(11)
    seqs = rng.integers(0, 2, (3, 6, system.d)).astype(bool)
    logs = log_traces(real_form(system), seqs.transpose(1, 0, 2))
    for seq, lt in zip(seqs, logs):
        exact = exact_covariances(system, [tuple(int(g) for g in v) for v in seq])
        target = [float(sp.re(sp.N(Pk.trace()))) for Pk in exact]
        np.testing.assert_allclose(np.exp(lt), target, rtol=1e-11)


def test_traces_into_writes_a_row_per_step_from_its_first_path_and_refuses_c_order():
    # the kernel writes each step's traces of a block of paths contiguously: out is in Fortran order,
    # a run of paths fills its own rows from `first` (chunks of a longer run), the same bits as one run
    # over all paths, and tr P itself: exp of log_traces to rounding
    model = real_form(TRI)
    received = np.random.default_rng(3).random((6, 300, TRI.d)) < 0.6
    whole = np.empty((6, 300)).T
    traces_into(model, received, whole)
    np.testing.assert_allclose(whole, np.exp(log_traces(model, received)[:, :6]), rtol=1e-14)
    parts = np.full((6, 310), np.nan).T
    traces_into(model, received[:, :200], parts, 3)
    traces_into(model, received[:, 200:], parts, 203)
    assert np.array_equal(parts[3:303], whole) and np.isnan(parts[:3]).all() and np.isnan(parts[303:]).all()
    with pytest.raises(ShapeError, match="Fortran order.* in C order"):
        traces_into(model, received, np.empty((300, 6)))
    with pytest.raises(ShapeError, match="first \\+ paths = 301"):
        traces_into(model, received, whole, 1)


def test_log_traces_follow_thousands_of_unstable_steps():
    # everything lost for 3000 steps: P_{k+1} = A P A^T + Q with A = 2 R(pi/2), P0 = Q = I,
    # so P_k = (4^(k+1) - 1)/3 I and log tr P_k = log(2 (4^(k+1) - 1) / 3) (hand-derived:
    # A A^T = 4 I); float64 covariances overflow after ~510 steps
    system = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])])
    lost = np.zeros((3000, 2, 1), bool)
    logs = log_traces(real_form(system), lost)
    k = np.arange(3001)
    np.testing.assert_allclose(logs[0], np.log(2 / 3) + (k + 1) * np.log(4) + np.log1p(-4.0 ** -(k + 1)),
                               rtol=1e-12)


def _rotations(n: int, modulus: str) -> sp.Matrix:
    """n/2 rotation blocks of ``modulus`` by the rational angles of (3, 4, 5), (5, 12, 13), ... in turn"""
    A = sp.zeros(n, n)
    for b in range(n // 2):
        x, y, r = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25)][b % 4]
        A[2 * b:2 * b + 2, 2 * b:2 * b + 2] = sp.Rational(modulus) / r * sp.Matrix([[x, -y], [y, x]])
    return A


# n = 8 (STRAIGHT_MAX): its kernel alone compiles in 11 CPU-s, so it runs in the full tier
@pytest.mark.parametrize("n, modulus, loss", [(2, "9/10", 0.5), (4, "6/5", 0.2),
                                               pytest.param(8, "11/10", 0.3, marks=pytest.mark.full),
                                               (12, "21/20", 0.2), (34, "9/10", 0.3)])
def test_log_traces_match_the_covariance_form_on_stable_runs(n, modulus, loss):
    # an independent computation: the float64 covariance recursion (information-form update,
    # predicted_covariances) is accurate while P stays moderate, here 300 steps of mean-square
    # stable runs; 300 paths leave a partial block of the compiled kernel (blocks of 64 or 128).
    # n = 12 runs the loop kernel with its unrolled kernels (symkf.numeric.unrolled_kernels), n = 34 with
    # the loops beyond UNROLLED_MAX.
    # Two-row sensors with correlated noise exercise the whitening.
    rng = np.random.default_rng(n)
    with budget.limits(max_dimension=max(n, budget.LIMITS.max_dimension)):
        sensors = [Sensor(C=rng.integers(-2, 3, (2, n)).tolist(), R=[[2, 1], [1, 3]]),
                   Sensor(C=[[1] + [0] * (n - 1)])]
        system = System(A=_rotations(n, modulus), sensors=sensors)
    paths = 300 if n <= 12 else 40                            # the reference's cost grows like n^3
    gamma = rng.random((paths, 300, 2)) >= loss               # (paths, horizon, d)
    plain = predicted_covariances(system, gamma, check_every=0)
    logs = log_traces(real_form(system), gamma.transpose(1, 0, 2))
    assert logs.shape == (paths, 301)
    np.testing.assert_allclose(logs[:, :300], np.log(plain), rtol=1e-10)


@pytest.mark.parametrize("n", [3, 6, 11])
def test_log_traces_of_a_dense_A_match_the_covariance_form(n):
    # the kernel takes A lower Hessenberg: a dense A runs in an orthonormal basis that makes it so
    # (reduced to upper Hessenberg form, then the states reversed; tr P is unchanged); the float64
    # covariance recursion in the original basis is the reference
    from symkf.numeric.filters import _hessenberg_basis, _kernel_arguments
    rng = np.random.default_rng(100 + n)
    M = rng.integers(-3, 4, (n, n))
    radius = max(abs(np.linalg.eigvals(M)))
    A = sp.Matrix(M) * sp.Rational(9, 10) / sp.Rational(int(radius * 100) + 1, 100)
    T = _hessenberg_basis(np.array(A, float))
    np.testing.assert_allclose(T @ T.T, np.eye(n), atol=1e-14)
    assert np.abs(np.tril(T @ np.array(A, float) @ T.T, -2)).max() < 1e-14 * max(1, np.abs(M).max())
    with budget.limits(max_dimension=max(n, budget.LIMITS.max_dimension)):
        system = System(A=A, sensors=[Sensor(C=rng.integers(-2, 3, (1, n)).tolist()), Sensor(C=[[1] + [0] * (n - 1)])],
                        Q=sp.diag(*range(1, n + 1)))
    gamma = rng.random((200, 150, 2)) >= 0.4
    plain = predicted_covariances(system, gamma, check_every=0)
    kernel_A = _kernel_arguments(real_form(system), gamma.transpose(1, 0, 2))[0]
    assert not np.any(np.triu(kernel_A, 2)) and np.any(np.tril(kernel_A, -1))
    logs = log_traces(real_form(system), gamma.transpose(1, 0, 2))
    np.testing.assert_allclose(logs[:, :150], np.log(plain), rtol=1e-10)


def test_log_traces_keep_an_unobserved_unstable_mode_beyond_float64():
    # A = diag(2, 1/2), P0 = Q = I, the sensor sees only the stable coordinate: P stays diagonal,
    # p1_{k+1} = 4 p1_k + 1 whatever is received (p1_k = (4^(k+1) - 1)/3, beyond 1e308 after
    # 512 steps) and p2 follows the scalar Riccati recursion p2 <- p2 / (1 + p2) on received
    # steps, then p2 <- p2 / 4 + 1 (hand-derived: C = [0 1], R = 1).  The compiled kernel's
    # measurement noise 2^-E underflows to zero after ~540 steps; log tr P must not notice.
    # (symkf.System refuses this undetectable pair, so the float data are given directly)
    model = FloatSystem(A=np.diag([2.0, 0.5]), Q=np.eye(2), P0=np.eye(2), H=np.array([[0.0, 1.0]]),
                        W=np.eye(1), row_sensor=np.zeros(1, int))
    received = np.random.default_rng(5).random(2000) < 0.5
    p2, log_p2 = 1.0, [0.0]
    for got in received:
        p2 = (p2 / (1 + p2) if got else p2) / 4 + 1
        log_p2.append(np.log(p2))
    k = np.arange(2001)
    log_p1 = (k + 1) * np.log(4) + np.log1p(-4.0 ** -(k + 1)) - np.log(3)
    expected = np.logaddexp(log_p1, np.array(log_p2))
    logs = log_traces(model, received[:, None, None])
    np.testing.assert_allclose(logs[0], expected, rtol=1e-12)


def test_log_traces_follow_the_burst_of_2R_2pi3_up_to_the_float_horizon():
    # A = 2 R(2 pi/3), C = [1 0], received at phases 0 mod 3 (the decisive burst of
    # test_float_horizon_caps_bursts_float64_cannot_follow): independent oracle, the
    # covariance form in 60-digit mpmath.  float64 A is structured only to 1e-16, so the float
    # filter follows the exact log tr P to 1e-10 up to float_horizon (41 steps) and departs
    # after ~50 (measured: 3e-8 at 50, 4% at 60)
    import mpmath as mp
    system = System(A=[[-1, "-sqrt(3)"], ["sqrt(3)", -1]], sensors=[Sensor(C=[[1, 0]])])
    with mp.workdps(60):
        A, C, P = mp.matrix([[-1, -mp.sqrt(3)], [mp.sqrt(3), -1]]), mp.matrix([[1, 0]]), mp.eye(2)
        exact = []
        for k in range(42):
            exact.append(float(mp.log(P[0, 0] + P[1, 1])))
            if k % 3 == 0:
                P = P - P * C.T * C * P / (1 + P[0, 0])
            P = A * P * A.T + mp.eye(2)
    received = (np.arange(41) % 3 == 0)[:, None, None]
    np.testing.assert_allclose(log_traces(real_form(system), received)[0], exact, rtol=1e-10)


def test_log_traces_keep_the_exact_structure_of_a_float_exact_burst():
    # A = 2 R(pi/2) = [[0, -2], [2, 0]] and h = [1, 1] (exact in float64), received at even steps
    # only: in the basis u1 = [1, 1]/sqrt2, u2 = [1, -1]/sqrt2, A = [[0, 2], [-2, 0]], so P (= I at
    # first, Q = I) stays diagonal: a received step maps p1 -> p1 / (1 + 2 p1) (h = sqrt2 u1),
    # then p1, p2 -> 4 p2 + 1, 4 p1 + 1 (hand-derived).  The unseen direction grows 16x per
    # period for 2000 steps; an FMA-contracted kernel lost 32 of the final 2773 here
    import mpmath as mp
    model = real_form(System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[1, 1]])]))
    p1, p2, expected = mp.mpf(1), mp.mpf(1), []
    for k in range(2001):
        expected.append(float(mp.log(p1 + p2)))
        if k % 2 == 0:
            p1 = p1 / (1 + 2 * p1)
        p1, p2 = 4 * p2 + 1, 4 * p1 + 1
    received = np.zeros((2000, 1, 2), bool)
    received[::2, 0, 1] = True
    np.testing.assert_allclose(log_traces(model, received)[0], expected, rtol=1e-12)


def test_a_noise_free_contracting_system_keeps_finite_logs_over_thousands_of_steps():
    # A = I/2, Q = 0 (a FloatSystem may have it), nothing received: tr P_k = 2 / 4^k exactly; the
    # process noise's scale 2^(-E/2) passed float64 at step 1024 and inf * 0 made every later log nan
    model = FloatSystem(A=0.5 * np.eye(2), Q=np.zeros((2, 2)), P0=np.eye(2), H=np.eye(2), W=np.eye(2),
                        row_sensor=np.array([0, 1]))
    logs = log_traces(model, np.zeros((1500, 4, 2), bool))
    np.testing.assert_allclose(logs, np.tile(np.log(2) - np.log(4) * np.arange(1501), (4, 1)), rtol=1e-13)
