"""Channel allocation under i.i.d. losses: the cheapest loss probabilities that keep every
block's margin at most a bound, as exact rationals the engine certifies.

In ``x_j = -ln eps_j`` the requirement is linear (Sui-You-Fu Theorem 4 with eq. 36): block ``i``
with modulus ``alpha_i`` and class period ``g_i`` keeps ``alpha_i^2 rho_i <= mu`` iff for every
hyperplane ``H`` of its elements ``sum_j k_j(H) x_j >= ln alpha_i^(2 g_i) - g_i ln mu``, ``k_j(H)``
counting sensor ``j``'s elements outside ``H``.  The usual energy model prices a channel at
``w_j x_j`` (the transmit energy that buys a loss probability ``eps_j`` grows as ``-ln eps_j``),
so the cheapest qualities solve a linear programme.  Its rows are generated as needed: solve over
the hyperplanes found so far, round the losses down to rationals, let the engine decide them,
and add the decisive hyperplanes of any block over the bound.  The programme over a subset of the
rows is a relaxation, so its optimum, bounded below exactly through its dual values (or solved
exactly by the pure-Python fallback), bounds the true optimum from below: the gap of the answer.
"""
from __future__ import annotations

import collections
import itertools
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Callable, Sequence

import flint
import sympy as sp

from .. import budget
from ..output import JsonDocument
from ..arguments import check_public
from ..engine.region import simplest
from ..engine.recovery import critical_recovery_rate
from ..engine.stability import Verdict, critical_loss_rate, stability
from ..errors import InputError, require_extra
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import to_exact
from ..model.gilbert_elliott import GilbertElliott
from ..model.iid import IID
from ..model.system import System
from .constraints import Cuts, HyperplaneCut, Requirement
from .programmes import cheapest_point
from .selection import candidate_costs


def _fraction(x: flint.arb) -> Fraction:
    mantissa, exponent = x.man_exp()
    return Fraction(int(mantissa)) * Fraction(2) ** int(exponent)


def _log_bounds(value: sp.Expr) -> tuple[Fraction, Fraction]:
    """Rational bounds of ``ln value`` for a positive algebraic ``value`` (certified: flint's ball
    logarithm of the certified rational bounds of ``value``)."""
    lo, hi = AlgebraicNumber.from_expr(value).refine(sp.Rational(1, 10 ** 30)).interval
    low = flint.arb(flint.fmpq(lo.numerator, lo.denominator)).log().lower()
    high = flint.arb(flint.fmpq(hi.numerator, hi.denominator)).log().upper()
    return _fraction(low), _fraction(high)


def _below(x: float) -> sp.Rational:
    """A rational loss probability at most ``exp(-x)`` (rounded down: a loss that low is safer)."""
    if x > 700:
        return sp.Integer(0)
    value = Fraction(math.exp(-x)).limit_denominator(10 ** 12)
    while value > 0 and math.exp(-x) < float(value):
        value = value * Fraction(999_999, 1_000_000)
    return sp.Rational(value.numerator, value.denominator)


def _near(x: float) -> sp.Rational:
    """The simplest rational within a relative 1e-9 below ``exp(-x)`` (or just above it)."""
    if x > 700:
        return sp.Integer(0)
    value = math.exp(-x)
    q = simplest(Fraction(value * (1 - 1e-9)), Fraction(value * (1 + 1e-12)))
    return sp.Rational(q.numerator, q.denominator)


