"""The compiled square-root filter kernel behind :func:`symkf.numeric.filters.log_traces`.

numba-compiled loops (``cache=True``: compiled once per installation, then
loaded from ``__pycache__``) over blocks of :func:`lanes` paths, the innermost loop
running across the paths of a block so that the compiler vectorises it (every
path does the same arithmetic; a lost row is an identity rotation, not a
branch).

Per path ``P_{k|k-1} = 2^E S S^T`` with an even integer ``E`` and ``tr(S S^T)``
brought into ``[1/2, 2)`` once it has left ``[2^-WINDOW, 2^WINDOW]``, so
``log tr P = E log 2 + log tr(S S^T)`` over any dynamic range; scaling by
powers of two is exact, and the kernels' bits do not depend on when it is done.
In these units the whitened measurement noise is ``2^-E`` and the process
noise ``2^-E Q``.

* Measurement update (Yang et al. eq. 8, rows independent with unit variance
  after whitening): Carlson's triangular form (N. A. Carlson, "Fast triangular
  formulation of the square root filter", AIAA Journal 11(9), 1973), reversed to
  a lower-triangular ``S`` and written as Givens rotations, one received row
  ``h`` at a time: ``f = S^T h``, ``s_n = 2^(-E/2)``, and for ``j = n-1..0``
  ``s_j = max(sqrt(2^-E + f_j^2 + ... + f_{n-1}^2), s_{j+1})``, ``c = s_{j+1} / s_j``,
  ``sn = f_j / s_j``, ``S_ij <- c S_ij - sn v_i`` and ``v_i <- c v_i + sn S_ij`` (``v``
  the later columns weighted by their ``f``): ``S S^T`` becomes ``P - P h h^T P / (|f|^2
  + 2^-E)`` and ``S`` stays lower triangular, one square root and one division per
  column.  The square roots of the running sums, never of their products (whose
  product form ``sqrt(s_{j+1}^2 s_j^2)`` underflows); the ``max`` keeps a column whose
  noise and ``f`` underflow to 0 from being zeroed for ever.  A lost row is a rotation
  by ``c = 1``, ``sn = 0``, not a branch.  Unlike Potter's full update, the
  triangular one collapses an observed direction exactly: on a badly
  conditioned path its ``log tr P`` stays with a high-precision reference where
  Potter's drifted off by tens (``test_square_root``), though beyond float64's
  resolution neither is reliable (see below; docs/performance.md).
* Time update (Sui-You-Fu eq. 9, ``P <- A P A^T + Q``): Householder
  triangularisation (Golub and Van Loan, Matrix Computations, section 5.2.1) of
  the stacked ``[(A S)^T; 2^(-E/2) U_Q]`` (``U_Q`` upper triangular,
  ``U_Q^T U_Q = Q``), giving a lower-triangular ``S`` with the same ``S S^T``.  The
  kernel takes ``A`` lower Hessenberg (:mod:`symkf.numeric.filters` writes a dense ``A``
  in an orthonormal basis, in reversed order, that makes it so; ``tr P`` does not
  change): ``A S`` is lower Hessenberg, so column ``c``'s reflector spans rows ``c``,
  ``c + 1`` and ``U_Q``'s rows ``0..c`` (``c + 3`` of them, against ``n + 1`` for a
  full ``S``), and the zeros of ``A`` and ``S`` are skipped in ``A S``.  Each reflector
  ``v = x + sign(x_0) |x| e_1`` stays unnormalised and is applied as ``y - (v^T y) v /
  (|x| (|x| + |x_0|))`` (``|v|^2 = 2 |x| (|x| + |x_0|)``): one square root per column and
  one division per applied column.

The divider (division and square root share it) bounds the kernel at small
``n``: these forms need ``rows n + n - 1`` divisions and ``rows n + n`` square
roots per path-step, where Potter's full update needed one of each per row: up to
n = 4, where the reflectors are hardly shorter, this kernel is the slower
(0.69-0.90x at n = 2; docs/performance.md).  Below 2^-1022 a denominator
is dropped (its reciprocal could overflow); what it would remove is below
2^-511 of ``S``'s scale.

``P`` stays positive semidefinite by construction, and errors in its small
directions are ``~1e-16 ||S||``, i.e. ``1e-32 ||P||`` after squaring: once a
path's scales are 1e32 apart (``log tr P`` beyond ~75 on a well-observed
system) the float filter no longer resolves its small directions, whatever
the rounding (``benchmarks/float_resolution.py`` measures where on
``ge-two-sensors`` and ``ge-recovery.toml``).  Float-exact systems
(``A = 2 R(pi/2)``) keep their exact cancellations over thousands of steps
(tests in ``test_filtering``); FMA contraction would break them (a fused
``c S_ij - sn v_i`` does not cancel to the same rounding as the product it
subtracts), so none is used.
This module imports numba; :mod:`symkf.numeric.filters` imports it only when a
simulation runs, so ``import symkf`` and the exact engine never pay for it.
"""

from __future__ import annotations

import functools
import hashlib
import math
import numbers
import re
from pathlib import Path

import numpy as np
from numba import cfunc, njit, types
from numba.extending import intrinsic

from .. import budget
from ..arguments import check_public
from ..errors import ShapeError
from ..run.progress import compiling
from .kernel_parts import (BIG, LOOP_LANES, NORMAL, OPTIONS, ROOT_MAX, _aligned, _aligned_int, _pow2, _receptions,
                           _rescale, _store)

#: the first 16 hex digits of the SHA-256 of symkf/numeric/kernel_parts.py, whose pieces this module's
#: kernels inline (:func:`_jit`; a test compares)
KERNEL_PARTS = "2c4a229dea463059"


def _inlined_digest() -> str | None:
    """The first 16 hex digits of the SHA-256 of :mod:`symkf.numeric.kernel_parts`' source (None where
    the source cannot be read)."""
    try:
        source = (Path(__file__).parent / "kernel_parts.py").read_text(encoding="utf-8")
    except OSError:
        return None
    return hashlib.sha256(source.encode()).hexdigest()[:16]


_PARTS = _inlined_digest()


