"""When V_k converges (symkf.capacity.convergence; Yang et al., Theorem 4): the LMI of condition 1)
with exact certificates on both sides of known thresholds, the infeasibility certificate on balls
equal to the exact one, positive definiteness by pivots (Schur complements, number fields)
against Sylvester's minors, condition 2) on the unit circle."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf import IID, Sensor, System
from symkf.capacity import MARE, mare_converges, mare_stabilizable, unit_circle_condition
from symkf.errors import AssumptionError
from symkf.exact.linalg import positive_definite

from conftest import period_24_block, refused_within

R = sp.Rational
ROTATION = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])], name="rotation")
FULL_C = System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=[[1, 0], [0, 1]])], name="full C")
ROTATION_PI_4 = System(A=[[sp.sqrt(2), -sp.sqrt(2)], [sp.sqrt(2), sp.sqrt(2)]], sensors=[Sensor(C=[[1, 0]])])
ROTATION_PI_6 = System(A=[[sp.sqrt(3), -1], [1, sp.sqrt(3)]], sensors=[Sensor(C=[[1, 0]])])
SCALAR2 = System(A=[[2]], sensors=[Sensor(C=[[1]]), Sensor(C=[[1]])], name="scalar x2")


@pytest.mark.parametrize("system, good, bad", [
    (System(A=[[2]], sensors=[Sensor(C=[[1]])]), "1/5", "3/10"),           # a^2 (1 - lambda) < 1: loss < 1/4
    (ROTATION, "1/20", "1/12"),                                             # loss < 1/M^2 = 1/16 (Elia)
    (FULL_C, "1/10", "1/8"),                                                # invertible C: loss < 1/rho^2 = 1/9
    (SCALAR2, "7/20", "9/20"),                                              # 4 < 1 + 2q: loss < 2/5
    (ROTATION_PI_4, "1/17", "1/15"),                                        # certificates in Q(sqrt 2): 1/16 again
    (ROTATION_PI_6, "1/17", "1/15"),                                        # and in Q(sqrt 3)
])
def test_theorem4_condition1_known_thresholds(system, good, bad):
    yes, no = mare_stabilizable(system, IID([good] * system.d)), mare_stabilizable(system, IID([bad] * system.d))
    assert yes.holds is True and no.holds is False
    # the certified gain makes the second-moment map of eq. 24 contract
    A = np.array(system.A, dtype=float)
    L = np.array(yes.gain, dtype=float)
    lam = 1 - float(R(good))
    blocks, start = [], 0
    for s in system.sensors:
        blocks.append((L[:, start:start + s.m], np.array(s.C, dtype=float)))
        start += s.m
    Acl = A - lam * sum(Li @ Ci for Li, Ci in blocks)
    T = np.kron(Acl.T, Acl.T) + lam * (1 - lam) * sum(np.kron((Li @ Ci).T, (Li @ Ci).T) for Li, Ci in blocks)
    assert max(abs(np.linalg.eigvals(T))) < 1


@pytest.mark.parametrize("system, bad", [(ROTATION, "1/12"), (ROTATION_PI_4, "1/15"), (ROTATION_PI_6, "1/15"),
                                         (SCALAR2, "9/20")])   # (FULL_C at 1/8 is decided by ln rho, before any SDP)
def test_the_infeasibility_certificate_on_balls_is_the_exact_one(system, bad, monkeypatch):
    # the projected multiplier W - sum_k c_k F_k is judged on certified balls first: every judgement
    # must be the exact projection's (the certificate of each infeasible SDP: positive definite),
    # and so for random symmetric W (their projections: indefinite)
    from symkf.capacity import convergence as cv
    seen = []

    def both(K, entries, gram, rhs, start):
        on_balls = projected(K, entries, gram, rhs, start)
        coef = cv.solve_rows(K, gram, rhs)
        seen.append((on_balls, positive_definite(K, cv._combination(K, [-c for c in coef], entries, len(start), start))))
        return on_balls
    projected = cv._projected_positive
    monkeypatch.setattr(cv, "_projected_positive", both)
    assert mare_stabilizable(system, IID([bad] * system.d)).holds is False
    basis, _, _ = cv._basis(system, IID([bad] * system.d))
    K, entries = cv._entries(basis)
    gram, size = cv._gram(K, entries), basis[0].shape[0]
    for X in np.random.default_rng(3).normal(size=(4, size, size)):
        Wr = [[cv._rational(cv._dyadic(v)) for v in row] for row in X @ X.T / size + np.eye(size) / 4]
        both(K, entries, gram, [cv._frobenius(K, P, Wr) for P in entries], Wr)
    assert all(x == y for x, y in seen) and (True, True) in seen and (False, False) in seen


def test_theorem4_agrees_with_mare_iteration():
    for loss, expected in ((IID(["7/20", "7/20"]), True), (IID(["9/20", "9/20"]), False)):
        assert mare_converges(SCALAR2, loss) is expected
        if expected:
            MARE(SCALAR2, loss).fixed_point()
        else:
            with pytest.raises(AssumptionError):
                MARE(SCALAR2, loss).fixed_point(max_iter=20_000)


def test_theorem4_below_ln_rho_is_certified_without_sdp():
    v = mare_stabilizable(ROTATION, IID(["1/3"]))
    assert v.holds is False and "ln rho" in v.certificate


def test_condition2_with_unit_circle_eigenvalues():
    assert unit_circle_condition(System(A=[[0, -1], [1, 0]], sensors=[Sensor(C=[[1, 0]])]))
    assert unit_circle_condition(System(A=[[1, 1], [0, 1]], sensors=[Sensor(C=[[1, 0]])],
                                        Q=[[1, 0], [0, R(1, 100)]]))




def test_an_lmi_of_320_noisy_sensors_is_refused_by_its_price():
    # the 4-dim block diag(2R(pi/6), 2R(pi/4)) with 320 scalar sensors at loss 1/10: one LMI of size 4 (2 + 320) = 1288 in 1290 coordinates, about 110 CPU-s estimated
    S = period_24_block(320)
    refused_within(5, r"mare_stabilizable: .*LMIs of size 1288 in 1290 coordinates.*max_work", lambda: mare_stabilizable(S, IID(["1/10"] * 320)))
