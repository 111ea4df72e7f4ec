"""Baseline for ``simulate_traces``: the float64 covariance-form filter in NumPy, all paths at once.

The strongest plain-NumPy version we know: ``P`` packed as ``vech P`` with one column per path,
so the time update ``A P A^T + Q`` is one GEMM with the congruence matrix of ``A`` on packed
symmetric matrices, and each whitened measurement row ``h`` is a rank-one update
``P <- P - gamma (P h)(P h)^T / (h^T P h + 1)`` (Yang et al. eq. 8, rows independent after
whitening): one GEMM for ``P h`` and elementwise work on the packed entries.  Receptions are
drawn vectorised over paths, one step at a time (i.i.d.: one comparison; Gilbert-Elliott: the
previous reception chooses the threshold).  No log-scale, no PSD checks: it is the fast textbook
route the square-root kernel is measured against.  Import numpy only after fixing BLAS to one
thread (``OPENBLAS_NUM_THREADS=1`` etc.): ``bench_simulate.py`` does.
"""

from __future__ import annotations

import numpy as np


def packing(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Row and column of each packed entry (i <= j)."""
    return np.triu_indices(n)


def congruence(A: np.ndarray) -> np.ndarray:
    """``T`` with ``vech(A P A^T) = T vech(P)`` for symmetric ``P``."""
    n = A.shape[0]
    r, c = packing(n)
    T = np.einsum("ak,bl->abkl", A, A)                       # (A P A^T)_ab = sum_kl A_ak A_bl P_kl
    full = T[r, c]                                            # (N, n, n)
    return np.where(r == c, full[:, r, c], full[:, r, c] + full[:, c, r])


def row_product(h: np.ndarray) -> np.ndarray:
    """``G`` (n, N) with ``P h = G vech(P)``."""
    n = h.size
    r, c = packing(n)
    G = np.zeros((n, r.size))
    G[r, np.arange(r.size)] += h[c]
    off = r != c
    G[c[off], np.flatnonzero(off)] += h[r[off]]
    return G


def receptions_step(rng: np.random.Generator, prev: np.ndarray | None, stay: np.ndarray, back: np.ndarray,
                    first: np.ndarray, paths: int) -> np.ndarray:
    """Receptions (d, paths) of one step: P(received) = first, then stay (after a reception) or back."""
    u = rng.random((stay.size, paths))
    if prev is None:
        return u < first[:, None]
    return u < np.where(prev, stay[:, None], back[:, None])


def trace_batch(A: np.ndarray, Q: np.ndarray, P0: np.ndarray, H: np.ndarray, row_sensor: np.ndarray,
                horizon: int, paths: int, stay: np.ndarray, back: np.ndarray, first: np.ndarray,
                seed: int) -> np.ndarray:
    """``tr P_{k|k-1}`` (paths, horizon) of the covariance-form filter on receptions it draws."""
    n = A.shape[0]
    r, c = packing(n)
    diag = np.flatnonzero(r == c)
    T = congruence(A)
    q = Q[r, c][:, None]
    G = [row_product(h) for h in H]
    V = np.repeat(P0[r, c][:, None], paths, axis=1)
    out = np.empty((horizon, paths))
    rng = np.random.default_rng(seed)
    got = None
    Ph = np.empty((n, paths))
    for k in range(horizon):
        np.sum(V[diag], axis=0, out=out[k])
        got = receptions_step(rng, got, stay, back, first, paths)
        for j, s in enumerate(row_sensor):
            np.matmul(G[j], V, out=Ph)
            scale = got[s] / (H[j] @ Ph + 1.0)
            V -= Ph[r] * (Ph[c] * scale)
        V = T @ V
        V += q
    return out.T
