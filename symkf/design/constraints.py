"""What a design must satisfy, and the constraints that rule candidate sets out.

A design query asks for a set ``S`` of a system's sensors (or for their channel qualities) such
that every eigen-block's margin ``alpha_i^2 rho_i`` (Sui-You-Fu eq. 36) stays below a bound under
a loss process: :class:`Requirement`.  The engine decides one set at a time (:meth:`Cuts.verdict`:
the system of ``S`` alone under the process seen through ``S``,
:class:`~symkf.model.subsets.Selected`).  A failing verdict names, per failing block ``i``, a
decisive hyperplane (the elements received); the whole system's elements in their span make a
hyperplane ``H``, and losing every element outside ``H`` for a whole period leaves the block
unobservable, so for *every* set ``T``

    ``alpha_i^(2 g_i) * prod_{j in T} r_j(H) >= bound^(g_i)``  implies that ``T`` fails too,

``r_j(H)`` being the rate at which sensor ``j``'s own channel loses its elements outside ``H``
(``eps_j^(k_j)`` for i.i.d. losses; a Perron root for a Gilbert-Elliott channel, Sui-You-Fu
Theorem 9), since ``rho_i^(g_i)`` is the largest such rate over the deficient patterns.  In the
logarithms ``w_j = -ln r_j(H)`` this is a covering constraint ``sum_{j in T} w_j > ln(alpha^(2g))
- g ln(bound)``: :class:`HyperplaneCut`.  Where the factors are not single sensors (a joint Markov
chain) the rates do not split by sensor and only monotonicity is used: a failing set ``U`` rules
out every subset of it (:class:`SubsetCut`), as adding a sensor never raises a rate.

Floats (the logarithms) only choose which sets to decide; every statement a result makes is
checked exactly (:meth:`HyperplaneCut.fails`, :meth:`Cuts.verdict`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

import sympy as sp

from ..arguments import check_public
from ..engine.blocks import block_rows
from ..engine.rows import BlockRows
from ..errors import BudgetError, UnobservableError
from ..exact.linalg import rank_rows
from ..engine.rates import Patterns, exact_rate, factor_rates
from ..engine.stability import Verdict, stability
from ..exact.algebraic import sign
from ..exact.numbers import sympify
from ..model.loss import LossModel, checked
from ..model.subsets import Selected
from ..model.system import System

#: slack of the float covering test: a set within it of a constraint's need counts as meeting
#: it, so the programme over the cuts relaxes the exact one (a lower bound) and the engine decides
TOLERANCE = 1e-9


def _log(value: Any) -> float:
    """``-ln value`` for an exact rate in ``[0, 1]`` (``inf`` at 0)."""
    v = sympify(value)
    if v == 0:
        return math.inf
    if v.is_Rational:
        return -(math.log(int(v.p)) - math.log(int(v.q)))
    return -float(sp.log(v).evalf(30))


def loss_words(loss: LossModel) -> str:
    """The model in a few words: its kind and parameters, a parameter shared by every sensor once."""
    fields = loss.fields()
    if not fields or any(len(values) != loss.d for _, _, values in fields):
        return loss.words()
    parts = [f"{key} {values[0]}" if len(set(values)) == 1 else f"{key} {', '.join(map(str, values))}"
             for key, _, values in fields]
    same = all(len(set(values)) == 1 for _, _, values in fields)
    return f"{loss.label[1]} losses, {'; '.join(parts)}" + (f" (each of {loss.d} sensors)" if same and loss.d > 1 else "")


@dataclass(frozen=True)
class Requirement:
    """Every block's margin ``alpha_i^2 rho_i`` below ``bound`` (``strict``) or at most it, under ``loss``.

    ``words`` says it for reports: "stable under i.i.d. losses 1/10", "critical i.i.d. loss rate
    at least 1/2" (the margins at that rate at most 1), ...
    """

    loss: LossModel
    bound: sp.Rational = sp.Integer(1)
    strict: bool = True
    words: str = ""

    def met(self, verdict: Verdict) -> bool:
        """Whether the verdict's margins meet the requirement (exact comparisons)."""
        return not self.failing_blocks(verdict)

    def failing_blocks(self, verdict: Verdict) -> list[int]:
        """The blocks whose margin breaks the bound."""
        return [i for i, m in enumerate(verdict.margins) if not (m < self.bound if self.strict else m <= self.bound)]


