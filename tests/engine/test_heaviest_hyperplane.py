"""The i.i.d. decay rate from the weight-screened hyperplane search (BlockRows.heaviest) equals the
one from enumerating every hyperplane (outside_counts over BlockRows.inside): value and decisive
hyperplane, including ties (equal losses) and unequal losses."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, example, given, settings, strategies as st

import symkf as sk
from conftest import rotation
from symkf.engine.search import _weights, block_rate
from symkf.engine.stability import critical_loss_rate
from symkf.engine.rows import BlockRows
from symkf.engine.blocks import block_rows


BLOCKS = {  # each a single eigen-block (eigenvalue ratios are roots of unity) of dimension 2, 3, 4
    "2R(pi/6)": rotation(sp.pi / 6, 2),
    "diag(2R(pi/3), -2)": sp.diag(rotation(sp.pi / 3, 2), -2),
    "diag(21/20 R(pi/3), 21/20 R(pi/4))": sp.diag(rotation(sp.pi / 3, sp.Rational(21, 20)),
                                                  rotation(sp.pi / 4, sp.Rational(21, 20))),
}
CASES = [  # (block, sensor rows, losses): ties (equal losses) and unequal losses
    ("2R(pi/6)", [[1, 0], [1, 1]], ["1/10", "1/5"]),
    ("diag(2R(pi/3), -2)", [[1, 0, 1], [0, 1, 1]], ["1/10", "1/10"]),
    ("diag(2R(pi/3), -2)", [[1, 0, 1], [1, 1, 0], [0, 1, 2]], ["1/10", "1/2", "1/3"]),
    ("diag(2R(pi/3), -2)", [[1, 0, 1], [2, 0, 2], [0, 1, 1]], ["1/5", "1/5", "9/10"]),  # parallel rows
    ("diag(21/20 R(pi/3), 21/20 R(pi/4))", [[1, 0, 1, 0], [0, 1, 1, 1]], ["1/10", "1/10"]),
    ("diag(21/20 R(pi/3), 21/20 R(pi/4))", [[1, 0, 1, 0], [1, 2, 0, -1]], ["1/10", "1/2"]),
]


@pytest.mark.parametrize("name, rows, losses", CASES)
def test_heaviest_equals_enumeration(name, rows, losses):
    loss = sk.IID(losses)
    fast, full = (sk.System(A=BLOCKS[name], sensors=[sk.Sensor(C=[r]) for r in rows]) for _ in range(2))
    (br_fast,), (br_full,) = block_rows(fast), block_rows(full)
    weights = _weights(loss)
    assert br_fast.heaviest([weights[e.sensor] for e in br_fast.elements]) is not None  # the screen ran
    br_full.inside  # computed first: block_rate then compares every hyperplane
    a, b = block_rate(br_fast, loss), block_rate(br_full, loss)
    assert sp.simplify(a.per_period - b.per_period) == 0
    assert a.hyperplane == b.hyperplane
    assert a.hyperplane in br_full.hyperplanes


JORDAN = sp.Matrix([[2, 1], [0, 2]])  # a constant-velocity model's Jordan chain, at modulus 2
MULTI = {  # one eigen-block each, elements of several generators: (A, each sensor's rows)
    "2R(pi/2) + 2R(pi/3), two-row sensors": (sp.diag(rotation(sp.pi / 2, 2), rotation(sp.pi / 3, 2)),
                                             [[[1, 0, 1, 0], [0, 1, 1, 1]], [[1, 2, 0, -1], [1, 0, 0, 0]]]),
    "J(2) + 2R(pi/3)": (sp.diag(JORDAN, rotation(sp.pi / 3, 2)),
                        [[[1, 0, 1, 0]], [[0, 1, 1, 1]], [[2, -1, 0, 1]]]),
    "J_3(2) + 2R(pi/2)": (sp.diag(sp.Matrix([[2, 1, 0], [0, 2, 1], [0, 0, 2]]), rotation(sp.pi / 2, 2)),
                          [[[1, 0, 0, 1, 0]], [[0, 1, 1, 0, 1]], [[0, 0, 1, 1, 1]]]),
    "J(2) + J(2), a one- and a two-row sensor": (sp.diag(JORDAN, JORDAN),
                                                 [[[1, 0, 1, 0]], [[0, 1, 0, 0], [0, 0, 1, 0]]]),
}


@pytest.mark.parametrize("name", MULTI)
def test_elements_of_several_generators_screened_as_enumerated(name):
    """Two-row sensors and Jordan chains (an element is inside a hyperplane when all its
    generators are): the search through their flats gives the decay rate, decisive hyperplane and critical
    loss rate of the listing, with unequal losses."""
    A, rows = MULTI[name]
    loss = sk.IID(["1/10", "1/3", "1/2"][:len(rows)])
    fast, full = (sk.System(A=A, sensors=[sk.Sensor(C=r) for r in rows]) for _ in range(2))
    (br_fast,), (br_full,) = block_rows(fast), block_rows(full)
    assert any(len(gs) > 1 for gs in br_fast.generators)
    weights = _weights(loss)
    heavy = br_fast.heaviest([weights[e.sensor] for e in br_fast.elements])
    assert heavy is not None and "inside" not in br_fast.__dict__
    best = max(sum(weights[br_full.elements[e].sensor] for e in H) for H in br_full.hyperplanes)
    assert {H for H in br_full.hyperplanes
            if sum(weights[br_full.elements[e].sensor] for e in H) > best - 1e-9} <= set(heavy)
    a, b = block_rate(br_fast, loss), block_rate(br_full, loss)
    assert sp.simplify(a.per_period - b.per_period) == 0 and a.hyperplane == b.hyperplane
    assert critical_loss_rate(fast) == critical_loss_rate(full)


@pytest.mark.parametrize("name", MULTI)
def test_elements_of_several_generators_with_a_zero_floor_give_every_hyperplane(name):
    """``floor = 0``: every maximal element set of the listing, and nothing else (the sets held
    by hyperplanes, less those strictly inside another)."""
    A, rows = MULTI[name]
    br = block_rows(sk.System(A=A, sensors=[sk.Sensor(C=r) for r in rows]))[0]
    w = np.random.default_rng(2).random(len(br.elements)).tolist()
    got = br.heaviest(w, floor=0.0)
    assert got is not None and "inside" not in br.__dict__
    assert set(got) == set(br.hyperplanes)


FOUR_DIM = [sp.diag(rotation(sp.pi / 2, 2), rotation(sp.pi / 3, 2)), sp.diag(JORDAN, rotation(sp.pi / 3, 2)),
            sp.diag(JORDAN, JORDAN), sp.diag(rotation(sp.pi / 3, 2), rotation(2 * sp.pi / 3, 2))]


@settings(max_examples=12)
# a random run's: with generators weighted below an additive bound (w / count^2) the screen missed
# this maximiser
@example(FOUR_DIM[0], [([[0, 1, 0, 0], [0, 1, 0, 1]], "1/10")])
@given(st.sampled_from(FOUR_DIM),
       st.lists(st.tuples(st.lists(st.lists(st.integers(-2, 2), min_size=4, max_size=4), min_size=1, max_size=2),
                          st.sampled_from(["1/10", "1/5", "1/3", "1/2", "9/10"])), min_size=1, max_size=3))
def test_drawn_sensors_of_one_or_two_rows_screened_as_enumerated(A, sensors):
    """Drawn sensors of one or two rows on 4-dim blocks (rotations, Jordan chains): the screen's
    sets hold every maximiser of the listing, and the decay rates agree exactly."""
    try:
        fast, full = (sk.System(A=A, sensors=[sk.Sensor(C=r) for r, _ in sensors]) for _ in range(2))
    except sk.errors.UnobservableError:
        assume(False)
    loss = sk.IID([q for _, q in sensors])
    (br_fast,), (br_full,) = block_rows(fast), block_rows(full)
    weights = _weights(loss)
    w = [weights[e.sensor] for e in br_fast.elements]
    heavy = br_fast.heaviest(w)
    assume(heavy is not None)  # the generators span less than K^4 mod p: the listing's case
    best = max((sum(w[e] for e in H) for H in br_full.hyperplanes), default=0)
    assert {H for H in br_full.hyperplanes if sum(w[e] for e in H) > best - 1e-9} <= set(heavy)
    assert all(any(H <= G for G in br_full.hyperplanes) for H in heavy)  # each rank deficient


def test_a_tracker_beside_an_oscillator_is_screened_not_refused():
    """A planar constant-velocity model beside an oscillator of the same modulus, three scalar
    sensors: C(36, 5) = 376 992 hyperplanes to list, above the default cap; the screen decides."""
    A = sp.diag(JORDAN, JORDAN, rotation(sp.pi / 3, 2))
    rows = [[0, 1, -1, 2, 1, 0], [-2, 1, 1, 0, 2, -1], [1, 1, 0, -2, 0, 1]]
    S = sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows])
    assert critical_loss_rate(S) == sp.Rational(1, 2)


@pytest.mark.parametrize("name, rows", sorted({(name, str(rows)): (name, rows) for name, rows, _ in CASES}.values()))
def test_common_critical_loss_rate_from_the_heaviest_hyperplanes(name, rows):
    """The critical common loss rate binds at the hyperplanes holding the most elements: from the
    screen (no enumeration happens) it equals the value over every hyperplane."""
    fast, full = (sk.System(A=BLOCKS[name], sensors=[sk.Sensor(C=[r]) for r in rows]) for _ in range(2))
    (br_fast,), (br_full,) = block_rows(fast), block_rows(full)
    br_full.inside  # computed first: the bound is taken over every hyperplane
    a = critical_loss_rate(fast)
    assert "inside" not in br_fast.__dict__  # the screen answered
    assert a == critical_loss_rate(full)


FIVE = sp.diag(rotation(sp.pi / 3, 2), rotation(sp.pi / 2, 2), 2)  # one block of dimension 5, period 12
FULL = pytest.mark.full
FOUR = BLOCKS["diag(21/20 R(pi/3), 21/20 R(pi/4))"]
RANDOM = [  # (A, rows, losses, shifted): random rows, parallel rows, repeated losses; more in the full tier
    (FOUR, [[2, -2, 0, -2], [1, 1, 1, 1]], ["1/10", "1/3"], True),
    (FOUR, [[2, -2, 0, -2], [1, 1, 1, 1]], ["1/10", "1/3"], False),
    (FIVE, [[-1, 2, -2, 0, -2], [-2, 4, -4, 0, -4]], ["1/10", "1/3"], True),
    pytest.param(FIVE, [[1, 1, -2, 0, 2], [1, 1, 0, 1, 0]], ["1/5", "1/5"], False, marks=FULL),
    pytest.param(FOUR, [[1, -2, 0, 2], [1, 1, 0, 1], [2, -4, 0, 4]], ["1/5", "1/10", "1/2"], True, marks=FULL),
    pytest.param(FOUR, [[0, 2, -2, 1], [-1, -2, -1, -2], [0, 1, -1, 1]], ["1/5", "1/10", "1/5"], False, marks=FULL),
]


@pytest.mark.parametrize("A, rows, losses, shifted", RANDOM)
def test_heaviest_with_and_without_the_phase_shift(A, rows, losses, shifted, monkeypatch):
    """The screen by orbits of the phase shift, and element by element (no symmetry used), against
    full enumeration, on blocks of dimension 4 and 5 (the recursive flats)."""
    if not shifted:
        monkeypatch.setattr(BlockRows, "_shift", lambda self, live: None)
    loss = sk.IID(losses)
    fast, full = (sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows]) for _ in range(2))
    (br_fast,), (br_full,) = block_rows(fast), block_rows(full)
    live = np.array([e for e, gs in enumerate(br_fast.generators) if gs])  # one point per element
    assert (br_fast._shift(live) is not None) == shifted
    weights = _weights(loss)
    heavy = br_fast.heaviest([weights[e.sensor] for e in br_fast.elements])
    assert heavy is not None and set(heavy) <= set(br_full.hyperplanes)
    a, b = block_rate(br_fast, loss), block_rate(br_full, loss)
    assert sp.simplify(a.per_period - b.per_period) == 0 and a.hyperplane == b.hyperplane
    assert critical_loss_rate(fast) == critical_loss_rate(full)


@pytest.mark.parametrize("A, rows", [
    (sp.diag(rotation(sp.pi / 6, 2), rotation(sp.pi / 4, 2)), [[-2, 1, 0, 2]]),   # period 24, 970 hyperplanes
    (sp.diag(rotation(sp.pi / 2, 2), rotation(sp.pi / 3, 2)), [[1, 0, 0, 0], [0, 0, 1, 0], [1, 1, 1, 1]]),
])
def test_a_floor_below_every_weight_returns_every_hyperplane(A, rows):
    """With ``floor = 0`` no additive bound rules anything out: the screen keeps lower flats too
    (rank below n - 1, holding no hyperplane), drops them, and returns exactly the listing."""
    S = sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows])
    br = block_rows(S)[0]
    w = np.random.default_rng(1).random(len(br.elements)).tolist()
    got = br.heaviest(w, floor=0.0)
    assert got is not None and "inside" not in br.__dict__
    assert set(got) == set(br.hyperplanes)


@pytest.mark.parametrize("name, rows, losses", CASES)
def test_proportional_weights_are_screened_once(name, rows, losses, monkeypatch):
    # heaviest without a floor is kept per direction of the weights: proportional weights (a common
    # rate's critical value, then a verdict at equal rates) reuse it, and what it returns holds the
    # maximisers a fresh screen at the scaled weights finds; another direction is screened anew
    loss = sk.IID(losses)
    cached, fresh = (sk.System(A=BLOCKS[name], sensors=[sk.Sensor(C=[r]) for r in rows]) for _ in range(2))
    (br,), (br_fresh,) = block_rows(cached), block_rows(fresh)
    weights = [_weights(loss)[e.sensor] for e in br.elements]
    screens = []
    screened = BlockRows._heaviest
    monkeypatch.setattr(BlockRows, "_heaviest",
                        lambda self, w, floor, **kw: screens.append(1) or screened(self, w, floor, **kw))
    first = br.heaviest(weights)
    again = br.heaviest([4.0 * w for w in weights])   # (exactly proportional in floats: 2.5 w need not be)
    assert len(screens) == 1 and set(again) == set(first)
    scaled = br_fresh.heaviest([4.0 * w for w in weights])
    best = max(sum(4.0 * weights[e] for e in H) for H in scaled)
    assert {H for H in scaled if sum(4.0 * weights[e] for e in H) >= best - 1e-9} <= set(again)
    br.heaviest([w * (1 + br.elements[e].sensor) for e, w in enumerate(weights)])
    assert len(screens) == 3   # the fresh system's screen, then the new direction


def _many_sensors(rows):
    """The 4-dim block diag(2R(pi/6), 2R(pi/4)) (modulus 2, period 24) seen by scalar sensors."""
    return sk.System(A=sp.diag(rotation(sp.pi / 6, 2), rotation(sp.pi / 4, 2)),
                     sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)])


SIXTEEN = [[int(v) for v in np.random.default_rng(16).integers(1, 3, 4)] for _ in range(16)]


def test_eighty_sensors_under_the_work_cap_run_and_five_copies_take_the_fifth_root():
    """80 sensors, above the former size cap of 64, run under max_work: sixteen rows each sent by
    five sensors.  A hyperplane holds every copy of a row or none, so each exponent vector is five
    times the sixteen sensors' and the critical common loss rate is the fifth root of theirs."""
    once = critical_loss_rate(_many_sensors(SIXTEEN))
    five = critical_loss_rate(_many_sensors([r for r in SIXTEEN for _ in range(5)]))
    assert sp.simplify(five.exact ** 5 - once.exact) == 0 and 0 < five < 1