@dataclass(frozen=True)
class Allocation(JsonDocument):
    """The cheapest i.i.d. loss probabilities found, certified by the engine.

    ``losses`` (exact rationals, one per sensor) meet ``requirement`` (the engine's ``verdict``
    says so); ``cost`` is ``sum_j w_j (-ln eps_j)`` at them (float), ``lower_bound`` a certified
    lower bound of the cost of *any* losses meeting it, so the answer is within ``gap`` of the
    optimum.  ``rows`` hyperplane constraints were generated in ``rounds`` rounds."""

    system: System = field(repr=False)
    requirement: Requirement = field(repr=False)
    weights: tuple[sp.Rational, ...] = field(repr=False)
    losses: tuple[sp.Rational, ...]
    cost: float
    lower_bound: Fraction
    verdict: Verdict = field(repr=False)
    rows: int
    rounds: int
    solver: str

    @property
    def gap(self) -> float:
        return self.cost - float(self.lower_bound)

    def __repr__(self) -> str:
        return (f"Allocation(losses={[str(e) for e in self.losses]}, cost={self.cost:.6g}, "
                f"lower_bound={float(self.lower_bound):.6g})")

    def __str__(self) -> str:
        names = self.system.sensor_names
        convex = self.solver.startswith("SLSQP")
        lines = [f"cheapest i.i.d. channel qualities meeting: {self.requirement.words}",
                 f"  cost {'(the given convex function)' if convex else 'sum w_j (-ln eps_j)'} = {self.cost:.6f}; "
                 f"no allocation costs less than {float(self.lower_bound):.6f} (gap {self.gap:.2e})"]
        lines += [f"  {n}: loss {e} ~ {float(e):.6f} ({'slope' if convex else 'weight'} {float(w):.6g})"
                  for n, e, w in zip(names, self.losses, self.weights)]
        lines.append(f"  verdict: limiting margin {self.verdict.limiting_margin.evalf(6)}; "
                     f"{self.rows} hyperplane rows in {self.rounds} rounds ({self.solver})")
        return "\n".join(lines)

    def _repr_latex_(self) -> str:
        eps = r",\ ".join(rf"\varepsilon_{{\mathrm{{{n}}}}} = {sp.latex(e)}" for n, e in zip(self.system.sensor_names, self.losses))
        return rf"${eps};\quad \mathrm{{cost}} = {self.cost:.6g} \geq {float(self.lower_bound):.6g}$"

    def to_dict(self) -> dict[str, Any]:
        return {"requirement": self.requirement.words, "sensors": list(self.system.sensor_names),
                "weights": [str(w) for w in self.weights], "losses": [str(e) for e in self.losses],
                "cost": self.cost, "lower_bound": str(self.lower_bound), "gap": self.gap,
                "margins": [str(m.exact) for m in self.verdict.margins], "rows": self.rows, "rounds": self.rounds,
                "solver": self.solver}


