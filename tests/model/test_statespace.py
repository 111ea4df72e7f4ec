"""The python-control bridge (symkf.model.statespace): System.from_statespace / to_statespace (the
actuators as the columns of B), and at zero loss symkf's Riccati limit against control.dlqe."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.errors import ExtraNotInstalledError, InexactInputError, InputError, ShapeError
from symkf.numeric.filters import predicted_covariances
from symkf.model.statespace import float_matrix

ct = pytest.importorskip("control")


def _riccati_limit(S: sk.System, horizon: int = 400) -> np.ndarray:
    """P_{K|K-1} of symkf's filter with every packet received (zero loss), K = horizon."""
    return predicted_covariances(S, np.ones((1, horizon, S.d), dtype=np.int8), keep="last")[0]


def test_scalar_riccati_limit_is_the_hand_derived_root():
    # A = 2, C = Q = R = 1: P = A^2 P - A^2 P^2 / (P + R) + Q = 4P/(P + 1) + 1, so
    # P^2 - 4P - 1 = 0 and P = 2 + sqrt(5) (the positive root)
    S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]], name="s")])
    _, P, _ = ct.dlqe(*(S.to_statespace().A, np.eye(1), S.to_statespace().C, np.eye(1), np.eye(1)))
    exact = float(2 + sp.sqrt(5))
    assert P[0, 0] == pytest.approx(exact, rel=1e-12)
    assert _riccati_limit(S)[0, 0] == pytest.approx(exact, rel=1e-12)


def test_zero_loss_riccati_limit_equals_dlqe_for_two_sensors():
    S = sk.System(A=[["11/10", 1], [0, "-3/2"]], Q=[[2, 1], [1, 1]],
                  sensors=[sk.Sensor(C=[[1, 0]], R=[["1/2"]], name="pos"),
                           sk.Sensor(C=[[1, 1], [0, 1]], R=[[1, 0], [0, 3]], name="pair")])
    plant = S.to_statespace()
    Q = float_matrix(S.Q, "Q")
    R = float_matrix(S.R, "R")
    _, P, _ = ct.dlqe(plant.A, np.eye(2), plant.C, Q, R)
    np.testing.assert_allclose(_riccati_limit(S), P, rtol=1e-10)
    assert plant.output_labels == ["pos", "pair[0]", "pair[1]"]


def test_round_trip_is_exact_for_dyadic_entries():
    # 1/2, 3, -1, 5/4 are exact in binary, so their float64 copies are read back exactly, without
    # rationalize and without a warning
    S = sk.System(A=[["1/2", 3], [-1, "5/4"]],
                  sensors=[sk.Sensor(C=[[1, 0]], name="a"), sk.Sensor(C=[[0, 2], [1, 1]], name="b")])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = sk.System.from_statespace(S.to_statespace(), {"a": [0], "b": [1, 2]})
    assert back.A == S.A and back.sensor_names == ("a", "b")
    assert [s.C for s in back.sensors] == [s.C for s in S.sensors]


def test_floats_are_refused_unless_rationalized():
    plant = ct.ss([[0.1, 0], [0, 2]], [[1], [0]], [[1, 1]], 0, dt=0.5)
    # 1.0, 2.0 and 0.5 are exact in binary; 0.1 is not, and is named
    with pytest.raises(InexactInputError, match=r"A\[0\]\[0\]: the float 0.1 is not exact"):
        sk.System.from_statespace(plant)
    with pytest.warns(UserWarning):
        S = sk.System.from_statespace(plant, rationalize=True)
    assert S.A[0, 0] == sp.Rational(1, 10)   # the float's shortest repr, as everywhere in symkf
    assert S.sensor_names == ("y[0]",)


