"""Claim checked: Assumption 2 for the inverted pendulum of the fusion paper (arXiv:2012.04896), Section 4.

Source: Optimal linear sensor fusion over lossy channels (arXiv:2012.04896), Section 4: "(1 - min lambda_i) rho^2(A) = 0.5 x 1.00042 < 1".

Finding: Assumption 2 holds, but the number is ``exp(2 s / 1000) / 2`` with
``s`` the largest real root of ``3505 x^3 + 501 x^2 - 686 x - 98`` (the unstable
pendulum pole of ``A_c``, g = 49/5), i.e. ``0.5 x 1.000885...``; the printed
1.00042 is neither rho(A)^2 = 1.000885 nor rho(A) = 1.000442.

Method: exact expression and certified interval (python-flint balls around the
roots of the characteristic polynomial of the exact ``A_c``; rho(exp(A_c Ts)) =
exp(Ts max Re eig A_c)), ``symkf.fusion.FusionModel.assumption2``; the interval
is compared with 0.5 x 1.00042 exactly.
"""

import sys
from fractions import Fraction
from pathlib import Path

import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def main() -> bool:
    from symkf.fusion import pendulum_model
    from symkf.fusion.pendulum import pendulum_continuous
    a2 = pendulum_model().assumption2
    lo, hi = a2.interval
    x = sp.Symbol("x")
    s = sp.CRootOf(sp.Poly(3505 * x**3 + 501 * x**2 - 686 * x - 98, x), 2)
    charpoly_ok = sp.factor(pendulum_continuous()[0].charpoly(x).as_expr()) == sp.factor(
        x * (3505 * x**3 + 501 * x**2 - 686 * x - 98) / 3505)
    expected = sp.exp(2 * s / 1000) / 2
    printed = Fraction(1, 2) * Fraction(100042, 100000)
    print(f"exact value {a2.exact} in [{float(lo):.12f}, {float(hi):.12f}] "
          f"(= 0.5 x {2 * float(lo):.9f}); printed 0.5 x 1.00042 = {float(printed)}")
    ok = (charpoly_ok and sp.simplify(a2.exact - expected) == 0 and hi < 1 and a2.holds
          and not lo <= printed <= hi and hi - lo < Fraction(1, 10**12))
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
