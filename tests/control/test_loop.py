"""The TCP-like loop: the region over (observation, control) arrival rates and the loop's verdict."""

from __future__ import annotations

import pytest
import sympy as sp

import symkf as sk
from symkf.control import lqg_stable, tcp_region
from symkf.errors import AssumptionError, InputError

R = sp.Rational


@pytest.fixture
def scalar():
    return sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])


@pytest.fixture
def two_modes():
    """diag(2, 3), one sensor seeing both, one actuator per mode (independent channels)."""
    return sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 1]])],
                     actuators=[sk.Actuator(B=[[1], [0]], name="u2"), sk.Actuator(B=[[0], [1]], name="u3")])


def test_scalar_region_is_the_square_of_one_minus_inverse_square(scalar):
    r = tcp_region(scalar)
    assert r.gamma_c == R(3, 4) and r.nu_c.exact == R(3, 4)
    assert r.contains("4/5", "4/5") is True
    assert r.contains("3/4", "4/5") is False and r.contains("4/5", "3/4") is False


def test_region_answers_none_inside_an_open_bracket():
    S = sk.System(A=sp.diag(2, 3, 5), sensors=[sk.Sensor(C=sp.eye(3))],
                  actuators=[sk.Actuator(B=[[1, 0], [0, 1], [1, 1]])])
    r = tcp_region(S, "1e-6")
    inside = R(29, 30) + R(1, 10 ** 7)
    assert r.contains(1, inside) is None and r.contains(1, R(29, 30)) is False and r.contains(1, 1) is True


def test_loop_is_bounded_iff_both_sides_are(scalar):
    assert lqg_stable(scalar, sk.IID(loss=["1/10"]), sk.IID(loss=["1/10"])).stable is True
    control_fails = lqg_stable(scalar, sk.IID(loss=["1/10"]), sk.IID(loss=["3/10"]))
    assert control_fails.stable is False and control_fails.estimation.stable
    estimation_fails = lqg_stable(scalar, sk.IID(loss=["3/10"]), sk.IID(loss=["1/10"]))
    assert estimation_fails.stable is False and estimation_fails.control is True


def test_estimator_side_takes_any_loss_model(scalar):
    # Gilbert-Elliott sensor channel: the engine's exact verdict decides the estimator side
    v = lqg_stable(scalar, sk.GilbertElliott(fail=["1/10"], recover=["9/10"]), sk.IID(loss=["1/10"]))
    assert v.estimation.stable and v.stable is True


def test_mode_reached_by_one_lossy_actuator_alone_is_not_stabilizable(two_modes):
    v = lqg_stable(two_modes, sk.IID(loss=["1/100"]), sk.IID(loss=["1/100", "1/5"]))
    assert v.control is False and "u3 alone" in v.control_reason and "8/9" in v.control_reason


def test_independent_channels_decided_by_the_dual_lmi(two_modes):
    pytest.importorskip("cvxpy")
    v = lqg_stable(two_modes, sk.IID(loss=["1/100"]), sk.IID(loss=["1/100", "1/100"]))
    assert v.control is True and "verified exactly" in v.control_reason


def test_markov_control_channels_are_refused_naming_the_missing_result(scalar):
    with pytest.raises(AssumptionError, match="Markov jump"):
        lqg_stable(scalar, sk.IID(loss=["1/10"]), sk.GilbertElliott(fail=["1/10"], recover=["1/2"]))


def test_wrong_number_of_actuator_channels_is_refused(scalar):
    with pytest.raises(InputError, match="2 channels for 1 actuators"):
        lqg_stable(scalar, sk.IID(loss=["1/10"]), sk.IID(loss=["1/10", "1/10"]))
