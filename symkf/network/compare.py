"""Theorems 1-2 of Quevedo et al. against the exact verdict: critical parameters, sufficient versus exact.

For a Markov network state (Assumption 1) and a time-invariant ``A``,
:func:`~symkf.network.loss.induced_loss` is a loss model that the exact engine
(:func:`symkf.engine.stability.stability`, Sui-You-Fu Theorems 4, 7 and 9) decides.
Along one scalar parameter ``t`` of the network model (a link success
probability ``phi_{m|j}`` or a transition probability ``p_ij``, entering
polynomially), :func:`compare` computes three subsets of ``(0, 1)``, each as
open intervals with exact algebraic end points:

* Theorem 1 (eq. 22): ``nu_i(t) ||A||^2 < 1`` for every ``i``, polynomial
  inequalities (:func:`symkf.engine.region.stable_intervals`);
* Theorem 2 (eq. 32, as corrected in :mod:`.semi_markov`) on the same chain
  seen as semi-Markov with ``psi_j(1) = 1`` (Sec. VII-B), where it reduces to
  Theorem 1 -- computed independently, as a check;
* the exact stable set.  Block ``i`` is stable iff
  ``alpha_i^(2g) rho(M_H(t)) < 1`` for every hyperplane ``H`` (eq. 36), with
  ``M_H`` the chain's one-period transfer restricted to ``H``.  A margin can
  cross 1 only where ``det(I - alpha_i^(2g) M_H(t)) = 0`` (the Perron root is
  an eigenvalue), a polynomial in ``t``; its real roots in ``(0, 1)`` are the
  candidate end points, and each gap between them is classified by
  :func:`symkf.engine.stability.stability` at a rational point inside it (a candidate
  between two stable gaps by the engine at the candidate itself).

Theorem 1 is sufficient, so its set must lie inside the exact one
(:attr:`Comparison.sufficient_inside_exact`).  :data:`FAMILY` lists the
examples of the table in ``docs/quevedo.md``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, Sequence

import sympy as sp

from ..arguments import check_public
from ..engine.rates import restricted_transfer
from ..engine.search import capped_hyperplanes
from ..errors import AssumptionError, InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import sympify
from ..model.loss import LossModel
from ..model.system import Sensor, System
from ..engine.blocks import block_rows
from ..engine.region import distinct, roots_in_unit, stable_intervals, stable_set
from ..engine.stability import stability
from .conditions import theorem1
from .dynamics import PeriodicDynamics
from .loss import NetworkLoss, induced_loss
from .semi_markov import theorem2
from .state import MarkovNetworkState
from .tree import SensorTree

#: The scalar parameter every example varies.
t = sp.Symbol("t", positive=True)

Intervals = tuple[tuple[AlgebraicNumber, AlgebraicNumber], ...]


@dataclass(frozen=True)
class NetworkExample:
    """A sensor tree over a Markov network state with one parameter ``t`` in ``(0, 1)``.

    ``P`` (network-state transitions) and ``phi[m][j]`` may contain :data:`t`;
    ``C[m]`` is sensor ``S_m``'s observation matrix; ``parameter`` says what ``t`` is.
    """

    name: str
    source: str
    parameter: str
    A: Any
    C: Sequence[Any]
    parents: Sequence[int]
    P: Any
    phi: Any

    @cached_property
    def dynamics(self) -> PeriodicDynamics:
        return PeriodicDynamics(self.A, list(self.C))

    @cached_property
    def system(self) -> System:
        return System(self.A, [Sensor(C=c, name=f"S{m}") for m, c in enumerate(self.C, start=1)])

    @cached_property
    def loss(self) -> NetworkLoss:
        """The network loss with ``t`` symbolic."""
        return NetworkLoss(SensorTree(list(self.parents)), MarkovNetworkState(self.P), self.phi)

    @cached_property
    def engine_loss(self) -> LossModel:
        """:func:`induced_loss` with ``t`` symbolic (a lumped MarkovLoss or the hidden chain)."""
        return induced_loss(self.loss, self.dynamics)

    def at(self, value: Any) -> LossModel:
        """The engine's loss model at ``t = value``."""
        return self.engine_loss.subs({t: value})


