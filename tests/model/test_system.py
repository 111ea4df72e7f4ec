"""Systems, sensors and actuators (symkf.model.system): exact entries, named errors, detectability
and stabilizability.

A system is built from exact data only (floats with ``rationalize=``, warning at the caller's
line); every refusal names the entry and the error type; undetectable pairs name the mode, and
so do pairs (A, B) that no actuator stabilizes; size caps (sensors, actuators, dimension) are
checked before anything is built; systems, verdicts and errors pickle exactly."""

from __future__ import annotations

import itertools
import json
import re
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.errors import (
    BudgetError,
    InexactInputError,
    NotPositiveDefiniteError,
    ShapeError,
    SymkfError,
    UncontrollableError,
    UnobservableError,
)
from symkf.exact.algebraic import AlgebraicNumber
from symkf.exact.spectral import eigen_blocks
from symkf.io import files

R = sp.Rational


def test_bad_inputs_raise_named_errors():
    (cv,) = eigen_blocks([[1, 1], [0, 1]])  # constant velocity: one Jordan chain, accepted
    assert cv.defective and cv.members[0].geometric == 1 and cv.members[0].multiplicity == 2
    with pytest.raises(InexactInputError, match=r"A\[0\]\[1\].*'1/10'"):
        sk.System(A=[[1, 0.1], [0, 1]], sensors=[sk.Sensor(C=[[1, 0]])])
    with pytest.raises(ShapeError, match="A: must be square"):
        sk.System(A=[[1, 0, 0], [0, 1, 0]], sensors=[sk.Sensor(C=[[1, 0, 0]])])
    with pytest.raises(UnobservableError, match="eigenvalue 3"):
        sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 0]])])
    with pytest.raises(NotPositiveDefiniteError, match="R"):
        sk.Sensor(C=[[1, 0]], R=[[-1]])
    with pytest.raises(SymkfError, match="unknown name"):
        sk.Sensor(C=[["__import__", 0]])


def test_rationalize_converts_and_warns():
    with pytest.warns(UserWarning, match="1/10"):
        S = sk.System(A=[[1, 0.1], [0, 2]], sensors=[sk.Sensor(C=[[1, 1]])], rationalize=True)
    assert S.A[0, 1] == sp.Rational(1, 10)


def test_exact_inputs_accepted():
    S = sk.System(A=[[Fraction(1, 2), "sqrt(3)/2"], ["-sqrt(3)/2", "cos(pi/3)"]], sensors=[sk.Sensor(C=[[1, 0]])])
    assert S.A[1, 1] == sp.Rational(1, 2)



def test_one_dimensional_numpy_C_is_a_row():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=np.array([1, 0]))])
    assert S.sensors[0].C == sp.Matrix([[1, 0]])
    assert sk.critical_loss_rate(S) == R(1, 16)  # 2R(pi/2), C = [1 0]: 1/16


def test_an_entry_rational_in_value_but_not_in_form():
    """(1/2 + sqrt 5/2)^2 - sqrt 5/2 + 5/2 is 4: the field of the entries is Q, and the entry is
    read through the field's conversion (a TypeError from sympy's Rational before)."""
    four = "-sqrt(5)/2 + 5/2 + (1/2 + sqrt(5)/2)**2"
    assert [(e.expr, e.multiplicity) for e in sk.eigenvalues([[four, 0], [0, 1]])] == [(4, 1), (1, 1)]
    written = sk.System([[four, 1], [0, 3]], [sk.Sensor([[1, 0]])])
    plain = sk.System([[4, 1], [0, 3]], [sk.Sensor([[1, 0]])])
    assert sk.critical_loss_rate(written) == sk.critical_loss_rate(plain) == sp.Rational(1, 16)


def test_warnings_point_at_the_callers_line():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sk.System(A=[[0.1, 0], [0, 2]], sensors=[sk.Sensor(C=[[1, 1]])], rationalize=True)
    assert [Path(w.filename).name for w in caught] == ["test_system.py"]


def system(A, *Cs):
    return sk.System(A=A, sensors=[sk.Sensor(C=C) for C in Cs])


