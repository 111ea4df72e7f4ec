"""Sensor selection, exactly: the cheapest set of candidate sensors that meets a stability
requirement, and the front of cost against the critical i.i.d. loss rate.

Adding a sensor never raises a decay rate (it only adds received rows), so the sets that meet a
requirement are closed upwards.  The search alternates two steps until they agree: the cheapest
set meeting every constraint found so far (:func:`symkf.design.programmes.cheapest_cover`, a
relaxation of the exact problem, so its cost is a lower bound), and the engine's verdict on that
set (:meth:`symkf.design.constraints.Requirement.decide`).  A failing verdict adds the decisive
hyperplanes of its failing blocks as constraints on every candidate (Sui-You-Fu eq. 36 with the
rates split by sensor) and the failing set itself (monotonicity); a passing one ends the search
with the optimum.  The certificate lists those constraints: every cheaper set fails one of them,
each exactly, and :meth:`SelectionCertificate.check` re-derives all of it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Mapping, Sequence

import sympy as sp

from .. import budget
from ..output import JsonDocument
from ..arguments import check_public
from ..engine.blocks import block_rows
from ..engine.rates import exact_rate
from ..engine.region import between
from ..engine.stability import Verdict, critical_loss_rate
from ..errors import InputError, UnobservableError
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import sympify, to_exact
from ..model.gilbert_elliott import GilbertElliott
from ..model.iid import IID
from ..model.loss import LossModel, checked, probability
from ..model.system import System
from .constraints import TOLERANCE, Cuts, HyperplaneCut, Requirement, SubsetCut, loss_words, subset_cut, subsystem
from .programmes import cheapest_cover


def candidate_costs(system: System, costs: Any, entry: str = "costs") -> tuple[sp.Rational, ...]:
    """One exact non-negative cost per sensor: ``None`` (every sensor 1: the fewest sensors), a
    sequence in sensor order, or a mapping from sensor names (missing names cost 1); ``entry``
    names the argument in errors."""
    d, names = system.d, system.sensor_names
    if costs is None:
        return (sp.Integer(1),) * d
    if isinstance(costs, Mapping):
        unknown = [k for k in costs if k not in names]
        if unknown:
            raise InputError(f"{entry}: {unknown[0]!r} is not a sensor of the system ({', '.join(names)})")
        values = [costs.get(n, 1) for n in names]
        where = [f"{entry}[{n!r}]" for n in names]
    else:
        if isinstance(costs, (str, bytes)) or not isinstance(costs, Sequence):
            raise InputError(f"{entry}: expected one cost per sensor (a list or a mapping from sensor names), "
                             f"got {type(costs).__name__}")
        if len(costs) != d:
            raise InputError(f"{entry}: {len(costs)} costs for {d} sensors")
        values, where = list(costs), [f"{entry}[{j}]" for j in range(d)]
    out = []
    for v, at in zip(values, where):
        c = to_exact(v, at)
        if not c.is_Rational or c < 0:
            raise InputError(f"{at}: {c} is not a non-negative rational cost")
        out.append(c)
    return tuple(out)


def requirement_of(system: System, loss: LossModel | None, critical_rate: Any, recovery_rate: Any,
                   margin: Any) -> Requirement:
    """The :class:`Requirement` of a query: stable under ``loss`` (every margin below 1, or at
    most ``margin``); a critical common i.i.d. loss rate at least ``critical_rate`` (the margins at
    that rate at most 1); or, for Gilbert-Elliott channels with ``loss``'s fail probabilities, a
    critical common recovery rate at most ``recovery_rate``."""
    given = [k for k, v in (("critical_rate", critical_rate), ("recovery_rate", recovery_rate)) if v is not None]
    if len(given) > 1:
        raise InputError("give one of critical_rate and recovery_rate")
    d = system.d
    if critical_rate is not None:
        if loss is not None or margin is not None:
            raise InputError("critical_rate: asks for the critical common i.i.d. loss rate; give no loss or margin with it")
        t = probability(critical_rate, "critical_rate")
        return Requirement(IID([t] * d), sp.Integer(1), False, f"critical i.i.d. loss rate at least {t}")
    if recovery_rate is not None:
        fail = None if loss is None else loss.channel_fail
        if fail is None:
            raise InputError("recovery_rate: give the Gilbert-Elliott channels (loss=GilbertElliott(fail, recover); "
                             "their fail probabilities are kept, the recovery probability varies)")
        q = probability(recovery_rate, "recovery_rate")
        if margin is not None:
            raise InputError("recovery_rate: the requirement is the critical recovery rate; give no margin with it")
        channels = GilbertElliott(list(fail), [q] * d)
        return Requirement(channels, sp.Integer(1), False,
                           f"critical recovery rate at most {q} ({loss_words(channels).replace(f'; recover {q}', '')})")
    if loss is None:
        raise InputError("give the loss model (loss=...), a critical_rate or a recovery_rate")
    loss = checked(loss, system, numbers=True)
    if margin is None:
        return Requirement(loss, sp.Integer(1), True, f"stable under {loss_words(loss)}")
    mu = to_exact(margin, "margin")
    if not mu.is_Rational or not 0 < mu <= 1:
        raise InputError(f"margin: {mu} is not a rational in (0, 1]; every block's margin alpha^2 rho must stay at most it")
    return Requirement(loss, mu, False, f"every margin alpha^2 rho at most {mu} under {loss_words(loss)}")


@dataclass(frozen=True)
class SelectionCertificate:
    """Why no cheaper set meets the requirement: every set cheaper than the answer fails one of
    ``cuts`` (the covering programme over them, solved again by :meth:`check`), and each cut is
    exact: a :class:`~symkf.design.constraints.HyperplaneCut` (a deficient hyperplane whose rates
    the engine computes) or a :class:`~symkf.design.constraints.SubsetCut` (a set the engine
    decided failing, with all its subsets).  ``decisions`` counts the engine's verdicts."""

    cuts: tuple[HyperplaneCut | SubsetCut, ...]
    decisions: int
    solver: str

    def summary(self) -> str:
        hyper = sum(isinstance(c, HyperplaneCut) for c in self.cuts)
        return (f"{self.decisions} engine verdicts; every cheaper set fails one of {hyper} hyperplane "
                f"constraint(s) or lies inside one of {len(self.cuts) - hyper} failing set(s)")


