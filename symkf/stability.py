"""Exact stability verdicts and critical values (Sui-You-Fu Theorems 4, 7 and 9).

The filter is mean-square stable iff ``alpha_i^2 rho_i < 1`` for every
eigen-block ``i`` (eq. 32); with ``g_i`` the block's projection period this is
``alpha_i^(2 g_i) rho_i^(g_i) < 1``, an exact comparison of an algebraic number
with 1.  Margin exactly 1 is not stable.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import sympy as sp

from .decay import BlockRate, block_rate
from .errors import AssumptionError, InputError
from .exact.algebraic import AlgebraicNumber
from .exact.numbers import to_exact
from .losses import IID, LossModel
from .model import System
from .observability import BlockRows, block_rows


@dataclass(frozen=True)
class BlockCertificate:
    """What a reader needs to re-check one block's margin."""

    modulus: sp.Expr
    period: int
    decisive_elements: tuple[tuple[str, int], ...]  # (sensor name, phase) inside the decisive hyperplane
    rate_per_period: sp.Expr                         # rho_i^g
    margin_power: sp.Expr                            # alpha_i^(2g) rho_i^g, compared with 1
    interval: tuple[Any, Any]                        # exact rational bounds of the margin


@dataclass(frozen=True)
class Verdict:
    """Mean-square stability of the multi-sensor Kalman filter, with its certificate."""

    stable: bool
    margins: tuple[AlgebraicNumber, ...]   # alpha_i^2 rho_i per eigen-block
    limiting_block: int
    theorem: str
    assumptions: tuple[str, ...]
    certificate: tuple[BlockCertificate, ...] = field(repr=False)

    def __bool__(self) -> bool:
        return self.stable

    def __str__(self) -> str:
        lines = [f"{'stable' if self.stable else 'NOT stable'} ({self.theorem})"]
        for i, (m, c) in enumerate(zip(self.margins, self.certificate)):
            lo, hi = c.interval
            lines.append(f"  block {i}: alpha = {c.modulus}, period {c.period}, margin alpha^2 rho = {m} "
                         f"in [{float(lo):.6g}, {float(hi):.6g}]{'  <- limiting' if i == self.limiting_block else ''}")
            lines.append(f"    decisive pattern: only {list(c.decisive_elements) or 'nothing'} received; "
                         f"alpha^{2 * c.period} * rho^{c.period} = {c.margin_power}")
        lines.append("  assumptions checked: " + "; ".join(self.assumptions))
        return "\n".join(lines)

    def _repr_latex_(self) -> str:
        rows = " \\\\ ".join(f"{i} & {sp.latex(c.modulus)} & {c.period} & {sp.latex(m.exact)} \\approx {m.evalf(6)}"
                             for i, (m, c) in enumerate(zip(self.margins, self.certificate)))
        return (f"$\\text{{{'stable' if self.stable else 'not stable'} ({self.theorem})}}\\quad"
                f"\\begin{{array}}{{cccc}} i & \\alpha_i & g_i & \\alpha_i^2\\rho_i \\\\ \\hline {rows}\\end{{array}}$")


def _check_loss(system: System, loss: LossModel) -> list[str]:
    if not isinstance(loss, LossModel):
        raise InputError(f"loss: expected an IID, GilbertElliott or MarkovLoss, got {type(loss).__name__}")
    if loss.d != system.d:
        raise InputError(f"loss: the model has {loss.d} sensor(s), the system has {system.d} "
                         f"({', '.join(system.sensor_names)})")
    loss.require_positive()
    return ["A diagonalizable (Assumption 3)", "(A, C) observable",
            "loss process " + ("i.i.d. (Assumption 4)" if isinstance(loss, IID) else
                               "Markov with positive transitions (Assumption 2)")]


def _margin(br: BlockRows, rate: BlockRate) -> tuple[AlgebraicNumber, sp.Expr]:
    alpha = br.block.modulus.exact
    power = sp.sympify(alpha ** (2 * br.period) * rate.per_period)
    return AlgebraicNumber.from_expr(sp.root(power, br.period) if br.period > 1 else power), power


