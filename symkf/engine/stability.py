"""Exact stability verdicts and critical values (Sui-You-Fu Theorems 4, 7 and 9).

The filter is mean-square stable iff ``alpha_i^2 rho_i < 1`` for every
eigen-block ``i`` (eq. 32); with ``g_i`` the block's projection period this is
``alpha_i^(2 g_i) rho_i^(g_i) < 1``, an exact comparison of an algebraic number
with 1.  Margin exactly 1 is not stable.
"""

from __future__ import annotations

import warnings

import sys
import textwrap
from dataclasses import dataclass, field
from functools import cached_property
from decimal import Decimal, localcontext
from fractions import Fraction
from typing import Any, Iterable, Sequence

import flint
import sympy as sp

from .rates import BlockRate

from .search import block_rate, least_iid_bound, outside_counts
from ..errors import AssumptionError, InputError
from ..output import JsonDocument
from ..exact.algebraic import AlgebraicNumber, real_kth_root, sympy_to_fmpz, with_prec
from ..arguments import check_public
from ..exact.numbers import sympify, to_exact
from ..exact.text import number_text, printed_text
from ..model.loss import LossModel, checked
from ..model.system import System
from .rows import BlockRows
from .blocks import block_rows


@dataclass(frozen=True)
class BlockCertificate:
    """What a reader needs to re-check one block's margin."""

    modulus: sp.Expr
    class_period: int                                # g: the block's class period (its governing period when periodic)
    decisive_elements: tuple[tuple[str, int], ...]  # (sensor name, phase) inside the decisive hyperplane
    rate_per_period: sp.Expr                         # rho_i^g
    margin_power: sp.Expr                            # alpha_i^(2g) rho_i^g, compared with 1
    interval: tuple[Any, Any]                        # exact rational bounds of the margin


def pattern_words(elements: Iterable[tuple[str, int]]) -> str:
    """A decisive loss pattern in words: the (sensor, phase) elements received in each period,
    every other packet lost (``[("s1", 0)]`` reads "s1 received at phase 0 only").

    >>> pattern_words([("s1", 0)]), pattern_words([])
    ('s1 received at phase 0 only', 'nothing received')
    >>> pattern_words([("a", 0), ("b", 1), ("a", 1)])
    'a received at phases 0 and 1, b at phase 1, nothing else'
    """
    phases: dict[str, list[int]] = {}
    for name, phase in elements:
        phases.setdefault(name, []).append(phase)
    if not phases:
        return "nothing received"

    def at(ks: list[int]) -> str:
        ks = sorted(ks)
        return f"phase {ks[0]}" if len(ks) == 1 else f"phases {', '.join(map(str, ks[:-1]))} and {ks[-1]}"

    parts = [f"{name} at {at(ks)}" for name, ks in phases.items()]
    first = parts[0].replace(" at ", " received at ", 1)
    return f"{first} only" if len(parts) == 1 else ", ".join([first, *parts[1:]]) + ", nothing else"


def _readable(expr: sp.Expr, pointer: str, degree: int | None = None) -> str:
    """``expr`` as text, or a pointer to the exact data when it is a root too long to read
    (the Perron root of a large lifted chain: a ``CRootOf`` of degree 56 for Example 4's robot;
    the modulus ``cos(pi/211)``: 40-digit coefficients of degree 105; ``2^6930 / 10^6160``, past
    Python's limit on integer-to-text conversion, for a class period of 3465)."""
    try:
        text = number_text(expr, 200) or printed_text(str(expr))
    except ValueError:
        text = None
    if text is not None and len(text) <= 200:
        return text
    what = (f"a root of a degree-{degree} polynomial" if degree else f"a closed form of {len(text)} characters"
            if text is not None else f"a closed form with integers of more than {sys.get_int_max_str_digits()} digits")
    return f"{what} (exact: {pointer}, or --json)"


def _approx(q: Any) -> str:
    """Six significant digits of an exact rational bound, also beyond the float range (A = 10^200)."""
    q = Fraction(q)
    try:
        return f"{float(q):.6g}"
    except OverflowError:
        with localcontext() as ctx:
            ctx.prec = 6
            return str(Decimal(q.numerator) / Decimal(q.denominator))


