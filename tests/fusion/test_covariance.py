"""Error covariances at the remote estimator (symkf.fusion.covariance; arXiv:2012.04896, eqs. 17-20,
Lemma 3): the holding-time covariance against step-by-step propagation, its mean against the
average over holding times."""

import numpy as np
import pytest

from symkf import budget
from symkf.errors import BudgetError
from symkf.fusion import expected_remote_covariance, fusion_sigma, remote_error_covariance


@pytest.mark.parametrize("tau", [(0, 0, 0), (3, 0, 1), (0, 5, 2), (4, 4, 0)])
def test_holding_time_covariance_matches_propagation(small_fusion, tau):
    P = remote_error_covariance(small_fusion, tau)
    assert np.allclose(P, remote_error_covariance(small_fusion, tau, method="propagation"), rtol=1e-10, atol=1e-12)
    assert np.allclose(P, P.T) and np.linalg.eigvalsh(fusion_sigma(small_fusion, P))[0] > -1e-10   # Lemma 3


@pytest.mark.full
def test_expected_covariance_is_the_average_over_holding_times(small_fusion):
    lam = [float(x) for x in small_fusion.model.arrival]
    avg = np.zeros_like(small_fusion.Pi)
    for t0 in range(40):
        for t1 in range(25):
            for t2 in range(16):
                p = np.prod([l * (1 - l) ** t for l, t in zip(lam, (t0, t1, t2))])
                avg += p * remote_error_covariance(small_fusion, (t0, t1, t2))
    assert np.allclose(avg, expected_remote_covariance(small_fusion), rtol=1e-7, atol=1e-9)


def test_the_expected_covariance_over_max_work_is_refused_by_its_price(small_fusion):
    # the small set-up's three sensors: 9 + 6 Stein equations, refused under a cap of
    # 1 CPU-ms (1024 sensors of two states: about 110 CPU-s estimated, above the default)
    with budget.limits(max_work=1), pytest.raises(BudgetError, match=r"expected_remote_covariance: .*Stein equations"):
        expected_remote_covariance(small_fusion)
