"""The hypothesis strategies (symkf.model.strategies): what they draw holds by construction, bad
arguments are named with what the strategy takes."""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis.errors import InvalidArgument

from symkf.errors import UnobservableError
from symkf.exact.algebraic import AlgebraicNumber
from symkf.exact.linalg import rank
from symkf.model import strategies as sks
from symkf.model.system import Sensor, System

FAST = settings(max_examples=15, deadline=None)


@FAST
@given(sks.rotation_systems(scale="3/2", max_denominator=6))
def test_rotations_have_modulus_and_period(rot):
    A = sp.Matrix(rot.system.A)
    q = rot.angle.denominator
    assert sp.simplify(A.det() - sp.Rational(9, 4)) == 0
    power = sp.simplify(A ** q / rot.scale ** q)   # R(pi p) = +-I
    assert power in (sp.eye(2), -sp.eye(2))


@FAST
@given(sks.diagonalizable_systems([("3/2", 2), ("1/2", 1)], sensors=2))
def test_diagonalizable_block_structure(S):
    assert sp.Matrix(S.A).eigenvals() == {sp.Rational(3, 2): 1, sp.Rational(-3, 2): 1, sp.Rational(1, 2): 1}
    assert S.d == 2


@FAST
@given(sks.diagonalizable_systems([("5/4", 1), ("1/2", 1)], sensors=2, observable=False))
def test_violating_sensors_are_unobservable(case):
    A, Cs = case
    C = sp.Matrix.vstack(*Cs)
    assert rank(sp.Matrix.vstack(C, C * A)) < 2
    with pytest.raises(UnobservableError):
        System(A=A, sensors=[Sensor(C=c) for c in Cs])


@FAST
@given(sks.loss_rates_near(sp.Rational(1, 16), "1/4", side="below"),
       sks.loss_rates_near(sp.Rational(1, 16), "1/4", side="above"))
def test_margins_around_critical(below, above):
    assert sp.Rational(1, 32) <= below <= sp.Rational(3, 64)
    assert sp.Rational(5, 64) <= above <= sp.Rational(3, 32)


@FAST
@given(sks.iid_losses(3, high="1/2"), sks.gilbert_elliott_losses(2))
def test_loss_models(iid, ge):
    assert iid.d == 3 and all(0 <= e <= sp.Rational(1, 2) for e in iid.loss)
    assert ge.d == 2 and all(0 < f < 1 for f in ge.fail)


# exact observability checks of complex systems are slow in sympy: few examples
@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(sks.complex_diagonal_systems(2, moduli=["3/2"], max_denominator=4))
def test_complex_diagonal_systems(S):
    assert S.n == 2 and any(e.is_real is False for e in S.A)
    assert all(sp.simplify(abs(S.A[i, i]) - sp.Rational(3, 2)) == 0 for i in range(2))


@pytest.mark.parametrize("call, name", [
    (lambda: sks.loss_rates_near("3/2", "1/4", side="below"), "critical"),
    (lambda: sks.loss_rates_near("1/2", "3/4", side="below"), "margin"),
    (lambda: sks.loss_rates_near("1/2", "1/4", side="left"), "side"),
    (lambda: sks.loss_rates_near("9/10", "1/4", side="above", max_denominator=10), "critical"),
    (lambda: sks.diagonalizable_systems([("3/2", 3)]), "size"),
    (lambda: sks.diagonalizable_systems([("3/2", 2), ("3/2", 1)]), "blocks"),
    (lambda: sks.rotation_systems(scale=0.1), "scale"),
    (lambda: sks.iid_losses(0), "d"),
])
def test_arguments_validated_up_front(call, name):
    with pytest.raises(InvalidArgument, match=name):
        call()


@settings(max_examples=15, deadline=None)
@given(sks.rotation_systems(scale="3/2", max_denominator=6))
def test_hand_derived_rotation_threshold_equals_the_engine(rot):
    """The strategy's closed form r^(-2q/(q-1)) against the exact engine (hyperplanes over g = q)."""
    from symkf.engine.stability import critical_loss_rate
    assert critical_loss_rate(rot.system) == AlgebraicNumber.from_expr(rot.critical_loss_rate())


def test_strategy_errors_offer_what_strategies_take():
    strategies = pytest.importorskip("symkf.model.strategies")
    from hypothesis.errors import InvalidArgument
    with pytest.raises(InvalidArgument) as info:
        strategies.rotation_systems(scale=0.3)
    assert str(info.value) == "scale: the float 0.3 is not exact; give the string '0.3', a Fraction or a Decimal"
