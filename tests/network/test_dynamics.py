"""Plant data for the network conditions (symkf.network.dynamics): the exact squared spectral norm
against numpy."""

from __future__ import annotations

import pytest
import sympy as sp

from symkf.network import spectral_norm_squared

R = sp.Rational


def test_spectral_norm_squared_against_numpy():
    np = pytest.importorskip("numpy")
    for M in ([[R(5, 4), 0], [1, R(11, 10)]], [[0, -2], [2, 0]], [[1, 2, 0], [0, 1, 3], [1, 0, 1]]):
        v = spectral_norm_squared(sp.Matrix(M))
        assert abs(float(v) - np.linalg.norm(np.array(M, dtype=float), 2) ** 2) < 1e-10
