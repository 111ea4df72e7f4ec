"""Theory against simulation: the exact verdict of Sui-You-Fu Theorems 4/7 beside a Monte Carlo test.

:func:`verify` decides mean-square stability exactly (:func:`symkf.stability.stability`)
and, independently, estimates the growth rate of ``E[tr P_k]`` by simulation
(:func:`symkf.montecarlo.divergence_test`), then compares them.  The outcome is

* ``"agree"``: the simulation reached a verdict and it is the theory's;
* ``"undecided"``: the simulation's confidence interval straddles the
  tolerance (typical near the critical value), or float64 broke down on the
  longest bursts and forced a horizon shorter than requested (then the
  transient from ``P0`` can pass for growth), so it neither confirms nor
  contradicts the theory;
* ``"disagree"``: the simulation decided the opposite of the theory.

For i.i.d. losses the simulation samples the loss bursts that dominate
``E[P_k]``: the theory's decisive pattern (the sensors and phases outside the
limiting block's decisive hyperplane, eq. 36) with growth ``alpha^(2g)`` per
period ``g`` steers :func:`~symkf.montecarlo.burst_estimate`; the tilt is
undone by the likelihood ratio, so it affects the variance, never the
estimate.  For Markov losses only plain Monte Carlo is available; it rarely
samples those bursts, so it can show growth but never certify boundedness:
its verdict is ``"unstable"`` or ``"undecided"``.

:func:`verify_family` runs :func:`verify` on every member of a parameter family
(a TOML family file with a ``[loss]`` template, see :mod:`symkf.families`) with
:func:`symkf.sweep.sweep`, serially, on local processes or on a Dask cluster.
Member ``i`` is simulated with the seeds ``seed + 2i`` and ``seed + 2i + 1``, fixed
by its place in the family, so the reports are identical however the sweep runs.

When the theory says unstable, ``E[tr P_k]`` grows like ``(alpha_i^2
rho_i)^k`` for the limiting block, so the exact rate is also compared with
the simulated rate's interval (reported, not part of the outcome: slowly
decaying transients and polynomial factors bias a finite-horizon rate).
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

import sympy as sp

from .errors import AssumptionError, FileFormatError, SymkfError
from .exact.algebraic import AlgebraicNumber
from .families import Member, load_family
from .files import read_toml
from .losses import IID, LossModel
from .model import System
from .montecarlo import (MIN_HALVED_HORIZON, DivergenceResult, burst_pattern, divergence_test,
                         estimate_mean_trace, exact_growth_rate, growth_rate_interval)
from .progress import progress
from .stability import Verdict, critical_loss_rate, stability
from .sweep import sweep

OUTCOMES = ("agree", "undecided", "disagree")
#: outcome of a family member whose theorem assumptions fail (shown as --- in tables)
INAPPLICABLE = "inapplicable"


def number_json(a: AlgebraicNumber | sp.Expr, digits: int = 12) -> dict[str, Any]:
    """JSON form of an exact value: exact string, decimal, isolating interval and minimal polynomial."""
    a = a if isinstance(a, AlgebraicNumber) else AlgebraicNumber.from_expr(a)
    lo, hi = a.refine(sp.Rational(1, 10 ** (digits + 2))).interval
    return {"exact": str(a.exact), "decimal": str(a.evalf(digits)), "interval": [str(lo), str(hi)],
            "minpoly": str(a.minpoly.as_expr())}


def _plain_growth(system: System, loss: LossModel, seed: int, horizon: int, paths: int,
                  tolerance: float, confidence: float) -> dict[str, Any]:
    """Growth of ``E[tr P_k]`` between ``k = horizon/2`` and ``horizon`` from two independent plain runs."""
    k1, k2 = horizon // 2, horizon
    runs = [estimate_mean_trace(system, loss, k, paths, seed=s, confidence=confidence)
            for k, s in ((k1, seed), (k2, seed + 1))]
    rate, low, high = growth_rate_interval(*((float(r.mean[-1]), float(r.stderr[-1])) for r in runs),
                                           k2 - k1, confidence)
    return {"method": "plain Monte Carlo (estimate_mean_trace); cannot certify boundedness",
            "verdict": "unstable" if low > 1 + tolerance else "undecided",
            "rate": rate, "rate_interval": [low, high], "confidence": confidence,
            "tolerance": tolerance, "horizon": horizon, "paths": paths, "seeds": [seed, seed + 1],
            "horizons": [k1, k2]}


def _divergence_json(r: DivergenceResult, pattern: Any, growth: Any) -> dict[str, Any]:
    return {"method": "divergence_test: burst importance sampling of the decisive loss pattern",
            "verdict": r.verdict, "rate": r.rate, "rate_interval": [r.rate_low, r.rate_high],
            "confidence": r.confidence, "tolerance": r.tolerance, "horizon": r.horizon, "paths": r.paths,
            "seeds": [r.seed, r.seed + 1], "horizons": [r.horizon // 2, r.horizon],
            "pattern": pattern, "growth_per_governing_period": None if growth is None else str(growth),
            "sampling": r.sampling}


def verify(system: System, loss: LossModel, *, seed: int = 0, paths: int = 20_000, horizon: int = 80,
           tolerance: float = 0.01, confidence: float = 0.99) -> dict[str, Any]:
    """Run the exact verdict and a Monte Carlo test on ``(system, loss)``; JSON-serialisable report.

    Keys: ``theory`` (verdict, theorem, margins ``alpha_i^2 rho_i``, the
    exact growth rate ``max(1, max_i alpha_i^2 rho_i)`` of ``E[tr P_k]``, the
    critical common i.i.d. loss rate), ``simulation`` (method, verdict, rate
    with its interval, seeds, horizons, paths), ``outcome`` (one of
    :data:`OUTCOMES`) and ``rate_consistent`` (exact rate inside the simulated
    interval when the theory says unstable, else None).
    """
    with progress(2, "verify") as bar:
        v = stability(system, loss)
        growth_exact = exact_growth_rate(v)
        theory = {"stable": v.stable, "theorem": v.theorem, "assumptions": list(v.assumptions),
                  "margins": [number_json(m) for m in v.margins], "limiting_block": v.limiting_block,
                  "growth_rate": number_json(growth_exact),
                  "critical_common_loss_rate": number_json(critical_loss_rate(system))}
        bar.update()
        sim = simulated_verdict(system, loss, v, seed=seed, paths=paths, horizon=horizon, tolerance=tolerance,
                                confidence=confidence)
        bar.update()
    if sim["verdict"] == "undecided":
        outcome = "undecided"
    else:
        outcome = "agree" if (sim["verdict"] == "stable") == v.stable else "disagree"
    low, high = sim["rate_interval"]
    consistent = bool(low <= float(growth_exact) <= high) if not v.stable else None
    return {"theory": theory, "simulation": sim, "outcome": outcome, "rate_consistent": consistent}


def simulated_verdict(system: System, loss: LossModel, v: Verdict, *, seed: int = 0, paths: int = 20_000,
                      horizon: int = 80, tolerance: float = 0.01, confidence: float = 0.99) -> dict[str, Any]:
    """The simulation half of :func:`verify`, steered by the theory's verdict ``v`` (JSON form)."""
    phases, growth = burst_pattern(system, v)
    # a pattern lost with probability 0 or 1 cannot steer burst sampling (and needs none)
    if not isinstance(loss, IID) or not 0 < sp.Mul(*[loss.loss[s] for ph in phases for s in ph]) < 1:
        return _plain_growth(system, loss, seed, horizon, paths, tolerance, confidence)
    r = divergence_test(system, loss, seed=seed, horizon=horizon, paths=paths, pattern=phases, growth=growth,
                        exact_rate=exact_growth_rate(v).exact, tolerance=tolerance, confidence=confidence)
    out = _divergence_json(r, phases, growth)
    if r.horizon < horizon:
        withheld = r.horizon < MIN_HALVED_HORIZON
        out["note"] = (f"horizon halved from {horizon} to {r.horizon} by float64 breakdown"
                       + ("; verdicts at such short horizons are withheld" if withheld else ""))
    return out


