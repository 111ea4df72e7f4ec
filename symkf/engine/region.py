"""Stability regions in the loss parameters, exactly (Sui-You-Fu Theorems 4 and 7 with eq. 36).

Under i.i.d. losses block ``i`` (modulus ``alpha_i``, projection period
``g_i``) is stable iff ``alpha_i^(2 g_i) prod_j eps_j^(k_j(H)) < 1`` for every
hyperplane ``H`` of its elements, ``k_j(H)`` counting sensor ``j``'s elements
outside ``H`` (:func:`symkf.engine.search.outside_counts`).  The stability region is
the intersection of these monomial inequalities; only the componentwise
minimal exponent vectors matter, since ``eps^k`` decreases in ``k`` on
``[0, 1]``.  In ``(-ln eps_1, -ln eps_2)`` the region is an intersection of
half-planes, so for two sensors its boundary ``eps_2 = f(eps_1)`` is a
minimum of power laws ``(alpha^(2g) eps_1^(k_1))^(-1/k_2)``, with breakpoints
where two laws cross (algebraic numbers).

Under Gilbert-Elliott channels each hyperplane gives ``alpha^(2g) prod_j
tr(M_{H,j}) < 1`` with polynomial traces (:func:`symkf.engine.rates.hyperplane_rate`), so
with symbolic (fail, recover) the region is again an ``And`` of polynomial
inequalities, and along one varying parameter its boundary points are real
roots of polynomials (:func:`stable_intervals`).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable, Iterable, Sequence

import sympy as sp

from ..arguments import check_public
from .rates import hyperplane_rate
from .search import capped_hyperplanes, outside_counts, price_margins
from ..errors import InputError
from ..exact.algebraic import AlgebraicNumber, root_between, sign, sympy_to_fmpz, unit_roots
from ..exact.numbers import sympify, to_exact
from ..model.loss import LossModel, checked
from ..model.system import System
from .blocks import block_rows


@dataclass(frozen=True)
class Constraint:
    """``growth * prod_j eps_j^(exponents[j]) < 1``: one block's hyperplane condition."""

    block: int
    growth: sp.Expr                 # alpha_i^(2 g_i)
    exponents: tuple[int, ...]      # elements of each sensor outside the hyperplane
    hyperplane: frozenset[int]      # one hyperplane with these exponents (element indices)

    def margin(self, loss: Sequence[sp.Expr]) -> sp.Expr:
        """``growth * prod_j loss_j^(exponents[j])`` at the i.i.d. losses ``loss``: the condition holds iff < 1."""
        return self.growth * sp.Mul(*[e ** k for e, k in zip(loss, self.exponents)])


def iid_constraints(system: System) -> tuple[Constraint, ...]:
    """The non-redundant i.i.d. constraints of every block (minimal exponent vectors; cached)."""
    cached = system._cache.get("iid_constraints")
    if cached is None:
        out = []
        for i, br in enumerate(block_rows(system)):
            growth = sympify(br.block.modulus.exact ** (2 * br.class_period))
            vectors = outside_counts(br)
            for ks, H in vectors.items():
                if not any(o != ks and all(a <= b for a, b in zip(o, ks)) for o in vectors):
                    out.append(Constraint(i, growth, ks, H))
        cached = system._cache["iid_constraints"] = tuple(out)
    return cached


def _holds(expr: sp.Expr) -> bool:
    """Exact ``expr < 1`` for a numeric algebraic ``expr``."""
    return sign(sympify(expr) - 1) < 0


def _condition(margin: sp.Expr) -> sp.Basic:
    margin = sympify(margin)
    return sp.Lt(margin, 1) if margin.free_symbols else sp.true if _holds(margin) else sp.false


@dataclass(frozen=True)
class Piece:
    """On ``lo < eps_1 < hi`` the critical ``eps_2`` is ``expr`` (in the symbol ``eps_1``)."""

    lo: AlgebraicNumber
    hi: AlgebraicNumber
    expr: sp.Expr


