"""The Kalman decomposition per sensor (symkf.fusion.decomposition; arXiv:2012.04896, eqs. 3-5,
Assumption 1): exact observable dimensions, block lower triangular form, collective
observability refused naming the assumption."""

import numpy as np
import pytest
import sympy as sp

from symkf import Sensor
from symkf.errors import AssumptionError
from symkf.fusion import FusionModel

from conftest import FUSION_A3


def test_observable_dimensions_are_exact(small_fusion, pendulum_fusion):
    assert [loc.n_o for loc in small_fusion.model.local] == [2, 1, 2]
    # Section 4: x is invisible to velocity / angle sensors, sensors 2, 3, 5 see everything.
    assert [loc.n_o for loc in pendulum_fusion.model.local] == [3, 4, 4, 3, 4, 3, 3, 3, 3, 3]
    loc = small_fusion.model.local[0]
    assert sp.Matrix(loc.exact_basis).T * sp.Matrix([0, 0, 1]) == sp.zeros(2, 1)


def test_kalman_decomposition_is_block_lower_triangular(pendulum_fusion):
    m = pendulum_fusion.model
    for loc in m.local:
        V_un = np.linalg.svd(loc.V.T)[2][loc.n_o:].T          # orthonormal complement
        if V_un.size:
            assert np.abs(loc.V.T @ m.A @ V_un).max() < 1e-12   # V_o' A V_unobs = 0
        assert np.allclose(loc.V.T @ loc.V, np.eye(loc.n_o))


def test_collective_observability_failure_names_assumption():
    with pytest.raises(AssumptionError, match="Assumption 1"):
        FusionModel.discrete(FUSION_A3, np.eye(3).astype(int).tolist(), [Sensor([[0, 0, 1]])], ["1/2"])
