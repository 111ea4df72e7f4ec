"""Polynomials over a number field K = Q(theta): characteristic polynomial, gcd, norm, factorisation.

A polynomial is its coefficient list (low to high) of :class:`~symkf.exact.field.NumberField`
elements.  Factorisation is Trager's algorithm (Cohen, *A Course in Computational
Algebraic Number Theory*, Algorithm 3.6.4): after a shift ``x -> x - k theta`` making the
norm ``N(x) = Res_y(m(y), f(x, y))`` squarefree, the irreducible factors over K are
``gcd_K(f, q)`` for the irreducible factors ``q`` of ``N`` over Q (python-flint); only
gcds are computed over K.  Squarefree parts come from Yun's algorithm.

Two shortcuts skip the norm, whose resultant dominates the time and memory of large fields
(degree 1600 for a rotation by 2 pi/1601): a quadratic whose discriminant is negative at a real
embedding of K is irreducible (:func:`factor`), and the roots of an irreducible factor that are
``c`` times primitive ``m``-th roots of unity are recognised by the powers of ``x`` modulo it
(:func:`unit_root_minpoly`).
"""

from __future__ import annotations

import cmath
import math
from fractions import Fraction
from itertools import count

import flint
import sympy as sp

from ..arguments import check_public
from .algebraic import with_prec
from .field import Elem, NumberField

Poly = list[Elem]

_XY = flint.fmpq_mpoly_ctx.get(("x", "y"), "lex")


def _trim(f: Poly) -> Poly:
    f = list(f)
    while f and f[-1].is_zero():
        f.pop()
    return f


def monic(K: NumberField, f: Poly) -> Poly:
    inv = K.inv(f[-1])
    return [K.mul(c, inv) for c in f]


def divmod_(K: NumberField, a: Poly, b: Poly) -> tuple[Poly, Poly]:
    """Quotient and remainder of ``a`` by the nonzero ``b`` over K."""
    a, b = _trim(a), _trim(b)
    inv = K.inv(b[-1])
    q = [flint.fmpq_poly([]) for _ in range(max(len(a) - len(b) + 1, 0))]
    while len(a) >= len(b):
        c = K.mul(a[-1], inv)
        s = len(a) - len(b)
        q[s] = c
        for i, bi in enumerate(b):
            a[s + i] = (a[s + i] - c * bi) % K.modulus
        a = _trim(a)
    return q, a


def gcd(K: NumberField, a: Poly, b: Poly) -> Poly:
    """The monic gcd over K (Euclid)."""
    a, b = _trim(a), _trim(b)
    while b:
        a, b = b, divmod_(K, a, b)[1]
    return monic(K, a)


def derivative(K: NumberField, f: Poly) -> Poly:
    return _trim([c * i for i, c in enumerate(f)][1:])


def _sub(K: NumberField, a: Poly, b: Poly) -> Poly:
    n = max(len(a), len(b))
    zero = flint.fmpq_poly([])
    return _trim([((a[i] if i < len(a) else zero) - (b[i] if i < len(b) else zero)) % K.modulus
                  for i in range(n)])


def squarefree(K: NumberField, f: Poly) -> list[tuple[Poly, int]]:
    """Yun's squarefree decomposition of the monic ``f``: ``f = prod s_e^e``, the ``s_e`` coprime."""
    df = derivative(K, f)
    a = gcd(K, f, df)
    b, c = divmod_(K, f, a)[0], divmod_(K, df, a)[0]
    d = _sub(K, c, derivative(K, b))
    out = []
    for e in count(1):
        if len(b) <= 1:
            return out
        a = gcd(K, b, d) if d else monic(K, b)
        if len(a) > 1:
            out.append((a, e))
        b, c = divmod_(K, b, a)[0], divmod_(K, d, a)[0] if d else []
        d = _sub(K, c, derivative(K, b))


def shift(K: NumberField, f: Poly, k: int) -> Poly:
    """``f(x - k theta)`` (Horner)."""
    kt = flint.fmpq_poly([0, -k]) % K.modulus
    out: Poly = []
    for c in reversed(f):
        prod = [flint.fmpq_poly([])] + out  # x * out
        for i, a in enumerate(out):
            prod[i] = (prod[i] + K.mul(kt, a)) % K.modulus
        prod[0] = (prod[0] + c) % K.modulus
        out = prod
    return _trim(out)


def norm(K: NumberField, f: Poly) -> flint.fmpq_poly:
    """``N_{K/Q}(f) = Res_y(m(y), f(x, y))``, a polynomial over Q."""
    m = _XY.from_dict({(0, j): c for j, c in enumerate(K.modulus.coeffs()) if c})
    fxy = _XY.from_dict({(i, j): c for i, a in enumerate(f) for j, c in enumerate(a.coeffs()) if c})
    res = m.resultant(fxy, "y")
    coeffs = {e[0]: c for e, c in zip(res.monoms(), res.coeffs())}
    return flint.fmpq_poly([coeffs.get(i, 0) for i in range(max(coeffs) + 1)])


def _negative_at_real_embedding(K: NumberField, a: Elem) -> bool:
    """True when ``theta`` is real and ``a(theta) < 0`` (certified balls): then ``a`` is no square
    in K, as ``sigma(b)^2 >= 0`` at a real embedding ``sigma``; False when that is not shown."""
    for prec in (64, 256, 1024, 4096, 16384):
        theta = K.theta_ball(prec)
        if not theta.imag.is_zero():
            return False
        v = with_prec(prec, lambda: flint.arb_poly([flint.arb(c) for c in a.coeffs()])(theta.real))
        if v < 0 or v > 0:
            return bool(v < 0)
    return False