def test_the_screen_is_priced_by_the_points_it_classifies(monkeypatch):
    """The units priced before the screen are the work it then does: every point a stage
    classifies is counted (none more), and the incidences bound the pairs of classes its lines
    test."""
    from symkf import budget
    from symkf.engine import hyperplane_screen
    priced, classified, searching = [], [0], [False]
    price, classes, search = budget.price, hyperplane_screen._classes, hyperplane_screen.search

    def spy_price(entry, what, **units):
        priced.append(units)
        return price(entry, what, **units)

    def spy_classes(X, p):
        classified[0] += len(X) if searching[0] else 0
        return classes(X, p)

    def spy_search(*args):
        searching[0] = True
        try:
            return search(*args)
        finally:
            searching[0] = False
    monkeypatch.setattr(budget, "price", spy_price)
    monkeypatch.setattr(hyperplane_screen, "_classes", spy_classes)
    monkeypatch.setattr(hyperplane_screen, "search", spy_search)
    critical_loss_rate(_many_sensors(SIXTEEN * 2))
    *least, units = priced   # the points of the cheaper plan, priced before the floor, then the plan's
    assert units["screen_point"] == classified[0] > 0 and all(u["screen_point"] <= classified[0] for u in least)


def test_a_markov_query_over_max_work_is_refused_before_its_screens():
    """Gilbert-Elliott channels on 128 sensors of rows in -2..2: the two screens of the Markov
    search are priced together (about 1.4 CPU-s) before the first runs; under a cap of 1 CPU-s
    (1000 CPU-ms) they are refused at once, naming the cap and its option."""
    import time
    rows = [[int(v) for v in r] for r in np.random.default_rng(128).integers(-2, 3, (128, 4)) if r.any()]
    S = _many_sensors(rows)
    loss = sk.GilbertElliott(["1/10"] * len(rows), ["1/2"] * len(rows))
    start = time.process_time()
    with sk.budget.limits(max_work=1000), pytest.raises(sk.errors.BudgetError,
                                                        match=r"2 such screens\) is .* above the cap max_work = 1000 "
                                                              r"CPU-ms.*--max-work"):
        sk.stability(S, loss)
    assert time.process_time() - start < 10


