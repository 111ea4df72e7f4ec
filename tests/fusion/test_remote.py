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


def test_a_simulation_whose_records_pass_max_memory_is_refused_before_it_allocates(small_fusion):
    """10^9 steps of 10^3 paths of three sensors in three states: 8 (2 * 3 + 3 * 3 + 1) = 128 bytes
    of error records per path and step (one step more) and 3 of arrivals, 131 * 10^12 + 128 * 10^3
    bytes, above the default 2 GiB."""
    import pytest
    from symkf.errors import BudgetError
    with pytest.raises(BudgetError, match=r"^symkf.fusion.simulate_fusion: the bytes \(estimate\) of 1000 paths x "
                                          r"1000000000 steps of 3 sensors' errors is 131000000128000, above the cap 2147483648.*--max-memory"):
        simulate_fusion(small_fusion, horizon=10 ** 9, paths=1000, seed=0)


def test_a_simulation_that_would_pass_max_work_is_stopped_within_a_tenth_of_it(small_fusion):
    """200 000 steps of 50 paths under a cap of 2 CPU-s: the weights of new holding times, metered
    per path and step, are projected past the cap once 0.2 CPU-s are spent, and refused, naming it."""
    import time

    import pytest
    from symkf import budget
    from symkf.errors import BudgetError
    start = time.process_time()
    with budget.limits(max_work=2000), pytest.raises(BudgetError, match=r"^symkf.fusion.simulate_fusion: the fusion "
                                                                       r"weights of 50 paths x 200001 steps .* rounds; "
                                                                       r"the \d+ left .*max_work = 2000"):
        simulate_fusion(small_fusion, horizon=200_000, paths=50, seed=0)
    assert time.process_time() - start < 1.5
