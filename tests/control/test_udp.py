"""UDP-like results: the scalar noiseless region and the rows' hypotheses."""

from __future__ import annotations

import pytest
import sympy as sp

import symkf as sk
from symkf.control import udp_region, udp_threshold
from symkf.errors import InputError

R = sp.Rational


def test_udp_threshold_meets_tcp_at_perfect_observations():
    assert udp_threshold(2, 1) == R(3, 4) and udp_threshold(3, 1) == R(8, 9)


def test_udp_threshold_by_hand():
    # a = 2, gamma = 9/10: 9/10 * 3 / (4 - 1/10 * 7) = 27/33
    assert udp_threshold(2, R(9, 10)) == R(9, 11)


def test_udp_threshold_rises_to_one_at_the_estimation_threshold():
    assert udp_threshold(2, R(3, 4) + R(1, 10 ** 6)) > R(99, 100)
    with pytest.raises(InputError, match="1 - 1/a\\^2"):
        udp_threshold(2, R(3, 4))


def test_rows_for_scalar_plant():
    S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])
    exact = udp_region(S, noiseless=True)
    assert [r.status for r in exact.rows] == ["outer bound", "exact", "exact"]
    assert [r.status for r in udp_region(S).rows] == ["outer bound", "outer bound", "outer bound"]


def test_rows_without_invertible_c_do_not_apply():
    S = sk.System(A=[[2, 1], [0, 3]], sensors=[sk.Sensor(C=[[1, 0]])], actuators=[sk.Actuator(B=[[0], [1]])])
    rows = udp_region(S, noiseless=True).rows
    assert [r.status for r in rows] == ["outer bound", "does not apply", "does not apply"]
    assert "nonlinear" in rows[2].statement
