"""UDP-like LQG control of a scalar plant with noiseless measurements: the coupled equations and the
boundary of their region.

Claim.  Schenato, Sinopoli, Franceschetti, Poolla, Sastry, "Foundations of control and estimation
over lossy networks", 2007, Section V: without acknowledgements, with ``C`` invertible and ``R = 0``,
the optimal controller is linear and the cost-to-go is ``s x_hat^2 + (s + t) P`` with

    s = a^2 s + w - nu a^2 s^2 / m,   t = (1 - gamma) a^2 t + nu a^2 s^2 / m,
    m = b^2 s + u + (1 - gamma)(1 - nu) b^2 t,

(``b`` the input gain, ``w, u > 0`` the weights).  For ``|a| > 1`` they have a solution iff
``gamma > 1 - 1/a^2`` and ``nu > nu_udp(gamma) = gamma (a^2 - 1) / (a^2 - (1 - gamma)(2 a^2 - 1))``.

Argument.
(a) *The equations.*  Given the estimate ``x_hat`` and its error variance ``P`` (``e = x - x_hat``),
    ``x+ = a x + nu_k b u + noise`` and, with the estimator's ``x_hat+ = a x_hat + nu_bar b u`` when the
    measurement is lost (probability ``1 - gamma``), ``e+ = a e + (nu_k - nu_bar) b u + noise``; on
    arrival ``e+ = 0`` (``R = 0``).  The expected stage cost plus ``s x+^2 + t e+^2``-type terms is a
    quadratic in ``u``; minimizing it (symbolically below) gives the displayed recursion, with
    ``u = -(nu... ) s a b x_hat / m`` linear in ``x_hat``.
(b) *The boundary.*  The recursion is monotone and, for large ``s, t``, homogeneous of degree one
    (``w, u`` negligible).  A solution exists iff the homogeneous map has no fixed direction
    ``(s, t) = (1, r)`` with growth at least one; solving the homogeneous fixed direction exactly
    gives ``r = (a^2 - 1)/(1 - (1 - gamma) a^2)`` and ``nu = nu_udp(gamma)`` (below, symbolic);
    ``t``'s own equation needs ``(1 - gamma) a^2 < 1``.  At ``gamma = 1`` it is TCP's ``1 - 1/a^2``.

Checks.
1. (a) symbolic: the minimizer and the recursion from the expected quadratic.
2. (b) symbolic: the homogeneous fixed direction solves to ``nu_udp``; the value at ``gamma = 1``.
3. On a grid (a = 6/5, 2, 3; five gamma each): iterating the equations from ``s = t = 1`` in floats
   stays below 10^12 for 20000 steps at ``nu_udp + 1/100`` and passes 10^12 at ``nu_udp - 1/100``
   (decisive margins; floats only in this check).
4. ``symkf.control.udp_threshold`` equals the formula; ``symkf.control.udp_region`` states it.

Status: derived (the paper states the coupled equations; the closed boundary is derived here) and
checked on the grid.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

import symkf as sk  # noqa: E402
from symkf.control import udp_threshold  # noqa: E402

a, b, g, nu, s, t, w, u, xh, P, U = sp.symbols("a b gamma nu s t w u xhat P U", real=True)


def equations() -> bool:
    # one step: E over nu_k ~ Bernoulli(nu), the measurement arrival ~ Bernoulli(gamma)
    ex2 = a ** 2 * (xh ** 2 + P) + 2 * nu * a * b * xh * U + nu * b ** 2 * U ** 2          # E[x+^2] (+ noise)
    ee2 = (1 - g) * (a ** 2 * P + nu * (1 - nu) * b ** 2 * U ** 2)                          # E[e+^2] (+ noise)
    cost = w * (xh ** 2 + P) + nu * u * U ** 2 + s * ex2 + t * ee2
    Ustar = sp.solve(sp.diff(cost, U), U)[0]
    m = b ** 2 * s + u + (1 - g) * (1 - nu) * b ** 2 * t
    linear = sp.simplify(Ustar + s * a * b * xh / m) == 0
    V = sp.expand(cost.subs(U, Ustar))
    s_next = sp.simplify(V.coeff(xh, 2))
    sp_next = sp.simplify(V.coeff(P, 1))        # coefficient of P is s + t at the next step
    ok_s = sp.simplify(s_next - (a ** 2 * s + w - nu * a ** 2 * b ** 2 * s ** 2 / m)) == 0
    ok_t = sp.simplify(sp_next - s_next - ((1 - g) * a ** 2 * t + nu * a ** 2 * b ** 2 * s ** 2 / m)) == 0
    ok = linear and ok_s and ok_t
    print(f"{'ok ' if ok else 'BAD'} the minimizer is linear in x_hat and gives the coupled equations for s, t")
    return ok


def boundary() -> bool:
    r = sp.Symbol("r", positive=True)
    m = 1 + (1 - g) * (1 - nu) * r                     # b = 1, s = 1, weights dropped
    eqs = [sp.Eq(1, a ** 2 - nu * a ** 2 / m), sp.Eq(r * (1 - (1 - g) * a ** 2), nu * a ** 2 / m)]
    sol = sp.solve(eqs, [r, nu], dict=True)
    formula = g * (a ** 2 - 1) / (a ** 2 - (1 - g) * (2 * a ** 2 - 1))
    ok = any(sp.simplify(x[nu] - formula) == 0 for x in sol) and sp.simplify(formula.subs(g, 1) - (1 - 1 / a ** 2)) == 0
    print(f"{'ok ' if ok else 'BAD'} the homogeneous fixed direction gives nu_udp(gamma); nu_udp(1) = 1 - 1/a^2")
    return ok


def _bounded(av: float, gv: float, nv: float) -> bool:
    S = T = 1.0
    for _ in range(20000):
        m = S + 1 + (1 - gv) * (1 - nv) * T
        S, T = av * av * S + 1 - nv * av * av * S * S / m, (1 - gv) * av * av * T + nv * av * av * S * S / m
        if S > 1e12 or T > 1e12:
            return False
    return True


def grid() -> bool:
    ok = True
    for av in (sp.Rational(6, 5), sp.Integer(2), sp.Integer(3)):
        low = 1 - 1 / av ** 2
        for k in range(1, 6):
            gv = low + (1 - low) * sp.Rational(k, 5)
            star = udp_threshold(av, gv)
            ok &= sp.simplify(star - g * (a ** 2 - 1) / (a ** 2 - (1 - g) * (2 * a ** 2 - 1))).subs({a: av, g: gv}) == 0
            above, below = float(star) + 0.01, float(star) - 0.01
            ok &= (above > 1 or _bounded(float(av), float(gv), above)) and not _bounded(float(av), float(gv), below)
    print(f"{'ok ' if ok else 'BAD'} 15 grid points: bounded at nu_udp + 1/100, divergent at nu_udp - 1/100")
    return ok


def library() -> bool:
    S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])], actuators=[sk.Actuator(B=[[1]])])
    row = sk.control.udp_region(S, noiseless=True).rows[1]
    ok = row.status == "exact" and "3*gamma/(7*gamma - 3)" in row.statement and udp_threshold(2, sp.Rational(9, 10)) == sp.Rational(27, 33)
    print(f"{'ok ' if ok else 'BAD'} symkf states nu_udp for a = 2: {row.statement}")
    return ok


def main() -> bool:
    ok = all([equations(), boundary(), grid(), library()])
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
