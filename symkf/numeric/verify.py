"""Theory against simulation: the exact verdict of Sui-You-Fu Theorems 4/7 beside a Monte Carlo test.

:func:`verify` decides mean-square stability exactly (:func:`symkf.engine.stability.stability`)
and, independently, estimates the margin ``m = alpha^2 rho`` of ``E[tr P_k]`` by simulation
(:func:`symkf.numeric.montecarlo.divergence_test`), then compares them (:func:`judge`).  The
outcome is one of

* ``"consistent"``: the simulation decides the theory's verdict and its margin interval
  (when resolved) contains the exact margin ``max_i alpha_i^2 rho_i``;
* ``"contradiction"``: the exact margin lies outside the simulated margin interval (which
  also covers a stable theory meeting decisive growth, ``m < 1 <`` interval, and the
  reverse).  Either the theory or the simulation has a bug; the CLI exits with status 1.
  Intervals are at 99.9 % by default: an interval test flags a correct pair of theory and
  simulation with probability ``1 - confidence``, and a contradiction claims a bug (at 99 %
  the calibration's 234 resolved intervals missed once, by 0.002 %);
* ``"undecided"``: neither, with the reason (too close to the threshold for the budget,
  or the change of ``E[tr P_k]`` not resolved from its noise) and what would decide.

The simulation samples, for every loss model the engine decides (i.i.d., Gilbert-Elliott,
joint Markov, network), final loss bursts of the theory's decisive pattern (the sensors
and phases outside the limiting block's decisive hyperplane, eq. 36): the loss chain
conditioned to stay in the pattern (its restricted transfer ``M_H``) with exact likelihood
ratios, so the tilt changes the variance, never the estimate
(:func:`symkf.numeric.montecarlo.burst_sample`).  Covariances are propagated in square-root form
with a log-scale (:func:`symkf.numeric.filters.log_traces`), so divergent runs never overflow.

The margin, not a finite-horizon rate: on both sides of the threshold ``E_k = a m^k + b +
o(m^k)`` (unstable: the bounded part ``b`` and the geometric tail of shorter bursts;
stable: ``E_k`` rising or falling to its limit ``b``).  ``log E[tr P_k]`` at ``h, 2h, 3h``
gives ``m^h = (E_{3h} - E_{2h}) / (E_{2h} - E_h)``, in which ``b`` cancels exactly;
its interval is Fieller's for a ratio of normal differences
(:func:`symkf.numeric.montecarlo.margin_interval`).  One residual allowance remains
(:func:`symkf.numeric.montecarlo.polynomial_allowance`), ``delta = p ln((k + 2h) / (k + h)) / h``
(``p = 1`` for a diagonalizable limiting block: ``ln(3/2) / h``, 1.0 % at ``h = 40``; ``p =
3`` for a Jordan chain of length 2, :func:`symkf.numeric.montecarlo.polynomial_degree`), derived:
``p`` factors ``k`` in ``E_k`` raise the ratio by at most ``((k + 2h) / (k + h))^p``, so the
interval's lower end is lowered by ``delta``.  The horizons stay where float64 resolves every
sampled path (:func:`symkf.numeric.montecarlo.float_horizon`).  Simulated "unstable" means
the widened interval's lower end exceeds 1; "stable" means the Fieller interval's upper end
is below 1, or (margin not resolved) that ``E[tr P_k]`` grew by less than ``(1 +
tolerance)`` per step from ``h`` to ``3h``.  A stable simulation against an unstable theory
whose margin lies in the widened interval is "undecided", never "consistent".

"""

from __future__ import annotations

import html
import math
import textwrap
from dataclasses import dataclass
from typing import Any

import sympy as sp

from ..output import JsonDocument
from ..arguments import check_public
from ..errors import InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.text import printed_text
from ..model.loss import LossModel
from ..model.system import System
from .montecarlo import DivergenceResult, divergence_test, exact_growth_rate, polynomial_degree, verdict_plan
from ..run.progress import progress
from ..engine.stability import Verdict, critical_loss_rate, stability

OUTCOMES = ("consistent", "undecided", "contradiction")
#: outcome of a family member whose theorem assumptions fail (shown as --- in tables)
INAPPLICABLE = "inapplicable"
#: outcome of a family member whose simulation broke down numerically
BREAKDOWN = "breakdown"


def number_json(a: AlgebraicNumber | sp.Expr, digits: int = 12) -> dict[str, Any]:
    """JSON form of an exact value: exact string, decimal, isolating interval and minimal polynomial."""
    return (a if isinstance(a, AlgebraicNumber) else AlgebraicNumber.from_expr(a)).to_dict(digits)


