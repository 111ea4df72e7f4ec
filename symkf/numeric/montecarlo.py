"""Expectations of the filter's covariance: exact enumeration, Monte Carlo, importance sampling.

The stability notion of Sui-You-Fu (eq. 7) and Yang et al. is boundedness
of ``E[P_k]`` over the loss process.  Near the critical loss rate this mean
is dominated by rare long loss bursts, so plain Monte Carlo
(:func:`estimate_mean_trace`) underestimates it; :func:`log_mean_trace`
samples final bursts of the theory's decisive loss pattern under every loss
model, with exact likelihood ratios that keep it unbiased (checked against
:func:`exact_mean_covariances`).  :func:`divergence_test` turns
``E[tr P_k]`` at three horizons into an estimate of the margin
``alpha^2 rho`` and a verdict.  Every result records its seed, sample sizes
and confidence level: simulation is evidence, not proof.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from statistics import NormalDist
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
import sympy as sp

from .. import budget
from . import receptions
from ..errors import BudgetError, InputError, ShapeError, SymkfError
from ..exact.algebraic import AlgebraicNumber
from ..arguments import check_public, count, float_array
from ..exact.perron import perron_float
from ..exact.numbers import sympify, to_exact
from .filters import (FloatSystem, _positive, _run, exact_covariances, log_traces, real_form, receival_table,
                      traces_into)
from ..model.loss import LossModel, checked
from .receptions import LossFactor, chain_states, cumulative, emit_into, groups
from ..model.system import System
from ..run.progress import progress
from ..run.sweep import sweep

if TYPE_CHECKING:
    from ..engine.stability import Verdict

#: paths per batch: bounds memory and moves the progress bar
CHUNK = 50_000
#: plain Monte Carlo resolves E[tr P_k] at step k when the relative standard error is at most
#: this and no single path carries more than MAX_PATH_SHARE of the sum (a diverging filter's
#: mean sits on bursts too rare for the sample; the intervals of those steps mean nothing)
MAX_REL_STDERR = 0.25
MAX_PATH_SHARE = 0.1


def _progress(total: int, work: int, desc: str):
    """A bar over ``total`` chunks of ``work`` filter steps, shown only for long runs."""
    return progress(total, desc, enabled=None if work >= 5 * 10 ** 7 else False)


# ------------------------------------------------------------ exact enumeration

def _patterns(d: int, length: int) -> np.ndarray:
    """All receival-code sequences of ``length`` steps as (length, 2^(d length)) codes."""
    budget.check_power("max_patterns", 2, d * length, "horizon", "the number of receival sequences 2^(d (horizon-1)) "
                       "to enumerate (estimate_mean_trace simulates instead)")
    count = 2 ** (d * length)
    p = np.arange(count)
    return (p[None, :] >> (d * np.arange(length))[:, None]) & (2 ** d - 1)


def pattern_probabilities(loss: LossModel, codes: np.ndarray) -> np.ndarray:
    """Float probability of each code sequence (columns of ``codes``), by the forward recursion.

    Vectorised over sequences; agrees with :meth:`LossChain.sequence_probability`.
    """
    P, init, emit = loss.numeric()
    state_code = (emit.astype(np.intp) << np.arange(emit.shape[1])).sum(axis=1)
    alpha = init[None, :] * (state_code[None, :] == codes[0][:, None])
    for c in codes[1:]:
        alpha = (alpha @ P) * (state_code[None, :] == c[:, None])
    return alpha.sum(axis=1)


def exact_mean_covariances(system: System, loss: LossModel, horizon: int,
                           exact: bool = False) -> np.ndarray | list[sp.Matrix]:
    """``E[P_{k|k-1}]`` for k = 0..horizon-1 by enumerating every receival sequence.

    ``P_{k|k-1}`` depends on ``gamma_0..gamma_{k-1}``, so the 2^(d(horizon-1))
    sequences of length horizon-1, weighted by their probabilities, give all
    horizon expectations at once.  ``exact=False``: float64, the filter
    vectorised over sequences, probabilities by the forward recursion.
    ``exact=True``: sympy, :func:`~symkf.numeric.filters.exact_covariances` and
    :meth:`LossChain.sequence_probability` per sequence (small cases only).
    """
    horizon = _positive(horizon, "horizon")
    loss = checked(loss, system)
    codes = _patterns(system.d, horizon - 1)
    table = receival_table(system.d)
    if exact:
        total = [sp.zeros(system.n, system.n) for _ in range(horizon)]
        for col in codes.T:
            seq = [tuple(int(g) for g in table[c]) for c in col]
            p = loss.sequence_probability(seq) if seq else sp.Integer(1)
            if p != 0:
                for k, Pk in enumerate(exact_covariances(system, seq)):
                    total[k] += p * Pk
        return [M.applyfunc(lambda e: sp.radsimp(sp.expand(e, complex=True))) for M in total]
    weights = pattern_probabilities(loss, codes) if horizon > 1 else np.ones(1)
    states = np.vstack([codes, np.zeros((1, codes.shape[1]), np.intp)])
    model = real_form(system)
    P, vech = _run(model, states, table, "all", 50)
    mean = np.einsum("p,pkt->kt", weights, P)
    full = vech.unpack(mean)
    if model.n != system.n:   # back from the real form: P = 2 (P_r11 + i P_r21)
        n = system.n
        full = 2 * (full[:, :n, :n] + 1j * full[:, n:, :n])
    return full


def exact_mean_trace(system: System, loss: LossModel, horizon: int) -> np.ndarray:
    """``E[tr P_{k|k-1}]``, k = 0..horizon-1, by exact enumeration (float64)."""
    return np.real(np.trace(exact_mean_covariances(system, loss, horizon), axis1=1, axis2=2))


# ------------------------------------------------------------------ Monte Carlo

#: bytes per value of a per-step record of the command line (the step's mean, low and high; 32 more
#: per step for the mean's float): ``Simulation.to_dict``'s floats, tuples and lists, and with
#: ``--json`` also ``json.dumps(..., indent=2)``'s chunks and text.  Chosen so that ``32 + 3
#: RECORD_BYTES`` per step covers the peak RSS measured above the simulation's own, all steps
#: resolved, with the lists' and the text's growth at long horizons (docs/performance.md)
RECORD_BYTES = {"text": 52, "json": 152}


def memory_estimate(system: System, loss: LossModel, horizon: int, paths: int, *, components: int | None = None,
                    records: str | None = None, jobs: int = 1) -> int:
    """Peak bytes of the arrays one simulation allocates, phase by phase (the largest phase counts).

    ``components is None``: :func:`simulate_traces` / :func:`estimate_mean_trace` (plain Monte
    Carlo, chunks of :data:`CHUNK` paths) and, with ``records`` (``"text"`` or ``"json"``), the
    command line's per-step records of the mean and its interval (:data:`RECORD_BYTES`).  Otherwise
    :func:`burst_sample` with that many burst components, on ``jobs`` processes.  Counted, per
    chunk of ``m`` paths and ``K`` steps: the receptions and chain states; plain Monte Carlo, the
    kernel writes ``tr P`` into the traces itself (:func:`symkf.numeric.filters.traces_into`; its
    buffer is one step's receptions of a block of paths);
    for bursts the kernel's log traces ``8 (K + 1) m``
    (:func:`symkf.numeric.filters.log_traces`: the kernel writes the logs), the law table, the likelihood
    ratios ``8 C K m`` and their tail sums (one more of that size), and the log-trace
    rows; the traces ``8 paths K`` kept whole (from the first chunk on: a row per step, in
    Fortran order, :func:`simulate_traces`) and the standard deviation's copy of them; per path results ``72 paths`` for
    bursts.  Checked against measured peak RSS in
    ``tests/numeric/test_memory_estimate.py``.
    """
    d, K = system.d, horizon
    if components is None:
        # a chunk's chain states (one byte per sensor and step) and receptions beside the traces,
        # counted whole: in Fortran order every chunk writes into every step's row, so that the
        # first chunk already touches (huge) pages all along them
        m = min(paths, _trace_chunk(K, d))
        phases = [d * K * m + max(8 * K * m, d * K * m) + 8 * paths * K, 16 * paths * K]
        if records is not None:
            phases.append(K * (32 + 3 * RECORD_BYTES[records]))
        return max(phases)
    m = min(paths, _burst_chunk_size(components, K))
    two_state = all(len(f.P) == 2 for f in loss_factors(loss, d))
    # held to the chunk's end: law table, last transition index, log-trace rows (logtr is a view of
    # them), receptions, chain states, likelihood ratios
    held = 24 * (K + 1) * m + d * K * m + (d if two_state else 8) * K * m + 8 * components * K * m
    kernel = 8 * (K + 1) * m + 24 * (K + 1) * m
    tails = 8 * components * (K + 1) * m   # written in place (_burst_chunk)
    return min(jobs, -(-paths // m)) * (held + max(kernel, tails, 24 * K * m)) + 72 * paths


def _trace_chunk(horizon: int, d: int) -> int:
    """Paths per chunk of :func:`_simulate`: a chunk's receptions and chain states take 2 horizon x
    paths x d bytes, about 32 MB, in whole blocks of 64 paths."""
    return min(CHUNK, max(64, 2 ** 24 // (horizon * d) // 64 * 64))


def _simulate(system: System, loss: LossModel, horizon: int, paths: int, seed: int | None) -> np.ndarray:
    """tr P_{k|k-1} (paths, horizon) in Fortran order (:func:`simulate_traces`), receptions drawn from ``loss``
    per factor (:meth:`LossModel.sample`)."""
    horizon, paths = _positive(horizon, "horizon"), _positive(paths, "paths")
    # refused before numpy tries to allocate the arrays
    budget.check("max_memory", memory_estimate(system, loss, horizon, paths), "paths x horizon",
                 f"the bytes (estimate) of a simulation of {paths} paths over {horizon} steps")
    model = real_form(system)
    factors = loss_factors(loss, system.d)
    rng = np.random.default_rng(seed)
    # Fortran order: the kernel writes each step's traces of a block of paths contiguously (traces_into)
    traces = np.empty((horizon, paths)).T
    chunk = _trace_chunk(horizon, system.d)
    chunks = range(0, paths, chunk)
    with _progress(len(chunks), paths * horizon, "simulate") as bar:
        for start in chunks:
            stop = min(start + chunk, paths)
            received = receptions.sample(factors, horizon, stop - start, system.d, rng)
            traces_into(model, received, traces, start)   # tr P beyond float64 is inf; log_mean_trace keeps logs
            bar.update()
    return traces


def simulate_traces(system: System, loss: LossModel, horizon: int, paths: int,
                    seed: int | None = None) -> np.ndarray:
    """``tr P_{k|k-1}`` as an array (paths, horizon), k = 0..horizon-1 (Sui-You-Fu eq. 9).

    Receival sequences are drawn from ``loss`` with ``numpy.random.default_rng(seed)``, factor by
    factor (:meth:`~symkf.model.loss.LossModel.sample`: independent sensors never build the joint
    ``2^d`` chain; memory is linear in ``d``).

    The array is in Fortran order: the transposed view of a C-contiguous (horizon, paths) buffer,
    so that a step's traces of all paths are contiguous in memory (the compiled kernel writes them
    so, without a transposing copy).  Its values do not depend on the order; code that needs a
    path's traces contiguous takes ``np.ascontiguousarray(traces)``.
    """
    return _simulate(system, loss, horizon, paths, seed)


@dataclass(frozen=True)
class TraceEstimate:
    """An estimate of ``E[tr P_{k|k-1}]``, k = 0..horizon-1, with confidence intervals on the log
    scale (delta method: ``mean * exp(+-z stderr / mean)``, positive like the trace itself).

    Plain Monte Carlo: a step is ``resolved`` when its relative standard error is at most
    :data:`MAX_REL_STDERR` and no path carries more than :data:`MAX_PATH_SHARE` of the sum;
    elsewhere the mean is carried by bursts too rare for ``paths`` (a diverging filter: use
    :func:`log_mean_trace`) and ``low``, ``high`` are NaN.  ``sampling`` names the law the
    paths were drawn from.
    """

    mean: np.ndarray
    low: np.ndarray
    high: np.ndarray
    stderr: np.ndarray
    confidence: float
    paths: int
    horizon: int
    seed: int | None
    sampling: str
    resolved: np.ndarray


    def covers(self, values: np.ndarray) -> np.ndarray:
        """Which steps' intervals contain ``values``."""
        values = float_array(values, "values")
        if values.shape not in ((), self.low.shape):
            raise ShapeError(f"values: expected one value or {self.low.shape[0]} (one per step), got shape {values.shape}")
        return (self.low <= values) & (values <= self.high)


