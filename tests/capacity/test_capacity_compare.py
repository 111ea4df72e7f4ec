"""Capacity conditions against exact critical loss rates (symkf.capacity.compare): which
conditions are tight on systems whose critical rate is derived by hand, Theorem 5's row orders
capped, an inconsistent engine value flagged."""

from __future__ import annotations

import sympy as sp

from symkf import IID, Sensor, System, budget
from symkf.capacity import comparison_table, critical_loss_comparison, verdict_comparison
from symkf.capacity.compare import theorem5_common_threshold

R = sp.Rational
ROTATION = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])], name="rotation")
LOWER_TRI = System(A=[[R(5, 4), 0], [1, R(11, 10)]], sensors=[Sensor(C=[[1, 1]])], name="lower-tri")
FULL_C = System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=[[1, 0], [0, 1]])], name="full C")
SCALAR2 = System(A=[[2]], sensors=[Sensor(C=[[1]]), Sensor(C=[[1]])], name="scalar x2")


def test_comparison_against_hand_derived_critical_rates():
    rows = [critical_loss_comparison(S, eps) for S, eps in
            ((ROTATION, R(1, 16)), (LOWER_TRI, R(16, 25)), (FULL_C, R(1, 9)), (SCALAR2, R(1, 2)))]
    tight = [(r["tight_ln_rho"], r["tight_entropy"], r["tight_theorem5"]) for r in rows]
    assert tight == [(False, True, True), (True, False, False), (True, False, True), (True, True, False)]
    assert all(r["consistent"] for r in rows)
    assert rows[3]["theorem5"]["exact"] == "1/4"
    table = comparison_table(rows)
    assert table.count("\n") == 5 and "64/121" in table
    v = verdict_comparison(SCALAR2, IID(["1/10", "9/10"]), exact_stable=True)  # 4 * 9/100 < 1
    assert v["consistent"] and v["C_gt_ln_rho"] and v["theorem5_per_sensor"] is True


def test_theorem5_row_orders_are_capped_by_max_order_rows():
    """FULL_C (A = [[2, 1], [0, 3]], C = I): in the given row order the first row e1 observes all
    of A, one Wonham block of Mahler measure 2 * 3 (common threshold 1/36); in the other order
    e2 observes the eigenvalue 3 alone and the blocks are [3], [2] (largest 3: 1/9 = eps*).
    With max_order_rows = 1 < 2 rows only the given order is tried."""
    assert theorem5_common_threshold(FULL_C) == R(1, 9)
    with budget.limits(max_order_rows=1):
        assert theorem5_common_threshold(FULL_C) == R(1, 36)
    with budget.limits(max_order_rows=2):
        assert theorem5_common_threshold(FULL_C) == R(1, 9)


def test_inconsistent_engine_value_is_flagged():
    assert not critical_loss_comparison(ROTATION, R(1, 2))["consistent"]          # above 1/rho^2 = 1/4