def allocate_channels(system: System, weights: Any = None, *, margin: Any = "1/2", solver: str = "auto",
                      max_rounds: int = 200, cost: Callable[[Any], float] | None = None) -> Allocation:
    """The cheapest i.i.d. loss probabilities ``eps_j`` (cost ``sum_j w_j (-ln eps_j)``) with every
    block's margin ``alpha_i^2 rho_i`` at most ``margin``.

    Parameters
    ----------
    system : System
    weights : sequence or mapping, optional
        Positive exact prices per sensor (in order or by name); default 1 each.
    margin : number, default 1/2
        A rational in (0, 1): the bound on every margin (1 would allow losses at the boundary).
    solver : {"auto", "highs", "python"}
        The linear programme's solver: HiGHS through SciPy, or SymPy's exact simplex.
    max_rounds : int, default 200
        Rounds of row generation before giving up.
    cost : callable, optional
        Instead of ``weights``: a convex differentiable cost of ``x = (-ln eps_j)`` (a NumPy
        array), minimised by SciPy's SLSQP over the same rows (the ``design`` extra); the lower
        bound is then the linear programme of its tangent at the answer (convexity makes the
        tangent a minorant), and ``weights`` are the tangent's slopes, by central differences:
        the bound holds as far as those slopes do (for the linear cost it holds exactly).

    Returns
    -------
    Allocation
        Exact rational losses the engine certifies, their cost, and a certified lower bound of
        the optimum.

    Examples
    --------
    ``A = 2R(pi/2)`` with sensors ``[1, 0]`` and ``[1, 1]``: the region is ``16 eps_1 eps_2^2 < 1``
    and ``16 eps_1^2 eps_2 < 1`` (:func:`~symkf.engine.region.stability_region`); with margin 1/2
    (``alpha^4 rho^2 <= 1/4``) both rows read ``x_1 + 2 x_2 >= ln 64`` and ``2 x_1 + x_2 >= ln 64``
    in ``x = -ln eps``, so at equal weights the optimum is ``x_1 = x_2 = ln 4``: ``eps = 1/4``
    each, cost ``2 ln 4 = 2.7726`` (by hand):

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> a = sk.design.allocate_channels(S)
    >>> [round(float(e), 6) for e in a.losses], round(a.cost, 4), round(float(a.lower_bound), 4)
    ([0.25, 0.25], 2.7726, 2.7726)
    """
    if solver not in ("auto", "highs", "python"):
        raise InputError(f"solver: {solver!r} is not one of 'auto', 'highs', 'python'")
    if cost is not None and (weights is not None or not callable(cost)):
        raise InputError("cost: give a callable cost of x = -ln(eps) (a NumPy array) instead of weights, not both")
    if isinstance(max_rounds, bool) or not isinstance(max_rounds, int) or max_rounds < 1:
        raise InputError(f"max_rounds: expected a positive int, got {max_rounds!r}")
    w = candidate_costs(system, weights, "weights")
    if any(v <= 0 for v in w):
        raise InputError("weights: every price must be positive (a free channel would be made lossless)")
    mu = to_exact(margin, "margin")
    if not mu.is_Rational or not 0 < mu < 1:
        raise InputError(f"margin: {mu} is not a rational in (0, 1); every block's margin alpha^2 rho stays at most it")
    d = system.d
    start = critical_loss_rate(system).exact * mu
    losses = tuple([_below(-float(sp.log(start).evalf(20)))] * d) if start != 0 else (sp.Integer(0),) * d
    requirement = Requirement(IID(list(losses)), mu, False, f"every margin alpha^2 rho at most {mu} (i.i.d. losses)")
    cuts = Cuts(system, requirement)
    rounds, safe = 0, False
    meter = budget.Meter("symkf.design.allocate_channels", "the row generation (a linear programme and a verdict "
                                                            "per round)")
    while True:
        meter.round()
        rounds += 1
        requirement = Requirement(IID(list(losses)), mu, False, requirement.words)
        cuts.requirement = requirement
        verdict, blocks = cuts.verdict(range(d))
        new = cuts.record(verdict, blocks, range(len(verdict.certificate)))   # every block: a row
        if requirement.met(verdict) and rounds > 1:
            break
        if rounds > max_rounds:
            raise InputError(f"max_rounds: {max_rounds} rounds of row generation did not reach an allocation the "
                             "engine certifies; raise max_rounds")
        # the simplest rationals near the minimiser, unless rounding them crossed a known row:
        # then the minimiser of rows with a slack, rounded down
        safe = safe or (not requirement.met(verdict) and new == 0 and rounds > 1)
        if cost is None:
            x, _ = _solve(cuts.hyperplane, w, mu, solver, point=True, slack=safe)
        else:
            x = _convex(cost, cuts.hyperplane, mu, d, slack=safe)
        losses = tuple(_below(v) if safe else _near(v) for v in x)
    x_final = [-float(sp.log(e).evalf(20)) if e != 0 else math.inf for e in losses]
    if cost is None:
        value = float(sum(float(wj) * xj for wj, xj in zip(w, x_final)))
    else:   # the tangent at the answer: a minorant of a convex cost, its slopes the weights of the bound
        value, w = _tangent(cost, x_final)
    _, bound = _solve(cuts.hyperplane, w, mu, solver, point=False)
    if cost is not None:
        bound = bound + Fraction(value) - sum((Fraction(int(wj.p), int(wj.q)) * Fraction(xj)
                                               for wj, xj in zip(w, x_final)), Fraction(0))
    return Allocation(system, requirement, w, losses, value, bound, verdict, len(cuts.hyperplane), rounds,
                      ("SLSQP, " if cost is not None else "")
                      + ("HiGHS" if solver != "python" and _has_scipy() else "SymPy simplex"))


