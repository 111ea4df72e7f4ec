"""The quotient bound on the critical control-packet arrival rate, and its tightness where it is checked.

Claim (lower bound, proved).  For TCP-like LQG control of ``x+ = A x + nu_k B u + w`` with i.i.d.
control arrivals at rate ``nu`` on one channel (Schenato, Sinopoli, Franceschetti, Poolla, Sastry,
"Foundations of control and estimation over lossy networks", 2007, Section IV; ``W > 0``, ``U > 0``),
for every ``A``-invariant subspace ``V``, the quotient ``(A_Q, B_Q)`` on ``R^n / V`` of
``r = rank B_Q >= 1`` satisfies

    nu_c(A, B) >= 1 - |det A_Q|^(-2/r).

Argument.
(a) *Quotients.*  For ``nu > nu_c`` some linear gain ``K`` makes the loop mean-square stable.  The
    quotient state ``z = P x`` obeys ``z+ = A_Q z + nu_k B_Q u + P w``, whose future given ``(z, u)``
    does not depend on the rest of ``x``; so the quotient's LQ problem (state weight ``W_Q > 0``) is
    a fully observed Markov decision problem whose optimum over all causal policies is at most the
    finite cost of ``u = K x``.  Its value iteration, the quotient's control MARE from ``S = 0``, is
    bounded and increasing, hence converges to a fixed point ``S >= W_Q > 0``.
(b) *Determinants.*  With ``B_Q`` of full column rank ``r`` (drop dependent inputs: they change
    neither the range nor, after the matching transformation of ``U``, positivity), and
    ``y = B_Q' S A_Q x`` in the range of ``B_Q' S B_Q``,
    ``y'(B_Q' S B_Q + U)^{-1} y <= y'(B_Q' S B_Q)^{-1} y``, so
        ``S = A_Q' S A_Q + W_Q - nu A_Q' S B_Q (B_Q' S B_Q + U)^{-1} B_Q' S A_Q
            > A_Q' S^(1/2) (I - nu Pi) S^(1/2) A_Q``,
    ``Pi = S^(1/2) B_Q (B_Q' S B_Q)^{-1} B_Q' S^(1/2)`` an orthogonal projection of rank ``r``.
    ``X > Y >= 0`` gives ``det X > det Y``: ``det S > (1 - nu)^r det(A_Q)^2 det S``.  So every
    ``nu > nu_c`` has ``(1 - nu)^r |det A_Q|^2 < 1``, i.e. ``nu > 1 - |det A_Q|^(-2/r)``.
(c) *Closed forms.*  One input (``rank B = 1``): ``r = 1`` on every quotient reached by ``B``, and the
    largest determinant is that of the whole unstable part: ``1 - 1/prod |lambda_u|^2`` (Elia 2005;
    Schenato et al.'s single-input case).  ``B`` square invertible: ``r = dim Q``, and
    ``|det A_Q|^(2/dim Q)`` (a geometric mean of ``|lambda|^2``) is largest for the top eigenvalue alone:
    ``1 - 1/rho(A)^2`` (Schenato et al.'s invertible case).  ``symkf.control.quotient_bound`` gives both.

Tightness (checked, not proved): the bound is the threshold wherever a rational gain verified
exactly at the bound plus ``10^-12`` exists (``symkf.control.critical_arrival_rate``).  The check:
60 seeded random integer plants (n = 2..4, m = 1..n, entries in -3..3 for A and -2..2 for B,
controllable, rho(A) > 1) and the hand examples below.  On every one the certified bracket reaches
width ``10^-12``, so there ``nu_c`` is the bound to within ``10^-12``; a plant where it does not would
be reported by the function as an open bracket.

Checks (exact):
1. (b)'s two facts on a symbolic example: ``det(I - nu Pi) = (1 - nu)^r`` for a rank-2 projection in
   R^3, and the inverse inequality on a 1x1 example.
2. Hand values: diag(2, 3) with b = (1, 1): 1 - 1/36; diag(2, 3, 5) with B = [e1 + e3, e2 + e3]
   (rank 2 on every quotient of dimension >= 2): max(1 - 1/25, 1 - 1/15, 1 - 1/30) = 29/30;
   the companion matrix of x^2 - 3x + 1 with B = I: ``1 - 1/rho^2``, ``rho = (3 + sqrt 5)/2``.
3. The closed forms on 20 seeded single-input and 20 invertible-B plants: the bound equals the
   closed form exactly.
4. Tightness on the family above: bracket width at most 10^-12 for every member.

Status: the lower bound is proved by the argument; tightness is checked on the stated family.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import sympy as sp  # noqa: E402

import symkf as sk  # noqa: E402
from symkf.control import critical_arrival_rate, quotient_bound  # noqa: E402
from symkf.exact.algebraic import AlgebraicNumber  # noqa: E402
from symkf.exact.spectral import eigenvalues  # noqa: E402

from fractions import Fraction  # noqa: E402

R = sp.Rational
TOL = Fraction(1, 10 ** 12)


def determinant_facts() -> bool:
    nu = sp.Symbol("nu")
    V = sp.Matrix([[1, 0], [1, 1], [0, 2]])
    Pi = V * (V.T * V).inv() * V.T
    projection = sp.simplify(Pi * Pi - Pi) == sp.zeros(3, 3) and Pi.rank() == 2
    det = sp.factor(sp.det(sp.eye(3) - nu * Pi)) == sp.factor((1 - nu) ** 2)
    s, u, y = sp.symbols("s u y", positive=True)
    inverse = sp.simplify(y ** 2 / s - y ** 2 / (s + u)) == sp.simplify(y ** 2 * u / (s * (s + u)))
    ok = projection and det and inverse
    print(f"{'ok ' if ok else 'BAD'} det(I - nu Pi) = (1 - nu)^2 for a rank-2 projection; (s + u)^-1 <= s^-1")
    return ok


def hand_values() -> bool:
    cases = [(sp.diag(2, 3), sp.Matrix([1, 1]), R(35, 36)),
             (sp.diag(2, 3, 5), sp.Matrix([[1, 0], [0, 1], [1, 1]]), R(29, 30)),
             (sp.Matrix([[0, -1], [1, 3]]), sp.eye(2), 1 - 1 / ((3 + sp.sqrt(5)) / 2) ** 2)]
    ok = True
    for A, B, expected in cases:
        q = quotient_bound(A, B)
        good = sp.simplify(q.bound.exact - expected) == 0
        ok &= good
        print(f"{'ok ' if good else 'BAD'} {A.tolist()}, B = {B.tolist()}: bound {q.bound.exact} ({q.words()})")
    return ok


def _plants(seed: int, count: int, shape) -> list[tuple[sp.Matrix, sp.Matrix]]:
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        n, m = shape(rng)
        A = rng.integers(-3, 4, (n, n))
        B = rng.integers(-2, 3, (n, m))
        Af = A.astype(float)
        if np.linalg.matrix_rank(np.hstack([np.linalg.matrix_power(Af, k) @ B for k in range(n)])) < n:
            continue
        if max(abs(np.linalg.eigvals(Af))) <= 1.01:
            continue
        if m == n and round(np.linalg.det(B)) == 0:
            continue
        out.append((sp.Matrix(A.tolist()), sp.Matrix(B.tolist())))
    return out


def closed_forms() -> bool:
    ok = True
    for A, B in _plants(11, 20, lambda r: (int(r.integers(2, 5)), 1)):
        prod = AlgebraicNumber.from_expr(1)
        for e in eigenvalues(A):
            if e.modulus > 1:
                prod = prod * e.modulus ** (2 * e.multiplicity)
        ok &= quotient_bound(A, B).bound == 1 - 1 / prod
    single = ok
    for A, B in _plants(12, 20, lambda r: (n := int(r.integers(2, 4)), n)):
        rho = max(e.modulus for e in eigenvalues(A))
        ok &= quotient_bound(A, B).bound == 1 - 1 / rho ** 2
    print(f"{'ok ' if single else 'BAD'} one input: bound = 1 - 1/prod|lambda_u|^2 on 20 plants")
    print(f"{'ok ' if ok else 'BAD'} B invertible: bound = 1 - 1/rho(A)^2 on 20 plants")
    return ok


def tightness() -> bool:
    widths = []
    for A, B in _plants(7, 60, lambda r: (n := int(r.integers(2, 5)), int(r.integers(1, n + 1)))):
        plant = sk.System(A=A, sensors=[sk.Sensor(C=sp.eye(A.rows))], actuators=[sk.Actuator(B=B)])
        widths.append(critical_arrival_rate(plant, TOL).width)
    ok = all(w <= TOL for w in widths)
    print(f"{'ok ' if ok else 'BAD'} 60 random plants: certified bracket width <= 1e-12 on "
          f"{sum(w <= TOL for w in widths)} of 60 (largest {float(max(widths)):.2e})")
    return ok


def main() -> bool:
    ok = all([determinant_facts(), hand_values(), closed_forms(), tightness()])
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
