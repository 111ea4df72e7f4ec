"""Quevedo-Ahlén-Johansson, end of the proof of Theorem 1: the constants in (18).

Claim: from (43), E{V_k} <= rho^k V_0 + beta_bar (1 - rho^k)/(1 - rho), "(18) holds
with alpha = rho V_0 and beta = beta_bar/(1 - rho)".

Method: symbolic.  (43) at k = 0 is the equality E{V_0} = V_0 = tr P0, so (18) with
alpha = rho V_0 needs V_0 <= rho V_0 + beta_bar/(1 - rho), which fails for
V_0 > beta_bar/(1 - rho)^2 (e.g. rho = 1/2, beta_bar = 1, V_0 = 5: 5 > 9/2).
With alpha = V_0 the bound follows for every k: the difference
V_0 rho^k + beta_bar/(1-rho) - (rho^k V_0 + beta_bar (1-rho^k)/(1-rho)) = beta_bar rho^k/(1-rho) >= 0.

Finding: a slip in the constant (alpha should be V_0, not rho V_0); the theorem
is unaffected, since exponential boundedness only asks for some finite alpha.
"""

from __future__ import annotations

import sympy as sp


def main() -> bool:
    rho, bbar, V0 = sp.symbols("rho beta_bar V_0", positive=True)
    k = sp.Symbol("k", integer=True, nonnegative=True)
    bound43 = rho ** k * V0 + bbar * (1 - rho ** k) / (1 - rho)
    printed = rho * V0 * rho ** k + bbar / (1 - rho)
    fixed = V0 * rho ** k + bbar / (1 - rho)
    vals = {rho: sp.Rational(1, 2), bbar: 1, V0: 5}
    fails = (bound43.subs(k, 0) - printed.subs(k, 0)).subs(vals) > 0
    print(("PASS" if fails else "FAIL") + ": alpha = rho V_0 does not follow from (43) at k = 0 "
          "(rho = 1/2, beta_bar = 1, V_0 = 5)")
    gap = sp.simplify(fixed - bound43 - bbar * rho ** k / (1 - rho))
    print(("PASS" if gap == 0 else "FAIL") + ": alpha = V_0 gives (18) with slack beta_bar rho^k/(1 - rho)")
    ok = bool(fails) and gap == 0
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
