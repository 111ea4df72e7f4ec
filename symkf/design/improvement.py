"""Which channel to improve: the rise of the critical i.i.d. loss rate when one sensor's channel
alone gets better, and the constraints that limit a system at its current losses, in words.

Along the ray where sensor ``j`` loses ``t * eps`` and every other sensor ``eps``, each block's
hyperplane ``H`` gives ``alpha^(2g) t^(k_j) eps^(K) < 1`` (``K = sum_l k_l(H)``), so the critical
``eps`` is ``min_H (alpha^(2g) t^(k_j))^(-1/K)``: piecewise a power of ``t``, rising as ``t``
falls, fastest through the hyperplanes where ``j`` has many elements outside (Sui-You-Fu Theorem 4
with eq. 36; :func:`symkf.engine.stability.critical_loss_rate` with ``ray``).  At ``t = 0``
(a lossless channel) only the hyperplanes holding all of ``j``'s elements remain.
"""
from __future__ import annotations

import html

from dataclasses import dataclass, field
from typing import Any, Sequence

import sympy as sp

from .. import budget
from ..output import JsonDocument
from ..arguments import check_public
from ..engine.blocks import block_rows
from ..engine.search import outside_counts
from ..engine.stability import critical_loss_rate, stability
from ..exact.algebraic import AlgebraicNumber, sign
from ..exact.numbers import sympify, to_exact
from ..model.loss import LossModel, checked
from ..model.system import System
from .constraints import hyperplane_of, outside_of


@dataclass(frozen=True)
class Upgrade:
    """Sensor ``sensor``'s channel made better alone, its loss ``t`` times the others' ``eps``:

    * ``elasticity``: ``d ln eps_c / d ln(1/t)`` at ``t = 1`` (exact), the smallest ``k_j(H) / K(H)``
      over the hyperplanes that decide the critical rate now: how fast it rises at first;
    * ``improved``: the critical rate at ``t = 9/10`` (a tenth fewer losses) and ``lossless`` at
      ``t = 0`` (exact);
    * :meth:`critical_at`: the whole curve, exactly.
    """

    system: System = field(repr=False)
    sensor: str
    elasticity: sp.Rational
    improved: AlgebraicNumber
    lossless: AlgebraicNumber

    def critical_at(self, t: Any) -> AlgebraicNumber:
        """The common critical rate when this sensor loses ``t * eps`` (``0 <= t <= 1``), exactly."""
        return _along(self.system, self.sensor, to_exact(t, "t"))


@dataclass(frozen=True)
class Upgrades(JsonDocument):
    """Every sensor's :class:`Upgrade`, the most valuable first (the largest critical rate with a
    tenth fewer of its losses, then the largest elasticity)."""

    base: AlgebraicNumber
    ranked: tuple[Upgrade, ...]

    def __repr__(self) -> str:
        return "Upgrades(" + ", ".join(f"{u.sensor}: {float(u.improved.evalf(6)):.4g}" for u in self.ranked) + ")"

    def __str__(self) -> str:
        lines = [f"common critical i.i.d. loss rate now {self.base.exact} ~ {float(self.base.evalf(8)):.6f}; "
                 "with a tenth fewer of one sensor's losses (elasticity at the start; lossless):"]
        lines += [f"  {u.sensor}: {float(u.improved.evalf(8)):.6f} (+{float(u.improved.evalf(8)) - float(self.base.evalf(8)):.6f}; "
                  f"{u.elasticity}; {float(u.lossless.evalf(8)):.6f})" for u in self.ranked]
        return "\n".join(lines)

    def _repr_latex_(self) -> str:
        rows = r" \\ ".join(rf"\text{{{u.sensor}}} & {sp.latex(u.elasticity)} & {float(u.improved.evalf(8)):.6f} & "
                             rf"{float(u.lossless.evalf(8)):.6f}" for u in self.ranked)
        return (rf"$\varepsilon_c = {sp.latex(self.base.exact)}\quad\begin{{array}}{{lccc}} \text{{sensor}} & "
                rf"\text{{elasticity}} & t = 9/10 & t = 0 \\ \hline {rows}\end{{array}}$")

    def to_dict(self) -> dict[str, Any]:
        return {"critical_rate": str(self.base.exact),
                "upgrades": [{"sensor": u.sensor, "elasticity": str(u.elasticity), "improved": str(u.improved.exact),
                              "lossless": str(u.lossless.exact)} for u in self.ranked]}


def _along(system: System, sensor: str, t: sp.Expr) -> AlgebraicNumber:
    """The common critical i.i.d. rate when ``sensor`` loses ``t`` times the others' loss."""
    return critical_loss_rate(system, ray=[t if n == sensor else 1 for n in system.sensor_names])


def _elasticities(system: System, base: AlgebraicNumber) -> list[sp.Rational]:
    """Per sensor, ``min k_j(H) / K(H)`` over the hyperplanes with ``alpha^(2g) eps_c^K = 1`` (the
    decisive ones at the critical rate): the heaviest hyperplanes of each block at equal weights."""
    out: list[sp.Rational | None] = [None] * system.d
    for br in block_rows(system):
        growth = sympify(br.block.modulus.exact ** (2 * br.class_period))
        for ks in outside_counts(br, [1.0] * system.d):
            K = sum(ks)
            if K and sign(growth * base.exact ** K - 1) == 0:
                for j, k in enumerate(ks):
                    share = sp.Rational(k, K)
                    out[j] = share if out[j] is None else min(out[j], share)
    return [sp.Integer(0) if v is None else v for v in out]


