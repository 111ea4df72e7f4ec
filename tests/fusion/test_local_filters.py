"""Local steady-state filters and their joint covariance (symkf.fusion.local_filters;
arXiv:2012.04896, Lemmas 1-2): the DARE and the Stein equation against their iterations."""

import numpy as np

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
