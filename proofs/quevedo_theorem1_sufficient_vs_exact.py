"""Quevedo-Ahlén-Johansson, Theorem 1 (eq. 22) is sufficient: it implies exact stability.

Claim: for a Markov network state (Assumption 1) and a time-invariant A, if
max_i nu_i ||A||^2 < 1 (eq. 22) then the Kalman filter is stable -- so the set of
parameters where Theorem 1 holds lies inside the set where the exact
necessary-and-sufficient verdict (Sui-You-Fu Theorems 4, 7, 9 with eq. 36,
`symkf.engine.stability.stability` on `induced_loss(...)`) says stable.  Also checked:
Theorem 2 (eq. 32, corrected) with psi_j(1) = 1 gives the same set as Theorem 1
(Sec. VII-B), and the exact stable sets of `symkf.network.compare` agree with the
engine pointwise.

Source: Quevedo, Ahlén, Johansson, Sec. V (Theorem 1, eqs. 20-22), Sec. VI (Corollary 1), Sec. VII-B.

Method: exhaustive check over the stated finite family
`symkf.network.compare.FAMILY` (nine sensor-network examples: scalar and 2x2 and
3x3 A, one, two and five sensors, i.i.d., Gilbert-Elliott and fading two-state
channels, a relay tree, Example 3's tree), each with one parameter t in (0, 1):
(a) exact containment of Theorem 1's set (polynomial inequalities, algebraic end
points) in the exact stable set (algebraic end points from
det(I - alpha^(2g) M_H(t)) = 0, gaps classified by the engine);
(b) pointwise at t = k/10, k = 1..9: `theorem1(...).holds` implies
`stability(...).stable`, and membership in the exact set equals the verdict.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf.network.compare import FAMILY, compare, describe, t  # noqa: E402
from symkf.network.conditions import theorem1  # noqa: E402
from symkf.engine.stability import stability  # noqa: E402


def _inside(intervals, v) -> bool:
    return any(lo < v and v < hi for lo, hi in intervals)


def main() -> bool:
    ok = True
    for ex in FAMILY:
        c = compare(ex)
        same = len(c.theorem1) == len(c.theorem2) and all(
            a == b for x, y in zip(c.theorem1, c.theorem2) for a, b in zip(x, y))
        row = c.sufficient_inside_exact and same
        for k in range(1, 10):
            v = sp.Rational(k, 10)
            holds = theorem1(ex.loss.subs({t: v}), ex.dynamics).holds
            stable = stability(ex.system, ex.at(v)).stable
            row = row and (stable or not holds) and _inside(c.exact, v) == stable and _inside(c.theorem1, v) == holds
        print(("PASS" if row else "FAIL") + f": {ex.name}: Theorem 1 {describe(c.theorem1)}; exact {describe(c.exact)}")
        ok &= row
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
