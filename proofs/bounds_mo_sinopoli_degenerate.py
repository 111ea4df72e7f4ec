"""Mo and Sinopoli (IEEE TAC 57(3), 2012): the degenerate second-order critical value.

Claim checked: for ``A`` of order 2 with two simple eigenvalues of modulus ``r`` whose ratio
is a primitive ``p``-th root of unity and one measurement row (rank C = 1), the critical
i.i.d. loss probability is ``eps_c = r^(-2p/(p-1))``.

Reading: ``p`` is the order of ``lambda_1 / lambda_2``, i.e. the block's governing period ``g``
(least ``k`` with ``A^k`` a scalar multiple of ``I``), not the period ``tau`` (least ``k`` with
``A^k = r^k I``): for ``A = 2R(pi/2)`` the ratio is ``-1`` (``p = 2``, ``eps_c = 1/16``), while
``tau = 4`` would give ``2^(-8/3)``.

Method: exhaustive over a stated family against the exact engine (``symkf.critical_loss_rate``,
Sui-You-Fu Theorems 4/9 with eq. 36): ``A = r R(pi k/m)`` for ``m <= M``, ``0 < k < m``,
``gcd(k, m) = 1`` (``M = 3`` by default, ``12`` with ``full=True``), ``r in {2, 3/2}``, and
``A = diag(r, -r)``, with ``C in {[1 0], [1 1], [1 2]}`` (``diag(r, -r)`` without ``[1 0]``,
which does not see ``-r``).  The number of members where the
``tau`` reading differs is counted too.  Status: checked (with the reading above).
"""

from __future__ import annotations

import sys
from math import gcd

import sympy as sp

import symkf as sk
from symkf.bounds import bounds
from symkf.reports.plots import rotation_system


def family(M: int) -> list[sk.System]:
    out = []
    for r in (sp.Integer(2), sp.Rational(3, 2)):
        for C in ([[1, 0]], [[1, 1]], [[1, 2]]):
            if C != [[1, 0]]:  # diag(r, -r) with C = [1 0] does not see -r
                out.append(sk.System(A=[[r, 0], [0, -r]], sensors=[sk.Sensor(C=C)]))
            out += [rotation_system(r, sp.pi * sp.Rational(k, m), C)
                    for m in range(2, M + 1) for k in range(1, m) if gcd(k, m) == 1]
    return out


def main(full: bool = False) -> bool:
    systems = family(12 if full else 3)
    agree = tau_differs = 0
    for S in systems:
        row = bounds(S, lmi_steps=0).row("mo-sinopoli-degenerate")
        block = S.eigen_blocks()[0]
        exact = sk.critical_loss_rate(S)
        if not row.applies or row.value != exact:
            print(f"FAIL: {S.A.tolist()}, C = {S.C.tolist()}: {row.failed or row.value} vs exact {exact.exact}")
            return False
        agree += 1
        r, tau = block.modulus.exact, block.tau
        tau_differs += sk.AlgebraicNumber.from_expr(sp.radsimp(r ** sp.Rational(-2 * tau, tau - 1))) != exact
    print(f"PASS: eps_c = r^(-2p/(p-1)) with p the governing period on all {agree} members; "
          f"with tau instead of p it would fail on {tau_differs}")
    return agree == len(systems) and tau_differs > 0


if __name__ == "__main__":
    sys.exit(0 if main("--full" in sys.argv) else 1)
