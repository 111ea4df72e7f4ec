"""The decisive hyperplane of an eigen-block and its rate (Sui-You-Fu Theorems 4, 7 and 9 with
eq. 36): ``rho_i^g = max_H`` of the rate of "received only inside ``H``" (:mod:`symkf.engine.rates`).

:func:`block_rate` chooses the search from the loss model's capabilities: independent
Bernoulli losses (``bernoulli``) take the i.i.d. screen, every other model the Markov search,
per independent factor.  Neither lists every hyperplane when a screen applies:
:func:`outside_counts` (i.i.d.), :func:`markov_search` (Markov losses) and
:func:`least_iid_bound` (critical loss rates along a ray or of one sensor) reduce them to
:meth:`~symkf.engine.rows.BlockRows.heaviest`, each with its no-miss argument; blocks in general
position beyond the list go through :mod:`symkf.engine.generic_hyperplanes`, blocks split into
cylinders through each cylinder's own search (:mod:`symkf.engine.cylinders`).
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction
from typing import Any, Callable, Sequence

import flint
import numpy as np
import sympy as sp

from .. import budget
from ..arguments import check_public
from ..errors import InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.numbers import sympify
from ..model.loss import LossModel
from . import generic_hyperplanes
from .rows import BlockRows, _set
from .rates import BlockRate, FactorRates, Patterns, exact_rate, factor_rates


def outside_counts(br: BlockRows, weights: Sequence[float] | None = None) -> dict[tuple[int, ...], frozenset[int]]:
    """Per distinct exponent vector ``(k_1, ..., k_d)`` -- the number of sensor ``j``'s elements
    outside a hyperplane ``H`` -- one such ``H``.  Under i.i.d. losses ``H`` decays at
    ``prod_j loss_j^(k_j)`` per period, so hyperplanes sharing a vector are interchangeable.

    ``weights`` (per sensor, floats >= 0): only the hyperplanes that may maximise ``sum_{e in H}
    weights[sensor e]`` (:meth:`BlockRows.heaviest`), which is all a caller minimising ``prod_j
    c_j^(k_j)`` with ``c_j = exp(-weights[j])`` needs; every hyperplane when the screen does not
    apply or every hyperplane is already known (cached: counting is then cheaper than the
    screen).  The screen's sets in lexicographic order keep the enumeration's tie-break (the
    first maximiser)."""
    if weights is not None and "inside" not in br.__dict__:
        heaviest = br.heaviest([weights[e.sensor] for e in br.elements])
        if heaviest is not None:
            return _outside_vectors(br, sorted(heaviest, key=sorted))
    return _outside_vectors(br, listed_hyperplanes(br))


def listed_hyperplanes(br: BlockRows) -> np.ndarray | list[frozenset[int]]:
    """Every hyperplane: with elements of several generators the search through their flats at
    floor 0 (:meth:`BlockRows.heaviest`, refused up front by its work estimate; index sets in
    lexicographic order), else :attr:`BlockRows.inside`, priced up front from their estimated
    number (:meth:`BlockRows.listing_estimate`) and refused above ``budget.Limits.max_work`` or,
    for the memory they take (:meth:`BlockRows.listing_bytes`), ``max_memory``."""
    if br.several_generators and "inside" not in br.__dict__:
        sets = br.heaviest([0.0] * len(br.elements), floor=0.0)
        if sets is not None:
            return sorted(sets, key=sorted)
    if "inside" not in br.__dict__ and br.size > 1:
        estimate, formula = br.listing_estimate()
        entry = f"eigen-block of modulus {br.block.modulus}"
        unit = "flat_hyperplane_degree" if br.through_element_flats else "hyperplane_degree"
        budget.price(entry, f"listing the hyperplanes ({formula}; no screen applies) over a field of degree "
                            f"{br.K.degree}", **{unit: estimate * br.K.degree})
        budget.check("max_memory", br.listing_bytes(estimate), entry,
                     lambda: f"the bytes (estimate) of listing {estimate} hyperplanes ({formula}; no screen applies)")
    return br.inside


def price_margins(br: BlockRows, what: str, unit: str = "margin") -> None:
    """Refuse, before the hyperplanes are listed, a step that builds ``what`` for each of them when
    its estimated work (``budget.COSTS[unit]``, a margin in flint or a symbolic one, per hyperplane
    of :meth:`BlockRows.listing_estimate`) is above ``max_work``."""
    if "inside" not in br.__dict__ and br.size > 1:
        estimate, formula = br.listing_estimate()
        budget.price(lambda: f"eigen-block of modulus {br.block.modulus}",
                     lambda: f"{what} of every hyperplane ({formula})", **{unit.replace(" ", "_"): estimate})


#: estimated CPU seconds (``budget.COSTS["hyperplane degree"]``) of a listing above which a block
#: in general position goes through its special and generic hyperplanes (:func:`_beyond_listing`)
#: rather than the list: about 300 000 hyperplanes over a field of degree 8
LIST_BELOW = 2.5


def capped_hyperplanes(br: BlockRows) -> tuple[frozenset[int], ...]:
    """Every hyperplane as index sets, by :func:`listed_hyperplanes` (refused up front as it is)."""
    listed = listed_hyperplanes(br)
    return br.hyperplanes if isinstance(listed, np.ndarray) else tuple(listed)


def _outside_vectors(br: BlockRows, inside) -> dict[tuple[int, ...], frozenset[int]]:
    """:func:`outside_counts` of the hyperplanes ``inside`` (boolean rows or index sets, in
    lexicographic order: the first hyperplane of each vector is kept)."""
    sensor = np.array([e.sensor for e in br.elements])
    rows = isinstance(inside, np.ndarray)
    if rows:
        per_sensor = (sensor[:, None] == np.arange(sensor.max() + 1)).astype(np.int64)  # elements x d
        outside = (~inside).astype(np.int64) @ per_sensor                               # hyperplanes x d
    else:   # counted from the members: boolean rows of the g sets over d g elements grow as g^2
        sizes = np.array([len(H) for H in inside], dtype=np.int64)
        members = np.fromiter(itertools.chain.from_iterable(inside), dtype=np.int64, count=int(sizes.sum()))
        outside = np.tile(np.bincount(sensor), (len(inside), 1))
        np.subtract.at(outside, (np.repeat(np.arange(len(inside)), sizes), sensor[members]), 1)
    _, first = np.unique(outside, axis=0, return_index=True)
    return {tuple(outside[h].tolist()): _set(inside[h]) if rows else frozenset(inside[h]) for h in sorted(first.tolist())}


def _weights(loss: LossModel) -> list[float] | None:
    """``-log loss_j`` per sensor of i.i.d. losses: the slowest-decaying hyperplane maximises ``sum_{e
    in H} -log loss_(sensor e)``; None when a loss is 0 or symbolic (then every hyperplane is compared)."""
    if loss.symbols or any(e == 0 for e in loss.bernoulli):
        return None
    return [-float(sp.log(e).evalf(20)) for e in loss.bernoulli]


def block_rate(br: BlockRows, loss: LossModel) -> BlockRate:
    """``rho_i^g`` (per projection period) for one block, exactly (eq. 36).

    i.i.d. losses: the heaviest hyperplanes (:func:`outside_counts`).  Markov losses: the
    product over the model's independent factors of their restricted transfers' Perron roots,
    maximised by :func:`markov_search` (aperiodic blocks too: their elements' generators are
    class projections, docs/sui.md)."""
    if loss.bernoulli is not None:   # i.i.d.: the rate depends on the exponent vector only
        counts = outside_counts(br, _weights(loss))
        cands = [(H, sp.Mul(*[e ** k for e, k in zip(loss.bernoulli, ks)])) for ks, H in counts.items()]
        H, best = _maximum(cands)
        return BlockRate(best, H, tuple(cands))
    if loss.symbols:
        raise _symbolic()
    return markov_search(br, factor_rates(br, loss))


def _symbolic() -> InputError:
    return InputError("loss: symbolic loss parameters have no numeric decay rate; "
                      "use symkf.stability_conditions for the stability region as conditions")


def _maximum(candidates: list[tuple[frozenset[int], sp.Expr]]) -> tuple[frozenset[int], sp.Expr]:
    if any(v.free_symbols for _, v in candidates):
        raise _symbolic()
    return max(candidates, key=lambda hv: AlgebraicNumber.from_expr(hv[1]))


def least_iid_bound(br: BlockRows, losses: Callable[[AlgebraicNumber], Sequence[sp.Expr]],
                    bound: Callable[[tuple[int, ...]], Any], start: AlgebraicNumber,
                    growth: sp.Expr, least: Callable[[list], AlgebraicNumber],
                    safe: AlgebraicNumber | None = None) -> AlgebraicNumber | None:
    """``min(start, min_H x_H)`` without listing every hyperplane, or None when the screen
    declines (then list them: :func:`outside_counts`).

    ``losses(x)`` are the i.i.d. losses at the parameter ``x`` (each non-decreasing in ``x``, at
    most 1 up to ``safe``, default ``start``); ``bound(k)`` is ``x_H`` for a hyperplane whose
    exponent vector is ``k``: the ``x`` at which its margin ``growth * prod_j loss_j(x)^(k_j)``
    reaches 1 (None when it never does), in any form that ``least`` takes: ``least(bounds)`` is
    their least value, or ``start`` when none is below it (the caller's, which may compare
    certified balls before making any value exact: an exact root of high degree is costly, and
    there may be hundreds).

    Why no hyperplane is missed.  With weights ``w_e(x) = -log loss_(sensor e)(x)`` the margin of
    ``H`` is ``log growth - T(x) + sum_(e in H) w_e(x)`` (``T`` the total weight of the elements
    with a generator; the others lie in every hyperplane), and it increases with ``x``; so ``x_H
    <= x`` iff that margin is ``>= 0`` at ``x``, i.e. iff ``H`` weighs at least ``T(x) - log
    growth``.  Take ``x`` = the least ``x_H`` over a few hyperplanes spanned by the heaviest
    generators (:meth:`BlockRows.spanned`; exact) or, when none lies below ``start``, one step of
    Dinkelbach's iteration at ``safe`` (the heaviest hyperplanes there: their least ``x_H``, or
    ``start`` when none lies below it, is an upper bound of the answer).  Then ``heaviest(w(x),
    floor=T(x) - log growth)`` returns every hyperplane with ``x_H <= x`` (its no-miss argument
    for a floor), and the least of their ``x_H`` is the minimum: one screen when the guess is
    good.  Weights the screen cannot take directly are made admissible without losing a set:

    * a loss of 0 (weight infinite): the weight ``B = T_finite + |log growth| + 1``.  A hyperplane
      missing such an element has rate 0 and never binds; one holding all ``Z`` of them weighs
      ``Z B`` plus its finite weight, and every set missing one weighs less than ``Z B``, so the
      floor ``Z B + T_finite - log growth`` keeps exactly the hyperplanes that may bind (and the
      heaviest hold them all when any does);
    * a loss above 1 (``x`` above ``safe``, weight negative): every weight is raised by ``c``, the
      most negative's size; a hyperplane holds at least ``n - 1`` elements with a generator (it has
      rank ``n - 1``), so its raised weight is at least its weight plus ``c (n - 1)``, and the
      floor raised by ``c (n - 1)`` still keeps it (with more sets, rated exactly and discarded).

    Declines (None) when a loss is symbolic or the screen does not apply."""
    live = br.live
    log_growth = float(sp.log(growth).evalf(20))

    def weights(x: AlgebraicNumber) -> tuple[list[float], float, float] | None:
        """The admissible weights at ``x``, the floor of the hyperplanes binding at ``x`` and the
        raise ``c`` (above)."""
        values = [sympify(v) for v in losses(x)]
        if any(v.free_symbols or not v.is_real or v < 0 for v in values):
            return None
        raw = [np.inf if v == 0 else -float(sp.log(v).evalf(20)) for v in values]
        finite = [raw[br.elements[e].sensor] for e in live if raw[br.elements[e].sensor] < np.inf]
        zeros = len(live) - len(finite)
        c = max(0.0, -min(finite, default=0.0))
        big = 2 * sum(v + c for v in finite) + abs(sum(finite)) + 2 * abs(log_growth) + 1
        w = [big if raw[e.sensor] == np.inf else raw[e.sensor] + c for e in br.elements]
        return w, sum(finite) - log_growth + zeros * big + c * max(0, br.size - 1 - zeros), c

    def least_of(sets) -> AlgebraicNumber | None:
        found = [b for b in (bound(ks) for ks in _outside_vectors(br, sorted(sets, key=sorted))) if b is not None]
        return least(found) if found else None

    at = start if safe is None or not safe < start else safe
    first = weights(start)
    if first is None:
        return None
    x = least_of(br.spanned(first[0]))
    if x is None or not x < start:
        step = weights(at)
        if step is None or step[2] > 0:   # Dinkelbach needs losses <= 1: the heaviest bind first
            return None
        sets = br.heaviest(step[0])
        if sets is None:
            return None
        x = least_of(sets)
        if x is None or not x < start:
            if at == start:   # every margin is at most 1 at start
                return start
            x = start
    final = weights(x)
    if final is None:
        return None
    w, floor, _ = final
    sets = br.heaviest(w, floor=floor - 1e-9 * (1 + abs(floor)))
    if sets is None:
        return None
    found = least_of(sets)
    return x if found is None or not found < x else found


def markov_search(br: BlockRows, rates: Sequence[FactorRates]) -> BlockRate:
    """``max_H prod_f rho(M_(H, f))`` over the hyperplanes ``H``, exactly, without listing them
    when every factor is in the segment form (:class:`FactorRates`) and the block's elements
    admit the screen (:meth:`BlockRows.heaviest`; elements of several generators through its
    additive bound).

    Why no maximiser is missed.  ``rho(M_H)`` is monotone in ``H`` (a larger set allows more
    states: the restricted transfer grows entrywise), so the maximum over rank-deficient sets
    is attained at hyperplanes.  Two screens:

    1. ``heaviest(gamma)`` with ``gamma_e = log rho({e}) - log rho({})``, the gain of ``e``
       alone (>= 0 by monotonicity): its sets are hyperplanes, rated exactly; the largest
       gives a proved lower bound ``tau`` of the maximum (float log less its error bound).
    2. Per factor ``f``, ``rho_f(H) <= c_f^(g - n_f(H)) <= c_f^g prod_(e in H, e of f) c_f^(-1)``
       with ``c_f = max_l (P^l)_(z, z)`` (:meth:`FactorRates.lost_bound`) and ``n_f(H) <= |H_f|``
       the phases where ``H`` holds an element of ``f``: an additive upper bound with weights
       ``beta_e = -log c_f >= 0``, or the least of the other bounds of
       :meth:`FactorRates.gain_bound` (:func:`_additive_bound`: a hyperplane holds at most ``n - 1``
       consecutive phases of a sensor that sees every mode, which bounds a one-sensor factor's
       words).  A maximiser ``H*`` has ``C + sum_(e in H*) beta_e >= log rho(H*) >= tau`` (``C =
       sum_f g log c_f``), so ``heaviest(beta, floor=tau - C)``, which returns every hyperplane
       whose weight reaches the floor (its no-miss argument), holds it; of what it keeps only the
       sets whose rate may reach ``tau`` are confirmed (:func:`_reaching`).

    Every returned hyperplane is rated; those whose float log is within the proved errors of the
    largest are compared exactly (rationals), and the first maximum in lexicographic order is
    the enumeration's.  Otherwise (or when a screen declines) every hyperplane is listed
    (:func:`listed_hyperplanes`, capped) and screened the same way in floats when the factors
    have twins, else compared exactly.
    """
    patterns = Patterns(br, rates)
    sets = _screened(br, rates, patterns) if all(r.screened for r in rates) else None
    if sets is None:
        sets = _beyond_listing(br, rates, patterns)
    if sets is None:
        sets = list(capped_hyperplanes(br))
    return _decide(sets, patterns)


def _beyond_listing(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """Where listing the hyperplanes would cost more than :data:`LIST_BELOW`: the special ones (at
    least ``n`` elements with a generator: the screen with unit weights and a strict floor) and,
    when it is larger than all of theirs, the best rate of ``n - 1`` such elements, attained by generic hyperplanes
    (:mod:`symkf.engine.generic_hyperplanes`, which also says why no maximiser is missed), the first of
    them in lexicographic order.  None when that does not apply (the caller lists, refused by the
    estimate)."""
    if not _general_position(br):
        return None
    generic = generic_hyperplanes.best_elements(br, rates)
    if generic is None:
        return None
    special = _special(br)
    if special is None:
        return None
    rate, S = generic
    top = max((patterns.rate(H) for H in special), default=None)
    # larger than every special one: S is a generic hyperplane; equal: it is one of the maxima (the
    # list's first may be generic) if it is a hyperplane, else its rate is some special one's
    if top is None or rate > top or (rate == top and generic_hyperplanes.is_hyperplane(br, S)):
        return special + [S]
    return special


def _general_position(br: BlockRows) -> bool:
    """Whether :mod:`symkf.engine.generic_hyperplanes` is the way past the list: listing would cost
    more than :data:`LIST_BELOW` CPU-s (``budget.seconds`` of its hyperplanes times the field's
    degree) and the block is one of single generators without cylinders."""
    return not ("inside" in br.__dict__ or br.cylinders or br.size < 2 or br.several_generators
                or budget.seconds(hyperplane_degree=br.listing_estimate()[0] * br.K.degree) <= LIST_BELOW)


def _special(br: BlockRows) -> list[frozenset[int]] | None:
    """The special hyperplanes (at least ``n`` live elements): the screen with unit weights and a
    strict floor; None when it declines."""
    return br.heaviest([1.0 if gs else 0.0 for gs in br.generators], floor=br.size - 0.5, strict=True)


def _screened(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """The hyperplanes of :func:`markov_search`'s two screens; None when a screen declines or the
    bound cannot rule out the generic hyperplanes (through ``n - 1`` elements of one generator in
    general position, :meth:`BlockRows.generic_weight`: then listing is cheaper)."""
    if br.cylinders:
        return _through_cylinders(br, rates, patterns)
    first = _first_screen(br, rates, patterns, screens=2)   # screen 2 priced with it
    if first is None:
        return None
    tau = max(lg - err for lg, err in map(patterns.log_rate, first))
    second = _reaching(br, rates, patterns, tau)
    return None if second is None else list({*first, *second})


def _through_cylinders(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> list[frozenset[int]] | None:
    """The sets of :func:`markov_search` for a block over several parts (:mod:`symkf.engine.cylinders`):
    each cylinder's own search (the sub-system's rows over its own, smaller field, with the same
    factors at its class period), its candidates lifted; their largest rate, less its proved
    error, is ``tau``, and every hyperplane meeting every part is ruled out by the additive bound
    of screen 2 (``log rho(M_H) <= C + sum_(e in H) beta_e``) when the fibres bound its weight
    below ``tau - C``.  Each lifted set is rated over this block's period (a pattern repeated
    ``g / g_S`` times); None when the bound does not rule those hyperplanes out."""
    beta, C = _additive_bound(br, rates, patterns)
    tol = 1e-9 * (1 + abs(C))
    # tau <= C + the heaviest cylinder's beta: when the fibres cannot put every full-support
    # hyperplane below that (heaviest declines), they never will, and the cylinders' own searches
    # are not run (2R(2pi/5) + ... + 2R(2pi/11) with two sensors: a refusal of a three-part screen
    # estimated at 1.5e9, which ran past 15 min when allowed)
    if not np.isfinite(C) or br.heaviest(beta) is None:
        return None
    sets = {br.lift(rows, H) for rows in br.cylinders
            for H, _ in markov_search(rows, [FactorRates(r.factor, rows.class_period) for r in rates]).candidates}
    tau = max(lg - err for lg, err in map(patterns.log_rate, sets))
    floor = tau - C
    return list(sets) if np.isfinite(tau) and br.meet_every_part_below(beta, floor - tol - 1e-9 * abs(floor)) else None


def _additive_bound(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns) -> tuple[list[float], float]:
    """``(beta, C)`` of screen 2 of :func:`markov_search`: ``log rho(M_H) <= C + sum_(e in H)
    beta_e`` for every hyperplane ``H`` (:meth:`FactorRates.gain_bound`, per factor, at ``n - 1``
    elements inside; the words of a factor of one sensor no longer than the consecutive phases of
    it that a hyperplane may hold, :meth:`BlockRows.longest_run`, not asked of a block over
    several parts, whose direct rows it would build); ``C`` is -inf or NaN where a factor has no
    finite bound."""
    def longest(sensors: Sequence[int]) -> int | None:
        return br.longest_run(sensors[0]) if len(sensors) == 1 and not br.cylinders else None
    bounds = [r.gain_bound(br.size - 1, longest(r.factor.sensors)) for r in rates]
    beta = [bounds[f][1][rates[f].factor.sensors.index(br.elements[e].sensor)] for e, (f, _, _) in enumerate(patterns.of)]
    return beta, sum(C for C, _ in bounds)


def _first_screen(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns, screens: int = 1
                  ) -> list[frozenset[int]] | None:
    """Screen 1 of :func:`markov_search`: the hyperplanes heaviest in the gains of single elements
    (priced with the ``screens - 1`` screens the caller runs after it: :meth:`BlockRows.heaviest`)."""
    empty = [r.log_rate({}) for r in rates]
    gains = [max(0.0, rates[f].log_rate({phase: bit}) - empty[f]) for f, bit, phase in patterns.of]
    return br.heaviest(gains, screens=screens) if all(np.isfinite(gains)) else None


def _reaching(br: BlockRows, rates: Sequence[FactorRates], patterns: Patterns, tau: float
              ) -> list[frozenset[int]] | None:
    """Every hyperplane whose rate may reach ``exp(tau)`` (screen 2 of :func:`markov_search`);
    None when the additive bound cannot rule out the generic hyperplanes or a screen declines.
    A set the screen keeps whose float rate plus its proved error is below ``tau`` is not
    confirmed (``needed`` of :meth:`BlockRows.heaviest`): the rates of its subsets are at most its
    own (``rho(M_H)`` is monotone in ``H``), and so are those of its phase shifts' (a shift rotates
    the period's product of transfers, whose spectrum it keeps)."""
    beta, C = _additive_bound(br, rates, patterns)
    if not np.isfinite(tau) or not np.isfinite(C):
        return None
    floor = tau - C
    if not br.several_generators and br.generic_weight(beta) >= floor:
        return None
    return br.heaviest(beta, floor=floor - 1e-9 * (1 + abs(floor) + abs(C)),
                       needed=lambda H: sum(patterns.log_rate(H)) >= tau)


