"""Optimal unbiased fusion weights (symkf.fusion.weights; arXiv:2012.04896, Problems 1-3,
Theorem 2): the closed form, the SDP and Problem 3 reach one optimum, on drawn singular Sigma and
on the pendulum; Sigma vanishing on null(Vo') is not inverted; invalid inputs named."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf.errors import AssumptionError, NotPositiveDefiniteError, ShapeError
from symkf.fusion import fused_covariance, fusion_sigma, optimal_weights, remote_error_covariance, unbiasedness_matrix
from symkf.fusion.covariance import stacked_bases
from symkf.fusion.remote import RemoteFusion


def random_sigma(rng, n, N):
    """Singular Sigma as in eq. (20): Diag(V_i) P Diag(V_i)' with random orthonormal V_i."""
    Vs = [np.linalg.qr(rng.standard_normal((n, k)))[0] for k in rng.integers(1, n, N)]
    Vs[0] = np.eye(n)
    L = rng.standard_normal((sum(V.shape[1] for V in Vs),) * 2)
    P = L @ L.T
    Vb = np.zeros((n * N, P.shape[0]))
    c = 0
    for i, V in enumerate(Vs):
        Vb[i * n:(i + 1) * n, c:c + V.shape[1]] = V
        c += V.shape[1]
    return Vb @ P @ Vb.T, np.vstack([V @ V.T for V in Vs])


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 10**6), st.integers(2, 4), st.integers(2, 4))
def test_three_methods_reach_the_same_optimum(seed, n, N):
    Sigma, Vo = random_sigma(np.random.default_rng(seed), n, N)
    assert np.linalg.matrix_rank(Sigma) < n * N
    W = {m: optimal_weights(Sigma, Vo, m) for m in ("closed-form", "sdp", "problem3")}
    ref = np.trace(fused_covariance(Sigma, W["closed-form"]))
    for w in W.values():
        assert np.abs(w.T @ Vo - np.eye(n)).max() < 1e-7
        assert abs(np.trace(fused_covariance(Sigma, w)) - ref) <= 1e-6 * ref
        assert np.abs(Sigma @ (w - W["closed-form"])).max() <= 1e-4 * np.abs(Sigma).max()
    # any other feasible W is worse: perturb inside the constraint set
    D = np.random.default_rng(seed + 1).standard_normal(Vo.shape)
    D -= Vo @ np.linalg.pinv(Vo) @ D
    assert np.trace(fused_covariance(Sigma, W["closed-form"] + 0.1 * D)) >= ref


def test_methods_agree_on_the_pendulum(pendulum_fusion):
    Sigma = fusion_sigma(pendulum_fusion, remote_error_covariance(pendulum_fusion, (0, 1, 0, 2, 0, 1, 0, 3, 0, 1)))
    Vo = unbiasedness_matrix(pendulum_fusion)
    traces = {m: np.trace(fused_covariance(Sigma, optimal_weights(Sigma, Vo, m)))
              for m in ("closed-form", "problem3", "sdp")}
    # 3.30624e-4 is the optimum computed at 300 bits (flint arb_mat) from the same float model.
    for m, t in traces.items():
        assert 3.3062e-4 <= t <= 3.3062e-4 * (1.02 if m == "sdp" else 1.001), (m, t)
    U, tr = RemoteFusion(pendulum_fusion).weights((0, 1, 0, 2, 0, 1, 0, 3, 0, 1))
    assert abs(tr - traces["closed-form"]) < 1e-3 * tr
    assert np.abs((stacked_bases(pendulum_fusion) @ U).T @ Vo - np.eye(4)).max() < 1e-8


def test_closed_form_when_sigma_vanishes_on_null_vo():
    """Instance 0 of proofs/fusion_closed_form.py: N' Sigma N is exactly 0 (N spans null(Vo')), and
    rounds to ~1e-17; it must not be inverted.  Exact optimum (sympy, eq. 27): P* = [[1, -2], [-2, 4]]."""
    Sigma = np.array([[0, 0, 0, 0], [0, 4, 6 / 5, 8 / 5], [0, 6 / 5, 9 / 25, 12 / 25], [0, 8 / 5, 12 / 25, 16 / 25]])
    Vo = np.array([[0, 0], [0, 1], [9 / 25, 12 / 25], [12 / 25, 16 / 25]])
    W = optimal_weights(Sigma, Vo)
    assert np.abs(W.T @ Vo - np.eye(2)).max() < 1e-12
    assert np.abs(fused_covariance(Sigma, W) - np.array([[1, -2], [-2, 4]])).max() < 1e-12


def test_invalid_inputs_name_entry_and_assumption():
    Sigma, Vo = random_sigma(np.random.default_rng(0), 2, 3)
    with pytest.raises(NotPositiveDefiniteError, match="Sigma.*Lemma 3"):
        optimal_weights(Sigma - 10 * np.eye(6), Vo)
    with pytest.raises(NotPositiveDefiniteError, match="not symmetric"):
        optimal_weights(Sigma + np.triu(np.ones((6, 6)), 1), Vo)
    with pytest.raises(ShapeError, match="Vo"):
        optimal_weights(Sigma, Vo[:4])
    with pytest.raises(AssumptionError, match="Assumption 1"):
        optimal_weights(Sigma, np.hstack([Vo[:, :1], Vo[:, :1]]))


def test_the_weights_are_priced_by_the_size_of_sigma_before_any_factorisation():
    """Problem 2's SDP for a 200 x 200 Sigma: 200^4 units of 0.4 µs, 640 CPU-s, refused at once
    naming max_work; the closed form of a 512 x 512 Sigma (512^3 units of 0.8 ns, 0.11 CPU-s) is
    within 4x of its measured cost (one BLAS thread)."""
    import time

    from threadpoolctl import threadpool_limits

    from symkf import budget
    from symkf.errors import BudgetError
    Vo = np.ones((200, 1))
    start = time.process_time()
    with pytest.raises(BudgetError, match=r"^symkf.fusion.optimal_weights: the estimated work of the weights by "
                                          r'method="sdp" for a 200 x 200 Sigma is 640 CPU-s, .*--max-work'):
        optimal_weights(np.eye(200), Vo, "sdp")
    assert time.process_time() - start < 0.5
    Sigma, Vo = random_sigma(np.random.default_rng(5), 4, 128)
    optimal_weights(*random_sigma(np.random.default_rng(5), 4, 3))
    with threadpool_limits(1):
        start = time.process_time()
        optimal_weights(Sigma, Vo)
        measured = time.process_time() - start
    estimate = budget.seconds(weights_cube=512 ** 3)
    assert measured / 4 < estimate < 4 * measured