@dataclass(frozen=True)
class Selection(JsonDocument):
    """The cheapest set of a system's sensors meeting a requirement, with its certificate.

    ``sensors`` (names) and ``indices`` of the chosen set, its exact ``cost``, the
    ``requirement`` in words, the engine's ``verdict`` for the chosen set (the others never
    delivering) and the ``certificate`` of optimality; ``None`` sensors when not even all
    candidates together meet the requirement (``verdict`` is then all candidates')."""

    system: System = field(repr=False)
    requirement: Requirement = field(repr=False)
    costs: tuple[sp.Rational, ...] = field(repr=False)
    indices: tuple[int, ...] | None
    verdict: Verdict = field(repr=False)
    certificate: SelectionCertificate = field(repr=False)

    @property
    def sensors(self) -> tuple[str, ...] | None:
        return None if self.indices is None else tuple(self.system.sensor_names[j] for j in self.indices)

    @property
    def cost(self) -> sp.Rational | None:
        return None if self.indices is None else sum((self.costs[j] for j in self.indices), sp.Integer(0))

    def __repr__(self) -> str:
        if self.indices is None:
            return f"Selection(none of {self.system.d} candidates: {self.requirement.words} fails with all)"
        return f"Selection(sensors={list(self.sensors)}, cost={self.cost}, {self.requirement.words})"

    def __str__(self) -> str:
        if self.indices is None:
            return (f"no set of the {self.system.d} candidate sensors meets: {self.requirement.words}\n"
                    f"  all of them together: limiting margin {self.verdict.limiting_margin.evalf(6)}")
        return "\n".join([
            f"cheapest set meeting: {self.requirement.words}",
            f"  sensors: {', '.join(self.sensors) or '(none)'} ({len(self.indices)} of {self.system.d}), cost {self.cost}",
            f"  its verdict: limiting margin {self.verdict.limiting_margin.evalf(6)} ({self.verdict.theorem})",
            f"  optimality: {self.certificate.summary()}"])

    def _repr_latex_(self) -> str:
        names = ", ".join(rf"\mathrm{{{n}}}" for n in (self.sensors or ()))
        return (rf"$S^\star = \{{{names}\}},\ \mathrm{{cost}} = {sp.latex(self.cost)},\ "
                rf"\max_i \alpha_i^2\rho_i = {sp.latex(self.verdict.limiting_margin.exact)}$")

    def to_dict(self) -> dict[str, Any]:
        """Exact values as strings: the chosen sensors, cost, requirement, margins and certificate counts."""
        return {"requirement": self.requirement.words, "candidates": list(self.system.sensor_names),
                "costs": [str(c) for c in self.costs],
                "sensors": None if self.indices is None else list(self.sensors),
                "cost": None if self.cost is None else str(self.cost),
                "margins": [str(m.exact) for m in self.verdict.margins],
                "certificate": {"decisions": self.certificate.decisions, "solver": self.certificate.solver,
                                "hyperplane_constraints": sum(isinstance(c, HyperplaneCut) for c in self.certificate.cuts),
                                "failing_sets": [[self.system.sensor_names[j] for j in c.failing]
                                                 for c in self.certificate.cuts if isinstance(c, SubsetCut)]}}

    def check(self) -> bool:
        """Re-derive the answer: the chosen set passes the engine; every hyperplane constraint is a
        deficient hyperplane with the rates the engine computes and every failing set fails again;
        and the covering programme over the constraints, solved by the pure-Python branch and bound,
        finds nothing cheaper.  Returns True, or raises :class:`AssertionError` naming what differs."""
        req, system = self.requirement, self.system
        fresh = Cuts(system, req)
        if self.indices is not None:
            verdict, _ = fresh.verdict(self.indices)
            assert verdict is not None and req.met(verdict), "the chosen set does not meet the requirement"
        else:
            verdict, _ = fresh.verdict(range(system.d))
            assert not req.met(verdict), "all candidates together meet the requirement"
            return True
        for cut in self.certificate.cuts:
            if isinstance(cut, SubsetCut):
                if not cut.failing:   # no sensor at all: every deciding block is blind (alpha^2 >= 1)
                    continue
                verdict, _ = fresh.verdict(cut.failing)
                assert verdict is None or not req.met(verdict), f"the set {cut.failing} meets the requirement"
            else:
                assert block_rows(system)[cut.block].deficient(cut.inside), "a constraint's hyperplane is not deficient"
                again = fresh._rates(cut.block)
                for r, masks in zip(again.rates, again.of_set(cut.inside)):
                    j = r.factor.sensors[0]
                    assert sp.simplify(exact_rate(r.rate(masks)) - cut.rates[j]) == 0, f"sensor {j}'s rate differs"
        best = cheapest_cover([float(c) for c in self.costs], [c.weights for c in self.certificate.cuts],
                              [c.need for c in self.certificate.cuts], TOLERANCE, solver="python")
        assert best is not None and sum(self.costs[j] for j in best) >= self.cost, "a cheaper set meets every constraint"
        return True