def upgrades(system: System) -> Upgrades:
    """For each sensor, how the common critical i.i.d. loss rate rises when its channel alone
    improves (its loss ``t`` times the others'), ranked from the most valuable.

    Examples
    --------
    ``A = 2R(pi/2)`` with sensors ``a = [1, 0]``, ``b = [0, 1]``, ``c = [1, 1]``: over a period of
    two steps the six elements lie on four lines, ``a`` at phase 0 with ``b`` at phase 1, ``a``
    at phase 1 with ``b`` at phase 0, and ``c``'s two alone.  A blind period keeps one line, so
    the decisive lines are the first two, losing one element of ``a``, one of ``b`` and both of
    ``c``: ``16 eps^4 < 1``, critical ``1/2``, elasticities ``1/4, 1/4, 2/4``.  With ``c``'s
    losses cut by a tenth (``t = 9/10``) those lines give ``16 (9/10)^2 eps^4 < 1``, ``eps_c =
    sqrt(10)/6``, below the bound ``(72/5)^(-1/5)`` of a line of ``c``; with ``a``'s, ``16 (9/10)
    eps^4 < 1``, ``(72/5)^(-1/4)`` (by hand):

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="a"),
    ...     sk.Sensor(C=[[0, 1]], name="b"), sk.Sensor(C=[[1, 1]], name="c")])
    >>> u = sk.design.upgrades(S)
    >>> u.base.exact, [(x.sensor, x.elasticity, x.improved.exact) for x in u.ranked]
    (1/2, [('c', 1/2, sqrt(10)/6), ('a', 1/4, 10**(1/4)*sqrt(3)/6), ('b', 1/4, 10**(1/4)*sqrt(3)/6)])
    """
    d = system.d
    # 2d + 1 critical rates, each a heaviest-hyperplane search whose cost grows about as d^2 here
    budget.price("symkf.design.upgrades", lambda: f"{2 * d + 1} critical i.i.d. loss rates of {d} sensors (the common "
                                                  "one and two along each sensor's ray)",
                 ray_query=(2 * d + 1) * d * d)
    base = critical_loss_rate(system)
    names = system.sensor_names
    shares = _elasticities(system, base)
    out = []
    for j, n in enumerate(names):
        out.append(Upgrade(system, n, shares[j], _along(system, n, sp.Rational(9, 10)), _along(system, n, sp.Integer(0))))
    return Upgrades(base, tuple(sorted(out, key=lambda u: (u.improved, u.elasticity), reverse=True)))


@dataclass(frozen=True)
class ActiveConstraint:
    """One block's decisive hyperplane at the current losses: its margin and, per sensor with
    elements outside the hyperplane, how many of its ``period`` phases a blind period loses."""

    block: int
    modulus: sp.Expr
    period: int
    margin: AlgebraicNumber
    outside: tuple[tuple[str, int], ...]

    @property
    def words(self) -> str:
        who = [n for n, _ in self.outside]
        together = (f"sensors {', '.join(who[:-1])} and {who[-1]} together limit" if len(who) > 1 else
                    f"sensor {who[0]} alone limits" if who else "no sensor sees")
        lost = "; ".join(f"{n} {k} of {self.period} phases" for n, k in self.outside)
        return (f"{together} block {self.block} (|lambda| = {self.modulus}, margin {float(self.margin.evalf(6)):.4g}): "
                f"a blind period loses {lost or 'nothing'}")


@dataclass(frozen=True)
class ActiveConstraints(JsonDocument):
    """The :class:`ActiveConstraint` of every deciding block, most binding first (a sequence)."""

    constraints: tuple[ActiveConstraint, ...]

    def __iter__(self):
        return iter(self.constraints)

    def __len__(self) -> int:
        return len(self.constraints)

    def __getitem__(self, i: int) -> ActiveConstraint:
        return self.constraints[i]

    def __str__(self) -> str:
        return "\n".join(c.words for c in self.constraints) or "no block decides (every |lambda| < 1)"

    def _repr_html_(self) -> str:
        rows = "".join(f"<tr><td>{c.block}</td><td>{html.escape(str(c.modulus))}</td><td>{c.period}</td>"
                       f"<td>{float(c.margin.evalf(6)):.4g}</td><td>{html.escape(', '.join(f'{n} {k}' for n, k in c.outside))}"
                       "</td></tr>" for c in self.constraints)
        return ("<table><tr><th>block</th><th>|&lambda;|</th><th>period</th><th>margin</th>"
                f"<th>phases lost in a blind period</th></tr>{rows}</table>")

    def to_dict(self) -> dict[str, Any]:
        return {"active": [{"block": c.block, "modulus": str(c.modulus), "period": c.period,
                            "margin": str(c.margin.exact), "outside": dict(c.outside), "words": c.words}
                           for c in self.constraints]}


def active_constraints(system: System, loss: LossModel) -> ActiveConstraints:
    """Per deciding block, the hyperplane that limits it under ``loss`` (the engine's decisive
    pattern, closed over every sensor's elements), with the sensors it names, most binding first.

    Examples
    --------
    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> print(sk.design.active_constraints(S, sk.IID(["1/10", "1/10"]))[0].words)
    sensors s1 and s2 together limit block 0 (|lambda| = 2, margin 0.1265): a blind period loses s1 1 of 2 phases; s2 2 of 2 phases
    """
    loss = checked(loss, system, numbers=True, positive=True)
    verdict = stability(system, loss)
    out = []
    for i, cert in enumerate(verdict.certificate):
        inside = hyperplane_of(system, i, set(cert.decisive_elements))
        counts = () if inside is None else outside_of(system, i, inside)
        outside = tuple((system.sensor_names[j], k) for j, k in enumerate(counts) if k)
        out.append(ActiveConstraint(i, cert.modulus, cert.class_period, verdict.margins[i], outside))
    return ActiveConstraints(tuple(sorted(out, key=lambda c: c.margin, reverse=True)))


check_public(globals())
