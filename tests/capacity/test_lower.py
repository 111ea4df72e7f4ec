"""The lower bound of E[P_k^-] (symkf.capacity.lower; Yang et al., Proposition 1, Theorems 1-2,
Remark 2): the convergence boundary exactly, the limit solving its Stein equation exactly, its
limits for stable A."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from symkf import IID, Sensor, System
from symkf.capacity import lower_bound_converges, lower_bound_limit, lower_bound_sequence, theorem2
from symkf.errors import AssumptionError

R = sp.Rational


def test_theorem1_boundary_is_exact():
    S = System(A=[[2]], sensors=[Sensor(C=[[1]])])
    assert not lower_bound_converges(S, IID(["1/4"]))             # c rho^2 = 1: diverges (<=)
    assert lower_bound_converges(S, IID(["249/1000"]))
    assert theorem2(S, IID(["1/4"])) == {"diverges": True, "Gbar": None}
    with pytest.raises(AssumptionError, match="eq. 14"):
        lower_bound_limit(S, IID(["1/3"]))


def test_lower_bound_limit_solves_stein_exactly():
    assert lower_bound_limit(System(A=[[2]], sensors=[Sensor(C=[[1]])]), IID(["1/8"]))[0, 0] == 2
    S = System(A=[[R(6, 5), 1], [0, R(-1, 2)]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])],
               Q=[[1, R(1, 2)], [R(1, 2), 2]])
    loss = IID(["1/3", "1/2"])
    G = lower_bound_limit(S, loss)
    assert G == R(1, 6) * S.A * G * S.A.T + S.Q                    # exact fixed point of m
    seq = lower_bound_sequence(S, loss, 200)
    assert np.allclose(seq[-1], np.array(G, dtype=float), rtol=1e-12)
    assert lower_bound_sequence(S, loss, 3, exact=True)[2] == R(1, 6) * S.A * S.Q * S.A.T + S.Q


def test_remark2_limits_of_gbar():
    """Remark 2 (stable A): Gbar = Q when some lambda_i = 1; Gbar solves Sigma - A Sigma A' = Q when all lambda_i = 0."""
    S = System(A=[[R(1, 2), 1], [0, R(-1, 3)]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1]])],
               Q=[[2, 1], [1, 3]])
    assert lower_bound_limit(S, IID(["0", "1/2"])) == S.Q
    Sigma = lower_bound_limit(S, IID(["1", "1"]))
    assert Sigma - S.A * Sigma * S.A.T == S.Q
