"""The pieces the compiled kernels inline (symkf.numeric.kernel_parts): the scaled logarithm within
an ulp of the exact one, 2^e exactly as ldexp at every exponent (with and without AVX-512),
arrays aligned to a cache line, and one step's receptions copied sensor-major."""

import os
import subprocess
import sys

import numpy as np
import pytest


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
from test_kernel_parts import _ldexp_bits, _powers
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
