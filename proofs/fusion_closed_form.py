"""Claim: Theorem 2 of the fusion paper (arXiv:2012.04896) (via Lemma 5, Albert 1973) solves Problem 1.

Source: Optimal linear sensor fusion over lossy channels (arXiv:2012.04896), Problem 1 and eq. (27):
``W* = [I - (M Sigma M)^+ M Sigma] (V_o')^+``, ``M = I - V_o V_o^+``, is a
minimiser of ``tr(W' Sigma W)`` subject to ``W' V_o = I`` for singular PSD
``Sigma`` and full-column-rank ``V_o``.

Method: exact rational arithmetic (sympy pseudo-inverses) over a stated
family: 12 seeded random instances with n = 2, N = 2 or 3 sensors, rational
orthonormal bases V_i (coordinate axes or the rotation (3/5, 4/5)),
Sigma = Diag(V_i) P Diag(V_i)' with P = L L' (L random integer, possibly rank
deficient).  For each, W* satisfies the KKT conditions of the convex QP
exactly: ``W*' V_o = I`` and ``M Sigma W* = 0`` (i.e. ``2 Sigma W* = V_o Lambda'``
for some Lambda), which are sufficient for optimality.  The general argument
(``(M Sigma M)^+ = M (M Sigma M)^+`` and ``(M Sigma M)^+ V_o = 0``) is in
``symkf/fusion/weights.py``.

symkf's own code is then run on each instance: ``symkf.fusion.optimal_weights``
(``method="closed-form"``, the same formula computed in floating point through an
orthonormal basis of null(V_o')) must give ``W' V_o = I`` and the exact optimal
``P* = W*' Sigma W*`` (unique although ``W*`` is not) to ``1e-9`` relative.  So the
formula is checked exactly and symkf's implementation of it to rounding.
"""

import random
import sys
from pathlib import Path

import numpy as np
import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from symkf.fusion.weights import fused_covariance, optimal_weights  # noqa: E402

TOL = 1e-9

BASES = [sp.Matrix([[1], [0]]), sp.Matrix([[0], [1]]), sp.Matrix([[sp.Rational(3, 5)], [sp.Rational(4, 5)]]),
         sp.eye(2)]


def instance(rng: random.Random):
    N = rng.choice([2, 3])
    Vs = [rng.choice(BASES) for _ in range(N)]
    if not any(V.shape[1] == 2 for V in Vs) and sp.Matrix.hstack(*Vs).rank() < 2:
        Vs[0] = sp.eye(2)
    total = sum(V.shape[1] for V in Vs)
    L = sp.Matrix(total, rng.choice([total, total - 1]), lambda i, j: rng.randint(-3, 3))
    Vblk = sp.diag(*Vs)
    Sigma = Vblk * L * L.T * Vblk.T
    Vo = sp.Matrix.vstack(*[V * V.T for V in Vs])
    return Sigma, Vo


def main() -> bool:
    rng = random.Random(3)
    ok = True
    for k in range(12):
        Sigma, Vo = instance(rng)
        if Vo.rank() < 2:
            continue
        nN = Sigma.shape[0]
        M = sp.eye(nN) - Vo * Vo.pinv()
        W = (sp.eye(nN) - (M * Sigma * M).pinv() * M * Sigma) * Vo.T.pinv()
        feasible = sp.simplify(W.T * Vo - sp.eye(2)) == sp.zeros(2, 2)
        stationary = sp.simplify(M * Sigma * W) == sp.zeros(nN, 2)
        P = sp.simplify(W.T * Sigma * W)
        Sf, Vf = np.array(Sigma, dtype=float), np.array(Vo, dtype=float)
        Wf = optimal_weights(Sf, Vf)
        scale = max(1.0, float(max(abs(v) for v in P)))
        implemented = (np.abs(Wf.T @ Vf - np.eye(2)).max() < TOL
                       and np.abs(fused_covariance(Sf, Wf) - np.array(P, dtype=float)).max() < TOL * scale)
        ok &= feasible and stationary and implemented
        print(f"instance {k}: nN = {nN}, rank Sigma = {Sigma.rank()}, W'Vo = I: {feasible}, "
              f"M Sigma W = 0: {stationary}, tr P* = {P.trace()}, symkf.fusion agrees: {implemented}")
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