@dataclass(frozen=True)
class Verdict(JsonDocument):
    """Mean-square stability of the multi-sensor Kalman filter, with its certificate.

    Returned by :func:`stability`; ``bool(verdict)`` is ``verdict.stable``.

    Its fields:

    * ``stable``: whether every margin is below 1 (Sui-You-Fu eq. 32);
    * ``margins``: the exact ``alpha_i^2 rho_i`` per decided eigen-block;
    * ``limiting_block``: the index of the largest margin, None when no block decides;
    * ``theorem``: the theorem applied (Theorem 4 for one eigen-block, Theorem 7 for several);
    * ``assumptions``: the assumptions that were checked;
    * ``certificate``: per block a :class:`BlockCertificate` (modulus, governing period,
      decisive loss pattern, ``alpha^(2g) rho^g`` and exact rational bounds of the margin);
    * ``set_aside``: ``(eigenvalues, reason)`` of the blocks of modulus below 1 left out.

    Examples
    --------
    The system of :func:`stability` at ``eps = 1/10``: each of the four rows ``C_j A^k``
    spans a hyperplane (a line) holding no other row, so every decisive pattern receives one
    packet per period and loses three; the certificate names the first, ``s1``'s at phase 0,
    and ``alpha^4 rho^2 = 16 * (1/10)^3 = 2/125`` (by hand):

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> v = sk.stability(S, sk.IID(["1/10", "1/10"]))
    >>> bool(v), v.theorem, v.limiting_margin.exact
    (True, 'Theorem 4 with eq. (36)', sqrt(10)/25)
    >>> c = v.certificate[0]
    >>> c.class_period, c.decisive_elements, c.margin_power
    (2, (('s1', 0),), 2/125)
    """

    stable: bool
    margins: tuple[AlgebraicNumber, ...]   # alpha_i^2 rho_i per decided eigen-block
    limiting_block: int | None             # None when no block decides (every |lambda| < 1)
    theorem: str
    assumptions: tuple[str, ...]
    certificate: tuple[BlockCertificate, ...] = field(repr=False)
    set_aside: tuple[tuple[tuple[str, ...], str], ...] = ()  # (eigenvalues, why) of blocks left out

    def __bool__(self) -> bool:
        return self.stable

    def to_dict(self) -> dict[str, Any]:
        """The ``verdict`` object of ``symkf analyze --json``: the margins as exact numbers
        (:meth:`AlgebraicNumber.to_dict`), the theorem, the assumptions and the certificate."""
        return {"stable": self.stable, "theorem": self.theorem,
                "margins": [m.to_dict() for m in self.margins], "limiting_block": self.limiting_block,
                "assumptions": list(self.assumptions),
                "certificate": [{"modulus": str(c.modulus), "class_period": c.class_period,
                                 "decisive_received": [list(e) for e in c.decisive_elements],
                                 # text (json_text's default=str): a class period of 3465 makes it
                                 # 6000 digits, which the text verdict points to instead
                                 "alpha^(2g) rho^g": c.margin_power} for c in self.certificate]}

    @property
    def limiting_margin(self) -> AlgebraicNumber:
        """``max_i alpha_i^2 rho_i``; 0 when no block decides (every mode set aside, nothing grows)."""
        if self.limiting_block is None:
            return AlgebraicNumber.from_expr(sp.Integer(0))
        return self.margins[self.limiting_block]

    def __str__(self) -> str:
        lines = [f"{'stable' if self.stable else 'NOT stable'} ({self.theorem})"]
        for i, (m, c) in enumerate(zip(self.margins, self.certificate)):
            lo, hi = c.interval
            alpha = _readable(c.modulus, f"Verdict.certificate[{i}].modulus",
                              c.modulus.poly.degree() if isinstance(c.modulus, sp.CRootOf) else None)
            lines.append(f"  block {i}: alpha = {alpha}, class period g = {c.class_period}, "
                         f"margin alpha^2 rho = {_readable(m.exact, f'Verdict.margins[{i}].exact and .minpoly', m.minpoly.degree())} "
                         f"in [{_approx(lo)}, {_approx(hi)}]{'  <- limiting' if i == self.limiting_block else ''}")
            lines.append(f"    decisive pattern: {pattern_words(c.decisive_elements)}; "
                         f"alpha^{2 * c.class_period} * rho^{c.class_period} = "
                         f"{_readable(c.margin_power, f'Verdict.certificate[{i}].margin_power')}")
        for eigenvalues, why in self.set_aside:
            lines.append(f"  set aside: {', '.join(eigenvalues)} ({why})")
        lines.append("  assumptions checked: " + "; ".join(self.assumptions))
        return "\n".join(wrapped for line in lines for wrapped in textwrap.wrap(
            line.lstrip(), 100, initial_indent=line[:len(line) - len(line.lstrip())],
            subsequent_indent=line[:len(line) - len(line.lstrip())] + "    ",
            break_long_words=False, break_on_hyphens=False))

    def _repr_latex_(self) -> str:
        rows = " \\\\ ".join(f"{i} & {sp.latex(c.modulus)} & {c.class_period} & {sp.latex(m.exact)} \\approx {m.evalf(6)}"
                             for i, (m, c) in enumerate(zip(self.margins, self.certificate)))
        return (f"$\\text{{{'stable' if self.stable else 'not stable'} ({self.theorem})}}\\quad"
                f"\\begin{{array}}{{cccc}} i & \\alpha_i & g_i & \\alpha_i^2\\rho_i \\\\ \\hline {rows}\\end{{array}}$")