@dataclass(frozen=True)
class StabilityRegion:
    """The exact i.i.d. stability region ``{(eps_1, ..., eps_d) in [0, 1]^d : stable}``.

    Returned by :func:`stability_region`: :meth:`conditions` as sympy inequalities,
    :meth:`contains` for exact membership, and for two sensors the boundary curve
    ``eps_2 = f(eps_1)`` (:meth:`boundary`, :meth:`boundary_at`).

    Examples
    --------
    ``A = 2R(pi/2)`` with sensors ``[1, 0]`` and ``[1, 1]``: governing period 2, four rows
    ``C_j A^k`` in distinct directions, so a hyperplane (a line) holds one of them and the
    three outside must all be lost.  By hand, the region is ``16 eps_1 eps_2^2 < 1`` and
    ``16 eps_1^2 eps_2 < 1``; the two laws ``eps_2 = 1/(4 sqrt(eps_1))`` and
    ``eps_2 = 1/(16 eps_1^2)`` cross at ``eps_1 = 2^(-4/3)``, and the first reaches 1 at
    ``eps_1 = 1/16``:

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> region = sk.stability_region(S)
    >>> region.contains("1/4", "1/4"), region.contains("1/2", "1/2")
    (True, False)
    >>> region.boundary_at("1/4").exact
    1/2
    >>> [(p.lo.exact, p.hi.exact, p.expr) for p in region.boundary()]
    [(0, 1/16, 1), (1/16, 2**(2/3)/4, 1/(4*sqrt(eps_s1))), (2**(2/3)/4, 1, 1/(16*eps_s1**2))]
    """

    system: System
    constraints: tuple[Constraint, ...]

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        """One nonnegative symbol ``eps_<sensor name>`` per sensor, the variables of the conditions."""
        return tuple(sp.Symbol(f"eps_{name}", nonnegative=True) for name in self.system.sensor_names)

    def conditions(self, loss: Sequence[Any] | None = None) -> sp.Basic:
        """``And`` of the constraints, in :attr:`symbols` or the given (symbolic or numeric) losses."""
        loss = self.symbols if loss is None else _losses(loss, self.system.d)
        return sp.And(*[_condition(c.margin(loss)) for c in self.constraints])

    def contains(self, *loss: Any) -> bool:
        """Exact membership of the loss vector ``(eps_1, ..., eps_d)`` (strict: margin 1 is outside)."""
        eps = _losses(loss, self.system.d)
        if any(e.free_symbols for e in eps):
            raise InputError("contains: give numbers; use conditions() for symbols")
        return all(_holds(c.margin(eps)) for c in self.constraints)

    def __str__(self) -> str:
        return f"stable iff {self.conditions()}"

    def _repr_latex_(self) -> str:
        return f"$\\text{{stable iff }} {sp.latex(self.conditions())}$"

    def boundary(self) -> tuple[Piece, ...]:
        """Two sensors: the critical ``eps_2 = f(eps_1)`` on ``0 < eps_1 < 1``, piecewise.

        Stable iff ``eps_2 < f(eps_1)``; ``f = 1`` where no ``eps_2 < 1`` destabilises and
        ``f = 0`` where ``eps_1`` alone destabilises (as :func:`symkf.engine.stability.critical_loss_rate`
        with ``sensor``, ``others``)."""
        if self.system.d != 2:
            raise InputError(f"boundary: the curve eps_2 = f(eps_1) needs 2 sensors, the system has {self.system.d}")
        e1 = self.symbols[0]
        laws = [sp.root(c.growth * e1 ** c.exponents[0], -c.exponents[1]) for c in self.constraints if c.exponents[1]]
        cuts = [c.growth * e1 ** c.exponents[0] for c in self.constraints if not c.exponents[1]]
        breaks = [AlgebraicNumber.from_expr(0), AlgebraicNumber.from_expr(1)]
        for c in self.constraints:  # where a law reaches 1, or eps_1 alone destabilises (k_2 = 0)
            if c.exponents[0]:
                breaks.append(AlgebraicNumber.from_expr(sp.root(1 / c.growth, c.exponents[0])))
        for a, b in _pairs([c for c in self.constraints if c.exponents[1]]):
            (a1, a2), (b1, b2) = a.exponents, b.exponents
            if a1 * b2 != b1 * a2:  # ga^b2 e^(a1 b2) = gb^a2 e^(b1 a2)
                breaks.append(AlgebraicNumber.from_expr(sp.root(b.growth ** a2 / a.growth ** b2, a1 * b2 - b1 * a2)))
        points = distinct(b for b in breaks if b >= 0 and b <= 1)
        pieces: list[Piece] = []
        for lo, hi in zip(points, points[1:]):
            t = between(lo, hi)
            if not all(_holds(cut.subs(e1, t)) for cut in cuts):
                expr = sp.Integer(0)
            else:
                expr = min([sp.Integer(1)] + laws, key=lambda law: AlgebraicNumber.from_expr(law.subs(e1, t)))
            if pieces and pieces[-1].expr == expr:
                pieces[-1] = Piece(pieces[-1].lo, hi, expr)
            else:
                pieces.append(Piece(lo, hi, expr))
        return tuple(pieces)

    def boundary_at(self, eps1: Any) -> AlgebraicNumber:
        """``f(eps_1)`` at one point: 0 if ``eps_1`` alone destabilises, else the least law, capped at 1."""
        if self.system.d != 2:
            raise InputError(f"boundary_at: needs 2 sensors, the system has {self.system.d}")
        e = _losses([eps1, 0], 2)[0]
        values = [AlgebraicNumber.from_expr(1)]
        for c in self.constraints:
            k1, k2 = c.exponents
            if not k2 and not _holds(c.growth * e ** k1):
                return AlgebraicNumber.from_expr(0)
            if k2 and (e != 0 or not k1):
                values.append(AlgebraicNumber.from_expr(sp.root(c.growth * e ** k1, -k2)))
        return min(values)


