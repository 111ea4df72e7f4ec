"""The multi-sensor MARE and the upper bound V_k (symkf.capacity.mare; Yang et al., eqs. 18-21,
Lemma 1, Theorem 3): E[Gamma X Gamma] = Lambda (W o X) Lambda by enumeration, the printed form and
Sinopoli et al.'s, monotone and concave, its fixed point and divergence."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf import IID, Sensor, System
from symkf.capacity import MARE, hadamard_weight
from symkf.errors import AssumptionError

R = sp.Rational


def test_weight_matrix_is_second_moment_of_gamma():
    """E[Gamma X Gamma] = Lambda (W o X) Lambda, by enumeration of the receival patterns."""
    dims, arrival = [1, 2], [R(1, 3), R(3, 4)]
    W = hadamard_weight(IID([1 - a for a in arrival]), dims)
    X = sp.Matrix(3, 3, lambda i, j: R(i + 2 * j + 1, i * j + 2))
    E = sp.zeros(3, 3)
    for g in itertools.product((0, 1), repeat=2):
        p = sp.Mul(*[a if gi else 1 - a for gi, a in zip(g, arrival)])
        Gam = sp.diag(g[0], g[1], g[1])
        E += p * Gam * X * Gam
    Lam = sp.diag(arrival[0], arrival[1], arrival[1])
    assert E == Lam * W.multiply_elementwise(X) * Lam


def test_mare_equals_printed_form_and_sinopoli():
    S = System(A=[[R(6, 5), 1], [0, R(-1, 2)]], sensors=[Sensor(C=[[1, 0]], R=[[2]]),
                                                        Sensor(C=[[0, 1], [1, 1]], R=[[2, 1], [1, 2]])])
    loss = IID(["1/4", "3/5"])
    g = MARE(S, loss)
    X = np.array([[2.0, 0.3], [0.3, 1.0]])
    from scipy.linalg import sqrtm
    H = np.vstack([np.linalg.inv(sqrtm(np.array(s.R, dtype=float))) @ np.array(s.C, dtype=float)
                   for s in S.sensors])
    A = np.array(S.A, dtype=float)
    printed = A @ X @ A.T + np.eye(2) - A @ X @ H.T @ np.linalg.solve(g.W * (H @ X @ H.T + np.eye(3)), H @ X @ A.T)
    assert np.allclose(g(X), printed, rtol=1e-12)
    one = System(A=[[2, 1], [0, 3]], sensors=[Sensor(C=[[1, 1]], R=[[3]])])
    lam = 0.7
    Hs = np.array([[1.0, 1.0]]) / np.sqrt(3)
    A1 = np.array([[2.0, 1.0], [0.0, 3.0]])
    eq32 = A1 @ X @ A1.T + np.eye(2) - lam * A1 @ X @ Hs.T @ np.linalg.solve(Hs @ X @ Hs.T + 1, Hs @ X @ A1.T)
    assert np.allclose(MARE(one, IID(["3/10"]))(X), eq32, rtol=1e-12)


def _spd(seed_entries):
    M = np.array(seed_entries, dtype=float).reshape(2, 2)
    return M @ M.T + 0.1 * np.eye(2)


MARE_EX = MARE(System(A=[[R(6, 5), 1], [0, R(-1, 2)]],
                      sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1], [1, 1]], R=[[2, 1], [1, 2]])]),
               IID(["1/4", "3/5"]))
ENTRIES = st.lists(st.floats(-3, 3, allow_nan=False), min_size=4, max_size=4)


@settings(max_examples=60, deadline=None)
@given(ENTRIES, ENTRIES, st.floats(0.05, 0.95))
def test_lemma1_monotone_and_concave(a, b, alpha):
    X, D = _spd(a), _spd(b)
    Y = X + D
    tol = 1e-9 * (1 + np.abs(Y).max()) ** 2
    assert np.linalg.eigvalsh(MARE_EX(Y) - MARE_EX(X))[0] >= -tol                    # Lemma 1, 1)
    Z = alpha * X + (1 - alpha) * Y
    gap = MARE_EX(Z) - alpha * MARE_EX(X) - (1 - alpha) * MARE_EX(Y)
    assert np.linalg.eigvalsh(gap)[0] >= -tol                                           # Lemma 1, 2)


def test_mare_fixed_point_and_divergence():
    S = System(A=[[2]], sensors=[Sensor(C=[[1]])])
    V = MARE(S, IID(["1/8"])).fixed_point()
    # scalar MARE: V = 4V + 1 - (7/8) 4 V^2/(V+1)  =>  7 V^2/2 - 5 V - 1 = 0 ... solved exactly:
    x = sp.Symbol("x", positive=True)
    root = max(sp.solve(sp.Eq(x, 4 * x + 1 - R(7, 8) * 4 * x ** 2 / (x + 1)), x))
    assert V[0, 0] == pytest.approx(float(root), rel=1e-9)
    with pytest.raises(AssumptionError, match="Theorem 4"):
        MARE(S, IID(["3/10"])).fixed_point(max_iter=20_000)