@dataclass(frozen=True)
class Comparison:
    """Stable parameter sets of one example: Theorem 1, Theorem 2 (psi = 1) and the exact verdict."""

    example: NetworkExample
    theorem1: Intervals
    theorem2: Intervals
    exact: Intervals
    candidates: tuple[AlgebraicNumber, ...]   # roots of det(I - alpha^(2g) M_H(t)) in (0, 1)

    @property
    def sufficient_inside_exact(self) -> bool:
        """Every interval where Theorem 1 holds lies inside an exact stable interval."""
        return all(any(lo >= a and hi <= b for a, b in self.exact) for lo, hi in self.theorem1)

    @property
    def coverage(self) -> float | None:
        """Length of Theorem 1's set over the exact set's (display only; None if the exact set is empty)."""
        exact = _length(self.exact)
        return None if exact == 0 else _length(self.theorem1) / exact


def _length(intervals: Intervals) -> float:
    return sum(float(b) - float(a) for a, b in intervals)


def critical(intervals: Intervals) -> AlgebraicNumber | None:
    """The critical parameter when the set is ``(0, c)`` or ``(c, 1)``; None otherwise."""
    if len(intervals) != 1:
        return None
    lo, hi = intervals[0]
    if lo == 0 and hi != 1:
        return hi
    if hi == 1 and lo != 0:
        return lo
    return None


def describe(intervals: Intervals, digits: int = 6) -> str:
    """``t > c``, ``t < c``, ``all t``, ``never``, or the union of intervals, exact values with decimals."""
    def show(a: AlgebraicNumber) -> str:
        e = a.exact
        return str(e) if e.is_Rational else f"{a.evalf(digits)}"

    if not intervals:
        return "never"
    if len(intervals) == 1:
        lo, hi = intervals[0]
        if lo == 0 and hi == 1:
            return "all t"
        if lo == 0:
            return f"t < {show(hi)}"
        if hi == 1:
            return f"t > {show(lo)}"
    return " or ".join(f"{show(a)} < t < {show(b)}" for a, b in intervals)


def exact_candidates(example: NetworkExample) -> tuple[AlgebraicNumber, ...]:
    """Real roots in ``(0, 1)`` of ``det(I - alpha^(2g) M_H(t))`` over blocks and hyperplanes.

    ``M_H`` has zero columns outside the states received inside ``H`` at the
    last phase; those columns of ``I - c M_H`` are unit vectors, so the
    determinant is that of the principal submatrix on the other states.
    """
    loss = example.engine_loss
    roots = []
    for br in block_rows(example.system):
        growth = sympify(br.block.modulus.exact ** (2 * br.class_period))
        for H in capped_hyperplanes(br):  # symbolic t: no screen; refused up front when too many
            M = restricted_transfer(br, H, loss).applyfunc(sp.expand)
            keep = [j for j in range(M.cols) if not M.col(j).is_zero_matrix]
            if keep:
                det = sp.expand((sp.eye(len(keep)) - growth * M.extract(keep, keep)).det(method="berkowitz"))
                if det == 0:  # 1/growth is an eigenvalue for every t: its roots locate nothing
                    raise AssumptionError(f"{example.name}: det(I - alpha^(2g) M_H(t)) vanishes identically",
                                          assumption="isolated boundary candidates",
                                          applies_instead="symkf.stability at chosen values of t")
                roots += roots_in_unit(det, t)
    return tuple(distinct(roots))


def exact_stable_set(example: NetworkExample, candidates: Sequence[AlgebraicNumber]) -> Intervals:
    """The exact ``{t in (0, 1) : stable}``: gaps between candidates classified by the engine."""
    return stable_set(candidates, lambda v: stability(example.system, example.at(v)).stable)


def compare(example: NetworkExample) -> Comparison:
    """Theorem 1, Theorem 2 (psi = 1) and the exact stable sets of ``t`` for one example."""
    th1 = theorem1(example.loss, example.dynamics)
    semi = NetworkLoss(example.loss.tree, example.loss.state.as_semi_markov(), example.loss.phi.tolist())
    th2 = theorem2(semi, example.dynamics)
    cands = exact_candidates(example)
    return Comparison(example, stable_intervals(list(th1.lhs.values()), t),
                      stable_intervals(list(th2.lhs.values()), t), exact_stable_set(example, cands), cands)


def _r(s: str) -> sp.Rational:
    return sp.Rational(s)


