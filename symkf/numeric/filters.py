"""The intermittent multi-sensor Kalman filter (Sui-You-Fu Theorem 1, eqs. 8-9).

Time convention of Sui-You-Fu: ``P_{0|-1} = P0`` is the prior of ``x_0`` and
the first measurements are taken at ``k = 0``; Yang et al. start one step
later (``P_{0|0} = Pi``, eqs. 4-5), which is a shift of the index.

* :func:`predicted_covariances` runs the covariance recursion in float64,
  batched across paths (no Python loop over paths), in the information form
  of Yang et al. eq. (8), ``P_{k|k}^{-1} = P_{k|k-1}^{-1} + sum_i gamma_k^i
  C_i^T R_i^{-1} C_i``.  Covariances are stored as their upper triangles
  (symmetry kept by construction); positive semidefiniteness is checked,
  and a failure raises :class:`NumericalBreakdownError` rather than
  returning garbage.
* :func:`simulate_trajectories` also draws states and measurements and runs
  the estimates (eq. 8).
* :func:`exact_covariances` is the oracle: eq. (9) verbatim, with the gain
  ``K_k = P C^* Upsilon (Upsilon C P C^* Upsilon + R)^{-1}`` in exact sympy
  arithmetic, for short horizons.
* :func:`sample_receptions` draws receival sequences of any loss model per independent
  factor (:meth:`~symkf.model.loss.LossModel.sample`), vectorised across paths.

Complex systems (``x in C^n`` with circular noise) are simulated through
their real form (:func:`real_form`), which has the same ``tr P_k``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import sympy as sp

from ..arguments import check_public
from .. import budget
from ..errors import InputError, NumericalBreakdownError, ShapeError
from ..model.loss import LossModel, checked
from ..model.system import System
from .receptions import draw


# ---------------------------------------------------------------- float data

@dataclass(frozen=True)
class FloatSystem:
    """Float64 data of a real system, measurement rows whitened.

    ``H`` stacks the rows of ``L_i^{-1} C_i`` (``R_i = L_i L_i^T``), so the
    whitened measurement noise is standard normal; ``row_sensor[r]`` is the
    sensor that row ``r`` belongs to and ``W`` the block-diagonal ``L^{-1}``.
    """

    A: np.ndarray
    Q: np.ndarray
    P0: np.ndarray
    H: np.ndarray
    W: np.ndarray
    row_sensor: np.ndarray

    @property
    def n(self) -> int:
        """State dimension ``n``."""
        return self.A.shape[0]

    @property
    def d(self) -> int:
        """Number of sensors ``d``."""
        return int(self.row_sensor.max()) + 1


def _float(M: sp.MatrixBase) -> np.ndarray:
    return np.array(sp.Matrix(M).evalf(30).tolist(), dtype=complex)


def _realify(M: np.ndarray) -> np.ndarray:
    return np.block([[M.real, -M.imag], [M.imag, M.real]])


def real_form(system: System) -> FloatSystem:
    """Float data of ``system``; a complex system is replaced by its real form.

    ``x = u + i v`` with circular noise becomes ``(u, v)`` with
    ``A_r = [[Re A, -Im A], [Im A, Re A]]``, ``C_r`` alike, and covariances
    ``Q_r = realify(Q) / 2`` (likewise R, P0).  Realification is a
    ``*``-algebra homomorphism, so ``P_r,k = realify(P_k) / 2`` for every
    receival sequence and ``tr P_r,k = tr P_k``.

    Cached per system (a System is immutable, the arrays are read-only): the sympy evaluation
    is a noticeable share of a short simulation's time at many states (docs/performance.md).
    """
    if not isinstance(system, System):
        raise InputError(f"system: expected a symkf.System, got {type(system).__name__}")
    return _real_form(system)


@functools.lru_cache(maxsize=32)
def _real_form(system: System) -> FloatSystem:
    A, Q, P0 = _float(system.A), _float(system.Q), _float(system.P0)
    Cs = [_float(s.C) for s in system.sensors]
    Rs = [_float(s.R) for s in system.sensors]
    if any(np.iscomplexobj(M) and np.any(M.imag) for M in [A, Q, P0, *Cs, *Rs]):
        A, Q, P0 = _realify(A), _realify(Q) / 2, _realify(P0) / 2
        Cs = [_realify(C) for C in Cs]
        Rs = [_realify(R) / 2 for R in Rs]
    else:
        A, Q, P0, Cs, Rs = A.real, Q.real, P0.real, [C.real for C in Cs], [R.real for R in Rs]
    whiten = [np.linalg.inv(np.linalg.cholesky(R)) for R in Rs]
    H = np.vstack([Wi @ C for Wi, C in zip(whiten, Cs)])
    W = np.zeros((H.shape[0], H.shape[0]))
    row_sensor = np.concatenate([np.full(C.shape[0], i) for i, C in enumerate(Cs)])
    start = 0
    for Wi in whiten:
        W[start:start + len(Wi), start:start + len(Wi)] = Wi
        start += len(Wi)
    for M in (A, Q, P0, H, W, row_sensor):
        M.flags.writeable = False
    return FloatSystem(A, Q, P0, H, W, row_sensor)


# ------------------------------------------------ upper-triangle (vech) algebra

class _Vech:
    """Linear maps on the upper triangle ``vech(P)`` of a symmetric ``n x n`` matrix."""

    def __init__(self, n: int):
        self.n = n
        self.iu, self.ju = np.triu_indices(n)
        self.N = len(self.iu)
        self.diag = (self.iu == self.ju).astype(float)
        # duplication: full row-major vec from vech
        self.D = np.zeros((n * n, self.N))
        for t, (i, j) in enumerate(zip(self.iu, self.ju)):
            self.D[i * n + j, t] = self.D[j * n + i, t] = 1.0
        self.pick = self.iu * n + self.ju

    def pack(self, P: np.ndarray) -> np.ndarray:
        return P[..., self.iu, self.ju]

    def unpack(self, V: np.ndarray) -> np.ndarray:
        return (V @ self.D.T).reshape(V.shape[:-1] + (self.n, self.n))

    def congruence(self, A: np.ndarray) -> np.ndarray:
        """``T`` with ``vech(A P A^T) = vech(P) @ T``."""
        return (np.kron(A, A)[self.pick] @ self.D).T

    def inverse(self, V: np.ndarray) -> np.ndarray:
        """``vech(P^{-1})`` for every column of ``V``; closed form for n <= 2."""
        if self.n == 1:
            return 1.0 / V
        if self.n == 2:
            a, b, c = V
            det = a * c - b * b
            return np.stack([c, -b, a]) / det
        return self.pack(np.linalg.inv(self.unpack(V.T))).T

    def matvec(self, V: np.ndarray, u: np.ndarray) -> np.ndarray:
        """``P u`` column by column, ``u`` of shape (n, paths)."""
        out = np.zeros_like(u)
        for t, (i, j) in enumerate(zip(self.iu, self.ju)):
            out[i] += V[t] * u[j]
            if i != j:
                out[j] += V[t] * u[i]
        return out


def _check_psd(V: np.ndarray, vech: _Vech, step: int, tol: float = 1e-9) -> None:
    """Raise unless every ``P`` (vech, one column per path) is finite and PSD."""
    if not np.all(np.isfinite(V)):
        bad = int(np.sum(~np.all(np.isfinite(V), axis=0)))
        raise NumericalBreakdownError(
            f"P_{{{step}|{step - 1}}} overflowed float64 on {bad} path(s); shorten the horizon")
    lam = np.linalg.eigvalsh(vech.unpack(V.T))
    bad = lam[..., 0] < -tol * np.maximum(lam[..., -1], 1.0)
    if np.any(bad):
        raise NumericalBreakdownError(
            f"P_{{{step}|{step - 1}}} lost positive semidefiniteness on {int(bad.sum())} path(s) "
            f"(smallest eigenvalue {lam[bad, 0].min():.3g}, largest {lam[bad, -1].max():.3g}): "
            "the covariance is too ill-conditioned for float64; shorten the horizon")


def _codes(gamma: np.ndarray, d: int) -> tuple[np.ndarray, np.ndarray]:
    """Receival vectors (paths, horizon, d) as codes (horizon, paths) into a table of all 2^d vectors."""
    gamma = np.asarray(gamma)
    if gamma.ndim != 3 or gamma.shape[2] != d:
        raise ShapeError(f"receptions: expected an array (paths, horizon, {d}), got shape {gamma.shape}")
    if not np.all((gamma == 0) | (gamma == 1)):
        raise InputError("receptions: entries must be 0 (lost) or 1 (received)")
    codes = (gamma.astype(np.intp) << np.arange(d)).sum(axis=2).T
    return np.ascontiguousarray(codes), receival_table(d)


def receival_table(d: int) -> np.ndarray:
    """All 2^d receival vectors, row ``c`` holding the bits of ``c`` (sensor i = bit i)."""
    if isinstance(d, bool) or not isinstance(d, int) or d < 0:
        raise InputError(f"d: expected a number of sensors, got {d!r}")
    budget.check_power("max_patterns", 2, d, "d", "the receival vectors 2^d of the table")
    return ((np.arange(2 ** d)[:, None] >> np.arange(d)) & 1).astype(bool)


def _run(model: FloatSystem, states: np.ndarray, emit: np.ndarray, keep: str, check_every: int,
         noise: tuple[np.ndarray, np.ndarray] | None = None):
    """The batched recursion shared by every float mode (Yang et al. eqs. 4-10).

    ``states`` (horizon, paths) index the receival table ``emit`` (S, d).
    Covariances are held as ``vech(P)`` with one column per path, so a step
    is a few BLAS products and elementwise operations over all paths.  The
    measurement update is the information form (8), ``P_{k|k} = (P_{k|k-1}^{-1}
    + J_k)^{-1}`` with ``J_k = sum_i gamma_k^i C_i^T R_i^{-1} C_i`` looked up
    per state: it stays accurate for far more ill-conditioned ``P`` (long
    bursts) than the covariance form, whose subtraction cancels.  Paths that
    receive nothing skip the update.  Returns ``vech P_{k|k-1}`` as requested
    by ``keep`` ("trace", "all", "last") and, with ``noise = (x, z)`` (true
    states and whitened measurements, (paths, horizon, .)), the predicted and
    filtered estimates (eqs. 9-10: ``x_{k|k} = x_{k|k-1} + P_{k|k} sum_r
    gamma h_r (z_r - h_r^T x_{k|k-1})`` over whitened rows ``h_r``).
    """
    vech = _Vech(model.n)
    if emit.shape[1] != model.d:
        raise ShapeError(f"loss: models {emit.shape[1]} sensor(s), the system has {model.d}")
    row_gamma = emit[:, model.row_sensor].astype(float)                       # (S, rows)
    J = vech.pack(np.einsum("sr,ri,rj->sij", row_gamma, model.H, model.H)).T  # (N, S)
    receives = row_gamma.any(axis=1)
    horizon, paths = states.shape
    Tt = vech.congruence(model.A).T
    q = vech.pack(model.Q)[:, None]
    V = np.repeat(vech.pack(model.P0)[:, None], paths, axis=1)
    out = np.empty((horizon, paths)) if keep == "trace" else (
        np.empty((horizon, vech.N, paths)) if keep == "all" else None)
    track = noise is not None
    if track:
        zt = np.ascontiguousarray(np.transpose(noise[1], (1, 2, 0)))   # (horizon, rows, paths)
        xp = np.zeros((model.n, paths))
        x_pred = np.empty((horizon, model.n, paths))
        x_filt = np.empty((horizon, model.n, paths))
        V_filt = np.empty((horizon, vech.N, paths))
    diag = np.flatnonzero(vech.diag)
    for k in range(horizon):
        if keep == "trace":
            np.sum(V[diag], axis=0, out=out[k])
        elif keep == "all":
            out[k] = V
        if check_every and (k % check_every == 0):
            _check_psd(V, vech, k)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            post = vech.inverse(vech.inverse(V) + J.take(states[k], axis=1))
        V = np.where(receives.take(states[k]), post, V)
        if track:
            x_pred[k] = xp
            g = row_gamma.take(states[k], axis=0).T                   # (rows, paths)
            innovation = g * (zt[k] - model.H @ xp)
            xp = xp + vech.matvec(V, model.H.T @ innovation)
            x_filt[k] = xp
            V_filt[k] = V
            xp = model.A @ xp
        with np.errstate(over="ignore", invalid="ignore"):  # overflow is caught by _check_psd
            V = Tt @ V
        V += q
    if check_every:
        _check_psd(V, vech, horizon)
    if track:
        return (np.moveaxis(out, (0, 1, 2), (1, 2, 0)), np.moveaxis(x_pred, (0, 1, 2), (1, 2, 0)),
                np.moveaxis(x_filt, (0, 1, 2), (1, 2, 0)), np.moveaxis(V_filt, (0, 1, 2), (1, 2, 0)), vech)
    if keep == "last":
        return V.T, vech
    return (out.T if keep == "trace" else np.moveaxis(out, (0, 1, 2), (1, 2, 0))), vech


def _psd_factor(M: np.ndarray) -> np.ndarray:
    """A square root ``F`` with ``F F^T = M`` of a symmetric PSD matrix (eigh: ``M`` may be singular)."""
    w, U = np.linalg.eigh(M)
    return U * np.sqrt(np.clip(w, 0.0, None))


def _kernel_arguments(model: FloatSystem, received: np.ndarray) -> tuple:
    """Checked receptions and the kernel's factors."""
    received = np.asarray(received, bool)
    if received.ndim != 3:
        raise ShapeError(f"receptions: expected an array (horizon, paths, d), got shape {received.shape}")
    d = received.shape[2]
    if d != model.d:
        raise ShapeError(f"receptions: {d} sensor(s) given, the system has {model.d}")
    if not np.any(model.P0):
        raise InputError("P0: the prior covariance is zero; log tr P_0 is undefined")
    received = np.ascontiguousarray(received)
    A, H, P0, Q = model.A, model.H, model.P0, model.Q
    if np.any(np.triu(A, 2)):
        # the kernel takes A lower Hessenberg: its measurement update keeps S lower triangular
        # (Carlson's), so A S is lower Hessenberg and the time update's reflector of column c spans
        # c + 3 rows instead of n + 1, and A S skips A's zeros.  The state in an orthonormal basis
        # that makes it so, which leaves tr P unchanged (P -> T P T^T): a Householder reduction to
        # upper Hessenberg form where A is not already, then the states in reverse order
        # (J A J is lower Hessenberg for the reversal J; P -> J P J)
        if np.any(np.tril(A, -2)):
            T = _hessenberg_basis(A)
            A, H, P0, Q = np.triu(T @ A @ T.T, -1), H @ T.T, T @ P0 @ T.T, T @ Q @ T.T
        A, H, P0, Q = A[::-1, ::-1], H[:, ::-1], P0[::-1, ::-1], Q[::-1, ::-1]
    # triangular factors: S0 S0^T = P0 (lower), U_Q^T U_Q = Q (upper), from QR of any square root
    S0 = np.linalg.qr(_psd_factor(P0).T, mode="r").T
    UQ = np.linalg.qr(_psd_factor(Q).T, mode="r")
    c = functools.partial(np.array, order="C")   # writable copies: numba compiles read-only arrays apart
    return c(A), c(UQ), c(H), c(model.row_sensor), c(S0), received


