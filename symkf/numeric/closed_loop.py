"""Monte Carlo of the closed LQG loop over lossy networks (float64, simulation only).

Schenato, Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and estimation over
lossy networks", Proc. IEEE 95(1), 2007, Sections III-V.  The plant

    x_{k+1} = A x_k + Gamma_k B u_k + w_k,    y_k = gamma_k (C x_k + v_k),

``w ~ N(0, Q)``, ``v ~ N(0, R)``, ``x_0 ~ N(0, P0)``, stage cost ``x' W x + u' Gamma U Gamma u``
(``nu_k u' U u`` with one control channel).  ``gamma_k`` (observations) and ``Gamma_k``
(controls: ``nu_k I``, or ``diag(nu_k^i I_{m_i})`` over the actuators' column groups) are the
receptions of symkf loss models (:mod:`symkf.numeric.receptions`: an actuator loss model is an
ordinary :class:`~symkf.model.loss.LossModel` whose "sensors" are the actuators), or one
Bernoulli channel of a given arrival rate.

* **TCP-like** (acknowledged controls, Section IV): the estimator knows ``Gamma_k``:
  ``x^_{k+1|k} = A x^_{k|k} + Gamma_k B u_k``, ``P_{k+1|k} = A P_{k|k} A' + Q``, and the
  Kalman update on the rows received.  Separation holds; the optimal controller is
  ``u_k = -L x^_{k|k}`` with the steady gain ``L = (B'SB + U)^{-1} B'SA`` of the control MARE
  ``S = A'SA + W - nu A'SB (B'SB + U)^{-1} B'SA``.  Per actuator,
  ``E[Gamma M Gamma] = Lambda (Wh o M) Lambda`` with ``Wh`` of
  :func:`arrival_weight` (Yang et al., eqs. 19-20, transposed to the actuators), so the
  expectation of the cost-to-go, minimised over ``u``, gives
  ``S = A'SA + W - A'SB (Wh o (B'SB + U))^{-1} B'SA`` and
  ``L = Lambda^{-1} (Wh o (B'SB + U))^{-1} B'SA`` (:func:`control_riccati`).
* **UDP-like** (no acknowledgements, Section V): the estimator uses the expected input,
  ``x^_{k+1|k} = A x^_{k|k} + B Lambda u_k``.  The error ``e_{k+1} = A e_{k|k} + B (Gamma_k -
  Lambda) u_k + w_k`` has ``E[(Gamma - Lambda) u u' (Gamma - Lambda)] = V o (u u')``,
  ``V_ij = lambda_a (1 - lambda_a)`` when columns ``i, j`` belong to the same actuator ``a`` and
  0 otherwise (independent channels), so ``P_{k+1|k} = A P_{k|k} A' + Q + B (V o u u') B'``
  (``nu (1 - nu) B u u' B'`` with one channel, Section V); the update is the same.  The
  controller is ``u_k = -L x^_{k|k}`` with a gain the caller gives (the optimal UDP
  controller is nonlinear in general, Section V).

:func:`simulate_loop` runs the loop on the true state, paths vectorised (leading axis), and
estimates ``E[x_k' W x_k]`` and ``E[||x_k||^2]`` per step with standard errors
(:class:`LoopSimulation`).

:func:`loop_divergence` decides from simulation whether ``E[x'Wx]`` stays bounded with the
discipline of :func:`symkf.numeric.verify.verify` (three independent runs at ``h, 2h, 3h``,
:func:`symkf.numeric.montecarlo._divergence_verdict`: the margin's Fieller interval, its
allowance, a verdict).  Given the loss sequences the loop is linear, with the filter's gains a
function of the observations' losses (TCP-like: the Kalman gain of ``P_{k|k-1}``; UDP-like: ``P``
takes ``E[u u' | losses]`` in place of ``u u'``, the simulated estimator's gain when the
measurements are noiseless), so ``Sigma_k = E[z_k z_k' | losses]``, ``z = (x_k - x^_{k|k-1},
x^_{k|k-1})``, follows ``Sigma' = M_o Sigma M_o' + N_o R N_o' + Q_z`` for each step's reception
state ``o`` and ``E[x_K' W x_K | losses]`` is computed, not sampled (Rao-Blackwellisation: the
noises leave the estimator's variance).  Only the losses are drawn (:func:`_moment_sample`), from
a path-level mixture whose components' path probabilities are known on every path, with the
exact balance-heuristic ratio ``p / sum_c a_c q_c``:

0. the losses' own law (defensive);
1. the controls twisted by ``<H_{k+1}, E[x_{k+1} x_{k+1}' | o]>``, ``H_k`` the backward value of
   the controls' jump linear system ``x+ = (A - B Gamma L) x`` from ``W``, observations from their law;
2. every outcome twisted by ``<H'_{k+1}, Sigma'_o> + c_{k+1}``, the backward value (with its noise
   term) of the loop's linear model with the steady gain of the filter that receives everything
   (exact for the UDP-like scalar noiseless loop);
3. (i.i.d. observations) a window of lost observations (every sensor) at a uniform place, of a
   length drawn ``~ (p_lost rho(A)^2)^l`` and at most as long as float64 follows (the filter's
   heavy tail: a burst's covariance, moved into ``x^`` by the next reception), the losses' own
   law elsewhere; ``q / p`` sums over the windows the path's runs of losses contain.

The gains are computed in square-root form (:func:`_gains`), and TCP-like ``E[e e' | losses]``
must stay the filter's own ``P``: paths where the two part (a burst spread a covariance beyond
float64's resolution) may carry at most :data:`MAX_PARTED_SHARE` of the estimate, else the run
is refused (:class:`~symkf.errors.NumericalBreakdownError`: a shorter horizon resolves it).
"""

from __future__ import annotations

import dataclasses

import html
import math
import numbers
from dataclasses import dataclass
from typing import Any, Literal, Sequence

import numpy as np

from .. import budget
from ..arguments import check_public, count, float_array
from ..errors import InputError, NotPositiveDefiniteError, NumericalBreakdownError, ShapeError
from ..model.loss import LossFactor, LossModel, checked
from ..model.system import System
from ..output import JsonDocument
from . import receptions
from .montecarlo import (MAX_PATH_SHARE, MAX_REL_STDERR, RESOLUTION_BITS, DivergenceResult, _burst_lengths,
                         _divergence_verdict, _weighted_log_mean, _z, rate_horizons)

PROTOCOLS = ("tcp", "udp")