#: The family of the table in docs/quevedo.md (hand-derived values in tests/network/test_network_compare.py).
FAMILY: tuple[NetworkExample, ...] = (
    NetworkExample("iid-scalar", "Sec. VI, |B| = 1 (i.i.d. dropouts)", "phi_{1|1}",
                   [[2]], [[[1]]], [0], [[1]], [[t]]),
    NetworkExample("ge-scalar-fail", "Sec. VI, phi = (1, 0): Gilbert-Elliott, p22 = 1/3", "p12",
                   [[_r("3/2")]], [[[1]]], [0], [[1 - t, t], [_r("2/3"), _r("1/3")]], [[1, 0]]),
    NetworkExample("ge-scalar-stay", "Sec. VI, phi = (1, 0): Gilbert-Elliott, p12 = 1/2", "p22",
                   [[_r("3/2")]], [[[1]]], [0], [[_r("1/2"), _r("1/2")], [1 - t, t]], [[1, 0]]),
    NetworkExample("ge-norm-vs-radius", "Sec. VI, phi = (1, 0), A 2x2 non-normal, C = I, p12 = 1/5", "p22",
                   [[1, 1], [0, _r("6/5")]], [[[1, 0], [0, 1]]], [0],
                   [[_r("4/5"), _r("1/5")], [1 - t, t]], [[1, 0]]),
    NetworkExample("fading-scalar", "Example 2: good/bad state, phi_{1|1} = 9/10", "phi_{1|2}",
                   [[_r("3/2")]], [[[1]]], [0], [[_r("9/10"), _r("1/10")], [_r("1/2"), _r("1/2")]],
                   [[_r("9/10"), t]]),
    NetworkExample("viic-plant-iid", "Sec. VII-C plant (33), C1 = [1 1], q_ij = 1/2 as a Markov chain",
                   "phi_{1|1} = phi_{1|2}", [[_r("5/4"), 0], [1, _r("11/10")]], [[[1, 1]]], [0],
                   [[_r("1/2"), _r("1/2")], [_r("1/2"), _r("1/2")]], [[t, t]]),
    NetworkExample("viic-plant-markov", "Sec. VII-C plant (33), C1 = [1 1], sticky good/bad states",
                   "phi_{1|2}", [[_r("5/4"), 0], [1, _r("11/10")]], [[[1, 1]]], [0],
                   [[_r("9/10"), _r("1/10")], [_r("1/10"), _r("9/10")]], [[_r("9/10"), t]]),
    NetworkExample("relay-rotation", "Example 2 channel, S2 relayed by S1, A = 2R(pi/2) (g = 2)",
                   "phi_{1|2} = phi_{2|2}", [[0, -2], [2, 0]], [[[1, 0]], [[0, 1]]], [0, 1],
                   [[_r("9/10"), _r("1/10")], [_r("1/2"), _r("1/2")]],
                   [[_r("9/10"), t], [_r("9/10"), t]]),
    NetworkExample("example3-tree", "Example 3 (Fig. 4), C_m = [1 m m^2], A = diag(2, 1, 1/2); "
                   "E1, E2 obstructed in state 2", "phi_{1|2} = phi_{2|2}",
                   sp.diag(2, 1, _r("1/2")), [[[1, m, m * m]] for m in range(1, 6)], [0, 0, 1, 2, 2],
                   [[_r("9/10"), _r("1/10")], [_r("3/10"), _r("7/10")]],
                   [[_r("19/20"), t], [_r("19/20"), t]] + [[_r("19/20"), _r("19/20")]] * 3),
)


def example(name: str) -> NetworkExample:
    """The member of :data:`FAMILY` called ``name``."""
    for ex in FAMILY:
        if ex.name == name:
            return ex
    raise InputError(f"name: {name!r} is not an example of the family; one of {', '.join(ex.name for ex in FAMILY)}")


def markdown_table(comparisons: Sequence[Comparison], digits: int = 6) -> str:
    """The comparison as a markdown table (exact end points; decimals for irrational ones)."""
    def fmt(c: AlgebraicNumber | None) -> str:
        if c is None:
            return "-"
        return str(c.exact) if c.exact.is_Rational else f"{c.evalf(digits)}"

    lines = ["| example | t | Theorem 1 holds | Theorem 2 (psi = 1) | exact: stable iff | "
             "critical t (Thm 1 / exact) | gap | coverage | Thm 1 inside exact |",
             "|---|---|---|---|---|---|---|---|---|"]
    for c in comparisons:
        s, e = critical(c.theorem1), critical(c.exact)
        gap = f"{abs(float(s) - float(e)):.{digits}g}" if s is not None and e is not None else "-"
        cov = "-" if c.coverage is None else f"{c.coverage:.4f}"
        param = c.example.parameter.replace("|", "\\|")  # a bare | would split the markdown cell
        lines.append(f"| {c.example.name} | {param} | {describe(c.theorem1, digits)} | "
                     f"{describe(c.theorem2, digits)} | {describe(c.exact, digits)} | {fmt(s)} / {fmt(e)} | "
                     f"{gap} | {cov} | {'yes' if c.sufficient_inside_exact else 'NO'} |")
    return "\n".join(lines)

check_public(globals())