def _hessenberg_basis(A: np.ndarray) -> np.ndarray:
    """An orthogonal ``T`` with ``T A T^T`` upper Hessenberg up to rounding (Householder
    reflections of the columns below the subdiagonal, Golub and Van Loan, Matrix Computations,
    section 7.4.2)."""
    n = A.shape[0]
    M, T = np.array(A, float), np.eye(n)
    for k in range(n - 2):
        v = M[k + 1:, k].copy()
        v[0] += np.copysign(np.linalg.norm(v), v[0])
        norm = np.linalg.norm(v)
        if norm == 0.0:
            continue
        v /= norm
        for B in (M, T):                               # B <- (I - 2 v v^T) B on rows k+1..
            B[k + 1:] -= 2.0 * np.outer(v, v @ B[k + 1:])
        M[:, k + 1:] -= 2.0 * np.outer(M[:, k + 1:] @ v, v)
    return T


def log_traces(model: FloatSystem, received: np.ndarray) -> np.ndarray:
    """``log tr P_{k|k-1}`` (paths, horizon + 1), k = 0..horizon, for receptions ``received``
    (horizon, paths, d) bool: a transposed view (Fortran order), each step's logs contiguous as the
    kernel writes them.

    Square-root filter with a running power-of-two scale per path (Carlson's triangular
    measurement update one whitened row at a time, Yang et al. eq. 8 and Carlson, "Fast
    triangular formulation of the square root filter", 1973; Householder time update,
    Sui-You-Fu eq. 9), compiled: :mod:`symkf.numeric.square_root`.  ``log tr P`` is available over
    any dynamic range (thousands of unstable steps), and ``P`` stays positive semidefinite
    by construction.
    """
    from .square_root import log_trace_paths
    arguments = _kernel_arguments(model, received)
    horizon, paths, _ = arguments[-1].shape
    trace = np.empty((horizon + 1, paths))
    log_trace_paths(*arguments, trace)   # the kernel takes the log: one pass over the output
    return trace.T