def distinct(values: Iterable[AlgebraicNumber]) -> list[AlgebraicNumber]:
    """The values sorted, exact duplicates removed."""
    out: list[AlgebraicNumber] = []
    for v in sorted(values):
        if not out or out[-1] != v:
            out.append(v)
    return out


def _pairs(items: list) -> list:
    return [(a, b) for i, a in enumerate(items) for b in items[i + 1:]]


def _losses(loss: Sequence[Any], d: int) -> tuple[sp.Expr, ...]:
    if len(loss) != d:
        raise InputError(f"loss: {len(loss)} values for {d} sensors")
    return tuple(to_exact(v, f"loss[{j}]", symbols=True) for j, v in enumerate(loss))


def stability_region(system: System) -> StabilityRegion:
    """The exact stability region of i.i.d. loss probabilities (all blocks, all hyperplanes).

    Sui-You-Fu Theorems 4 and 7 with eq. (36), as monomial inequalities in the losses.

    Parameters
    ----------
    system : System

    Returns
    -------
    StabilityRegion
        Its conditions are in one nonnegative symbol ``eps_<sensor name>`` per sensor.

    Examples
    --------
    For the system of :class:`StabilityRegion` (region derived there by hand):

    >>> import symkf as sk
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"),
    ...                                             sk.Sensor(C=[[1, 1]], name="s2")])
    >>> sk.stability_region(S).conditions()
    (16*eps_s1*eps_s2**2 < 1) & (16*eps_s1**2*eps_s2 < 1)
    """
    return StabilityRegion(system, iid_constraints(system))


def ge_margins(system: System, loss: LossModel) -> list[sp.Expr]:
    """Per block and hyperplane, ``alpha^(2g) rho(M_H)``: polynomials in (fail, recover)."""
    out = []
    for br in block_rows(system):
        growth = sympify(br.block.modulus.exact ** (2 * br.class_period))
        seen = set()
        price_margins(br, "the symbolic margin")
        for H in capped_hyperplanes(br):
            m = sp.expand(growth * hyperplane_rate(br, H, loss))
            if m not in seen:
                seen.add(m)
                out.append(m)
    return out


def stability_conditions(system: System, loss: LossModel) -> sp.Basic:
    """Mean-square stability as sympy conditions in the loss model's symbols.

    i.i.d.: an ``And`` of ``alpha^(2g) prod_j eps_j^(k_j) < 1``; Gilbert-Elliott: an ``And`` of
    ``alpha^(2g) prod_j tr(M_{H,j}) < 1`` (polynomials).  Parameters are taken to be
    probabilities (in ``[0, 1]``; in ``(0, 1)`` for Gilbert-Elliott, Assumption 2).  Numeric
    parameters give ``true`` or ``false``, decided exactly.

    Parameters
    ----------
    system : System
    loss : IID or GilbertElliott
        Its parameters exact numbers or sympy symbols.

    Returns
    -------
    sympy.logic.boolalg.Boolean
        An ``And`` of strict polynomial inequalities, or ``true`` / ``false``.

    Raises
    ------
    ShapeError
        The loss model's sensor count differs from the system's.
    InputError
        The model gives no conditions (a joint Markov or network loss:
        a joint Markov or network loss).

    Examples
    --------
    A scalar ``A = 2`` with one sensor on a Gilbert-Elliott channel: a run of losses continues
    with probability ``1 - q``, so (by hand) the filter is stable iff ``4 (1 - q) < 1``:

    >>> import sympy as sp
    >>> import symkf as sk
    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])])
    >>> q = sp.Symbol("q")
    >>> sk.stability_conditions(S, sk.GilbertElliott(fail=["1/4"], recover=[q]))
    4 - 4*q < 1
    >>> sk.stability_conditions(S, sk.IID(["1/5"]))  # 4/5 < 1
    True
    """
    loss = checked(loss, system)
    if loss.bernoulli is not None:       # i.i.d.: the monomial inequalities of the region
        return stability_region(system).conditions(loss.bernoulli)
    if loss.channel_fail is not None:    # two-state channels: polynomial margins per hyperplane
        return sp.And(*[_condition(m) for m in ge_margins(system, loss)])
    raise InputError(f"loss: stability conditions are given for i.i.d. losses and Gilbert-Elliott channels, not "
                     f"{loss.words()}; substitute numbers and use symkf.stability")


