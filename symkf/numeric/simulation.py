"""Simulated ``E[tr P_{k|k-1}]`` as a result object: :func:`simulate` (``sk.simulate``).

A :class:`Simulation` holds the plain Monte Carlo estimate
(:func:`symkf.numeric.montecarlo.estimate_mean_trace`), optionally the importance-sampled curve of
``log E[tr P_k]`` (:func:`symkf.numeric.montecarlo.mean_trace_curve`), and the exact growth rate of
the mean (``max(1, max_i alpha_i^2 rho_i)``, Sui-You-Fu Theorems 4 and 7) when the theory
applies.  It says in words what the data cannot support: the steps whose mean plain Monte
Carlo does not resolve (a diverging filter's mean sits on loss bursts too rare for the
sample), and where and why the importance-sampled curve stops (float64,
:func:`symkf.numeric.montecarlo.float_horizon`).  ``to_dict()`` is the document of ``symkf simulate
--json`` (without ``system``, ``loss`` and ``plot``, which the command adds).
"""

from __future__ import annotations

import html
import math
import textwrap
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..output import JsonDocument
from ..errors import SymkfError
from ..arguments import check_public
from ..exact.algebraic import AlgebraicNumber
from ..exact.text import algebraic_text
from ..model.loss import LossModel
from ..model.system import System
from .montecarlo import MAX_PATH_SHARE, MAX_REL_STDERR, MeanTraceCurve, TraceEstimate

__all__ = ["Simulation", "simulate"]

QUANTITY = "E[tr P_{k|k-1}], k = 0..horizon-1"
METHOD = "plain Monte Carlo (estimate_mean_trace), intervals on the log scale"


@dataclass(frozen=True, repr=False)
class Simulation(JsonDocument):
    """Simulated ``E[tr P_{k|k-1}]`` of ``system`` under ``loss`` (module docstring).

    ``estimate``: plain Monte Carlo with per-step resolution; ``curve``: the importance-sampled
    ``log E[tr P_k]`` or None; ``growth_rate``: the exact growth rate per step (an
    :class:`~symkf.exact.algebraic.AlgebraicNumber`) or None when no theorem applies;
    ``stable``: the exact verdict or None.
    """

    system: System
    loss: LossModel
    estimate: TraceEstimate
    curve: MeanTraceCurve | None
    growth_rate: AlgebraicNumber | None
    stable: bool | None

    @cached_property
    def resolved(self) -> np.ndarray:
        """Per step, whether plain Monte Carlo resolves the mean (:class:`TraceEstimate`); for a
        diverging filter no step after the first unresolved one is (its mean outgrows every
        sample: a later step that looks resolved has merely missed the bursts carrying it).
        Computed once (``interval(k)`` for every step made ``to_dict`` quadratic in the horizon);
        read-only."""
        ok = self.estimate.resolved
        out = np.logical_and.accumulate(ok) if self.stable is False else ok.copy()
        out.flags.writeable = False
        return out

    @property
    def resolved_until(self) -> int:
        """The number of leading steps whose mean is resolved (``horizon`` when all are)."""
        bad = np.flatnonzero(~self.resolved)
        return int(bad[0]) if bad.size else self.horizon

    def interval(self, k: int) -> tuple[float, float] | None:
        """The confidence interval of ``E[tr P_k]`` (log scale), None where the data cannot support one."""
        return (float(self.estimate.low[k]), float(self.estimate.high[k])) if self.resolved[k] else None

    @property
    def horizon(self) -> int:
        return self.estimate.horizon

    @property
    def paths(self) -> int:
        return self.estimate.paths

    def summary_steps(self, points: int = 8) -> list[int]:
        """``points`` evenly spread steps, and the first unresolved one."""
        h = self.horizon
        count = min(points, h)
        ks = {round(i * (h - 1) / max(count - 1, 1)) for i in range(count)}
        if self.resolved_until < h:
            ks.add(self.resolved_until)
        return sorted(ks)

    def notes(self) -> list[str]:
        """What the data cannot support, in words."""
        e, out = self.estimate, []
        bad = int((~self.resolved).sum())
        if bad:
            where = (f"from k = {self.resolved_until} on" if self.stable is False else
                     f"at {bad} of {e.horizon} steps (the first: k = {self.resolved_until})")
            why = (f"{where}, a few paths carry the mean (relative standard error above {MAX_REL_STDERR:.0%} or "
                   f"one path above {MAX_PATH_SHARE:.0%} of the sum), so no interval is given there")
            if self.stable is False:
                why += (f"; the filter diverges (exact growth {algebraic_text(self.growth_rate, 5)}"
                        f" per step) and its mean sits on loss bursts too rare for {e.paths} paths: plain Monte "
                        "Carlo cannot resolve it; the importance-sampled curve (--plot, Simulation.curve) follows it")
            out.append(why)
        if self.curve is not None and self.curve.stop_reason:
            out.append(self.curve.stop_reason)
        return out

    def to_dict(self) -> dict[str, Any]:
        """The ``symkf simulate --json`` document (docs/json.md), NaN written as null."""
        e = self.estimate
        shown = [self.interval(k) or (None, None) for k in range(e.horizon)]
        rows = [{"k": k, "mean": float(e.mean[k]), "low": shown[k][0], "high": shown[k][1],
                 "resolved": bool(self.resolved[k])} for k in self.summary_steps()]
        out: dict[str, Any] = {
            "quantity": QUANTITY, "method": METHOD, "horizon": e.horizon, "paths": e.paths, "seed": e.seed,
            "confidence": e.confidence, "summary": rows, "mean": e.mean.tolist(),
            "low": [s[0] for s in shown], "high": [s[1] for s in shown], "resolved_until": self.resolved_until,
            "exact_growth_rate": None if self.growth_rate is None else str(self.growth_rate.exact),
            "notes": self.notes()}
        if self.curve is not None:
            c = self.curve
            out["growth_curve"] = {"method": c.sampling, "k": c.ks.tolist(), "log_mean": c.log_mean.tolist(),
                                   "rel_stderr": c.rel_stderr.tolist(), "stops": c.stop_reason}
        return out

    def __str__(self) -> str:
        e = self.estimate
        lines = [f"{QUANTITY}: plain Monte Carlo, {e.paths} paths, seed {e.seed}",
                 f"{'k':>6} {'mean':>12}  {100 * e.confidence:g}% interval (log scale)"]
        for k in self.summary_steps():
            lines.append(f"{k:>6} {e.mean[k]:>12.6g}  {_interval_text(self.interval(k))}")
        if self.growth_rate is not None:
            lines.append("exact: " + ("stable, E[tr P_k] stays bounded" if self.stable else
                                      f"NOT stable, E[tr P_k] grows by {algebraic_text(self.growth_rate)} per step") + " (Sui-You-Fu Theorems 4/7)")
        if self.curve is not None:
            c = self.curve
            lines.append(f"log10 E[tr P_k] by {c.sampling}:")
            steps = ", ".join(f"k = {k}: {m / math.log(10):.4g}" for k, m in zip(c.ks, c.log_mean))
            lines += textwrap.wrap(steps, 100, initial_indent="  ", subsequent_indent="  ")
        for note in self.notes():
            lines += textwrap.wrap(f"note: {note}", 100, subsequent_indent="      ")
        return "\n".join(lines)

    def __repr__(self) -> str:
        e = self.estimate
        exact = "" if self.growth_rate is None else f", exact growth {algebraic_text(self.growth_rate)} per step"
        return (f"<Simulation of E[tr P_k]: {e.paths} paths x {e.horizon} steps, seed {e.seed}, plain Monte "
                f"Carlo resolves {int(self.resolved.sum())} of {e.horizon} steps{exact}>")

    def _repr_html_(self) -> str:
        e = self.estimate
        rows = "".join(f"<tr><td>{k}</td><td>{e.mean[k]:.6g}</td><td>{_interval_text(self.interval(k))}</td></tr>"
                       for k in self.summary_steps())
        notes = "".join(f"<p>{html.escape(n)}</p>" for n in self.notes())
        exact = "" if self.growth_rate is None else (
            f"<p>exact growth rate of E[tr P<sub>k</sub>]: {html.escape(str(self.growth_rate.exact))} "
            f"&asymp; {float(self.growth_rate):.6g} per step</p>")
        return (f"<p>E[tr P<sub>k|k-1</sub>], plain Monte Carlo, {e.paths} paths, seed {e.seed}</p>"
                f"<table><tr><th>k</th><th>mean</th><th>{100 * e.confidence:g}% interval</th></tr>{rows}</table>"
                f"{exact}{notes}")

    def _repr_latex_(self) -> str:
        e = self.estimate
        rows = r" \\ ".join(f"{k} & {e.mean[k]:.6g} & "
                            + (_interval_text(self.interval(k)) if self.resolved[k] else r"\text{not resolved}")
                            for k in self.summary_steps())
        return (r"$\begin{array}{rrl} k & \mathrm{E}[\mathrm{tr}\,P_{k|k-1}] & "
                f"{100 * e.confidence:g}\\%\\ \\text{{interval}} \\\\ \\hline {rows}\\end{{array}}$")