@dataclass(frozen=True, repr=False)
class Verification(JsonDocument):
    """Theory against simulation for one system (:func:`verify`, ``sk.verify``).

    ``verdict`` is the exact :class:`~symkf.engine.stability.Verdict`; ``growth_rate`` the exact growth
    rate ``max(1, max_i alpha_i^2 rho_i)`` of ``E[tr P_k]`` and ``critical_common_loss_rate``
    the critical common i.i.d. loss rate (both :class:`~symkf.exact.algebraic.AlgebraicNumber`);
    ``simulation`` the Monte Carlo half in JSON form (floats: ``verdict``, the margin ``rate``
    with its ``rate_interval`` or None when not resolved, the finite-horizon ``growth`` with
    its interval, seeds, horizons, paths); ``outcome`` one of :data:`OUTCOMES`, ``reason`` why
    in words, ``rate_consistent`` whether the exact margin lies in the simulated interval (None
    when that is not resolved).  ``str()`` is the ``symkf verify`` report, ``to_dict()`` its
    ``--json`` document (without ``system`` and ``loss``).
    """

    verdict: Verdict
    growth_rate: AlgebraicNumber
    critical_common_loss_rate: AlgebraicNumber
    simulation: dict[str, Any]
    outcome: str
    reason: str
    rate_consistent: bool | None

    @property
    def stable(self) -> bool:
        return self.verdict.stable

    @property
    def margin(self) -> AlgebraicNumber:
        """The exact limiting margin ``max_i alpha_i^2 rho_i``."""
        return self.verdict.limiting_margin

    @property
    def simulated_margin(self) -> tuple[float, float, float] | None:
        """``(estimate, low, high)`` of the simulated margin, None when not resolved."""
        s = self.simulation
        return None if s["rate_interval"] is None else (s["rate"], *s["rate_interval"])

    def to_dict(self) -> dict[str, Any]:
        v = self.verdict
        theory = {"stable": v.stable, "theorem": v.theorem, "assumptions": list(v.assumptions),
                  "margins": [number_json(m) for m in v.margins], "limiting_block": v.limiting_block,
                  "growth_rate": number_json(self.growth_rate),
                  "critical_common_loss_rate": number_json(self.critical_common_loss_rate)}
        return {"theory": theory, "simulation": self.simulation, "outcome": self.outcome,
                "rate_consistent": self.rate_consistent, "reason": self.reason}

    def __str__(self) -> str:
        return summary(self.to_dict())

    def __repr__(self) -> str:
        sim = self.simulated_margin
        simulated = "not resolved" if sim is None else f"{sim[0]:.5g} in [{sim[1]:.5g}, {sim[2]:.5g}]"
        return (f"<Verification {self.outcome}: exact margin {self.margin.exact} ~ {float(self.margin):.6g} "
                f"({'stable' if self.stable else 'not stable'}), simulated {simulated}, "
                f"{self.simulation['paths']} paths per run>")

    def _repr_html_(self) -> str:
        return f"<pre>{html.escape(str(self))}</pre>"

    def _repr_latex_(self) -> str:
        m = self.margin
        state = "stable" if self.stable else "not stable"
        return (rf"$\max_i \alpha_i^2\rho_i = {sp.latex(m.exact)} \approx {m.evalf(6)}\ (\text{{{state}}});\quad"
                rf"\text{{simulation: {self.simulation['verdict']}; outcome: {self.outcome}}}$")


def verify(system: System, loss: LossModel, *, seed: int = 0, paths: int = 20_000, horizon: int = 120,
           tolerance: float = 0.01, confidence: float = 0.999, jobs: int = 1) -> Verification:
    """Run the exact verdict and a Monte Carlo test on ``(system, loss)`` (:class:`Verification`).

    ``seed``: the simulation's first seed (three runs take ``seed`` .. ``seed + 2``); ``paths``
    per run; ``horizon``: the longest horizon (capped where float64 stops resolving paths);
    ``tolerance`` and ``confidence``: the rules of the module docstring; ``jobs``: worker
    processes for the simulated paths.
    """
    with progress(2, "verify") as bar:
        v = stability(system, loss)
        growth_exact, critical = exact_growth_rate(v), critical_loss_rate(system)
        bar.update()
        sim = simulated_verdict(system, loss, v, seed=seed, paths=paths, horizon=horizon, tolerance=tolerance,
                                confidence=confidence, jobs=jobs)
        bar.update()
    return Verification(v, growth_exact, critical, sim, **judge(v, sim))


