"""The closed forms and sufficient/necessary conditions of the atlas (``symkf.bounds``) hold
wherever their hypotheses hold: no row is ``violated`` on a stated family.

Claims checked (each row's, as stated in docs/bounds.md): Sinopoli et al. 2004's lower
bound (``eps_c <= 1/rho^2``) and its case ``C`` invertible (``eps_c = 1/rho^2``); Plarre and
Bullo 2009 (``eps_c = 1/rho^2`` when ``C_o`` is invertible); Mo and Sinopoli 2012
(non-degenerate: ``eps_c = 1/rho^2``; over a Gilbert-Elliott channel stable iff
``(1 - q) rho^2 < 1``); Huang and Dey 2007 (sufficient ``(1 - q) rho^2 < 1`` for ``C`` of full
column rank); Quevedo et al. Theorem 1 (sufficient); Yang et al. Theorems 2 (necessary) and 5
(sufficient); the corrected Theorem 12 of Sui-You-Fu (exact).  (The degenerate closed form,
You-Fu-Xie's condition and the LMI have files of their own: ``bounds_*.py``.)

Method: exhaustive over the family, each row against the exact stable set of the engine
(Sui-You-Fu Theorems 4/7/9): ``A = 2 R(pi k/m)`` (``m <= 3``; ``m <= 8`` with ``full=True``) with
``C in {[1 0], [1 1], I}``; ``diag(a, b)`` for ``(a, b)`` in ``(2, 3), (2, -2), (3, -3), (2, 1/2),
(-2, 3)`` with ``C in {[1 1], [1 0], I}`` (detectable ones); the Jordan block ``[[2, 1], [0, 2]]``
with ``C = [1 0]``; the 3-dim ``diag(2, -2, 3)`` with ``C = I`` and ``[[1, 1, 0], [0, 0, 1]]``;
each under i.i.d. losses and Gilbert-Elliott channels with ``f = 1/2`` (``f in {1/5, 1/2, 4/5}``
with ``full=True``).  Counts of
members where each row applied are printed.  Status: checked (0 violations).
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
    for m in range(2, M + 1):
        for k in range(1, m):
            if gcd(k, m) == 1:
                theta = sp.pi * sp.Rational(k, m)
                out += [rotation_system(2, theta, C) for C in ([[1, 0]], [[1, 1]], [[1, 0], [0, 1]])]
    for a, b in [(2, 3), (2, -2), (3, -3), (2, sp.Rational(1, 2)), (-2, 3)]:
        for C in ([[1, 1]], [[1, 0]], [[1, 0], [0, 1]]):
            try:
                out.append(sk.System(A=[[a, 0], [0, b]], sensors=[sk.Sensor(C=C)]))
            except sk.SymkfError:  # not detectable: not a system
                pass
    out.append(sk.System(A=[[2, 1], [0, 2]], sensors=[sk.Sensor(C=[[1, 0]])]))
    for C in ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[1, 1, 0], [0, 0, 1]]):
        out.append(sk.System(A=sp.diag(2, -2, 3), sensors=[sk.Sensor(C=C)]))
    return out


def main(full: bool = False) -> bool:
    applied: dict[str, int] = {}
    members = 0
    fails = ("1/5", "1/2", "4/5") if full else ("1/2",)
    for S in family(8 if full else 3):
        for loss in (None, *(sk.GilbertElliott([f], ["1/2"]) for f in fails)):
            atlas = bounds(S, loss, lmi_steps=0)
            members += 1
            for r in atlas.rows:
                applied[r.key] = applied.get(r.key, 0) + r.applies
            if atlas.violations:
                r = atlas.violations[0]
                print(f"FAIL: {r.result} on A = {S.A.tolist()}, C = {S.C.tolist()}, loss {loss}: "
                      f"its set {r.stable}, exact {atlas.quantity.stable}")
                return False
    print(f"PASS: no violation on {members} members; rows applied: {applied}")
    return all(applied.values())


if __name__ == "__main__":
    sys.exit(0 if main("--full" in sys.argv) else 1)
