"""Theorem 1 of Quevedo, Ahlén, Johansson against the exact engine (symkf.network.compare): critical parameters over symkf.network.compare.FAMILY."""

import runpy
import sys

import pytest
import sympy as sp

from symkf.exact.algebraic import AlgebraicNumber
from symkf.network.compare import FAMILY, compare, critical, describe, example, markdown_table, t
from symkf.engine.stability import stability
from conftest import ROOT

R = sp.Rational


@pytest.fixture(scope="module")
def table():
    return {ex.name: compare(ex) for ex in FAMILY}


def _set(c, which):
    return tuple((a.exact, b.exact) for a, b in getattr(c, which))


def test_family_has_at_least_five_rows_with_both_sides_computed(table):
    assert len(table) >= 5
    assert sum(1 for c in table.values() if critical(c.exact) is not None) >= 5


@pytest.mark.parametrize("name", [ex.name for ex in FAMILY])
def test_theorem1_region_inside_exact_region(table, name):
    """Theorem 1 is sufficient: where it holds the exact engine must say stable."""
    c = table[name]
    assert c.sufficient_inside_exact
    for lo, hi in c.theorem1:  # and pointwise at the midpoint of each Theorem 1 interval
        mid = (sp.Rational(lo.interval[0]) + sp.Rational(hi.interval[1])) / 2
        assert stability(c.example.system, c.example.at(mid)).stable


@pytest.mark.parametrize("name", [ex.name for ex in FAMILY])
def test_theorem2_with_unit_holding_times_is_theorem1(table, name):
    """Sec. VII-B: with q = p and psi_j(1) = 1 condition (32) reduces to (22)."""
    assert _set(table[name], "theorem2") == _set(table[name], "theorem1")


def test_iid_scalar_critical_is_one_minus_one_over_a_squared(table):
    # a = 2, i.i.d. success t: exact margin a^2 (1 - t) (Sui-You-Fu, d = 1), Corollary 1 the same: tight
    c = table["iid-scalar"]
    assert _set(c, "exact") == ((R(3, 4), 1),) == _set(c, "theorem1")


def test_gilbert_elliott_scalar_hand_derived(table):
    # a = 3/2, phi = (1, 0): exact margin a^2 p22 (a loss burst continues w.p. p22);
    # Corollary 1 / Sec. VI: a^2 max(p12, p22) < 1.
    fail = table["ge-scalar-fail"]            # p22 = 1/3: a^2/3 = 3/4 < 1 for every p12
    assert _set(fail, "exact") == ((0, 1),)
    assert _set(fail, "theorem1") == ((0, R(4, 9)),)
    stay = table["ge-scalar-stay"]            # p12 = 1/2: a^2/2 = 9/8, Theorem 1 never holds
    assert _set(stay, "exact") == ((0, R(4, 9)),)
    assert stay.theorem1 == ()


def test_norm_versus_spectral_radius(table):
    # A = [[1, 1], [0, 6/5]], C = I: exact p22 < 1/(6/5)^2 = 25/36; Theorem 1 p22 < 1/||A||^2
    c = table["ge-norm-vs-radius"]
    assert _set(c, "exact") == ((0, R(25, 36)),)
    x = sp.Symbol("x")
    G = sp.Matrix([[1, 1], [0, R(6, 5)]])
    norm2 = max(sp.solve((G.T * G).charpoly(x).as_expr(), x), key=lambda r: float(r))
    assert critical(c.theorem1) == AlgebraicNumber.from_expr(1 / norm2)


def test_fading_scalar_hand_derived(table):
    # a^2 = 9/4, P = [[9/10, 1/10], [1/2, 1/2]], phi = (9/10, t), x = 1 - t.
    # Theorem 1: state 2 binds, 9/4 (1/20 + x/2) < 1  <=>  t > 19/90.
    # Exact: lost-lost transfer [[9/100, x/10], [1/20, x/2]]; det(I - 9/4 M) = 319/400 - 2952 x/3200 = 0
    # <=> x = 319/369, t = 50/369.
    c = table["fading-scalar"]
    assert _set(c, "theorem1") == ((R(19, 90), 1),)
    assert _set(c, "exact") == ((R(50, 369), 1),)


def test_viic_plant_theorem1_never_applies(table):
    # C1 = [1 1] has rank 1 < 2: nu_i = 1 and Theorem 1 never holds (Remark 4); exact: the 5/4 block
    # with i.i.d. success t is stable iff (25/16)(1 - t) < 1, t > 9/25; with the sticky chain
    # det(I - 25/16 [[9/100, x/10], [1/100, 9x/10]]) = 55/64 - 2480 x/2048 = 0 gives t = 9/31.
    assert table["viic-plant-iid"].theorem1 == table["viic-plant-markov"].theorem1 == ()
    assert _set(table["viic-plant-iid"], "exact") == ((R(9, 25), 1),)
    assert _set(table["viic-plant-markov"], "exact") == ((R(9, 31), 1),)


