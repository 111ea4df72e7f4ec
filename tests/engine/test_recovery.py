"""The critical recovery rate of Gilbert-Elliott channels (symkf.engine.recovery).

Values derived by hand (two sensors, one sensor, extremes), a non-monotone case refused for the
monotone search and given as its stable intervals, and the monotone search against the listing of
every hyperplane (``stable_recovery_intervals``): the same exact algebraic number on small systems
(periods 2-24, unequal fail rates, tied sensors), and eight sensors checked on both sides."""


import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf.engine.blocks import block_rows
from symkf.engine.rates import m_matrix
from symkf.engine.recovery import (
    _recovery_model,
    critical_recovery_rate,
    listed_margins,
    monotone_critical_recovery,
    stable_recovery_intervals,
)
from symkf.engine.region import ge_margins, stable_intervals
from symkf.engine.stability import stability
from symkf.exact.algebraic import AlgebraicNumber
from symkf.io.files import load

from conftest import rotation, stacked_rotations

TWO = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])
# alpha^2 = 3/2, governing period 2: fail 1/2 gives margin 9/4 (q/2 + (1-q)^2), stable iff 2/3 < q < 5/6
NONMONO = sk.System(A=[[0, "-sqrt(6)/2"], ["sqrt(6)/2", 0]], sensors=[sk.Sensor(C=[[1, 0]])])
q = sp.Symbol("q")


def _float_radius(M):
    return max(abs(np.linalg.eigvals(np.array(M.evalf().tolist(), dtype=float)))) if M.shape[0] else 0.0


def test_recovery_two_sensors_by_hand():
    # hyperplanes are single elements; the worst loses sensor 2 (fail 1/3) entirely and
    # sensor 1 at one phase: 16 (q/3 + (1-q)^2) (1-q)^2 = 1 (traces of 2x2 restricted transfers)
    qc = critical_recovery_rate(TWO, ["1/4", "1/3"])
    hand = sp.Poly(48 * (1 - q) ** 4 + 16 * q * (1 - q) ** 2 - 3, q)
    assert sp.Poly(qc.minpoly.as_expr().subs(sp.Symbol("x"), q), q).monic() == hand.monic()
    lo, hi = qc.refine(sp.Rational(1, 10 ** 9)).interval
    assert not stability(TWO, sk.GilbertElliott(["1/4", "1/3"], [lo - sp.Rational(1, 10 ** 9)] * 2)).stable
    assert stability(TWO, sk.GilbertElliott(["1/4", "1/3"], [hi + sp.Rational(1, 10 ** 9)] * 2)).stable


def test_recovery_of_one_sensor_by_hand():
    # 4 (q/4 + (1-q)^2) < 1 iff 3/4 < q < 1, and 20/3 (1-q)^2 < 1 is weaker there
    assert critical_recovery_rate(TWO, ["1/4", "1/3"], recover=[0, "1/2"], sensor="s1") == sp.Rational(3, 4)


def test_recovery_is_not_monotone():
    (lo, hi), = stable_recovery_intervals(NONMONO, ["1/2"])
    assert (lo, hi) == (sp.Rational(2, 3), sp.Rational(5, 6))
    with pytest.raises(sk.SymkfError, match="monotone"):
        critical_recovery_rate(NONMONO, ["1/2"])
    (br,) = block_rows(NONMONO)
    for r, stable in [("3/5", False), ("3/4", True), ("9/10", False)]:
        loss = sk.GilbertElliott(["1/2"], [r])
        assert stability(NONMONO, loss).stable is stable
        M, _ = m_matrix(br, loss)  # independent of the hyperplane traces
        assert bool(2.25 * _float_radius(M) < 1) is stable


