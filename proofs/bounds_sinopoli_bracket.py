"""Sinopoli et al. (IEEE TAC 49(9), 2004), the lower bound and the LMI of Theorem 5: they bracket the critical
loss probability, ``1 - lambda_max <= eps_c <= 1/rho(A)^2``, and both can be strict at once
(You, Fu and Xie, 2011).

Claim checked: on a stated family, (a) ``eps_c <= 1/rho(A)^2`` exactly; (b) the LMI of
Theorem 5, decided at each bisection point with exact certificates
(``symkf.capacity.convergence``), is never feasible at a loss where the engine says the filter
is unstable: the certified feasible end ``lo`` of the bracket lies below ``eps_c``; (c) for a
scalar measurement the bracket holds ``1/M(A)^2`` (Elia's threshold, Yang et al. Corollary 1);
(d) for ``A = [[0, -4], [1, -2]]``, ``C = [1 0]`` (ratio a cube root of unity) the certified
bracket lies strictly below ``eps_c = 1/8 < 1/4``: the critical value is strictly between.

Method: the spectra of ``2 R(t)``, ``t = pi/2, pi/3, 2 pi/3, pi/4``, in companion form (the LMI is
similarity invariant; the companion forms are rational but for ``t = pi/4``), ``C = [1 0]`` (and
``C = I`` with ``full=True``); diag(2, 3) with ``C = [1 1]``; 4 bisection steps.  Status: checked.
"""

from __future__ import annotations

import sys


import symkf as sk
from symkf.bounds import bounds
from symkf.capacity.quantities import mahler_measure

#: companion matrices of x^2 - 4 cos(t) x + 4, the spectra of 2 R(t) for t = pi/2, pi/3, 2 pi/3, pi/4
SPECTRA = [[[0, -4], [1, 0]], [[0, -4], [1, 2]], [[0, -4], [1, -2]], [[0, -4], [1, "2*sqrt(2)"]]]


def main(full: bool = False) -> bool:
    ok = True
    sensors = ([[1, 0]], [[1, 0], [0, 1]]) if full else ([[1, 0]],)
    systems = [sk.System(A=A, sensors=[sk.Sensor(C=C)]) for A in SPECTRA for C in sensors]
    systems.append(sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 1]])]))
    for S in systems:
        atlas = bounds(S, lmi_steps=4)
        exact = atlas.quantity.critical
        upper, lmi = atlas.row("sinopoli-lower"), atlas.row("sinopoli-lmi")
        lo, hi = (sk.AlgebraicNumber.from_expr(v) for v in lmi.bracket)
        scalar = S.C.shape[0] == 1
        elia = sk.AlgebraicNumber.from_expr(1 / mahler_measure(S.A).exact ** 2)
        good = (upper.relation in ("equal", "holds") and lo < exact and lmi.relation != "violated"
                and (not scalar or lo <= elia <= hi))
        print(f"{'ok  ' if good else 'FAIL'} A = {S.A.tolist()}, C = {S.C.tolist()}: eps_c = {exact.exact}, "
              f"1/rho^2 = {upper.value.exact}, LMI bracket [{lmi.bracket[0]}, {lmi.bracket[1]}]")
        ok &= good
    cx = bounds(sk.System(A=[[0, -4], [1, -2]], sensors=[sk.Sensor(C=[[1, 0]])]), lmi_steps=4)
    hi = sk.AlgebraicNumber.from_expr(cx.row("sinopoli-lmi").bracket[1])
    strict = hi < cx.quantity.critical < cx.row("sinopoli-lower").value
    print(f"{'PASS' if ok and strict else 'FAIL'}: bounds bracket eps_c on {len(systems)} systems; "
          f"strictly between for the cube-root ratio: {strict}")
    return ok and strict


if __name__ == "__main__":
    sys.exit(0 if main("--full" in sys.argv) else 1)