def test_undetectable_pair_names_the_mode():
    with pytest.raises(sk.errors.UnobservableError, match=r"eigenvalue 2 .*not detectable"):
        system([[2, 0], [0, R(1, 2)]], [[0, 1]])
    with pytest.raises(sk.errors.UnobservableError, match=r"eigenvalue 1 "):  # marginal modes must be seen
        system([[1, 1], [0, 1]], [[0, 1]])


@pytest.mark.parametrize("build, option", [
    (lambda: sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])] * (2 ** 14 + 1)), "--max-sensors"),
    (lambda: sk.System(A=[[1 if i == j else 0 for j in range(1000)] for i in range(1000)],
                       sensors=[sk.Sensor(C=[[1] * 1000])]), "--max-dimension"),
    (lambda: sk.IID(["1/2"] * (2 ** 14 + 1)), "--max-sensors"),
    (lambda: sk.MarkovLoss({h: {(0,): "1/2", (1,): "1/2"} for h in itertools.product([(0,), (1,)], repeat=9)},
                           order=9), "--max-markov-states"),
])
def test_large_inputs_refused_early(build, option):
    with pytest.raises(BudgetError, match=option):
        build()


def test_exact_objects_and_errors_pickle():
    """Plain pickle carries algebraic numbers, systems (without their derived cache), verdicts and
    symkf errors exactly: what process pools, Dask and users' multiprocessing need."""
    import pickle

    from symkf.errors import AssumptionError
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    eps = sk.critical_loss_rate(S)                       # fills S's cache with flint objects
    assert pickle.loads(pickle.dumps(eps)) == sp.Rational(1, 16)
    S2 = pickle.loads(pickle.dumps(S))
    assert S2 == S and S2._cache == {} and sk.critical_loss_rate(S2) == eps
    v = pickle.loads(pickle.dumps(sk.stability(S, sk.IID(["1/20"]))))
    assert v.stable and v.margins[0] == AlgebraicNumber.from_expr(2 * sp.sqrt(5) / 5)
    e = pickle.loads(pickle.dumps(AssumptionError("x", assumption="A1", applies_instead="f")))
    assert (type(e), str(e), e.assumption, e.applies_instead) == \
        (AssumptionError, "A1 fails: x. What applies instead: f", "A1", "f")


def test_a_system_reads_in_one_line_and_renders_in_a_notebook():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    assert repr(S) == "System(n=2, A=[[0, -2], [2, 0]], sensors: s1 [[1, 0]], s2 [[1, 1]])"
    assert S._repr_latex_().startswith(r"$x_{k+1} = \left[\begin{matrix}0 & -2\\2 & 0\end{matrix}\right]")
    many = sk.System(A=sp.diag(2, 3, 4, 5, 6), sensors=[sk.Sensor(C=[[1, 1, 1, 1, 1]]) for _ in range(12)])
    assert repr(many) == ("System(n=5, A=<5x5>, sensors: s1 <1x5>, s2 <1x5>, s3 <1x5>, s4 <1x5>, s5 <1x5>, "
                          "s6 <1x5>, s7 <1x5>, s8 <1x5>, ... (12 sensors))")


TRACKER_Q = sp.Matrix([[R(1, 4), R(1, 2)], [R(1, 2), 1]])   # q G G', G = (1/2, 1)', q = 1


def test_singular_process_noise_of_the_constant_velocity_tracker_is_accepted_and_driven():
    S = sk.System(A=[[1, 1], [0, 1]], sensors=[sk.Sensor(C=[[1, 0]])], Q=TRACKER_Q)
    assert S.Q == TRACKER_Q and S.undriven() == ()   # [G, AG] = [[1/2, 3/2], [1, 1]] has det -1