def test_recovery_extremes():
    assert critical_recovery_rate(QUARTER_TURN := sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])]),
                                  ["1/4"]) == 1  # 16 (q/4 + (1-q)^2) >= 15/4 for every q
    assert stability(QUARTER_TURN, sk.GilbertElliott(["1/4"], ["7/8"])).stable is False
    stable_A = sk.System(A=[["1/2", 0], [0, "1/3"]], sensors=[sk.Sensor(C=[[1, 1]])])
    assert critical_recovery_rate(stable_A, ["1/2"]) == 0


def test_recovery_input_errors():
    with pytest.raises(sk.SymkfError, match="fail"):
        critical_recovery_rate(TWO, ["1/4"])
    with pytest.raises(sk.SymkfError, match="recover"):
        critical_recovery_rate(TWO, ["1/4", "1/3"], sensor="s1")


# -- against the listing of every hyperplane ---------------------------------------------------

def _system(A, rows):
    return sk.System(A=A, sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)])


def _every_hyperplane(S, fail, recover=None, sensor=None):
    """The stable set from every hyperplane's margin condition (symkf.engine.region), not the monotone search."""
    q = sp.Symbol("q", positive=True)
    return stable_intervals(ge_margins(S, _recovery_model(S, fail, recover, sensor, q)), q)


def _listed(S, fail):
    (lo, hi), = _every_hyperplane(S, fail)
    assert hi == 1
    return lo


def test_the_bound_above_q_max_is_iid_losses_at_the_largest_fail():
    """Fail 1/3 on both channels of TWO: above ``q_max = 2/3`` every run term is at most 1/3, and
    i.i.d. losses 1/3 are stable (``16 eps^3 < 1`` iff ``eps < 0.397``), so the monotone search
    answers; a bound of ``f (1 + f) = 4/9`` per lost phase is not stable there and left it to the list."""
    fail = [sp.Rational(1, 3)] * 2
    assert stability(TWO, sk.IID(["1/3", "1/3"])).stable and not stability(TWO, sk.IID(["4/9", "4/9"])).stable
    fast = monotone_critical_recovery(TWO, fail)
    assert fast is not None and fast == _listed(TWO, fail) and fast.minpoly == _listed(TWO, fail).minpoly


def _stable_around(S, fail, qc, width=sp.Rational(1, 10 ** 9)):
    """The verdicts at rationals just below and just above ``qc``: (False, True) for a critical rate."""
    lo, hi = qc.refine(width).interval
    return tuple(stability(S, sk.GilbertElliott(fail, [r] * len(fail))).stable
                 for r in (sp.Rational(lo) - width, sp.Rational(hi) + width))


GENERIC = [  # (orders, rows, fail): blocks whose screens cannot rule the generic hyperplanes out
    ((4, 6), [[2, -1, -2, 2]], ["2/100"]),
    ((3, 5), [[1, 2, 1, -2], [-1, 0, 1, 0]], ["1/10", "1/10"]),
]


@pytest.mark.parametrize("orders, rows, fail", GENERIC)
def test_recovery_beyond_the_list_equals_the_list(orders, rows, fail, monkeypatch):
    """The list's estimate pretended past ``search.LIST_BELOW``: the certificate's hyperplanes come from
    the special ones and the rates of any ``n - 1`` live elements reaching the floor
    (generic_hyperplanes.reaching_elements), not from a refused list, and the critical rate is the
    list's exact number, unstable just below and stable just above."""
    from symkf.engine import rows as engine_rows, search
    answered = []
    beyond = search._reaching_beyond_listing

    def spy(br, rates, low):
        out = beyond(br, rates, low)
        answered.append(out is not None)
        return out
    fail = [sp.Rational(f) for f in fail]
    with monkeypatch.context() as m:
        m.setattr(search, "_reaching_beyond_listing", spy)
        m.setattr(engine_rows.BlockRows, "listing_estimate", lambda self: (10 ** 12, "pretended"))
        got = monotone_critical_recovery(stacked_rotations(orders, rows), fail)
    S = stacked_rotations(orders, rows)
    assert answered and all(answered)
    assert got is not None and got == _listed(S, fail) and got.minpoly == _listed(S, fail).minpoly
    assert _stable_around(S, fail, got) == (False, True)