def factor(K: NumberField, f: Poly) -> list[tuple[Poly, int]]:
    """Irreducible monic factors of ``f`` over K with multiplicities (Trager; a quadratic
    ``x^2 + b x + c`` with ``b^2 - 4 c`` negative at a real embedding is irreducible as it is)."""
    out = []
    for s, e in squarefree(K, monic(K, _trim(f))):
        if len(s) == 3 and _negative_at_real_embedding(K, (s[1] * s[1] - 4 * s[0]) % K.modulus):
            out.append((s, e))
            continue
        for k in count():
            g = shift(K, s, k)
            N = norm(K, g)
            if N.gcd(N.derivative()).degree() == 0:
                break
        for q, _ in N.factor()[1]:
            h = gcd(K, g, [flint.fmpq_poly([c]) for c in q.coeffs()])
            if len(h) > 1:
                out.append((shift(K, h, -k), e))
    return out


def _mulmod(K: NumberField, a: Poly, b: Poly, h: Poly) -> Poly:
    prod = [flint.fmpq_poly([])] * (len(a) + len(b) - 1)
    for i, ai in enumerate(a):
        for j, bj in enumerate(b):
            prod[i + j] = prod[i + j] + ai * bj
    return divmod_(K, [c % K.modulus for c in prod], h)[1]


def _x_power(K: NumberField, h: Poly, k: int) -> Poly:
    """``x^k`` modulo the monic ``h`` over K (square and multiply)."""
    out, base = [flint.fmpq_poly([1])], divmod_(K, [flint.fmpq_poly([]), flint.fmpq_poly([1])], h)[1]
    while k:
        if k & 1:
            out = _mulmod(K, out, base, h)
        base = _mulmod(K, base, base, h)
        k >>= 1
    return _trim(out)


def unit_root_minpoly(K: NumberField, h: Poly) -> flint.fmpz_poly | None:
    """The minimal polynomial over Q of the roots of the monic irreducible ``h`` over K when they are
    ``c zeta`` with ``zeta`` a primitive ``m``-th root of unity (``m >= 3``, rational ``c > 0``):
    ``c^d Phi_m(x/c)`` made primitive; None when they are not (or ``c`` and ``m`` are not guessed).

    ``c`` and ``m`` are read off one root in floating point; the answer is exact: in the field
    ``K[y]/(u)``, ``u(y) = h(c y) / c^deg h``, ``y^m = 1`` and ``y^(m/q) != 1`` for each prime
    ``q | m`` say that every root of ``h`` over c is a primitive m-th root of unity, so a root of the irreducible
    ``c^d Phi_m(x/c)``.  This replaces the norm of ``h`` (a resultant of degree ``deg h [K:Q]``) for
    the eigenvalues of scaled rotations over cyclotomic fields."""
    if K.is_rational or len(h) < 2:
        return None
    for prec in (128, 512, 2048):
        theta = K.theta_ball(prec)
        balls = with_prec(prec, lambda: [flint.acb_poly([flint.acb(flint.arb(c)) for c in a.coeffs()])(theta) for a in h])
        try:
            z = with_prec(prec, lambda: flint.acb_poly(balls).roots(tol=2.0 ** -80, maxprec=prec)[0])
        except ValueError:
            continue
        if z.rad() < 2.0 ** -60 * (1 + abs(z.mid())):
            break
    else:
        return None
    z = complex(z.mid())
    c2 = Fraction(abs(z) ** 2).limit_denominator(10 ** 6)
    turn = Fraction(cmath.phase(z) / (2 * math.pi) % 1).limit_denominator(10 ** 6)
    p, q = math.isqrt(c2.numerator), math.isqrt(c2.denominator)
    m = turn.denominator
    if p * p != c2.numerator or q * q != c2.denominator or m < 3 or sp.totient(m) > (len(h) - 1) * K.degree:
        return None
    c = Fraction(p, q)
    # the roots over c: h(c y) / c^deg h, whose powers of y stay small
    unit = [(a * flint.fmpq(c.numerator, c.denominator) ** (i - len(h) + 1)) % K.modulus for i, a in enumerate(h)]

    def is_one(k: int) -> bool:
        return _x_power(K, unit, k) == [flint.fmpq_poly([1])]
    if not is_one(m) or any(is_one(m // r) for r in sp.primefactors(m)):
        return None
    phi = flint.fmpz_poly.cyclotomic(m).coeffs()
    d = len(phi) - 1
    g = flint.fmpz_poly([int(a) * c.numerator ** (d - k) * c.denominator ** k for k, a in enumerate(phi)])
    return g / g.content()


def charpoly(K: NumberField, M: list[list[Elem]]) -> Poly:
    """Characteristic polynomial ``det(x I - M)`` over K (Faddeev-LeVerrier)."""
    n = len(M)
    zero, one = flint.fmpq_poly([]), flint.fmpq_poly([1])
    c: Poly = [zero] * n + [one]
    Mk = [[zero] * n for _ in range(n)]
    for k in range(1, n + 1):
        Mk = [[(K.dot(M[i], [Mk[r][j] for r in range(n)]) + (c[n - k + 1] if i == j else zero)) % K.modulus
               for j in range(n)] for i in range(n)]
        tr = sum((K.dot(M[i], [Mk[r][i] for r in range(n)]) for i in range(n)), zero)
        c[n - k] = (-tr / k) % K.modulus
    return c

check_public(globals())
