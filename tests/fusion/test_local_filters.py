"""Local steady-state filters and their joint covariance (symkf.fusion.local_filters;
arXiv:2012.04896, Lemmas 1-2): the DARE and the Stein equation against their iterations."""

import time

import numpy as np
import pytest

import symkf as sk
from symkf import budget
from symkf.errors import BudgetError
from symkf.fusion import FusionModel, local_filters

from symkf.fusion.local_filters import lemma2_iteration


def test_dare_and_stein_agree_with_iterations(small_fusion):
    for loc, f, i in zip(small_fusion.model.local, small_fusion.filters, range(3)):
        X = np.eye(loc.n_o)
        for _ in range(2000):                                   # h_i(g~_i(X)), eqs. (7)-(8)
            X = loc.A @ (X - X @ loc.C.T @ np.linalg.inv(loc.C @ X @ loc.C.T + loc.R) @ loc.C @ X) @ loc.A.T + loc.Q
        assert np.allclose(X, f.P_pred, atol=1e-10)
        assert np.allclose(f.P, small_fusion.block(i, i), atol=1e-10)   # diagonal of the joint Stein solution
    assert np.allclose(lemma2_iteration(small_fusion, 0, 2, 3000), small_fusion.block(0, 2), atol=1e-10)
    assert np.abs(small_fusion.block(0, 2)).max() > 1e-2


def many_sensor_model(N):
    """x+ = A x + w with A = [[11/10, 1], [0, 11/10]] and N sensors alternating [0, 1] (one observable
    state) and [1, 0] (two): N / 2 * (1 + 2) local states in all, arrival 9/10 each."""
    sensors = [sk.Sensor(C=[[1, 0]] if j % 2 else [[0, 1]]) for j in range(N)]
    return FusionModel.discrete([["11/10", 1], [0, "11/10"]], [[1, 0], [0, 1]], sensors, ["9/10"] * N)


def test_local_filters_over_max_work_are_refused_by_their_price():
    # 32 sensors: 32 Riccati equations and a joint Stein equation of size 48, 0.033 CPU-s estimated,
    # refused under a cap of 0.01 CPU-s before the first (the default refuses past about 1500 sensors,
    # whose model alone takes longer than a test should)
    model = many_sensor_model(32)
    start = time.process_time()
    with budget.limits(max_work=10), pytest.raises(BudgetError, match=r"local_filters: .*Stein equation of size 48.*max_work"):
        local_filters(model)
    assert time.process_time() - start < 2


def test_the_local_filters_estimate_is_within_4x_of_their_cost():
    # 128 sensors, a joint Stein equation of size 192: 0.16 CPU-s estimated, 0.15 measured
    model = many_sensor_model(128)
    estimate = budget.seconds(local_filter=128, float_cube=192 ** 3)
    local_filters(many_sensor_model(2))   # threadpoolctl's first look at the loaded libraries, once per process
    start = time.process_time()
    lf = local_filters(model)
    measured = time.process_time() - start
    assert lf.offsets[-1] == 192
    assert measured / 4 < estimate < 4 * measured   # 3x in fresh processes (docs/caps.md); 4x beside other tests
