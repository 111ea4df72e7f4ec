"""Yang et al., Lemma 2 and Corollary 2: when do the critical capacities meet?

Claim (Lemma 2): "When A has only one unstable eigenvalue, ln rho(A) = h(A)"
(the lower critical capacity, eq. 16, equals the upper, eq. 29).
Corollary 2: for a first-order unstable system they meet.

Method: exhaustive exact check over every integer 2x2 matrix with entries in
{-2, ..., 2} (625 matrices) and every scalar a in {-3, ..., 3} / {1/2, 3/2}:
``capacity_bounds_meet(A)`` (exact comparison of rho(A) and M(A) as algebraic
numbers) is compared with the characterisation "exactly one eigenvalue of
modulus > 1 counted with algebraic multiplicity, or rho(A) = 1".

Finding: Lemma 2 holds only when "one unstable eigenvalue" counts
multiplicity.  A = 2 I has a single distinct unstable eigenvalue, yet
rho(A) = 2 < M(A) = 4, so ln rho(A) = ln 2 < h(A) = ln 4.
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf.capacity.quantities import mahler_measure, spectral_radius  # noqa: E402
from symkf.capacity.theorems import capacity_bounds_meet, unstable_count  # noqa: E402
from symkf.exact.spectral import eigenvalues  # noqa: E402


def main() -> bool:
    ok = True
    for e in itertools.product(range(-2, 3), repeat=4):
        A = [[e[0], e[1]], [e[2], e[3]]]
        predicted = unstable_count(A) == 1 or spectral_radius(A) == 1
        if capacity_bounds_meet(A) != predicted:
            print(f"FAIL: characterisation wrong for A = {A}")
            ok = False
    for a in [-3, -2, 2, 3, sp.Rational(3, 2), sp.Rational(-3, 2)]:  # Corollary 2
        ok &= capacity_bounds_meet([[a]])
    A = [[2, 0], [0, 2]]
    distinct_unstable = sum(1 for ev in eigenvalues(A) if ev.modulus > 1)
    counter = distinct_unstable == 1 and spectral_radius(A) == 2 and mahler_measure(A) == 4
    ok &= counter and not capacity_bounds_meet(A)
    print("PASS" if ok else "FAIL", "- Lemma 2 holds with multiplicity; A = 2I (one distinct unstable "
          "eigenvalue) has ln rho = ln 2 < h(A) = ln 4")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
