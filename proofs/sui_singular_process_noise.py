"""A singular process noise Q >= 0 leaves the verdicts of Sui-You-Fu's Theorems 4 and 7 unchanged
when P0 > 0, except for undriven modes on the unit circle.

Claim.  Let ``R > 0``, ``P0 > 0`` and ``Q >= 0`` (Sui-You-Fu assume ``Q > 0``, Section II).  For every
loss process, ``sup_k E[P_k]`` is finite for ``Q`` iff it is finite for ``Q + I``, unless an
eigen-block of modulus 1 that holds a mode not driven by ``Q`` (PBH on ``(A, Q^(1/2))``) has margin
``alpha^2 rho >= 1``; there the two can differ.

Argument.
(a) *Stable for Q + I implies stable for Q.*  For a fixed receival sequence the Riccati recursion
    ``P_{k+1} = A (P_k^(-1) + C_g' R^(-1) C_g)^(-1) A' + Q`` is monotone in ``P_k`` and in ``Q``, so
    ``P_k(Q) <= P_k(Q + I)`` pathwise and in expectation.
(b) *Unstable for Q + I implies unstable for Q*, off the exception.  The necessity half of
    Theorems 4 and 7 (Sui-You-Fu, proof of Theorem 4, eq. 28) uses ``Q > 0`` once: ``P_N >= p I``
    for all ``N``, through ``x' P_N x`` for ``x`` in the generalized eigenspace ``V_u`` of the blocks
    with ``|lambda| > 1`` whose growth ``alpha^(2N)`` it bounds.  That bound holds for ``Q = 0``
    (hence, by (a)'s monotonicity, for every ``Q >= 0``): write ``z = (z_s, z_u)`` along
    ``V_s + V_u`` (``V_s`` the blocks with ``|lambda| <= 1``).  Conditioning on ``z_s(0)`` lowers the
    error covariance of ``z_u``; with ``Q = 0`` it then makes ``z_s(k) = A_s^k z_s(0)`` known, leaving the
    filter of ``z_u`` alone, with ``A_u`` invertible, prior covariance the Schur complement ``S > 0``, and
    information
        ``J_k = A_u^(-k)' S^(-1) A_u^(-k) + sum_{j<k} gamma_j A_u^(-(k-j))' C_u' R^(-1) C_u A_u^(-(k-j))``
        ``    <= sup_k |A_u^(-k)|^2 |S^(-1)| I + G,   G = A_u^(-1)' (G + C_u' R^(-1) C_u) A_u^(-1)``,
    finite because ``A_u^(-1)`` is stable.  So the covariance of ``z_u`` is at least ``(sup J)^(-1) > 0``
    at every step of every sequence, and eq. (28) follows as printed.  A block of modulus 1 never has
    a margin above 1 that grows (``alpha = 1``); its margin 1 means a deficiency with probability 1,
    where ``Q > 0`` adds noise every step (linear growth) and an undriven mode may add none.
(c) *The exception is real*: ``A = diag(2, 1)``, the unit mode seen only by a sensor that never
    reports, ``Q = diag(1, 0)``: the unit mode's error stays at ``P0``'s entry for ever, while with
    ``Q + I`` it grows by 1 per step.  symkf refuses that verdict (``symkf.stability``) and the
    detectability failure of an unseen undriven unit mode says so (``System.check_detectable``).

Checks (exact arithmetic, every receival sequence up to the length given):
1. (a) on the constant-velocity tracker ``Q = G G'``, ``G = (1/2, 1)'`` (rank 1, ``(A, G)``
   controllable), one position sensor: ``P_k(Q + I) - P_k(Q) >= 0`` for all ``2^6`` sequences.
2. (b)'s bound on ``A = diag(2, 6/5)``, ``C = [1 1]``, ``Q = 0`` (both modes undriven), ``P0 = I``:
   ``P_k - (I + G)^(-1) >= 0`` for all ``2^8`` sequences, ``G`` the exact solution of its Stein equation
   (``|A^(-k)| <= 1`` here).
3. (c): ``P_k[1, 1] = 1`` for ``Q = diag(1, 0)`` and ``1 + k`` for ``Q + I``.
4. The engine: the verdicts and critical values of symkf with the singular ``Q`` equal those with
   ``Q = I`` on 1 and 2, and the assumption line names the undriven modes.

Status: proved by the argument; the script checks its inequalities exactly on the examples
(the simulation on both sides of the threshold is in tests/numeric/test_verify.py).
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

import symkf as sk  # noqa: E402
from symkf.numeric.filters import exact_covariances  # noqa: E402

R = sp.Rational


def psd(M: sp.Matrix) -> bool:
    """2x2 symmetric ``M >= 0``: nonnegative diagonal and determinant."""
    M = sp.simplify(M)
    return M[0, 0] >= 0 and M[1, 1] >= 0 and sp.simplify(M.det()) >= 0


def monotone_in_Q() -> bool:
    G = sp.Matrix([R(1, 2), 1])
    Q = G * G.T
    A, sensors = [[1, 1], [0, 1]], [sk.Sensor(C=[[1, 0]])]
    singular, shifted = sk.System(A=A, sensors=sensors, Q=Q), sk.System(A=A, sensors=sensors, Q=Q + sp.eye(2))
    ok = True
    for seq in itertools.product([0, 1], repeat=6):
        rec = [[g] for g in seq]
        ok &= all(psd(b - a) for a, b in zip(exact_covariances(singular, rec), exact_covariances(shifted, rec)))
    print(f"{'ok ' if ok else 'BAD'} (a) P_k(Q) <= P_k(Q + I) on the tracker, all 64 sequences of length 6")
    return ok


def information_bound() -> bool:
    A = sp.diag(2, R(6, 5))
    C = sp.Matrix([[1, 1]])
    S = sk.System(A=A, sensors=[sk.Sensor(C=C)], Q=sp.zeros(2, 2))
    Ai = A.inv()
    g = sp.Matrix(sp.symbols("g0:4")).reshape(2, 2)
    G = g.subs(sp.solve(list(g - Ai.T * (g + C.T * C) * Ai), list(g)))
    floor = (sp.eye(2) + G).inv()
    ok = all(psd(P - floor) for seq in itertools.product([0, 1], repeat=8)
             for P in exact_covariances(S, [[x] for x in seq]))
    print(f"{'ok ' if ok else 'BAD'} (b) Q = 0 on diag(2, 6/5): P_k >= (I + G)^(-1) = {floor.tolist()} "
          "on all 256 sequences of length 8")
    return ok


def unit_circle_exception() -> bool:
    A, sensors = sp.diag(2, 1), [sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]])]
    rec = [[1, 0]] * 8
    undriven = exact_covariances(sk.System(A=A, sensors=sensors, Q=sp.diag(1, 0)), rec)
    driven = exact_covariances(sk.System(A=A, sensors=sensors, Q=sp.diag(2, 1)), rec)
    ok = [P[1, 1] for P in undriven] == [1] * 9 and [P[1, 1] for P in driven] == list(range(1, 10))
    print(f"{'ok ' if ok else 'BAD'} (c) unseen unit mode: P_k[1,1] = 1 undriven, 1 + k driven")
    return ok


def engine_unchanged() -> bool:
    G = sp.Matrix([R(1, 2), 1])
    cases = [([[1, 1], [0, 1]], [[1, 0]], G * G.T, "controllable"),
             ([[2, 0], [0, R(6, 5)]], [[1, 1]], sp.zeros(2, 2), "2, 6/5 not driven")]
    ok = True
    for A, C, Q, said in cases:
        singular = sk.System(A=A, sensors=[sk.Sensor(C=C)], Q=Q)
        positive = sk.System(A=A, sensors=[sk.Sensor(C=C)])
        same = sk.critical_loss_rate(singular) == sk.critical_loss_rate(positive)
        for eps in [R(1, 5), R(3, 10), R(9, 10)]:
            a, b = sk.stability(singular, sk.IID([eps])), sk.stability(positive, sk.IID([eps]))
            same &= a.stable == b.stable and a.margins == b.margins
        line = sk.stability(singular, sk.IID([R(1, 5)])).assumptions
        named = any(said.split(" not")[0] in s and "Q singular" in s for s in line)
        ok &= same and named
        print(f"{'ok ' if same and named else 'BAD'} engine on A = {A}: critical value "
              f"{sk.critical_loss_rate(singular).exact} with Q = {Q.tolist()} and with Q = I")
    return ok


def main() -> bool:
    ok = monotone_in_Q() & information_bound() & unit_circle_exception() & engine_unchanged()
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
