"""Issue 3: critical recovery rates, the two-sensor stability region, symbolic conditions."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given, settings, strategies as st

from symkf.exact.numbers import sympify as exact
import symkf as sk
from symkf.engine.rates import m_matrix
from symkf.engine.search import block_rate
from symkf.exact.algebraic import AlgebraicNumber
from symkf.engine.blocks import block_rows
from symkf.engine.region import stability_conditions, stability_region
from symkf.engine.stability import critical_alpha, critical_loss_rate, stability
from symkf.engine.recovery import critical_recovery_rate, stable_recovery_intervals

TWO = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])
# alpha^2 = 3/2, governing period 2: fail 1/2 gives margin 9/4 (q/2 + (1-q)^2), stable iff 2/3 < q < 5/6
NONMONO = sk.System(A=[[0, "-sqrt(6)/2"], ["sqrt(6)/2", 0]], sensors=[sk.Sensor(C=[[1, 0]])])
TWO_BLOCKS = sk.System(A=[["5/4", 0, 0], [0, 0, "-6/5"], [0, "6/5", 0]],
                       sensors=[sk.Sensor(C=[[1, 1, 0]]), sk.Sensor(C=[[0, 1, 1]])])
THREE = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]]),
                                                 sk.Sensor(C=[[1, 2]])])
q = sp.Symbol("q")
rationals = st.fractions(min_value=0, max_value=1, max_denominator=12)


def _float_radius(M):
    return max(abs(np.linalg.eigvals(np.array(M.evalf().tolist(), dtype=float)))) if M.shape[0] else 0.0


# -- Gilbert-Elliott: critical recovery rates ------------------------------------------
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
    assert critical_recovery_rate(DESIGN_GE := sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])]),
                                  ["1/4"]) == 1  # 16 (q/4 + (1-q)^2) >= 15/4 for every q
    assert stability(DESIGN_GE, sk.GilbertElliott(["1/4"], ["7/8"])).stable is False
    stable_A = sk.System(A=[["1/2", 0], [0, "1/3"]], sensors=[sk.Sensor(C=[[1, 1]])])
    assert critical_recovery_rate(stable_A, ["1/2"]) == 0


def test_recovery_input_errors():
    with pytest.raises(sk.SymkfError, match="fail"):
        critical_recovery_rate(TWO, ["1/4"])
    with pytest.raises(sk.SymkfError, match="recover"):
        critical_recovery_rate(TWO, ["1/4", "1/3"], sensor="s1")


@settings(max_examples=8, deadline=None)
@given(st.sampled_from([(1, 4), (1, 3), (1, 2)]), st.sampled_from(["3/2", "5/4", 2]),
       st.lists(st.integers(-2, 2), min_size=2, max_size=2).filter(lambda v: v != [0, 0]),
       st.lists(st.sampled_from(["1/5", "1/3", "1/2", "3/4"]), min_size=4, max_size=4))
def test_ge_hyperplane_rate_equals_spectral_radius_of_full_m(angle, scale, c, params):
    # angle pi makes A a multiple of I: unobservable unless c is independent of [1, 0]
    assume(angle != (1, 2) or c[1] != 0)
    t = 2 * sp.pi * angle[0] / angle[1]
    A = exact(scale) * sp.Matrix([[sp.cos(t), -sp.sin(t)], [sp.sin(t), sp.cos(t)]])
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[c])])
    loss = sk.GilbertElliott(params[:2], params[2:])
    (br,) = block_rows(S)
    M, _ = m_matrix(br, loss)
    assert abs(float(AlgebraicNumber.from_expr(block_rate(br, loss).per_period)) - _float_radius(M)) < 1e-9


# -- the i.i.d. stability region ----------------------------------------------------------
def test_region_two_sensors_by_hand():
    R = stability_region(TWO)
    assert sorted(c.exponents for c in R.constraints) == [(1, 2), (2, 1)]
    e1, e2 = R.symbols
    assert R.conditions() == sp.And(16 * e1 * e2 ** 2 < 1, 16 * e1 ** 2 * e2 < 1)
    pieces = R.boundary()
    assert [(p.lo, p.hi) for p in pieces] == [(0, sp.Rational(1, 16)), (sp.Rational(1, 16), 2 ** sp.Rational(2, 3) / 4),
                                            (2 ** sp.Rational(2, 3) / 4, 1)]
    assert [p.expr for p in pieces] == [1, 1 / (4 * sp.sqrt(e1)), 1 / (16 * e1 ** 2)]
    # the common critical rate is where the curve meets the diagonal
    eps = critical_loss_rate(TWO)
    assert R.boundary_at(eps.exact) == eps


def test_region_cut_where_one_sensor_alone_destabilises():
    # A^2 = 4 I (g = 2); sensor 2's rows all lie on x_2 = 0, which holds no row of sensor 1:
    # 16 eps_1^2 < 1 whatever eps_2, so eps_1 >= 1/4 is unstable
    S = sk.System(A=[[2, 0], [0, -2]], sensors=[sk.Sensor(C=[[1, 1]]), sk.Sensor(C=[[1, 0]])])
    R = stability_region(S)
    assert (2, 0) in [c.exponents for c in R.constraints]
    last = R.boundary()[-1]
    assert (last.lo, last.hi, last.expr) == (sp.Rational(1, 4), 1, 0)
    assert R.boundary_at(sp.Rational(1, 4)) == 0 == critical_loss_rate(S, "s2", others=[sp.Rational(1, 4), 0])
    assert R.boundary_at(sp.Rational(1, 5)) == critical_loss_rate(S, "s2", others=[sp.Rational(1, 5), 0]) > 0


@pytest.mark.parametrize("system", [TWO, TWO_BLOCKS])
@settings(max_examples=15, deadline=None)
@given(e1=rationals, e2=rationals)
def test_region_agrees_with_stability(system, e1, e2):
    R = stability_region(system)
    verdict = stability(system, sk.IID([e1, e2])).stable
    assert R.contains(e1, e2) is verdict
    assert bool(R.conditions([e1, e2])) is verdict
    assert bool(R.conditions().subs(dict(zip(R.symbols, [sp.Rational(e1), sp.Rational(e2)])))) is verdict


@pytest.mark.parametrize("system", [TWO, TWO_BLOCKS])
@settings(max_examples=10, deadline=None)
@given(e1=st.fractions(min_value=0, max_value=1, max_denominator=40))
def test_region_boundary_is_the_critical_loss_of_sensor_two(system, e1):
    R = stability_region(system)
    crit = critical_loss_rate(system, system.sensor_names[1], others=[e1, 0])
    assert R.boundary_at(e1) == crit
    inside = [p for p in R.boundary() if p.lo < e1 < p.hi]
    if inside:
        assert AlgebraicNumber.from_expr(inside[0].expr.subs(R.symbols[0], sp.Rational(e1))) == crit


def test_region_boundary_needs_two_sensors():
    with pytest.raises(sk.SymkfError, match="2 sensors"):
        stability_region(THREE).boundary()


# -- symbolic loss parameters ------------------------------------------------------------
def test_symbolic_iid_conditions_match_stability():
    a, b, c = sp.symbols("a b c", nonnegative=True)
    cond = stability_conditions(THREE, sk.IID([a, b, c]))
    assert cond.free_symbols == {a, b, c}
    for vals in [("1/10", "1/5", "1/3"), ("1/2", "1/2", "1/2"), ("1/3", "1/4", "1/5"), ("1/16", 1, "1/2")]:
        subs = dict(zip((a, b, c), map(sp.Rational, vals)))
        assert bool(cond.subs(subs)) is stability(THREE, sk.IID(vals)).stable
    with pytest.raises(sk.SymkfError, match="stability_conditions"):
        stability(THREE, sk.IID([a, b, c]))


def test_symbolic_ge_conditions_match_stability():
    f, r = sp.symbols("f r", positive=True)
    cond = stability_conditions(TWO, sk.GilbertElliott([f, "1/3"], [r, "1/2"]))
    assert sp.Lt(4 * f * r + 4 * r ** 2 - 8 * r + 4, 1) in cond.args  # 16 (f r + (1-r)^2) (1/2)^2
    for fv, rv in [("1/4", "1/2"), ("1/10", "9/10"), ("1/2", "4/5"), ("1/20", "19/20")]:
        verdict = stability(TWO, sk.GilbertElliott([fv, "1/3"], [rv, "1/2"])).stable
        assert bool(cond.subs({f: sp.Rational(fv), r: sp.Rational(rv)})) is verdict


def test_numeric_conditions_are_decided_exactly():
    # 16 * (1/16) * 1 = 1 exactly: not stable, decided without floating point
    assert stability_conditions(TWO, sk.IID(["1/16", 1])) == sp.false
    assert stability_conditions(TWO, sk.IID(["1/17", 1])) == sp.true


# -- acceptance properties --------------------------------------------------------------
@settings(max_examples=6, deadline=None)
@given(st.sampled_from([(1, 4), (1, 3), (1, 6)]), st.sampled_from(["5/4", "3/2", 2]),
       st.lists(st.integers(-2, 2), min_size=2, max_size=2).filter(lambda v: v != [0, 0]))
def test_critical_loss_decreases_with_alpha(angle, scale, c):
    t = 2 * sp.pi * angle[0] / angle[1]
    R = sp.Matrix([[sp.cos(t), -sp.sin(t)], [sp.sin(t), sp.cos(t)]])
    sensors = [sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[c])]
    small = sk.System(A=exact(scale) * R, sensors=sensors)
    large = sk.System(A=exact(scale) * sp.Rational(11, 10) * R, sensors=sensors)
    assert critical_loss_rate(large) < critical_loss_rate(small)
    loss = sk.IID(["1/10", "1/10"])
    alpha_c = critical_alpha(small, loss)
    assert stability(small, loss).stable is (AlgebraicNumber.from_expr(exact(scale)) < alpha_c)


@settings(max_examples=10, deadline=None)
@given(st.lists(st.integers(-2, 2), min_size=2, max_size=2).filter(lambda v: v != [0, 0]),
       st.lists(st.sampled_from(["1/5", "1/3", "1/2", "2/3"]), min_size=4, max_size=4))
def test_adding_a_sensor_never_destabilises_markov(extra, params):
    A = [[0, -2], [2, 0]]
    base = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]])])
    more = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[extra])])
    one = stability(base, sk.GilbertElliott(params[:1], params[2:3]))
    two = stability(more, sk.GilbertElliott(params[:2], params[2:]))
    assert two.margins[0] <= one.margins[0]


def test_region_prints_and_renders_its_conditions():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    r = stability_region(S)
    # every single element is a hyperplane: receiving one element in a period of g = 2 is deficient
    assert str(r) == "stable iff (16*eps_s1*eps_s2**2 < 1) & (16*eps_s1**2*eps_s2 < 1)"
    assert r._repr_latex_().startswith("$\\text{stable iff }") and "\\wedge" in r._repr_latex_()


@pytest.mark.parametrize("power, k, sign, exponent, poly", [
    (630, 560, -1, sp.Rational(-9, 8), [-1, 0, 0, 0, 0, 0, 0, 0, 512]),  # 2^-630 = (2^-9)^70, 560 = 8 * 70
    (3, 2, 1, sp.Rational(3, 2), [-8, 0, 1]),                               # 2^3 is no square: x^2 - 8 as it is
    (6, 4, 1, sp.Rational(3, 2), [-8, 0, 1]),                               # 2^6 = 8^2: x^2 - 8, not x^4 - 64
])
def test_critical_value_roots_of_rational_powers(power, k, sign, exponent, poly):
    """A bound (alpha^power)^(sign/k) with alpha rational: the k-th root of a rational q-th power
    (q | k) is reduced before its polynomial is factored; the value and its minimal polynomial are
    those derived by hand."""
    import flint
    from symkf.exact.algebraic import AlgebraicNumber
    from symkf.engine.stability import _Bound
    got = _Bound(AlgebraicNumber.from_expr(2), power, 1, k, sign).value()
    assert sp.simplify(got.exact - sp.Integer(2) ** exponent) == 0
    assert got._poly == flint.fmpz_poly(poly)