@pytest.mark.parametrize("A, Q, undriven", [
    ([[2, 0], [0, R(6, 5)]], [[0, 0], [0, 1]], [2]),            # w' = e_1' annihilates Q
    ([[2, 0], [0, R(6, 5)]], [[0, 0], [0, 0]], [2, R(6, 5)]),
    ([[2, 1], [0, 3]], [[0, 0], [0, 1]], []),                   # e_2 reaches e_1 through A[0][1]
    ([[2, 1], [0, 3]], [[1, 0], [0, 0]], [3]),                  # left eigenvector of 3 is (0, 1)
])
def test_undriven_modes_by_pbh_on_a_and_q(A, Q, undriven):
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 1]])], Q=Q)
    assert sorted(lam.expr for lam in S.undriven()) == sorted(undriven)


@pytest.mark.parametrize("Q, rows, minor", [
    ([[1, 2], [2, 1]], "[0, 1]", "-3"),
    ([[0, 1], [1, 1]], "[0, 1]", "-1"),       # a zero variance with a nonzero covariance
    ([[1, 0, 0], [0, 1, 0], [0, 0, -1]], "[2]", "-1"),
])
def test_indefinite_process_noise_names_a_negative_principal_minor(Q, rows, minor):
    n = len(Q)
    with pytest.raises(sk.errors.NotPositiveDefiniteError, match=re.escape(
            f"Q: not positive semidefinite, the principal minor on rows {rows} is {minor} < 0")):
        sk.System(A=sp.eye(n) * 2, sensors=[sk.Sensor(C=[[1] * n])], Q=Q)


def test_singular_initial_covariance_is_still_refused():
    with pytest.raises(sk.errors.NotPositiveDefiniteError, match="P0: not positive definite"):
        sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], P0=[[0]])


def test_unseen_undriven_unit_mode_is_named_with_what_applies():
    with pytest.raises(sk.errors.UnobservableError, match=r"eigenvalue 1 .*not driven by Q either.*without this undriven"):
        sk.System(A=[[2, 0], [0, 1]], sensors=[sk.Sensor(C=[[1, 0]])], Q=[[1, 0], [0, 0]])


def test_a_systems_dict_is_its_file_and_reads_back_exactly():
    S = sk.System(A=[["sqrt(3)/2", "-1/2"], ["1/2", "sqrt(3)/2"]], sensors=[sk.Sensor(C=[[1, 0]], R=[["1/2"]], name="a")],
                  name="rotation")
    read, loss = files.parse(json.loads(S.to_json()), "doc")
    assert read.A == sp.Matrix([[sp.sqrt(3) / 2, -sp.Rational(1, 2)], [sp.Rational(1, 2), sp.sqrt(3) / 2]])
    assert (read.name, read.sensor_names, read.sensors[0].R, loss) == ("rotation", ("a",), sp.Matrix([[sp.Rational(1, 2)]]), None)


# -- actuators: the plant x+ = A x + B u + w and the LQG cost of Schenato et al. (2007, Section II) --

def test_an_actuator_counts_its_columns_and_weights_them_by_the_identity():
    a = sk.Actuator(B=[[0], [1]])
    assert (a.m, a.B, a.U, a.name) == (1, sp.Matrix([[0], [1]]), sp.eye(1), None)
    assert sk.Actuator(B=[0, "1/2"]).B == sp.Matrix([[0], [R(1, 2)]])          # a flat list is one column
    two = sk.Actuator(B=[[1, 0], [0, 1], [1, 1]], U=[[2, 1], [1, 1]], name="arm")
    assert two.m == 2 and two.U == sp.Matrix([[2, 1], [1, 1]])
    assert sk.model.Actuator is sk.Actuator


@pytest.mark.parametrize("build, error, message", [
    (lambda: sk.Actuator(B=[[0], [1]], U=[[0]]), NotPositiveDefiniteError,
     "actuator U: not positive definite, leading 1x1 minor is 0"),
    (lambda: sk.Actuator(B=[[1, 0]], U=[[1, 2], [2, 1]], name="u"), NotPositiveDefiniteError,
     "actuator 'u' U: not positive definite, leading 2x2 minor is -3"),
    (lambda: sk.Actuator(B=[[1, 0]], U=[[1]]), ShapeError, "actuator U: shape 1x1, expected 2x2"),
    (lambda: sk.Actuator(B=[[0.1]]), InexactInputError, r"actuator B[0][0]: the float 0.1 is not exact"),
    (lambda: sk.Actuator(B=[]), ShapeError, "actuator B: expected a non-empty list of rows"),
])
def test_a_bad_actuator_names_its_entry(build, error, message):
    with pytest.raises(error, match=re.escape(message)):
        build()