def approximately(exact: str, decimal: str | float, digits: int = 5) -> str:
    """``exact ~ decimal`` for people, or ``exact`` alone when the decimal would repeat it (``1``, ``1/2``)."""
    try:
        shown = f"{float(decimal):.{digits}g}"
    except ValueError:
        raise InputError(f"decimal: {decimal!r} is not a decimal number") from None
    return str(exact) if str(exact) == shown or str(exact) == shown.rstrip("0").rstrip(".") else f"{exact} ~ {shown}"


def judge(v: Verdict, sim: dict[str, Any]) -> dict[str, Any]:
    """``outcome``, ``reason`` and ``rate_consistent`` of a simulation against the exact verdict
    (rules in the module docstring)."""
    interval, tol = sim["rate_interval"], sim["tolerance"]
    margin = float(v.limiting_margin)
    side = "stable" if v.stable else "unstable"
    if interval is None:
        inside = None
    else:
        low, high = interval
        inside = low <= margin <= high
        if not inside:
            return {"outcome": "contradiction", "rate_consistent": False, "reason":
                    f"exact margin alpha^2 rho = {margin:.6g} outside the simulated {100 * sim['confidence']:g}% "
                    f"interval [{low:.5g}, {high:.5g}] of the margin"}
    if sim["verdict"] == side:
        decisive = sim.get("fieller_interval") if v.stable else interval
        how = (f"simulated margin interval [{decisive[0]:.5g}, {decisive[1]:.5g}] "
               f"{'below' if v.stable else 'above'} 1 and, widened by the allowance, containing the exact "
               f"margin {margin:.6g}"
               if decisive is not None and (decisive[1] < 1 if v.stable else decisive[0] > 1) else
               f"simulated growth of E[tr P_k] over horizons {sim['horizons'][0]}..{sim['horizons'][-1]}, "
               f"interval [{sim['growth_interval'][0]:.5g}, {sim['growth_interval'][1]:.5g}], below "
               f"1 + tolerance = {1 + tol:g}")
        return {"outcome": "consistent", "rate_consistent": inside, "reason": how}
    return {"outcome": "undecided", "rate_consistent": inside, "reason": _undecided(sim, margin, v.stable)}


def _undecided(sim: dict[str, Any], margin: float, stable: bool) -> str:
    """Why the simulation does not decide, and what budget would."""
    budget = f"{sim['paths']} paths x horizons {', '.join(map(str, sim['horizons']))}"
    if sim["rate_interval"] is None:
        return (f"the change of E[tr P_k] between the horizons is not resolved from the noise of {budget} "
                f"(the margin interval needs E_{{2h}} - E_h decisively nonzero); exact margin {margin:.6g}: "
                + ("more paths or a longer horizon would decide" if abs(margin - 1) > 0.005 else
                   "this close to 1 the change is too slow to show at any practical horizon"))
    low, high = sim["rate_interval"]
    text = f"simulated margin interval [{low:.5g}, {high:.5g}] contains 1 (too close to the threshold for {budget})"
    if sim["verdict"] not in ("undecided", "stable" if stable else "unstable"):
        return (text + f"; the finite-horizon growth is below 1 + tolerance = {1 + sim['tolerance']:g}, but the "
                f"exact margin {margin:.6g} > 1: growth this slow does not show at this horizon")
    f_low, f_high = sim["fieller_interval"]
    half = (math.log(f_high) - math.log(max(f_low, 1e-300))) / 2       # sampling error only
    # unstable is decided on the widened lower end: the allowance does not shrink with more paths
    gap = -math.log(sim["rate"]) if stable else math.log(sim["rate"]) - sim["allowance"]
    if gap > 0:
        text += f"; about {math.ceil(sim['paths'] * (half / gap) ** 2 * 1.2)} paths per run would decide"
    elif not stable and sim["rate"] > 1:
        text += (f"; the estimate is within the allowance {sim['allowance']:.3g} (log) of 1, which does not "
                 "shrink with more paths: a longer horizon would decide"
                 + (", beyond what float64 resolves here (the horizon is capped at "
                    f"{sim['horizons'][-1]}; montecarlo.float_horizon)" if "note" in sim else ""))
    else:
        text += "; the estimate itself is on the other side, as expected this close to the threshold"
    return text


def simulated_verdict(system: System, loss: LossModel, v: Verdict, *, seed: int = 0, paths: int = 20_000,
                      horizon: int = 120, tolerance: float = 0.01, confidence: float = 0.999,
                      jobs: int = 1) -> dict[str, Any]:
    """The simulation half of :func:`verify`, steered by the theory's verdict ``v`` (JSON form)."""
    plan = verdict_plan(system, v, loss)
    r = divergence_test(system, loss, seed=seed, horizon=horizon, paths=paths, plan=plan,
                        exact_rate=exact_growth_rate(v), tolerance=tolerance, confidence=confidence,
                        degree=polynomial_degree(system, v), jobs=jobs)
    return _divergence_json(r, horizon)