def first_screen(br: BlockRows, loss: LossModel) -> list[frozenset[int]]:
    """Hyperplanes of large rate under ``loss`` (screen 1 of :func:`markov_search`, no claim of
    the maximum); empty when the screen declines."""
    rates = factor_rates(br, loss)
    if not all(r.screened for r in rates):
        return []
    return _first_screen(br, rates, Patterns(br, rates)) or []


def rates_reaching(br: BlockRows, loss: LossModel, floor: AlgebraicNumber) -> list[tuple[frozenset[int], sp.Rational]] | None:
    """Every hyperplane ``H`` with ``rho(M_H) >= floor`` (exact, > 0) and its exact rate, without listing the
    hyperplanes: screen 2 of :func:`markov_search` with ``tau`` the float log of ``floor`` less a
    margin (an additive upper bound rules out every set it leaves), then each returned set rated
    exactly; when a screen declines, every hyperplane (:func:`listed_hyperplanes`, capped).  None
    when the factors are not in the segment form."""
    rates = factor_rates(br, loss)
    if not all(r.screened for r in rates) or not floor > 0:
        return None
    patterns = Patterns(br, rates)
    low, _ = floor.interval
    tau = math.log(low.numerator) - math.log(low.denominator) if low > 0 else math.log(float(floor))
    tau -= 1e-6 * (1 + abs(tau))
    sets = _reaching(br, rates, patterns, tau)
    while not low > 0:   # a positive rational below floor: the generic rates are cut against it
        low = floor.refine((floor.interval[1] - low) / 4).interval[0]
    if sets is None:
        sets = _reaching_beyond_listing(br, rates, low)
    if sets is None:
        sets = list(capped_hyperplanes(br))
    sets = [H for H in sets if sum(patterns.log_rate(H)) >= tau]  # float log plus its proved error
    rated = ((H, exact_rate(patterns.rate(H))) for H in sets)
    return [(H, v) for H, v in rated if not floor > v]