@dataclass(frozen=True)
class RecoveryAllocation(JsonDocument):
    """Per-sensor recovery probabilities of Gilbert-Elliott channels (``fail`` fixed), stable and
    no single channel cheaper (:func:`allocate_recovery`): for each sensor, ``critical[j]`` is the exact least recovery that
    keeps the filter stable with the others at ``recover`` (Sui-You-Fu Theorem 9 with eq. 36;
    :func:`symkf.engine.recovery.critical_recovery_rate` with ``sensor``), and ``recover[j]`` is a
    rational within ``slack`` above it.  ``cost`` is ``sum_j w_j (-ln(1 - recover_j))``."""

    system: System = field(repr=False)
    fail: tuple[sp.Expr, ...]
    recover: tuple[sp.Rational, ...]
    critical: tuple[AlgebraicNumber, ...] = field(repr=False)
    weights: tuple[sp.Rational, ...] = field(repr=False)
    cost: float
    sweeps: int
    verdict: Verdict = field(repr=False)

    #: how the point was found, for reports
    method: str = ("local search: each sensor's recovery lowered to its exact critical value (the others "
                   "fixed) plus the slack, and exchanges from dear to cheap channels, until a sweep saves less than "
                   "the slack; certified: no single channel can be made cheaper (not a global optimum)")

    def __repr__(self) -> str:
        return f"RecoveryAllocation(recover={[str(q) for q in self.recover]}, cost={self.cost:.6g})"

    def _repr_latex_(self) -> str:
        q = r",\ ".join(rf"q_{{\mathrm{{{n}}}}} = {sp.latex(r)}" for n, r in zip(self.system.sensor_names, self.recover))
        return rf"${q};\quad \mathrm{{cost}} = {self.cost:.6g}$"

    def __str__(self) -> str:
        lines = [f"per-sensor recovery probabilities (fail {', '.join(map(str, self.fail))}): stable, cost "
                 f"sum w_j (-ln(1 - q_j)) = {self.cost:.6f} after {self.sweeps} sweeps"]
        lines += [f"  {n}: recover {q} ~ {float(q):.6f} (its critical value with the others fixed ~ "
                  f"{float(c.evalf(10)):.6f})" for n, q, c in zip(self.system.sensor_names, self.recover, self.critical)]
        lines.append(f"  method: {self.method}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        return {"fail": [str(f) for f in self.fail], "recover": [str(q) for q in self.recover],
                "critical": [str(c.exact) for c in self.critical], "weights": [str(w) for w in self.weights],
                "cost": self.cost, "sweeps": self.sweeps, "method": self.method,
                "margins": [str(m.exact) for m in self.verdict.margins]}