def test_sensor_splits_and_their_errors():
    plant = ct.ss([[2, 0], [0, 3]], [[1], [1]], [[1, 0], [0, 1], [1, 1]], 0, dt=True)  # integer floats: exact
    assert sk.System.from_statespace(plant, ["x", "y", "z"]).sensor_names == ("x", "y", "z")
    S = sk.System.from_statespace(plant, {"u": [0, 2], "v": [1]}, R={"v": [[2]]})
    assert S.sensors[0].C.tolist() == [[1, 0], [1, 1]] and S.sensors[1].R.tolist() == [[2]]
    with pytest.raises(ShapeError, match="2 names for the 3 rows"):
        sk.System.from_statespace(plant, ["x", "y"], rationalize=True)
    with pytest.raises(InputError, match="every row 0..2 must belong to exactly one sensor"):
        sk.System.from_statespace(plant, {"u": [0, 1], "v": [1, 2]}, rationalize=True)
    with pytest.raises(InputError, match="R: no sensor named 'w'"):
        sk.System.from_statespace(plant, ["x", "y", "z"], R={"w": [[1]]}, rationalize=True)
    with pytest.raises(InputError, match="discrete-time"):
        sk.System.from_statespace(ct.ss([[2]], [[1]], [[1]], 0), rationalize=True)


def test_complex_systems_are_refused_by_to_statespace():
    S = sk.System(A=[["2*I"]], sensors=[sk.Sensor(C=[[1]])])
    with pytest.raises(InputError, match="A: complex entries"):
        S.to_statespace()


def test_missing_control_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "control", None)
    S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])])
    with pytest.raises(ExtraNotInstalledError, match=r"pip install 'symkf\[control\]'"):
        S.to_statespace()


QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])


def test_statespace_has_sampling_time_one_and_says_there_is_no_input():
    pytest.importorskip("control")
    G = QUARTER_TURN.to_statespace()
    assert G.dt == 1 and G.input_labels == ["no_input"] and not G.B.any()


LOOP = sk.System(A=[["1/2", 3], [-1, "5/4"]], sensors=[sk.Sensor(C=[[1, 0]], name="y"), sk.Sensor(C=[[0, 2]], name="z")],
                 actuators=[sk.Actuator(B=[["1/4"], [0]], name="u"), sk.Actuator(B=[[-1], [2]], name="v")])


def test_actuators_round_trip_through_a_statespace_as_its_input_columns():
    G = LOOP.to_statespace()
    assert G.input_labels == ["u", "v"] and G.output_labels == ["y", "z"]
    np.testing.assert_array_equal(G.B, [[0.25, -1], [0, 2]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")                       # dyadic entries: exact without a warning
        back = sk.System.from_statespace(G, rationalize=True)
    assert (back.A, back.C, back.B) == (LOOP.A, LOOP.C, LOOP.B)
    assert (back.sensor_names, back.actuator_names) == (LOOP.sensor_names, LOOP.actuator_names)
    # no actuator: the "no_input" column that does not act gives none back
    assert sk.System.from_statespace(QUARTER_TURN.to_statespace()).actuators == ()


def test_actuator_splits_weights_and_their_errors():
    plant = ct.ss([[2, 0], [0, 3]], [[1, 0, 1], [0, 1, 1]], [[1, 1]], 0, dt=True)   # inputs u[0], u[1], u[2]
    assert sk.System.from_statespace(plant).actuator_names == ("u[0]", "u[1]", "u[2]")
    S = sk.System.from_statespace(plant, None, {"arm": [0, 1], "w": [2]}, U={"arm": [[2, 0], [0, 3]]}, W=[[1, 0], [0, 0]])
    assert S.actuators[0].B == sp.eye(2) and S.actuators[0].U == sp.diag(2, 3) and S.actuators[1].U == sp.eye(1)
    assert S.W == sp.diag(1, 0)
    G = S.to_statespace()
    assert G.input_labels == ["arm[0]", "arm[1]", "w"]
    with pytest.raises(ShapeError, match="actuators: 2 names for the 3 columns of B"):
        sk.System.from_statespace(plant, None, ["a", "b"])
    with pytest.raises(InputError, match="every column 0..2 must belong to exactly one actuator"):
        sk.System.from_statespace(plant, None, {"a": [0, 1], "b": [1, 2]})
    with pytest.raises(InputError, match="U: no actuator named 'x'"):
        sk.System.from_statespace(plant, U={"x": [[1]]})
    with pytest.raises(InputError, match=r"from_statespace.*actuators"):   # checked at the boundary
        sk.System.from_statespace(plant, None, {"a": "0"})