#: the 6-dim block (3/2) diag(R(pi/2), R(pi/3), R(2 pi/3)) (period 12) with three sensors in general
#: position: C(36, 5) hyperplanes to list
SIX = sk.System(A=sp.Rational(3, 2) * sp.diag(rotation(sp.pi / 2, 1), rotation(sp.pi / 3, 1), rotation(2 * sp.pi / 3, 1)),
                sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(
                    [[-2, -2, -2, 0, -1, 0], [0, 2, -1, 2, -2, 2], [-1, 1, 1, 2, 0, 2]])])
SIX_FAIL = ["1/2", "1/2", "3/10"]


def test_recovery_of_a_block_in_general_position_without_the_list(monkeypatch):
    """The critical rate comes from the special hyperplanes and the best rates of five elements,
    no hyperplane's margin listed: degree 36, ``q_c ~ 0.2872187181941923``, unstable just below and
    stable just above."""
    from symkf.engine import recovery

    def listing(*args):
        raise AssertionError("the hyperplanes were listed")
    with monkeypatch.context() as m:
        m.setattr(recovery, "listed_margins", listing)
        m.setattr(recovery, "ge_margins", listing)
        qc = sk.critical_recovery_rate(SIX, fail=SIX_FAIL)
    assert qc.minpoly.degree() == 36 and abs(float(qc) - 0.2872187181941923) < 1e-15
    assert _stable_around(SIX, SIX_FAIL, qc) == (False, True)


def test_listing_every_margin_is_priced_before_a_hyperplane_is_listed():
    """The 6-dim block's C(36, 5) = 376 992 margins, at 20 µs each in flint (budget.COSTS["margin"],
    about 7.5 CPU-s; 6.9 measured) and 200 µs in sympy ("symbolic margin", about 75 CPU-s): under a
    max_work of 5 CPU-s both routes that build every margin are refused at once, naming the cap and
    the count; at 10 CPU-s the route in sympy only."""
    from symkf import budget
    from symkf.engine.recovery import _monotone_recovery
    from symkf.errors import BudgetError
    with budget.limits(max_work=5_000):
        with pytest.raises(BudgetError, match=r"max_work.*376992 margins at 20 µs"):
            _monotone_recovery(SIX, SIX_FAIL, None, None)[2]()
        with pytest.raises(BudgetError, match=r"max_work.*376992 symbolic margins at 200 µs"):
            _every_hyperplane(SIX, SIX_FAIL)
    with budget.limits(max_work=10_000):
        assert budget.seconds(margin=376992) < 10
        with pytest.raises(BudgetError, match=r"max_work.*376992 symbolic margins"):
            _every_hyperplane(SIX, SIX_FAIL)


@pytest.mark.full  # the list of C(36, 5) hyperplanes and their margins: about 8 CPU-s
def test_recovery_of_a_block_in_general_position_equals_the_raised_list():
    # every hyperplane's margin built in flint (recovery.listed_margins), as the fallback lists them
    from symkf.engine.recovery import _monotone_recovery
    qc = sk.critical_recovery_rate(SIX, fail=SIX_FAIL)
    (listed, one), = _monotone_recovery(SIX, SIX_FAIL, None, None)[2]()
    assert one == 1 and qc == listed and qc.minpoly == listed.minpoly


def test_two_sensor_example():
    S, loss = load(sk.examples.system("ge-two-sensors"))
    expected = sp.CRootOf(16 * sp.Symbol("x") ** 4 - 60 * sp.Symbol("x") ** 3 + 88 * sp.Symbol("x") ** 2
                          - 60 * sp.Symbol("x") + 15, 0)
    fast = monotone_critical_recovery(S, loss.fail)
    assert fast is not None and fast == _listed(S, loss.fail)
    assert fast.minpoly.as_expr() == 16 * sp.Symbol("x") ** 4 - 60 * sp.Symbol("x") ** 3 + 88 * sp.Symbol("x") ** 2 \
        - 60 * sp.Symbol("x") + 15
    assert abs(float(fast) - float(expected)) < 1e-14
    assert sk.critical_recovery_rate(S, fail=["1/4", "1/4"]) == fast


