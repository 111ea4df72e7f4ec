"""The reproduce entries of the control side: every check holds."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import pytest
import sympy as sp

from symkf.control import critical_arrival_rate
from symkf.control.reproduce import (_lmi_point, _mare_root, _udp_mixture, reproduce_schenato_claims,
                                     reproduce_schenato_closed_forms, reproduce_schenato_scalar, scalar_plant)


def test_scalar_entry_checks_hold_with_the_loop_simulated_on_both_sides(tmp_path):
    rep = reproduce_schenato_scalar(str(tmp_path), paths=1000, horizon=60)
    assert rep["checks"] and all(rep["checks"].values()), rep["checks"]
    assert [p["outcome"] for p in rep["results"]["tcp_simulation"]] == ["consistent"] * 4
    assert rep["results"]["udp_boundary"]["9/10"] == "9/11" and (tmp_path / "schenato_scalar_regions.png").exists()


def test_closed_form_entry_checks_hold():
    rep = reproduce_schenato_closed_forms(simulate=False)
    assert len(rep["checks"]) == 4 and all(rep["checks"].values()), rep["checks"]


@pytest.mark.full
def test_closed_form_entry_checks_hold_with_the_loop_simulated():
    rep = reproduce_schenato_closed_forms(paths=8000, horizon=90)
    assert all(rep["checks"].values()), rep["checks"]


def test_claims_entry_checks_hold_and_lists_four_misstatements_of_the_secondary_source():
    rep = reproduce_schenato_claims()
    assert len(rep["checks"]) == 8 and all(rep["checks"].values()), rep["checks"]
    assert [d["printed"] for d in rep["discrepancies"]] == [
        "bounded at theta_bar = theta_c", "a minimum (attained)", "unbounded above theta_c", "the upper bound in (3)"]
    assert "could not be read" in rep["results"]["not_compared"]
    assert {k: v["theta_c"] for k, v in rep["results"]["fully_observed_theta_c"].items()} == {
        "diag(2, 3)": "8/9", "diag(2, 3, 5)": "24/25", "2R(pi/3)": "3/4", "a = 2": "3/4"}


def test_scalar_control_mare_has_a_positive_root_only_above_three_quarters():
    # (3 - 16/5) S^2 + 4 S + 1 = 0 is S^2 - 20 S - 5 = 0 at nu = 4/5; at 3/4 it is 4 S + 1 = 0
    assert _mare_root(sp.Rational(4, 5)) == 10 + sp.sqrt(105)
    assert _mare_root(sp.Rational(3, 4)) is None and _mare_root(sp.Rational(1, 2)) is None


def test_theorem2_lmi_holds_at_the_certified_rate_and_fails_below_the_threshold():
    S = scalar_plant()
    t = critical_arrival_rate(S)
    assert _lmi_point(S, t) == {"nu": "1500000000001/2000000000000", "psi_positive_definite": True,
                                "Y_below_I": True}
    # the same (Y, Z) at nu = 7/10 < nu_c = 3/4: no point is feasible there
    assert _lmi_point(S, dataclasses.replace(t, upper=Fraction(7, 10)))["psi_positive_definite"] is False


def test_udp_posterior_mean_is_nonlinear_in_the_measurement_unless_noiseless():
    mix = _udp_mixture()
    assert mix["dw"] == mix["mean"] == mix["variance"] == mix["curvature_formula"] == 0
    # r d^3 nu (1 - nu)(1 - 2 nu)/(p + r)^3 at d = p = r = 1, nu = 9/10: (9/10)(1/10)(-8/10)/8
    assert mix["curvature_9/10"] == sp.Rational(-9, 1000) and mix["curvature_noiseless"] == 0
