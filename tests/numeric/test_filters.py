"""The batched float filter against the exact oracle (Sui-You-Fu eq. 9) and against its own simulation."""

import os
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from symkf import budget
from symkf.errors import InputError, ShapeError
from symkf.numeric.filters import (FloatSystem, exact_covariances, log_traces, predicted_covariances, real_form,
                                   sample_receptions, simulate_trajectories)
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.model.system import Sensor, System

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
    # the kernel takes A upper Hessenberg: a dense A runs in an orthonormal basis that makes it so
    # (tr P is unchanged); the float64 covariance recursion in the original basis is the reference
    from symkf.numeric.filters import _hessenberg_basis
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


# 5: the last phased time update (PHASED_MAX); 5 and 8 (STRAIGHT_MAX) in the full tier: their
# straight kernels compile in 5 and 11 CPU-s
@pytest.mark.parametrize("n", [1, 2, 3, 4, pytest.param(5, marks=pytest.mark.full),
                               pytest.param(8, marks=pytest.mark.full)])
def test_straight_line_kernels_equal_the_loop_kernel_bit_for_bit(n):
    # symkf.numeric.square_root writes the filter out per state dimension (up to STRAIGHT_MAX); the
    # loop kernel does the same operations in the same order, so every output bit must agree:
    # dense and sparse (integer, block-diagonal) A and H, two-row sensors, paths that receive
    # nothing or everything, and a 600-step stretch of mostly lost steps (wide scales)
    from symkf.numeric.square_root import LOOP_LANES, STRAIGHT_MAX, _loop_kernel, _straight, lanes, log_trace_paths
    assert n <= STRAIGHT_MAX
    width = max(lanes(n), LOOP_LANES)   # the buffers' lanes: each kernel's block fits
    rng = np.random.default_rng(n)
    dense = rng.normal(size=(n, n))
    # (A upper Hessenberg, as the kernels take it: symkf.numeric.filters's arguments reduce a dense A)
    for A, H in ((np.triu(dense, -1) * 1.5 / np.abs(np.linalg.eigvals(np.triu(dense, -1))).max(), rng.normal(size=(3, n))),
                 (np.kron(np.eye(-(-n // 2)), [[0.0, -2.0], [2.0, 0.0]])[:n, :n] + np.diag([0.0] * (n - 1) + [1.5 * (n % 2)]),
                  rng.integers(-1, 2, (3, n)).astype(float))):
        M = rng.normal(size=(n, n))
        UQ = np.linalg.qr(M.T, mode="r")
        S0 = np.linalg.qr(rng.normal(size=(n, n)).T, mode="r").T
        rows = np.array([0, 1, 1])
        received = rng.random((600, 2 * width + 37, 2)) < 0.3   # whole blocks of both kernels' lanes, and a partial one
        received[:, :64] = False
        received[:, 64:128] = True
        out = []
        for kernel in (_straight(n), _loop_kernel(n)):
            logs, linear = np.empty((601, 2 * width + 37)), np.empty((150, 600))
            kernel(A, UQ, H, rows, S0, received, logs, np.empty((1, width)), False)
            kernel(A, UQ, H, rows, S0, received, linear, np.empty((64, width)), True)   # the first 150 paths
            out.append((logs, linear))
        assert all(np.array_equal(x, y) for x, y in zip(*out))
        logs, linear = out[0]
        # through log_trace_paths, whose buffer holds fewer steps for wide blocks (8 at n <= 2)
        chosen = np.empty((150, 600))
        log_trace_paths(A, UQ, H, rows, S0, received, chosen, True)
        assert np.array_equal(chosen, linear)
        assert np.all(np.isfinite(logs)) and np.ptp(logs) > 100
        # linear units: the same trace times 2^E (inf beyond float64), so its log agrees to rounding
        held = np.isfinite(linear)
        assert held.mean() > 0.2
        np.testing.assert_allclose(np.log(linear[held]), logs[:600, :150].T[held], rtol=4e-16, atol=4e-15)


def test_a_lane_loops_paths_interleave_with_their_own_names_and_shared_reductions():
    # the n = 2 time update runs two paths per iteration, statement by statement: names the body
    # assigns before reading are each path's own, names it reads first (reductions) are shared
    from symkf.numeric.square_root import _interleaved
    body = ["x = S[0, p] * 2.0", "x += t[p]", "top = max(top, x)", "acc += x", "out[p] = x"]
    assert _interleaved(body, 2, 64) == [
        "x = S[0, p] * 2.0", "x_1w = S[0, p + 64] * 2.0", "x += t[p]", "x_1w += t[p + 64]",
        "top = max(top, x)", "top = max(top, x_1w)", "acc += x", "acc += x_1w", "out[p] = x", "out[p + 64] = x_1w"]


def test_the_kernels_log_is_within_an_ulp_of_the_exact_log():
    # log t + e ln 2 (fdlibm's log, branch-free so that the kernel's lane loops vectorise) against
    # 40-digit mpmath: t over the kernel's range [1/2, 2) and its edges, e over the exponents of
    # thousands of unstable steps; 0 -> -inf, inf and nan pass through
    import mpmath as mp
    from symkf.numeric.kernel_parts import _log_scaled
    rng = np.random.default_rng(7)
    ts = np.concatenate([rng.uniform(0.5, 2.0, 3000), [0.5, np.nextafter(2.0, 0), 1.0, np.nextafter(1.0, 2),
                                                       np.nextafter(1.0, 0), np.sqrt(2), np.nextafter(np.sqrt(2), 2)]])
    es = rng.integers(-3000, 3000, ts.size)
    es[:40] = 0
    with mp.workdps(40):
        for t, e in zip(ts, es):
            got = _log_scaled(float(t), int(e))
            exact = mp.log(mp.mpf(float(t))) + int(e) * mp.log(2)
            assert abs(mp.mpf(got) - exact) <= np.spacing(abs(float(exact))) or (got == 0.0 and exact == 0)
    assert _log_scaled(0.0, 4) == -np.inf and _log_scaled(np.inf, 0) == np.inf and np.isnan(_log_scaled(np.nan, 0))


def _row_kernel(kind: str, n: int, unrolled: bool, data: np.ndarray, vectors: np.ndarray) -> None:
    """Run ``kind``'s kernel for ``n`` in place: the one the loop kernel uses (``unrolled``), or its
    loops (which the loop kernel uses beyond UNROLLED_MAX)."""
    import ctypes

    from symkf.numeric import square_root
    kernel = square_root._unrolled(kind, n) if unrolled else square_root._row_loops(kind)
    pointer = ctypes.POINTER(ctypes.c_double)
    kernel.ctypes(data.ctypes.data_as(pointer), vectors.ctypes.data_as(pointer), n)


@pytest.mark.parametrize("n", [1, 2, 9, 16, 32])   # 32: UNROLLED_MAX["householder"], the largest written out
def test_the_unrolled_householder_kernels_equal_the_loops_bit_for_bit(n):
    # beyond 8 states the time update triangularises with symkf.numeric.unrolled_kernels (rows written
    # out) and beyond UNROLLED_MAX with _householder_loops: the same operations in the same order.
    # X as the time update builds it (U_Q's rows zero left of their diagonal), with a lane whose
    # columns are zero (|v| = 0: the reflector divides by inf) and negative pivots; compared
    # where the time update reads it afterwards (row j from column j on)
    from symkf.numeric.square_root import LOOP_LANES
    rng = np.random.default_rng(n)
    X = np.zeros((2 * n, n | 1, LOOP_LANES))
    X[:n, :n] = rng.normal(size=(n, n, LOOP_LANES))
    for i in range(n):
        X[n + i, i:n] = rng.normal(size=(n - i, LOOP_LANES))
    X[:, :, 0] = 0.0
    outs = []
    for unrolled in (True, False):
        Y = X.copy()
        _row_kernel("householder", n, unrolled, Y, np.full((n + 3) * LOOP_LANES, np.nan))
        outs.append(Y)
    upper = np.triu(np.ones((2 * n, n | 1), bool))[:, :, None] & (np.arange(2 * n) < n)[:, None, None]
    upper = np.broadcast_to(upper, X.shape)
    assert np.array_equal(outs[0][upper], outs[1][upper])
    R = np.where(upper, outs[0], 0.0)[:n, :n]           # R^T R = X^T X in every lane
    np.testing.assert_allclose(np.einsum("kip,kjp->ijp", R, R), np.einsum("kip,kjp->ijp", X[:, :n], X[:, :n]),
                               atol=1e-9)
    assert np.all(R[:, :, 0] == 0.0)


@pytest.mark.parametrize("n", [1, 2, 9, 16, 17])   # 16: UNROLLED_MAX["potter"]; 17: the loops alone
def test_the_unrolled_potter_kernels_equal_the_loops_bit_for_bit(n):
    # S <- S - (S f) g^T, row by row: the written-out rows and _potter_loops agree in every bit
    # and with numpy's product (to rounding); the padding column of S (n | 1 columns) is untouched
    from symkf.numeric.square_root import LOOP_LANES
    rng = np.random.default_rng(n)
    S = rng.normal(size=(n, n | 1, LOOP_LANES))
    fg = np.concatenate([rng.normal(size=(2 * n, LOOP_LANES)), np.full((1, LOOP_LANES), np.nan)])
    outs = []
    for unrolled in (True, False):
        T = S.copy()
        _row_kernel("potter", n, unrolled, T, fg.copy())
        outs.append(T)
    assert np.array_equal(outs[0], outs[1])
    f, g = fg[:n], fg[n:2 * n]
    expected = S[:, :n] - np.einsum("ijp,jp->ip", S[:, :n], f)[:, None, :] * g[None, :, :]
    np.testing.assert_allclose(outs[0][:, :n], expected, atol=1e-12 * n)
    assert np.array_equal(outs[0][:, n:], S[:, n:])


def _powers(pow2):
    """A compiled loop of ``pow2`` over an array of exponents (the kernels' lane loops call it so)."""
    from numba import njit

    @njit
    def powers(es):
        out = np.empty(es.size)
        for i in range(es.size):
            out[i] = pow2(es[i])
        return out
    return powers


def _ldexp_bits(es):
    with np.errstate(over="ignore"):
        return np.ldexp(1.0, np.clip(es, -5000, 5000)).view(np.int64)


@pytest.mark.parametrize("implementation", ["_pow2", "_pow2_bits"])
def test_the_kernels_power_of_two_rounds_as_ldexp_at_every_exponent(implementation):
    # the lane loops' 2^e, by llvm.ldexp where the target has AVX-512 (_pow2 here on such a CPU)
    # and from exponent bits elsewhere (_pow2_bits): every e a path's scale can reach, the
    # subnormal range, the underflow to 0 (ties to even at 2^-1075) and the overflow to inf
    from numba import njit

    from symkf.numeric import kernel_parts
    pow2 = getattr(kernel_parts, implementation)
    powers = _powers(pow2 if implementation == "_pow2" else njit(pow2))
    es = np.concatenate([np.arange(-5000, 5001), [-2 ** 62, 2 ** 62]])
    assert np.array_equal(powers(es).view(np.int64), _ldexp_bits(es))


def test_the_kernels_power_of_two_without_avx512_is_built_from_exponent_bits(tmp_path):
    # compiled for a CPU without AVX-512 (numba's target set by its environment variables), _pow2
    # must not become llvm.ldexp, which LLVM would turn into a libm call per lane: no vscalefpd,
    # no call, and every value ldexp's
    script = f"""
import sys
sys.path.insert(0, {os.path.dirname(__file__)!r})
import numpy as np
from symkf.numeric.square_root import _pow2
from test_filters import _ldexp_bits, _powers
powers = _powers(_pow2)
es = np.arange(-2200, 2200)
got = powers(es)
asm = powers.inspect_asm(powers.signatures[0])
assert 'vscalefpd' not in asm and 'ldexp' not in asm, 'ldexp in the code'
assert np.array_equal(got.view(np.int64), _ldexp_bits(es))
print('ok')
"""
    env = dict(os.environ, NUMBA_CPU_NAME="haswell", NUMBA_CPU_FEATURES="+64bit,+avx,+avx2,+fma,+sse2,+sse4.1,+sse4.2,+popcnt",
               NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=300)
    assert out.stdout.strip() == "ok", out.stderr[-2000:]


@pytest.mark.parametrize("module, generator", [("straight_kernels", "_straight_module"),
                                               ("unrolled_kernels", "_unrolled_module")])
def test_the_generated_kernel_modules_are_the_generators_output(module, generator):
    # symkf/numeric/straight_kernels.py and unrolled_kernels.py are generated (by symkf.numeric.square_root):
    # never edited by hand
    import importlib
    from pathlib import Path

    import symkf.numeric.square_root
    generated = importlib.import_module(f"symkf.numeric.{module}")
    assert Path(generated.__file__).read_text(encoding="utf-8") == getattr(symkf.numeric.square_root, generator)()


def test_kernel_arrays_start_on_a_cache_line():
    # the lane loops' 64-byte vector loads must not span two cache lines: numba's own np.zeros is
    # 32-byte aligned (half of these sizes start 32 bytes off a line in a typical process)
    from numba import njit
    from symkf.numeric.square_root import _aligned, _aligned_int

    @njit
    def offsets(sizes):
        out = np.empty((len(sizes), 3), np.int64)
        for i in range(len(sizes)):
            a, e = _aligned((3, sizes[i], 8)), _aligned_int((sizes[i],))
            out[i] = a.ctypes.data % 64, e.ctypes.data % 64, int(a.sum()) + e.sum() + a.shape[1] - sizes[i]
        return out
    got = offsets(np.arange(1, 41))
    assert not got.any(), got


@pytest.mark.parametrize("d", range(1, 11))
def test_a_steps_receptions_are_copied_sensor_major(d):
    # one compiled copy per sensor count up to 8 (each its own interleaved vector code), strided passes
    # beyond; the block's paths past the last (a partial last block) receive nothing; one sensor's
    # whole blocks are read in place, copied nowhere
    from symkf.numeric.square_root import _receptions, lanes
    width = lanes(2)
    paths = 2 * width + 37
    received = np.random.default_rng(d).random((3, paths, d)) < 0.5
    for k, start in ((0, 0), (2, width), (1, 2 * width)):
        block = np.ones((d, width), bool)
        direct = _receptions(received, k, start, block)
        count = min(width, paths - start)
        assert direct == (d == 1 and count == width)
        assert block.all() if direct else not block[:, count:].any()
        rows = received.reshape(3, paths)[k:k + 1, start:start + width] if direct else block
        np.testing.assert_array_equal(rows[:, :count], received[k, start:start + count].T)
        assert not rows[:, count:].any()


def test_the_kernel_takes_receptions_in_any_memory_order():
    # log_trace_paths is public: receptions as a transposed view (sensor-major in memory) give the
    # traces of the same receptions in C order
    from symkf.numeric.square_root import log_trace_paths
    A, UQ, S0 = np.array([[1.0, 0.5], [0.0, 1.2]]), np.eye(2), np.eye(2)
    H, rows = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]), np.array([0, 1, 2])
    sensor_major = np.random.default_rng(0).random((30, 3, 700)) < 0.5
    view = sensor_major.transpose(0, 2, 1)
    assert not view.flags.c_contiguous
    traces = [np.empty((31, 700)) for _ in range(2)]
    log_trace_paths(A, UQ, H, rows, S0, view, traces[0])
    log_trace_paths(A, UQ, H, rows, S0, np.ascontiguousarray(view), traces[1])
    assert np.array_equal(*traces) and np.isfinite(traces[0]).all()


def test_a_noise_free_contracting_system_keeps_finite_logs_over_thousands_of_steps():
    # A = I/2, Q = 0 (a FloatSystem may have it), nothing received: tr P_k = 2 / 4^k exactly; the
    # process noise's scale 2^(-E/2) passed float64 at step 1024 and inf * 0 made every later log nan
    model = FloatSystem(A=0.5 * np.eye(2), Q=np.zeros((2, 2)), P0=np.eye(2), H=np.eye(2), W=np.eye(2),
                        row_sensor=np.array([0, 1]))
    logs = log_traces(model, np.zeros((1500, 4, 2), bool))
    np.testing.assert_allclose(logs, np.tile(np.log(2) - np.log(4) * np.arange(1501), (4, 1)), rtol=1e-13)


@pytest.mark.parametrize("dtype", [np.uint8, np.int64, np.float64])
def test_the_kernel_takes_receptions_of_any_dtype_as_nonzero_received(dtype):
    # one sensor's receptions are read in place: any dtype is made bool first (the in-place row and a
    # partial block's copy must be one type), 0 lost, anything else received
    from symkf.numeric.square_root import log_trace_paths
    A, UQ, S0 = np.array([[1.0, 0.5], [0.0, 1.2]]), np.eye(2), np.eye(2)
    H, rows = np.array([[1.0, 1.0]]), np.array([0])
    received = np.random.default_rng(1).random((20, 2100, 1)) < 0.5   # whole blocks and a partial one
    traces = [np.empty((21, 2100)) for _ in range(2)]
    log_trace_paths(A, UQ, H, rows, S0, received, traces[0])
    log_trace_paths(A, UQ, H, rows, S0, received.astype(dtype) * 3, traces[1])
    assert np.array_equal(*traces)
    with pytest.raises(ShapeError, match="received: expected"):
        log_trace_paths(A, UQ, H, rows, S0, received[:, :, 0], traces[0])


@pytest.mark.parametrize("n", [1, 2, 3, 4])
@pytest.mark.parametrize("power", [200, -200])
def test_the_kernels_rescale_a_trace_that_leaves_the_window_in_one_step(n, power):
    # up to PHASED_MAX the straight-line kernels rescale only once a trace has left [2^-32, 2^32]:
    # A = 2^200 I (or 2^-200 I), no noise, nothing received moves tr P by 2^(+-400) a step, out of the
    # window at every step and out of float64 by the third unless each step is rescaled; a block's
    # paths all at once, and a partial block's (the loop kernel rescales every step: the same bits).
    # With Q = 0 the process noise's scale 2^(-E/2) would pass 2^1024 at the seventh shrinking step
    # (ROOT_MAX): inf times U_Q's zeros made every log nan from there
    from symkf.numeric.square_root import _loop_kernel, log_trace_paths
    A, UQ, S0 = 2.0 ** power * np.eye(n), np.zeros((n, n)), np.eye(n)
    H, rows = np.ones((1, n)), np.array([0])
    received = np.zeros((30, 515, 1), bool)
    logs = np.empty((31, 515))
    log_trace_paths(A, UQ, H, rows, S0, received, logs)
    expected = np.log(n) + 2 * power * np.log(2) * np.arange(31)
    np.testing.assert_allclose(logs, np.repeat(expected[:, None], 515, axis=1), rtol=1e-14)
    looped = np.empty_like(logs)
    _loop_kernel(n)(A, UQ, H, rows, S0, received, looped, np.empty((1, 128)), False)
    assert np.array_equal(logs, looped)


@pytest.mark.parametrize("bad", ["A", "UQ", "S0", "H", "row_sensor"])
def test_the_kernel_refuses_arguments_that_disagree(bad):
    # the compiled loops do not check bounds: a row of a sensor past the receptions' last axis, or a
    # factor of another size, is refused before they run
    from symkf.errors import ShapeError
    from symkf.numeric.square_root import log_trace_paths
    args = dict(A=np.eye(2), UQ=np.eye(2), H=np.ones((2, 2)), row_sensor=np.array([0, 1]), S0=np.eye(2))
    args[bad] = np.array([0, 2]) if bad == "row_sensor" else np.eye(3)
    with pytest.raises(ShapeError, match=bad):
        log_trace_paths(**args, received=np.ones((4, 8, 2), bool), trace=np.empty((5, 8)))