PLANT = [[2, 0], [0, R(1, 2)]]
E1, E2 = [[1], [0]], [[0], [1]]


def test_a_system_without_actuators_has_an_empty_input_matrix():
    S = system(PLANT, [[1, 1]])
    assert (S.actuators, S.actuator_names, S.inputs, S.B.shape, S.U.shape, S.W) == ((), (), 0, (2, 0), (0, 0), sp.eye(2))
    assert "actuators" not in S.to_dict() and "W" not in S.to_dict()["system"]   # files and JSON unchanged


def test_actuators_are_named_stacked_and_weighted():
    S = sk.System(A=PLANT, sensors=[sk.Sensor(C=[[1, 1]])], W=[[1, 0], [0, 0]],
                  actuators=[sk.Actuator(B=E1), sk.Actuator(B=[[1, 0], [1, 1]], U=[[3, 0], [0, 5]], name="pair")])
    assert S.actuator_names == ("a1", "pair") and S.inputs == 3 and len(S.actuators) == 2
    assert S.B == sp.Matrix([[1, 1, 0], [0, 1, 1]]) and S.U == sp.diag(1, 3, 5)
    assert S.W == sp.Matrix([[1, 0], [0, 0]])                                # positive semidefinite is enough
    assert S.actuator_index("pair") == 1 and S.sensor_index("s1") == 0
    with pytest.raises(sk.errors.InputError, match=r"no actuator named 'u'; actuators are \['a1', 'pair'\]"):
        S.actuator_index("u")


@pytest.mark.parametrize("actuators, W, error, message", [
    ([sk.Actuator(B=[[1], [0], [0]])], None, ShapeError, "actuators[0].B: has 3 rows, A is 2x2"),
    ([sk.Actuator(B=[[1], [0], [0]], name="u")], None, ShapeError, "actuators[0].B ('u'): has 3 rows, A is 2x2"),
    ([sk.Actuator(B=E1, name="u"), sk.Actuator(B=E2, name="u")], None, sk.errors.InputError,
     "actuators: names must be distinct, got ['u', 'u']"),
    ([sk.Actuator(B=E1, name="s1")], None, sk.errors.InputError, "actuators: the name 's1' is also a sensor's"),
    ([sk.Sensor(C=[[1, 0]])], None, sk.errors.InputError, "actuators[0]: expected a symkf.Actuator, got Sensor"),
    ([sk.Actuator(B=E1)], [[1, 2], [2, 1]], NotPositiveDefiniteError,
     "W: not positive semidefinite, the principal minor on rows [0, 1] is -3 < 0"),
    ([sk.Actuator(B=E1)], [[1]], ShapeError, "W: shape 1x1, expected 2x2"),
])
def test_actuators_that_do_not_fit_the_system_are_refused_by_name(actuators, W, error, message):
    with pytest.raises(error, match=re.escape(message)):
        sk.System(A=PLANT, sensors=[sk.Sensor(C=[[1, 1]])], actuators=actuators, W=W)


def test_too_many_actuators_are_refused_by_the_sensors_cap():
    with pytest.raises(BudgetError, match="actuators: the number of actuators is 16385.*--max-sensors"):
        sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])] * (2 ** 14 + 1))


def test_many_sensors_stack_into_C_in_their_order():
    """1024 sensors (above the former size cap of 64: the sensors' count bounds memory only) stack
    into the 1024 x 2 C row by row, and the system is observable exactly when some row sees the
    rotation."""
    rows = [[j % 3, (j + 1) % 2] for j in range(1024)]
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[r]) for r in rows])
    assert S.C.shape == (1024, 2) and S.C.tolist() == rows and S.observable


def controlled(A, *Bs):
    n = len(A)
    return sk.System(A=A, sensors=[sk.Sensor(C=[[1] * n])], actuators=[sk.Actuator(B=B) for B in Bs])