def allocate_recovery(system: System, fail: Sequence[Any], weights: Any = None, *, slack: Any = "1/1000",
                      max_sweeps: int = 20) -> RecoveryAllocation:
    """Per-sensor recovery probabilities ``q_j`` of Gilbert-Elliott channels with fail
    probabilities ``fail``, stable at low cost ``sum_j w_j (-ln(1 - q_j))``.

    The stability region in ``q`` is not a polyhedron (the rates are Perron roots of the channels'
    restricted transfers), so the answer is a local search, certified at its end: from the common
    critical recovery rate plus ``slack``, each sweep lowers every sensor (the dearest first) to a
    rational within ``slack`` above its exact critical value with the others fixed, then tries
    exchanges (a cheaper channel's recovery moved half or an eighth of the way to 1, a dearer one
    lowered to its new critical value), until a sweep saves less than ``slack``.  At the end every
    ``q_j`` is within ``slack`` of its exact critical value given the others (``critical``): no
    single channel can be made cheaper; exchanges of other sizes, or of several channels, might.

    Examples
    --------
    One sensor ``[1, 0]`` on ``2R(pi/2)`` failing with probability 1/100: its critical recovery
    rate is the common one (:func:`~symkf.engine.recovery.critical_recovery_rate`), and the answer
    is within the slack above it:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])
    >>> a = sk.design.allocate_recovery(S, ["1/100"])
    >>> q = sk.critical_recovery_rate(S, ["1/100"])
    >>> 0 < float(a.recover[0] - q.exact) <= 1e-3, a.verdict.stable
    (True, True)
    """
    w = candidate_costs(system, weights, "weights")
    if any(v <= 0 for v in w):
        raise InputError("weights: every price must be positive")
    if isinstance(max_sweeps, bool) or not isinstance(max_sweeps, int) or max_sweeps < 1:
        raise InputError(f"max_sweeps: expected a positive int, got {max_sweeps!r}")
    step = to_exact(slack, "slack")
    if not step.is_Rational or not 0 < step < 1:
        raise InputError(f"slack: {step} is not a rational in (0, 1)")
    fails = GilbertElliott(list(fail), ["1/2"] * system.d).fail if not isinstance(fail, GilbertElliott) else fail.fail
    if len(fails) != system.d:
        raise InputError(f"fail: {len(fails)} probabilities for {system.d} sensors")
    d = system.d
    # the common rate, one sweep (each sensor lowered, two trials per exchange from a dearer to a
    # cheaper channel) and the final pass: critical recovery rates of d sensors each; a further
    # sweep (at most max_sweeps) costs as much as the first
    exchanges = (d * d - sum(c * c for c in collections.Counter(w).values())) // 2
    budget.price("symkf.design.allocate_recovery",
                 lambda: f"{2 * d + 1 + 2 * exchanges} critical recovery rates of {d} sensors (the common one, a sweep "
                         f"with {exchanges} exchanges, the final pass)",
                 recovery_query=2 * d + 1 + 2 * exchanges, recovery_pair=(2 * d + 1 + 2 * exchanges) * d * d)
    common = critical_recovery_rate(system, list(fails))
    if common >= 1:
        raise InputError("fail: no common recovery probability below 1 makes the filter stable; no allocation exists")
    q = [_above(common, step)] * system.d
    names = system.sensor_names

    def lowered(point: list[sp.Rational], j: int) -> sp.Rational:
        return _above(critical_recovery_rate(system, list(fails), recover=point, sensor=names[j]), step)

    def cost_of(point: Sequence[sp.Rational]) -> float:
        return float(sum(float(wj) * -math.log1p(-float(qj)) for wj, qj in zip(w, point)))

    sweeps = 0
    while sweeps < max_sweeps:
        sweeps += 1
        before = cost_of(q)
        for j in sorted(range(system.d), key=lambda j: w[j], reverse=True):   # lower each, the dearest first
            q[j] = lowered(q, j)
        # exchanges: a cheap channel made better lets a dear one be lowered further
        for i, j in itertools.permutations(range(system.d), 2):
            if w[i] >= w[j]:
                continue
            for t in (sp.Rational(1, 2), sp.Rational(1, 8)):
                trial = list(q)
                trial[i] = q[i] + (1 - q[i]) * t
                trial[j] = lowered(trial, j)
                if cost_of(trial) < cost_of(q):
                    q = trial
                    break
        if cost_of(q) > before - float(step):
            break
    # every q_j's critical value at the final point (the others moved after it)
    critical = [critical_recovery_rate(system, list(fails), recover=q, sensor=names[j]) for j in range(system.d)]
    verdict = stability(system, GilbertElliott(list(fails), q))
    if not verdict.stable:   # pragma: no cover - each step keeps q_j above its critical value
        raise AssertionError("the allocated recovery rates are not stable")
    cost = float(sum(float(wj) * -math.log1p(-float(qj)) for wj, qj in zip(w, q)))
    return RecoveryAllocation(system, tuple(fails), tuple(q), tuple(critical), w, cost, sweeps, verdict)