def between(a: AlgebraicNumber, b: AlgebraicNumber) -> sp.Rational:
    """A rational strictly between ``a < b`` (the simplest in the separating gap)."""
    while a.interval[1] >= b.interval[0]:
        a.refine(sp.Rational(a.interval[1] - a.interval[0]) / 4 or sp.Rational(1, 10 ** 30))
        b.refine(sp.Rational(b.interval[1] - b.interval[0]) / 4 or sp.Rational(1, 10 ** 30))
    lo, hi = a.interval[1], b.interval[0]
    return sp.Rational(simplest(lo, hi))


def simplest(lo: Fraction, hi: Fraction) -> Fraction:
    """The rational with least denominator in the open interval ``(lo, hi)``."""
    if not lo < hi:
        raise InputError(f"simplest: the interval ({lo}, {hi}) is empty; give lo < hi")
    q = 1
    while True:
        n = (lo * q).__floor__() + 1
        if Fraction(n, q) < hi:
            return Fraction(n, q)
        q += 1 if q < 64 else q


def roots_in_unit(expr: sp.Expr, t: sp.Symbol) -> list[AlgebraicNumber]:
    """Real roots in (0, 1) of ``expr = 0`` (a polynomial in ``t`` with algebraic coefficients):
    a superset, via the norm to Q when the coefficients are irrational."""
    if not isinstance(t, sp.Symbol):
        raise InputError(f"t: expected a sympy Symbol, got {type(t).__name__}")
    poly = sp.Poly(sp.expand(sympify(expr, "expr")), t, extension=True)
    if poly.is_zero or poly.degree() < 1:
        return []
    if not poly.domain.is_QQ and not poly.domain.is_ZZ:
        poly = poly.norm()
    # per factor its roots in (0, 1) by Descartes' rule, each made exact by its own ball: a factor
    # without one there has none of its complex roots isolated
    return [root_between(f, lo, hi) for f, _ in sympy_to_fmpz(poly.as_expr().subs(t, sp.Symbol("x"))).factor()[1]
            for lo, hi in unit_roots(f if f.leading_coefficient() > 0 else -f)]


def stable_intervals(margins: Sequence[sp.Expr], t: sp.Symbol) -> tuple[tuple[AlgebraicNumber, AlgebraicNumber], ...]:
    """The open set ``{t in (0, 1) : every margin(t) < 1}`` as disjoint open intervals, exactly.

    The margins are polynomials in ``t``; the set changes only at real roots of ``margin - 1``."""
    return stable_set([r for m in margins for r in roots_in_unit(m - 1, t)],
                      lambda v: all(_holds(sympify(m).subs(t, v)) for m in margins))


def stable_set(candidates: Sequence[AlgebraicNumber], stable_at: Callable[[Any], bool]
               ) -> tuple[tuple[AlgebraicNumber, AlgebraicNumber], ...]:
    """``{t in (0, 1) : stable_at(t)}`` as disjoint open intervals, given every point where the
    verdict can change (``candidates``): each gap is classified at a rational point, and a
    candidate between two stable gaps is kept as a boundary point unless it is stable itself."""
    points = distinct([AlgebraicNumber.from_expr(0), *candidates, AlgebraicNumber.from_expr(1)])
    out: list[tuple[AlgebraicNumber, AlgebraicNumber]] = []
    for lo, hi in zip(points, points[1:]):
        if not stable_at(between(lo, hi)):
            continue
        if out and out[-1][1] is lo and stable_at(lo.exact):
            out[-1] = (out[-1][0], hi)
        else:
            out.append((lo, hi))
    return tuple(out)

check_public(globals())