@pytest.mark.parametrize("A, B, stabilizable, controllable", [
    (PLANT, E2, False, False),            # the left eigenvector e_1' of 2 annihilates e_2
    (PLANT, E1, True, False),             # 1/2 is not reached, but decays by itself
    ([[2, 1], [0, 2]], E1, False, False),  # Jordan block: the left eigenvector of 2 is e_2', e_2' e_1 = 0
    ([[2, 1], [0, 2]], E2, True, True),   # [B, AB] = [[0, 1], [1, 2]]
    ([[0, -2], [2, 0]], E1, True, True),  # 2R(pi/2): one real input reaches the pair +-2i, [B, AB] = [[1, 0], [0, 2]]
    ([[R(1, 2), 0], [0, R(1, 3)]], E1, True, False),   # every mode stable
])
def test_stabilizability_is_the_pbh_rank_on_the_unstable_modes(A, B, stabilizable, controllable):
    S = controlled(A, B)
    assert (S.stabilizable, S.controllable) == (stabilizable, controllable)
    n = len(A)
    for lam in (e for b in S.eigen_blocks() for e in b.members):   # against the rank of [A - lambda I, B]
        assert S.unreached(lam) == (sp.Matrix.hstack(S.A - lam.expr * sp.eye(n), S.B).rank(simplify=True) < n)


def test_an_unreached_unstable_mode_is_named_with_what_applies():
    with pytest.raises(UncontrollableError, match=re.escape(
            "(A, B) stabilizable: PBH rank [A - lambda I, B] = n for |lambda| >= 1 fails: the eigenvalue 2 of A "
            "(|lambda| = 2 >= 1) is not reached by any actuator")) as info:
        controlled(PLANT, E2).check_stabilizable()
    assert "add an actuator acting on the mode of 2" in info.value.applies_instead
    assert info.value.exit_status == 3
    controlled(PLANT, E1).check_stabilizable()                              # stabilizable: returns
    with pytest.raises(UncontrollableError, match=r"eigenvalue sqrt\(2\) .*not reached"):   # in Q(sqrt 2)
        controlled([["sqrt(2)", 0], [0, R(1, 2)]], E2).check_stabilizable()
    with pytest.raises(UncontrollableError, match=r"eigenvalue 2 .*\(the system has none\)"):
        system(PLANT, [[1, 1]]).check_stabilizable()
    system([[R(1, 2)]], [[1]]).check_stabilizable()                        # nothing to stabilize


def test_a_system_with_actuators_reads_in_one_line_renders_and_pickles():
    import pickle
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="y")],
                  actuators=[sk.Actuator(B=E2, name="u")], name="loop")
    assert repr(S) == "System('loop', n=2, A=[[0, -2], [2, 0]], sensors: y [[1, 0]], actuators: u [[0], [1]])"
    assert r"x_k + \left[\begin{matrix}0\\1\end{matrix}\right]\, u_k + w_k" in S._repr_latex_()
    assert "actuators u" in S._repr_latex_()
    back = pickle.loads(pickle.dumps(S))
    assert back == S and hash(back) == hash(S) and back.actuators[0].U == sp.eye(1)
    assert S != sk.System(A=S.A, sensors=S.sensors, name="loop")            # the actuators count in equality


def test_a_system_with_actuators_reads_back_from_its_dict():
    S = sk.System(A=PLANT, sensors=[sk.Sensor(C=[[1, 1]], name="y")], W=[[2, 0], [0, "1/3"]], name="loop",
                  actuators=[sk.Actuator(B=E1, U=[["1/2"]], name="u"), sk.Actuator(B=[[1, 0], [0, 1]], name="v")])
    doc = json.loads(S.to_json())
    assert doc["system"]["W"] == [["2", "0"], ["0", "1/3"]]
    assert doc["actuators"][0] == {"name": "u", "B": [["1"], ["0"]], "U": [["1/2"]]}
    read, loss = files.parse(doc, "doc")
    assert read == S and loss is None
