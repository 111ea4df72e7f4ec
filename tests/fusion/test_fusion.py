"""Tests of symkf.fusion (seed 003): decomposition, filters, covariances, weights, remote estimator."""


import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf import Sensor
from symkf.errors import AssumptionError, NotPositiveDefiniteError, ProbabilityError, ShapeError
from symkf.fusion import (FusionModel, expected_remote_covariance, fusion_sigma, fused_covariance, local_filters,
                          optimal_weights, pendulum_model, proposition1_bound, remote_error_covariance, simulate,
                          unbiasedness_matrix)
from symkf.fusion.covariance import stacked_bases
from symkf.fusion.local_filters import lemma2_iteration
from symkf.fusion.remote import RemoteFusion

A3 = [["11/10", "1/5", 0], [0, "9/10", 0], [0, 0, "1/2"]]


def small_model(arrival=("1/2", "3/5", "4/5")):
    sensors = [Sensor([[1, 0, 0]], name="a"), Sensor([[0, 0, 1]], [[2]], name="b"), Sensor([[0, 1, 1]], name="c")]
    return FusionModel.discrete(A3, [[1, 0, 0], [0, 1, 0], [0, 0, 1]], sensors, list(arrival))


@pytest.fixture(scope="module")
def small():
    return local_filters(small_model())


@pytest.fixture(scope="module")
def pendulum():
    return local_filters(pendulum_model())


def test_observable_dimensions_are_exact(small, pendulum):
    assert [loc.n_o for loc in small.model.local] == [2, 1, 2]
    # Section 4: x is invisible to velocity / angle sensors, sensors 2, 3, 5 see everything.
    assert [loc.n_o for loc in pendulum.model.local] == [3, 4, 4, 3, 4, 3, 3, 3, 3, 3]
    loc = small.model.local[0]
    assert sp.Matrix(loc.exact_basis).T * sp.Matrix([0, 0, 1]) == sp.zeros(2, 1)


def test_kalman_decomposition_is_block_lower_triangular(pendulum):
    m = pendulum.model
    for loc in m.local:
        V_un = np.linalg.svd(loc.V.T)[2][loc.n_o:].T          # orthonormal complement
        if V_un.size:
            assert np.abs(loc.V.T @ m.A @ V_un).max() < 1e-12   # V_o' A V_unobs = 0
        assert np.allclose(loc.V.T @ loc.V, np.eye(loc.n_o))


def test_collective_observability_failure_names_assumption():
    with pytest.raises(AssumptionError, match="Assumption 1"):
        FusionModel.discrete(A3, np.eye(3).astype(int).tolist(), [Sensor([[0, 0, 1]])], ["1/2"])


def test_singular_uncontrollable_Q_and_bad_rates():
    with pytest.raises(AssumptionError, match="Q > 0"):
        FusionModel.discrete(A3, [[0, 0, 0], [0, 0, 0], [0, 0, 1]], [Sensor([[1, 0, 0]]), Sensor([[0, 0, 1]])],
                             ["1/2", "1/2"])
    with pytest.raises(ProbabilityError, match=r"arrival\[1\]"):
        small_model(arrival=("1/2", "3/2", "1/2"))


def test_assumption2_exact_values():
    a2 = small_model().assumption2                       # (1 - 1/2) * (11/10)^2
    assert a2.exact == sp.Rational(121, 200) and a2.holds
    assert small_model(arrival=("1/10", "1", "1")).assumption2.holds is False   # 9/10 * 121/100 > 1


def test_dare_and_stein_agree_with_iterations(small):
    for loc, f, i in zip(small.model.local, small.filters, range(3)):
        X = np.eye(loc.n_o)
        for _ in range(2000):                                   # h_i(g~_i(X)), eqs. (7)-(8)
            X = loc.A @ (X - X @ loc.C.T @ np.linalg.inv(loc.C @ X @ loc.C.T + loc.R) @ loc.C @ X) @ loc.A.T + loc.Q
        assert np.allclose(X, f.P_pred, atol=1e-10)
        assert np.allclose(f.P, small.block(i, i), atol=1e-10)   # diagonal of the joint Stein solution
    assert np.allclose(lemma2_iteration(small, 0, 2, 3000), small.block(0, 2), atol=1e-10)
    assert np.abs(small.block(0, 2)).max() > 1e-2