def _z(confidence: float) -> float:
    if not isinstance(confidence, float) or not 0 < confidence < 1:
        raise InputError(f"confidence: expected a float in (0, 1), got {confidence!r}")
    return NormalDist().inv_cdf(0.5 + confidence / 2)


def estimate_mean_trace(system: System, loss: LossModel, horizon: int, paths: int,
                        seed: int | None = None, confidence: float = 0.95) -> TraceEstimate:
    """Plain Monte Carlo estimate of ``E[tr P_{k|k-1}]``, k = 0..horizon-1, with normal intervals
    (the mean of :func:`simulate_traces`)."""
    z = _z(confidence)
    f = _simulate(system, loss, horizon, paths, seed)
    mean = f.mean(axis=0)
    stderr = f.std(axis=0, ddof=1) / math.sqrt(len(f)) if len(f) > 1 else np.full_like(mean, np.inf)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        rel = stderr / mean
        resolved = np.isfinite(mean) & (rel <= MAX_REL_STDERR) & (f.max(axis=0) <= MAX_PATH_SHARE * f.sum(axis=0))
        low, high = (np.where(resolved, mean * np.exp(s * z * rel), np.nan) for s in (-1, 1))
    return TraceEstimate(mean, low, high, stderr, confidence, len(f), f.shape[1], seed, repr(loss), resolved)


