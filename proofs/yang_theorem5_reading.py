"""Yang et al., Theorems 5 and 6: "if C > h(A), {V_k} converges" needs the existential reading.

Claim (Theorem 5, eq. 28): "In particular, if C > h(A), {V_k} converges."  The
appendix proves: for a capacity C above sum_i max_j h(A_ij) there is *some*
allocation of rates (one with C_i > max_j h(A_ij) for every sensor) under which
V_k converges, and closes with h(A) = sum_ij h(A_ij) ">" sum_i max_j h(A_ij).

Findings, with exact certificates:
1. Read for the given rates, the sentence is false.  a = 2, two sensors with
   C_1 = C_2 = 1 and lambda_1 = lambda_2 = 11/20: C = ln(20/9) > ln 2 = h(A)
   exactly, yet condition 1) of Theorem 4 fails (exact dual certificate; by
   hand, min_L rho(T_L) = a^2 / (1 + q_1 + q_2) = 36/31 >= 1), so V_k diverges.
2. The existential reading holds there: theorem6_allocation gives rates with
   the same capacity ln(20/9) and C_i > r_i for which condition 1) is
   certified (exact primal certificate).
3. The appendix's strict ">" is a slip for ">=": for one sensor with scalar
   output on A = [[0, -2], [2, 0]] there is one block, so the two sides are
   both ln 4.
Method: exact certificates of symkf.capacity.convergence (LMI of Theorem 4)
and exact comparisons of algebraic numbers.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf import IID, Sensor, System  # noqa: E402
from symkf.capacity.convergence import mare_stabilizable  # noqa: E402
from symkf.capacity.quantities import capacity_exceeds, mahler_measure, transmission_capacity  # noqa: E402
from symkf.capacity.theorems import theorem5_requirements, theorem6_allocation  # noqa: E402


def main() -> bool:
    S = System(A=[[2]], sensors=[Sensor(C=[[1]]), Sensor(C=[[1]])])
    given = IID(["9/20", "9/20"])
    q = sp.Rational(11, 9)
    ok = capacity_exceeds(given, mahler_measure(S.A))
    ok &= 4 / (1 + 2 * q) == sp.Rational(36, 31)
    ok &= mare_stabilizable(S, given).holds is False
    alloc = theorem6_allocation(S, sp.Rational(20, 9))
    ok &= sp.simplify(transmission_capacity(alloc) - transmission_capacity(given)) == 0
    ok &= mare_stabilizable(S, alloc).holds is True
    R = System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])])
    ok &= sp.simplify(sum(theorem5_requirements(R)) - sp.log(mahler_measure(R.A).exact)) == 0
    print("PASS" if ok else "FAIL", "- C > h(A) does not make V_k converge for the given rates "
          "(lambda = 11/20, 11/20 on a = 2); some allocation of the same capacity does")
    return bool(ok)


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
