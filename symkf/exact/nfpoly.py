"""Polynomials over a number field K = Q(theta): characteristic polynomial, gcd, norm, factorisation.

A polynomial is its coefficient list (low to high) of :class:`~symkf.exact.field.NumberField`
elements.  Factorisation is Trager's algorithm (Cohen, *A Course in Computational
Algebraic Number Theory*, Algorithm 3.6.4): after a shift ``x -> x - k theta`` making the
norm ``N(x) = Res_y(m(y), f(x, y))`` squarefree, the irreducible factors over K are
``gcd_K(f, q)`` for the irreducible factors ``q`` of ``N`` over Q (python-flint); only
gcds are computed over K.  Squarefree parts come from Yun's algorithm.
"""

from __future__ import annotations

from itertools import count

import flint

from ..arguments import check_public
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


def factor(K: NumberField, f: Poly) -> list[tuple[Poly, int]]:
    """Irreducible monic factors of ``f`` over K with multiplicities (Trager)."""
    out = []
    for s, e in squarefree(K, monic(K, _trim(f))):
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