CASES = [  # (A, rows, fail): periods 2, 3, 4, 6 and 24, tied and unequal channels
    (rotation(sp.pi / 2), [[1, 0], [1, 1]], ["1/4", "1/4"]),
    (rotation(sp.pi / 2), [[1, 0], [1, 0]], ["1/5", "1/5"]),          # parallel rows: ties
    (rotation(sp.pi / 2), [[1, 0], [0, 1], [1, 1]], ["1/10", "1/5", "1/8"]),
    (rotation(2 * sp.pi / 3), [[1, 0], [1, 2]], ["1/6", "1/3"]),
    (rotation(sp.pi / 4), [[1, 0]], ["1/10"]),
    (rotation(sp.pi / 3), [[1, 0], [2, -1]], ["1/7", "1/10"]),
    (sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)), [[1, 0, -1, 2]], ["1/10"]),
    # irrational moduli: the crossings are roots of rho(q) = alpha^(-2g) with alpha^(2g) algebraic
    ([[2, 1], [1, 1]], [[1, 0], [1, -1]], ["1/10", "1/4"]),                     # (3 + sqrt 5)/2
    ([[1, -2, 0], [1, 1, 1], [0, 1, 2]], [[1, 0, 0], [0, 0, 1]], ["1/8", "1/5"]),  # a dense 3x3
    (sp.diag(sp.sqrt(2) * rotation(sp.pi / 2, 1), [[3, 1], [1, 1]]), [[1, 0, 1, 0], [0, 1, 0, 1]], ["1/10", "1/10"]),
]


@pytest.mark.parametrize("A, rows, fail", CASES)
def test_equals_listing(A, rows, fail):
    S = _system(A, rows)
    fail = [sp.Rational(f) for f in fail]
    fast = monotone_critical_recovery(S, fail)
    assert fast is not None
    assert fast == _listed(S, fail)
    assert fast.minpoly == _listed(S, fail).minpoly
    assert stable_recovery_intervals(S, fail) == _every_hyperplane(S, fail) == ((fast, 1),)


SEVERAL = [  # (A, sensors' rows, fail): elements of several generators, through their flats
    (sp.diag(rotation(sp.pi / 2), rotation(sp.pi / 3)), [[[1, 0, 1, 0], [0, 1, 1, 1]], [[1, 2, 0, -1], [1, 0, 0, 0]]],
     ["1/10", "1/8"]),
    (sp.diag(sp.Matrix([[2, 1], [0, 2]]), rotation(sp.pi / 3)), [[[1, 0, 1, 0]], [[0, 1, 1, 1]], [[2, -1, 0, 1]]],
     ["1/10", "1/5", "1/20"]),
    (sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)), [[[1, -1, 0, 2], [0, 1, 2, 1]], [[2, 0, -1, 1], [1, 1, 0, 0]]],
     ["1/10", "1/10"]),
]


@pytest.mark.parametrize("A, rows, fail", SEVERAL)
def test_several_rows_and_jordan_chains_equal_listing(A, rows, fail):
    """Two-row sensors and a Jordan chain: the monotone search (its screens through the elements'
    flats) against every hyperplane of the generator listing (computed first on its own copy)."""
    fast, full = (sk.System(A=A, sensors=[sk.Sensor(C=r) for r in rows]) for _ in range(2))
    fail = [sp.Rational(f) for f in fail]
    got = monotone_critical_recovery(fast, fail)
    assert got is not None
    for br in block_rows(full):
        br.inside
    assert got == _listed(full, fail)