def summary(report: dict[str, Any]) -> str:
    """The report as a few lines of plain text."""
    t, s = report["theory"], report["simulation"]
    lines = [f"theory:     {'stable' if t['stable'] else 'NOT stable'} ({t['theorem']})",
             "            margins alpha_i^2 rho_i: " + ", ".join(
                 f"{m['exact']} ~ {float(m['decimal']):.6g}" for m in t["margins"]),
             f"            exact growth rate of E[tr P_k]: {t['growth_rate']['exact']} "
             f"~ {float(t['growth_rate']['decimal']):.6g}",
             f"            critical common i.i.d. loss rate: {t['critical_common_loss_rate']['exact']} "
             f"~ {float(t['critical_common_loss_rate']['decimal']):.6g}",
             f"simulation: {s['verdict']} ({s['method']})",
             f"            growth rate {s['rate']:.5g}, {100 * s['confidence']:g}% interval "
             f"[{s['rate_interval'][0]:.5g}, {s['rate_interval'][1]:.5g}], tolerance {s['tolerance']:g}",
             f"            {s['paths']} paths per run, horizons {s['horizons']}, seeds {s['seeds']}"]
    if "note" in s:
        lines.append(f"            note: {s['note']}")
    if report["rate_consistent"] is not None:
        lines.append(f"            exact rate {'inside' if report['rate_consistent'] else 'OUTSIDE'} "
                     "the simulated interval")
    lines.append({"agree": "outcome:    theory and simulation AGREE",
                  "undecided": "outcome:    simulation UNDECIDED (no contradiction; try more paths "
                               "or a longer horizon)",
                  "disagree": "outcome:    theory and simulation DISAGREE"}[report["outcome"]])
    return "\n".join(lines)