def _reaching_beyond_listing(br: BlockRows, rates: Sequence[FactorRates], low: Fraction) -> list[frozenset[int]] | None:
    """Where listing would be refused (:func:`_general_position`): the special hyperplanes and, per
    rate of ``n - 1`` live elements at least ``low``, one set of such elements
    (:func:`symkf.engine.generic_hyperplanes.reaching_elements`: every generic hyperplane is such a
    set, and every such set lies in a hyperplane, so their rates reaching ``low`` are the
    hyperplanes' that do).  None when that does not apply."""
    if not _general_position(br):
        return None
    generic = generic_hyperplanes.reaching_elements(br, rates, low)
    special = None if generic is None else _special(br)
    return None if special is None else special + generic


def _decide(sets: list[frozenset[int]], patterns: Patterns) -> BlockRate:
    """The first exact maximum (lexicographic order) of the rates of ``sets``; with float twins
    only the sets within the proved errors of the largest float are compared exactly."""
    sets = sorted(sets, key=sorted)
    if np.isfinite(patterns.word_error):
        rated = [patterns.log_rate(H) for H in sets]
        top = max(lg - err for lg, err in rated)
        sets = [H for H, (lg, err) in zip(sets, rated) if lg + err >= top]
    cands = [(H, patterns.rate(H)) for H in sets]
    if all(isinstance(v, flint.fmpq) for _, v in cands):
        H, best = max(cands, key=lambda hv: hv[1])
        return BlockRate(exact_rate(best), H, tuple((H, exact_rate(v)) for H, v in cands))
    cands = [(H, exact_rate(v)) for H, v in cands]
    H, best = _maximum(cands)
    return BlockRate(best, H, tuple(cands))


check_public(globals())