def traces_into(model: FloatSystem, received: np.ndarray, out: np.ndarray, first: int = 0) -> None:
    """``out[first + p, k] = tr P_{k|k-1}``, k = 0..horizon-1, by the filter of :func:`log_traces`
    for ``received`` (horizon, paths, d): the exact product of its trace and power-of-two scale
    (``inf`` where ``tr P`` exceeds float64), written by the kernel without a log.  ``out`` is a
    float64 array (at least ``first + paths``, horizon) in Fortran order (``out.T`` C-contiguous,
    as ``np.empty((horizon, m)).T`` is): the kernel writes each step's traces of a block of paths
    contiguously, where rows of a C-ordered ``out`` would take a transposing copy."""
    from .square_root import log_trace_paths
    arguments = _kernel_arguments(model, received)
    horizon, paths = np.shape(received)[:2]
    if isinstance(first, bool) or not isinstance(first, (int, np.integer)) or first < 0:
        raise ShapeError(f"first: expected the row of out that takes the first path (an integer >= 0), got {first!r}")
    if (not isinstance(out, np.ndarray) or out.ndim != 2 or out.dtype != np.float64 or not out.T.flags.c_contiguous
            or not out.flags.writeable or out.shape[1] != horizon or out.shape[0] < first + paths):
        raise ShapeError(f"out: expected a writeable float64 array in Fortran order (out.T C-contiguous) of {horizon} "
                         f"columns and at least first + paths = {first + paths} rows, got "
                         f"{getattr(out, 'shape', None)} {getattr(out, 'dtype', type(out).__name__)}"
                         f"{'' if getattr(out, 'ndim', 0) != 2 or out.T.flags.c_contiguous else ' in C order'}")
    log_trace_paths(*arguments, out.T, True, int(first))