@pytest.mark.parametrize("A, rows, fail", CASES[:4] + [SEVERAL[0]])
def test_listed_margins_equal_sympys(A, rows, fail):
    """The fallback's margins built in flint (recovery.listed_margins) are sympy's expansion of the
    same products (region.ge_margins), exactly, common and one sensor's rate alike."""
    S = sk.System(A=A, sensors=[sk.Sensor(C=r if isinstance(r[0], list) else [r]) for r in rows])
    q = sp.Symbol("q", positive=True)
    fail = [sp.Rational(f) for f in fail]
    for sensor, recover in ((None, None), (0, [sp.Rational(1, 3)] * len(rows))):
        model = _recovery_model(S, fail, recover, None if sensor is None else S.sensors[sensor].name, q)
        got = listed_margins(S, fail, recover, sensor)
        assert got is not None
        margins = {sp.expand(sp.Poly([sp.Rational(int(c.p), int(c.q)) for c in reversed(rho.coeffs())], q).as_expr()
                             / gamma.exact) for gamma, rates in got for rho in rates}
        assert margins == set(ge_margins(S, model))


BEYOND_Q_MAX = [  # (A, rows, fail, recover, sensor): q_c above 1 - max fail, or several intervals: the list decides
    (rotation(sp.pi / 2), [[1, 0], [1, 1]], ["1/2", "1/2"], None, None),
    (rotation(sp.pi / 2), [[1, 0], [0, 1], [1, 1]], ["3/5", "1/2", "9/10"], None, None),
    (rotation(sp.pi / 3), [[1, 0], [2, -1]], ["7/10", "1/5"], None, None),
    ([[0, "-sqrt(6)/2"], ["sqrt(6)/2", 0]], [[1, 0]], ["1/2"], None, None),                   # two end points
    ([[2, 1], [1, 1]], [[1, 0], [1, -1]], ["4/5", "1/2"], None, None),                         # (3 + sqrt 5)/2
    (rotation(sp.pi / 2), [[1, 0], [1, 1]], ["4/5", "1/10"], ["9/10", "9/10"], "s1"),
]


@pytest.mark.parametrize("A, rows, fail, recover, sensor", BEYOND_Q_MAX)
def test_the_listed_stable_set_equals_sympys(A, rows, fail, recover, sensor):
    """Where the monotone search does not answer, the stable set from the listed rates in flint
    (crossings isolated by Descartes' rule, the ones inside another margin's unstable range dropped,
    the gaps decided by exact rates) is the one from every margin expanded in sympy and solved
    root by root (region.stable_intervals), interval for interval."""
    from symkf.engine.recovery import _monotone_recovery
    S = _system(A, rows)
    fixed = None if sensor is None else [sp.Rational(r) for r in recover]
    j = None if sensor is None else S.sensor_index(sensor)
    assert monotone_critical_recovery(S, [sp.Rational(f) for f in fail], fixed, j) is None
    got = _monotone_recovery(S, fail, recover, sensor)[2]()
    assert got == _every_hyperplane(S, fail, recover, sensor) and got
    assert all(lo.minpoly == a.minpoly for (lo, _), (a, _) in zip(got, _every_hyperplane(S, fail, recover, sensor)))


def test_four_channels_whose_critical_rate_lies_above_q_max():
    """The period-24 block with four sensors failing at (3/5, 1/2, 3/5, 9/10): ``q_c ~ 0.3209 > q_max
    = 1/10``, so every hyperplane is listed (135 568, 39 distinct rates of degree 96) and the stable
    set comes from their crossings: ``(q_c, 1)`` with ``q_c`` of degree 16, unstable just below and
    stable just above."""
    S = _system(sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)),
                [[2, 1, 0, -1], [-1, -2, -2, -2], [-2, 2, 1, 2], [0, 1, 2, 1]])
    fail = ["3/5", "1/2", "3/5", "9/10"]
    assert monotone_critical_recovery(S, [sp.Rational(f) for f in fail]) is None
    qc = sk.critical_recovery_rate(S, fail=fail)
    assert qc.minpoly.degree() == 16 and abs(float(qc) - 0.3209414826056192) < 1e-15
    assert _stable_around(S, fail, qc) == (False, True)

