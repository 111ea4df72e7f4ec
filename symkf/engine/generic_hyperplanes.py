"""The largest Markov rate over the hyperplanes of an eigen-block in general position, without
listing them (Sui-You-Fu eq. 36, ``max_H rho(M_H)``).

A hyperplane whose elements all have one generator holds at least ``n - 1`` of those with a
generator ("live"); it is *generic* when it holds exactly ``n - 1`` (independent, no other element
in their span), *special* when it holds more.  A block in general position has ``C(E, n - 1)``
generic hyperplanes and few special ones; the screens of :func:`symkf.engine.search.markov_search` then
cannot rule the generic ones out (their additive bound reaches them all), and listing them is
priced (``budget.Limits.max_work``, ``max_memory``) and refused beyond them.

Why the maximum needs no list.  ``rho(M_S)`` is monotone in the element set ``S``.  Every ``n - 1``
live elements lie in some hyperplane (the elements span ``K^n``), and one of rank below ``n - 1``,
or whose span holds another element, lies only in special ones.  So

    ``max_H rho(M_H) = max(max over special H, max over all n - 1 live elements S of rho(M_S))``

(the elements without a generator belong to every set), and when the second term is the larger,
every set attaining it is a generic hyperplane.  The special hyperplanes are those of at least
``n`` live elements: :meth:`~symkf.engine.rows.BlockRows.heaviest` with unit weights and a strict
floor.  The second term is combinatorial (:func:`best_elements`): in the segment form of
:class:`symkf.engine.rates.FactorRates` a factor's rate depends only on the multiset of its words (runs
of non-zero masks between phases of mask 0), so the best ``m`` elements of a factor are a best
multiset of words of ``m`` bits in all, and the factors share the ``n - 1`` elements by a knapsack
on ``m``, exactly (rationals).
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Sequence

import flint
from sympy.utilities.iterables import multiset_permutations

from ..arguments import check_public
from ..exact.linalg import nullspace_rows
from .rows import BlockRows

if TYPE_CHECKING:   # the rates call this module: it takes their FactorRates, never builds one
    from .rates import FactorRates

#: the most multisets of words one factor may be searched over (joint chains of many sensors
#: have many words of a few bits; beyond, the caller lists the hyperplanes, refused by its cap)
MAX_SHAPES = 20_000


def best_elements(br: BlockRows, rates: Sequence[FactorRates]) -> tuple[Any, frozenset[int]] | None:
    """``(rho, S)``: the largest ``rho(M_S)`` over the sets ``S`` of the elements without a
    generator and ``n - 1`` live elements of one generator each (module docstring), exactly,
    and the first such ``S`` in lexicographic order, the list's tie-break: per factor its words
    packed from phase 0 (one phase of mask 0 between runs) in the order that comes first, the
    first pattern so among equal rates, and on ties between factors the most elements to the
    earlier (elements are numbered sensor by sensor).  None when it does not apply: an element
    of several generators, a factor outside the segment form, a sensor live at some phases only,
    a factor with live and dead sensors, or more than :data:`MAX_SHAPES` multisets of words."""
    shapes = _factor_shapes(br, rates)
    if shapes is None:
        return None
    n, (index, table) = br.size, shapes
    knapsack: list[tuple[Any, tuple] | None] = [(1, ())] + [None] * (n - 1)
    for best in map(_best_per_count, table):
        step: list[tuple[Any, tuple] | None] = [None] * n
        for total in range(n - 1, -1, -1):   # more elements to the earlier factors first
            held = knapsack[total]
            if held is None:
                continue
            for m, (rate, masks) in enumerate(best[:n - total]):
                value = held[0] * rate
                if step[total + m] is None or value > step[total + m][0]:
                    step[total + m] = (value, held[1] + (masks,))
        knapsack = step
    if knapsack[n - 1] is None:
        return None
    value, chosen = knapsack[n - 1]
    return value, _members(index, rates, chosen)


def reaching_elements(br: BlockRows, rates: Sequence[FactorRates], floor: Fraction) -> list[frozenset[int]] | None:
    """Every rate ``rho(M_S) >= floor`` of the sets ``S`` of :func:`best_elements` (the elements
    without a generator and ``n - 1`` live ones), each through one such ``S``: a factor's rate
    depends only on its multiset of words, so one ``S`` per combination of the factors' multisets
    whose product reaches ``floor`` (exact rationals; a product that the best rates of the factors
    still to choose cannot lift to ``floor`` is cut).  With the special hyperplanes this holds
    every hyperplane rate at least ``floor`` (module docstring: a generic hyperplane is such an
    ``S``, and every ``S`` lies in some hyperplane).  None when :func:`best_elements` does not
    apply or more than :data:`MAX_SHAPES` combinations reach ``floor``."""
    shapes = _factor_shapes(br, rates)
    if shapes is None:
        return None
    most, (index, table) = br.size - 1, shapes
    floor = flint.fmpq(floor.numerator, floor.denominator)
    # reach[f][m]: the largest product of the factors f.. over m elements in all (None: no such)
    reach: list[list[Any]] = [[1] + [None] * most]
    for factor in reversed(table):
        best, after = _best_per_count(factor), reach[0]
        reach.insert(0, [max((best[m][0] * after[total - m] for m in range(min(total, len(best) - 1) + 1)
                              if after[total - m] is not None), default=None) for total in range(most + 1)])
    found: list[tuple] = []

    def extend(f: int, used: int, value: Any, chosen: tuple) -> bool:
        if f == len(table):
            found.append(chosen)
            return len(found) <= MAX_SHAPES
        for m, rate, masks in table[f]:
            bound = reach[f + 1][most - used - m] if used + m <= most else None
            if bound is not None and value * rate * bound >= floor:
                if not extend(f + 1, used + m, value * rate, chosen + (masks,)):
                    return False
        return True
    if not extend(0, 0, 1, ()):
        return None
    return [_members(index, rates, chosen) for chosen in found]


def _factor_shapes(br: BlockRows, rates: Sequence[FactorRates]) -> tuple[dict, list[list[tuple[int, Any, dict[int, int]]]]] | None:
    """The element index ``{(sensor, phase): e}`` and per factor every ``(m, rate, masks)`` of its
    patterns of ``m <= n - 1`` live elements, one per multiset of words (:func:`_shapes`; a factor
    of dead sensors: its full pattern, ``m = 0``); None where :func:`best_elements` does not apply."""
    n, g = br.size, br.class_period
    index = {(e.sensor, e.phase): i for i, e in enumerate(br.elements)}
    live = {}
    for sensor in {e.sensor for e in br.elements}:
        counts = {len(br.generators[index[sensor, r]]) for r in range(g)}
        if len(counts) > 1 or counts - {0, 1}:
            return None
        live[sensor] = counts == {1}
    table = []
    for r in rates:
        sensors = r.factor.sensors
        if not r.screened or len({live[j] for j in sensors}) > 1:
            return None
        if not live[sensors[0]]:   # every element of the factor lies in every set
            full = (1 << len(sensors)) - 1
            masks = {phase: full for phase in range(g)}
            table.append([(0, r.rate(masks), masks)])
            continue
        shapes = _shapes(r, [[index[j, phase] for phase in range(g)] for j in sensors], n - 1)
        if shapes is None:
            return None
        table.append(shapes)
    return index, table


def _members(index: dict, rates: Sequence[FactorRates], chosen: tuple[dict[int, int], ...]) -> frozenset[int]:
    """The elements of the factors' patterns ``chosen`` (``{phase: mask}`` each)."""
    return frozenset(index[r.factor.sensors[b], phase] for r, masks in zip(rates, chosen)
                     for phase, mask in masks.items() for b in range(len(r.factor.sensors)) if mask >> b & 1)


