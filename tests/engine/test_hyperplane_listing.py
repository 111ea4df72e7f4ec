"""The listing of every hyperplane (BlockRows.inside) through the flats of the elements of several
generators (two-row sensors, Jordan chains) against the listing through every flat of the
generators: the same maximal element sets, at most the estimated number of them, and the
Gilbert-Elliott verdict it decides equal to the i.i.d. one where the two laws coincide."""

import math

import numpy as np
import sympy as sp
from hypothesis import assume, example, given, settings, strategies as st

import symkf as sk
from conftest import rotation
from symkf.engine import rows as observability
from symkf.engine.search import listed_hyperplanes
from symkf.engine.rows import BlockRows
from symkf.engine.blocks import block_rows

JORDAN = sp.Matrix([[2, 1], [0, 2]])
BLOCKS = [sp.diag(rotation(sp.pi / 2, 2), rotation(sp.pi / 3, 2)), sp.diag(JORDAN, rotation(sp.pi / 3, 2)),
          sp.diag(JORDAN, JORDAN), sp.diag(rotation(sp.pi / 6, 2), rotation(sp.pi / 4, 2)),
          sp.diag(sp.Matrix([[2, 1, 0], [0, 2, 1], [0, 0, 2]]), rotation(sp.pi / 2, 2)),
          sp.diag(rotation(sp.pi / 2, 2), rotation(sp.pi / 3, 2), -2)]


def _every_flat(br: BlockRows) -> set[frozenset[int]]:
    """The maximal sets from the listing through every flat of ``n - 2`` generators."""
    saved, observability._element_flats = observability._element_flats, lambda *args: None
    try:
        return set(BlockRows(br.block, br.K, br.class_period, br.elements, br.generators, br.size, br.T, br.diag,
                             br.phase_shift).hyperplanes)
    finally:
        observability._element_flats = saved


@settings(max_examples=15, deadline=None)
# a random run's: extensions of an element's generators by earlier generators only missed a hyperplane
@example(4, [([[0] * 6, [0] * 6, [1, 0, 0, 0, 0, 0]], False), ([[0, 0, 0, 0, 1, 0]], False)])
@given(st.integers(0, len(BLOCKS) - 1),
       st.lists(st.tuples(st.lists(st.lists(st.integers(-2, 2), min_size=6, max_size=6), min_size=1, max_size=3),
                          st.booleans()), min_size=1, max_size=3))
def test_element_flats_list_the_maximal_sets_of_every_flat(block, drawn):
    """Drawn sensors of one to three rows (``twin``: the second row twice the first) on blocks of
    dimension 4 and 5: every maximal set, and only those, when fewer flats are visited."""
    A = BLOCKS[block]
    n = A.shape[0]
    sensors = []
    for C, twin in drawn:
        C = [r[:n] for r in C]
        if twin and len(C) > 1:
            C[1] = [2 * v for v in C[0]]
        sensors.append(sk.Sensor(C=C))
    try:
        S = sk.System(A=A, sensors=sensors)
    except sk.errors.UnobservableError:
        assume(False)
    (br,) = block_rows(S)
    vectors, bases = br._bases
    assume(observability._element_flats(bases, len(vectors), n) is not None)
    assume(math.comb(len(vectors), n - 1) <= 60_000)  # the reference listing stays small
    listed = set(br.hyperplanes)
    assert listed == _every_flat(br)
    assert len(listed) <= br.listing_estimate()[0]


def test_flats_of_two_row_sensors_are_counted_per_element():
    """One two-row sensor on 2R(pi/2) + 2R(pi/3) (period 12, 12 elements of two generators in
    dimension 4): a hyperplane through an element's plane is spanned by one more generator, so
    the estimate is sum_e C(V - 2, 1) = 12 (V - 2) for V generators, against C(V, 3) over every flat."""
    S = sk.System(A=BLOCKS[0], sensors=[sk.Sensor(C=[[1, 0, 1, 0], [0, 1, 1, 1]])])
    (br,) = block_rows(S)
    V = len(br._bases[0])
    assert all(len(b) == 2 for b in br._bases[1]) and len(br.elements) == 12
    assert br.listing_estimate()[0] == 12 * (V - 2) < math.comb(V, 3)
    assert set(br.hyperplanes) == _every_flat(br)