def test_irrational_modulus_by_hand():
    """A = [[2, 1], [1, 1]] with one sensor failing at 1/20: the unstable mode alpha = (3 + sqrt 5)/2 (the other,
    1/alpha, decays) is seen at every step, so the decisive pattern is a run of losses, rate
    ``1 - q`` per step: stable iff ``alpha^2 (1 - q) < 1``, ``q_c = 1 - alpha^(-2) = (3 sqrt 5 - 5)/2``
    (``alpha^(-1) = (3 - sqrt 5)/2``: ``alpha^(-2) = (7 - 3 sqrt 5)/2``)."""
    S = _system([[2, 1], [1, 1]], [[1, 0]])
    fast = monotone_critical_recovery(S, [sp.Rational(1, 20)])
    assert fast is not None and fast == (3 * sp.sqrt(5) - 5) / 2
    assert sk.critical_recovery_rate(S, fail=["1/20"]) == fast
    assert fast == _listed(S, ["1/20"])


def test_irrational_fail_rate_by_hand():
    """As above with fail = sqrt(2)/10: the run of losses' rate ``1 - q`` does not depend on it, so
    ``q_c`` is the same; the hyperplanes are listed over Q(sqrt 2) (the monotone search takes
    rational rates), and the certificate's verdicts are decided there."""
    S = _system([[2, 1], [1, 1]], [[1, 0]])
    assert sk.critical_recovery_rate(S, fail=["sqrt(2)/10"]) == (3 * sp.sqrt(5) - 5) / 2


def test_irrational_fail_rates_against_verdicts():
    """Two two-row sensors on the period-24 block, fail sqrt(2)/10: the listed margins' crossing
    (degree 96) against the Markov search's verdicts just below and above it (the certificate's
    rational points once had 4000-digit terms, which Python refused to print: ValueError)."""
    S = sk.System(A=sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)),
                  sensors=[sk.Sensor(C=[[2, 1, 0, -1], [-1, -2, -2, -2]], name="s1"),
                           sk.Sensor(C=[[-2, 2, 1, 2], [0, 1, 2, 1]], name="s2")])
    fail = ["sqrt(2)/10", "sqrt(2)/10"]
    qc = sk.critical_recovery_rate(S, fail=fail)
    lo, hi = qc.refine(sp.Rational(1, 10 ** 9)).interval
    at = lambda q: sk.stability(S, sk.GilbertElliott(fail, [q, q])).stable  # noqa: E731
    assert 0 < qc < 1 and not at(sp.Rational(lo) - sp.Rational(1, 10 ** 6)) and at(sp.Rational(hi) + sp.Rational(1, 10 ** 6))


@pytest.mark.full
def test_equals_listing_benchmark_block():
    import numpy as np
    rng = np.random.default_rng(0)
    rows = []
    while len(rows) < 3:
        r = [int(v) for v in rng.integers(-2, 3, 4)]
        if any(r):
            rows.append(r)
    S = _system(sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)), rows)
    for d in (1, 2, 3):
        sub = _system(S.A, rows[:d])
        fail = [sp.Rational(1, 10)] * d
        assert monotone_critical_recovery(sub, fail) == _listed(sub, fail)


# -- one sensor's recovery rate, the others fixed --------------------------------------------------

def _listed_one(S, fail, recover, j):
    """``critical_recovery_rate``'s value from the listing of every hyperplane: 1 when no ``q`` is
    stable, None when the stable set is not an interval ``(q_c, 1)``."""
    intervals = _every_hyperplane(S, fail, recover, f"s{j + 1}")
    if not intervals:
        return AlgebraicNumber.from_expr(1)
    (lo, hi), = intervals
    assert hi == 1
    return lo


