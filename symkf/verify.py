"""Theory against simulation: the exact verdict of Sui-You-Fu Theorems 4/7 beside a Monte Carlo test.

:func:`verify` decides mean-square stability exactly (:func:`symkf.stability.stability`)
and, independently, estimates the growth rate of ``E[tr P_k]`` by simulation
(:func:`symkf.montecarlo.divergence_test`), then compares them (:func:`judge`).  The
outcome is one of

* ``"consistent"``: the simulation decides the theory's verdict (its rate interval lies
  above ``1 + tolerance`` when unstable, below it when stable) and, when unstable, its
  interval contains the exact rate ``alpha^2 rho`` up to the finite-horizon allowance;
* ``"contradiction"``: the simulation decisively disagrees: the exact rate lies outside
  the (allowance-widened) interval, or a stable theory meets decisive growth.  Either the
  theory or the simulation has a bug; the CLI exits with status 1;
* ``"undecided"``: neither, with the reason (too close to the threshold for the budget)
  and the number of paths that would decide.

The simulation samples, for every loss model the engine decides (i.i.d., Gilbert-Elliott,
joint Markov, network), final loss bursts of the theory's decisive pattern (the sensors
and phases outside the limiting block's decisive hyperplane, eq. 36): the loss chain
conditioned to stay in the pattern (its restricted transfer ``M_H``) with exact likelihood
ratios, so the tilt changes the variance, never the estimate
(:func:`symkf.montecarlo.burst_sample`).  Covariances are propagated in square-root form
with a log-scale (:func:`symkf.filtering.log_traces`), so divergent runs never overflow.

Finite-horizon allowance: the simulated rate is ``(E_{k_2} / E_{k_1})^(1 / k_1)``, not the
limit.  When unstable, ``E_k = c m^k (1 + O(k m^(-k)))`` up to at most one factor of ``k``
(ties of patterns), so the rate may differ from ``m`` by ``(ln(1 + k_2 m^(-k_1)) + ln 2) /
k_1`` in log; when stable, ``E_k`` rises to its limit like ``1 - O(k m^k)``, so the rate
may exceed 1 by ``ln(1 + k_2 m^(k_1)) / k_1``.  Contradictions are claimed only beyond these.

:func:`verify_family` runs :func:`verify` on every member of a parameter family
(a TOML family file with a ``[loss]`` template, see :mod:`symkf.families`) with
:func:`symkf.sweep.sweep`, serially, on local processes or on a Dask cluster.
Member ``i`` is simulated with the seeds ``seed + 2i`` and ``seed + 2i + 1``, fixed
by its place in the family, so the reports are identical however the sweep runs.  A
member whose assumptions fail or whose simulation breaks down gets its own row with the
reason; the run continues.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any

import sympy as sp

from .errors import AssumptionError, FileFormatError, NumericalBreakdownError, SymkfError
from .exact.algebraic import AlgebraicNumber
from .families import Member, load_family
from .files import read_toml
from .losses import LossModel
from .model import System
from .montecarlo import DivergenceResult, divergence_test, exact_growth_rate, verdict_plan
from .progress import progress
from .stability import Verdict, critical_loss_rate, stability
from .sweep import sweep

OUTCOMES = ("consistent", "undecided", "contradiction")
#: outcome of a family member whose theorem assumptions fail (shown as --- in tables)
INAPPLICABLE = "inapplicable"
#: outcome of a family member whose simulation broke down numerically
BREAKDOWN = "breakdown"


def number_json(a: AlgebraicNumber | sp.Expr, digits: int = 12) -> dict[str, Any]:
    """JSON form of an exact value: exact string, decimal, isolating interval and minimal polynomial."""
    a = a if isinstance(a, AlgebraicNumber) else AlgebraicNumber.from_expr(a)
    lo, hi = a.refine(sp.Rational(1, 10 ** (digits + 2))).interval
    return {"exact": str(a.exact), "decimal": str(a.evalf(digits)), "interval": [str(lo), str(hi)],
            "minpoly": str(a.minpoly.as_expr())}


def verify(system: System, loss: LossModel, *, seed: int = 0, paths: int = 20_000, horizon: int = 120,
           tolerance: float = 0.01, confidence: float = 0.99, jobs: int = 1) -> dict[str, Any]:
    """Run the exact verdict and a Monte Carlo test on ``(system, loss)``; JSON-serialisable report.

    Keys: ``theory`` (verdict, theorem, margins ``alpha_i^2 rho_i``, the exact growth rate
    ``max(1, max_i alpha_i^2 rho_i)`` of ``E[tr P_k]``, the critical common i.i.d. loss
    rate), ``simulation`` (method, verdict, rate with its interval, seeds, horizons,
    paths), ``outcome`` (one of :data:`OUTCOMES`), ``reason`` (why, in words) and
    ``rate_consistent`` (exact rate inside the allowance-widened interval when the theory
    says unstable, else None).  ``jobs``: worker processes for the simulated paths.
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
                                confidence=confidence, jobs=jobs)
        bar.update()
    return {"theory": theory, "simulation": sim, **judge(v, sim)}