def _check_loss(system: System, loss: LossModel) -> tuple[LossModel, list[str]]:
    """The model for ``system`` (:func:`checked`) and the assumptions its verdict rests on."""
    loss = checked(loss, system, positive=True)
    brs = block_rows(system)
    out = [("A" if not system.set_aside() else "the decided blocks") + " diagonalizable (Assumption 3)"
           if not any(br.block.defective for br in brs) else
           "Jordan chains on |lambda| >= 1 (symkf's extension of Assumption 3, docs/sui.md)",
           "(A, C) observable" if system.observable else "(A, C) detectable (PBH on |lambda| >= 1)",
           _noise_assumption(system), "loss process " + loss.assumption]
    if loss.bernoulli is None and not all(br.block.is_periodic for br in brs):
        out.append("aperiodic block under Markov losses (symkf's extension of Theorem 9, docs/sui.md)")
    return loss, out


def _noise_assumption(system: System) -> str:
    """How the process noise meets the theorems' ``Q > 0`` (see :meth:`System.undriven`)."""
    if system.noise_definite:
        return "Q > 0"
    undriven = system.undriven()
    if not undriven:
        return "Q singular, (A, Q^(1/2)) controllable (PBH)"
    names = ", ".join(str(lam.expr) for lam in undriven)
    return f"Q singular, eigenvalue(s) {names} not driven by the noise (PBH on (A, Q^(1/2))), P0 > 0"


def _undriven_unit_block(system: System, br: BlockRows, margin: AlgebraicNumber) -> None:
    """Refuse a verdict that a unit-circle block with an undriven mode decides: with ``Q > 0`` a
    margin 1 there means linear growth, but an undriven mode's error need not grow."""
    if br.block.modulus != 1 or margin < 1:
        return
    undriven = {lam.key for lam in system.undriven()}
    modes = [str(lam.expr) for lam in br.block.members if lam.key in undriven]
    if modes:
        raise AssumptionError(
            f"the unit-circle eigenvalue(s) {', '.join(modes)} of A, not driven by Q, decide the verdict "
            f"(margin {margin.exact}): with Q > 0 that margin means unbounded growth, but an undriven mode's "
            "error can stay at its initial level",
            assumption="Q > 0, or (A, Q^(1/2)) controllable on the unit circle (Sui-You-Fu, Section II)",
            applies_instead="drive the mode (add process noise on it) or leave it out of the model")


