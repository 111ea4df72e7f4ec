"""The compiled square-root filter kernels (symkf.numeric.square_root, and the generated
symkf.numeric.straight_kernels and unrolled_kernels): the straight-line and unrolled kernels equal
the loop kernel bit for bit, the generated modules are the generators' output, the kernels record
the digest of the parts they inline (a stale one turns numba's cache off), and log_trace_paths
takes receptions in any memory order and dtype, rescales traces that leave the window in one step
and refuses arguments that disagree."""


import numpy as np
import pytest

from symkf.errors import ShapeError


# 5: the last kernel whose time update takes the traces (TRACED_MAX); 5 and 8 (STRAIGHT_MAX) in the full tier: their
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
    # (A lower Hessenberg, as the kernels take it: symkf.numeric.filters's arguments reduce a dense A)
    for A, H in ((np.tril(dense, 1) * 1.5 / np.abs(np.linalg.eigvals(np.tril(dense, 1))).max(), rng.normal(size=(3, n))),
                 (np.kron(np.eye(-(-n // 2)), [[0.0, -2.0], [2.0, 0.0]])[:n, :n] + np.diag([0.0] * (n - 1) + [1.5 * (n % 2)]),
                  rng.integers(-1, 2, (3, n)).astype(float))):
        M = rng.normal(size=(n, n))
        UQ = np.linalg.qr(M.T, mode="r")
        S0 = np.linalg.qr(rng.normal(size=(n, n)).T, mode="r").T
        rows = np.array([0, 1, 1])
        received = rng.random((600, 2 * width + 37, 2)) < 0.3   # whole blocks of both kernels' lanes, and a partial one
        received[:, :64] = False
        received[:, 64:128] = True
        paths = received.shape[1]
        out = []
        for kernel in (_straight(n), _loop_kernel(n)):
            logs = np.empty((601, paths))
            # the traces into columns 5.. of a wider array (a chunk of a longer run): the others untouched
            linear = np.full((600, paths + 9), np.nan)
            kernel(A, UQ, H, rows, S0, received, logs, 0, False)
            kernel(A, UQ, H, rows, S0, received, linear, 5, True)
            out.append((logs, linear))
        assert all(np.array_equal(x, y, equal_nan=True) for x, y in zip(*out))
        logs, linear = out[0]
        assert np.all(np.isnan(linear[:, :5])) and np.all(np.isnan(linear[:, 5 + paths:]))
        linear = linear[:, 5:5 + paths]
        chosen = np.empty((600, paths))
        log_trace_paths(A, UQ, H, rows, S0, received, chosen, True)
        assert np.array_equal(chosen, linear)
        assert np.all(np.isfinite(logs)) and np.ptp(logs) > 100
        # linear units: the same trace times 2^E (inf beyond float64), so its log agrees to rounding
        held = np.isfinite(linear)
        assert held.mean() > 0.2
        np.testing.assert_allclose(np.log(linear[held]), logs[:600][held], rtol=4e-16, atol=4e-15)


def _row_kernel(kind: str, n: int, unrolled: bool, data: np.ndarray, vectors: np.ndarray) -> None:
    """Run ``kind``'s kernel for ``n`` in place: the one the loop kernel uses (``unrolled``), or its
    loops (which the loop kernel uses beyond UNROLLED_MAX)."""
    import ctypes

    from symkf.numeric import square_root
    kernel = square_root._unrolled(kind, n) if unrolled else square_root._row_loops(kind)
    pointer = ctypes.POINTER(ctypes.c_double)
    kernel.ctypes(data.ctypes.data_as(pointer), vectors.ctypes.data_as(pointer), n)


# 16: UNROLLED_MAX["householder"], the largest written out, in the full tier (5 CPU-s to compile); 17: the loops
@pytest.mark.parametrize("n", [1, 2, 9, pytest.param(16, marks=pytest.mark.full), 17])
def test_the_unrolled_householder_kernels_equal_the_loops_bit_for_bit(n):
    # beyond 8 states the time update triangularises with symkf.numeric.unrolled_kernels (columns
    # written out) and beyond UNROLLED_MAX with _householder_loops: the same operations in the same
    # order.  X as the time update builds it ((A S)^T upper Hessenberg, U_Q's rows zero left of their
    # diagonal; the entries below, never read, nan), with a lane whose columns are zero (|v| = 0: the
    # reflector divides by inf) and negative pivots; compared where the time update reads it
    # afterwards (row j from column j on)
    from symkf.numeric.square_root import LOOP_LANES
    rng = np.random.default_rng(n)
    X = np.full((2 * n, n | 1, LOOP_LANES), np.nan)
    for i in range(n):
        X[:min(i + 2, n), i] = rng.normal(size=(min(i + 2, n), LOOP_LANES))
        X[n + i, i:n] = rng.normal(size=(n - i, LOOP_LANES))
    X[:, :n, 0] = np.where(np.isnan(X[:, :n, 0]), np.nan, 0.0)
    outs = []
    for unrolled in (True, False):
        Y = X.copy()
        _row_kernel("householder", n, unrolled, Y, np.full((n + 3) * LOOP_LANES, np.nan))
        outs.append(Y)
    upper = np.triu(np.ones((2 * n, n | 1), bool))[:, :, None] & (np.arange(2 * n) < n)[:, None, None]
    upper = np.broadcast_to(upper, X.shape)
    assert np.array_equal(outs[0][upper], outs[1][upper], equal_nan=True)
    R = np.where(upper, outs[0], 0.0)[:n, :n]           # R^T R = X^T X in every lane
    dense = np.nan_to_num(X[:, :n])
    np.testing.assert_allclose(np.einsum("kip,kjp->ijp", R, R), np.einsum("kip,kjp->ijp", dense, dense), atol=1e-9)
    assert np.all(R[:, :, 0] == 0.0)


# 16: UNROLLED_MAX["carlson"], in the full tier (2 CPU-s to compile); 17: the loops alone
@pytest.mark.parametrize("n", [1, 2, 9, pytest.param(16, marks=pytest.mark.full), 17])
def test_the_unrolled_carlson_kernels_equal_the_loops_bit_for_bit(n):
    # Carlson's rotations of a lower-triangular S, row by row: the written-out rows and
    # _carlson_loops agree in every bit; with the rotations of a received row h (as _loops makes
    # them) S S^T becomes P - P h h^T P / (h^T P h + r) (to rounding), and the upper triangle and the
    # padding column of S (n | 1 columns) are left as they were (never read or written)
    from symkf.numeric.square_root import LOOP_LANES
    rng = np.random.default_rng(n)
    S = np.full((n, n | 1, LOOP_LANES), np.nan)
    for i in range(n):
        S[i, :i + 1] = rng.normal(size=(i + 1, LOOP_LANES))
    h, r = rng.normal(size=n), 0.5
    f = np.einsum("ijp,i->jp", np.nan_to_num(np.tril(S[:, :n].transpose(2, 0, 1)).transpose(1, 2, 0)), h)
    cs = np.full((2 * n + 1, LOOP_LANES), np.nan)
    alpha, previous = np.full(LOOP_LANES, r), np.full(LOOP_LANES, np.sqrt(r))
    for j in reversed(range(n)):
        alpha = alpha + f[j] * f[j]
        root = np.sqrt(alpha)
        cs[j], cs[n + j], previous = previous / root, f[j] / root, root
    outs = []
    for unrolled in (True, False):
        T = S.copy()
        _row_kernel("carlson", n, unrolled, T, cs.copy())
        outs.append(T)
    assert np.array_equal(outs[0], outs[1], equal_nan=True)
    above = np.broadcast_to(~np.tril(np.ones((n, n | 1), bool))[:, :, None], S.shape)
    assert np.all(np.isnan(outs[0][above]))
    lower = np.nan_to_num(outs[0][:, :n])
    before = np.nan_to_num(S[:, :n])
    P = np.einsum("ikp,jkp->ijp", before, before)
    Ph = np.einsum("ijp,j->ip", P, h)
    expected = P - Ph[:, None] * Ph[None, :] / (np.einsum("ip,i->p", Ph, h) + r)
    np.testing.assert_allclose(np.einsum("ikp,jkp->ijp", lower, lower), expected, atol=1e-11 * n)


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


@pytest.mark.parametrize("n", [1, 2, 3, 4, 9])   # 9: the loop kernel through log_trace_paths
@pytest.mark.parametrize("power", [200, -200])
def test_the_kernels_rescale_a_trace_that_leaves_the_window_in_one_step(n, power):
    # up to TRACED_MAX the straight-line kernels and the loop kernel rescale only once a trace has left
    # [2^-32, 2^32]: A = 2^200 I (or 2^-200 I), no noise, nothing received moves tr P by 2^(+-400) a
    # step, out of the window at every step and out of float64 by the third unless each step is
    # rescaled; a block's paths all at once, and a partial block's (both kernels: the same bits).
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
    _loop_kernel(n)(A, UQ, H, rows, S0, received, looped, 0, False)
    assert np.array_equal(logs, looped)


def test_the_kernels_record_the_digest_of_the_parts_they_inline():
    # numba keys a cached kernel on its own file's time stamp alone: square_root.py and the generated
    # modules record kernel_parts.py's digest, so that an edit there changes them (regenerated, or
    # KERNEL_PARTS brought up to date)
    from symkf.numeric import square_root, straight_kernels, unrolled_kernels
    digest = square_root._inlined_digest()
    assert square_root.KERNEL_PARTS == straight_kernels.INLINED == unrolled_kernels.INLINED == digest


def _plus_one(x):
    return x + 1


def test_a_kernel_whose_recorded_digest_is_stale_is_compiled_without_numbas_cache():
    # a recorded digest that is not kernel_parts.py's (an edit not yet recorded) turns numba's on-disk
    # cache off: the kernel is compiled afresh rather than loaded with stale parts inlined
    from numba.core.caching import NullCache

    from symkf.numeric import square_root
    assert isinstance(square_root._jit("0" * 16)(_plus_one)._cache, NullCache)
    assert not isinstance(square_root._jit(square_root.KERNEL_PARTS)(_plus_one)._cache, NullCache)


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


def test_the_triangular_update_stays_with_a_high_precision_reference_on_an_ill_conditioned_path():
    # A = 8.4 diag(R(pi/3), R(pi/4)) (lower Hessenberg), one sensor h = (0, 1, -1, -1), P0 = Q = I,
    # R = 1, a path of 100 steps receiving 46 of them: tr P grows by 8.4^2 a lost step while each
    # reception collapses the observed direction to O(1), so P's scales drift up to e^90 apart.  A
    # full (Potter) update left a residue of its rounding in the collapsed direction and its log tr P
    # was off by 19 from the covariance form's in 300 digits; Carlson's triangular update stays within
    # 1e-4 (1.5e-6 measured)
    import mpmath as mp

    from symkf.numeric.square_root import log_trace_paths
    c3, s3, c4 = 0.5, np.sqrt(3.0) / 2, np.sqrt(0.5)
    A = 8.4 * np.array([[c3, -s3, 0, 0], [s3, c3, 0, 0], [0, 0, c4, -c4], [0, 0, c4, c4]])
    h = np.array([0.0, 1.0, -1.0, -1.0])
    got = [bit == "1" for bit in f"{0x67d643664bf700210633bc561:0100b}"]
    received = np.array(got).reshape(100, 1, 1)
    logs = np.empty((101, 1))
    log_trace_paths(A, np.eye(4), h[None, :], np.array([0]), np.eye(4), received, logs)
    mp.mp.dps = 300
    Am, hm, P = mp.matrix(A.tolist()), mp.matrix(h.tolist()), mp.eye(4)
    reference = []
    for k in range(101):
        reference.append(float(mp.log(sum(P[i, i] for i in range(4)))))
        if k < 100 and got[k]:
            Ph = P * hm
            P = P - Ph * Ph.T / ((hm.T * Ph)[0] + 1)
        P = Am * P * Am.T + mp.eye(4)
    assert max(reference) - min(reference) > 80
    np.testing.assert_allclose(logs[:, 0], reference, rtol=0, atol=1e-4)


def test_the_straight_line_kernels_read_and_write_only_the_lower_triangle_of_s():
    # S stays lower triangular (Carlson's update keeps it so, the time update writes R^T): no kernel
    # reads an entry above the diagonal (S0's, zero, are never loaded) nor writes one
    import re

    from symkf.numeric import straight_kernels
    from symkf.numeric.square_root import STRAIGHT_MAX, _straight_source
    for n in range(1, STRAIGHT_MAX + 1):
        entries = {(int(i), int(j)) for i, j in re.findall(r"\bS0?\[(\d+), (\d+)", _straight_source(n))}
        assert entries == {(i, j) for i in range(n) for j in range(i + 1)}
    assert "S[0, 1, p]" not in open(straight_kernels.__file__, encoding="utf-8").read()


def test_the_kernel_refuses_an_a_that_is_not_lower_hessenberg():
    # the time update's reflectors span c + 3 rows only because A S is lower Hessenberg: an A with an
    # entry above its superdiagonal is refused, naming the form (symkf.numeric.filters reduces a dense A)
    from symkf.numeric.square_root import log_trace_paths
    A = np.triu(np.ones((3, 3)))
    with pytest.raises(ShapeError, match="A: the kernel takes A lower Hessenberg"):
        log_trace_paths(A, np.eye(3), np.ones((1, 3)), np.array([0]), np.eye(3), np.ones((4, 8, 1), bool),
                        np.empty((5, 8)))