def test_two_row_sensors_at_period_24_are_listed_not_refused():
    """Three two-row sensors on diag(2R(pi/6), 2R(pi/4)) (period 24): C(144, 3) = 487 344
    hyperplanes over every flat, above the default cap; 72 (144 - 2) = 10 224 through the elements' flats.
    Gilbert-Elliott channels with ``fail + recover = 1`` are i.i.d. losses ``fail``: the verdict
    from the listing equals the one the i.i.d. screen gives on a fresh copy."""
    rng = np.random.default_rng(0)
    C = [[[int(v) for v in rng.integers(-2, 3, 4)] for _ in range(2)] for _ in range(3)]
    S, fresh = (sk.System(A=BLOCKS[3], sensors=[sk.Sensor(C=c) for c in C]) for _ in range(2))
    (br,) = block_rows(S)
    assert len(br._bases[0]) == 144 and br.listing_estimate()[0] == 72 * 142
    listed_hyperplanes(br)
    ge = sk.stability(S, sk.GilbertElliott(["1/5"] * 3, ["4/5"] * 3))
    iid = sk.stability(fresh, sk.IID(["1/5"] * 3))
    assert "inside" not in block_rows(fresh)[0].__dict__
    assert ge.margins[0] == iid.margins[0] and ge.stable and iid.stable


def _built(br: BlockRows) -> int:
    """The number of generator hyperplanes the listing builds (the rows of BlockRows.inside's matrices)."""
    vectors, bases = br._bases
    n = br.size
    return len(observability._generator_hyperplanes(br.K, vectors, n, observability._element_flats(bases, len(vectors), n)))


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 3), st.lists(st.lists(st.lists(st.integers(-2, 2), min_size=4, max_size=4), min_size=2, max_size=3),
                                   min_size=1, max_size=2))
def test_listing_estimate_bounds_the_generator_hyperplanes_built(block, drawn):
    """Drawn sensors of two or three rows on the 4-dim blocks (periods 12 and 24): the estimate is
    at least the generator hyperplanes the listing builds (its work and memory), themselves at
    least the element sets it lists."""
    try:
        S = sk.System(A=BLOCKS[block], sensors=[sk.Sensor(C=C) for C in drawn])
    except sk.errors.UnobservableError:
        assume(False)
    (br,) = block_rows(S)
    built = _built(br)
    assert len(br.inside) <= built <= br.listing_estimate()[0]


def test_three_row_sensors_price_every_hyperplane_through_their_flats():
    """A three-row sensor on diag(2R(pi/6), 2R(pi/4)) (24 elements, each spanning a hyperplane of
    3 of the V = 72 generators): the listing visits the flat of two of them and every hyperplane
    through it, at most V - 2 = 70 per element: 24 * 70 = 1680 estimated, 1608 built (24 elements
    of one generator hyperplane each would be 24)."""
    S = sk.System(A=BLOCKS[3], sensors=[sk.Sensor(C=[[-1, 1, 0, 2], [1, 2, 2, 0], [-2, 2, 0, 1]])])
    (br,) = block_rows(S)
    assert len(br._bases[0]) == 72 and all(len(b) == 3 for b in br._bases[1])
    assert br.listing_estimate()[0] == 24 * 70 >= _built(br) > 24 * 60


def test_estimate_of_two_row_sensors_is_within_ten_percent_of_the_hyperplanes_built():
    """Four two-row sensors on diag(2R(pi/6), 2R(pi/4)) (96 elements, V = 192): the estimate
    96 (192 - 2) = 18 240 against 16 920 generator hyperplanes built; the element sets listed
    are 72 (each set a union over many generator hyperplanes through one element's plane)."""
    rng = np.random.default_rng(0)
    C = [[[int(v) for v in rng.integers(-2, 3, 4)] for _ in range(2)] for _ in range(4)]
    (br,) = block_rows(sk.System(A=BLOCKS[3], sensors=[sk.Sensor(C=c) for c in C]))
    assert br.listing_estimate()[0] == 96 * 190 and _built(br) == 16_920 and len(br.inside) == 72