def _margin(br: BlockRows, rate: BlockRate) -> tuple[AlgebraicNumber, sp.Expr]:
    """The block's margin ``alpha^2 rho = (alpha^(2g) rho^g)^(1/g)`` (Sui-You-Fu eq. 36) and the
    power ``alpha^(2g) rho^g``, in flint's arithmetic of algebraic numbers (:class:`_Bound`)."""
    g = br.class_period
    power = sympify(br.block.modulus.exact ** (2 * g) * rate.per_period)
    return _Bound(br.block.modulus, 2 * g, rate.per_period, g, sign=1).value(), power


def stability(system: System, loss: LossModel) -> Verdict:
    """Decide mean-square stability exactly (Sui-You-Fu Theorems 4 and 7 with eq. 36).

    Parameters
    ----------
    system : System
    loss : LossModel
        :class:`~symkf.model.iid.IID`, :class:`~symkf.model.gilbert_elliott.GilbertElliott`,
        :class:`~symkf.model.markov.MarkovLoss` or a network loss, without free symbols.

    Returns
    -------
    Verdict
        ``.stable``, the exact margins ``alpha_i^2 rho_i`` per eigen-block (stable iff all are
        below 1), the theorem used, the assumptions checked and a certificate naming the
        decisive loss pattern.

    Examples
    --------
    ``A = 2R(pi/2)`` has governing period 2; its four rows ``C_j A^k`` (k = 0, 1) point in
    four distinct directions, so the filter is blind when three of four packets of a period
    are lost: ``(alpha^2 rho)^2 = alpha^4 eps^3``, i.e. ``16/1000`` at ``eps = 1/10``.

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> v = sk.stability(S, sk.IID(["1/10", "1/10"]))
    >>> v.stable, v.margins[0].exact, v.margins[0].exact ** 2
    (True, sqrt(10)/25, 2/125)
    """
    loss, assumptions = _check_loss(system, loss)
    if loss.symbols:
        raise InputError(f"loss: symbols {sorted(map(str, loss.symbols))} have no value; "
                         "symkf.stability_conditions(system, loss) gives the stability region as conditions")
    margins, certs = [], []
    for br in block_rows(system):
        rate = block_rate(br, loss)
        margin, power = _margin(br, rate)
        _undriven_unit_block(system, br, margin)
        margins.append(margin)
        names = system.sensor_names
        certs.append(BlockCertificate(
            br.block.modulus.exact, br.class_period,
            tuple((names[br.elements[e].sensor], br.elements[e].phase) for e in sorted(rate.hyperplane)),
            rate.per_period, power, margin.refine(sp.Rational(1, 10 ** 12)).interval))
    limiting = max(range(len(margins)), key=lambda i: margins[i]) if margins else None
    stable = all(m < 1 for m in margins)
    theorem = ("no eigenvalue with |lambda| >= 1" if not margins else
               ("Theorem 4" if len(margins) == 1 else "Theorem 7") + " with eq. (36)")
    aside = tuple((tuple(e.label for e in b.members), why) for b, why in system.set_aside())
    return Verdict(stable, tuple(margins), limiting, theorem, tuple(assumptions), tuple(certs), aside)


def _vectors(system: System) -> list[tuple[AlgebraicNumber, int, tuple[int, ...]]]:
    """``(alpha_i, 2g, (k_1, ..., k_d))`` for every block and the exponent vectors that matter
    for a common loss ``eps``: its bound ``(alpha_i^(2g) eps^K)`` binds first at the fewest
    elements ``K`` outside, so only the hyperplanes holding the most elements
    (:func:`symkf.engine.search.outside_counts` with equal weights) are needed."""
    return [(br.block.modulus, 2 * br.class_period, ks)
            for br in block_rows(system) for ks in outside_counts(br, [1.0] * system.d)]