def _best_per_count(shapes: list[tuple[int, Any, dict[int, int]]]) -> list[tuple[Any, dict[int, int]]]:
    """Per ``m = 0..`` (up to ``n - 1``, or the factor's one full pattern): the first shape of the
    largest rate among those of ``m`` elements (:func:`_shapes` lists them in the tie-break's order)."""
    best: list[tuple[Any, dict[int, int]] | None] = [None] * (max(m for m, _, _ in shapes) + 1)
    for m, rate, masks in shapes:
        if best[m] is None or rate > best[m][0]:
            best[m] = (rate, masks)
    return best


def _shapes(rates: FactorRates, element: list[list[int]], most: int) -> list[tuple[int, Any, dict[int, int]]] | None:
    """Per multiset of words of at most ``most`` elements in all that fits the period: ``(m, rate,
    masks)``, its words packed in the order whose elements ``element[bit][phase]`` come first in
    lexicographic order, listed by rate and then by that order within each ``m`` (so the first of
    the largest rate is the one that comes first); None beyond :data:`MAX_SHAPES` multisets, or
    when some ``m`` has none."""
    g, bits = rates.g, len(element)
    words = []

    def extend(word: tuple[int, ...], used: int) -> None:
        for mask in range(1, 1 << bits):
            count = used + bin(mask).count("1")
            if count <= most:
                words.append(word + (mask,))
                extend(word + (mask,), count)
    extend((), 0)
    weight = [sum(bin(m).count("1") for m in w) for w in words]
    found: list[tuple[int, Any, list[int], dict[int, int]]] = []

    def packed(chosen: tuple[int, ...]) -> tuple[list[int], dict[int, int]]:
        masks, phase = {}, 0
        for w in chosen:
            for mask in words[w]:
                masks[phase] = mask
                phase += 1
            phase += 1
        return sorted(element[b][p] for p, mask in masks.items() for b in range(bits) if mask >> b & 1), masks

    def choose(first: int, chosen: list[int], used: int, span: int) -> bool:
        if len(found) >= MAX_SHAPES:
            return False
        key, masks = min(map(packed, _orders(chosen, words)))   # the order of the runs that comes first
        found.append((used, rates.rate(masks), key, masks))
        for w in range(first, len(words)):   # multisets: words in non-decreasing index order
            if used + weight[w] <= most and span + len(words[w]) + 1 <= g:
                if not choose(w, chosen + [w], used + weight[w], span + len(words[w]) + 1):
                    return False
        return True
    if not choose(0, [], 0, 0) or {m for m, _, _, _ in found} != set(range(most + 1)):
        return None
    found.sort(key=lambda shape: (shape[0], -shape[1], shape[2]))
    return [(m, rate, masks) for m, rate, _, masks in found]