# ------------------------------------------------------------------ patterns

def _real(value: Any, entry: str) -> float:
    """A float tuning value (a burst pattern only steers sampling, never a verdict)."""
    return float(value) if isinstance(value, (int, float)) else float(to_exact(value, entry))


def burst_pattern(system: System, verdict) -> tuple[tuple[tuple[int, ...], ...], sp.Expr]:
    """The limiting block's decisive loss pattern, one tuple of lost sensors per phase, and its growth.

    ``verdict`` is :func:`symkf.engine.stability.stability`'s: in the limiting eigen-block
    (largest margin ``alpha_i^2 rho_i``, Sui-You-Fu eq. 36) with class period ``g``,
    the decisive hyperplane lists the elements (sensor, phase) that may be received while
    ``O_N^i`` stays rank deficient.  Returns, per phase ``0..g-1``, the sensors that must
    be lost (the elements outside the hyperplane), and the exact growth ``alpha_i^(2g)``
    of ``P`` per period while the pattern holds.
    """
    if verdict.limiting_block is None:  # no eigenvalue with |lambda| >= 1: nothing grows, nothing to steer
        return ((),), sp.Integer(1)
    cert = verdict.certificate[verdict.limiting_block]
    received = set(cert.decisive_elements)
    phases = tuple(tuple(j for j, name in enumerate(system.sensor_names) if (name, phase) not in received)
                   for phase in range(cert.class_period))
    return phases, sympify(cert.modulus) ** (2 * cert.class_period)


def exact_growth_rate(verdict: "Verdict") -> AlgebraicNumber:
    """The exact per-step growth rate of ``E[tr P_k]``: ``max_i alpha_i^2 rho_i`` when unstable,
    else 1 (bounded), as an AlgebraicNumber."""
    return max(verdict.margins) if not verdict.stable else AlgebraicNumber.from_expr(sp.Integer(1))


def _verdict(system: System, loss: LossModel):
    from ..engine.stability import stability  # the engine imports nothing from simulation
    return stability(system, loss)


# ------------------------------------------------------------------ loss bursts

def _template(pattern: Any, d: int) -> tuple[tuple[int, ...], ...]:
    """A burst template: one tuple of sensor indices per phase of the period."""
    if isinstance(pattern, (list, tuple)) and pattern and all(isinstance(i, int) for i in pattern):
        pattern = [pattern]
    try:
        phases = tuple(tuple(sorted(set(int(i) for i in ph))) for ph in pattern)
    except TypeError:
        raise InputError(f"pattern: expected sensor indices or a list of them per phase, got {pattern!r}") from None
    if not phases or not any(phases) or any(i < 0 or i >= d for ph in phases for i in ph):
        raise InputError(f"pattern: expected non-empty sets of sensor indices in 0..{d - 1}, got {pattern!r}")
    return phases


# ------------------------------------------------------------------ final bursts, any loss model

def loss_factors(loss: LossModel, d: int) -> list[LossFactor]:
    """The loss model's independent factors in float64 (never the joint 2^d chain of independent sensors)."""
    return [f.numeric() for f in checked(loss, d, numbers=True).factors]


#: weight of the original law at each step inside a burst: keeps every ratio p/q below 1/DEFENSIVE.
#: Per step, so a burst path stays in the pattern for L steps with probability ~(1 - DEFENSIVE)^L,
#: which must stay large at the horizons simulated: 0.995^200 = 0.37, where 0.05 would leave
#: 0.95^196 = 4e-5 of the paths a full burst, too few for a sample to carry the mean (unbiased
#: either way: exact ratios; docs/simulation.md)
DEFENSIVE = 0.005


@dataclass(frozen=True)
class _Tilt:
    """One factor's burst law for one pattern: per phase ``r`` the transition into a state at
    time ``k = r mod g`` (``cum``) and ``log(q/p)`` of every transition (``logr``); ``rate`` is
    the factor's burst probability per period (Perron root of its restricted transfer)."""

    cum_init: np.ndarray
    cum: np.ndarray
    logr_init: np.ndarray
    logr: np.ndarray
    rate: float


def _factor_tilt(f: LossFactor, allowed: np.ndarray, weights: np.ndarray | None = None) -> _Tilt:
    """The chain conditioned to stay in the pattern (Doob h-transform of the restricted
    transfer ``M_H``, Sui-You-Fu eq. 36), mixed with ``DEFENSIVE`` of the original law.

    ``allowed`` (g, d): which sensors may be received at each phase.  ``D_r`` keeps the
    states whose received sensors are all allowed at phase ``r``; ``v_r`` is the right
    Perron vector of the one-period transfer seen from phase ``r``; the conditioned step
    into phase ``r`` is ``P(x, y) D_r(y) v_r(y) / (P D_r v_r)(x)``.  ``weights`` (g, states),
    nonnegative, replaces the 0/1 ``D_r``: the chain twisted by the multiplicative functional
    ``prod_k D(x_k)``, whose growth per period is then the Perron root ``rate``.
    """
    g = allowed.shape[0]
    D = (np.array([np.all(~f.emit | allowed[r][list(f.sensors)], axis=1) for r in range(g)], float)
         if weights is None else np.asarray(weights, float))
    M = np.eye(len(f.P))
    for r in range(1, g + 1):
        M = M @ f.P * D[r % g]
    rate, v0 = perron_float(M)
    v = [v0] * g
    for r in range(g - 1, 0, -1):
        nxt = f.P @ (D[(r + 1) % g] * v[(r + 1) % g])
        v[r] = nxt / nxt.max() if nxt.max() > 0 else nxt

    def mix(p: np.ndarray, weight: np.ndarray) -> np.ndarray:
        q = p * weight
        total = q.sum(axis=-1, keepdims=True)
        q = np.divide(q, total, out=np.array(p, float), where=total > 0)
        return (1 - DEFENSIVE) * q + DEFENSIVE * p

    q_init = mix(f.init, D[0] * v[0])
    q = np.stack([mix(f.P, (D[r] * v[r])[None, :]) for r in range(g)])
    with np.errstate(divide="ignore", invalid="ignore"):
        logr_init = np.where(f.init > 0, np.log(q_init) - np.log(f.init), 0.0)
        logr = np.where(f.P[None] > 0, np.log(q) - np.log(f.P)[None], 0.0)
    return _Tilt(cumulative(q_init), cumulative(q), logr_init, logr, rate)