def critical_loss_rate(system: System, sensor: str | None = None, *, others: Sequence[Any] | None = None,
                       ray: Sequence[Any] | None = None) -> AlgebraicNumber:
    """The critical i.i.d. loss probability, exactly: stable iff loss < critical value.

    * default: a common loss probability ``eps`` for all sensors;
    * ``ray=(w_1, ..., w_d)``: losses ``eps * w_j``; the result is the critical ``eps``;
    * ``sensor=NAME, others=[...]``: that sensor's loss with the other sensors' losses fixed
      (``others`` lists the other ``d - 1`` losses in order, or all ``d`` with the named sensor's
      entry ignored).

    Each block gives ``alpha_i^(2g) * prod_outside(eps w_j) < 1`` for every hyperplane H,
    i.e. ``eps < (alpha_i^(2g) W_H)^(-1/K_H)``.  The value 1 means no loss rate below 1 destabilises;
    along a ray with a weight ``w_j > 1`` the value is at most ``1/w_j`` (the loss of sensor ``j``
    reaches 1 there: a warning names it when that, not a hyperplane, ends the stable range).

    Parameters
    ----------
    system : System
    sensor : str, optional
        Vary only this sensor's loss (then ``others`` gives the other sensors' losses).
    others : sequence, optional
        The fixed loss probabilities of the other sensors (exact numbers), or of all sensors.
    ray : sequence, optional
        Weights ``w_j`` of the losses ``eps * w_j``.

    Returns
    -------
    AlgebraicNumber
        The critical value, with ``.exact``, ``.minpoly`` and a certified ``.interval``.

    Examples
    --------
    Two sensors watching ``2R(pi/2)`` (see :func:`stability`): ``16 eps^3 < 1``.

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> eps = sk.critical_loss_rate(S)
    >>> eps.exact, eps.minpoly.as_expr()
    (2**(2/3)/4, 16*x**3 - 1)
    """
    d = system.d
    if sensor is None:
        if ray is not None and len(ray) != d:   # counted before a weight is read
            raise InputError(f"ray: {len(ray)} weights for {d} sensors")
        w = [to_exact(v, f"ray[{j}]") for j, v in enumerate(ray)] if ray is not None else [sp.Integer(1)] * d
        if len(set(w)) == 1:
            return _min_capped([_Bound(alpha, power, w[0] ** sum(ks), sum(ks)) for alpha, power, ks in _vectors(system)
                                if w[0] != 0 and sum(ks)])
        top = max((AlgebraicNumber.from_expr(wj) for wj in w), default=None)
        safe = 1 / top if top is not None and top > 1 else None   # losses above 1 beyond it
        value = _least(system, lambda x: [x * wj for wj in w], lambda a2g, ks: _ray_bound(a2g, ks, w), safe)
        if safe is not None and value > safe:   # the ray leaves the probabilities first: it ends there
            heaviest = system.sensor_names[max(range(d), key=lambda j: AlgebraicNumber.from_expr(w[j]))]
            warnings.warn(f"ray: sensor {heaviest}'s loss eps * {top.exact} reaches 1 at eps = {safe.exact}, before "
                          "any loss destabilises the filter; the critical value is capped there (stable along the "
                          "whole ray)", stacklevel=3)
            return safe
        return value
    j = system.sensor_index(sensor)
    if others is not None and len(others) == d - 1:   # the other sensors' losses only
        others = [*others[:j], 1, *others[j:]]
    if others is None or len(others) != d:
        raise InputError(f"others: give the {d - 1} loss probabilities of the other sensors, in order (or all {d}, "
                         f"entry {j} ignored)")
    fixed = [to_exact(v, f"others[{i}]") if i != j else sp.Integer(1) for i, v in enumerate(others)]

    def bound(a2g: AlgebraicNumber, ks: tuple[int, ...]) -> AlgebraicNumber | None:
        rest = sp.Mul(*[f ** k for i, (f, k) in enumerate(zip(fixed, ks)) if i != j])
        if ks[j] == 0:
            return AlgebraicNumber.from_expr(0) if _Bound(a2g, 1, rest, 1, sign=1).value() >= 1 else None
        return _Bound(a2g, 1, rest, ks[j]) if rest != 0 else None
    return _least(system, lambda x: [x if i == j else f for i, f in enumerate(fixed)], bound)


