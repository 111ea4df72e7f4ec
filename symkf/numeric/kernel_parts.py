"""The pieces the compiled square-root filter kernels inline: float bit tricks, the scaled
logarithm, powers of two, aligned arrays, the rescale and the stores of traces
(:mod:`symkf.numeric.square_root` generates the kernels; it and the generated modules
:mod:`symkf.numeric.straight_kernels` and :mod:`symkf.numeric.unrolled_kernels` import these
and record this file's digest, since numba keys a cached kernel on its own file alone:
:func:`symkf.numeric.square_root._jit`).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import binding as llvm, ir
from numba import njit, types
from numba.core import cgutils
from numba.core.imputils import impl_ret_new_ref
from numba.extending import intrinsic
from numba.np.arrayobj import _empty_nd_impl

from ..arguments import check_public

#: paths per block of the loop kernel (more states than the straight-line kernels).  Its passes over a
#: block's S and X (n^2 and 2n^2 lanes of 8 bytes: 835 KiB at n = 16 and 128 lanes) run at the speed
#: of the cache that holds them: 64 lanes keep them in the L2 cache with room to spare, and were
#: 1.6-1.7x faster than 128 at n = 12 and 16, 1.15x at n = 24; 32 lanes, whose lane loops are four
#: vectors long, 0.6-0.7x (docs/performance.md)
LOOP_LANES = 64
#: the smallest normal float64, 2^-1022: a Carlson s_j or a Householder ``|v|^2 / 2`` below it
#: is dropped (its reciprocal could overflow; what it would change is below 2^-511 of ``S``'s scale)
NORMAL = float(np.finfo(np.float64).tiny)
#: the largest finite float64: a Carlson column whose ``s_j = sqrt(2^-E + f_j^2 + ...)`` is beyond it
#: (the measurement noise 2^-E = inf) is left as it is, as a lost row leaves it
BIG = float(np.finfo(np.float64).max)
#: below this ``tr S S^T`` (2^-960) the rescale scales by ``sum |S_ij|`` instead: the squares of an ``S``
#: whose entries are all below 2^-537 underflow (Carlson's update collapses an observed direction
#: exactly), a zero trace of a nonzero ``S`` that the trace's exponent cannot bring back
TINY_TRACE = 2.0 ** -960
#: the largest exponent of the process noise's scale 2^(-E/2): beyond, tr P < 2^-2048 < tr Q, so
#: Q = 0 (a time update leaves tr P >= tr Q), and 2^(-E/2) = inf would make inf * 0 = nan of its
#: zero entries (A = I/2, Q = 0: nan from step 1024 on); the measurement noise 2^-E may be inf
#: (a Carlson column beyond BIG is left alone: no row moves a P below 2^-1024 R)
ROOT_MAX = 1023
# error_model="numpy": divisions need no Python zero check, so the path loops vectorise.
# No fastmath, not even FMA contraction: a fused c S - sn v does not cancel to the same
# rounding as the product it subtracts, so a float-exact system (A = 2 R(pi/2)) would drift off
# its exact log tr P over a long periodic burst and float_horizon would cap it (test_filtering)
OPTIONS = {"nogil": True, "error_model": "numpy"}
_compiled = njit(cache=True, **OPTIONS)


@intrinsic
def _float_bits(typingctx, bits):
    """The float64 whose IEEE bits are the int64 ``bits`` (a register move: it vectorises)."""
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())
    return types.float64(types.int64), codegen


@intrinsic
def _bits_of(typingctx, value):
    """The IEEE bits of the float64 ``value`` as an int64 (a register move: it vectorises)."""
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))
    return types.int64(types.float64), codegen


@intrinsic
def _fma(typingctx, a, b, c):
    """``a b + c`` rounded once (``llvm.fma``: one vector instruction where the CPU has FMA)."""
    def codegen(context, builder, signature, args):
        double = ir.DoubleType()
        fma = cgutils.get_or_insert_function(builder.module, ir.FunctionType(double, [double] * 3), "llvm.fma.f64")
        return builder.call(fma, args)
    return types.float64(types.float64, types.float64, types.float64), codegen


#: fdlibm's e_log.c (Sun Microsystems, 1993): ln 2 split so that ``k ln2_hi`` is exact for
#: |k| < 2^20, and the minimax coefficients of ``(log(1 + f) - f + f^2/2) / s`` in ``s^2``,
#: ``s = f / (2 + f)``, error below 2^-58.7 on |s| <= 0.1716
LN2_HI, LN2_LO = 6.93147180369123816490e-01, 1.90821492927058770002e-10
LG = (6.666666666666735130e-01, 3.999999999940941908e-01, 2.857142874366239149e-01, 2.222219843214978396e-01,
      1.818357216161805012e-01, 1.531383769920937332e-01, 1.479819860511658591e-01)


@_compiled
def _log_scaled(t: float, e: int) -> float:
    """``log t + e ln 2`` for ``t`` zero or a normal float (-inf at 0, ``t`` itself if inf or nan), with
    fdlibm's ``log`` (below one ulp): branch-free, so that a lane loop of it vectorises, where
    ``math.log`` is a call per path.  ``t = m 2^k``, ``m`` in [sqrt(2)/2, sqrt(2)), ``f = m - 1``
    exact; then ``log t = (k + e) ln 2 + f - f^2/2 + s (f^2/2 + R(s^2))``.  The polynomial ``R`` and
    ``s (f^2/2 + R) + k ln2_lo`` are evaluated with fused multiply-adds (one rounding where fdlibm
    has two; 7 vector operations fewer per path-step): small terms, added last, whose rounding
    fdlibm's error analysis bounds; the final ``f - f^2/2`` and ``k ln2_hi`` are fdlibm's, unfused.
    Measured: at most 0.758 ulp over 480 000 arguments in [1/2, 2), near 1 and near sqrt 2, as
    fdlibm unfused (the two differ in 35 of 240 000 results)."""
    bits = _bits_of(t)
    k = ((bits >> 52) & 2047) - 1023
    m = _float_bits((bits & 0xFFFFFFFFFFFFF) | 0x3FF0000000000000)   # [1, 2)
    high = m > 1.4142135623730951
    m = m * 0.5 if high else m
    f = m - 1.0
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    R = _fma(z, _fma(w, _fma(w, _fma(w, LG[6], LG[4]), LG[2]), LG[0]), w * _fma(w, _fma(w, LG[5], LG[3]), LG[1]))
    half_f2 = 0.5 * f * f
    dk = float(k + (1 if high else 0) + e)
    value = dk * LN2_HI - ((half_f2 - _fma(s, half_f2 + R, dk * LN2_LO)) - f)
    if 0.0 < t < math.inf:
        return value
    return -math.inf if t == 0.0 else t


class _Aligned64:
    """numba's target context with 64-byte array alignment (its own is 32: AVX's)."""

    def __init__(self, context) -> None:
        self._context = context

    def __getattr__(self, name: str):
        return getattr(self._context, name)

    def get_preferred_array_alignment(self, ty) -> int:
        return 64


def _aligned_zeros(dtype):
    """An intrinsic ``zeros(shape)`` of ``dtype`` (C order) at a 64-byte boundary.  numba's own arrays
    are aligned to 32 bytes: in about half of all processes they start 32 bytes off a cache line,
    and then every 64-byte vector load of a lane loop spans two lines, so that the kernel's speed
    would depend on the process (docs/performance.md).  The allocation is numba's own
    (:func:`numba.np.arrayobj._empty_nd_impl`), in the kernel's body, so that the compiler still
    tells the arrays apart and knows their shapes (a view of another dtype would hide both, and
    the kernel would run several times slower)."""
    @intrinsic
    def zeros(typingctx, shape):
        array = types.Array(dtype, len(shape), "C")

        def codegen(context, builder, signature, args):
            out = _empty_nd_impl(_Aligned64(context), builder, array, cgutils.unpack_tuple(builder, args[0]))
            cgutils.memset(builder, out.data, builder.mul(out.itemsize, out.nitems), 0)
            return impl_ret_new_ref(context, builder, array, out._getvalue())
        return array(shape), codegen
    return zeros


_aligned, _aligned_int = _aligned_zeros(types.float64), _aligned_zeros(types.int64)


def _pow2_bits(e: int) -> float:
    """``2^e`` as the product of two normal powers of two built from their exponent bits, ``e``
    clamped to their range first (a table look-up is a gather, paid on every path-step of the lane
    loops)."""
    e = min(max(e, -2044), 2046)
    half = e >> 1
    return _float_bits((half + 1023) << 52) * _float_bits((e - half + 1023) << 52)


def _clamped(e: int) -> int:
    """``e`` within [-2100, 2100], where ``2^e`` is 0 or inf beyond (an int32 for ``llvm.ldexp``)."""
    return min(max(e, -2100), 2100)


@intrinsic
def _pow2(typingctx, e):
    """``2^e`` rounded as ``ldexp(1, e)`` (0 for e <= -1075, inf for e >= 1024).  Where the compile
    target has AVX-512 and LLVM has the ``llvm.ldexp`` intrinsic (LLVM 17 on; an older LLVM aborts
    the process on the unknown symbol), ``llvm.ldexp``: one ``vscalefpd`` per 8 lanes (fewer
    instructions than :func:`_pow2_bits`); elsewhere LLVM would call libm's ``ldexp`` lane by lane,
    and :func:`_pow2_bits` is inlined instead (the same value: both are exact)."""
    def codegen(context, builder, signature, args):
        if "+avx512f" not in getattr(context.codegen(), "_tm_features", "") or llvm.llvm_version_info < (17,):
            return context.compile_internal(builder, _pow2_bits, signature, args)
        i32 = ir.IntType(32)
        power = builder.trunc(context.compile_internal(builder, _clamped, types.int64(types.int64), args), i32)
        ldexp = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.DoubleType(), [ir.DoubleType(), i32]),
                                               "llvm.ldexp.f64.i32")
        return builder.call(ldexp, [ir.Constant(ir.DoubleType(), 1.0), power])
    return types.float64(types.int64), codegen


@_compiled
def _rescale(S: np.ndarray, E: np.ndarray, t: np.ndarray, scale: np.ndarray) -> None:
    """Scale every ``S`` (n, n, paths; lower triangular) by a power of two so that ``tr S S^T`` is in
    [1/2, 2) (below :data:`TINY_TRACE`: ``sum |S_ij|`` in [1/2, 1)), adding the (even) exponent taken
    out to ``E``; ``t`` receives the new trace, summed from the scaled entries."""
    n = S.shape[0]
    for p in range(LOOP_LANES):
        t[p] = 0.0
        scale[p] = 0.0
    for i in range(n):
        for j in range(i + 1):
            for p in range(LOOP_LANES):
                t[p] += S[i, j, p] * S[i, j, p]
                scale[p] += abs(S[i, j, p])
    for p in range(LOOP_LANES):
        # t = m 2^e with m in [1/2, 1): e from the exponent field (frexp's, without a call)
        e = ((_bits_of(t[p]) >> 52) & 2047) - 1022 if t[p] > 0.0 else 0
        e -= e & 1
        e = 2 * (((_bits_of(scale[p]) >> 52) & 2047) - 1022) if t[p] < TINY_TRACE and scale[p] > 0.0 else e
        E[p] += e
        scale[p] = _float_bits((1023 - e // 2) << 52)   # -e / 2 in [-512, 1022]: one power of two
        t[p] = 0.0
    for i in range(n):
        for j in range(i + 1):
            for p in range(LOOP_LANES):
                S[i, j, p] *= scale[p]
                t[p] += S[i, j, p] * S[i, j, p]


@_compiled
def _linear_scaled(t: float, e: int) -> float:
    """``t 2^e`` by two exact power-of-two factors (inf only beyond float64)."""
    half = e // 2
    return t * _pow2(half) * _pow2(e - half)


@_compiled
def _row(trace: np.ndarray, spare: np.ndarray, k: int, start: int, offset: int, paths: int) -> np.ndarray:
    """Where a lane loop writes step ``k``'s traces of the block at path ``start`` (``spare.size``
    lanes) of a run of ``paths`` paths: ``trace[k, offset + start + p]``, the row of step ``k``
    (one store per lane, at unit stride), or ``spare`` for a partial last block (:func:`_flush`
    copies what it holds) and for a step beyond ``trace``'s rows."""
    if k < trace.shape[0] and start + spare.size <= paths:
        return trace[k, offset + start:offset + start + spare.size]
    return spare


