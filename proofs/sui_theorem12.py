"""Sui-You-Fu, Theorem 12, eq. (38): refuted as printed; corrected statement checked.

Claim (as printed): under Assumptions 4-6 the estimator of a second-order
system is stable iff ``alpha^(2 tau) prod_i (1 - p_i)^tau / min_j p_j^* < 1``,
``tau`` the least integer with ``A^tau = alpha^tau I`` (Assumption 5), ``p_j^*``
from Definition 1 and eq. (37).

Finding: the exponent must be the governing period ``g`` (least ``k`` with
``A^k`` a scalar multiple of ``I``; ``g`` divides ``tau``), and sensors with
``rank C_i = 2`` must be left out of the congruent sets.  Corrected statement
(``symkf.engine.second_order.critical_loss_rate`` and ``theorem12``): stable iff
``alpha^(2g) max_i prod_j (1 - p_j)^(g - [j in J_i]) < 1`` over the rank-one
sensors ``i`` (``alpha^2 prod (1 - p_j) < 1`` if ``g`` is infinite).

Method: brute-force enumeration, exact and symbolic in the loss ``eps``.  By
Theorem 4 (with eq. 32) stability is ``alpha^2 lim P(R_N)^(1/N) < 1``.  For each
counterexample, ``P(R_N)`` is enumerated over all ``2^N`` receival patterns
(``symkf.engine.rates.probability_rank_deficient``, which tests the rank of ``O_N``
directly) for ``N = 1..8`` and must equal the closed form
``F_N(eps) = eps^N + sum_{r < g} eps^(N - N_r) (1 - eps^(N_r))`` (``N_r`` = number of
``k < N`` with ``k = r mod g``: the received times all lie in one residue class
mod ``g``), or ``eps^N`` for a rank-2 sensor.  Each term of ``F_N`` lies
between ``(1 - eps) eps^(N - N_r)`` and ``eps^(N - N_r)``, so ``F_N^(1/N) ->
eps^((g - 1)/g)`` (the check confirms that the lowest power of ``eps`` in the
enumerated ``P(R_N)`` is ``N - ceil(N/g)``) and the critical loss is
``alpha^(-2g/(g-1))`` (``alpha^-2`` for rank 2); the check confirms this equals
the corrected closed form and the engine, and differs from (38) as printed:

1. ``A = [[0, -2], [2, 0]]``, ``C = [1, 0]``: ``tau = 4``, ``g = 2``; critical ``1/16``, (38) ``2^(-8/3)``;
2. ``A = 2 diag(e^(i pi/6), e^(7 i pi/6))``, ``C = [1, 1]``: ``tau = 12``, ``g = 2``; ``1/16`` vs ``2^(-24/11)``;
3. ``A = diag(lambda, -lambda)``, ``lambda = 2(3 + 4i)/5``: ``tau`` infinite, ``g = 2``; ``1/16`` vs ``1/4``;
4. ``A = 2 R(pi/2)``, ``C = I`` (rank 2): ``P(R_N) = eps^N``; critical ``1/4``, (38) ``4^(-4/3)``.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf import IID, Sensor, System, critical_loss_rate  # noqa: E402
from symkf import second_order as so  # noqa: E402
from symkf.engine.rates import probability_rank_deficient  # noqa: E402

eps = sp.Symbol("eps", positive=True)
lam = 2 * (3 + 4 * sp.I) / 5
CASES = [  # (label, A, C, g or None for rank 2, correct critical, printed critical)
    ("2R(pi/2), C = [1, 0]", [[0, -2], [2, 0]], [[1, 0]], 2, sp.Rational(1, 16), 2 ** sp.Rational(-8, 3)),
    ("2diag(e^(i pi/6), e^(7i pi/6)), C = [1, 1]",
     sp.diag(2 * sp.exp(sp.I * sp.pi / 6), 2 * sp.exp(7 * sp.I * sp.pi / 6)), [[1, 1]], 2,
     sp.Rational(1, 16), 2 ** sp.Rational(-24, 11)),
    ("diag(2(3+4i)/5, -2(3+4i)/5), C = [1, 1]", sp.diag(lam, -lam), [[1, 1]], 2,
     sp.Rational(1, 16), sp.Rational(1, 4)),
    ("2R(pi/2), C = I", [[0, -2], [2, 0]], [[1, 0], [0, 1]], None, sp.Rational(1, 4), 4 ** sp.Rational(-4, 3)),
]


def closed_form(N: int, g: int | None) -> sp.Expr:
    """P(R_N) for one sensor: received times confined to one residue class mod g."""
    if g is None:
        return eps ** N
    counts = [len(range(r, N, g)) for r in range(g)]
    return sp.expand(eps ** N + sum(eps ** (N - c) * (1 - eps ** c) for c in counts))


def main() -> bool:
    ok = True
    for label, A, C, g, correct, printed in CASES:
        S = System(A=A, sensors=[Sensor(C=C)])
        probs = [sp.expand(probability_rank_deficient(S, IID([eps]), N)[0]) for N in range(1, 9)]
        enum = all(sp.expand(P - closed_form(N, g)) == 0 for N, P in enumerate(probs, start=1))
        # decay: the lowest power of eps in P(R_N) is N - ceil(N/g) (N for rank 2)
        lowest = [min(m[0] for m in sp.Poly(P, eps).monoms()) for P in probs]
        decay = lowest == [N - (-(-N // g) if g else 0) for N in range(1, 9)]
        alpha = so.second_order_form(S)[0]
        # F_N ~ eps^((g-1)N/g): critical loss alpha^(-2g/(g-1)); rank 2: alpha^(-2)
        from_enumeration = alpha ** (sp.Rational(-2 * g, g - 1) if g else -2)
        checks = {
            "enumeration = closed form F_N, N = 1..8": enum,
            "lowest power of eps in P(R_N) is N - ceil(N/g)": decay,
            "corrected Theorem 12 = enumeration": so.critical_loss_rate(S) == from_enumeration == correct,
            "engine = enumeration": critical_loss_rate(S) == correct,
            "printed (38) = stated value != enumeration":
                so.critical_loss_rate(S, period="tau") == printed and printed != correct,
        }
        cs = so.congruent_sets(S)
        print(f"{label}: tau = {so.second_order_form(S)[1]}, g = {so.second_order_form(S)[2]}; "
              f"critical loss {correct} (printed (38): {printed} ~ {float(printed):.4f})"
              + f"; J = {[sorted(J) for J in cs.sets]}")
        for claim, good in checks.items():
            print(f"  {'ok ' if good else 'BAD'} {claim}")
        ok &= all(checks.values())
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