def arrival_weight(arrival: Sequence[Any], dims: Sequence[int]) -> list[list[Any]]:
    """``W = 1 1' + D^{-1} I_blk`` (Yang et al., eqs. 19-20) as rows: 1 off the diagonal blocks,
    ``1 / lambda_i`` on block ``i`` (size ``dims[i]``), so that ``E[Gamma M Gamma] = Lambda (W o M)
    Lambda`` for independent Bernoulli ``Gamma = diag(gamma_i I_{dims[i]})`` of means ``lambda_i``
    (``E[gamma_i gamma_j] = lambda_i lambda_j`` for ``i != j``, ``E[gamma_i^2] = lambda_i``).  Exact
    or float as the ``lambda_i`` are; every ``lambda_i`` must be nonzero."""
    sizes = [count(p, f"dims[{i}]", 1) for i, p in enumerate(dims)]
    if len(sizes) != len(arrival):
        raise InputError(f"arrival: expected one rate per block of dims ({len(sizes)}), got {len(arrival)}")
    if not all(isinstance(a, numbers.Number) or hasattr(a, "is_zero") for a in arrival):
        raise InputError(f"arrival: expected numbers (floats or exact), got {[type(a).__name__ for a in arrival]}")
    if any(a == 0 for a in arrival):
        raise InputError("arrival: a channel with arrival rate 0 has no entry 1 / lambda_i; leave it out")
    labels = [i for i, p in enumerate(sizes) for _ in range(p)]
    return [[1 / arrival[i] if i == j else 1 for j in labels] for i in labels]


# ------------------------------------------------------------------ the plant