BLOCK = sp.diag(rotation(sp.pi / 2), rotation(sp.pi / 3))
ONE = [  # (A, rows, fail, recover, sensor, expected kind): interior values, 0 and 1 (a margin without q)
    (rotation(sp.pi / 2), [[1, 0], [0, 1], [1, 1]], ["1/10", "1/5", "1/8"], ["1/2"] * 3, 0, "interior"),
    (rotation(sp.pi / 2), [[1, 0], [0, 1], [1, 1]], ["1/10", "1/5", "1/8"], ["1/2"] * 3, 1, "interior"),
    (rotation(sp.pi / 2), [[1, 0], [0, 1], [1, 1]], ["1/10", "1/5", "1/8"], ["1/3", "3/4", "1/5"], 2, "interior"),
    (rotation(sp.pi / 2), [[1, 0], [1, 1]], ["1/4", "1/4"], ["9/10", "9/10"], 1, "interior"),
    (rotation(sp.pi / 2), [[1, 0], [1, 0]], ["1/5", "1/5"], ["1/3", "3/4"], 0, "interior"),  # parallel rows
    (rotation(2 * sp.pi / 3), [[1, 0], [1, 2]], ["1/6", "1/3"], ["9/10", "9/10"], 1, "interior"),
    (rotation(sp.pi / 3), [[1, 0], [2, -1]], ["1/7", "1/10"], ["1/10", "1/10"], 1, "interior"),
    (rotation(sp.pi / 4), [[1, 0]], ["1/10"], ["1/2"], 0, "interior"),
    (BLOCK, [[1, 0, 0, 0], [0, 0, 1, 0], [1, 1, 1, 1]], ["1/10"] * 3, ["9/10"] * 3, 0, "interior"),
    (BLOCK, [[1, 0, 0, 0], [0, 0, 1, 0], [1, 1, 1, 1]], ["1/10"] * 3, ["9/10"] * 3, 1, "zero"),
    (BLOCK, [[1, 0, 0, 0], [0, 0, 1, 0]], ["1/3"] * 2, ["1/20"] * 2, 0, "one"),
    (BLOCK, [[1, 1, 0, 0], [1, 0, 1, 0], [0, 1, 0, 1]], ["1/10"] * 3, ["9/10"] * 3, 2, "zero"),
]


@pytest.mark.parametrize("A, rows, fail, recover, j, kind", ONE)
def test_one_sensor_equals_listing(A, rows, fail, recover, j, kind):
    """Periods 2-12, unequal channels, parallel rows; the answer 0 (the others alone keep the
    filter stable), 1 (a hyperplane holding every element of the sensor has margin >= 1) and
    values inside: the monotone search decides and agrees with the listing."""
    S = _system(A, rows)
    fast = monotone_critical_recovery(S, [sp.Rational(f) for f in fail], [sp.Rational(r) for r in recover], j)
    assert fast is not None
    listed = _listed_one(S, fail, recover, j)
    assert fast == listed and {"zero": fast == 0, "one": fast == 1, "interior": 0 < fast < 1}[kind]
    assert sk.critical_recovery_rate(S, fail=fail, recover=recover, sensor=f"s{j + 1}") == fast


@settings(max_examples=12, deadline=None)
@given(st.lists(st.sampled_from(["1/20", "1/10", "1/5", "1/3"]), min_size=3, max_size=3),
       st.lists(st.sampled_from(["1/10", "1/2", "4/5", "19/20"]), min_size=3, max_size=3),
       st.integers(0, 2), st.sampled_from([2, 3, 6]))
def test_one_sensor_hypothesis_against_listing(fail, recover, j, q):
    """Hypothesis-drawn channels on three sensors of 2R(pi/q): whenever the monotone search
    answers, the listing of every hyperplane gives the same exact number."""
    S = _system(rotation(sp.pi / q), [[1, 0], [1, 1], [2, -1]])
    fast = monotone_critical_recovery(S, [sp.Rational(f) for f in fail], [sp.Rational(r) for r in recover], j)
    if fast is not None:
        assert fast == _listed_one(S, fail, recover, j)