def _above(value: AlgebraicNumber, step: sp.Rational) -> sp.Rational:
    """The simplest rational in ``(value, value + step)`` below 1 (``step`` when ``value`` is 0)."""
    lo, hi = value.refine(step / 8).interval
    top = min(Fraction(hi) + Fraction(int(step.p), int(step.q)) / 2, (Fraction(hi) + 1) / 2)
    r = simplest(Fraction(hi), top)
    return sp.Rational(r.numerator, r.denominator)


def _needs(rows: Sequence[HyperplaneCut], mu: sp.Rational, point: bool, slack: bool = False) -> list[Fraction]:
    """The rows' needs ``ln growth - g ln mu``: for the minimiser (``point``) rounded up (plus a
    slack when ``slack``), so that it meets the rows it was given; else rounded down, a relaxation
    whose bound holds."""
    mu_low, mu_high = _log_bounds(mu)
    needs = []
    for cut in rows:
        low, high = _log_bounds(cut.growth)
        needs.append(high - cut.period * mu_low + (_SLACK if slack else 0) if point else low - cut.period * mu_high)
    return needs


def _convex(cost: Callable[[Any], float], rows: Sequence[HyperplaneCut], mu: sp.Rational, d: int, slack: bool) -> list[float]:
    """The minimiser of a convex ``cost`` of ``x`` over the rows (SciPy's SLSQP, from the point
    where every row is met by equal ``x``)."""
    import numpy as np
    optimize = require_extra("scipy.optimize", "design", "a convex cost of the channel allocation")
    K = np.array([list(cut.outside) for cut in rows], dtype=float)
    b = np.array([float(n) for n in _needs(rows, mu, point=True, slack=slack)])
    start = np.full(d, max([0.0] + [n / max(k.sum(), 1) for k, n in zip(K, b)]) + 1.0)
    res = optimize.minimize(lambda x: float(cost(x)), start, method="SLSQP", bounds=[(0, None)] * d,
                            constraints=[{"type": "ineq", "fun": lambda x: K @ x - b, "jac": lambda x: K}],
                            options={"maxiter": 500, "ftol": 1e-12})
    if not res.success:
        raise InputError(f"cost: SLSQP did not converge ({res.message}); is the cost convex and differentiable?")
    return [max(float(v), 0.0) for v in res.x]


def _tangent(cost: Callable[[Any], float], x: Sequence[float]) -> tuple[float, tuple[sp.Rational, ...]]:
    """``cost(x)`` and its slopes at ``x`` (central differences), clipped at 0: the tangent plane,
    a minorant of a convex cost non-decreasing in each ``x_j``."""
    import numpy as np
    point = np.array(x, dtype=float)
    value = float(cost(point))
    slopes = []
    for j in range(len(point)):
        h = 1e-6 * max(1.0, abs(point[j]))
        up, down = point.copy(), point.copy()
        up[j] += h
        down[j] = max(point[j] - h, 0.0)
        slope = (float(cost(up)) - float(cost(down))) / (up[j] - down[j])
        slopes.append(sp.Rational(Fraction(max(slope, 0.0)).limit_denominator(10 ** 12)))
    return value, tuple(slopes)


def _has_scipy() -> bool:
    try:
        import scipy  # noqa: F401
    except ImportError:
        return False
    return True


def _solve(rows: Sequence[HyperplaneCut], w: Sequence[sp.Rational], mu: sp.Rational, solver: str,
           point: bool, slack: bool = False) -> tuple[list[float], Fraction]:
    """The programme over ``rows``: its minimiser and a lower bound of its optimum that holds
    exactly (the needs of :func:`_needs`)."""
    needs = _needs(rows, mu, point, slack)
    return cheapest_point([Fraction(int(v.p), int(v.q)) for v in w], [list(cut.outside) for cut in rows], needs, solver)


#: added to the needs of the minimiser's programme, so that rounding its losses to rationals
#: cannot undo a row it meets with equality
_SLACK = Fraction(1, 10 ** 9)


check_public(globals())