@pytest.mark.parametrize("tau", [(0, 0, 0), (3, 0, 1), (0, 5, 2), (4, 4, 0)])
def test_holding_time_covariance_matches_propagation(small, tau):
    P = remote_error_covariance(small, tau)
    assert np.allclose(P, remote_error_covariance(small, tau, method="propagation"), rtol=1e-10, atol=1e-12)
    assert np.allclose(P, P.T) and np.linalg.eigvalsh(fusion_sigma(small, P))[0] > -1e-10   # Lemma 3


@pytest.mark.full
def test_expected_covariance_is_the_average_over_holding_times(small):
    lam = [float(x) for x in small.model.arrival]
    avg = np.zeros_like(small.Pi)
    for t0 in range(40):
        for t1 in range(25):
            for t2 in range(16):
                p = np.prod([l * (1 - l) ** t for l, t in zip(lam, (t0, t1, t2))])
                avg += p * remote_error_covariance(small, (t0, t1, t2))
    assert np.allclose(avg, expected_remote_covariance(small), rtol=1e-7, atol=1e-9)


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


def test_methods_agree_on_the_pendulum(pendulum):
    Sigma = fusion_sigma(pendulum, remote_error_covariance(pendulum, (0, 1, 0, 2, 0, 1, 0, 3, 0, 1)))
    Vo = unbiasedness_matrix(pendulum)
    traces = {m: np.trace(fused_covariance(Sigma, optimal_weights(Sigma, Vo, m)))
              for m in ("closed-form", "problem3", "sdp")}
    # 3.30624e-4 is the optimum computed at 300 bits (flint arb_mat) from the same float model.
    for m, t in traces.items():
        assert 3.3062e-4 <= t <= 3.3062e-4 * (1.02 if m == "sdp" else 1.001), (m, t)
    U, tr = RemoteFusion(pendulum).weights((0, 1, 0, 2, 0, 1, 0, 3, 0, 1))
    assert abs(tr - traces["closed-form"]) < 1e-3 * tr
    assert np.abs((stacked_bases(pendulum) @ U).T @ Vo - np.eye(4)).max() < 1e-8


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


def test_simulated_errors_match_predicted_covariance(small):
    # x grows like 1.1^k: beyond ~300 steps float rounding of x swamps the errors.
    sim = simulate(small, horizon=120, paths=200, seed=7)
    emp = (np.linalg.norm(sim.fused[:, 1:], axis=-1) ** 2).mean()
    pred = sim.trace_P[:, 1:].mean()
    assert abs(emp - pred) < 0.1 * pred                      # 24 000 correlated samples
    b = proposition1_bound(small)
    assert pred <= 1.1 * b.bound and b.bound < b.trace_expected_sigma
    single = (np.linalg.norm(sim.single[:, 1:, 0], axis=-1) ** 2).mean()
    assert emp < single                                      # sensor a cannot see x3




def test_reproduce_short(tmp_path):
    from symkf.fusion import reproduce_fusion_pendulum
    out = reproduce_fusion_pendulum(outdir=str(tmp_path), paths=4, horizon=150, seed=1)
    assert out["example"] == "fusion-pendulum" and len(out["results"]["figures"]) == 2
    assert out["checks"]["Assumption 2 holds: (1 - min lambda) rho(A)^2 < 1"]
    assert out["checks"]["closed form, SDP and Problem 3 reach the same optimum"]
    # the misprinted 0.5 x 1.00042 is a discrepancy with both values, not a failed check.  The
    # Monte Carlo check of boundedness is the full run's (test_reproduce_full): 4 paths over 150
    # steps cannot decide it (E||e||^2 sits near the bound; 2 of seeds 1..8 fail it either way)
    bounded = "fusion error stays bounded (second-half mean <= 1.5 x first-half mean, and E||e||^2 <= valid bound)"
    assert bounded in out["checks"]
    assert all(v for k, v in out["checks"].items() if k != bounded), out["checks"]
    [misprint] = out["discrepancies"]
    assert misprint["printed"] == "0.5 x 1.00042" and "0.5 x 1.000885" in misprint["computed"]


@pytest.mark.full
def test_reproduce_full():
    from symkf.fusion import reproduce_fusion_pendulum
    out = reproduce_fusion_pendulum()
    assert all(out["checks"].values()), out["checks"]
    assert [d["printed"] for d in out["discrepancies"]] == ["0.5 x 1.00042"]