@dataclass(frozen=True)
class HyperplaneCut:
    """Block ``block`` fails for every set ``T`` with ``growth * prod_{j in T} rates[j] >=
    bound^period`` (``>`` when the requirement is not strict): the element set ``inside`` (indices
    of the block's elements received: a hyperplane's, or a smaller deficient span's) leaves the
    block unobservable, so that product is a lower bound of ``alpha^(2g) rho^g`` for ``T`` (module
    docstring)."""

    block: int
    period: int
    growth: sp.Expr                       # alpha^(2g), exact
    inside: frozenset[int]                # element indices of the block's rows inside H
    rates: tuple[sp.Expr, ...]            # per sensor: its channel's rate of losing its elements outside H
    outside: tuple[int, ...]              # per sensor: its elements outside H (k_j(H))
    weights: tuple[float, ...] = field(repr=False)   # -ln rates
    need: float = field(repr=False)       # ln growth - period * ln bound

    def fails(self, present: Sequence[int], requirement: Requirement) -> bool:
        """Exactly: whether the cut proves that the set ``present`` fails ``requirement``."""
        value = sympify(self.growth * sp.Mul(*[self.rates[j] for j in present]))
        s = sign(value - requirement.bound ** self.period)
        return s >= 0 if requirement.strict else s > 0


@dataclass(frozen=True)
class SubsetCut:
    """The set ``failing`` fails the requirement (decided by the engine), so every subset of it
    does: a set must hold a sensor outside it."""

    failing: tuple[int, ...]
    weights: tuple[float, ...] = field(repr=False)
    need: float = field(repr=False, default=1.0)

    def fails(self, present: Sequence[int], requirement: Requirement | None = None) -> bool:
        return set(present) <= set(self.failing)


def subset_cut(failing: Sequence[int], d: int) -> SubsetCut:
    inside = set(failing)
    return SubsetCut(tuple(sorted(inside)), tuple(0.0 if j in inside else 1.0 for j in range(d)))


def subsystem(system: System, indices: Sequence[int]) -> System:
    """The system of the sensors ``indices`` alone (same A, Q, P0)."""
    return System(A=system.A, sensors=[system.sensors[j] for j in indices], Q=system.Q, P0=system.P0)


def hyperplane_of(system: System, block: int, received: set[tuple[str, int]]) -> frozenset[int] | None:
    """The elements (indices into the block's rows of the whole ``system``) inside the span of the
    elements ``received`` (sensor name, phase): a hyperplane, or a smaller deficient subspace
    (an aperiodic block's decisive pattern may receive nothing); None when they span the block."""
    br = block_rows(system)[block]
    names = system.sensor_names
    return _closure(br, [e for e, el in enumerate(br.elements) if (names[el.sensor], el.phase) in received])


def outside_of(system: System, block: int, inside: frozenset[int]) -> tuple[int, ...]:
    """Per sensor, its elements of the block outside the element set ``inside`` (``k_j(H)``)."""
    out = [0] * system.d
    for e, el in enumerate(block_rows(system)[block].elements):
        if e not in inside:
            out[el.sensor] += 1
    return tuple(out)


def _closure(br: BlockRows, given: Sequence[int]) -> frozenset[int] | None:
    """Every element of the block inside the span of the elements ``given``, when that span is
    deficient (else None): a pattern receiving only these leaves the block unobservable."""
    basis: list = []
    for e in given:
        for row in br.generators[e]:
            if rank_rows(br.K, basis + [row], br.size) > len(basis):
                basis.append(row)
    if len(basis) >= br.size:
        return None
    return frozenset(e for e in range(len(br.elements))
                     if rank_rows(br.K, basis + list(br.generators[e]), br.size) == len(basis))