@pytest.mark.parametrize("name, value", [("fading-scalar", R(50, 369)), ("viic-plant-markov", R(9, 31)),
                                         ("ge-scalar-stay", R(4, 9))])
def test_exact_critical_value_has_margin_one(name, value):
    """At the critical parameter the engine's largest margin is exactly 1 (not stable); just inside it is stable."""
    ex = example(name)
    v = stability(ex.system, ex.at(value))
    assert not v.stable and max(v.margins) == 1
    inside = value + R(1, 10 ** 6) if describe(compare(ex).exact).startswith("t >") else value - R(1, 10 ** 6)
    assert stability(ex.system, ex.at(inside)).stable


def test_irrational_critical_values_are_roots_of_the_candidate_polynomials(table):
    for name in ("relay-rotation", "example3-tree"):
        c = table[name]
        e, s = critical(c.exact), critical(c.theorem1)
        assert not e.is_rational and e in c.candidates
        assert s > e                              # strictly conservative on these rows
        lo, hi = e.refine(R(1, 10 ** 9)).interval
        assert not stability(c.example.system, c.example.at(sp.Rational(lo))).stable
        assert stability(c.example.system, c.example.at(sp.Rational(hi))).stable


def test_markdown_table_rows(table):
    md = markdown_table([table["iid-scalar"], table["fading-scalar"], table["ge-scalar-stay"]])
    lines = md.splitlines()
    assert len(lines) == 5
    assert "| iid-scalar | phi_{1\\|1} | t > 3/4 | t > 3/4 | t > 3/4 | 3/4 / 3/4 | 0 | 1.0000 | yes |" == lines[2]
    assert "| 19/90 / 50/369 |" in lines[3]
    assert "| never | never | t < 4/9 | - / 4/9 |" in lines[4]


def test_example_script_prints_the_table(capsys, monkeypatch):
    path = ROOT / "examples" / "quevedo_compare.py"
    monkeypatch.setattr(sys, "argv", [str(path), "iid-scalar", "ge-scalar-stay"])
    runpy.run_path(str(path), run_name="__main__")
    out = capsys.readouterr().out
    assert "| iid-scalar |" in out and "| ge-scalar-stay |" in out and "| fading-scalar |" not in out


def test_parameter_symbol_is_the_one_in_the_models():
    assert t in example("fading-scalar").loss.phi.free_symbols
    assert t in example("ge-scalar-stay").loss.state.P.free_symbols
    # NetworkLoss.subs substitutes into the network state too (transition probabilities, initial law)
    sub = example("ge-scalar-stay").loss.subs({t: R(1, 3)})
    assert sub.state.P == sp.Matrix([[R(1, 2), R(1, 2)], [R(2, 3), R(1, 3)]])
    assert sub.state.initial == sp.Matrix([[R(4, 7), R(3, 7)]])


def test_relay_and_example3_hand_derived(table):
    # relay-rotation: ||A||^2 = 4, r = 1 iff both links succeed (S2 is relayed by S1), so
    # nu_2 = (1/2)(19/100) + (1/2)(1 - t^2) and 4 nu_2 < 1 <=> t > sqrt(69)/10 (nu_1 binds later).
    assert critical(table["relay-rotation"].theorem1) == AlgebraicNumber.from_expr(sp.sqrt(69) / 10)
    # example3-tree: only the 2-block matters; nothing reaches the gateway iff E1 and E2 both fail,
    # y = (1 - t)^2: det(I - 4 [[9/4000, y/10], [3/4000, 7y/10]]) = 991/1000 - 2776 y/1000.
    e = critical(table["example3-tree"].exact)
    assert e == AlgebraicNumber.from_expr(1 - sp.sqrt(R(991, 2776)))


def test_identically_vanishing_determinant_is_refused():
    # a = 3/2, p22 = 4/9: the margin a^2 p22 is 1 for every p12 = t, so no root marks a boundary
    from symkf.errors import AssumptionError
    from symkf.network.compare import NetworkExample, exact_candidates
    ex = NetworkExample("flat", "stated", "p12", [[R(3, 2)]], [[[1]]], [0],
                        [[1 - t, t], [R(5, 9), R(4, 9)]], [[1, 0]])
    with pytest.raises(AssumptionError, match="vanishes identically"):
        exact_candidates(ex)
    assert max(stability(ex.system, ex.at(R(1, 3))).margins) == 1
