"""The remote estimator over lossy channels (symkf.fusion.remote, symkf.fusion.stability;
arXiv:2012.04896, eqs. 9-12, Proposition 1): simulated errors against the predicted covariance
and the bound."""

import numpy as np

from symkf.fusion import proposition1_bound, simulate_fusion


def test_simulated_errors_match_predicted_covariance(small_fusion):
    # x grows like 1.1^k: beyond ~300 steps float rounding of x swamps the errors.
    sim = simulate_fusion(small_fusion, horizon=120, paths=200, seed=7)
    emp = (np.linalg.norm(sim.fused[:, 1:], axis=-1) ** 2).mean()
    pred = sim.trace_P[:, 1:].mean()
    assert abs(emp - pred) < 0.1 * pred                      # 24 000 correlated samples
    b = proposition1_bound(small_fusion)
    assert pred <= 1.1 * b.bound and b.bound < b.trace_expected_sigma
    single = (np.linalg.norm(sim.single[:, 1:, 0], axis=-1) ** 2).mean()
    assert emp < single                                      # sensor a cannot see x3