def _search(system: System, requirement: Requirement, costs: Sequence[sp.Rational], solver: str,
            cuts: Cuts | None = None) -> Selection:
    cuts = cuts or Cuts(system, requirement)
    every = tuple(range(system.d))
    ok, verdict = cuts.decide(every)
    if not ok:   # adding sensors never helps beyond all of them
        return Selection(system, requirement, tuple(costs), None, verdict,
                         SelectionCertificate(tuple(cuts.all), cuts.decisions, solver))
    if not verdict.margins:   # no block decides: nothing needs a sensor
        return Selection(system, requirement, tuple(costs), (), verdict,
                         SelectionCertificate(tuple(cuts.all), cuts.decisions, solver))
    # with no sensor every deciding block is blind (margin alpha^2 >= 1): the empty set fails
    cuts.subsets.append(subset_cut((), system.d))
    floats = [float(c) for c in costs]
    meter = budget.Meter("symkf.design", "the covering search (a covering programme and a verdict per round)")
    while True:
        meter.round()
        chosen = cheapest_cover(floats, [c.weights for c in cuts.all], [c.need for c in cuts.all], TOLERANCE, solver)
        chosen = every if chosen is None else chosen
        ok, verdict = cuts.decide(chosen)
        if ok:
            return Selection(system, requirement, tuple(costs), tuple(chosen), verdict,
                             SelectionCertificate(tuple(cuts.all), cuts.decisions, solver))