def _divergence_json(r: DivergenceResult, requested: int) -> dict[str, Any]:
    out = {"method": "divergence_test: importance sampling of final bursts of the decisive loss pattern, "
                      "square-root filter with log-scale; margin from the difference ratio of E[tr P_k] at "
                      "three horizons (Fieller interval)",
           "verdict": r.verdict, "rate": r.rate,
           "rate_interval": None if r.rate is None else [r.rate_low, r.rate_high],
           "fieller_interval": None if r.rate is None else [r.fieller_low, r.fieller_high],
           "allowance": r.allowance, "growth": r.growth, "growth_interval": [r.growth_low, r.growth_high],
           "confidence": r.confidence, "tolerance": r.tolerance, "paths": r.paths,
           "seeds": [None if r.seed is None else r.seed + j for j in range(len(r.horizons))],
           "horizons": list(r.horizons), "sampling": r.sampling,
           "effective_sample_sizes": [e.ess for e in r.estimates]}
    if r.horizon < requested:
        out["note"] = (f"horizon capped from {requested} to {r.horizon}: beyond it float64 cannot resolve the "
                       "covariance of a path after a burst of the decisive pattern (see montecarlo.float_horizon)")
    return out


def summary(report: dict[str, Any]) -> str:
    """The report as a few lines of plain text."""
    if not {"theory", "simulation"} <= set(report):
        raise InputError("report: expected a report of symkf.numeric.verify.verify (keys 'theory' and 'simulation')")
    t, s = report["theory"], report["simulation"]
    lines = [f"theory:     {'stable' if t['stable'] else 'NOT stable'} ({t['theorem']})",
             "            margins alpha_i^2 rho_i: " + ", ".join(
                 approximately(printed_text(m["exact"]), m["decimal"], 6) for m in t["margins"]),
             f"            exact growth rate of E[tr P_k]: "
             f"{approximately(printed_text(t['growth_rate']['exact']), t['growth_rate']['decimal'], 6)}",
             f"            critical common i.i.d. loss rate: "
             f"{approximately(printed_text(t['critical_common_loss_rate']['exact']), t['critical_common_loss_rate']['decimal'], 6)}",
             f"simulation: {s['verdict']} ({s['method']})",
             f"            margin {interval_text(s)}; growth over the horizons {s['growth']:.5g} "
             f"[{s['growth_interval'][0]:.5g}, {s['growth_interval'][1]:.5g}], tolerance {s['tolerance']:g}",
             f"            {s['paths']} paths per run, horizons {', '.join(map(str, s['horizons']))}, "
             f"seeds {', '.join(map(str, s['seeds']))}"]
    if "note" in s:
        lines.append(f"            note: {s['note']}")
    if report["rate_consistent"] is not None:
        lines.append(f"            exact margin {'inside' if report['rate_consistent'] else 'OUTSIDE'} "
                     "the simulated margin interval")
    lines.append(f"outcome:    {report['outcome'].upper()}: {report['reason']}")
    return "\n".join(wrapped for line in lines for wrapped in textwrap.wrap(
        line, 100, subsequent_indent=" " * 14, break_long_words=False, break_on_hyphens=False))


def interval_text(s: dict[str, Any], short: bool = False) -> str:
    """The simulated margin with its interval, or why there is none (``short``: for a table row),
    from the ``"simulation"`` object of :meth:`Verification.to_dict` (its ``rate``,
    ``rate_interval`` and ``confidence``)."""
    missing = [key for key in ("rate", "rate_interval", "confidence") if key not in s]
    if missing:
        raise InputError(f"s: the simulation object of Verification.to_dict() has the keys rate, rate_interval "
                         f"and confidence; {', '.join(missing)} missing")
    if s["rate_interval"] is None:
        return "not resolved" + ("" if short else " (E_k changes less than its noise between the horizons)")
    try:
        low, high = map(float, s["rate_interval"])
        rate, confidence = float(s["rate"]), float(s["confidence"])
    except (TypeError, ValueError, ArithmeticError):
        raise InputError("s: rate and confidence must be numbers and rate_interval a pair of numbers or None, got "
                         f"{s['rate']!r:.40}, {s['confidence']!r:.40}, {s['rate_interval']!r:.60}") from None
    if short:
        return f"{rate:.5g} in [{low:.5g}, {high:.5g}]"
    return f"{rate:.5g}, {100 * confidence:g}% interval [{low:.5g}, {high:.5g}] with the allowance"


check_public(globals())