def predicted_covariances(system: System | FloatSystem, receptions: np.ndarray, keep: str = "trace",
                          check_every: int = 50) -> np.ndarray:
    """``P_{k|k-1}``, k = 0..horizon-1, for each receival sequence (Sui-You-Fu eq. 9).

    ``receptions`` is a 0/1 array (paths, horizon, d), ``receptions[p, k, i]
    = gamma_k^i``.  ``keep="trace"`` returns ``tr P_{k|k-1}`` (paths,
    horizon); ``"all"`` the matrices (paths, horizon, n, n); ``"last"``
    ``P_{horizon|horizon-1}`` (paths, n, n).  PSD is checked every
    ``check_every`` steps and at the end (0 disables the check).
    """
    if keep not in ("trace", "all", "last"):
        raise InputError(f"keep: expected 'trace', 'all' or 'last', got {keep!r}")
    model = system if isinstance(system, FloatSystem) else real_form(system)
    out, vech = _run(model, *_codes(receptions, model.d), keep, check_every)
    return out if keep == "trace" else vech.unpack(out)


@dataclass(frozen=True)
class Trajectories:
    """Batched filter runs: arrays indexed (path, time, ...).

    ``x`` true states, ``y`` measurements (real form, unwhitened, zero where
    lost), ``gamma`` receivals, ``x_pred``/``P_pred`` = ``x_{k|k-1}``,
    ``P_{k|k-1}`` and ``x_filt``/``P_filt`` = ``x_{k|k}``, ``P_{k|k}``.
    """

    x: np.ndarray
    y: np.ndarray
    gamma: np.ndarray
    x_pred: np.ndarray
    x_filt: np.ndarray
    P_pred: np.ndarray
    P_filt: np.ndarray
    seed: int | None


