"""You, Fu and Xie (Automatica 47(12), 2011): second-order systems under Markov (Gilbert-Elliott)
losses, in the form derived in ``symkf.bounds.you_fu_xie``.

Claim checked: for one sensor and ``n = 2``, with ``f = P(lost | received last)``,
``q = P(received | lost last)``: if ``A`` has two simple eigenvalues of modulus ``r`` whose
ratio has order ``p`` and ``rank C = 1``, the filter is stable iff
``r^(2p) (1 - q)^(p-2) ((1 - q)^2 + f q) < 1``; otherwise iff ``(1 - q) rho(A)^2 < 1``.
The stable set of ``q`` need not be an interval.

Method: exhaustive over a stated family, the formula's exact stable set (intervals with
algebraic end points, ``symkf.engine.region.stable_intervals``) against the engine's
(``symkf.stable_recovery_intervals``, Sui-You-Fu Theorem 9 with eq. 36 on the Gilbert-Elliott
chain): ``A = r R(pi k/m)``, ``m <= M`` (``M = 3``; ``6`` with ``full=True``), ``r in {2, sqrt(6)/2}``,
``C in {[1 0], I}``, ``diag(2, -2)``, ``diag(2, 3)`` and the Jordan block ``[[2, 1], [0, 2]]``
with ``C = [1 1]``; ``f in {1/4, 1/2, 3/4}``.  Status: checked; the non-monotone member
``(sqrt 6/2) R(pi/2)``, ``f = 1/2`` (stable iff ``2/3 < q < 5/6``) is among them.
"""

from __future__ import annotations

import sys
from math import gcd

import sympy as sp

import symkf as sk
from symkf.bounds import bounds
from symkf.reports.plots import rotation_system


def family(M: int) -> list[sk.System]:
    out = [sk.System(A=A, sensors=[sk.Sensor(C=[[1, 1]])]) for A in ([[2, 0], [0, -2]], [[2, 0], [0, 3]],
                                                                      [[2, 1], [0, 2]])]
    for r in (sp.Integer(2), sp.sqrt(6) / 2):
        for C in ([[1, 0]], [[1, 0], [0, 1]]):
            out += [rotation_system(r, sp.pi * sp.Rational(k, m), C)
                    for m in range(2, M + 1) for k in range(1, m) if gcd(k, m) == 1]
    return out


def main(full: bool = False) -> bool:
    members = non_interval = 0
    for S in family(6 if full else 3):
        for f in ("1/4", "1/2", "3/4"):
            atlas = bounds(S, sk.GilbertElliott([f], ["1/2"]), lmi_steps=0)
            row = atlas.row("you-fu-xie")
            if row.relation != "equal":
                print(f"FAIL: {S.A.tolist()}, C = {S.C.tolist()}, f = {f}: {row.relation}, "
                      f"formula {row.stable}, engine {atlas.quantity.stable}")
                return False
            members += 1
            non_interval += atlas.quantity.critical is None
    print(f"PASS: the stable sets agree exactly on {members} members ({non_interval} not of the form (q_c, 1))")
    return non_interval > 0


if __name__ == "__main__":
    sys.exit(0 if main("--full" in sys.argv) else 1)
