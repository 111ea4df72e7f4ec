"""Stability regions in the loss parameters (symkf.engine.region; Sui-You-Fu Theorems 4 and 7 with
eq. 36): the two-sensor region and its boundary by hand, against the verdict at drawn points,
against the critical loss rate of one sensor; symbolic i.i.d. and Gilbert-Elliott conditions
against the verdict, numeric ones decided exactly."""

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf.engine.region import stability_conditions, stability_region
from symkf.engine.stability import critical_loss_rate, stability
from symkf.exact.algebraic import AlgebraicNumber

TWO = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])
TWO_BLOCKS = sk.System(A=[["5/4", 0, 0], [0, 0, "-6/5"], [0, "6/5", 0]],
                       sensors=[sk.Sensor(C=[[1, 1, 0]]), sk.Sensor(C=[[0, 1, 1]])])
THREE = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]]),
                                                 sk.Sensor(C=[[1, 2]])])
rationals = st.fractions(min_value=0, max_value=1, max_denominator=12)


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


def test_region_prints_and_renders_its_conditions():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    r = stability_region(S)
    # every single element is a hyperplane: receiving one element in a period of g = 2 is deficient
    assert str(r) == "stable iff (16*eps_s1*eps_s2**2 < 1) & (16*eps_s1**2*eps_s2 < 1)"
    assert r._repr_latex_().startswith("$\\text{stable iff }") and "\\wedge" in r._repr_latex_()


# -- conditions in the symbols of the loss parameters --------------------------------------------

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


def test_simplest_refuses_an_empty_interval():
    from fractions import Fraction
    from symkf.engine.region import simplest
    with pytest.raises(sk.SymkfError, match=r"the interval \(1, 1/3\) is empty"):
        simplest(Fraction(1), Fraction(1, 3))   # looped forever
    assert simplest(Fraction(1, 3), Fraction(1, 2)) == Fraction(2, 5)