def simulate_trajectories(system: System, loss: LossModel, horizon: int, paths: int,
                          seed: int | None = None) -> Trajectories:
    """Draw ``x_0 ~ N(0, P0)``, ``x_{k+1} = A x_k + w_k``, measurements and
    receivals, and run the filter (Sui-You-Fu eqs. 8-9) on every path."""
    horizon, paths = _positive(horizon, "horizon"), _positive(paths, "paths")
    model = real_form(system)
    rng = np.random.default_rng(seed)
    gamma = sample_receptions(loss, horizon, paths, rng, model.d)
    states, emit = _codes(gamma, model.d)
    n, m = model.n, model.H.shape[0]
    LQ, LP = _psd_factor(model.Q), _psd_factor(model.P0)   # Q may be singular
    x = np.empty((paths, horizon, n))
    x[:, 0] = rng.standard_normal((paths, n)) @ LP.T
    for k in range(1, horizon):
        x[:, k] = x[:, k - 1] @ model.A.T + rng.standard_normal((paths, n)) @ LQ.T
    z = x @ model.H.T + rng.standard_normal((paths, horizon, m))  # whitened measurements
    P_pred, x_pred, x_filt, V_filt, vech = _run(model, states, emit, "all", 50, noise=(x, z))
    y = (z @ np.linalg.inv(model.W).T) * gamma[:, :, model.row_sensor]
    return Trajectories(x, y, gamma, x_pred, x_filt, vech.unpack(P_pred), vech.unpack(V_filt), seed)