def _jit(recorded: str, signature=None):
    """numba's compiler with the kernels' options (:data:`~symkf.numeric.kernel_parts.OPTIONS`;
    a ``cfunc`` of ``signature`` if given), its on-disk cache on only while ``recorded``, the digest of
    :mod:`symkf.numeric.kernel_parts` that the module of the compiled function records, is that
    file's.  numba keys a cached kernel on the time stamp of the file that defines it alone, not on
    those of the functions it inlines: an edit of kernel_parts.py would leave a stale kernel in the
    cache.  The digest recorded in the kernel's own file (:data:`KERNEL_PARTS`, the generated
    modules' ``INLINED``) ties the two: brought up to date, it changes that file's stamp; until it is,
    the kernels compile afresh in every process."""
    cache = recorded == _PARTS
    return njit(cache=cache, **OPTIONS) if signature is None else cfunc(signature, cache=cache, **OPTIONS)

#: paths per block of the straight-line kernels, a compile-time constant: the path loops have a
#: fixed trip count (no remainder loops, no per-entry set-up).  Up to SMALL_MAX states a lane loop's
#: set-up (the compiler's run-time checks that its arrays do not overlap) weighs on its few operations,
#: so the blocks widen as n falls: SMALL_LANES up to SMALL_MAX, TINY_LANES up to TINY_MAX, LANES above,
#: where a wider block is slower, and NARROW_LANES from NARROW_MIN on, where a block's S (n^2 lanes
#: of 8 bytes: 32 KiB at n = 8 and 64 lanes, the whole L1 data cache) leaves no room in the L1
#: cache for the time update's spilled entries.  At n = 2 each step's long lane loops (Carlson's,
#: the time update's) also fill and drain the core's window of overlapping paths, which a wide block
#: spreads over more paths.  Each width is the fastest measured for its range of n
#: (docs/performance.md, benchmarks/bench_kernel.py).  A run of fewer paths still computes a whole block
LANES = 64
NARROW_LANES = 32
NARROW_MIN = 8
SMALL_LANES = 128
SMALL_MAX = 4
TINY_LANES = 2048
TINY_MAX = 2
def lanes(n: int) -> int:
    """Paths per block of the kernel for ``n`` states."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise ShapeError(f"n: expected a positive number of states, got {n!r}")
    if n <= TINY_MAX:
        return TINY_LANES
    if n <= SMALL_MAX:
        return SMALL_LANES
    if n < NARROW_MIN:
        return LANES
    return NARROW_LANES if n <= STRAIGHT_MAX else LOOP_LANES


def log_trace_paths(A: np.ndarray, UQ: np.ndarray, H: np.ndarray, row_sensor: np.ndarray,
                    S0: np.ndarray, received: np.ndarray, trace: np.ndarray, linear: bool = False,
                    offset: int = 0) -> None:
    """``trace[k, offset + p] = log tr P_{k|k-1}`` (k = 0..horizon) for receptions ``received[k, p, i]``
    (sensor ``i``), ``A`` lower Hessenberg, from ``P_0 = S0 S0^T`` (``S0`` lower triangular), in blocks of :func:`lanes`
    ``(n)`` paths (a partial last block included).
    ``linear``: ``tr P_{k|k-1}`` itself, k = 0..horizon-1.  ``trace`` is C-contiguous float64 with a
    row per step (``horizon + 1`` rows, or ``horizon`` with ``linear``) and at least ``offset + paths``
    columns: the kernel writes each step's traces of a block of paths in place, at unit stride
    (``trace.T`` is the (paths, steps) array in Fortran order).  By :func:`_kernel` ``(n)``."""
    n = A.shape[0]
    if np.ndim(received) != 3:
        raise ShapeError(f"received: expected (horizon, paths, sensors), got shape {np.shape(received)}")
    horizon, paths, _ = received.shape
    if np.any(np.triu(A, 2)):   # the time update's short reflectors rely on A S lower Hessenberg
        raise ShapeError("A: the kernel takes A lower Hessenberg (symkf.numeric.filters's kernel arguments make it so)")
    if np.ndim(S0) == 2 and np.any(np.triu(S0, 1)):   # the kernels keep S lower triangular and read no other entry
        raise ShapeError("S0: the kernel takes S0 lower triangular (symkf.numeric.filters's kernel arguments make it so)")
    # the compiled loops do not check bounds
    steps = horizon if linear else horizon + 1
    if isinstance(offset, bool) or not isinstance(offset, numbers.Integral) or offset < 0:
        raise ShapeError(f"offset: expected a column (an integer >= 0), got {offset!r}")
    if (not isinstance(trace, np.ndarray) or trace.ndim != 2 or trace.dtype != np.float64
            or not trace.flags.c_contiguous or not trace.flags.writeable
            or trace.shape[0] != steps or trace.shape[1] < offset + paths):
        raise ShapeError(f"{'traces' if linear else 'log traces'}: expected a writeable C-contiguous float64 array "
                         f"of {steps} rows and at least {offset + paths} columns, got "
                         f"{getattr(trace, 'shape', None)} {getattr(trace, 'dtype', type(trace).__name__)}")
    shapes = {"A": np.shape(A), "UQ": np.shape(UQ), "S0": np.shape(S0), "H": np.shape(H), "row_sensor": np.shape(row_sensor)}
    if len({shapes[k] for k in ("A", "UQ", "S0")}) > 1 or shapes["A"] != (n, n) or shapes["H"] != (len(row_sensor), n):
        raise ShapeError("A, UQ, S0 (n x n), H (rows x n) and row_sensor (rows) disagree: "
                         + ", ".join(f"{k} {v}" for k, v in shapes.items()))
    if len(row_sensor) and not 0 <= min(row_sensor) <= max(row_sensor) < received.shape[2]:
        raise ShapeError(f"row_sensor: sensors 0..{received.shape[2] - 1} (the receptions' last axis), got "
                         f"{min(row_sensor)}..{max(row_sensor)}")
    kernel = _kernel(n)
    if n not in _READY:   # compiled (or loaded from numba's cache) on a path of one step first, with a notice
        warm(n)
    # bool in C order: a step's receptions are one flat row per block (_receptions), one sensor's read in place
    kernel(A, UQ, H, row_sensor, S0, np.ascontiguousarray(received, bool), trace, int(offset), linear)


#: state dimensions whose kernel this process has compiled or loaded
_READY: set[int] = set()


def warm(n: int, *, enabled: bool | None = None) -> None:
    """Compile (or load from numba's cache) the kernel of ``n`` states on one path of one step,
    saying so on stderr when that takes more than a second (:func:`symkf.run.progress.compiling`)."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ShapeError(f"n: expected a positive number of states, got {n!r}")
    budget.check("max_memory", 8 * 4 * n * n, "n", f"the bytes of the {n}-state kernel's matrices")
    A, S0 = np.eye(n), np.eye(n)
    H, row_sensor = np.ones((1, n)), np.zeros(1, dtype=np.int64)
    received = np.ones((1, 1, 1), dtype=bool)
    with compiling(f"the {n}-state filter kernel", enabled=enabled):
        for linear in (False, True):
            trace = np.empty((1, 1)) if linear else np.empty((2, 1))
            _kernel(n)(A, np.eye(n), H, row_sensor, S0, received, trace, 0, linear)
    _READY.add(n)


def _kernel(n: int):
    """The compiled kernel for ``n`` states: :func:`_straight` up to :data:`STRAIGHT_MAX`, beyond
    :func:`_loop_kernel`."""
    return _straight(n) if n <= STRAIGHT_MAX else _loop_kernel(n)


def _loop_kernel(n: int):
    """:func:`_loops` with the unrolled kernels of ``n`` states (:func:`_unrolled`)."""
    return functools.partial(_loops, householder=_unrolled("householder", n), carlson=_unrolled("carlson", n))


@_jit(KERNEL_PARTS)
def _loops(A: np.ndarray, UQ: np.ndarray, H: np.ndarray, row_sensor: np.ndarray,
           S0: np.ndarray, received: np.ndarray, trace: np.ndarray, offset: int,
           linear: bool, householder, carlson) -> None:
    """:func:`log_trace_paths` for any ``n``: loops over the entries, the lane loop innermost, and
    the kernels of :func:`_unrolled` for the time update's triangularisation (``householder``) and
    Carlson's triangular update of ``S`` by its rotations (``carlson``)."""
    horizon, paths, d = received.shape
    n = A.shape[0]
    rows = H.shape[0]
    # rows an odd number of lane slots (of 512 bytes) apart: at n = 16 a column's 17 rows would be
    # 8 KiB apart, all in the same 8 of the L1 cache's 64 sets (12 ways); padded, they spread over all
    cols = n | 1
    S = _aligned((n, cols, LOOP_LANES))
    X = _aligned((2 * n, cols, LOOP_LANES))
    V = _aligned(((n + 3) * LOOP_LANES,))
    cs = _aligned((2 * n + 1, LOOP_LANES))   # Carlson's f, then c (rows 0..n-1), sn (n..2n-1), a row of scratch
    alpha = _aligned((LOOP_LANES,))
    sprev = _aligned((LOOP_LANES,))
    noise = _aligned((LOOP_LANES,))
    half = _aligned((LOOP_LANES,))
    E = _aligned_int((LOOP_LANES,))
    t = _aligned((LOOP_LANES,))
    spare = _aligned((LOOP_LANES,))
    block = np.empty((d, LOOP_LANES), np.bool_)
    lone = received.reshape(horizon, paths * d)   # one sensor: a step's receptions in a row (_receptions)
    for start in range(0, paths, LOOP_LANES):
        for i in range(n):
            for j in range(n):
                for p in range(LOOP_LANES):
                    S[i, j, p] = S0[i, j]
        for p in range(LOOP_LANES):
            E[p] = 0
        _rescale(S, E, t, alpha)
        for k in range(horizon + 1):
            _store(k, start, t, E, trace, spare, offset, paths, linear)
            if k == horizon:
                break
            direct = _receptions(received, k, start, block)
            for p in range(LOOP_LANES):
                half[p] = _pow2(min(-(E[p] // 2), ROOT_MAX))
                noise[p] = half[p] * half[p]
            for r in range(rows):                   # Carlson, one whitened row at a time
                got = lone[k, start:start + LOOP_LANES] if direct else block[row_sensor[r]]
                for j in range(n):                  # f = S^T h, S lower triangular
                    for p in range(LOOP_LANES):
                        cs[j, p] = 0.0
                    for i in range(j, n):
                        if H[r, i] != 0.0:          # integer sensor rows are often sparse
                            for p in range(LOOP_LANES):
                                cs[j, p] += S[i, j, p] * H[r, i]
                for p in range(LOOP_LANES):
                    alpha[p] = noise[p]
                    sprev[p] = half[p]
                for j in range(n - 1, -1, -1):      # each column's rotation (as _straight_source)
                    for p in range(LOOP_LANES):
                        f = cs[j, p]
                        a = alpha[p] + f * f
                        alpha[p] = a
                        sq = max(math.sqrt(a), sprev[p])
                        ok = got[p] and sq >= NORMAL and sq <= BIG
                        inv = 1.0 / sq if ok else 0.0
                        cs[j, p] = sprev[p] * inv if ok else 1.0
                        cs[n + j, p] = f * inv
                        sprev[p] = sq
                carlson(_data(S), _data(cs), n)
            _time_update(S, A, UQ, E, X, V, half, householder, t)
            bits = t.view(np.int64)   # a trace's bits order as it does (it is not negative; nan above all)
            top, bottom = 0, WINDOW_BITS[1]
            for p in range(LOOP_LANES):
                top = max(top, bits[p])
                bottom = min(bottom, bits[p])
            if top > WINDOW_BITS[1] or bottom < WINDOW_BITS[0]:
                _rescale(S, E, t, alpha)


@_jit(KERNEL_PARTS)
def _time_update(S: np.ndarray, A: np.ndarray, UQ: np.ndarray, E: np.ndarray, X: np.ndarray,
                 V: np.ndarray, beta: np.ndarray, householder, t: np.ndarray) -> None:
    """``S <- R^T`` with ``R^T R = X^T X``, ``X = [(A S)^T; 2^(-E/2) U_Q]`` (Householder QR by
    ``householder``, :func:`_unrolled` ``("householder", n)``, its reflectors in ``V``; ``beta`` holds
    2^(-E/2)), and ``t`` the new ``tr S S^T``, summed as :func:`~symkf.numeric.kernel_parts._rescale`
    sums it while ``R`` is written back (one pass over ``S`` where a rescale at every step took
    three).  ``A`` lower Hessenberg and ``S`` lower triangular: ``(A S)^T`` is upper Hessenberg, and
    only those entries of ``X``'s top block are written (the reflectors read no other)."""
    n = A.shape[0]
    for i in range(n):           # X[j, i] = (A S)[i, j] = sum_l A[i, l] S[l, j], l = j..min(i + 1, n - 1)
        for j in range(min(i + 2, n)):
            for p in range(LOOP_LANES):
                X[j, i, p] = 0.0
            for l in range(j, min(i + 2, n)):
                if A[i, l] != 0.0:                  # block-diagonal A: skip its zero blocks
                    for p in range(LOOP_LANES):
                        X[j, i, p] += A[i, l] * S[l, j, p]
    # U_Q's upper triangle: row n + i left of column i is never read (the reflector of column c spans
    # U_Q's rows 0..c only: _reflector_rows)
    for i in range(n):
        for j in range(i, n):
            for p in range(LOOP_LANES):
                X[n + i, j, p] = beta[p] * UQ[i, j]
    householder(_data(X), _data(V), n)
    for p in range(LOOP_LANES):
        t[p] = 0.0
    for i in range(n):
        for j in range(i + 1):
            for p in range(LOOP_LANES):
                x = X[j, i, p]
                S[i, j, p] = x
                t[p] += x * x


#: the signature of the unrolled kernels (:func:`_unrolled`): pointers to the array they update and
#: to their vectors, and n.  Householder: ``X`` (2n, n | 1, LOOP_LANES) and ``V`` (n + 3,
#: LOOP_LANES: the reflector's up to n + 1 rows, two of scratch); Carlson: ``S`` (n, n | 1, LOOP_LANES)
#: and ``cs`` (2n + 1, LOOP_LANES: the rotations' c in n rows, their sn in n, one row of scratch)
ROW_KERNEL = types.void(types.CPointer(types.float64), types.CPointer(types.float64), types.int64)
#: largest n whose kernels are written out in :mod:`symkf.numeric.unrolled_kernels`; beyond, the loops
#: :func:`_householder_loops` and :func:`_carlson_loops` (numba compiles no source made at run
#: time: symkf runs no exec).  The Householder kernel is written out column by column (its reflectors'
#: lengths differ: :func:`_reflector_rows`), 2.8x as fast as the loops at n = 16 but 5.4 CPU-s to
#: compile there; the Carlson kernel row by row (docs/performance.md)
UNROLLED_MAX = {"householder": 16, "carlson": 16}


@intrinsic
def _data(typingctx, array):
    """The data pointer of a C-contiguous ``array``."""
    def codegen(context, builder, signature, args):
        return context.make_array(array)(context, builder, args[0]).data
    return types.CPointer(array.dtype)(array), codegen


def _reflector_offsets(j: int, n: int) -> list:
    """The offsets in the flat ``X`` (``2n`` rows of ``n | 1`` columns of LOOP_LANES) of column
    ``j``'s entries of the rows its reflector spans (:func:`_reflector_rows`), in that order."""
    L, st = LOOP_LANES, (n | 1) * LOOP_LANES
    return [row * st + j * L for row in _reflector_rows(j, n)]


@_jit(KERNEL_PARTS)
def _reflector_row(r: int, c: int, n: int) -> int:
    """The row of the time update's ``X`` (``2n`` rows: ``(A S)^T`` upper Hessenberg over
    ``2^(-E/2) U_Q``) of the ``r``-th row that column ``c``'s Householder reflector spans, in the
    order the kernels sum them: the pivot row ``c``, row ``c + 1`` (the subdiagonal of ``A S``;
    none at the last column) and ``U_Q``'s rows ``n..n + c`` (row ``n + i`` is zero left of column
    ``i``, and a reflection leaves a row with a zero pivot-column entry alone): ``c + 3`` rows,
    ``n + 1`` at the last column."""
    top = 2 if c < n - 1 else 1
    return c + r if r < top else n + r - top


def _householder_loops(X, V, n):
    """The operations of :func:`_householder_source` ``(n)`` in its order, for any ``n``, as loops
    over the rows (its sums through the scratch rows of ``V``: a test compares every bit)."""
    L, st = LOOP_LANES, (n | 1) * LOOP_LANES
    beta, acc = (n + 1) * L, (n + 2) * L
    for j in range(n):
        m = j + 3 if j < n - 1 else j + 2     # the reflector's rows (_reflector_row)
        b = j * (st + L)
        for p in range(L):
            V[acc + p] = 0.0
        for r in range(m):
            o = _reflector_row(r, j, n) * st + j * L
            for p in range(L):
                V[acc + p] += X[o + p] * X[o + p]
        for p in range(L):
            norm = math.sqrt(V[acc + p])
            x0 = X[b + p]
            head = norm if x0 >= 0.0 else -norm
            half_v2 = norm * (norm + abs(x0))
            V[beta + p] = 1.0 / half_v2 if half_v2 >= NORMAL else 0.0
            V[p] = x0 + head
            X[b + p] = -head
        for r in range(1, m):
            o = _reflector_row(r, j, n) * st + j * L
            for p in range(L):
                V[r * L + p] = X[o + p]
        for k in range(j + 1, n):
            for p in range(L):
                V[acc + p] = 0.0
            for r in range(m):
                o = _reflector_row(r, j, n) * st + k * L
                for p in range(L):
                    V[acc + p] += V[r * L + p] * X[o + p]
            for r in range(m):
                o = _reflector_row(r, j, n) * st + k * L
                for p in range(L):
                    X[o + p] -= V[beta + p] * V[acc + p] * V[r * L + p]


def _carlson_loops(S, cs, n):
    """The operations of :func:`_carlson_source` ``(n)`` in its order, for any ``n``, as loops over the
    entries, four columns per lane loop (``v`` in a register across them, through the scratch row
    of ``cs`` between lane loops: a test compares every bit)."""
    L, st = LOOP_LANES, (n | 1) * LOOP_LANES
    v = 2 * n * L
    for i in range(n):
        b = i * st
        for p in range(L):
            s = S[b + i * L + p]
            S[b + i * L + p] = cs[i * L + p] * s
            cs[v + p] = cs[(n + i) * L + p] * s
        j = i - 1
        while j >= 3:
            for p in range(L):
                x = cs[v + p]
                for k in range(j, j - 4, -1):
                    s = S[b + k * L + p]
                    S[b + k * L + p] = cs[k * L + p] * s - cs[(n + k) * L + p] * x
                    x = cs[k * L + p] * x + cs[(n + k) * L + p] * s
                cs[v + p] = x
            j -= 4
        for k in range(j, -1, -1):
            for p in range(L):
                s = S[b + k * L + p]
                S[b + k * L + p] = cs[k * L + p] * s - cs[(n + k) * L + p] * cs[v + p]
                cs[v + p] = cs[k * L + p] * cs[v + p] + cs[(n + k) * L + p] * s


def _carlson_source(n: int) -> str:
    """Source of ``_carlson_{n}``: Carlson's triangular measurement update (N. A. Carlson, "Fast
    triangular formulation of the square root filter", AIAA Journal 11(9), 1973, in Givens form:
    the module's text) of a lower-triangular ``S`` by the rotations ``c_j``, ``sn_j`` of its columns,
    row ``i`` in one lane loop: ``S_ij <- c_j S_ij - sn_j v`` and ``v <- c_j v + sn_j S_ij`` from
    column ``i`` (``v = sn_i S_ii``) down to 0, ``v`` in a register (each row's ``v`` depends on that
    row alone), every entry at a constant offset."""
    L, st = LOOP_LANES, (n | 1) * LOOP_LANES
    w = [f"def _carlson_{n}(S, cs, n):"]
    for i in range(n):
        w.append(f"    for p in range({L}):")
        w.append(f"        s = S[{i * st + i * L} + p]")
        w.append(f"        S[{i * st + i * L} + p] = cs[{i * L} + p] * s")
        w.append(f"        v = cs[{(n + i) * L} + p] * s")
        for j in range(i - 1, -1, -1):
            w.append(f"        s = S[{i * st + j * L} + p]")
            w.append(f"        S[{i * st + j * L} + p] = cs[{j * L} + p] * s - cs[{(n + j) * L} + p] * v")
            if j:   # column 0's v is never read
                w.append(f"        v = cs[{j * L} + p] * v + cs[{(n + j) * L} + p] * s")
    return "\n".join(w) + "\n"


def _householder_source(n: int) -> str:
    """Source of ``_householder_{n}``: the Householder triangularisation (Golub and Van Loan, Matrix
    Computations, section 5.2.1) of ``_time_update``'s ``X`` for ``n`` states, column ``j`` in one
    lane loop (norm, pivot, reflector ``v`` into ``V``; only row ``j`` of ``X`` is read afterwards)
    and its reflection of each later column ``k`` in one (``v^T x`` and ``x - 2 (v^T x) v`` over the
    reflector's rows, written out: the sum stays in a register).  Column ``j``'s reflector spans rows
    ``j``, ``j + 1`` and ``n..n + j`` (:func:`_reflector_rows`: ``(A S)^T`` is upper Hessenberg, and
    the rows below stay zero in the columns from ``j`` on): each column is written out apart."""
    L = LOOP_LANES
    w = [f"def _householder_{n}(X, V, n):"]
    a = w.append
    for j in range(n):
        rows = _reflector_offsets(j, n)
        v = [f"V[{r * L} + p]" if r else "V[p]" for r in range(len(rows))]
        a(f"    for p in range({L}):")
        w.extend(f"        x{r} = X[{o} + p]" for r, o in enumerate(rows))
        a("        sq = 0.0")
        w.extend(f"        sq += x{r} * x{r}" for r in range(len(rows)))
        a("        norm = math.sqrt(sq)")
        a("        head = norm if x0 >= 0.0 else -norm")
        # v = x + sign(x0) |x| e_1 unnormalised, 2 / |v|^2 = 1 / (|x| (|x| + |x0|)): one division and
        # no second square root per column; below the normal range the reflection is dropped (tau = 0)
        a("        half_v2 = norm * (norm + abs(x0))")
        a(f"        V[{(n + 1) * L} + p] = 1.0 / half_v2 if half_v2 >= NORMAL else 0.0")
        a("        x0 = x0 + head")
        w.extend(f"        {v[r]} = x{r}" for r in range(len(rows)))
        a(f"        X[{rows[0]} + p] = -head")
        if j == n - 1:   # the last column's reflector is never applied
            continue
        a(f"    for k in range({j + 1}, {n}):")
        a(f"        c = (k - {j}) * {L}")
        a(f"        for p in range({L}):")
        w.extend(f"            y{r} = X[c + {o} + p]" for r, o in enumerate(rows))
        a("            dot = 0.0")
        w.extend(f"            dot += {v[r]} * y{r}" for r in range(len(rows)))
        a(f"            twice = V[{(n + 1) * L} + p] * dot")
        w.extend(f"            X[c + {o} + p] = y{r} - twice * {v[r]}" for r, o in enumerate(rows))
    return "\n".join(w) + "\n"


#: each unrolled kernel's generator and its loops for any n
_UNROLLED = {"householder": (_householder_source, _householder_loops), "carlson": (_carlson_source, _carlson_loops)}


def _unrolled_module() -> str:
    """The text of :mod:`symkf.numeric.unrolled_kernels`: :func:`_householder_source` and
    :func:`_carlson_source` for n = 1.. :data:`UNROLLED_MAX` (regenerate it after changing a template:
    ``python -c "from symkf.numeric.square_root import _unrolled_module as m; print(m(), end='')" >
    symkf/numeric/unrolled_kernels.py``; a test compares)."""
    sizes = " and ".join(f"{kind} for n = 1..{top}" for kind, top in UNROLLED_MAX.items())
    head = ('"""The loop filter kernel\'s Householder time update and Carlson update (:func:`symkf.numeric.square_root._loops`),\n'
            f'each row\'s entries written out, the lane loop innermost ({sizes} states): generated by\n'
            ':func:`symkf.numeric.square_root._unrolled_module` (do not edit; a test compares it with the generator)."""\n\n'
            "import math\n\n"
            "from ..arguments import check_public\n"
            "from .kernel_parts import NORMAL\n\n"
            "#: SHA-256 (its first 16 hex digits) of symkf/numeric/kernel_parts.py, whose constants these kernels inline\n"
            "#: (symkf.numeric.square_root._jit)\n"
            "INLINED = \"%s\"\n\n\n" % _inlined_digest())
    sources = (_UNROLLED[kind][0](n) for n in range(1, max(UNROLLED_MAX.values()) + 1)
               for kind in UNROLLED_MAX if n <= UNROLLED_MAX[kind])
    return head + "\n\n".join(sources) + "\n\ncheck_public(globals())\n"


@functools.lru_cache(maxsize=None)
def _row_loops(kind: str):
    """``_{kind}_loops`` compiled (one ``cfunc`` for every ``n``)."""
    return _jit(KERNEL_PARTS, ROW_KERNEL)(_UNROLLED[kind][1])


@functools.lru_cache(maxsize=None)
def _unrolled(kind: str, n: int):
    """The compiled ``kind`` (``"householder"`` or ``"carlson"``) kernel for ``n`` states (a numba
    ``cfunc``: the loop kernel is compiled once for its type, whatever ``n``); from
    :mod:`symkf.numeric.unrolled_kernels` up to :data:`UNROLLED_MAX` ``[kind]``, compiled on first use once per
    installation (numba's cache), beyond :func:`_row_loops`."""
    if n > UNROLLED_MAX[kind]:
        return _row_loops(kind)
    from . import unrolled_kernels
    return _jit(unrolled_kernels.INLINED, ROW_KERNEL)(getattr(unrolled_kernels, f"_{kind}_{n}"))


#: largest state dimension with a straight-line kernel (compile time and code size grow like n^3)
STRAIGHT_MAX = 8
#: up to this n the straight-line kernel takes each step's traces in the time update's last lane loop,
#: written twice (for the logs and for the traces themselves); beyond, in a lane loop of their own
#: (docs/performance.md)
TRACED_MAX = 5
#: the kernels rescale ``S`` only when a path's ``tr S S^T`` has left [2^-WINDOW, 2^WINDOW]; the time
#: update's lane loop (up to TRACED_MAX; beyond STRAIGHT_MAX the loop kernel's write-back of
#: ``R^T``), or in between a lane loop of its own, takes the step's trace (for the logs it writes
#: anyway) and its range over the block.  Scaling by a power of two is exact, so the bits do
#: not depend on when it scales (short of the float range: within the window ``|S| <= 2^(WINDOW/2)``,
#: and a step overflows, underflows or drops a denominator below NORMAL only where one from
#: ``tr S S^T = 1`` would come within 2^WINDOW of doing so).  So on most steps the rescale's own
#: lane loop over ``S`` is skipped (on bench_kernel's systems it runs once per block;
#: docs/performance.md)
WINDOW = 32
#: the bits of 2^-WINDOW and 2^WINDOW (a trace's bits order as it does: it is not negative)
WINDOW_BITS = (1023 - WINDOW) << 52, (1023 + WINDOW) << 52
#: from PHASED_MIN to PHASED_MAX states the straight-line kernel runs its time update one lane loop per
#: Householder column (the live entries of ``X`` through memory between them): shorter chains of
#: dependent square roots and divisions per loop, so the core overlaps more paths; from n = 6 the
#: live entries' loads and stores cost more than the overlap gains (docs/performance.md)
PHASED_MIN = 2
PHASED_MAX = 5


def _sum(target: str, terms: list[str], indent: str) -> list[str]:
    """Source lines summing ``terms`` into ``target`` left to right from the first term.  Not from
    ``0.0``: without fast-math the compiler must keep that addition (it turns a sum of -0.0 into
    +0.0), one more vector operation per sum and path."""
    return [f"{indent}{target} = {terms[0]}"] + [f"{indent}{target} += {term}" for term in terms[1:]]


def _live(X: dict, c: int, n: int) -> list:
    """The entries of the time update's ``X`` that the steps from column ``c`` on read: columns
    ``c..``, of the rows ``c..n-1`` of ``(A S)^T`` and ``U_Q``'s rows ``n..n+c-1`` (row ``n + c``
    has not entered yet)."""
    return sorted(key for key in X if key[1] >= c and (c <= key[0] < n or n <= key[0] < n + c))


def _reflector_rows(c: int, n: int) -> list:
    """The rows of the time update's ``X`` that column ``c``'s reflector spans, in order
    (:func:`_reflector_row`, as the loops read them)."""
    return [_reflector_row.py_func(r, c, n) for r in range(c + 3 if c < n - 1 else c + 2)]


def _straight_source(n: int) -> str:
    """Source of ``_paths_{n}``: log_trace_paths for n states, every per-path operation of one
    step written out (the same operations in the same order as the loops of
    log_trace_paths / _time_update / _rescale and the unrolled kernels, but that its sums start
    from their first term where the loops add it to 0.0 and skip zero entries of ``H`` and ``A``:
    only a zero sum's sign can differ, and no trace sees it), the lane loop innermost.  ``S`` is
    lower triangular throughout: only its lower triangle is read or written."""
    L = []
    w = L.append
    R = range(n)
    W = lanes(n)
    lower = [(i, j) for i in R for j in range(i + 1)]

    def load_S(indent: str) -> None:   # the lane's S (its lower triangle) into locals s{i}_{j}
        for i, j in lower:
            w(f"{indent}s{i}_{j} = S[{i}, {j}, p]")
    w(f"def _paths_{n}(A, UQ, H, row_sensor, S0, received, trace, offset, linear):")
    w("    horizon, paths, d = received.shape")
    w(f"    block = np.empty((d, {W}), np.bool_)")   # a step's receptions of the block, sensor-major
    w("    lone = received.reshape(horizon, paths * d)")   # one sensor: a step's receptions in a row
    w("    rows = H.shape[0]")
    w(f"    S = _aligned(({n}, {n}, {W}))")
    w(f"    t = _aligned(({W},))")
    w(f"    E = _aligned_int(({W},))")
    w(f"    noise = _aligned(({W},))")
    w(f"    half = _aligned(({W},))")
    w(f"    spare = _aligned(({W},))")   # a partial last block's traces, or a step beyond trace's (_row)
    if PHASED_MIN <= n <= PHASED_MAX:   # the time update's live entries between its lane loops
        w(f"    X = _aligned(({2 * n}, {n}, {W}))")
    for i in R:                          # A lower Hessenberg (log_trace_paths)
        for l in range(min(i + 2, n)):
            w(f"    a{i}_{l} = A[{i}, {l}]")
    for i in R:
        for j in range(i, n):
            w(f"    q{i}_{j} = UQ[{i}, {j}]")
    w(f"    for start in range(0, paths, {W}):")
    w(f"        for p in range({W}):")
    w("            E[p] = 0")
    for i, j in lower:
        w(f"            S[{i}, {j}, p] = S0[{i}, {j}]")
    # the rescale runs only when a trace has left the window: up to TRACED_MAX the time update's lane
    # loop takes the traces (below), beyond a lane loop of their own at the start of each step
    traced = n <= TRACED_MAX
    trace_terms = [f"S[{i}, {j}, p] * S[{i}, {j}, p]" for i, j in lower]
    if traced:
        w("        wide = True")
    w("        for k in range(horizon + 1):")
    # --- rescale (as _rescale) and the trace of step k
    if traced:
        w("            if wide:")
    else:
        w("            top = 0")
        w(f"            bottom = {WINDOW_BITS[1]:#x}")
        w(f"            for p in range({W}):")
        L += _sum("tp", trace_terms, " " * 16)
        w("                t[p] = tp")
        w("                bt = _bits_of(tp)")   # t >= 0 orders as its bits; nan above every bound
        w("                top = max(top, bt)")
        w("                bottom = min(bottom, bt)")
        w(f"            if k == 0 or top > {WINDOW_BITS[1]:#x} or bottom < {WINDOW_BITS[0]:#x}:")
    body = " " * 20
    w(f"{body[:-4]}for p in range({W}):")
    L += _sum("tp", trace_terms, body)
    w(f"{body}e = ((_bits_of(tp) >> 52) & 2047) - 1022 if tp > 0.0 else 0")
    w(f"{body}e -= e & 1")
    # an S whose entries are all below 2^-537 has squares that underflow (Carlson's update collapses
    # an observed direction exactly): then the scale brings sum |S_ij| into [1/2, 1) (kernel_parts's
    # TINY_TRACE), and the trace is summed again from the scaled entries (tp times the square of the
    # scale, to the bit, wherever nothing underflows)
    L += _sum("ta", [f"abs(S[{i}, {j}, p])" for i, j in lower], body)
    w(f"{body}e = 2 * (((_bits_of(ta) >> 52) & 2047) - 1022) if tp < TINY_TRACE and ta > 0.0 else e")
    w(f"{body}Ep = E[p] + e")
    w(f"{body}E[p] = Ep")
    # e and E are even: 2^-e and 2^-E are squares of the halves, exactly (a power of two squares to
    # itself, or rounds to 0 or inf where 2^-E does), so two powers of two do for the three; -e / 2
    # is in [-512, 1022]: one power of two, from its exponent bits (as _rescale)
    w(f"{body}scale = _float_bits((1023 - e // 2) << 52)")
    for i, j in lower:
        w(f"{body}S[{i}, {j}, p] *= scale")
    L += _sum("tp", trace_terms, body)
    w(f"{body}t[p] = tp")
    w(f"{body}root = _pow2(min(-(Ep // 2), ROOT_MAX))")
    w(f"{body}half[p] = root")
    w(f"{body}noise[p] = root * root")
    if traced:
        w("            if k == horizon:")
        w("                _store(k, start, t, E, trace, spare, offset, paths, linear)")
        w("                break")
    else:
        w("            _store(k, start, t, E, trace, spare, offset, paths, linear)")
        w("            if k == horizon:")
        w("                break")
    w("            direct = _receptions(received, k, start, block)")
    # --- Carlson's triangular update (as _loops and the Carlson row kernels), one row at a time:
    # f = S^T h, then the columns from the last to the first, each a Givens rotation of S's column j
    # against v (the sum of the later columns weighted by their f): c = s_{j+1} / s_j, sn = f_j / s_j
    # with s_j = sqrt(2^-E + f_j^2 + ... + f_{n-1}^2)
    w("            for r in range(rows):")
    w(f"                got = lone[k, start:start + {W}] if direct else block[row_sensor[r]]")
    for i in R:
        w(f"                h{i} = H[r, {i}]")
    ind = " " * 16
    body = ind + " " * 4
    w(f"{ind}for p in range({W}):")
    load_S(body)
    for j in R:
        L.extend(_sum(f"f{j}", [f"s{i}_{j} * h{i}" for i in range(j, n)], body))
    w(f"{body}g = got[p]")
    w(f"{body}alpha = noise[p]")
    w(f"{body}sprev = half[p]")   # sqrt(2^-E), exactly (2^-E itself may underflow)
    for j in reversed(R):
        w(f"{body}alpha += f{j} * f{j}")
        # s_j >= s_{j+1} >= 2^(-E/2) even where the noise or the sum underflow: a column is never
        # zeroed by a rotation of 0 / 0; a lost row (or s_j outside the normal range) leaves S alone
        w(f"{body}sq = max(math.sqrt(alpha), sprev)")
        w(f"{body}ok = g and sq >= NORMAL and sq <= BIG")
        w(f"{body}inv = 1.0 / sq if ok else 0.0")
        w(f"{body}c = sprev * inv if ok else 1.0")
        w(f"{body}sn = f{j} * inv")
        if j > 0:
            w(f"{body}sprev = sq")
        for i in range(j, n):
            if i == j:
                w(f"{body}S[{i}, {j}, p] = c * s{i}_{j}")
                if j > 0:
                    w(f"{body}v{i} = sn * s{i}_{j}")
            else:
                w(f"{body}S[{i}, {j}, p] = c * s{i}_{j} - sn * v{i}")
                if j > 0:
                    w(f"{body}v{i} = c * v{i} + sn * s{i}_{j}")
    # --- time update (as _time_update and the Householder kernels): X[j][i] = (A S)[i, j], A lower
    # Hessenberg and S lower triangular: A S lower Hessenberg, X's top block upper Hessenberg; rows
    # n.. = 2^(-E/2) UQ, row n + c entering at column c.  Column c's reflector spans rows c, c + 1
    # and n..n + c: the rows below c + 1 are zero in columns c.. and stay so (no fill-in).  From
    # PHASED_MIN to PHASED_MAX one lane loop per column (the live entries kept in X between them),
    # else one loop
    X = {(j, i): f"x{j}_{i}" for i in R for j in range(min(i + 2, n))}
    X.update({(n + i, j): f"x{n + i}_{j}" for i in R for j in range(i, n)})
    phases = [[c] for c in R] if PHASED_MIN <= n <= PHASED_MAX else [list(R)]

    def time_update(cols: list, indent: str, trace: str = "") -> None:   # the lane loop of columns cols, and the traces by ``trace``
        w(f"{indent}for p in range({W}):")
        body = indent + " " * 4
        if cols[0] == 0:
            load_S(body)
            for i in R:
                for j in range(min(i + 2, n)):
                    L.extend(_sum(X[j, i], [f"a{i}_{l} * s{l}_{j}" for l in range(j, min(i + 1, n - 1) + 1)], body))
        else:
            for key in _live(X, cols[0], n):
                w(f"{body}{X[key]} = X[{key[0]}, {key[1]}, p]")
        w(f"{body}root = half[p]")
        for c in cols:
            for k in range(c, n):
                w(f"{body}{X[n + c, k]} = root * q{c}_{k}")
            rows = _reflector_rows(c, n)
            L.extend(_sum("sq", [f"{X[i, c]} * {X[i, c]}" for i in rows], body))
            w(f"{body}norm = math.sqrt(sq)")
            w(f"{body}x0 = {X[c, c]}")
            w(f"{body}head = norm if x0 >= 0.0 else -norm")
            if c < n - 1:   # the last column's reflector is never applied: only its pivot -head is kept
                w(f"{body}{X[c, c]} = x0 + head")
                w(f"{body}half_v2 = norm * (norm + abs(x0))")
                w(f"{body}tau = 1.0 / half_v2 if half_v2 >= NORMAL else 0.0")
                for k in range(c + 1, n):
                    L.extend(_sum("dot", [f"{X[i, c]} * {X[i, k]}" for i in rows], body))
                    w(f"{body}twice = tau * dot")
                    for i in rows:
                        w(f"{body}{X[i, k]} -= twice * {X[i, c]}")
            w(f"{body}{X[c, c]} = -head")
            for i in range(c, n):        # row c of R is final: column c of S = R^T
                w(f"{body}S[{i}, {c}, p] = {X[c, i]}")
        if cols[-1] < n - 1:
            for key in _live(X, cols[-1] + 1, n):
                w(f"{body}X[{key[0]}, {key[1]}, p] = {X[key]}")
        if trace:
            w(f"{body}out[p] = {trace}(t[p], E[p])")
            # the next step's trace, summed in the rescale's order (the same bits up to its power of
            # two); the entries of earlier lane loops' columns from S
            L.extend(_sum("tp", [f"{X[j, i]} * {X[j, i]}" if j in cols else f"S[{i}, {j}, p] * S[{i}, {j}, p]"
                                 for i, j in lower], body))
            w(f"{body}t[p] = tp")
            w(f"{body}bt = _bits_of(tp)")   # t >= 0 orders as its bits; nan above every bound
            w(f"{body}top = max(top, bt)")
            w(f"{body}bottom = min(bottom, bt)")

    for cols in phases[:-1]:
        time_update(cols, " " * 12)
    if not traced:
        time_update(phases[-1], " " * 12)
        return "\n".join(L) + "\n"
    # up to TRACED_MAX this step's traces are taken in the time update's last lane loop, which does
    # not read them: its square roots and the log's polynomial overlap.  That loop is written twice,
    # for the logs and for the traces themselves (linear): beyond TRACED_MAX double the compile
    # time, and no measured gain (docs/performance.md)
    w("            out = _row(trace, spare, k, start, offset, paths)")
    w("            top = 0")
    w(f"            bottom = {WINDOW_BITS[1]:#x}")
    w("            if linear:")
    time_update(phases[-1], " " * 16, "_linear_scaled")
    w("            else:")
    time_update(phases[-1], " " * 16, "_log_scaled")
    w(f"            wide = top > {WINDOW_BITS[1]:#x} or bottom < {WINDOW_BITS[0]:#x}")
    w("            _flush(trace, spare, k, start, offset, paths)")
    return "\n".join(L) + "\n"


def _straight_module() -> str:
    """The text of :mod:`symkf.numeric.straight_kernels`: :func:`_straight_source` for n = 1..STRAIGHT_MAX
    (regenerate it after any change to this file, which it records: ``python -c "from
    symkf.numeric.square_root import _straight_module as m; print(m(), end='')" > symkf/numeric/straight_kernels.py``;
    a test compares)."""
    head = ('"""Straight-line square-root filter kernels (Carlson\'s triangular measurement update, Carlson 1973;\n'
            'Householder time update, Sui-You-Fu eq. 9) for n = 1..%d states, the lane loop innermost: generated by\n'
            ':func:`symkf.numeric.square_root._straight_module` (do not edit; a test compares it with the generator)."""\n\n'
            "import math\n\nimport numpy as np\n\n"
            "from ..arguments import check_public\n"
            "from .kernel_parts import (BIG, NORMAL, ROOT_MAX, TINY_TRACE, _aligned, _aligned_int, _bits_of, _float_bits,\n"
            "                           _flush, _linear_scaled, _log_scaled, _pow2, _receptions, _row, _store)\n\n"
            "#: SHA-256 (its first 16 hex digits) of symkf/numeric/kernel_parts.py, whose helpers these kernels inline:\n"
            "#: numba's cache keys a compiled kernel on this file's time stamp alone, so a change there must change this file\n"
            "INLINED = \"%s\"\n\n\n" % (STRAIGHT_MAX, _inlined_digest()))
    return head + "\n\n".join(_straight_source(n) for n in range(1, STRAIGHT_MAX + 1)) + "\n\ncheck_public(globals())\n"


@functools.lru_cache(maxsize=None)
def _straight(n: int):
    """The compiled straight-line kernel for ``n`` states (:mod:`symkf.numeric.straight_kernels`, compiled
    on first use, once per installation: numba's cache)."""
    from . import straight_kernels
    return _jit(straight_kernels.INLINED)(getattr(straight_kernels, f"_paths_{n}"))


check_public(globals())
