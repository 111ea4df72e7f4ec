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
from typing import TYPE_CHECKING, Any, Sequence

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
    n, g = br.size, br.class_period
    index = {(e.sensor, e.phase): i for i, e in enumerate(br.elements)}
    live = {}
    for sensor in {e.sensor for e in br.elements}:
        counts = {len(br.generators[index[sensor, r]]) for r in range(g)}
        if len(counts) > 1 or counts - {0, 1}:
            return None
        live[sensor] = counts == {1}
    table = []   # per factor: per count m, (rate, masks) of its best m elements
    for r in rates:
        sensors = r.factor.sensors
        if not r.screened or len({live[j] for j in sensors}) > 1:
            return None
        if not live[sensors[0]]:   # every element of the factor lies in every set
            full = (1 << len(sensors)) - 1
            masks = {phase: full for phase in range(g)}
            table.append([(r.rate(masks), masks)])
            continue
        best = _best_words(r, [[index[j, phase] for phase in range(g)] for j in sensors], n - 1)
        if best is None:
            return None
        table.append(best)
    knapsack: list[tuple[Any, tuple] | None] = [(1, ())] + [None] * (n - 1)
    for best in table:
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
    members = frozenset(index[r.factor.sensors[b], phase] for r, masks in zip(rates, chosen)
                        for phase, mask in masks.items() for b in range(len(r.factor.sensors)) if mask >> b & 1)
    return value, members


def _best_words(rates: FactorRates, element: list[list[int]], most: int) -> list[tuple[Any, dict[int, int]]] | None:
    """Per ``m = 0..most``: the largest rate of the factor over its patterns of ``m`` elements, and
    of the patterns attaining it (exact comparison) the one whose elements ``element[bit][phase]``
    come first in lexicographic order; None beyond :data:`MAX_SHAPES` multisets of words."""
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
    best: list[tuple[Any, list[int], dict[int, int]] | None] = [None] * (most + 1)
    shapes = 0

    def packed(chosen: tuple[int, ...]) -> tuple[list[int], dict[int, int]]:
        masks, phase = {}, 0
        for w in chosen:
            for mask in words[w]:
                masks[phase] = mask
                phase += 1
            phase += 1
        return sorted(element[b][p] for p, mask in masks.items() for b in range(bits) if mask >> b & 1), masks

    def choose(first: int, chosen: list[int], used: int, span: int) -> bool:
        nonlocal shapes
        shapes += 1
        if shapes > MAX_SHAPES:
            return False
        key, masks = min(map(packed, _orders(chosen, words)))   # the order of the runs that comes first
        rate = rates.rate(masks)
        held = best[used]
        if held is None or rate > held[0] or (rate == held[0] and key < held[1]):
            best[used] = (rate, key, masks)
        for w in range(first, len(words)):   # multisets: words in non-decreasing index order
            if used + weight[w] <= most and span + len(words[w]) + 1 <= g:
                if not choose(w, chosen + [w], used + weight[w], span + len(words[w]) + 1):
                    return False
        return True
    if not choose(0, [], 0, 0) or not all(best):
        return None
    return [(rate, masks) for rate, _, masks in best]


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