def select_sensors(system: System, loss: LossModel | None = None, *, costs: Any = None, critical_rate: Any = None,
                   recovery_rate: Any = None, margin: Any = None, solver: str = "auto") -> Selection:
    """The cheapest set of ``system``'s sensors (the candidates) that meets a stability requirement.

    Parameters
    ----------
    system : System
        All candidate sensors (together they must make ``(A, C)`` detectable).
    loss : LossModel, optional
        The candidates' loss process: the set must be stable under it (every margin below 1, or
        at most ``margin``).  Any loss model: i.i.d., Gilbert-Elliott, joint Markov, network.
    costs : sequence or mapping, optional
        Exact non-negative costs, per sensor in order or by name; default 1 each (the fewest sensors).
    critical_rate : number, optional
        Instead of ``loss``: the set's critical common i.i.d. loss rate must be at least this.
    recovery_rate : number, optional
        With Gilbert-Elliott ``loss`` (its fail probabilities): the set's critical common recovery
        rate must be at most this.
    margin : number, optional
        With ``loss``: every block's margin ``alpha_i^2 rho_i`` at most this rational in (0, 1].
    solver : {"auto", "highs", "python"}
        The covering programme's solver (HiGHS through SciPy, or the pure-Python branch and bound).

    Returns
    -------
    Selection
        The chosen sensors, their cost, the engine's verdict for them and the certificate that no
        cheaper set meets the requirement (:meth:`Selection.check` re-derives it).

    Examples
    --------
    ``A = 2R(pi/2)`` with three sensors: each alone needs ``16 eps < 1`` (a period of two steps is
    blind when one of its two packets is lost), any two ``16 eps^3 < 1`` (three of four lost, by
    hand).  At ``eps = 1/10`` one sensor is not enough and two are; the cheapest pair:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="a"),
    ...     sk.Sensor(C=[[0, 1]], name="b"), sk.Sensor(C=[[1, 1]], name="c")])
    >>> pick = sk.design.select_sensors(S, sk.IID("1/10", d=3), costs={"a": 5, "b": 2, "c": 3})
    >>> pick.sensors, pick.cost, pick.verdict.limiting_margin.exact
    (('b', 'c'), 5, sqrt(10)/25)

    A critical i.i.d. loss rate of at least 1/4 needs two sensors (any pair: ``a`` and ``b`` see
    the same two directions over a period, ``16 eps^2 <= 1``; the others four, ``16 eps^3 <= 1``):

    >>> sk.design.select_sensors(S, critical_rate="1/4").cost
    2
    """
    if solver not in ("auto", "highs", "python"):
        raise InputError(f"solver: {solver!r} is not one of 'auto', 'highs', 'python'")
    requirement = requirement_of(system, loss, critical_rate, recovery_rate, margin)
    return _search(system, requirement, candidate_costs(system, costs), solver)


@dataclass(frozen=True)
class ParetoPoint:
    """A set on the front: no cheaper set has a critical i.i.d. loss rate as high."""

    sensors: tuple[str, ...]
    cost: sp.Rational
    critical_rate: AlgebraicNumber


@dataclass(frozen=True)
class ParetoFront(JsonDocument):
    """The sets trading cost against the critical common i.i.d. loss rate, cheapest first
    (each the cheapest set whose critical rate exceeds the previous point's)."""

    points: tuple[ParetoPoint, ...]
    decisions: int

    def __repr__(self) -> str:
        return f"ParetoFront({len(self.points)} points: " + "; ".join(
            f"cost {p.cost} -> {float(p.critical_rate.evalf(6)):.4g}" for p in self.points) + ")"

    def __str__(self) -> str:
        lines = ["cost  critical i.i.d. loss rate  sensors"]
        lines += [f"{str(p.cost):>4}  {str(p.critical_rate.exact):<14} ~ {float(p.critical_rate.evalf(6)):.6f}  "
                  f"{', '.join(p.sensors)}" for p in self.points]
        return "\n".join(lines)

    def _repr_latex_(self) -> str:
        rows = r" \\ ".join(rf"{sp.latex(p.cost)} & {sp.latex(p.critical_rate.exact)} \approx "
                             rf"{float(p.critical_rate.evalf(8)):.6f} & \text{{{', '.join(p.sensors)}}}"
                             for p in self.points)
        return rf"$\begin{{array}}{{rll}} \text{{cost}} & \varepsilon_c & \text{{sensors}} \\ \hline {rows}\end{{array}}$"

    def to_dict(self) -> dict[str, Any]:
        return {"points": [{"sensors": list(p.sensors), "cost": str(p.cost), "critical_rate": str(p.critical_rate.exact),
                            "approx": float(p.critical_rate.evalf(15))} for p in self.points],
                "decisions": self.decisions}