@dataclass(frozen=True)
class BurstPlan:
    """Importance sampling of final bursts: ``allowed`` (components, g, d) lists, per
    component (the decisive pattern and its shifts by whole phases) and phase, the sensors
    that may be received; ``growth`` is ``P``'s growth per period inside the pattern
    (``alpha^(2g)``), used with the patterns' burst probability to tilt the burst length."""

    allowed: np.ndarray
    growth: float

    @property
    def period(self) -> int:
        """The pattern's period ``g`` (phases)."""
        return self.allowed.shape[1]

    def describe(self, names: Sequence[str]) -> str:
        """The plan in words: the sensors lost at each phase, and the number of shifts."""
        lost = "; ".join(f"{', '.join(names[j] for j in range(len(names)) if not a[j])} at phase {k}"
                         for k, a in enumerate(self.allowed[0]) if not a.all()) or "nothing"
        return f"final bursts losing {lost} (and {len(self.allowed) - 1} shifted or tied pattern(s))"


def burst_plan(system: System, pattern: Any, growth: Any) -> BurstPlan:
    """A :class:`BurstPlan` from ``pattern`` and ``growth`` per period; every cyclic shift of
    the pattern is a component (a rank-deficient pattern stays one under a shift of time).

    ``pattern``: the sensors lost in a burst, as a list of sensor indices or one such list per
    phase of a period (``[[0], []]`` for Sui-You-Fu's 90-degree rotation, where ``C A^2`` is
    parallel to ``C`` and losing every other packet already blinds the filter); ``growth``:
    the factor ``alpha^(2 g)`` by which ``P`` grows per period while the pattern holds."""
    phases = _template(pattern, system.d)
    g = len(phases)
    base = np.ones((g, system.d), bool)
    for r, ph in enumerate(phases):
        base[r, list(ph)] = False
    shifts = []
    for c in range(g):
        a = np.roll(base, c, axis=0)
        if not any(np.array_equal(a, b) for b in shifts):
            shifts.append(a)
    growth_f = _real(growth, "growth")
    if growth_f <= 0:
        raise InputError(f"growth: expected a positive growth per period, got {growth}")
    return BurstPlan(np.stack(shifts), growth_f)


def verdict_plan(system: System, verdict, loss: LossModel | None = None) -> BurstPlan:
    """The :class:`BurstPlan` of the exact verdict's limiting block (its decisive hyperplane).

    With ``loss``, every hyperplane of that block whose burst rate (float Perron root of its
    restricted transfer) ties with the largest is a component too: with two alike sensors
    the pattern through either carries the mean, and tilting toward one only leaves the
    other to rare, heavily weighted paths (on ``ge-two-sensors`` the run means then come out low).
    """
    phases, growth = burst_pattern(system, verdict)
    # the engine's own exact growth, only steering the sampling: a float (burst_plan's input caps
    # are for numbers a user gives; a dense A's alpha^(2g) is a root of a degree-28 polynomial)
    plan = burst_plan(system, phases if any(phases) else [list(range(system.d))], float(growth))
    if loss is None or verdict.limiting_block is None:   # no block decides: no tie to search
        return plan
    from ..engine.search import capped_hyperplanes  # the engine imports nothing from simulation
    from ..engine.blocks import block_rows
    br = block_rows(system)[verdict.limiting_block]
    if br.class_period != plan.period:
        return plan
    try:   # every hyperplane (through the elements' flats when they have several generators)
        sets = capped_hyperplanes(br)
    except BudgetError:   # no ties searched where listing is refused
        return plan
    if len(sets) > budget.LIMITS.max_tie_search:
        return plan
    masks = []
    for H in sets:
        a = np.zeros((br.class_period, system.d), bool)
        for i in H:
            a[br.elements[i].phase, br.elements[i].sensor] = True
        masks.append(a)
    factors = loss_factors(loss, system.d)
    rates = [math.prod(_factor_tilt(f, a).rate for f in factors) for a in masks]
    best = max(rates)
    allowed = list(plan.allowed)
    for a, r in zip(masks, rates):
        if r >= best * (1 - 1e-9) and not any(np.array_equal(a, b) for b in allowed):
            allowed.append(a)
    return BurstPlan(np.stack(allowed), plan.growth)


@dataclass(frozen=True)
class LogMeanEstimate:
    """``log E[tr P_{K|K-1}]`` at ``K = horizon`` with the relative standard error of the mean
    (delta method: the stderr of ``log`` of the mean), effective sample size and seed."""

    log_mean: float
    rel_stderr: float
    ess: float
    paths: int
    horizon: int
    seed: int | None
    sampling: str


def _burst_lengths(horizon: int, per_step: float, rng: np.random.Generator, paths: int) -> tuple[np.ndarray, np.ndarray]:
    """Final-burst lengths ``L`` in 0..horizon: 9/10 from a law ``~ per_step^L`` (the
    contribution of a burst of length ``L`` to the mean), 1/10 uniform (defensive)."""
    L = np.arange(horizon + 1)
    if per_step > 0:
        log_tilt = L * math.log(per_step)
        tilt = np.exp(log_tilt - log_tilt.max())
    else:
        tilt = (L == 0).astype(float)
    law = 0.9 * tilt / tilt.sum() + 0.1 / (horizon + 1)
    draw = np.minimum(np.searchsorted(np.cumsum(law), rng.random(paths), side="right"), horizon)
    return draw, np.log(law)