class Cuts:
    """The cuts a query has found, with the per-block rates of the loss model (built once)."""

    def __init__(self, system: System, requirement: Requirement):
        checked(requirement.loss, system, numbers=True, positive=True)
        self.system, self.requirement = system, requirement
        self.hyperplane: list[HyperplaneCut] = []
        self.subsets: list[SubsetCut] = []
        self.decisions = 0
        self._patterns: dict[int, Patterns | None] = {}
        self._seen: set[tuple[int, frozenset[int]]] = set()

    @property
    def all(self) -> list[HyperplaneCut | SubsetCut]:
        return [*self.hyperplane, *self.subsets]

    def _rates(self, i: int) -> Patterns | None:
        if i not in self._patterns:
            br = block_rows(self.system)[i]
            rates = factor_rates(br, self.requirement.loss)
            single = all(len(r.factor.sensors) == 1 for r in rates)
            self._patterns[i] = Patterns(br, rates) if single else None
        return self._patterns[i]

    def cut_of(self, i: int, received: set[tuple[str, int]], period: int, modulus: sp.Expr) -> HyperplaneCut | None:
        """The cut of block ``i`` whose decisive pattern receives the elements ``received`` (sensor
        name, phase): the deficient subspace they span (a hyperplane, or smaller), closed over every
        candidate's elements.  None when the loss model's factors are not single sensors, the
        elements span the block, or the cut is known."""
        patterns = self._rates(i)
        if patterns is None:
            return None
        inside = hyperplane_of(self.system, i, received)
        if inside is None or (i, inside) in self._seen:
            return None
        self._seen.add((i, inside))
        rates = [sp.Integer(1)] * self.system.d
        for r, masks in zip(patterns.rates, patterns.of_set(inside)):
            rates[r.factor.sensors[0]] = exact_rate(r.rate(masks))
        growth = sympify(modulus ** (2 * period))
        bound = self.requirement.bound
        need = -_log(growth) - (period * -_log(bound) if bound != 1 else 0.0)
        return HyperplaneCut(i, period, growth, inside, tuple(rates), outside_of(self.system, i, inside),
                             tuple(_log(r) for r in rates), need)

    def verdict(self, present: Sequence[int]) -> tuple[Verdict | None, list[int]]:
        """The engine's verdict on the system of the sensors ``present`` alone (its hyperplanes are
        those of its own elements, far fewer than the whole system's) and, per block of it, the
        index of the same block of the whole system.  None when ``present`` leaves a mode with
        ``|lambda| >= 1`` unseen."""
        try:
            sub = subsystem(self.system, present)
        except UnobservableError:
            return None, []
        verdict = stability(sub, Selected(self.requirement.loss, list(present)))
        where = {tuple(m.label for m in br.block.members): i for i, br in enumerate(block_rows(self.system))}
        return verdict, [where[tuple(m.label for m in br.block.members)] for br in block_rows(sub)]

    def record(self, verdict: Verdict, blocks: Sequence[int], which: Iterable[int]) -> int:
        """Record the cuts of the blocks ``which`` of ``verdict`` (its blocks are the whole system's
        ``blocks``); returns how many are new (a block whose growth never fails gives none)."""
        new = 0
        for i in which:
            cert = verdict.certificate[i]
            cut = self.cut_of(blocks[i], set(cert.decisive_elements), cert.class_period, cert.modulus)
            if cut is not None and cut.need > 0:
                self.hyperplane.append(cut)
                new += 1
        return new

    def decide(self, present: Sequence[int]) -> tuple[bool, Verdict | None]:
        """Decide ``present`` with the engine; when it fails, record its cuts."""
        self.decisions += 1
        verdict, blocks = self.verdict(present)
        if verdict is not None and self.requirement.met(verdict):
            return True, verdict
        if verdict is not None:
            self.record(verdict, blocks, self.requirement.failing_blocks(verdict))
        self.subsets.append(subset_cut(present, self.system.d))
        return False, verdict


check_public(globals())