def test_the_incidences_are_not_counted_when_the_screen_points_alone_pass_the_cap(monkeypatch):
    """Gilbert-Elliott channels on 128 sensors of rows in -2..2: the cheaper plan classifies 210 758
    points in the two screens (0.105 CPU-s at 0.5 µs), the windowed plan the floor leads to 786 176
    (0.39 CPU-s). Under max_work = 200 CPU-ms the plan's points alone pass the cap: its incidences,
    a class count per stage, are counted under a cap of 0 (one stage); under 50 CPU-ms even the
    cheaper plan's points pass it, and the screen is refused before its floor reads any flat."""
    from symkf.engine import hyperplane_screen
    caps, floors, work, lower_bound = [], [], hyperplane_screen.work, hyperplane_screen.lower_bound

    def spy_work(X, p, plan, cap):
        caps.append(cap)
        return work(X, p, plan, cap)

    def spy_lower_bound(*args):
        floors.append(1)
        return lower_bound(*args)
    monkeypatch.setattr(hyperplane_screen, "work", spy_work)
    monkeypatch.setattr(hyperplane_screen, "lower_bound", spy_lower_bound)
    rows = [[int(v) for v in r] for r in np.random.default_rng(128).integers(-2, 3, (128, 4)) if r.any()]
    loss = sk.GilbertElliott(["1/10"] * len(rows), ["1/2"] * len(rows))
    with sk.budget.limits(max_work=200), pytest.raises(sk.errors.BudgetError, match=r"786176 screen points at 0.5 µs"):
        sk.stability(_many_sensors(rows), loss)
    assert caps == [0] and floors == [1]
    with sk.budget.limits(max_work=50), pytest.raises(sk.errors.BudgetError,
                                                      match=r"its points alone, whichever plan; 2 such screens\) is "
                                                            r"0.105 CPU-s.*\(the estimate: 210758 screen points"):
        sk.stability(_many_sensors(rows), loss)
    assert caps == [0] and floors == [1]