#: the most orders of one multiset of words that are packed to find the one that comes first
#: (seven distinct runs have 5040); beyond, the longest runs first
MAX_ORDERS = 720


def _orders(chosen: list[int], words: list[tuple[int, ...]]) -> list[tuple[int, ...]]:
    """The distinct orders of the runs ``chosen`` (word indices), or beyond :data:`MAX_ORDERS` the
    one with the longest words first (the first in lexicographic order for one sensor: a longer
    run packed from phase 0 leaves the smaller phases; with several sensors only the list's
    tie-break between equal rates can differ)."""
    counts = [chosen.count(w) for w in set(chosen)]
    if math.factorial(len(chosen)) // math.prod(map(math.factorial, counts)) > MAX_ORDERS:
        return [tuple(sorted(chosen, key=lambda w: (-len(words[w]), w)))]
    return [tuple(order) for order in multiset_permutations(chosen)]


def is_hyperplane(br: BlockRows, S: frozenset[int]) -> bool:
    """Whether the elements ``S`` (one generator each, or none) are a hyperplane: their generators
    have rank ``n - 1`` over K and no other element's lies in their span (exact)."""
    gens = [v for e in sorted(S) for v in br.generators[e]]
    normal = nullspace_rows(br.K, gens, br.size)
    return len(normal) == 1 and all(any(not br.K.dot(normal[0], v).is_zero() for v in gs)
                                    for e, gs in enumerate(br.generators) if e not in S and gs)


check_public(globals())