def _ray_bound(a2g: Any, ks: tuple[int, ...], w: Sequence[sp.Expr]) -> _Bound | None:
    """``eps`` at which ``alpha^(2g) prod_j (eps w_j)^(k_j)`` reaches 1 (``a2g`` = ``alpha^(2g)``,
    exact), None when it is 0: ``(a2g W)^(-1/k)`` as a :class:`_Bound` (a certified ball; flint's
    minimal polynomial only when :func:`_min_capped` needs the exact value)."""
    W = sp.Mul(*[wj ** k for wj, k in zip(w, ks)])
    return _Bound(AlgebraicNumber.from_expr(a2g), 1, W, sum(ks)) if W != 0 else None


def _least(system: System, losses, bound, safe: AlgebraicNumber | None = None) -> AlgebraicNumber:
    """The least hyperplane bound over every block, capped at 1: per block by the screened
    iteration (:func:`symkf.engine.search.least_iid_bound`; ``safe``: where the losses stop being at most
    1), else over every exponent vector (capped: :func:`symkf.engine.search.listed_hyperplanes`)."""
    one = AlgebraicNumber.from_expr(1)
    values = []
    for br in block_rows(system):
        a2g = br.block.modulus ** (2 * br.class_period)
        v = least_iid_bound(br, losses, lambda ks: bound(a2g, ks), one, sympify(a2g), _min_capped, safe)
        values.append(v if v is not None else
                      _min_capped([b for ks in outside_counts(br) if (b := bound(a2g, ks)) is not None]))
    return min(values, default=one)


def _positive_root(r: sp.CRootOf) -> bool:
    """Whether the ``CRootOf`` is a positive real number, decided on flint's certified balls (its index
    counts real roots first, ascending, as flint's does)."""
    try:
        return AlgebraicNumber._irreducible(sympy_to_fmpz(r.poly), int(r.index)) > 0
    except InputError:   # not real
        return False


class _Bound:
    """``(alpha^power c)^(sign/k)`` (``alpha > 0`` a block's modulus, ``c > 0``, ``k >= 1``): a
    critical value (``sign = -1``) or a margin (``sign = 1``).  A certified ball, and the exact
    value only when asked, from flint's minimal polynomials for rational ``c`` (sympy's minimal
    polynomial of a root of a high-degree ``CRootOf``, and its real-root isolation, are slow at the
    degrees of ``A = cos(pi/211)``); an algebraic ``c`` enters as its own minimal
    polynomial."""

    def __init__(self, alpha: AlgebraicNumber, power: int, c: sp.Expr, k: int, sign: int = -1) -> None:
        self.alpha, self.power, self.c, self.k, self.sign = alpha, power, sympify(c), k, sign
        self.key = (alpha, power, self.c, k, sign)

    def expr(self) -> sp.Expr:
        # sympy asks for the sign of a CRootOf by isolating every real root of its polynomial in pure
        # Python (most of the time of a dense 24 x 24 A, hopeless at degree 2016): positive roots enter
        # as positive symbols, which sympy's rules treat alike, and come back at the end
        alpha = self.alpha.exact
        stand_ins = {r: sp.Dummy(positive=True) for r in alpha.atoms(sp.CRootOf) if _positive_root(r)}
        base = sympify(alpha.xreplace(stand_ins) ** self.power) * self.c
        value = sympify(sp.root(base if self.sign > 0 else 1 / base, self.k))
        return value.xreplace({v: r for r, v in stand_ins.items()})

    def ball(self, prec: int) -> flint.arb:
        c = flint.fmpq(int(self.c.p), int(self.c.q)) if self.c.is_Rational else self._c._ball(prec).real
        return with_prec(prec, lambda: ((self.alpha._ball(prec).real ** self.power * c).log()
                                         * self.sign / self.k).exp())

    @cached_property
    def _c(self) -> AlgebraicNumber:
        return AlgebraicNumber.from_expr(self.c)

    def value(self) -> AlgebraicNumber:
        # the k-th root of gamma through p(x^k), also for algebraic c (a Gilbert-Elliott rate over
        # Q(sqrt 2)): sympy's minimal polynomial of the root of the product is far slower at k = 24
        # a rational alpha's power is a rational of power * log2(alpha) bits, cheap where the
        # exponent cap of AlgebraicNumber powers (a caller's exponents) refuses it: 2^90090 for five
        # rotations of class period 45045
        gamma = (AlgebraicNumber.from_expr(sp.Rational(self.alpha._value() ** self.power)) if self.alpha.is_rational
                 else self.alpha ** self.power) * self._c
        gamma = gamma if self.sign > 0 else 1 / gamma
        # sympy's root of a huge rational overflows a float in its perfect-power test (Gilbert-
        # Elliott losses at rationals near a critical recovery rate): no closed form then
        huge = gamma.is_rational and max(abs(gamma._value().numerator), gamma._value().denominator).bit_length() > 512
        exact = None if huge and self.k > 1 else self.expr()
        k = self.k
        if gamma.is_rational and k > 1:  # gamma = delta^q (q | k): the k-th root is delta's (k/q)-th root
            num, den = gamma._value().numerator, gamma._value().denominator
            for q in sp.primefactors(k):
                while k % q == 0:
                    (a, exact_a), (b, exact_b) = sp.integer_nthroot(abs(num), q), sp.integer_nthroot(den, q)
                    if not (exact_a and exact_b) or num < 0 and q == 2:
                        break
                    num, den, k = (a if num > 0 else -a), b, k // q
            gamma = AlgebraicNumber.from_expr(sp.Rational(num, den))
        if k == 1:
            return AlgebraicNumber._irreducible(gamma._poly, gamma._index, exact)
        f, index = real_kth_root(gamma, k, lambda prec: flint.acb(self.ball(prec)),
                                 "margin" if self.sign > 0 else "critical value")
        return AlgebraicNumber._irreducible(f, index, exact)