def is_family_file(path: str | Path) -> bool:
    """Whether ``path`` is a TOML file with a ``[family]`` table (else it is read as a system file)."""
    try:
        return isinstance(read_toml(path).get("family"), dict)
    except SymkfError:
        return False  # the system-file reader reports the problem


def verify_member(task: tuple[int, Member, int], **kw: Any) -> dict[str, Any]:
    """:func:`verify` on member ``(index, member, seed)`` of a family (runs on sweep workers).

    A member whose theorem assumptions fail gets outcome ``"inapplicable"`` and the reason,
    so one such member does not stop a campaign.
    """
    index, member, seed = task
    head = {"member": member.label, "index": index, "point": {k: str(v) for k, v in member.point},
            "seed": seed}
    system, loss = member.system()
    try:
        return {**head, **verify(system, loss, seed=seed, **kw)}
    except AssumptionError as exc:
        return {**head, "outcome": INAPPLICABLE, "reason": str(exc)}


def verify_family(path: str | Path, jobs: int = 1, scheduler: Any = None, *, seed: int = 0,
                  progress: bool | None = None, **kw: Any) -> list[dict[str, Any]]:
    """:func:`verify` on every member of the family file ``path``, in the family's order.

    The family needs a ``[loss]`` template.  Member ``i`` uses ``seed + 2i`` (its two
    simulation runs take ``seed + 2i`` and ``seed + 2i + 1``, so no two runs share a random
    stream), which makes the reports identical for ``jobs=1``, ``jobs=N`` and a Dask
    ``scheduler`` (see :func:`symkf.sweep.sweep`).  ``kw`` goes to :func:`verify`
    (``paths``, ``horizon``, ``tolerance``, ``confidence``).  Each report is
    :func:`verify`'s plus ``member`` (label), ``index``, ``point`` (grid coordinates) and
    ``seed``; a member whose assumptions fail has ``outcome = "inapplicable"`` and ``reason``.
    """
    family = load_family(path)
    if family.members[0].tables["loss"] is None:
        raise FileFormatError(f"{path}: [loss]: verify needs a loss model; give the family a [loss] "
                              "template, e.g. kind = \"iid\", loss = [\"eps\"] with eps in [grid]")
    tasks = [(i, m, seed + 2 * i) for i, m in enumerate(family.members)]
    return sweep(functools.partial(verify_member, **kw), tasks, jobs=jobs, scheduler=scheduler,
                 progress=progress, desc=f"verify {family.name}")


def family_summary(reports: list[dict[str, Any]]) -> str:
    """One line per member (theory, simulation, outcome) and a count of the outcomes."""
    width = max(len(r["member"]) for r in reports)
    lines = []
    for r in reports:
        if r["outcome"] == INAPPLICABLE:
            lines.append(f"{r['member']:<{width}}  INAPPLICABLE: {' '.join(r['reason'].split())}")
            continue
        t, s = r["theory"], r["simulation"]
        low, high = s["rate_interval"]
        lines.append(f"{r['member']:<{width}}  theory {'stable' if t['stable'] else 'NOT stable':<10} "
                     f"growth {t['growth_rate']['exact']} ~ {float(t['growth_rate']['decimal']):.5g}; "
                     f"simulation {s['verdict']:<9} rate {s['rate']:.5g} [{low:.5g}, {high:.5g}], "
                     f"seeds {s['seeds']}; {r['outcome'].upper()}")
    counts = [f"{sum(r['outcome'] == o for r in reports)} {o}" for o in (*OUTCOMES, INAPPLICABLE)]
    lines.append(f"{len(reports)} members: " + ", ".join(counts))
    return "\n".join(lines)