def burst_sample(system: System, loss: LossModel, horizon: int, paths: int, seed: int | None,
                 plan: BurstPlan | None, jobs: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """``log tr P_{K|K-1}`` (``K = horizon``) and the log likelihood ratio ``log dP/dQ`` per path.

    Without a plan: plain Monte Carlo (ratios 0).  With one, each path picks a component
    (uniformly) and a final-burst length ``L``; states ``X_0..X_{K-L-1}`` follow the loss
    law, ``X_{K-L}..X_{K-1}`` the component's conditioned chain (:func:`_factor_tilt`).  The
    ratio is exact: ``dQ/dP = mean_c sum_L pi(L) prod_{k >= K-L} q_c / p``, summed over
    every ``(c, L)`` that could have produced the path, so the estimator is unbiased for
    any plan.  Paths run in chunks (at most 32768 paths), each with its own child of
    ``SeedSequence(seed)``, on ``jobs`` processes (:func:`symkf.run.sweep.sweep`): the result
    does not depend on ``jobs``.
    """
    model = real_form(system)
    factors = loss_factors(loss, system.d)
    tilts = tuple(tuple(_factor_tilt(f, a) for f in factors) for a in plan.allowed) if plan is not None else ()
    budget.check("max_memory", memory_estimate(system, loss, horizon, paths, components=max(len(tilts), 1), jobs=jobs),
                 "paths x horizon", f"the bytes (estimate) of a burst sample of {paths} paths over {horizon} steps")
    chunk = _burst_chunk_size(max(len(tilts), 1), horizon)
    sizes = [min(chunk, paths - start) for start in range(0, paths, chunk)]
    seeds = np.random.SeedSequence(seed).spawn(len(sizes))
    chunk = functools.partial(_burst_chunk, model, tuple(factors), tilts,
                              None if plan is None else (plan.period, plan.growth), horizon)
    # no bar of its own: inside a caller's (divergence_test's) it moves that one, chunk by chunk
    parts = sweep(chunk, list(zip(sizes, seeds)), jobs=jobs, progress=False, cost=_chunk_paths)
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def _chunk_paths(task: tuple[int, np.random.SeedSequence]) -> int:
    return task[0]


def _burst_chunk_size(components: int, horizon: int) -> int:
    """Paths per chunk of :func:`burst_sample`.  A chunk holds components x horizon x paths
    likelihood ratios: about 1.6e7 floats at most; 32768 paths at most, so that jobs = 2 has two
    chunks from 32769 paths on (the chunks, not jobs, fix the random streams: default runs of
    20 000 paths are one chunk)."""
    return max(1024, min(32768, 2 ** 24 // (components * horizon)))


def _burst_chunk(model: FloatSystem, factors: tuple[LossFactor, ...], tilts: tuple, plan: tuple[int, float] | None,
                 K: int, task: tuple[int, np.random.SeedSequence]) -> tuple[np.ndarray, np.ndarray]:
    """One chunk of :func:`burst_sample` (module level, so worker processes can run it)."""
    m, seed = task
    rng = np.random.default_rng(seed)
    C = len(tilts)
    if plan is not None:
        g, growth = plan
        burst = math.prod(t.rate for t in tilts[0])
        L, log_law = _burst_lengths(K, (burst * growth) ** (1 / g), rng, m)
        comp = rng.integers(0, C, m)
        # law index per (step, path): 0 = the loss model, 1 + c g + r = component c's burst law at phase r
        table = np.where(np.arange(K)[:, None] >= K - L[None, :],
                         1 + comp[None, :] * g + (np.arange(K) % g)[:, None], 0)
        table[0] = np.where(L >= K, 1 + comp * g, 0)
    else:
        g, table = 1, None
    received = np.empty((K, m, model.d), bool)
    lr = np.zeros((C, K, m))
    for group in groups(factors):
        index = [factors.index(f) for f in group]
        # first[t, j, s], step[t, j, x, s]: cumulative law of the first state / next state under law t
        first = np.stack([np.stack([cumulative(f.init) for f in group])]
                         + [np.stack([tilt[i].cum_init for i in index]) for tilt in tilts for _ in range(g)])
        step = np.stack([np.stack([cumulative(f.P) for f in group])]
                        + [np.stack([tilt[i].cum[r] for i in index]) for tilt in tilts for r in range(g)])
        x = chain_states(first, step, table, rng, (K, m, len(group)))
        for j, i in enumerate(index if tilts else ()):
            if all(np.abs(t[i].logr).max() < 1e-12 and np.abs(t[i].logr_init).max() < 1e-12 for t in tilts):
                continue        # a sensor free in every component: its burst law is the loss law
            # transition (phase r, from s, to s') at flat index (r S + s) S + s': one take per sensor
            S = tilts[0][i].logr.shape[-1]
            at = ((np.arange(1, K) % g)[:, None] * S + x[:-1, :, j]) * S + x[1:, :, j]
            for c, tilt in enumerate(tilts):
                lr[c, 0] += tilt[i].logr_init[x[0, :, j]]
                lr[c, 1:] += tilt[i].logr.ravel().take(at)
        emit_into(received, group, x)
    logtr = log_traces(model, received)[:, K]
    if plan is None:
        return logtr, np.zeros(m)
    return logtr, _final_burst_log_ratio(lr, log_law)


def _final_burst_log_ratio(lr: np.ndarray, log_law: np.ndarray) -> np.ndarray:
    """``log dP/dQ`` per path of a final-burst mixture: ``dQ/dP = mean_c sum_L pi(L) prod_{k >= K-L}
    q_c / p``, from ``lr[c, k, path] = log(q_c / p)`` of the transition into step ``k`` under
    component ``c``'s burst law and ``log_law[L] = log pi(L)``, ``L = 0..K``."""
    C, K, m = lr.shape
    # the likelihood ratios' tail sums and the burst lengths' law, in one array written in place:
    # each temporary of C K m floats would cost the zeroing of its fresh pages (docs/performance.md)
    tail = np.empty((C, K + 1, m))
    tail[:, 0] = 0.0
    np.cumsum(lr[:, ::-1], axis=1, out=tail[:, 1:])
    tail += log_law[None, :, None]
    terms = tail.reshape(-1, m)
    top = terms.max(axis=0)                                  # log-sum-exp, shifted by the largest term
    terms -= top
    np.exp(terms, out=terms)
    return math.log(C) - top - np.log(terms.sum(axis=0))


def log_mean_trace(system: System, loss: LossModel, horizon: int, paths: int, seed: int | None = None,
                   plan: BurstPlan | None = None, jobs: int = 1) -> LogMeanEstimate:
    """``log E[tr P_{K|K-1}]`` by :func:`burst_sample` (plain Monte Carlo without ``plan``).

    Works in log space throughout: ``E = mean(w tr P)`` with ``log w + log tr P`` shifted by
    its maximum, so neither weights nor covariances overflow.
    """
    horizon, paths = _positive(horizon, "horizon"), _positive(paths, "paths")
    if paths < 2:
        raise InputError("paths: at least 2 are needed for a standard error")
    logtr, logw = burst_sample(system, loss, horizon, paths, seed, plan, jobs)
    return _weighted_log_mean(logtr, logw, horizon, seed,
                             "plain Monte Carlo" if plan is None else plan.describe(system.sensor_names))


def _weighted_log_mean(logv: np.ndarray, logw: np.ndarray, horizon: int, seed: int | None,
                      sampling: str) -> LogMeanEstimate:
    """``log E[v]`` from per-path ``log v`` and log likelihood ratios ``log w`` (``E = mean(w v)``),
    shifted by the largest ``log w + log v`` so that neither overflows, with its relative standard
    error and the weights' effective sample size."""
    y = logv + logw
    top = float(np.max(y))
    f = np.exp(y - top)
    mean = float(f.mean())
    w = np.exp(logw - logw.max())
    return LogMeanEstimate(top + math.log(mean), float(f.std(ddof=1) / mean / math.sqrt(len(f))),
                           float(w.sum() ** 2 / (w ** 2).sum()), len(f), horizon, seed, sampling)


# ------------------------------------------------------------------ divergence

@dataclass(frozen=True)
class DivergenceResult:
    """Verdict on the boundedness of ``E[tr P_k]`` from ``log E[tr P_k]`` at three horizons.

    ``horizons = (h, 2h, 3h)`` (multiples of the pattern's period), one independent run each.
    ``rate`` is the bias-corrected estimate of the margin ``m`` (the exact ``alpha^2 rho``):
    ``E_k = a m^k + b + o(m^k)`` on both sides of the threshold, so the difference ratio
    ``m^h = (E_{3h} - E_{2h}) / (E_{2h} - E_h)`` removes the bounded part ``b`` exactly
    (:func:`margin_interval`); ``[fieller_low, fieller_high]`` is its Fieller ``confidence``
    interval and ``[rate_low, rate_high]`` that interval with its lower end widened by
    ``exp(-allowance)`` (:func:`polynomial_allowance`), the interval a contradiction is judged against; all
    None when the differences are not resolved from the noise.  ``growth`` ``[growth_low,
    growth_high]`` is the finite-horizon growth ``(E_{3h} / E_h)^(1 / 2h)``
    (:func:`rate_interval`).  "unstable": ``rate_low > 1``; "stable": ``fieller_high < 1``,
    or else ``growth_high < 1 + tolerance`` (no growth faster than ``(1 + tolerance)^k`` over
    the horizon); "undecided" otherwise.  ``exact_rate`` (when given) is the theory's growth
    rate for comparison.
    """

    verdict: str
    rate: float | None
    rate_low: float | None
    rate_high: float | None
    fieller_low: float | None
    fieller_high: float | None
    growth: float
    growth_low: float
    growth_high: float
    allowance: float
    exact_rate: float | None
    exact_rate_expr: str | None
    tolerance: float
    confidence: float
    horizons: tuple[int, int, int]
    paths: int
    seed: int | None
    sampling: str
    estimates: tuple[LogMeanEstimate, LogMeanEstimate, LogMeanEstimate]

    @property
    def horizon(self) -> int:
        """The longest horizon ``3h``."""
        return self.horizons[-1]


def rate_interval(first: LogMeanEstimate, second: LogMeanEstimate, confidence: float) -> tuple[float, float, float]:
    """Per-step growth ``(E_2 / E_1)^(1 / (k_2 - k_1))`` of two independent estimates, with its
    ``confidence`` interval by the delta method on ``log E``."""
    steps = second.horizon - first.horizon
    slope = (second.log_mean - first.log_mean) / steps
    half = _z(confidence) * math.hypot(first.rel_stderr, second.rel_stderr) / steps
    return math.exp(slope), math.exp(slope - half), math.exp(slope + half)


def margin_interval(runs: Sequence[LogMeanEstimate], confidence: float) -> tuple[float, float, float] | None:
    """The margin ``m`` from ``E_k = a m^k + b`` at three equally spaced horizons, with its interval.

    ``m^h = D_2 / D_1`` with ``D_1 = E_{k+h} - E_k``, ``D_2 = E_{k+2h} - E_{k+h}`` (Aitken's
    difference ratio: the constant ``b`` cancels, so neither the bounded part of an unstable
    mean nor the limit of a stable one biases it).  The runs are independent and each
    ``E`` approximately normal with standard deviation ``E rel_stderr``; Fieller's interval
    for the ratio of the correlated normal differences is the set of ``rho`` with ``(D_2 -
    rho D_1)^2 <= z^2 Var(D_2 - rho D_1)``; ``m``'s interval is its ``1/h``-th power (lower
    end 0 when it reaches ``rho <= 0``).  None when ``D_1`` is not resolved from 0 at this
    level or the estimated ratio is not positive: the noise hides the change of ``E_k``.
    """
    k0, k1, k2 = (r.horizon for r in runs)
    h = k1 - k0
    if k2 - k1 != h or h <= 0:
        raise InputError(f"horizons: expected three equally spaced horizons, got {(k0, k1, k2)}")
    z = _z(confidence)
    top = max(r.log_mean for r in runs)
    e = [math.exp(r.log_mean - top) for r in runs]       # scaled: only ratios matter
    s2 = [(x * r.rel_stderr) ** 2 for x, r in zip(e, runs)]
    d1, d2 = e[1] - e[0], e[2] - e[1]
    v11, v22, v12 = s2[0] + s2[1], s2[1] + s2[2], -s2[1]
    a = d1 * d1 - z * z * v11
    if a <= 0 or d2 / d1 <= 0:
        return None
    b = d1 * d2 - z * z * v12
    c = d2 * d2 - z * z * v22
    root = math.sqrt(max(b * b - a * c, 0.0))
    lo, hi = (b - root) / a, (b + root) / a
    return (d2 / d1) ** (1 / h), max(lo, 0.0) ** (1 / h), hi ** (1 / h)


def polynomial_degree(system: System, verdict) -> int:
    """How many factors ``k`` the mean may carry: ``E_k ~ k^p m^k``, ``p <= 2 (s - 1) + 1``.

    ``s`` bounds the longest Jordan chain of the limiting block (multiplicity minus
    eigenvectors plus one): ``A^k`` has entries ``~ k^(s-1) alpha^k``, so ``P`` grows like
    ``k^(2(s-1))`` inside a burst; the ``+ 1`` is the one factor ``k`` seen for diagonalizable
    blocks (the position of a single reception a deficient pattern may contain, as in
    ``P(at most one reception in N steps) = eps^N + N (1 - eps) eps^(N-1)``).  1 when there
    is no limiting block.
    """
    if verdict.limiting_block is None:
        return 1
    from ..engine.blocks import block_rows  # the engine imports nothing from simulation
    block = block_rows(system)[verdict.limiting_block].block
    chain = max(e.multiplicity - (e.multiplicity if e.geometric is None else e.geometric) + 1
                for e in block.members)
    return 2 * (chain - 1) + 1


def polynomial_allowance(horizons: Sequence[int], degree: int = 1) -> float:
    """``p ln((k + 2h) / (k + h)) / h``: how far ``p`` factors ``k`` can move the difference ratio's ``log m``.

    With ``E_k = sum_{i <= p} c_i k^i m^k + b`` (``c_i >= 0``; ``p`` from
    :func:`polynomial_degree`), each term's differences have ratio ``m^h (A x - B) / (B x -
    C)`` with ``x = m^h``, ``A, B, C = (k + 2h)^i, (k + h)^i, k^i``; for ``m > 1`` this lies in
    ``[m^h, m^h (A / B)]``: above since ``A - B >= B - C`` (convexity), below since ``A C <=
    B^2`` (``k (k + 2h) = (k + h)^2 - h^2``).  The ratio of a sum lies between its terms'
    ratios, so ``m^h <= D_2 / D_1 <= m^h ((k + 2h) / (k + h))^p``: the bias is upward and the
    interval's lower end is lowered by this much; the upper end is not widened.  A downward
    bias on long sampled paths is float64 losing the small directions of ``P``, not statistics
    (``benchmarks/float_resolution.py`` recomputes the same paths' ``log tr P`` exactly and finds
    the exact estimate inside the lower half): :func:`float_horizon` keeps the horizons where
    float64 resolves every path.
    """
    if len(horizons) != 3 or not 0 < horizons[0] < horizons[1]:
        raise InputError(f"horizons: expected three increasing horizons (k, k + h, k + 2h), got {horizons!r}")
    k, k1, _ = horizons
    h = k1 - k
    return degree * math.log((k + 2 * h) / (k + h)) / h


def rate_horizons(horizon: int, period: int) -> tuple[int, int, int]:
    """``(h, 2h, 3h)`` with ``h`` the largest multiple of ``period`` up to ``horizon / 3`` (at least
    one period): equal phases, so a periodic factor of ``E[tr P_k]`` cancels in the ratios."""
    horizon, period = count(horizon, "horizon", 1), count(period, "period", 1)
    h = max(period, period * (horizon // (3 * period)))
    return h, 2 * h, 3 * h


#: bits of float64's 53 a sampled path may spend on the spread of its covariance's scales
RESOLUTION_BITS = 40


def float_horizon(system: System, plan: BurstPlan | None, longest: int = 2000) -> int | None:
    """The longest horizon whose bursts float64 can follow, or None when there is no limit.

    The float ``A`` has the exact structure of the decisive pattern only to ~1e-16 when its
    entries are not binary fractions (``2 R(2 pi/3)``: ``C A^{3k}`` are parallel only to that
    precision), so during a long burst the float system is slightly observable and ``P``
    stops growing once its scales differ by ~1e32 (``log tr P`` then levels off, which a
    verdict would take for a contradiction).  Checked directly: the filter runs one burst of the
    plan's first component for ``longest`` steps; the cap is 4/5 of the first step where the
    growth over four periods falls below half the growth of the first four periods.

    Sampled paths meet a second limit that the pure burst does not show: after a burst of
    ``L`` steps ``P`` spans scales ``alpha^(2L)`` apart, and a reception then leaves one
    direction of size ~1 beside others of size ``alpha^(2L)``; the square-root factor carries
    that small direction with an error ``~2^-53 alpha^L`` relative to it, which the following
    steps propagate into ``log tr P``.  So the horizon is also capped at ``RESOLUTION_BITS
    ln 2 / ln alpha`` (``alpha = growth^(1/(2g))``, the block's modulus): relative errors
    below ``2^(RESOLUTION_BITS - 53) = 1.2e-4`` in ``log tr P``.  Measured against exact rational traces on every
    sampled path (``benchmarks/float_resolution.py``, ``2 R`` with Gilbert-Elliott losses,
    ``alpha = 2``): all 15 000 paths within 2e-4 at ``k = 40`` (``2^-53 2^40 = 1.2e-4``), 17 %
    of the mean's weight on broken paths at ``k = 80``.
    """
    if plan is None or plan.growth <= 1:
        return None
    g = plan.period
    resolution = max(8, int(RESOLUTION_BITS * math.log(2) * 2 * g / math.log(plan.growth)))
    received = np.broadcast_to(plan.allowed[0][np.arange(longest) % g][:, None, :], (longest, 1, system.d))
    lt = log_traces(real_form(system), received)[0]
    w = 4 * g
    if longest < 3 * w:
        return resolution
    early = lt[2 * w] - lt[w]
    if early <= 0:
        return resolution
    local = lt[w:] - lt[:-w]
    slow = np.flatnonzero(local[w:] < early / 2)
    return resolution if not slow.size else min(resolution, max(8, int(0.8 * (slow[0] + w))))


def divergence_test(system: System, loss: LossModel, seed: int | None = None, *,
                    horizon: int = 120, paths: int = 20_000, pattern: Any = None, growth: Any = None,
                    exact_rate: Any = None, tolerance: float = 0.01, confidence: float = 0.999,
                    plan: BurstPlan | None = None, degree: int = 1, jobs: int = 1) -> DivergenceResult:
    """Decide from simulation whether ``E[tr P_k]`` stays bounded (Sui-You-Fu eq. 7), any loss model.

    Three independent :func:`log_mean_trace` runs (seeds ``seed``, ``seed + 1``, ``seed + 2``)
    estimate ``log E[tr P_k]`` at ``h, 2h, 3h`` (:func:`rate_horizons`); the margin ``m`` and
    its interval come from :func:`margin_interval`, the finite-horizon growth from
    :func:`rate_interval` (verdicts: :class:`DivergenceResult`).  The runs sample final
    bursts of ``pattern`` (sensors lost per phase) with ``growth`` per period, or of ``plan``;
    default: the exact verdict's decisive pattern (:func:`verdict_plan`), which also fills
    ``exact_rate`` (:func:`exact_growth_rate`) and ``degree`` (:func:`polynomial_degree`, the
    factors ``k`` the allowance admits; otherwise 1).  The sampling only steers:
    the estimate is unbiased for any pattern.  ``jobs``: worker processes for the paths.  The
    horizon is capped by :func:`float_horizon` when float64 cannot follow longer bursts.
    """
    horizon, paths = _positive(horizon, "horizon"), _positive(paths, "paths")
    if horizon < 8:
        raise InputError(f"horizon: at least 8 steps are needed to estimate a rate, got {horizon}")
    if not isinstance(tolerance, float) or tolerance <= 0:
        raise InputError(f"tolerance: expected a positive float, got {tolerance!r}")
    _z(confidence)  # validate before the runs
    if plan is None and pattern is None:
        verdict = _verdict(system, loss)
        plan = verdict_plan(system, verdict, loss)
        exact_rate = exact_growth_rate(verdict) if exact_rate is None else exact_rate
        degree = polynomial_degree(system, verdict)
    elif plan is None:
        if growth is None:
            raise InputError("growth: give the growth factor of P per period of the pattern")
        plan = burst_plan(system, pattern, growth)
    cap = float_horizon(system, plan)
    horizons = rate_horizons(horizon if cap is None else min(horizon, cap), plan.period)
    runs = []
    # the runs' work is paths x horizon filter steps: the bar moves with each batch of paths
    with _progress(paths * sum(horizons), paths * sum(horizons), "simulate") as bar:
        for j, k in enumerate(horizons):
            with bar.part(paths * k):
                runs.append(log_mean_trace(system, loss, k, paths, None if seed is None else seed + j, plan, jobs))
    return _divergence_verdict(runs, _shown_rate(exact_rate), tolerance, confidence, degree, paths, seed)


def _shown_rate(exact_rate: Any) -> tuple[float, str] | None:
    """``exact_rate`` as :class:`DivergenceResult` shows it (its float and its exact form): the
    engine's own (an AlgebraicNumber, certified: its ball gives the float, whatever its degree) as
    it is, a caller's value through the safe reader (:func:`symkf.exact.numbers.to_exact`)."""
    if exact_rate is None:
        return None
    if isinstance(exact_rate, AlgebraicNumber):
        return float(exact_rate), str(exact_rate.exact)
    value = to_exact(exact_rate, "exact_rate")
    return float(value), str(value)


def _divergence_verdict(runs: Sequence[LogMeanEstimate], exact_rate: tuple[float, str] | None, tolerance: float,
                       confidence: float, degree: int, paths: int, seed: int | None) -> DivergenceResult:
    """The :class:`DivergenceResult` of three independent estimates of ``log E`` at ``h, 2h, 3h``:
    the margin from :func:`margin_interval` widened by :func:`polynomial_allowance`, the growth from
    :func:`rate_interval`, and the verdict by the rules of :class:`DivergenceResult`."""
    horizons = tuple(r.horizon for r in runs)
    corrected = margin_interval(runs, confidence)
    allowance = polynomial_allowance(horizons, degree)
    rate, f_low, f_high = corrected if corrected is not None else (None, None, None)
    low, high = (None, None) if rate is None else (f_low * math.exp(-allowance), f_high)
    growth = rate_interval(runs[0], runs[2], confidence)
    verdict = ("unstable" if low is not None and low > 1 else
               "stable" if (f_high is not None and f_high < 1) or growth[2] < 1 + tolerance else "undecided")
    return DivergenceResult(verdict, rate, low, high, f_low, f_high, *growth, allowance,
                            *((None, None) if exact_rate is None else exact_rate),
                            tolerance, confidence, horizons, paths, seed, runs[-1].sampling, tuple(runs))


@dataclass(frozen=True)
class MeanTraceCurve:
    """``log E[tr P_{k|k-1}]`` at steps ``ks``, each from its own :func:`log_mean_trace` run
    (seed ``seed + j`` for the ``j``-th step), with relative standard errors."""

    ks: np.ndarray
    log_mean: np.ndarray
    rel_stderr: np.ndarray
    confidence: float
    paths: int
    seed: int | None
    sampling: str
    requested: int = 0            # the horizon asked for
    float_cap: int | None = None  # float_horizon's cap when it stopped the curve before ``requested``

    @property
    def stop_reason(self) -> str | None:
        """Why the curve stops before the requested horizon, in words (None when it does not)."""
        if self.float_cap is None:
            return None
        return (f"the importance-sampled curve stops at k = {int(self.ks[-1])} of {self.requested}: beyond "
                f"k = {self.float_cap} float64 cannot follow the covariance through a burst of the decisive "
                "pattern (montecarlo.float_horizon)")

    def band(self) -> tuple[np.ndarray, np.ndarray]:
        """``log E`` minus and plus ``z`` relative standard errors (delta method)."""
        half = _z(self.confidence) * self.rel_stderr
        return self.log_mean - half, self.log_mean + half


def mean_trace_curve(system: System, loss: LossModel, horizon: int, paths: int, seed: int | None = None, *,
                     points: int = 12, plan: BurstPlan | None = None, confidence: float = 0.95) -> MeanTraceCurve:
    """``log E[tr P_k]`` at ``points`` steps up to ``horizon`` (multiples of the plan's period), by
    final-burst importance sampling steered by ``plan`` (default: the exact verdict's,
    :func:`verdict_plan`; plain Monte Carlo when the theory does not apply); the horizon is
    capped by :func:`float_horizon`."""
    horizon, paths, points = _positive(horizon, "horizon"), _positive(paths, "paths"), _positive(points, "points")
    _z(confidence)
    if plan is None:
        try:
            plan = verdict_plan(system, _verdict(system, loss), loss)
        except SymkfError:
            plan = None
    g = plan.period if plan is not None else 1
    cap, requested = float_horizon(system, plan), horizon
    horizon = horizon if cap is None else min(horizon, cap)
    ks = np.unique(np.maximum(g, g * np.round(np.linspace(g, horizon, points) / g))).astype(int)
    runs = [log_mean_trace(system, loss, int(k), paths, None if seed is None else seed + j, plan)
            for j, k in enumerate(ks)]
    return MeanTraceCurve(ks, np.array([r.log_mean for r in runs]), np.array([r.rel_stderr for r in runs]),
                          confidence, paths, seed, runs[0].sampling, requested,
                          cap if cap is not None and cap < requested else None)


check_public(globals())
