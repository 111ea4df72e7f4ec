"""Capacity conditions for the upper bound (symkf.capacity.theorems; Yang et al., eq. 26,
Theorems 5-7, Corollaries 1-2, Lemma 2): the Wonham decomposition, requirements and allocations,
the necessary condition against certified verdicts, the single-sensor rates."""

from __future__ import annotations

import itertools

import pytest
import sympy as sp

from symkf import IID, Sensor, System
from symkf.capacity import (
    capacity_bounds_meet,
    corollary1_critical_capacity,
    mare_stabilizable,
    single_sensor_rates,
    theorem5_requirements,
    theorem5_sufficient,
    theorem6_allocation,
    theorem7_necessary,
    transmission_capacity,
    wonham_decomposition,
)
from symkf.errors import AssumptionError

R = sp.Rational
ROTATION = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])], name="rotation")
LOWER_TRI = System(A=[[R(5, 4), 0], [1, R(11, 10)]], sensors=[Sensor(C=[[1, 1]])], name="lower-tri")
FULL_C = System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=[[1, 0], [0, 1]])], name="full C")


def test_wonham_decomposition_structure():
    S = System(A=[[2, 1, 0], [0, 3, 1], [1, 0, R(1, 2)]],
               sensors=[Sensor(C=[[1, 0, 0]]), Sensor(C=[[0, 0, 1], [0, 1, 0]])])
    for order in (None, [(1, 1), (0, 0), (1, 0)]):
        dec = wonham_decomposition(S, order)
        At = sp.Matrix(dec.A_tilde)
        sizes = [B.shape[0] for _, _, B in dec.blocks]
        start = 0
        for k in sizes:                                     # block lower triangular
            assert At[start:start + k, start + k:].is_zero_matrix
            start += k
        assert sum(sizes) == 3
        char = sp.Mul(*[B.charpoly().as_expr() for _, _, B in dec.blocks])
        assert sp.expand(char - S.A.charpoly().as_expr()) == 0
    assert [B.shape[0] for _, _, B in wonham_decomposition(FULL_C, [(0, 1), (0, 0)]).blocks] == [1, 1]


def test_theorem5_requirements_and_allocation():
    S = System(A=[[2, 0], [0, 3]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[1, 1]])])
    assert theorem5_requirements(S) == (sp.log(2), sp.log(3))
    alloc = theorem6_allocation(S, 7)                       # C = ln 7 > h(A) = ln 6
    assert sp.simplify(transmission_capacity(alloc) - sp.log(7)) == 0
    assert theorem5_sufficient(S, alloc)
    assert mare_stabilizable(S, alloc).holds is True        # Theorem 5's conclusion, certified
    with pytest.raises(AssumptionError, match="27"):
        theorem6_allocation(S, 6)


def test_theorem7_necessary_against_certified_verdicts():
    """Decoupled modes 2 and 3, one sensor each: condition 1) iff loss_1 < 1/4 and loss_2 < 1/9."""
    S = System(A=[[2, 0], [0, 3]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])])
    for l1, l2 in itertools.product(["1/5", "1/10", "1/3"], ["1/12", "1/20", "1/5"]):
        loss = IID([l1, l2])
        truth = bool(R(l1) < R(1, 4) and R(l2) < R(1, 9))
        verdict = mare_stabilizable(S, loss).holds
        # feasible: always certified; infeasible in both modes: certified; infeasible in one mode only:
        # no positive definite dual certificate exists (documented), so None is the honest answer
        assert verdict is (truth if truth or (R(l1) > R(1, 4) and R(l2) > R(1, 9)) else None)
        if truth:
            assert theorem7_necessary(S, loss)
    assert not theorem7_necessary(S, IID(["1/5", "1/5"]))          # 25 < 36
    with pytest.raises(AssumptionError, match="Theorem 7"):
        theorem7_necessary(System(A=[[0, 1], [0, 2]], sensors=[Sensor(C=[[1, 0]])]), IID(["1/2"]))


def test_corollary1():
    S = System(A=[[2, 0], [0, 3]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[1, 1]])])
    assert corollary1_critical_capacity(S) == sp.log(6)
    with pytest.raises(AssumptionError, match="scalar measurements"):
        corollary1_critical_capacity(FULL_C)
    with pytest.raises(AssumptionError, match="unstable"):
        corollary1_critical_capacity(System(A=[[2, 0], [0, R(1, 2)]], sensors=[Sensor(C=[[1, 1]])]))


def test_lemma2_and_corollary2():
    assert capacity_bounds_meet([[2, 0], [0, R(1, 2)]]) and capacity_bounds_meet([[-3]])
    assert not capacity_bounds_meet([[2, 0], [0, 2]])


def test_single_sensor_rates():
    assert single_sensor_rates(ROTATION.A) == (R(3, 4), R(15, 16))
    assert single_sensor_rates(LOWER_TRI.A) == (R(9, 25), R(57, 121))
