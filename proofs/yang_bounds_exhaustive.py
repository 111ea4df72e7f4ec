"""Yang et al.: Proposition 1, Theorem 3 and Remark 3 by exhaustive enumeration of losses.

Claims: for i.i.d. arrivals ``lambda_i`` and every k,
* Proposition 1: ``G_k <= E[P_k^-]`` (``G_1 = 0``, ``G_{k+1} = prod(1 - lambda_i) A G_k A' + Q``);
* Theorem 3: ``E[P_k^-] <= V_k`` (``V_1 = P_1^-``, ``V_{k+1} = g_lambda(V_k)``, eq. 18);
* Remark 3: ``F_k <= E[P_k^-]`` (``F_{k+1} = A (F_k^{-1} + sum lambda_i S_i)^{-1} A' + Q``).

Remark 3 is justified in the paper by the convexity of ``gbar(X; S)`` in ``S``,
which alone does not carry the induction (``gbar`` is concave in ``X``, so
``E gbar(P_k) <= gbar(E P_k)``).  It holds nevertheless: in information form
``Y_{k+1} = (A (Y_k + S_k)^{-1} A' + Q)^{-1}`` is jointly operator-concave and
monotone in ``(Y_k, S_k)`` (a parallel sum), so ``Y_k`` is jointly concave in
``(S_1, ..., S_{k-1})``, ``P_k = Y_k^{-1}`` jointly convex, and Jensen gives
``E P_k >= P_k(E S_1, ..., E S_{k-1}) = F_k``.

Method: exhaustive enumeration of every receival pattern over k <= 6 steps
(2^(N k) sequences, exact probabilities), covariances by the float64 filter of
:mod:`symkf.numeric.filters`; each Loewner inequality is checked through the
smallest eigenvalue with tolerance 1e-9 times the matrix scale.  Family: the
systems listed in FAMILY (two sensors each, stable and unstable A, scalar and
vector outputs, non-identity R).
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

from symkf import IID, Sensor, System  # noqa: E402
from symkf.capacity.lower import information_lower_bound_sequence, lower_bound_sequence  # noqa: E402
from symkf.capacity.mare import MARE  # noqa: E402
from symkf.numeric.filters import predicted_covariances  # noqa: E402

R = sp.Rational
FAMILY = [
    (System(A=[[2]], sensors=[Sensor(C=[[1]]), Sensor(C=[[2]], R=[[3]])]), ["1/3", "1/2"]),
    (System(A=[[R(6, 5), 1], [0, R(-1, 2)]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[0, 1], [1, 1]], R=[[2, 1], [1, 2]])],
            Q=[[1, R(1, 2)], [R(1, 2), 2]], P0=[[3, 0], [0, 1]]), ["1/4", "3/5"]),
    (System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]]), Sensor(C=[[1, 1]])]), ["1/10", "1/5"]),
    (System(A=[[R(1, 2), 1], [0, R(-9, 10)]], sensors=[Sensor(C=[[1, 2]]), Sensor(C=[[1, 0]])]), ["7/10", "9/10"]),
]
HORIZON = 6


def _min_eig(M: np.ndarray) -> float:
    return float(np.linalg.eigvalsh((M + M.T) / 2)[0])


def check(system: System, losses: list[str]) -> bool:
    loss = IID(losses)
    d, K = system.d, HORIZON
    patterns = np.array(list(itertools.product((0, 1), repeat=d * K)), dtype=bool).reshape(-1, K, d)
    arrival = np.array([float(1 - R(e)) for e in losses])
    prob = np.prod(np.where(patterns, arrival, 1 - arrival), axis=(1, 2))
    P = predicted_covariances(system, patterns, keep="all")
    EP = np.einsum("p,pkij->kij", prob, P)
    G = lower_bound_sequence(system, loss, K)
    V = MARE(system, loss).sequence(K)
    F = information_lower_bound_sequence(system, loss, K)
    ok = True
    for k in range(K):
        tol = 1e-9 * max(1.0, np.abs(V[k]).max())
        for name, gap in (("G_k <= E P_k", EP[k] - G[k]), ("E P_k <= V_k", V[k] - EP[k]),
                          ("F_k <= E P_k", EP[k] - F[k])):
            if _min_eig(gap) < -tol:
                print(f"FAIL: {name} at k = {k + 1} for {system.A.tolist()}: min eig {_min_eig(gap):.3g}")
                ok = False
    return ok


def main() -> bool:
    ok = all([check(S, losses) for S, losses in FAMILY])
    print("PASS" if ok else "FAIL", f"- G_k <= E[P_k^-] <= V_k and F_k <= E[P_k^-] for k <= {HORIZON}, "
          f"all loss patterns, {len(FAMILY)} systems")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