@_compiled
def _flush(trace: np.ndarray, spare: np.ndarray, k: int, start: int, offset: int, paths: int) -> None:
    """After step ``k``'s lane loop has written :func:`_row`: a partial last block's traces from
    ``spare`` into ``trace``'s row ``k``."""
    if k < trace.shape[0] and start + spare.size > paths:
        row = trace[k, offset + start:offset + paths]
        for p in range(row.size):
            row[p] = spare[p]


@_compiled
def _store(k: int, start: int, t: np.ndarray, E: np.ndarray, trace: np.ndarray, spare: np.ndarray,
           offset: int, paths: int, linear: bool) -> None:
    """Step ``k`` of the block at ``start``: ``trace[k, offset + start + p] = log t + E ln 2``
    (:func:`_log_scaled`), or with ``linear`` ``t 2^E`` (:func:`_linear_scaled`), for the steps
    ``trace`` has, in a lane loop of its own (:func:`_row`, :func:`_flush`)."""
    out = _row(trace, spare, k, start, offset, paths)
    if linear:
        for p in range(out.size):
            out[p] = _linear_scaled(t[p], E[p])
    else:
        for p in range(out.size):
            out[p] = _log_scaled(t[p], E[p])
    _flush(trace, spare, k, start, offset, paths)


@_compiled
def _receptions(received: np.ndarray, k: int, start: int, block: np.ndarray) -> bool:
    """``block[i, p] = received[k, start + p, i]``: step ``k``'s receptions of the block of paths at
    ``start``, sensor-major (a lane loop reads them at unit stride); paths past the last receive
    nothing (a partial last block needs no padded copy of the receptions).  Up to 8 sensors the
    copy is compiled once per sensor count (:func:`_transpose`); beyond, one strided pass per sensor.
    One sensor's receptions of a whole block are already a row at unit stride: then nothing is
    copied and the result is True: the kernels read them in place, from ``received`` reshaped to
    (horizon, paths) in their own body (a function returning the row instead lost the gain of not
    copying: docs/performance.md)."""
    d, width = block.shape
    count = min(width, received.shape[1] - start)
    if d == 1 and count == width:
        return True
    rows = received[k, start:start + count]
    if d <= 8:
        flat = rows.reshape(count * d)
        if d == 1:
            _transpose(flat, block, count, 1)
        elif d == 2:
            _transpose(flat, block, count, 2)
        elif d == 3:
            _transpose(flat, block, count, 3)
        elif d == 4:
            _transpose(flat, block, count, 4)
        elif d == 5:
            _transpose(flat, block, count, 5)
        elif d == 6:
            _transpose(flat, block, count, 6)
        elif d == 7:
            _transpose(flat, block, count, 7)
        else:
            _transpose(flat, block, count, 8)
    else:
        for i in range(d):
            into = block[i]
            column = rows[:, i]
            for p in range(count):
                into[p] = column[p]
    for i in range(d):
        into = block[i]
        for p in range(count, width):
            into[p] = False
    return False


@_compiled
def _transpose(flat: np.ndarray, block: np.ndarray, count: int, d: int) -> None:
    """``block[i, p] = flat[p d + i]`` for the first ``count`` paths.  Called with ``d`` a constant
    (:func:`_receptions`), it is inlined with it, and the compiler vectorises the copy as ``d``
    interleaved byte streams, several times as fast as a strided pass per sensor; beyond 8 it
    does not, and the strided passes are as fast (docs/performance.md)."""
    for p in range(count):
        for i in range(d):
            block[i, p] = flat[p * d + i]


check_public(globals())