def judge(v: Verdict, sim: dict[str, Any]) -> dict[str, Any]:
    """``outcome``, ``reason`` and ``rate_consistent`` of a simulation against the exact verdict
    (rules and allowances in the module docstring)."""
    low, high = sim["rate_interval"]
    tol, (k1, k2) = sim["tolerance"], sim["horizons"]
    margin = float(max(v.margins))
    if v.stable:
        allowance = math.log1p(k2 * margin ** k1) / k1
        ceiling = (1 + tol) * math.exp(allowance)
        if low > ceiling:
            return {"outcome": "contradiction", "rate_consistent": None, "reason":
                    f"theory says bounded, but the simulated rate interval [{low:.5g}, {high:.5g}] lies above "
                    f"1 + tolerance = {1 + tol:g} even after the finite-horizon allowance ({ceiling:.5g})"}
        if high < 1 + tol:
            return {"outcome": "consistent", "rate_consistent": None, "reason":
                    f"simulated rate interval [{low:.5g}, {high:.5g}] below 1 + tolerance = {1 + tol:g}: bounded"}
        return {"outcome": "undecided", "rate_consistent": None,
                "reason": _undecided(sim, 1 + tol, "below")}
    allowance = (math.log1p(k2 * margin ** -k1) + math.log(2)) / k1
    lo_w, hi_w = low * math.exp(-allowance), high * math.exp(allowance)
    inside = lo_w <= margin <= hi_w
    if not inside:
        return {"outcome": "contradiction", "rate_consistent": False, "reason":
                f"exact rate {margin:.6g} outside the simulated interval [{low:.5g}, {high:.5g}] widened by the "
                f"finite-horizon allowance to [{lo_w:.5g}, {hi_w:.5g}]"}
    if low > 1 + tol:
        return {"outcome": "consistent", "rate_consistent": True, "reason":
                f"simulated rate interval [{low:.5g}, {high:.5g}] above 1 + tolerance = {1 + tol:g} and "
                f"consistent with the exact rate {margin:.6g}"}
    return {"outcome": "undecided", "rate_consistent": True, "reason": _undecided(sim, 1 + tol, "above")
            if margin > 1 + tol else
            f"exact rate {margin:.6g} is within the tolerance {tol:g} of 1: growth this slow is not "
            f"separable from boundedness at horizon {k2}; a longer horizon and smaller tolerance would be needed"}


def _undecided(sim: dict[str, Any], bound: float, side: str) -> str:
    """Why an interval straddles ``bound``, and how many paths would put it on ``side``."""
    low, high = sim["rate_interval"]
    half = (math.log(high) - math.log(low)) / 2
    gap = abs(math.log(sim["rate"]) - math.log(bound))
    on_side = (sim["rate"] < bound) == (side == "below")
    text = (f"simulated rate interval [{low:.5g}, {high:.5g}] contains 1 + tolerance = {bound:g} "
            f"(too close to the threshold for {sim['paths']} paths x horizons {sim['horizons']})")
    if on_side and gap > 0:
        need = math.ceil(sim["paths"] * (half / gap) ** 2 * 1.2)
        text += f"; about {need} paths per run would decide"
    else:
        text += ("; the estimate itself is on the other side, as expected this close to the threshold "
                 "(E_k approaches its limit or its growth slowly): a longer horizon is needed, not more paths")
    return text