def test_one_sensor_without_listing_at_period_24():
    """The 4-dim block of period 24 with 8 sensors: the list of every margin is refused (C(192, 3)
    hyperplanes estimated, their margins priced), the monotone search answers 0 (the other seven channels keep it stable, by the
    screened search at q = 0), so the stable set is all of (0, 1), and 1/2 is stable, as it must be."""
    import numpy as np

    from symkf.errors import BudgetError
    rng = np.random.default_rng(0)
    rows = []
    while len(rows) < 8:
        r = [int(v) for v in rng.integers(-2, 3, 4)]
        if any(r):
            rows.append(r)
    S = _system(sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 4)), rows)
    with pytest.raises(BudgetError, match=r"max-work .*1161280 symbolic margins"):
        _every_hyperplane(S, ["1/10"] * 8, ["1/2"] * 8, "s1")
    assert sk.critical_recovery_rate(S, fail=["1/10"] * 8, recover=["1/2"] * 8, sensor="s1") == 0
    assert stable_recovery_intervals(S, ["1/10"] * 8, recover=["1/2"] * 8, sensor="s1") == ((0, 1),)
    assert sk.stability(S, sk.GilbertElliott(["1/10"] * 8, ["1/100"] + ["1/2"] * 7)).stable


ROT = sp.Matrix([[sp.cos(sp.pi / 3), -sp.sin(sp.pi / 3)], [sp.sin(sp.pi / 3), sp.cos(sp.pi / 3)]])


@pytest.mark.full  # about 5 CPU-s on the shared machine
def test_critical_recovery_with_eight_gilbert_elliott_sensors():
    """Eight independent channels: per-sensor factors (no 2^8-state chain); the certificate inside
    critical_recovery_rate evaluates verdicts at rationals with huge numerators (margins as roots
    of q x^g - p, where sympy's root overflowed a float).  Checked again here on both sides."""
    from symkf.engine.recovery import critical_recovery_rate
    from symkf.engine.stability import stability
    rows = [[1, 0], [0, 1], [1, 1], [1, -1], [2, 1], [1, 2], [2, -1], [1, -2]]
    system = sk.System(A=2 * ROT, sensors=[sk.Sensor(C=[r], name=f"s{j}") for j, r in enumerate(rows)])
    fail = ["1/10"] * 8
    qc = critical_recovery_rate(system, fail)
    lo, hi = qc.refine(sp.Rational(1, 10 ** 6)).interval
    assert 0 < lo and hi < 1
    assert stability(system, sk.GilbertElliott(fail, [sp.Rational(hi) + sp.Rational(1, 10 ** 5)] * 8)).stable
    assert not stability(system, sk.GilbertElliott(fail, [sp.Rational(lo) - sp.Rational(1, 10 ** 5)] * 8)).stable


def test_a_gilbert_elliott_model_is_a_template_of_its_fail_probabilities():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    ge = sk.GilbertElliott(["1/4", "1/4"], ["1/2", "1/2"])
    assert sk.critical_recovery_rate(S, ge) == sk.critical_recovery_rate(S, ["1/4", "1/4"])
    with pytest.raises(sk.SymkfError, match="not Gilbert-Elliott channels"):
        sk.critical_recovery_rate(S, sk.IID(["1/4", "1/4"]))


def test_one_sensors_recovery_from_the_model_keeps_the_others_recovery():
    """A Gilbert-Elliott model as ``fail`` with ``sensor``: the other channels keep the model's
    recovery (ge-two-sensors with s2's recovery 1/2: q_c(s1) = 3/4, hand-derived in tests/test_cli.py)."""
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    model = sk.GilbertElliott(["1/4", "1/4"], ["1/2", "1/2"])
    assert sk.critical_recovery_rate(S, model, sensor="s1").exact == sp.Rational(3, 4)
    assert sk.critical_recovery_rate(S, model, sensor="s2") == sk.critical_recovery_rate(
        S, ["1/4", "1/4"], recover=["1/2", "1/2"], sensor="s2")
