"""TCP-like control over one Gilbert-Elliott channel: certificates and the burst obstruction."""

from __future__ import annotations

import pytest
import sympy as sp

import symkf as sk
from symkf.control import control_stabilizable
from symkf.errors import AssumptionError

R = sp.Rational


@pytest.fixture
def scalar():
    return sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])


@pytest.mark.parametrize("fail", ["1/10", "1/2", "9/10"])
def test_scalar_plant_needs_recovery_above_one_minus_inverse_square_whatever_the_failure_rate(scalar, fail):
    # a burst of L lost commands multiplies E[x^2] by 4^L; a received one can zero the state:
    # bounded iff (1 - q) 4 < 1, q > 3/4, for every fail rate
    assert control_stabilizable(scalar, sk.GilbertElliott(fail=[fail], recover=["4/5"]))[0] is True
    stable, reason = control_stabilizable(scalar, sk.GilbertElliott(fail=[fail], recover=["3/4"]))
    assert stable is False and "(1 - recover) rho(A)^2 = 1" in reason


def test_two_modes_one_input_decided_at_both_ends_and_open_between():
    S = sk.System(A=[[2, 1], [0, 3]], sensors=[sk.Sensor(C=[[1, 0]])], actuators=[sk.Actuator(B=[[0], [1]])])
    assert control_stabilizable(S, sk.GilbertElliott(fail=["1/10"], recover=["1/2"]))[0] is False
    assert control_stabilizable(S, sk.GilbertElliott(fail=["1/10"], recover=["999/1000"]))[0] is True
    # the coupled Riccati recursion diverges here (q below its threshold near 0.997 at f = 1/10), yet the
    # burst bound (1 - q) 9 < 1 cannot prove it: undecided, never a wrong answer
    stable, reason = control_stabilizable(S, sk.GilbertElliott(fail=["1/10"], recover=["98/100"]))
    assert stable is None and reason.startswith("undecided")


def test_per_actuator_markov_channels_are_refused_with_the_reason():
    S = sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 1]])],
                  actuators=[sk.Actuator(B=[[1], [0]]), sk.Actuator(B=[[0], [1]])])
    with pytest.raises(AssumptionError, match="Markov jump linear system"):
        control_stabilizable(S, sk.GilbertElliott(fail=["1/10", "1/10"], recover=["1/2", "1/2"]))
