"""The best Markov rate over the hyperplanes of a block in general position (symkf.engine.generic_hyperplanes):
against every n - 1 elements (brute force), the strict screen against the listed hyperplanes, and
Markov verdicts beyond the list against the list."""

import itertools

import pytest

import symkf as sk
from symkf import budget
from symkf.engine import rates as engine_rates, search, rows as observability
from symkf.engine.generic_hyperplanes import best_elements
from symkf.engine.blocks import block_rows
from conftest import stacked_rotations

GE = sk.GilbertElliott
# a joint chain of two sensors (one all-lost state: the segment form, words of two-bit masks)
JOINT = sk.MarkovLoss({(0, 0): {(0, 0): "1/2", (0, 1): "1/4", (1, 0): "1/8", (1, 1): "1/8"},
                       (0, 1): {(0, 0): "1/3", (0, 1): "1/3", (1, 0): "1/6", (1, 1): "1/6"},
                       (1, 0): {(0, 0): "1/5", (0, 1): "1/5", (1, 0): "2/5", (1, 1): "1/5"},
                       (1, 1): {(0, 0): "1/10", (0, 1): "1/5", (1, 0): "1/5", (1, 1): "1/2"}})
# (two rotations of modulus 2, rows, loss, which term of the maximum wins: the generic hyperplanes'
# best n - 1 elements or a special hyperplane), each a block whose screens cannot rule the
# generic hyperplanes out (found by a random search; a joint chain's screens decided every one tried)
CASES = [
    ((3, 5), [[1, 1, 0, -2]], GE(["6/100"], ["17/100"]), "generic"),
    ((3, 5), [[1, 2, 1, -2], [-1, 0, 1, 0]], GE(["80/100", "12/100"], ["15/100", "57/100"]), "generic"),
    ((7, 9), [[0, -2, -1, 1]], GE(["2/100"], ["62/100"]), "generic"),
    ((4, 6), [[2, -1, -2, 2]], GE(["2/100"], ["42/100"]), "special"),
    ((3, 5), [[1, 2, 1, -2], [-1, 0, 1, 0]], GE(["1/10", "1/10"], ["1/2", "1/2"]), None),
]


def _rows_and_rates(orders, rows, loss):
    br = next(b for b in block_rows(stacked_rotations(orders, rows)) if b.block.modulus.exact == 2)
    rates = engine_rates.factor_rates(br, loss)
    return br, rates, engine_rates.Patterns(br, rates)


@pytest.mark.parametrize("orders, rows, loss", [case[:3] for case in CASES] + [((4, 5), [[1, 0, 2, -1], [0, 1, -1, 1]], JOINT)])
def test_best_elements_is_the_best_rate_of_any_n_minus_1_elements(orders, rows, loss):
    br, rates, patterns = _rows_and_rates(orders, rows, loss)
    live = [e for e, gs in enumerate(br.generators) if gs]
    always = frozenset(e for e, gs in enumerate(br.generators) if not gs)
    best = max(patterns.rate(always | set(S)) for S in itertools.combinations(live, br.size - 1))
    value, S = best_elements(br, rates)
    assert value == best and patterns.rate(S) == value
    assert always <= S and len(S - always) == br.size - 1


@pytest.mark.parametrize("orders, rows", [((3, 5), [[1, 2, 1, -2], [-1, 0, 1, 0]]), ((5, 6), [[2, -1, -2, 2]])])
def test_the_strict_screen_finds_the_hyperplanes_of_n_live_elements_or_more(orders, rows):
    # heaviest with unit weights and a strict floor n - 1/2 against the listed hyperplanes
    br = next(b for b in block_rows(stacked_rotations(orders, rows)) if b.block.modulus.exact == 2)
    unit = [1.0 if gs else 0.0 for gs in br.generators]
    special = br.heaviest(unit, floor=br.size - 0.5, strict=True)
    listed = {H for H in br.hyperplanes if sum(unit[e] for e in H) >= br.size}
    assert special is not None and set(special) == listed and listed
    assert br.heaviest(unit, floor=10 ** 6, strict=True) == []   # strict: none, not the heaviest


@pytest.mark.parametrize("orders, rows, loss, wins", CASES)
def test_markov_verdicts_beyond_the_list_equal_the_list(orders, rows, loss, wins, monkeypatch):
    # the list's estimate pretended past search.LIST_BELOW: the special hyperplanes and the generic
    # maximum decide (not the list, not a refusal), and give the list's margin and decisive elements
    answered = []
    beyond = search._beyond_listing

    def spy(br, rates, patterns):
        out = beyond(br, rates, patterns)
        if out is not None:
            answered.append(best_elements(br, rates)[1] in out)
        return out
    with monkeypatch.context() as m:
        m.setattr(search, "_beyond_listing", spy)
        m.setattr(observability.BlockRows, "listing_estimate", lambda self: (10 ** 12, "pretended"))
        got = sk.stability(stacked_rotations(orders, rows), loss)
    assert answered and (wins is None or answered == [wins == "generic"])
    want = sk.stability(stacked_rotations(orders, rows), loss)
    assert [m.exact for m in got.margins] == [m.exact for m in want.margins]
    assert [c.decisive_elements for c in got.certificate] == [c.decisive_elements for c in want.certificate]


def test_two_rotations_seen_by_two_sensors_on_gilbert_elliott_channels():
    """2R(2 pi/7) + 2R(2 pi/11), two sensors in general position: C(154, 3) = 596 904 hyperplanes
    to list (about 40 CPU-s); the special ones and the generic maximum answer in under a second."""
    system = stacked_rotations((7, 11), [[2, 1, 0, -1], [-2, -2, 2, 1]])
    verdict = sk.stability(system, GE(["1/10", "1/10"], ["1/2", "1/2"]))
    assert not verdict.stable


@pytest.mark.full
def test_two_rotations_on_gilbert_elliott_channels_agree_with_the_list(monkeypatch):
    # the same system against the list, chosen whatever its estimate (about 40 CPU-s; priced at 72,
    # above the default max_work)
    loss = GE(["1/3", "1/20"], ["1/4", "2/3"])
    got = sk.stability(stacked_rotations((7, 11), [[2, 1, 0, -1], [-2, -2, 2, 1]]), loss)
    with monkeypatch.context() as m, budget.limits(max_work=200_000):
        m.setattr(search, "LIST_BELOW", float("inf"))
        want = sk.stability(stacked_rotations((7, 11), [[2, 1, 0, -1], [-2, -2, 2, 1]]), loss)
    assert [m.exact for m in got.margins] == [m.exact for m in want.margins]
    assert [c.decisive_elements for c in got.certificate] == [c.decisive_elements for c in want.certificate]


def test_the_orders_of_runs_tried_are_the_distinct_ones_up_to_the_cap():
    # a multiset of words is packed in each distinct order (15 for fourteen equal runs and one
    # other, not 15!), and beyond MAX_ORDERS (seven distinct runs: 5040) once, the longest first
    from symkf.engine.generic_hyperplanes import MAX_ORDERS, _orders
    words = [(1,), (1, 1), (1, 1, 1), (1,) * 4, (1,) * 5, (1,) * 6, (1,) * 7]
    assert sorted(_orders([0] * 14 + [1], words)) == sorted({tuple(o) for o in ([0] * k + [1] + [0] * (14 - k) for k in range(15))})
    assert len(_orders([0, 1, 2], words)) == 6 < MAX_ORDERS
    assert _orders(list(range(7)), words) == [(6, 5, 4, 3, 2, 1, 0)]