def stability(system: System, loss: LossModel) -> Verdict:
    """Decide mean-square stability exactly (Theorems 4 and 7 with eq. 36)."""
    assumptions = _check_loss(system, loss)
    margins, certs = [], []
    for br in block_rows(system):
        rate = block_rate(br, loss)
        margin, power = _margin(br, rate)
        margins.append(margin)
        names = system.sensor_names
        certs.append(BlockCertificate(
            br.block.modulus.exact, br.period,
            tuple((names[br.elements[e].sensor], br.elements[e].phase) for e in sorted(rate.hyperplane)),
            rate.per_period, power, margin.refine(sp.Rational(1, 10 ** 12)).interval))
    limiting = max(range(len(margins)), key=lambda i: margins[i])
    stable = all(m < 1 for m in margins)
    theorem = "Theorem 4" if len(margins) == 1 else "Theorem 7"
    return Verdict(stable, tuple(margins), limiting, theorem + " with eq. (36)", tuple(assumptions), tuple(certs))


def _exponents(br: BlockRows, weights: Sequence[sp.Expr]) -> list[tuple[int, sp.Expr]]:
    """Per hyperplane: (number of elements outside, product of their weights)."""
    out = []
    for H in br.hyperplanes:
        outside = [e for i, e in enumerate(br.elements) if i not in H]
        out.append((len(outside), sp.Mul(*[weights[e.sensor] for e in outside])))
    return out


def critical_loss_rate(system: System, sensor: str | None = None, *, others: Sequence[Any] | None = None,
                       ray: Sequence[Any] | None = None) -> AlgebraicNumber:
    """The critical i.i.d. loss probability, exactly: stable iff loss < critical value.

    * default: a common loss probability ``eps`` for all sensors;
    * ``ray=(w_1, ..., w_d)``: losses ``eps * w_j``; the result is the critical ``eps``;
    * ``sensor=NAME, others=[...]``: that sensor's loss with the other sensors' losses fixed
      (``others`` lists all d losses; the named sensor's entry is ignored).

    Each block gives ``alpha_i^(2g) * prod_outside(eps w_j) < 1`` for every hyperplane H,
    i.e. ``eps < (alpha_i^(2g) W_H)^(-1/K_H)``.  The value 1 means no loss rate below 1 destabilises.
    """
    d = system.d
    if sensor is None:
        w = [to_exact(v, f"ray[{j}]") for j, v in enumerate(ray)] if ray is not None else [sp.Integer(1)] * d
        if len(w) != d:
            raise InputError(f"ray: {len(w)} weights for {d} sensors")
        bounds = []
        for br in block_rows(system):
            a2g = br.block.modulus.exact ** (2 * br.period)
            for k, W in _exponents(br, w):
                if k == 0:
                    raise AssertionError("observability guarantees a non-empty complement")  # pragma: no cover
                if W != 0:
                    bounds.append(sp.root(1 / (a2g * W), k))
        return _min_capped(bounds)
    j = system.sensor_index(sensor)
    if others is None or len(others) != d:
        raise InputError(f"others: give the {d} loss probabilities of all sensors (entry {j} is ignored)")
    eps = sp.Symbol("eps", positive=True)
    fixed = [to_exact(v, f"others[{i}]") if i != j else eps for i, v in enumerate(others)]
    bounds = []
    for br in block_rows(system):
        a2g = br.block.modulus.exact ** (2 * br.period)
        for H in br.hyperplanes:
            outside = [e for i, e in enumerate(br.elements) if i not in H]
            k = sum(1 for e in outside if e.sensor == j)
            rest = sp.Mul(*[fixed[e.sensor] for e in outside if e.sensor != j])
            if k == 0:
                if AlgebraicNumber.from_expr(a2g * rest) >= 1:
                    return AlgebraicNumber.from_expr(0)
            elif rest != 0:
                bounds.append(sp.root(1 / (a2g * rest), k))
    return _min_capped(bounds)


def _min_capped(bounds: list[sp.Expr]) -> AlgebraicNumber:
    values = [AlgebraicNumber.from_expr(sp.sympify(b)) for b in bounds]
    best = min(values, default=AlgebraicNumber.from_expr(1))
    return best if best < 1 else AlgebraicNumber.from_expr(1)


def critical_alpha(system: System, loss: IID) -> AlgebraicNumber:
    """For a single eigen-block (Assumption 1), the critical modulus: stable iff alpha < value,
    with the eigenvalue directions and the losses fixed."""
    brs = block_rows(system)
    if len(brs) != 1:
        raise AssumptionError(f"A has {len(brs)} eigen-blocks of different moduli",
                              assumption="Assumption 1 (single eigen-block)",
                              applies_instead="stability(system, loss) for each scaled system")
    _check_loss(system, loss)
    br = brs[0]
    rate = block_rate(br, loss)
    if rate.per_period == 0:
        raise InputError("every decisive pattern has probability 0: no critical alpha exists")
    return AlgebraicNumber.from_expr(sp.sympify(sp.root(1 / rate.per_period, 2 * br.period)))