@dataclass(frozen=True, repr=False)
class LoopPlant(JsonDocument):
    """The float64 plant of the loop: ``A`` (n, n), ``B`` (n, m), ``C`` (p, n), noise covariances
    ``Q``, ``R``, ``P0``, cost weights ``W`` (n, n) and ``U`` (m, m); ``sensor_rows`` the rows of
    ``C`` per sensor, ``actuator_columns`` the columns of ``B`` per actuator, in order."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    W: np.ndarray
    U: np.ndarray
    P0: np.ndarray
    sensor_rows: tuple[int, ...]
    actuator_columns: tuple[int, ...]

    @property
    def n(self) -> int:
        return self.A.shape[0]

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {k: getattr(self, k).tolist() for k in ("A", "B", "C", "Q", "R", "W", "U", "P0")}
        out.update(sensor_rows=list(self.sensor_rows), actuator_columns=list(self.actuator_columns))
        return out

    def __repr__(self) -> str:
        return (f"<LoopPlant: n = {self.n}, {len(self.sensor_rows)} sensor(s) with rows {list(self.sensor_rows)}, "
                f"{len(self.actuator_columns)} actuator(s) with columns {list(self.actuator_columns)}>")


def _matrix(value: Any, shape: tuple[int, int], entry: str, default: np.ndarray | None = None) -> np.ndarray:
    if value is None and default is not None:
        return default
    M = np.atleast_2d(float_array(value, entry))
    if M.shape != shape:
        raise ShapeError(f"{entry}: expected shape {shape}, got {M.shape}")
    if not np.all(np.isfinite(M)):
        raise InputError(f"{entry}: expected finite numbers")
    return M


def _covariance(value: Any, size: int, entry: str, definite: bool) -> np.ndarray:
    M = _matrix(value, (size, size), entry, np.eye(size))
    low = np.linalg.eigvalsh((M + M.T) / 2).min() if size else 1.0
    # float entries: a semidefinite matrix may show an eigenvalue of -1e-17
    if not np.allclose(M, M.T) or low < -1e-12 * max(1.0, np.abs(M).max()) or (definite and low <= 0):
        raise NotPositiveDefiniteError(f"{entry}: expected a symmetric positive {'definite' if definite else 'semidefinite'} "
                         f"matrix (least eigenvalue {low:.3g})")
    return M


def _sizes(value: Sequence[int] | None, total: int, entry: str) -> tuple[int, ...]:
    if value is None:
        return (total,)
    sizes = tuple(count(v, f"{entry}[{i}]", 1) for i, v in enumerate(value))
    if not sizes or sum(sizes) != total:
        raise ShapeError(f"{entry}: expected positive sizes adding up to {total}, got {list(value)}")
    return sizes


def loop_plant(A: Any, B: Any, C: Any, Q: Any = None, R: Any = None, W: Any = None, U: Any = None,
               P0: Any = None, *, sensor_rows: Sequence[int] | None = None,
               actuator_columns: Sequence[int] | None = None) -> LoopPlant:
    """A :class:`LoopPlant` from arrays (numbers or rows); ``Q``, ``R``, ``W``, ``U``, ``P0`` default to
    identities, ``sensor_rows`` to one sensor with every row of ``C``, ``actuator_columns`` to one
    actuator with every column of ``B``.  ``R`` and ``U`` must be positive definite, the others
    positive semidefinite."""
    A = np.atleast_2d(float_array(A, "A"))
    n = A.shape[0]
    A = _matrix(A, (n, n), "A")
    B = np.atleast_2d(float_array(B, "B"))
    B = _matrix(B, (n, B.shape[-1]), "B")
    C = np.atleast_2d(float_array(C, "C"))
    C = _matrix(C, (C.shape[0], n), "C")
    m, p = B.shape[1], C.shape[0]
    if min(n, m, p) == 0:
        raise ShapeError(f"A, B, C: expected at least one state, input and output, got n = {n}, m = {m}, p = {p}")
    return LoopPlant(A, B, C, _covariance(Q, n, "Q", False), _covariance(R, p, "R", True),
                     _covariance(W, n, "W", False), _covariance(U, m, "U", True), _covariance(P0, n, "P0", False),
                     _sizes(sensor_rows, p, "sensor_rows"), _sizes(actuator_columns, m, "actuator_columns"))


def plant_of(system: System) -> LoopPlant:
    """The :class:`LoopPlant` of a :class:`~symkf.model.system.System` with an input: its ``A``,
    ``C``, ``Q``, ``R``, ``P0``, sensors, and ``system.B``, ``system.U``, ``system.W`` and the
    column groups of ``system.actuators`` (each actuator's ``m`` columns) where the system has
    them (``U``, ``W``: identities when absent or None)."""
    B = getattr(system, "B", None)
    if B is None or 0 in getattr(B, "shape", (1,)):     # a system without actuators: B is None or n x 0
        raise InputError("system.B: the system has no actuators (no input matrix B); give it actuators, or "
                         "give the arrays to symkf.numeric.closed_loop.loop_plant")
    actuators = getattr(system, "actuators", None)
    columns = None if not actuators else [getattr(a, "m", None) or np.atleast_2d(np.asarray(a.B)).shape[1]
                                          for a in actuators]

    def floats(M: Any) -> Any:
        return None if M is None else np.array(M.evalf(30) if hasattr(M, "evalf") else M, dtype=float)

    return loop_plant(floats(system.A), floats(B), floats(system.C), floats(system.Q), floats(system.R),
                      floats(getattr(system, "W", None)), floats(getattr(system, "U", None)), floats(system.P0),
                      sensor_rows=[s.m for s in system.sensors], actuator_columns=columns)


# ------------------------------------------------------------------ the control MARE

def _rates(arrival: Any, groups_: int, entry: str) -> np.ndarray:
    """Arrival rates: one (a single channel) or one per group, each in (0, 1]."""
    if isinstance(arrival, numbers.Real) and not isinstance(arrival, bool):
        rates = np.array([float(arrival)])
    elif isinstance(arrival, (list, tuple, np.ndarray)):
        rates = float_array(arrival, entry).ravel()
        if rates.size != groups_:
            raise ShapeError(f"{entry}: expected one arrival rate per actuator ({groups_}), got {rates.size}")
    else:
        raise InputError(f"{entry}: expected an arrival rate or one per actuator, got {type(arrival).__name__}")
    if not np.all((rates > 0) & (rates <= 1)):
        raise InputError(f"{entry}: arrival rates must lie in (0, 1] (an actuator that never receives never acts: "
                         f"leave its columns out of B), got {rates.tolist()}")
    return rates


def control_riccati(A: Any, B: Any, W: Any, U: Any, arrival: Any = 1.0, columns: Sequence[int] | None = None,
                    iterations: int = 100_000, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """``(S, L)``: the fixed point of the control MARE and the TCP-like steady gain (module docstring).

    ``S = A'SA + W - A'SB (Wh o (B'SB + U))^{-1} B'SA`` (Schenato et al. 2007, Section IV; per
    actuator with ``Wh = arrival_weight``), iterated in float64 from ``S = 0`` (monotone) until the
    relative change is at most ``tol``; ``L = Lambda^{-1} (Wh o (B'SB + U))^{-1} B'SA``.
    ``arrival``: one rate (a single channel for every column, the paper's ``nu``) or one per
    actuator, whose column counts ``columns`` gives (None: each column its own actuator when
    ``arrival`` has one rate per column).  Raises :class:`~symkf.errors.NumericalBreakdownError` when
    the iteration grows without bound or does not settle in ``iterations`` steps (below the
    critical control arrival rate no stabilising steady gain exists: pass an explicit gain to
    :func:`simulate_loop`)."""
    A = np.atleast_2d(float_array(A, "A"))
    n = A.shape[0]
    A = _matrix(A, (n, n), "A")
    B = np.atleast_2d(float_array(B, "B"))
    B = _matrix(B, (n, B.shape[-1]), "B")
    m = B.shape[1]
    if min(n, m) == 0:
        raise ShapeError(f"A, B: expected at least one state and one input, got n = {n}, m = {m}")
    W, U = _matrix(W, (n, n), "W"), _matrix(U, (m, m), "U")
    iterations = count(iterations, "iterations", 1)
    if not isinstance(tol, float) or not tol > 0:
        raise InputError(f"tol: expected a positive float, got {tol!r}")
    single = isinstance(arrival, numbers.Real) and not isinstance(arrival, bool)
    sizes = (m,) if single else _sizes(columns if columns is not None else [1] * m, m, "columns")
    rates = _rates(arrival, len(sizes), "arrival")
    Wh = np.array(arrival_weight(rates.tolist(), sizes), dtype=float)
    S = np.zeros((n, n))
    for _ in range(iterations):
        BSA = B.T @ S @ A
        try:
            nxt = A.T @ S @ A + W - BSA.T @ np.linalg.solve(Wh * (B.T @ S @ B + U), BSA)
        except np.linalg.LinAlgError:
            raise NumericalBreakdownError("control_riccati: Wh o (B'SB + U) became singular (U must be positive "
                                          "definite)") from None
        nxt = (nxt + nxt.T) / 2
        if not np.all(np.isfinite(nxt)) or np.abs(nxt).max() > 1e14:
            raise NumericalBreakdownError(
                f"control_riccati: the iteration of the control MARE grows without bound at arrival rates "
                f"{rates.tolist()} (below the critical control arrival rate no steady gain stabilises the "
                "loop); pass an explicit gain to simulate_loop")
        if np.abs(nxt - S).max() <= tol * max(1.0, np.abs(nxt).max()):
            S = nxt
            break
        S = nxt
    else:
        raise NumericalBreakdownError(f"control_riccati: the control MARE did not settle within {iterations} "
                                      f"iterations (tol {tol:g}); raise iterations or pass an explicit gain")
    lam = np.repeat(rates, sizes)
    L = np.linalg.solve(Wh * (B.T @ S @ B + U), B.T @ S @ A) / lam[:, None]
    return S, L


# ------------------------------------------------------------------ channels

@dataclass(frozen=True)
class _Channel:
    """One side's receptions: the loss model's float factors over ``d`` channels, the channel of
    each row (sensor side) or column (actuator side), the Bernoulli arrival rates (None when the
    model is not i.i.d.) and the model in words."""

    factors: tuple[LossFactor, ...]
    d: int
    index: np.ndarray
    rates: np.ndarray | None
    words: str


def _channel(arrival: Any, sizes: tuple[int, ...], entry: str) -> _Channel:
    if isinstance(arrival, LossModel):
        loss = checked(arrival, len(sizes), numbers=True)
        losses = loss.bernoulli
        return _Channel(tuple(f.numeric() for f in loss.factors), len(sizes), np.repeat(np.arange(len(sizes)), sizes),
                        None if losses is None else 1 - np.array([float(e) for e in losses]), repr(loss))
    if isinstance(arrival, numbers.Real) and not isinstance(arrival, bool) and 0 <= float(arrival) <= 1:
        p = float(arrival)
        factor = LossFactor((0,), np.array([[p, 1 - p], [p, 1 - p]]), np.array([p, 1 - p]),
                            np.array([[True], [False]]))
        return _Channel((factor,), 1, np.zeros(sum(sizes), np.intp), np.array([p]),
                        f"one Bernoulli channel, arrival rate {p:g}")
    raise InputError(f"{entry}: expected an arrival rate in [0, 1] (one channel) or a symkf loss model with one "
                     f"'sensor' per {'sensor' if entry == 'gamma' else 'actuator'}, got {type(arrival).__name__}")


# ------------------------------------------------------------------ the loop

def _root(M: np.ndarray) -> np.ndarray:
    """A square root ``F`` with ``F F' = M`` of a positive semidefinite ``M``."""
    vals, vecs = np.linalg.eigh(M)
    return vecs * np.sqrt(np.clip(vals, 0.0, None))


def _log_quadratic(x: np.ndarray, M: np.ndarray | None) -> np.ndarray:
    """``log x' M x`` per path (``log ||x||^2`` for None), scaled by each path's largest entry so
    that states beyond ``1e154`` still give finite logs."""
    s = np.abs(x).max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = x / np.where(s > 0, s, 1.0)[:, None]
        q = np.einsum("pi,pi->p", t, t) if M is None else np.einsum("pi,ij,pj->p", t, M, t)
        return 2 * np.log(s) + np.log(q)


def _run(plant: LoopPlant, L: np.ndarray, protocol: str, channels: tuple[_Channel, _Channel],
         received: Sequence[np.ndarray], rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Per path, of the loop driven by the receptions ``received`` (K, paths, channels) of both
    sides: ``"cost"`` ``log x_k' W x_k`` and ``"norm"`` ``log ||x_k||^2`` (``k = 0..K``), and after each update (``k = 0..K-1``)
    ``"error"`` ``log ||x_k - x^_{k|k}||^2`` and ``"trace"`` ``log tr P_{k|k}``, the estimator's
    own account of that error."""
    A, B, C, Q, R = plant.A, plant.B, plant.C, plant.Q, plant.R
    K, m = received[1].shape[:2]
    n, p = A.shape[0], C.shape[0]
    sensors, actuators = channels
    if protocol == "udp":
        lam = actuators.rates[actuators.index]
        same = actuators.index[:, None] == actuators.index[None, :]
        V = np.where(same, (lam * (1 - lam))[:, None], 0.0)
    fP0, fQ, fR = _root(plant.P0), _root(Q), _root(R)
    x = rng.standard_normal((m, n)) @ fP0.T
    xh = np.zeros((m, n))
    P = np.broadcast_to(plant.P0, (m, n, n)).copy()
    eye_p, eye_n = np.eye(p), np.eye(n)
    out: dict[str, list] = {"cost": [], "norm": [], "error": [], "trace": []}
    try:
        for k in range(K):
            out["cost"].append(_log_quadratic(x, plant.W))
            out["norm"].append(_log_quadratic(x, None))
            g = received[0][k][:, sensors.index].astype(float)
            y = x @ C.T + rng.standard_normal((m, p)) @ fR.T
            CP = np.einsum("ij,pjk->pik", C, P)
            # innovation covariance on the received rows, identity on the lost ones: the gain
            # S^{-1} Gamma C P has zero rows where nothing arrived
            S = (np.einsum("pik,jk->pij", CP, C) + R) * g[:, :, None] * g[:, None, :] + eye_p * (1 - g)[:, :, None]
            G = np.linalg.solve(S, CP * g[:, :, None])
            xh = xh + np.einsum("pin,pi->pn", G, g * (y - xh @ C.T))
            J = eye_n - np.einsum("pin,ik->pnk", G, C)              # I - K C, K = G'
            P = J @ P @ J.transpose(0, 2, 1) + np.einsum("pin,ij,pjk->pnk", G, R, G)     # Joseph form
            P = (P + P.transpose(0, 2, 1)) / 2
            out["error"].append(_log_quadratic(x - xh, None))
            out["trace"].append(np.log(np.trace(P, axis1=1, axis2=2)))
            u = -xh @ L.T
            a = received[1][k][:, actuators.index].astype(float)
            x = x @ A.T + (a * u) @ B.T + rng.standard_normal((m, n)) @ fQ.T
            P = A @ P @ A.T + Q
            if protocol == "tcp":
                xh = xh @ A.T + (a * u) @ B.T
            else:
                xh = xh @ A.T + (lam * u) @ B.T
                P = P + B @ (V * np.einsum("pj,pk->pjk", u, u)) @ B.T
            if not np.all(np.isfinite(x)) or not np.all(np.isfinite(P)):
                raise NumericalBreakdownError(f"the simulated loop overflowed float64 at step {k + 1} of {K}: a shorter "
                                              "horizon resolves it")
    except np.linalg.LinAlgError:   # a covariance whose entries left float64 made a solve singular
        raise NumericalBreakdownError(f"the simulated loop's covariances left float64 at step {k + 1} of {K}: "
                                      "a shorter horizon resolves it") from None
    out["cost"].append(_log_quadratic(x, plant.W))
    out["norm"].append(_log_quadratic(x, None))
    return {key: np.array(v) for key, v in out.items()}


def _gain(plant: LoopPlant, nu: _Channel, protocol: str, gain: Any) -> np.ndarray:
    shape = (plant.B.shape[1], plant.n)
    if gain is not None:
        return _matrix(gain, shape, "gain")
    if protocol == "udp":
        raise InputError("gain: the UDP-like loop needs an explicit gain (its optimal controller is nonlinear in "
                         "general, Schenato et al. 2007, Section V); control_riccati(...)[1] is the TCP-like one")
    if nu.rates is None:
        raise InputError("gain: the TCP-like steady gain needs Bernoulli (i.i.d.) control losses; pass a gain")
    single = nu.d == 1 and len(plant.actuator_columns) > 1
    return control_riccati(plant.A, plant.B, plant.W, plant.U,
                           float(nu.rates[0]) if single else nu.rates.tolist(),
                           None if single else list(plant.actuator_columns))[1]


def memory_estimate(plant: LoopPlant, horizon: int, paths: int, outcomes: int | None = None) -> int:
    """Peak bytes (estimate) of one run of :func:`simulate_loop` (``outcomes`` None) or of one of
    :func:`loop_divergence`'s runs over ``outcomes`` joint reception states per step.

    :func:`simulate_loop`: the receptions of both sides (one byte per channel, step and path; the
    chain states as many again), the per-path covariances and their temporaries (about eight
    arrays of ``n^2 + p^2 + n p`` floats) and the four per-step records (and their copy).
    :func:`loop_divergence`: per path and outcome, the next second moments, the loop's maps and
    their temporaries (about six arrays of ``(2n)^2`` floats, and the gains' ``3 n p + 2 n^2``),
    and the twists' values per step and outcome (``(2n)^2 + n^2`` floats)."""
    n, p = plant.n, plant.C.shape[0]
    if outcomes is None:
        channels = len(plant.sensor_rows) + len(plant.actuator_columns)
        step = 8 * paths * 8 * (n * n + p * p + n * p + n + p)
        return 2 * channels * horizon * paths + step + 8 * 8 * (horizon + 1) * paths
    return 8 * outcomes * (paths * (6 * 4 * n * n + 3 * n * p + 2 * n * n) + (horizon + 1) * 5 * n * n)


def _setup(plant: LoopPlant | System, gamma: Any, nu: Any, protocol: str,
           gain: Any) -> tuple[LoopPlant, tuple[_Channel, _Channel], np.ndarray]:
    plant = plant if isinstance(plant, LoopPlant) else plant_of(plant)
    if protocol not in PROTOCOLS:
        raise InputError(f"protocol: expected 'tcp' or 'udp', got {protocol!r}")
    channels = (_channel(gamma, plant.sensor_rows, "gamma"), _channel(nu, plant.actuator_columns, "nu"))
    if protocol == "udp" and channels[1].rates is None:
        raise InputError("nu: the UDP-like estimator uses the expected input Lambda u, defined for Bernoulli "
                         "(i.i.d.) control losses; give an arrival rate or an IID model")
    return plant, channels, _gain(plant, channels[1], protocol, gain)


# ------------------------------------------------------------------ the conditional-moment sampler

@dataclass(frozen=True)
class _Chain:
    """One side's receptions as one chain, the product of its factors' chains: transition ``T``,
    initial law ``init`` and, per joint state, each row's (sensors) or column's (actuators)
    reception as 0/1 floats (``emit``, states x rows)."""

    T: np.ndarray
    init: np.ndarray
    emit: np.ndarray


def _joint(ch: _Channel) -> _Chain:
    T, init, emit = np.ones((1, 1)), np.ones(1), np.zeros((1, ch.d), bool)
    for f in ch.factors:
        T, init = np.kron(T, f.P), np.kron(init, f.init)
        e = np.repeat(emit, len(f.P), axis=0)            # the new factor's state runs fastest, as in kron
        e[:, list(f.sensors)] = np.tile(f.emit, (len(emit), 1))
        emit = e
    return _Chain(T, init, emit[:, ch.index].astype(float))


def _states(channels: tuple[_Channel, _Channel]) -> int:
    """The number of joint reception states of both sides (the sampler's outcomes per step)."""
    return math.prod(len(f.P) for ch in channels for f in ch.factors)


def _gains(plant: LoopPlant, g: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Kalman gains ``K`` and updated covariances ``P_{k|k}`` per path (``P``: paths x n x n, the
    prediction ``P_{k|k-1}``) and reception pattern (rows ``g``, patterns x p: the received rows
    are measured, the lost ones are not): paths x patterns x n x p and paths x patterns x n x n.

    In square-root form: ``P = F F'`` (eigenvalues that rounding made negative taken as 0),
    ``G = R_g^{-1/2} C_g F = U s V'``; then ``K = F V diag(s / (1 + s^2)) U' R_g^{-1/2}`` and
    ``P_{k|k} = F V diag(1 / (1 + s^2)) V' F'`` (Woodbury).  Formed as ``P C' (C P C' + R)^{-1}``
    the gain is lost once ``P``'s scales spread beyond 1e16 (a long burst of lost observations):
    the rounded ``C P C' + R`` then mixes ``P``'s largest scale into its smallest directions."""
    C, R = plant.C, plant.R
    vals, vecs = np.linalg.eigh((P + np.swapaxes(P, -1, -2)) / 2)
    F = vecs * np.sqrt(np.maximum(vals, 0.0))[:, None, :]
    # per pattern: R of the received rows, unit noise on the lost ones (which C_g does not measure)
    Rg = R * (g[:, :, None] * g[:, None, :]) + np.eye(len(C)) * (1 - g)[:, :, None]
    rv, rw = np.linalg.eigh(Rg)
    Rih = (rw / np.sqrt(rv)[:, None, :]) @ np.swapaxes(rw, -1, -2)
    G = (Rih @ (g[:, :, None] * C))[None] @ F[:, None]
    U, s, Vt = np.linalg.svd(G, full_matrices=False)
    FV = F[:, None] @ np.swapaxes(Vt, -1, -2)
    K = (FV * (s / (1 + s * s))[..., None, :]) @ np.swapaxes(U, -1, -2) @ Rih[None]
    Fp = FV * np.sqrt(1 / (1 + s * s))[..., None, :]
    # a pattern measuring fewer rows than n leaves directions of F that G does not see
    rest = F[:, None] @ (np.eye(plant.n) - np.swapaxes(Vt, -1, -2) @ Vt)
    return K, Fp @ np.swapaxes(Fp, -1, -2) + rest @ np.swapaxes(rest, -1, -2)


def _loop_maps(plant: LoopPlant, L: np.ndarray, protocol: str, a: np.ndarray, lam: np.ndarray | None,
               K: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The loop given the receptions, on ``z_k = (e_k, x^_{k|k-1})``, ``e_k = x_k - x^_{k|k-1}``:
    ``z_{k+1} = M z_k + N v_k + (w_k, 0)`` with ``x^_{k|k} = J z_k + K v_k``; ``M``, ``N``, ``J`` for
    gains ``K`` (..., n, p) and control receptions ``a`` (..., m) broadcast together.  (In these
    coordinates ``x = e + x^`` adds parts that the TCP-like filter keeps uncorrelated, where
    ``(x, x^)`` would subtract nearly equal ones once ``x`` is large.)"""
    A, B, C = plant.A, plant.B, plant.C
    n = plant.n
    KC = K @ C
    J = np.concatenate([KC, np.broadcast_to(np.eye(n), KC.shape)], axis=-1)       # x^_{k|k} = x^ + K (C e + v)
    BGL = B @ (a[..., :, None] * L)
    BEL = BGL if protocol == "tcp" else np.broadcast_to(B @ (lam[:, None] * L), BGL.shape)
    # e' = A (I - K C) e - A K v - B (Gamma - E Gamma) L x^_{k|k} + w,  x^' = (A - B E Gamma L) x^_{k|k}
    # (E Gamma: Gamma TCP-like, Lambda UDP-like, so that the first term's x^ part is exactly 0 TCP-like)
    D = np.concatenate([BEL - BGL, A - BEL], axis=-2)
    M = D @ J
    M[..., :n, :n] += A - A @ KC
    N = D @ K
    N[..., :n, :] -= A @ K
    return M, N, J


def _steady(plant: LoopPlant) -> np.ndarray:
    """``P_{k|k-1}`` of the filter that receives everything, iterated from ``P0`` (for the twists'
    value model only: a plant whose filter diverges stops at 1e12)."""
    A, C, Q, R = plant.A, plant.C, plant.Q, plant.R
    P = plant.P0.copy()
    for _ in range(2000):
        CP = C @ P
        nxt = A @ (P - CP.T @ np.linalg.solve(CP @ C.T + R, CP)) @ A.T + Q
        nxt = (nxt + nxt.T) / 2
        if np.allclose(nxt, P, rtol=1e-12, atol=1e-14) or np.abs(nxt).max() > 1e12:
            return nxt
        P = nxt
    return P


#: the largest share of :func:`_moment_sample`'s estimate that paths beyond float64's resolution may
#: carry (their error moves ``log E`` by at most about this much)
MAX_PARTED_SHARE = 0.01

#: how :func:`loop_divergence` samples, in its results' words
SAMPLING = "conditional second moments given the losses, losses from a mixture of twisted laws (importance sampling)"

#: the mixture of :func:`_moment_sample` (module docstring): the losses' own law (defensive),
#: controls twisted, every outcome twisted, a window of lost observations (its share goes to the
#: losses' own law where the observations are not i.i.d.)
MIX = (0.1, 0.25, 0.15, 0.5)


def _moment_sample(plant: LoopPlant, L: np.ndarray, protocol: str, channels: tuple[_Channel, _Channel], K: int,
                   m: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """``log E[x_K' W x_K | losses]`` and ``log dP/dQ`` per path (module docstring, the sampler).

    Per step, every joint reception state ``o = (o_s, o_a)`` of the two sides is scored and one is
    drawn from the path's component of the mixture :data:`MIX` (each component's law is a
    function of the path so far, so every component's path probability is known on every path
    and the ratio ``p / sum_c MIX_c q_c`` is exact: the balance heuristic)."""
    A, B, Q, R, W = plant.A, plant.B, plant.Q, plant.R, plant.W
    n, n2 = plant.n, 2 * plant.n
    sensors, actuators = (_joint(ch) for ch in channels)
    Ns, Na = len(sensors.T), len(actuators.T)
    N = Ns * Na
    T = np.kron(sensors.T, actuators.T)
    a = np.tile(actuators.emit, (Ns, 1))                     # the controls received in joint state o
    lam = None
    if protocol == "udp":
        rates = channels[1].rates[channels[1].index]
        lam = rates
        V = np.where(channels[1].index[:, None] == channels[1].index[None, :], (rates * (1 - rates))[:, None], 0.0)
    Qz, Wz = np.zeros((n2, n2)), np.zeros((n2, n2))
    Qz[:n, :n], Wz = Q, np.tile(W, (2, 2))            # x' W x with x = e + x^
    # the twists' values: H (every outcome, the loop with the steady filter gain) and Hc (the
    # controls' jump linear system x+ = (A - B Gamma L) x), backward from W, per joint state
    Ms, Ns_, _ = _loop_maps(plant, L, protocol, a, lam, _gains(plant, sensors.emit, _steady(plant)[None])[0][0].repeat(Na, axis=0))
    F = A - B @ (actuators.emit[:, :, None] * L)
    noise = np.einsum("oij,jk,olk->oil", Ns_, R, Ns_) + Qz
    H, c, Hc = np.empty((K + 1, N, n2, n2)), np.zeros((K + 1, N)), np.empty((K + 1, Na, n, n))
    H[K], Hc[K] = Wz / np.trace(W), W / np.trace(W)
    for k in range(K - 1, -1, -1):
        nxt = np.einsum("so,oji,ojk,okl->sil", T, Ms, H[k + 1], Ms)
        cn = T @ (c[k + 1] + np.einsum("oij,oij->o", H[k + 1], noise))
        s = max(np.trace(nxt, axis1=1, axis2=2).max(), 1e-300)
        H[k], c[k] = nxt / s, cn / s
        nc = np.einsum("so,oji,ojk,okl->sil", actuators.T, F, Hc[k + 1], F)
        Hc[k] = nc / max(np.trace(nc, axis1=1, axis2=2).max(), 1e-300)
    Sig = np.zeros((m, n2, n2))
    Sig[:, :n, :n] = plant.P0
    P = np.broadcast_to(plant.P0, (m, n, n)).copy()
    logp, logq = np.zeros(m), np.zeros((2, m))
    mix = np.array(MIX)
    # the window component: a burst of lost observations (every sensor) of length ~ (p_lost rho(A)^2)^l
    # at a uniform place, the observations' own law elsewhere; for i.i.d. observations only
    lost = np.flatnonzero(~sensors.emit.any(axis=1))
    iid = lost.size == 1 and np.allclose(sensors.T, sensors.T[0]) and sensors.T[0, lost[0]] > 0
    if not iid:
        mix[3], mix[0] = 0.0, mix[0] + mix[3]
    comp = np.searchsorted(np.cumsum(mix), rng.random(m), side="right")
    if iid:
        p_lost, alpha = sensors.T[0, lost[0]], float(np.abs(np.linalg.eigvals(A)).max())
        # windows no longer than float64 follows: P spans alpha^(2l) (symkf.numeric.montecarlo.float_horizon)
        longest = K if alpha <= 1 else min(K, max(8, int(RESOLUTION_BITS * math.log(2) / math.log(alpha))))
        width, log_len = _burst_lengths(longest, p_lost * alpha ** 2, rng, m)
        start = (rng.random(m) * (K - width + 1)).astype(np.intp)
        ls = np.arange(longest + 1)
        # log sum_{l <= r} pi(l) / (K - l + 1) / p_lost^l: the window mixture's q / p at an end with r losses before it
        log_run = np.logaddexp.accumulate(log_len - np.log(K - ls + 1) - ls * math.log(p_lost))
        run, acc = np.zeros(m, np.intp), np.full(m, log_run[0])
        forced = np.zeros(N)
        forced[lost[0] * Na:(lost[0] + 1) * Na] = 1.0
    rows, parted = np.arange(m), np.zeros(m, bool)
    prev = None
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        for k in range(K):
            p = np.broadcast_to(np.kron(sensors.init, actuators.init), (m, N)) if prev is None else T[prev]
            Kg, Pg = _gains(plant, sensors.emit, P)                              # paths x Ns x ...
            Ko = np.repeat(Kg, Na, axis=1)
            M, Nv, J = _loop_maps(plant, L, protocol, a, lam, Ko)
            Sn = M @ Sig[:, None] @ np.swapaxes(M, -1, -2) + Nv @ R @ np.swapaxes(Nv, -1, -2) + Qz
            Sn = (Sn + np.swapaxes(Sn, -1, -2)) / 2
            hc = np.tile(Hc[k + 1], (Ns, 1, 1))
            Sx = Sn[:, :, :n, :n] + Sn[:, :, :n, n:] + Sn[:, :, n:, :n] + Sn[:, :, n:, n:]       # E[x x' | o]
            h1 = np.clip(np.einsum("poij,oij->po", Sx, hc), 1e-300, None).reshape(m, Ns, Na)
            pr = p.reshape(m, Ns, Na)
            q1 = pr * h1
            q1 = (pr.sum(axis=2, keepdims=True) * q1 / q1.sum(axis=2, keepdims=True)).reshape(m, N)
            q2 = p * np.clip(np.einsum("poij,oij->po", Sn, H[k + 1]) + c[k + 1], 1e-300, None)
            q2 = q2 / q2.sum(axis=1, keepdims=True)
            q = np.select([comp[:, None] == 1, comp[:, None] == 2], [q1, q2], p)
            if iid:
                inside = (comp == 3) & (start <= k) & (k < start + width)
                q = np.where(inside[:, None], p * forced / (p * forced).sum(axis=1, keepdims=True), q)
            o = np.minimum((np.cumsum(q, axis=1)[:, :-1] <= rng.random(m)[:, None]).sum(axis=1), N - 1)
            logp += np.log(p[rows, o])
            logq += np.log(np.stack([q1[rows, o], q2[rows, o]]))
            os_ = o // Na
            if iid:
                run = np.where(os_ == lost[0], run + 1, 0)
                acc = np.logaddexp(acc, log_run[np.minimum(run, longest)])
            Kp, P_post = Kg[rows, os_], Pg[rows, os_]
            if protocol == "udp":
                Jo = J[rows, o]
                Euu = L @ (Jo @ Sig @ np.swapaxes(Jo, -1, -2) + Kp @ R @ np.swapaxes(Kp, -1, -2)) @ L.T
            P = A @ P_post @ A.T + Q
            if protocol == "udp":
                P = P + B @ (V * Euu) @ B.T
            Sig, prev = Sn[rows, o], o
            # TCP-like, E[e e' | losses] is the filter's own P: where the two part by a share of the
            # second moment, float64 lost the small directions of a covariance spread beyond its
            # resolution (the gain is then noise)
            if protocol == "tcp":
                te, th = np.trace(Sig[:, :n, :n], axis1=1, axis2=2), np.trace(Sig[:, n:, n:], axis1=1, axis2=2)
                parted |= np.abs(te - np.trace(P, axis1=1, axis2=2)) > 0.01 * (te + th)
            if not (np.all(np.isfinite(P)) and np.all(np.isfinite(Sig))):
                raise NumericalBreakdownError(f"the loop's conditional second moments left float64 at step {k + 1} "
                                              f"of {K}: a shorter horizon resolves it")
        terms = [np.log(mix[0]) + logp, *(np.log(mix[1:3])[:, None] + logq)]
        if iid:
            terms.append(np.log(mix[3]) + logp + acc)
        logw = logp - np.logaddexp.reduce(np.vstack(terms), axis=0)
        logv = np.log(np.einsum("pij,ij->p", Sig, Wz))
    if not (np.all(np.isfinite(logv)) and np.all(np.isfinite(logw))):
        # a cost that rounding made negative: P's scales spread beyond float64 on some path
        raise NumericalBreakdownError(f"the loop's conditional second moments lost their definiteness in float64 "
                                      f"within {K} steps: a shorter horizon resolves it")
    y = logv + logw
    share = np.exp(y[parted] - y.max()).sum() / np.exp(y - y.max()).sum()
    if share > MAX_PARTED_SHARE:
        raise NumericalBreakdownError(f"paths whose second moments parted from the filter's covariance in float64 "
                                      f"(bursts that spread its scales beyond float64) carry {share:.1%} of the "
                                      f"estimate at {K} steps: a shorter horizon resolves it")
    return logv, logw


# ------------------------------------------------------------------ results

QUANTITIES = ("E[x_k' W x_k]", "E[||x_k||^2]")


@dataclass(frozen=True, repr=False)
class LoopSimulation(JsonDocument):
    """Plain Monte Carlo of the closed loop (:func:`simulate_loop`), steps ``k = 0..horizon``.

    ``log_cost``, ``log_norm``: ``log`` of the sample means of the stage cost ``x_k' W x_k`` and
    of ``||x_k||^2`` (the log scale: they may grow geometrically); ``cost_rel_stderr``,
    ``norm_rel_stderr``: their relative standard errors (the standard errors of the logs, delta
    method); ``resolved``: the steps where the cost's relative standard error is at most
    :data:`~symkf.numeric.montecarlo.MAX_REL_STDERR` and no path carries more than
    :data:`~symkf.numeric.montecarlo.MAX_PATH_SHARE` of the sum (elsewhere the mean sits on loss
    bursts too rare for the sample: :func:`loop_divergence` samples them).  ``log_error``,
    ``log_trace`` (steps ``k = 0..horizon-1``, after the update): ``log`` of the means of the
    estimator's actual error ``||x_k - x^_{k|k}||^2`` and of its own covariance ``tr P_{k|k}``,
    with relative standard errors: both estimators' ``P`` is the covariance of their error
    (TCP-like the Kalman filter's; UDP-like by the derivation in the module docstring), so the two
    means agree within the noise.
    """

    protocol: str
    gain: np.ndarray
    log_cost: np.ndarray
    cost_rel_stderr: np.ndarray
    log_norm: np.ndarray
    norm_rel_stderr: np.ndarray
    resolved: np.ndarray
    log_error: np.ndarray
    error_rel_stderr: np.ndarray
    log_trace: np.ndarray
    trace_rel_stderr: np.ndarray
    paths: int
    seed: int | None
    confidence: float
    channels: tuple[str, str]

    @property
    def horizon(self) -> int:
        return len(self.log_cost) - 1

    @property
    def cost(self) -> np.ndarray:
        """Mean stage cost per step (inf beyond float64)."""
        with np.errstate(over="ignore"):
            return np.exp(self.log_cost)

    @property
    def norm(self) -> np.ndarray:
        """Mean ``||x_k||^2`` per step (inf beyond float64)."""
        with np.errstate(over="ignore"):
            return np.exp(self.log_norm)

    def cost_interval(self, k: int) -> tuple[float, float]:
        """The ``confidence`` interval of ``E[x_k' W x_k]`` (log scale: ``mean exp(+-z rel_stderr)``)."""
        half = _z(self.confidence) * self.cost_rel_stderr[count(k, "k")]
        return float(np.exp(self.log_cost[k] - half)), float(np.exp(self.log_cost[k] + half))

    def to_dict(self) -> dict[str, Any]:
        return {"quantities": list(QUANTITIES), "protocol": self.protocol, "gain": self.gain.tolist(),
                "observations": self.channels[0], "controls": self.channels[1], "horizon": self.horizon,
                "paths": self.paths, "seed": self.seed, "confidence": self.confidence,
                "log_cost": self.log_cost.tolist(), "cost_rel_stderr": self.cost_rel_stderr.tolist(),
                "log_norm": self.log_norm.tolist(), "norm_rel_stderr": self.norm_rel_stderr.tolist(),
                "resolved": self.resolved.tolist(), "log_error": self.log_error.tolist(),
                "error_rel_stderr": self.error_rel_stderr.tolist(), "log_trace": self.log_trace.tolist(),
                "trace_rel_stderr": self.trace_rel_stderr.tolist()}

    def __str__(self) -> str:
        steps = sorted({round(i * self.horizon / 7) for i in range(8)})
        lines = [f"closed loop ({self.protocol.upper()}-like), gain {np.array2string(self.gain, precision=4)}: "
                 f"{self.paths} paths, seed {self.seed}",
                 f"{'k':>6} {QUANTITIES[0]:>16} {QUANTITIES[1]:>16}  rel. stderr"]
        lines += [f"{k:>6} {self.cost[k]:>16.6g} {self.norm[k]:>16.6g}  {self.cost_rel_stderr[k]:.3g}"
                  + ("" if self.resolved[k] else " (not resolved)") for k in steps]
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (f"<LoopSimulation {self.protocol.upper()}-like: {self.paths} paths x {self.horizon} steps, seed "
                f"{self.seed}, E[x'Wx] at k = {self.horizon}: {self.cost[-1]:.6g}, resolved "
                f"{int(self.resolved.sum())} of {self.horizon + 1} steps>")

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(str(self))}</pre>"


def _estimates(logv: np.ndarray, seed: int | None) -> tuple[np.ndarray, np.ndarray]:
    """``log`` of the mean and its relative standard error per step (rows of ``logv``)."""
    zero = np.zeros(logv.shape[1])
    runs = [_weighted_log_mean(v, zero, k, seed, "plain Monte Carlo") for k, v in enumerate(logv)]
    return np.array([r.log_mean for r in runs]), np.array([r.rel_stderr for r in runs])


def simulate_loop(plant: LoopPlant | System, gamma: Any, nu: Any, *, protocol: Literal["tcp", "udp"] = "tcp",
                  gain: Any = None, horizon: int = 100, paths: int = 2000, seed: int | None = 0,
                  confidence: float = 0.95) -> LoopSimulation:
    """Simulate the closed loop of ``plant`` (a :class:`LoopPlant`, or a System with an input,
    :func:`plant_of`) for ``horizon`` steps on ``paths`` paths (module docstring).

    ``gamma``: the observations' arrivals, a rate (one channel for every sensor) or a loss model
    with one sensor per sensor; ``nu``: the controls' arrivals, a rate (one channel) or a loss
    model with one "sensor" per actuator; ``protocol``: ``"tcp"`` (acknowledged) or ``"udp"``;
    ``gain``: ``L`` (m, n) of ``u = -L x^_{k|k}``, by default (TCP-like, Bernoulli controls) the
    steady gain of :func:`control_riccati`.  Receptions are drawn first (factor by factor,
    :func:`symkf.numeric.receptions.sample`), then ``x_0`` and each step's noises, all from
    ``numpy.random.default_rng(seed)``.  With a System as ``plant``, give a common-rate actuator
    model its size (``IID("1/10", d=len(system.actuators))``): symkf's argument check gives a
    model without one the number of the system's sensors.
    """
    plant, channels, L = _setup(plant, gamma, nu, protocol, gain)
    horizon, paths = count(horizon, "horizon", 1), count(paths, "paths", 2)
    _z(confidence)
    budget.check("max_memory", memory_estimate(plant, horizon, paths), "paths x horizon",
                 f"the bytes (estimate) of a closed-loop simulation of {paths} paths over {horizon} steps")
    rng = np.random.default_rng(seed)
    received = [receptions.sample(ch.factors, horizon, paths, ch.d, rng) for ch in channels]
    records = _run(plant, L, protocol, channels, received, rng)
    log_cost, rel = _estimates(records["cost"], seed)
    share = np.exp(records["cost"].max(axis=1) - log_cost) / paths       # the largest path's share of the sum
    return LoopSimulation(protocol, L, log_cost, rel, *_estimates(records["norm"], seed),
                          (rel <= MAX_REL_STDERR) & (share <= MAX_PATH_SHARE), *_estimates(records["error"], seed),
                          *_estimates(records["trace"], seed), paths, seed, confidence,
                          (channels[0].words, channels[1].words))


@dataclass(frozen=True, repr=False)
class LoopDivergence(JsonDocument):
    """Whether ``E[x_k' W x_k]`` of the closed loop stays bounded, from simulation
    (:func:`loop_divergence`): ``result`` is the :class:`~symkf.numeric.montecarlo.DivergenceResult`
    of the three runs (verdict "stable" / "unstable" / "undecided", the margin ``rate``, the
    growth factor per step of ``E[x'Wx]``, with its interval ``[rate_low, rate_high]``, the
    finite-horizon ``growth`` and their intervals)."""

    protocol: str
    gain: np.ndarray
    result: DivergenceResult

    @property
    def verdict(self) -> str:
        return self.result.verdict

    @property
    def rate(self) -> float | None:
        """The estimated growth factor per step of ``E[x'Wx]`` (the margin), None when not resolved."""
        return self.result.rate

    @property
    def rate_interval(self) -> tuple[float, float] | None:
        """Its interval, the lower end widened by the allowance; None when not resolved."""
        r = self.result
        return None if r.rate is None else (r.rate_low, r.rate_high)

    def to_dict(self) -> dict[str, Any]:
        r = self.result
        return {"quantity": QUANTITIES[0], "protocol": self.protocol, "gain": self.gain.tolist(),
                "verdict": r.verdict, "rate": r.rate, "rate_interval": None if r.rate is None else [r.rate_low, r.rate_high],
                "fieller_interval": None if r.rate is None else [r.fieller_low, r.fieller_high],
                "allowance": r.allowance, "growth": r.growth, "growth_interval": [r.growth_low, r.growth_high],
                "confidence": r.confidence, "tolerance": r.tolerance, "paths": r.paths,
                "seeds": [None if r.seed is None else r.seed + j for j in range(3)], "horizons": list(r.horizons),
                "sampling": r.sampling, "effective_sample_sizes": [e.ess for e in r.estimates]}

    def __repr__(self) -> str:
        ri = self.rate_interval
        rate = "not resolved" if ri is None else f"{self.rate:.5g} in [{ri[0]:.5g}, {ri[1]:.5g}]"
        r = self.result
        return (f"<LoopDivergence {self.protocol.upper()}-like: {r.verdict}; growth of E[x'Wx] per step {rate}; "
                f"{r.paths} paths x horizons {', '.join(map(str, r.horizons))}>")

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(repr(self))}</pre>"


#: the least effective sample size (of the three runs') on which :func:`loop_divergence` says "stable"
#: from the growth alone (its margin not resolved)
MIN_ESS = 100


#: the loop sampler's default paths and horizon, at which its verdicts were calibrated over seeds
#: (``benchmarks/calibrate_loop_verify.py``)
PATHS, HORIZON = 4000, 90


def loop_divergence(plant: LoopPlant | System, gamma: Any, nu: Any, *, protocol: Literal["tcp", "udp"] = "tcp",
                    gain: Any = None, horizon: int = HORIZON, paths: int = PATHS, seed: int | None = 0,
                    tolerance: float = 0.01, confidence: float = 0.999, degree: int = 1) -> LoopDivergence:
    """Decide from simulation whether ``E[x_k' W x_k]`` stays bounded (module docstring).

    Three independent runs (seeds ``seed .. seed + 2``) at ``h, 2h, 3h``
    (:func:`symkf.numeric.montecarlo.rate_horizons`, ``3h <= horizon``) estimate ``log E[x_K' W
    x_K]`` from the conditional second moments given sampled losses (:func:`_moment_sample`); the
    margin (growth factor per step) and the verdict follow
    :func:`symkf.numeric.montecarlo._divergence_verdict` (``degree``: the factors ``k`` the allowance
    admits, :func:`~symkf.numeric.montecarlo.polynomial_allowance`), "stable" from the growth alone
    only on effective sample sizes of at least :data:`MIN_ESS`.  Arguments as :func:`simulate_loop`.
    """
    plant, channels, L = _setup(plant, gamma, nu, protocol, gain)
    horizon, paths = count(horizon, "horizon", 8), count(paths, "paths", 2)
    degree = count(degree, "degree", 0)
    if not isinstance(tolerance, float) or tolerance <= 0:
        raise InputError(f"tolerance: expected a positive float, got {tolerance!r}")
    _z(confidence)
    budget.check("max_memory", memory_estimate(plant, horizon, paths, _states(channels)), "paths x horizon",
                 f"the bytes (estimate) of the closed loop's second moments on {paths} paths over {horizon} steps")
    runs = []
    for j, K in enumerate(rate_horizons(horizon, 1)):
        run_seed = None if seed is None else seed + j
        logv, logw = _moment_sample(plant, L, protocol, channels, K, paths, np.random.default_rng(run_seed))
        runs.append(_weighted_log_mean(logv, logw, K, run_seed, SAMPLING))
    result = _divergence_verdict(runs, None, tolerance, confidence, degree, paths, seed)
    if result.verdict == "stable" and result.rate is None and min(e.ess for e in result.estimates) < MIN_ESS:
        # "stable" from the growth alone trusts the sample to have seen the loop's heavy tail, which
        # only ever hides growth: not on weights that degenerated
        result = dataclasses.replace(result, verdict="undecided")
    return LoopDivergence(protocol, L, result)


check_public(globals())