def pareto_front(system: System, *, costs: Any = None, solver: str = "auto") -> ParetoFront:
    """Cost against the critical common i.i.d. loss rate: from the cheapest detectable set, each
    next point the cheapest set whose critical rate exceeds the last one's (exactly: stable at that
    rate), until no set does or the rate reaches 1.

    Examples
    --------
    The three sensors of :func:`select_sensors`, by hand: one sensor gives ``16 eps < 1``, a pair
    with ``c`` four directions per period (``16 eps^3 < 1``), all three six elements in three
    directions, two on each line (``16 eps^4 < 1``):

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="a"),
    ...     sk.Sensor(C=[[0, 1]], name="b"), sk.Sensor(C=[[1, 1]], name="c")])
    >>> [(len(p.sensors), p.cost, p.critical_rate.exact) for p in sk.design.pareto_front(S).points]
    [(1, 1, 1/16), (2, 2, 2**(2/3)/4), (3, 3, 1/2)]
    """
    if solver not in ("auto", "highs", "python"):
        raise InputError(f"solver: {solver!r} is not one of 'auto', 'highs', 'python'")
    weights = candidate_costs(system, costs)
    d, points = system.d, []
    # a point per number of sensors at unit costs (other costs may give more): each a covering
    # search deciding sets and a critical rate, a fixed cost and one growing about as d^2
    budget.price("symkf.design.pareto_front", lambda: f"the front of {d} sensors (up to {d} points, each a search "
                                                      "and a critical i.i.d. loss rate)",
                 front_point=d, front_pair=d * d * d)
    first, decisions = _cheapest_detectable(system, weights, solver)
    rate = critical_loss_rate(subsystem(system, first))
    points.append(ParetoPoint(tuple(system.sensor_names[j] for j in first), sum((weights[j] for j in first), sp.Integer(0)),
                              rate))
    while rate < 1:
        level = _just_above(system, rate)
        if level is None:
            break
        requirement = Requirement(IID([level] * d), sp.Integer(1), True,
                                  f"critical i.i.d. loss rate above {rate.exact}")
        found = _search(system, requirement, weights, solver)
        decisions += found.certificate.decisions
        if found.indices is None:
            break
        rate = critical_loss_rate(subsystem(system, found.indices))
        if points[-1].cost == found.cost:   # the same cost reaches further: the last one dominates
            points.pop()
        points.append(ParetoPoint(found.sensors, found.cost, rate))
    return ParetoFront(tuple(points), decisions)


def _just_above(system: System, rate: AlgebraicNumber) -> sp.Rational | None:
    """A rational ``v`` above ``rate`` with no critical common i.i.d. loss rate of any set of the
    sensors in ``(rate, v]`` (None when none exceeds ``rate``): each is ``alpha_i^(-2 g_i / K)`` for a
    block ``i`` and a count ``K`` of its elements (Sui-You-Fu eq. 36), so a set's rate exceeds
    ``rate`` iff it is stable at ``v``, a rational loss however high the degree of ``rate``."""
    floor = float(rate.evalf(20))
    candidates = []
    for br in block_rows(system):
        alpha, g = float(br.block.modulus.evalf(20)), br.class_period
        for K in range(1, len(br.elements) + 1):
            value = alpha ** (-2 * g / K)
            if value > floor * (1 - 1e-9) and value < 1:
                candidates.append((value, br, K))
    for _, br, K in sorted(candidates, key=lambda c: c[0]):
        exact = AlgebraicNumber.from_expr(sympify(br.block.modulus.exact ** (-sp.Rational(2 * br.class_period, K))))
        if exact > rate:
            return between(rate, exact)
    return sp.Integer(1) if rate < 1 else None


def _cheapest_detectable(system: System, costs: Sequence[sp.Rational], solver: str) -> tuple[tuple[int, ...], int]:
    """The cheapest set of sensors that sees every mode with ``|lambda| >= 1`` (PBH, by building
    its system): every critical rate above 0 needs it, and each such set has one (a deciding block
    with ``K >= 1`` elements lost per blind period gives ``alpha^(-2g/K) > 0``).  Failing sets rule
    out their subsets; returns the set and the number of sets decided."""
    failing: list[SubsetCut] = [subset_cut((), system.d)]
    decided = 0
    floats = [float(c) for c in costs]
    meter = budget.Meter("symkf.design", "the covering search (a covering programme and a verdict per round)")
    while True:
        meter.round()
        chosen = cheapest_cover(floats, [c.weights for c in failing], [c.need for c in failing], TOLERANCE, solver)
        decided += 1
        try:
            subsystem(system, chosen)
        except UnobservableError:
            failing.append(subset_cut(chosen, system.d))
            continue
        return tuple(chosen), decided


check_public(globals())
