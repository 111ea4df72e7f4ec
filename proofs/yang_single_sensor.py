"""Yang et al., Section III-E: the single-sensor reduction lambda_bar = 1 - 1/M(A)^2.

Claim: for N = 1 the MARE (18) reduces to Sinopoli's (32) and Theorem 5 turns
the LMI upper bound on the critical arrival rate into the closed form
``lambda_bar = 1 - 1/M(A)^2`` (beside Sinopoli's lower bound
``lambda_low = 1 - 1/rho(A)^2``): for ``lambda > lambda_bar`` the bound V_k
converges.  For scalar measurements ``lambda_bar`` is exact for V_k
(Corollary 1; Elia's theorem).

Scope: (a) is proved (a symbolic identity) for scalar systems, n = 1; (b) and (c)
are checked, not proved, for n = 2 on the six systems of ``FAMILY``.

Method:
(a) symbolic identity, n = 1: ``min_l (a - lambda l h)^2 + lambda (1 - lambda) l^2 h^2
    = a^2 (1 - lambda)``, so condition 1) of Theorem 4 is ``lambda > 1 - 1/a^2``;
(b) exact certificates on a stated family of 2x2 systems: at loss
    ``(1 - lambda_bar) * 4/5`` condition 1) is certified true (exact LMI
    certificate); for the scalar-output members, at loss ``(1 - lambda_bar) * 5/4``
    it is certified false (exact dual certificate);
(c) ``lambda_low <= lambda_bar`` exactly on the family.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf import IID, Sensor, System  # noqa: E402
from symkf.capacity.convergence import mare_stabilizable  # noqa: E402
from symkf.capacity.theorems import single_sensor_rates  # noqa: E402

R = sp.Rational
FAMILY = [  # (A, C, scalar output)
    ([[0, -2], [2, 0]], [[1, 0]], True),
    ([[R(5, 4), 0], [1, R(11, 10)]], [[1, 1]], True),
    ([[2, 0], [0, 3]], [[1, 1]], True),
    ([[2, 1], [0, R(1, 2)]], [[1, 0]], True),
    ([[1, 1], [-1, 1]], [[0, 1]], True),
    ([[2, 1], [0, 3]], [[1, 0], [0, 1]], False),
]


def main() -> bool:
    a, lam, l, h = sp.symbols("a lambda l h", positive=True)
    f = (a - lam * l * h) ** 2 + lam * (1 - lam) * l ** 2 * h ** 2
    lstar = sp.solve(sp.diff(f, l), l)[0]
    ok = sp.simplify(f.subs(l, lstar) - a ** 2 * (1 - lam)) == 0
    for A, C, scalar in FAMILY:
        S = System(A=A, sensors=[Sensor(C=C)])
        low, bar = single_sensor_rates(S.A)
        ok &= low <= bar
        # 1 - lambda_bar, or a rational within 1e-12 of it: the factors 4/5 and 5/4 keep the sides decisive
        eps_bar = 1 - (bar.exact if bar.is_rational else sp.Rational(bar.refine(R(1, 10 ** 12)).interval[1]))
        good = mare_stabilizable(S, IID([eps_bar * R(4, 5)])).holds is True
        bad = (mare_stabilizable(S, IID([min(eps_bar * R(5, 4), R(1))])).holds is False) if scalar else True
        if not (good and bad):
            print(f"FAIL: A = {A}, C = {C}: certified above {good}, certified below {bad}")
            ok = False
    print("PASS" if ok else "FAIL", "- single sensor: lambda_bar = 1 - 1/M(A)^2 certified on the family")
    return bool(ok)


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
