"""Upgrades and active constraints (symkf.design.improvement) against values by hand and the
critical rate along the ray."""

import time

import sympy as sp

import symkf as sk

from conftest import period_24_block, refused_within
from test_selection import three_sensors


def test_upgrade_values_of_three_sensors():
    u = sk.design.upgrades(three_sensors())
    assert u.base.exact == sp.Rational(1, 2)
    # a tenth fewer of c's losses: 16 (9/10)^2 eps^4 < 1 on the decisive lines; of a's: 16 (9/10) eps^4 < 1
    third = sp.Rational(72, 5) ** sp.Rational(-1, 4)
    assert [(x.sensor, x.elasticity, x.improved.exact) for x in u.ranked] == [
        ("c", sp.Rational(1, 2), sp.sqrt(10) / 6), ("a", sp.Rational(1, 4), third), ("b", sp.Rational(1, 4), third)]
    assert all(x.lossless.exact == 1 for x in u.ranked)   # any one sensor alone sees both directions


def test_the_curve_starts_at_the_base_rate_and_rises_at_the_elasticity():
    u = sk.design.upgrades(three_sensors())
    for x in u.ranked:
        assert x.critical_at(1) == u.base and x.critical_at(0) == x.lossless
        t = sp.Rational(999_999, 1_000_000)
        slope = (sp.log(x.critical_at(t).exact) - sp.log(u.base.exact)) / sp.log(1 / t)
        assert abs(float(slope.evalf(30)) - float(x.elasticity)) < 1e-5


def test_active_constraints_name_the_limiting_sensors():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    (c,) = sk.design.active_constraints(S, sk.IID(["1/10", "1/10"]))
    # the decisive line holds s1's phase-1 element only: one of s1's two phases and both of s2's lost
    assert c.outside == (("s1", 1), ("s2", 2)) and c.margin.exact == sp.sqrt(10) / 25
    assert c.words.startswith("sensors s1 and s2 together limit block 0")
    html = sk.design.active_constraints(S, sk.IID(["1/10", "1/10"]))._repr_html_()
    assert "<td>0</td><td>2</td><td>2</td><td>0.1265</td><td>s1 1, s2 2</td>" in html   # margin sqrt(10)/25


def test_front_and_upgrades_render_in_a_notebook():
    S = three_sensors()
    assert sk.design.pareto_front(S)._repr_latex_().count(r"\\") >= 3
    assert sk.design.upgrades(S)._repr_latex_().startswith(r"$\varepsilon_c = \frac{1}{2}")


def test_upgrades_of_64_sensors_are_refused_by_their_price():
    # 129 critical rates, each a search growing about as d^2: 264 CPU-s estimated, above max_work
    S = period_24_block(64)
    refused_within(2, r"upgrades: .*129 critical i.i.d. loss rates of 64 sensors.*max_work", lambda: sk.design.upgrades(S))


def test_the_upgrades_estimate_is_within_4x_of_their_cost():
    # 8 sensors: 17 critical rates, 0.54 CPU-s estimated
    S = period_24_block(8)
    estimate = sk.budget.seconds(ray_query=17 * 64)
    start = time.process_time()
    u = sk.design.upgrades(S)
    measured = time.process_time() - start
    assert len(u.ranked) == 8 and all(x.improved >= u.base for x in u.ranked)
    assert measured / 4 < estimate < 4 * measured   # 3x in fresh processes (docs/caps.md); 4x beside other tests
