"""Sui-You-Fu, Remark 13: for d = 1 Theorem 12 is the single-sensor result of You, Fu and Xie (2011).

Claim: substituting ``d = 1`` into Theorem 12 gives the i.i.d. case of Theorem 7
of You, Fu and Xie (2011) for second-order systems.  We could not consult that
paper; the single-sensor reference form used here is the one the paper's
substitution produces once the period is the one that governs the rank of
``O_N``: with one sensor ``J_1 = {1}``, ``p_1^* = 1 - p``, and the filter is stable iff
``alpha^(2g) (1 - p)^(g - 1) < 1``, i.e. the critical loss is
``1 - p_c = alpha^(-2g/(g - 1))`` with ``g`` the order of ``lambda_1/lambda_2`` as a
root of unity (the form of the single-sensor second-order critical value of
Mo and Sinopoli (2010), whose period is that of ``lambda_1/lambda_2``).

Method: symbolic identity in the symbols ``alpha`` and ``p_1``, for every
governing period ``g = 2..12`` and ``tau = g`` and ``tau = 2g`` (real rotations
``2 R(pi/g)`` have ``tau = 2g``; ``2 R(2 pi/g)`` for odd ``g`` has ``tau = g``):
``threshold(S)`` is exactly ``alpha^(2g) (1 - p_1)^(g - 1) < 1`` and
``critical_loss_expr(S)`` is ``Min(1, alpha^(-2g/(g-1)))``.  The printed
statement (``period="tau"``) reduces to ``alpha^(2 tau) (1 - p_1)^(tau - 1) < 1``,
which coincides with the single-sensor form iff ``tau = g``: Remark 13 holds
for the corrected Theorem 12 and fails for the printed one whenever ``tau = 2g``.
The single-sensor decay itself is checked against brute-force enumeration in
``proofs/sui_theorem12.py``.

Scope: every ``g = 2..12``, each a symbolic identity in ``alpha`` and ``p_1``; a
check on that range, not a proof for every ``g``.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf import Sensor, System  # noqa: E402
from symkf import second_order as so  # noqa: E402

alpha = so.ALPHA


def rotation(theta: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[2 * sp.cos(theta), -2 * sp.sin(theta)], [2 * sp.sin(theta), 2 * sp.cos(theta)]])


def single_sensor(P: int, p: sp.Symbol) -> sp.Basic:
    return sp.StrictLessThan(alpha ** (2 * P) * (1 - p) ** (P - 1), 1)


def main() -> bool:
    ok = True
    for g in range(2, 13):
        thetas = [sp.pi / g] + ([2 * sp.pi / g] if g % 2 else [])
        for theta in thetas:
            S = System(A=rotation(theta), sensors=[Sensor(C=[[1, 0]])])
            _, tau, gov = so.second_order_form(S)
            (p,) = so.arrival_symbols(S)
            corrected = so.threshold(S) == single_sensor(g, p)
            loss = so.critical_loss_expr(S) == sp.Min(1, alpha ** sp.Rational(-2 * g, g - 1))
            printed = sp.simplify(so.threshold(S, period="tau").lhs - single_sensor(tau, p).lhs) == 0
            coincide = (so.threshold(S, period="tau") == so.threshold(S)) == (tau == g)
            good = gov == g and corrected and loss and printed and coincide
            ok &= good
            print(f"{'ok ' if good else 'BAD'} theta = {theta}: g = {gov}, tau = {tau}; corrected: {so.threshold(S)}; "
                  f"printed: {sp.simplify(so.threshold(S, period='tau').lhs)} < 1")
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
