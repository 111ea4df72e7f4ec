"""The reproduce entries of the control side: every check holds."""

from __future__ import annotations

import pytest

from symkf.control.reproduce import reproduce_schenato_closed_forms, reproduce_schenato_scalar


def test_scalar_entry_checks_hold_with_the_loop_simulated_on_both_sides(tmp_path):
    rep = reproduce_schenato_scalar(str(tmp_path), paths=5000, horizon=90)
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