def _min_capped(bounds: list[_Bound | sp.Expr]) -> AlgebraicNumber:
    """The least bound, or 1 when none is below 1.  :class:`_Bound` candidates are compared by
    certified balls first, and only those the balls cannot separate from the least are made exact
    (the first least bound wins)."""
    values = [AlgebraicNumber.from_expr(b) for b in {b if isinstance(b, AlgebraicNumber) else sympify(b)
                                                     for b in bounds if not isinstance(b, _Bound)}]
    cands = list({b.key: b for b in bounds if isinstance(b, _Bound)}.values())
    one = flint.arb(1)
    for prec in (64, 256, 1024):
        balls = [b.ball(prec) for b in cands] + [v._ball(prec).real for v in values]
        cands = [b for b, z in zip(cands, balls) if not any(y < z for y in balls) and not one < z]
        if len(cands) <= 1:
            break
    values += [b.value() for b in cands]
    best = min(values, default=AlgebraicNumber.from_expr(1))
    return best if best < 1 else AlgebraicNumber.from_expr(1)


def critical_alpha(system: System, loss: LossModel) -> AlgebraicNumber:
    """For a single eigen-block (Assumption 1), the critical modulus: stable iff alpha < value,
    with the eigenvalue directions and the losses fixed.

    Parameters
    ----------
    system : System
        ``A`` with one eigen-block (all eigenvalues of one modulus).
    loss : IID

    Returns
    -------
    AlgebraicNumber

    Examples
    --------
    ``alpha^4 eps^3 < 1`` at ``eps = 1/10`` (see :func:`stability`): ``alpha < 10^(3/4)``.

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> sk.critical_alpha(S, sk.IID(["1/10", "1/10"])).exact
    10**(3/4)
    """
    brs = block_rows(system)
    if len(brs) != 1:
        raise AssumptionError(f"A has {len(brs)} eigen-blocks of different moduli" if brs else
                              "A has no eigenvalue with |lambda| >= 1 (every mode is set aside)",
                              assumption="Assumption 1 (single eigen-block)",
                              applies_instead="stability(system, loss) for each scaled system")
    loss, _ = _check_loss(system, loss)
    br = brs[0]
    rate = block_rate(br, loss)
    if rate.per_period == 0:
        raise InputError("every decisive pattern has probability 0: no critical alpha exists")
    return AlgebraicNumber.from_expr(sympify(sp.root(1 / rate.per_period, 2 * br.class_period)))


check_public(globals())