def _positive(value: int, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(f"{name}: expected a positive integer, got {value!r}")
    return int(value)


# ------------------------------------------------------------- receival draws

def sample_receptions(loss: LossModel, horizon: int, paths: int, rng: np.random.Generator,
                      d: int | None = None) -> np.ndarray:
    """Receival vectors ``gamma_k`` as a bool array (paths, horizon, d), 1 = received, drawn per
    independent factor of ``loss`` (:func:`symkf.numeric.receptions.draw`)."""
    return draw(checked(loss, d), horizon, paths, rng).transpose(1, 0, 2)


# ---------------------------------------------------------------- exact oracle

def exact_covariances(system: System, receptions: Sequence[Sequence[int]]) -> list[sp.Matrix]:
    """Exact ``P_{k|k-1}``, k = 0..len(receptions), for one receival sequence.

    Sui-You-Fu eq. (9) verbatim: ``P_{k|k} = P - K Upsilon C P`` with ``K =
    P C^* Upsilon (Upsilon C P C^* Upsilon + R)^{-1}``, then ``P_{k+1|k} = A
    P_{k|k} A^* + Q``; sympy arithmetic, entries simplified each step.
    """
    C, R = sp.Matrix(system.C), sp.Matrix(system.R)
    A, Q = sp.Matrix(system.A), sp.Matrix(system.Q)
    sizes = [s.m for s in system.sensors]
    P = sp.Matrix(system.P0)
    out = [P]
    for k, gamma in enumerate(receptions):
        if len(gamma) != system.d or set(gamma) - {0, 1}:
            raise InputError(f"receptions[{k}]: expected a 0/1 vector of length {system.d}, got {gamma!r}")
        U = sp.diag(*[sp.eye(m) * g for m, g in zip(sizes, gamma)])
        K = P * C.H * U * (U * C * P * C.H * U + R).inv()
        P = A * (P - K * U * C * P) * A.H + Q
        P = P.applyfunc(_simplify)
        out.append(P)
    return out


def _simplify(e: sp.Expr) -> sp.Expr:
    return e if e.is_Rational else sp.radsimp(sp.expand(e, complex=True))

check_public(globals())