def _interval_text(interval: tuple[float, float] | None) -> str:
    return "not resolved" if interval is None else f"[{interval[0]:.6g}, {interval[1]:.6g}]"


def simulate(system: System, loss: LossModel, horizon: int, paths: int, seed: int | None = 0, *,
             curve: bool = False, confidence: float = 0.95) -> Simulation:
    """Simulate ``E[tr P_{k|k-1}]``, k = 0..horizon-1, with ``paths`` paths from ``seed``.

    Plain Monte Carlo always (:func:`symkf.numeric.montecarlo.estimate_mean_trace`); with ``curve``,
    also ``log E[tr P_k]`` by final-burst importance sampling
    (:func:`symkf.numeric.montecarlo.mean_trace_curve`, the curve of :meth:`Simulation.figure`).  The
    exact growth rate is added when Sui-You-Fu's theorems apply to ``(system, loss)``.

    ``A = 2`` losing 1/8 of its measurements is stable (a lost step multiplies ``P`` by about 4:
    ``4/8 < 1``), but ``E[(tr P_k)^2]`` grows like ``(16/8)^k``, so the sample mean of 400 paths
    loses its precision after some steps (how many varies with the seed: 4 to 20 over seeds 1 to 40)
    and no interval is given from there on:

    >>> import symkf as sk
    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])])
    >>> sim = sk.simulate(S, sk.IID(["1/8"]), horizon=30, paths=400, seed=1)
    >>> sim.growth_rate.exact, sim.stable, sim.resolved_until < 30
    (1, True, True)
    """
    from .montecarlo import estimate_mean_trace, exact_growth_rate, mean_trace_curve
    from ..engine.stability import stability
    estimate = estimate_mean_trace(system, loss, horizon, paths, seed=seed, confidence=confidence)
    try:
        verdict = stability(system, loss)
        growth, stable = exact_growth_rate(verdict), verdict.stable
    except SymkfError:
        growth, stable = None, None
    sampled = mean_trace_curve(system, loss, horizon, paths, seed=seed, confidence=confidence) if curve else None
    return Simulation(system, loss, estimate, sampled, growth, stable)


check_public(globals())