def simulated_verdict(system: System, loss: LossModel, v: Verdict, *, seed: int = 0, paths: int = 20_000,
                      horizon: int = 120, tolerance: float = 0.01, confidence: float = 0.99,
                      jobs: int = 1) -> dict[str, Any]:
    """The simulation half of :func:`verify`, steered by the theory's verdict ``v`` (JSON form)."""
    plan = verdict_plan(system, v, loss)
    r = divergence_test(system, loss, seed=seed, horizon=horizon, paths=paths, plan=plan,
                        exact_rate=exact_growth_rate(v).exact, tolerance=tolerance, confidence=confidence,
                        jobs=jobs)
    return _divergence_json(r, horizon)


def _divergence_json(r: DivergenceResult, requested: int) -> dict[str, Any]:
    out = {"method": "divergence_test: importance sampling of final bursts of the decisive loss pattern, "
                      "square-root filter with log-scale",
            "verdict": r.verdict, "rate": r.rate, "rate_interval": [r.rate_low, r.rate_high],
            "confidence": r.confidence, "tolerance": r.tolerance, "paths": r.paths,
            "seeds": [r.seed, None if r.seed is None else r.seed + 1], "horizons": list(r.horizons),
            "sampling": r.sampling, "effective_sample_sizes": [e.ess for e in r.estimates]}
    if r.horizon < requested:
        out["note"] = (f"horizon capped from {requested} to {r.horizon}: beyond it float64 cannot follow a burst of "
                       "the decisive pattern (A's entries are not binary fractions; see montecarlo.float_horizon)")
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
                     "the simulated interval (with the finite-horizon allowance)")
    lines.append(f"outcome:    {report['outcome'].upper()}: {report['reason']}")
    return "\n".join(lines)


def is_family_file(path: str | Path) -> bool:
    """Whether ``path`` is a TOML file with a ``[family]`` table (else it is read as a system file)."""
    try:
        return isinstance(read_toml(path).get("family"), dict)
    except SymkfError:
        return False  # the system-file reader reports the problem


def verify_member(task: tuple[int, Member, int], **kw: Any) -> dict[str, Any]:
    """:func:`verify` on member ``(index, member, seed)`` of a family (runs on sweep workers).

    A member whose theorem assumptions fail gets outcome ``"inapplicable"``, one whose
    simulation breaks down numerically ``"breakdown"``, each with the reason naming the
    member, so one such member does not stop a campaign.
    """
    index, member, seed = task
    head = {"member": member.label, "index": index, "point": {k: str(v) for k, v in member.point},
            "seed": seed}
    system, loss = member.system()
    try:
        return {**head, **verify(system, loss, seed=seed, **kw)}
    except AssumptionError as exc:
        return {**head, "outcome": INAPPLICABLE, "reason": str(exc)}
    except NumericalBreakdownError as exc:
        return {**head, "outcome": BREAKDOWN, "reason": f"member {member.label}: {exc}"}


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
        if r["outcome"] in (INAPPLICABLE, BREAKDOWN):
            lines.append(f"{r['member']:<{width}}  {r['outcome'].upper()}: {' '.join(r['reason'].split())}")
            continue
        t, s = r["theory"], r["simulation"]
        low, high = s["rate_interval"]
        lines.append(f"{r['member']:<{width}}  theory {'stable' if t['stable'] else 'NOT stable':<10} "
                     f"growth {t['growth_rate']['exact']} ~ {float(t['growth_rate']['decimal']):.5g}; "
                     f"simulation {s['verdict']:<9} rate {s['rate']:.5g} [{low:.5g}, {high:.5g}], "
                     f"seeds {s['seeds']}; {r['outcome'].upper()}")
    counts = [f"{sum(r['outcome'] == o for r in reports)} {o}" for o in (*OUTCOMES, INAPPLICABLE, BREAKDOWN)]
    lines.append(f"{len(reports)} members: " + ", ".join(counts))
    return "\n".join(lines)
