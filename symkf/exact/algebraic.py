"""Real algebraic numbers with certified isolating intervals (python-flint).

An :class:`AlgebraicNumber` is the ``index``-th real root (ascending) of an
irreducible integer polynomial, its minimal polynomial.  python-flint's
``fmpz_poly.complex_roots`` returns disjoint balls, each holding exactly one
root, with real roots first in ascending order and exactly zero imaginary
part; the real ball of a root, read as a closed interval with rational end
points, is therefore a certified isolating interval, and raising the working
precision refines it.  Comparisons refine until intervals separate, so they
are exact.  The only numerical step is choosing, once, which root a sympy
expression denotes (as sympy's own ``minimal_polynomial`` does), and that
choice needs one isolating ball to meet the expression's value.
"""

from __future__ import annotations

import copyreg
import itertools
import math
import numbers
import operator
import re
from decimal import Decimal
from fractions import Fraction
from functools import cmp_to_key, lru_cache
from typing import Any, Callable

import flint
import numpy as np
import sympy as sp
from sympy.polys.polyerrors import NotAlgebraic

from .. import budget
from ..arguments import check_public, outside
from ..errors import BudgetError, InputError
from ..output import JsonDocument
from .numbers import price_sympy, sympify, to_exact, to_rational

x = sp.Symbol("x")


def _rational(q: Any) -> sp.Rational | None:
    if isinstance(q, bool):
        return None
    if isinstance(q, numbers.Integral):  # int and numpy integers
        return sp.Integer(int(q))
    if isinstance(q, Fraction):
        return sp.Rational(q.numerator, q.denominator)
    if isinstance(q, sp.Rational):
        return q
    return None


def fmpz_to_sympy(poly: flint.fmpz_poly) -> sp.Poly:
    """A flint integer polynomial as a sympy Poly in ``x``."""
    return sp.Poly([int(c) for c in reversed(poly.coeffs())], x)


def sympy_to_fmpz(poly: Any) -> flint.fmpz_poly:
    """A rational sympy polynomial in ``x`` as a flint integer one (denominators cleared, leading coefficient > 0)."""
    p = poly if isinstance(poly, sp.Poly) else sp.Poly(sympify(poly, "poly"), x)
    _, p = p.clear_denoms()
    out = flint.fmpz_poly([int(c) for c in reversed(p.all_coeffs())])
    return out if out.leading_coefficient() > 0 else -out


def _fmpz_poly_reduce(poly: flint.fmpz_poly) -> tuple:
    return flint.fmpz_poly, ([int(c) for c in poly.coeffs()],)


def _fmpq_poly_reduce(poly: flint.fmpq_poly) -> tuple:
    return flint.fmpq_poly, ([flint.fmpq(int(c.p), int(c.q)) for c in poly.coeffs()],)


# python-flint's polynomials do not pickle; algebraic numbers, number fields and everything
# holding them must cross process boundaries (symkf.sweep, users' multiprocessing, Dask)
copyreg.pickle(flint.fmpz_poly, _fmpz_poly_reduce)
copyreg.pickle(flint.fmpq_poly, _fmpq_poly_reduce)


def with_prec(prec: int, fn: Callable[[], Any]) -> Any:
    old = flint.ctx.prec
    flint.ctx.prec = prec
    try:
        return fn()
    finally:
        flint.ctx.prec = old


def precision(prec: Any, entry: str = "prec") -> int:
    """``prec`` checked as a number of bits of a ball: an int from 2 up to ``budget``
    ``max_precision`` (flint aborts the process when it cannot allocate; it is never asked)."""
    if isinstance(prec, bool) or not isinstance(prec, numbers.Integral):
        raise InputError(f"{entry}: expected an int number of bits, got {type(prec).__name__}")
    prec = int(prec)
    if prec < 2:
        raise InputError(f"{entry}: {prec} bits is too few; give at least 2")
    budget.check("max_precision", prec, entry, "the bits of precision asked for")
    return prec


def root_ball(poly: flint.fmpz_poly, index: int, prec: int) -> flint.acb:
    """Certified ball of root ``index`` of ``poly`` (flint's ordering) at ``prec`` bits: isolating
    (flint's ``complex_roots``), or for a real root of a polynomial whose real roots are known
    (:func:`known_real_roots`) the enclosure its source gives, which shrinks as ``prec`` grows."""
    coeffs = tuple(int(c) for c in poly.coeffs())
    known = _KNOWN_REAL_ROOTS.get(coeffs)
    if known is not None and index < len(known):
        prec = precision(prec)
        return with_prec(prec, lambda: flint.acb(known[index](prec)))
    return _complex_roots(coeffs, precision(prec))[index]


#: irreducible primitive integer polynomials (coefficients) whose real roots are known without
#: isolating all their roots: each real root's source of certified balls ``source(prec)``, ascending
#: (so position = flint's index).  Filled by :func:`known_real_roots`.
_KNOWN_REAL_ROOTS: dict[tuple[int, ...], tuple[Callable[[int], flint.arb], ...]] = {}

#: polynomials whose real roots are kept (a long sweep meets many systems)
_KNOWN_LIMIT = 1024

#: the working precisions at which membership and order of known real roots are decided
_LADDER = (64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384)


def known_real_roots(factors: list[flint.fmpz_poly], sources: list[Callable[[int], flint.arb]]) -> bool:
    """Record the real roots of the irreducible ``factors`` (primitive, positive leading
    coefficient) of a squarefree polynomial, given ``sources`` of certified balls of *all* its real
    roots (distinct numbers): each root goes to the one factor whose value on its ball keeps 0 (the
    others exclude it as the precision grows; distinct irreducible factors share no root), and each
    factor's roots are sorted by their balls, which separate since the roots are distinct.  Then
    :func:`root_ball` and :func:`identify` (``real=True``) name these roots by flint's index (real
    roots first, ascending) without isolating every complex root of a factor of degree in the
    thousands.  False when some membership is not decided at the highest precision tried (then
    nothing is recorded)."""
    owned: dict[int, list[Callable[[int], flint.arb]]] = {k: [] for k in range(len(factors))}
    for source in sources:
        if len(factors) == 1:
            owned[0].append(source)
            continue
        for prec in _LADDER:
            z = with_prec(prec, lambda: source(prec))
            cands = [k for k, f in enumerate(factors) if with_prec(prec, lambda: f(flint.acb(z))).contains(0)]
            if len(cands) == 1:
                owned[cands[0]].append(source)
                break
        else:
            return False
    for k, roots in owned.items():
        key = tuple(int(c) for c in factors[k].coeffs())
        _KNOWN_REAL_ROOTS[key] = tuple(sorted(roots, key=cmp_to_key(_order)))
    while len(_KNOWN_REAL_ROOTS) > _KNOWN_LIMIT:   # the oldest go: their roots are isolated again if asked
        del _KNOWN_REAL_ROOTS[next(iter(_KNOWN_REAL_ROOTS))]
    return True


def real_sign(ball_at: Callable[[int], flint.arb]) -> int:
    """-1 or 1: the sign of the nonzero real number in the balls ``ball_at(prec)``."""
    for prec in _LADDER:
        b = with_prec(prec, lambda: ball_at(prec))
        if b > 0 or b < 0:
            return 1 if b > 0 else -1
    raise InputError("the sign of a nonzero real number is not decided at 16384 bits")  # pragma: no cover


def real_kth_root(gamma: "AlgebraicNumber", k: int, ball_at: Callable[[int], flint.acb],
                  what: str) -> tuple[flint.fmpz_poly, int]:
    """The real root ``x`` of ``x^k = gamma`` in the balls ``ball_at(prec)``: its minimal polynomial and
    index, from ``p(x^k)`` (``p`` the minimal polynomial of ``gamma``).  When the real roots of ``p`` are
    known (:func:`known_real_roots`) and ``p(x^k)`` is proved irreducible (:func:`_binomial_irreducible`),
    its real roots are the real k-th roots of theirs, recorded so that no root of ``p(x^k)`` (degree
    6048 for the critical loss rate of a dense 64 x 64 A) is isolated."""
    c = [int(v) for v in gamma._poly.coeffs()]
    coeffs = [0] * (k * (len(c) - 1) + 1)
    for i, a in enumerate(c):
        coeffs[k * i] = a
    g = flint.fmpz_poly(coeffs)
    known = _KNOWN_REAL_ROOTS.get(tuple(c))
    irreducible = _binomial_irreducible(gamma._poly, k)
    if known is not None and tuple(coeffs) not in _KNOWN_REAL_ROOTS and irreducible:
        sources = []
        for t in known:
            size = lambda prec, t=t: abs(t(prec)).root(k)  # noqa: E731
            sign = real_sign(t)
            if k % 2:
                sources.append(size if sign > 0 else lambda prec, size=size: -size(prec))
            elif sign > 0:
                sources += [size, lambda prec, size=size: -size(prec)]
        known_real_roots([g], sources)
    return identify(g, ball_at, what, real=True, irreducible=irreducible)


def _binomial_irreducible(p: flint.fmpz_poly, k: int) -> bool:
    """Whether ``p(x^k)`` is proved irreducible for the irreducible ``p`` of root ``gamma``: by Capelli's
    theorem ``x^k - gamma`` is irreducible over ``Q(gamma)`` iff ``gamma`` is no q-th power there for
    each prime q dividing k (and not in ``-4 Q(gamma)^4`` when 4 divides k; Lang, Algebra, 3rd ed.
    2002, Chapter VI, Theorem 9.1), and then ``p(x^k)`` has degree ``k deg p`` over Q with the root
    ``gamma^(1/k)``.  No q-th power is proved by a prime ``l = 1 (mod q)``, not dividing the
    leading coefficient, at which ``p`` has a simple root ``r`` that is no q-th power mod ``l``:
    Hensel's lemma embeds ``Q(gamma)`` in the l-adic numbers with ``gamma`` a unit reducing to ``r``,
    and a q-th power would reduce to one.  False when 4 divides k or no such prime is among the
    first 64 tried (undecided)."""
    if k % 4 == 0:
        return False
    lead = int(p.leading_coefficient())
    for q in sp.primefactors(k):
        tried, ell = 0, 1
        while True:
            ell += q
            if not flint.fmpz(ell).is_prime() or lead % ell == 0:
                continue
            tried += 1
            reduced = flint.nmod_poly([int(v) % ell for v in p.coeffs()], ell)
            if any(m == 1 and int(r) and pow(int(r), (ell - 1) // q, ell) != 1 for r, m in reduced.roots()):
                break
            if tried == 64:
                return False
    return True


def _order(a: Callable[[int], flint.arb], b: Callable[[int], flint.arb]) -> int:
    """-1 or 1 as the distinct real numbers in the balls ``a(prec)``, ``b(prec)`` compare."""
    for prec in _LADDER:
        x, y = with_prec(prec, lambda: (a(prec), b(prec)))
        if x < y:
            return -1
        if y < x:
            return 1
    raise InputError("two known real roots are not separated at 16384 bits")  # pragma: no cover


@lru_cache(maxsize=512)
def _complex_roots(coeffs: tuple[int, ...], prec: int) -> tuple[flint.acb, ...]:
    """Isolating balls of all roots of the integer polynomial ``coeffs``, in flint's ordering (real
    roots first, ascending), except that roots known in closed form come without isolation
    (:func:`_known_roots`; isolating the roots of degree-800 cyclotomic polynomials dominated a
    rotation by 2 pi/401).  This is the one ordering of root indices in symkf.exact."""
    known = _known_roots(coeffs)
    if known is not None:
        def ball(kind: str, alpha: Fraction, beta: Fraction, j: int, m: int) -> flint.acb:
            if kind == "unit":
                return flint.arb(flint.fmpq(beta.numerator, beta.denominator)) * flint.acb(flint.arb(flint.fmpq(2 * j, m))).exp_pi_i()
            cosine = 2 * flint.arb(flint.fmpq(2 * j, m)).cos_pi()
            return flint.acb(flint.fmpq(alpha.numerator, alpha.denominator)
                             + flint.fmpq(beta.numerator, beta.denominator) * cosine)
        return with_prec(prec, lambda: tuple(ball(*root) for root in known))
    return with_prec(prec, lambda: tuple(r for r, _ in flint.fmpz_poly(list(coeffs)).complex_roots()))


Root = tuple[str, Fraction, Fraction, int, int]


@lru_cache(maxsize=512)
def _known_roots(coeffs: tuple[int, ...]) -> list[Root] | None:
    """The roots of ``c^d Phi_m(x / c)`` (``m >= 3``, rational ``c = p/q > 0``, made integral as
    ``sum a_k p^(d-k) q^k x^k``: ``c exp(2 pi i j/m)``, none real, listed ``j, -j`` for
    ``j = 1 .. m/2`` prime to m, in flint's order when ``q > 1``) as ``("unit", 0, c, j, m)``, and of
    the minimal polynomials of ``alpha + beta 2 cos(2 pi/m)`` (rational ``alpha``, ``beta``: cosines
    and sines, their squares ``(1 -+ cos 2t) / 2``, scaled and shifted) as ``("cos", alpha, beta, j,
    m)``, real and ascending as in flint; None for other polynomials.  Such roots are named
    without isolating every root of the polynomial, which is slow at degrees such as 230
    (``cos(pi/517)``, ``sin(2 pi/517)``)."""
    d, a = len(coeffs) - 1, coeffs
    if d < 2:
        return None
    if a[0] > 0 and a[d] > 0:
        (p, exact_p), (q, exact_q) = sp.integer_nthroot(a[0], d), sp.integer_nthroot(a[d], d)
        p, q = int(p), int(q)
        scale = [p ** (d - k) * q ** k for k in range(d + 1)] if exact_p and exact_q else []
        if scale and all(a[k] % s == 0 for k, s in enumerate(scale)):
            m = int(flint.fmpz_poly([a[k] // s for k, s in enumerate(scale)]).is_cyclotomic())
            if m >= 3:
                pairs = [k for k in range(1, (m + 1) // 2) if math.gcd(k, m) == 1]
                if q > 1:  # flint's order, which isolation gave them: by imaginary part, then real part
                    pairs.sort(key=lambda k: (-abs(4 * k - m), -k))
                return [("unit", Fraction(0), Fraction(p, q), j, m) for k in pairs for j in (k, m - k)]
    return _affine_cosine_roots(a)


def _affine_cosine_roots(a: tuple[int, ...]) -> list[Root] | None:
    """:func:`_known_roots` for ``p(alpha + beta y) ~ psi_m(y)``, ``psi_m`` the minimal polynomial
    of ``2 cos(2 pi/m)`` (degree ``d = phi(m)/2``).  Its roots' sum is ``mu(m)`` and the sum of
    their squares ``2d + c_m(2)`` (Ramanujan's sum: ``(2 cos t)^2 = 2 + 2 cos 2t``), so the mean
    and variance of ``p``'s roots (its two leading coefficients) give ``beta^2`` and ``alpha``;
    the identity of polynomials decides."""
    d = len(a) - 1
    s1 = Fraction(-a[d - 1], a[d])
    squares = s1 * s1 - 2 * Fraction(a[d - 2], a[d])
    spread = squares - s1 * s1 / d
    if spread <= 0:
        return None
    p = flint.fmpq_poly(list(a))
    for m in _inverse_totient(2 * d):
        mu = int(sp.mobius(m))
        g = math.gcd(m, 2)
        ramanujan = int(sp.mobius(m // g)) * 2 * d // int(sp.totient(m // g))  # phi(m) = 2d
        ratio = spread / (2 * d + ramanujan - Fraction(mu * mu, d))
        top, top_exact = sp.integer_nthroot(ratio.numerator, 2)
        bottom, bottom_exact = sp.integer_nthroot(ratio.denominator, 2)
        if not (top_exact and bottom_exact):
            continue
        psi = flint.fmpq_poly(flint.fmpz_poly.cos_minpoly(m))
        for beta in (Fraction(int(top), int(bottom)), -Fraction(int(top), int(bottom))):
            alpha = (s1 - beta * mu) / d
            image = p(flint.fmpq_poly([flint.fmpq(alpha.numerator, alpha.denominator),
                                       flint.fmpq(beta.numerator, beta.denominator)]))
            if image == psi * image[d]:  # 2 cos(2 pi j/m) ascends as j descends from m/2
                js = [j for j in range((m - 1) // 2 + (m % 2 == 0), 0, -1) if math.gcd(j, m) == 1]
                return [("cos", alpha, beta, j, m) for j in (js if beta > 0 else js[::-1])]
    return None


@lru_cache(maxsize=64)
def _inverse_totient(t: int) -> tuple[int, ...]:
    """Every ``m >= 3`` with ``phi(m) = t``, from a totient sieve up to ``6 t``: ``m / phi(m) < 6``
    below ``2 3 5 ... 23 = 223092870`` (the product of ``p / (p - 1)`` over those primes is 6.1),
    far beyond the degrees met (a missed ``m`` only costs :func:`_known_roots` its shortcut)."""
    phi = np.arange(6 * t + 1)
    for q in range(2, 6 * t + 1):
        if phi[q] == q:  # q is prime: no smaller prime has reduced it
            phi[q::q] -= phi[q::q] // q
    return tuple(int(m) for m in np.flatnonzero(phi == t) if m >= 3)


def _arb_interval(b: flint.arb) -> tuple[sp.Rational, sp.Rational]:
    m, e = b.mid().man_exp()
    r, f = b.rad().man_exp()
    mid = sp.Integer(int(m)) * sp.Integer(2) ** int(e)
    rad = sp.Integer(int(r)) * sp.Integer(2) ** int(f)
    return mid - rad, mid + rad


def identify(poly: flint.fmpz_poly, ball_at: Callable[[int], flint.acb],
             what: str | Callable[[], str] = "number", real: bool = False,
             irreducible: bool = False) -> tuple[flint.fmpz_poly, int]:
    """The irreducible factor of ``poly`` with a root in the ball, and that root's index.

    ``ball_at(prec)`` returns a certified acb ball for the number at ``prec``
    bits.  The answer is the unique root, over all factors, whose isolating
    ball meets it; precision grows until exactly one does.  For a number known to be ``real``,
    once a single factor can vanish on the ball and its real roots are known
    (:func:`known_real_roots`), the number is the one of them whose ball meets it: no isolation.
    ``irreducible=True`` is the caller's proof that ``poly`` is irreducible (factoring a binomial
    of degree 3201 takes 18 CPU-s).
    """
    if irreducible:
        primitive = poly / poly.content()
        factors = [primitive if primitive.leading_coefficient() > 0 else -primitive]
    else:
        factors = _factors(tuple(int(c) for c in poly.coeffs()))
    for prec in (64, 128, 256, 512, 1024, 4096):
        def hits() -> list[tuple[flint.fmpz_poly, int]]:
            z = ball_at(prec)
            cands = [f for f in factors if f(z).contains(0)]
            known = _KNOWN_REAL_ROOTS.get(tuple(int(c) for c in cands[0].coeffs())) if len(cands) == 1 else None
            if real and known is not None:
                return [(cands[0], i) for i, source in enumerate(known) if flint.acb(source(prec)).overlaps(z)]
            # isolate roots only of the factors that can vanish on the ball: root isolation dominates
            return [(f, i) for f in cands
                    for i, r in enumerate(_complex_roots(tuple(int(c) for c in f.coeffs()), prec)) if r.overlaps(z)]
        found = with_prec(prec, hits)
        if len(found) == 1:
            return found[0]
    what = what if isinstance(what, str) else what()
    raise InputError(f"cannot identify the {what} among the roots of {poly}")  # pragma: no cover


@lru_cache(maxsize=512)
def _factors(coeffs: tuple[int, ...]) -> list[flint.fmpz_poly]:
    """The irreducible factors (primitive, positive leading coefficient: the minimal polynomials
    that :class:`AlgebraicNumber` hashes and compares, and the spectrum keys its moduli by) of a
    nonconstant integer polynomial, cached: the moduli and phase orders of all eigenvalues of one
    minimal polynomial share one resultant of degree up to ``2 d^2``."""
    if coeffs in _KNOWN_REAL_ROOTS:   # recorded as irreducible, primitive, with positive leading coefficient
        return [flint.fmpz_poly(list(coeffs))]
    if _known_roots(coeffs) is not None:  # c^d Phi_m(x/c) and the polynomial of 2 cos(2 pi/m) are irreducible
        f = flint.fmpz_poly(list(coeffs))   # up to its content (sqrt(2) / 2: 4x^2 - 2)
        f = f / f.content()
        return [f if f.leading_coefficient() > 0 else -f]
    return [f if f.leading_coefficient() > 0 else -f for f, _ in flint.fmpz_poly(list(coeffs)).factor()[1]
            if f.degree() > 0]


def crootof_ball(expr: sp.CRootOf) -> flint.acb:
    """A ball holding sympy's isolating interval (exact rationals) of a ``CRootOf``: no refinement,
    which for high degrees costs far more than isolating the roots again in flint."""
    iv = expr._get_interval()
    (xlo, xhi), (ylo, yhi) = ((iv.a, iv.b), (0, 0)) if expr.is_real else ((iv.ax, iv.bx), (iv.ay, iv.by))

    def arb(lo: sp.Rational, hi: sp.Rational) -> flint.arb:
        return flint.arb(flint.fmpq(int(lo.p), int(lo.q))).union(flint.arb(flint.fmpq(int(hi.p), int(hi.q))))
    return flint.acb(arb(sp.Rational(xlo), sp.Rational(xhi)), arb(sp.Rational(ylo), sp.Rational(yhi)))


class FlintRoot(sp.Expr):
    """Root ``index`` (python-flint's ``complex_roots`` ordering) of the irreducible primitive
    integer polynomial ``poly``: an algebraic number known by its minimal polynomial and its
    isolating ball, so a number field can adjoin it without sympy's pure-Python root isolation
    (which a ``CRootOf`` needs for its own index: most of the time of a dense 16 x 16 system)."""

    is_number = True
    is_commutative = True

    def __new__(cls, poly: flint.fmpz_poly, index: int) -> "FlintRoot":
        if not isinstance(poly, flint.fmpz_poly) or isinstance(index, bool) or not isinstance(index, int):
            raise InputError(f"FlintRoot: expected a flint fmpz_poly and an int root index, got "
                             f"{type(poly).__name__} and {type(index).__name__}")
        return sp.Expr.__new__(cls, sp.Tuple(*[sp.Integer(int(c)) for c in poly.coeffs()]), sp.Integer(index))

    @property
    def poly(self) -> flint.fmpz_poly:
        return flint.fmpz_poly([int(c) for c in self.args[0]])

    @property
    def index(self) -> int:
        return int(self.args[1])

    def _eval_is_extended_real(self) -> bool:
        return root_ball(self.poly, self.index, 64).imag == 0

    def _eval_is_finite(self) -> bool:
        return True

    def _eval_evalf(self, prec: int) -> sp.Expr:
        b = root_ball(self.poly, self.index, prec + 16)
        digits = int(prec / 3.32) + 2
        part = lambda a: sp.Float(a.mid().str(digits, radius=False), digits)  # noqa: E731
        return part(b.real) + sp.I * part(b.imag) if b.imag != 0 else part(b.real)

    def _sympystr(self, printer: Any) -> str:
        return f"FlintRoot({fmpz_to_sympy(self.poly).as_expr()}, {self.index})"


def expr_ball(expr: sp.Expr, prec: int) -> flint.acb:
    """A ball around the value of the sympy number ``expr`` at about ``prec`` bits (sympy's evalf;
    for a ``CRootOf``, its isolating interval, which separates it from the other roots)."""
    if isinstance(expr, sp.CRootOf):
        return crootof_ball(expr)
    if isinstance(expr, FlintRoot):
        return root_ball(expr.poly, expr.index, prec)
    digits = prec // 3 + 10
    v = sp.N(expr, digits)
    re_, im_ = sp.re(v), sp.im(v)
    tol = flint.arb(0, float(2.0 ** (-prec // 1.2)) * (1 + abs(complex(v))))
    return flint.acb(flint.arb(str(re_)) + tol, flint.arb(str(im_)) + tol)


@lru_cache(maxsize=4096)
def root_of(expr: sp.Expr) -> tuple[flint.fmpz_poly, int]:
    """The algebraic number denoted by ``expr`` (real or complex): its minimal polynomial
    (sympy's ``minimal_polynomial``) and root index (flint's ordering), cached."""
    if expr.free_symbols:
        raise InputError(f"{expr}: has free symbols, not a number")
    if isinstance(expr, FlintRoot):
        return expr.poly, expr.index
    if isinstance(expr, sp.CRootOf):
        # a real root of an irreducible polynomial: sympy's index (real roots first, ascending) is
        # flint's, read without sympy isolating the real roots (seconds at degree 64)
        f = sympy_to_fmpz(expr.poly)
        coeffs = tuple(int(c) for c in f.coeffs())
        real = len(_KNOWN_REAL_ROOTS.get(coeffs, ())) or sum(1 for r in _complex_roots(coeffs, 64) if r.imag == 0)
        if _factors(coeffs) == [f] and int(expr.index) < real:
            return f, int(expr.index)
    poly = _root_of_unity_poly(expr)
    if poly is None:
        poly = sympy_to_fmpz(sp.Poly(sp.minimal_polynomial(expr, x), x))
    # the words only on failure: printing a large expression costs more than identifying it,
    # and Python refuses to print integers of more than 4300 digits
    return identify(poly, lambda prec: expr_ball(expr, prec), lambda: f"root denoted by {expr}")


def _root_of_unity_poly(expr: sp.Expr) -> flint.fmpz_poly | None:
    """An integer polynomial vanishing at ``exp(i pi r)``, ``cos(pi r)``, ``sin(pi r)`` (``r``
    rational), or their negatives (sympy writes ``sin(-x)`` as ``-sin(x)``), from flint's
    cyclotomic and ``2 cos(2 pi k/n)`` minimal polynomials; else None."""
    if expr.is_Mul and expr.args[0] == -1 and len(expr.args) == 2:
        poly = _root_of_unity_poly(expr.args[1])
        return None if poly is None else flint.fmpz_poly([(-1) ** k * int(c) for k, c in enumerate(poly.coeffs())])
    if not isinstance(expr, (sp.exp, sp.cos, sp.sin)):
        return None
    r = expr.args[0] / (sp.I * sp.pi if isinstance(expr, sp.exp) else sp.pi)
    if not r.is_Rational:
        return None
    if isinstance(expr, sp.sin):
        r = sp.Rational(1, 2) - r
    n = int((r / 2).q)  # exp(i pi r) is a primitive n-th root of unity
    if isinstance(expr, sp.exp):
        return flint.fmpz_poly.cyclotomic(n)
    psi = flint.fmpz_poly.cos_minpoly(n)  # minimal polynomial of 2 cos(2 pi k / n), gcd(k, n) = 1
    return flint.fmpz_poly([int(c) * 2 ** i for i, c in enumerate(psi.coeffs())])


#: ``other`` is not a real algebraic number: comparisons defer to it (``==`` is then False)
_INCOMPARABLE = (TypeError, NotAlgebraic, InputError)

_XY = flint.fmpz_mpoly_ctx.get(("x", "y"), "lex")


def _as_fmpz(poly: Any) -> flint.fmpz_poly:
    """``poly`` (flint, or a sympy Poly or expression in ``x`` with rational coefficients) as a flint one."""
    if isinstance(poly, flint.fmpz_poly):
        return poly
    try:
        p = poly if isinstance(poly, sp.Poly) else sp.Poly(sympify(poly, "poly"), x)
    except (sp.PolynomialError, sp.SympifyError, TypeError, ValueError):
        p = None
    if p is None or p.gens != (x,) or not (p.domain.is_ZZ or p.domain.is_QQ):
        raise InputError(f"{poly}: expected a polynomial in x with rational coefficients")
    return sympy_to_fmpz(p)


def _in_y(p: flint.fmpz_poly) -> flint.fmpz_mpoly:
    _, Y = _XY.gens()
    return sum((int(c) * Y ** k for k, c in enumerate(p.coeffs())), _XY.constant(0))


def _eliminate(F: flint.fmpz_mpoly, q: flint.fmpz_poly) -> flint.fmpz_poly:
    """``Res_y(F(x, y), q(y))``: vanishes at ``x = phi(y)`` for every root ``y`` of ``q`` when
    ``F(phi(y), y) = 0``."""
    terms = F.resultant(_in_y(q), "y").to_dict()
    coeffs = [0] * (max(i for i, _ in terms) + 1)
    for (i, _), c in terms.items():
        coeffs[i] = int(c)
    return flint.fmpz_poly(coeffs)


def _sum_poly(p: flint.fmpz_poly, q: flint.fmpz_poly) -> flint.fmpz_poly:
    """Vanishes at ``a + b`` for all roots ``a`` of ``p``, ``b`` of ``q``: ``Res_y(p(x - y), q(y))``."""
    X, Y = _XY.gens()
    return _eliminate(sum((int(c) * (X - Y) ** k for k, c in enumerate(p.coeffs())), _XY.constant(0)), q)


def _product_poly(p: flint.fmpz_poly, q: flint.fmpz_poly) -> flint.fmpz_poly:
    """Vanishes at ``a b`` for all roots ``a`` of ``p``, ``b != 0`` of ``q``: ``Res_y(y^deg p p(x/y), q(y))``."""
    X, Y = _XY.gens()
    d = p.degree()
    return _eliminate(sum((int(c) * X ** k * Y ** (d - k) for k, c in enumerate(p.coeffs())), _XY.constant(0)), q)


def _power_poly(p: flint.fmpz_poly, k: int) -> flint.fmpz_poly:
    """Vanishes at ``a^k`` for every root ``a`` of ``p``: ``Res_y(x - y^k, p(y))``."""
    X, Y = _XY.gens()
    return _eliminate(X - Y ** k, p)


def _subset_product_poly(coeffs: tuple[int, ...], k: int) -> flint.fmpz_poly:
    """``prod_S (x - c^k prod_{i in S} a_i)`` over the k-subsets ``S`` of the roots ``a_i`` of the
    integer polynomial ``coeffs`` (leading coefficient ``c``): the characteristic polynomial of the
    k-th compound matrix of ``c`` times a companion matrix, with integer coefficients (the ``c a_i``
    are algebraic integers).  Expanded from certified balls of the products and read off as the
    one integer in each coefficient's ball, the precision doubled until every ball holds one."""
    m, c = len(coeffs) - 1, abs(coeffs[-1])
    subsets = list(itertools.combinations(range(m), k))

    def expand(prec: int) -> flint.fmpz_poly | None:
        roots = [c * r for r in _complex_roots(coeffs, prec)]
        products = [math.prod((roots[i] for i in S), start=flint.acb(1)) for S in subsets]
        out = []
        for a in flint.acb_poly.from_roots(products).coeffs():
            z = a.real.unique_fmpz()
            if z is None or not a.imag.contains(0):
                return None
            out.append(int(z))
        return flint.fmpz_poly(out)

    # a coefficient is at most prod_S (1 + |product|) <= prod_i (1 + |c a_i|)^C(m-1, k-1) in absolute
    # value (1 + |x y| <= (1 + |x|)(1 + |y|)): its bits, plus guard bits
    bits = with_prec(64, lambda: sum(((1 + abs(c * r)).log() for r in _complex_roots(coeffs, 64)),
                                      flint.arb(0)) / flint.arb(2).log())
    prec = math.ceil(float(bits.upper()) * math.comb(m - 1, k - 1)) + 64
    while (poly := with_prec(prec, lambda: expand(prec))) is None:
        prec *= 2
    return poly


def subset_product(poly: flint.fmpz_poly, indices: list[int], entry: str = "A") -> "AlgebraicNumber":
    """``prod_{i in indices} a_i`` for distinct roots ``a_i`` of the irreducible integer ``poly``
    (flint's ordering), a real number (``indices`` closed under complex conjugation): a root of
    :func:`_subset_product_poly`, identified by its ball.  Its minimal polynomial has degree up to
    ``C(deg, k)`` (that many k-subset products when the Galois group is the symmetric group),
    capped by ``budget.Limits.max_compound_degree``; the product of all roots is rational."""
    coeffs = tuple(int(c) for c in poly.coeffs())
    m, k = len(coeffs) - 1, len(indices)
    if k == m:
        return AlgebraicNumber.from_expr(sp.Rational((-1) ** m * coeffs[0], coeffs[-1]))
    if k == 0:
        return AlgebraicNumber.from_expr(1)
    budget.check("max_compound_degree", math.comb(m, k), entry,
                 f"the degree C({m}, {k}) of the polynomial of a product of {k} of the {m} conjugate "
                 f"eigenvalues of minimal polynomial {fmpz_to_sympy(poly).as_expr()} (their product's "
                 f"degree for a generic Galois group)")
    scale = abs(coeffs[-1]) ** k
    f, idx = identify(_subset_product_poly(coeffs, k),
                      lambda prec: scale * math.prod((root_ball(poly, i, prec) for i in indices), start=flint.acb(1)),
                      "product of conjugate roots", real=True)
    return AlgebraicNumber._irreducible(f, idx) / scale


def _significant(q: Fraction, n: int) -> tuple[int, int]:
    """``q`` rounded half to even to ``n`` significant digits, as ``(mantissa, exponent)`` with
    ``q ~ mantissa * 10^exponent``; exact integer arithmetic (no decimal string of ``q`` is made)."""
    if q == 0:
        return 0, 0
    size = abs(q)
    e = int((size.numerator.bit_length() - size.denominator.bit_length()) * 0.30102999566398120)
    while size >= Fraction(10) ** (e + 1):
        e += 1
    while size < Fraction(10) ** e:
        e -= 1
    shift = n - 1 - e
    mantissa = round(q * Fraction(10) ** shift)
    if abs(mantissa) == 10 ** n:   # 9.99...5 rounds up to the next power of ten
        mantissa, shift = mantissa // 10, shift - 1
    return mantissa, -shift


def terminating_decimal(q: Fraction) -> Decimal | None:
    """``q`` as an exact Decimal when its denominator is ``2^a 5^b``; else None."""
    den, a, b = q.denominator, 0, 0
    while den % 2 == 0:
        den, a = den // 2, a + 1
    while den % 5 == 0:
        den, b = den // 5, b + 1
    if den != 1:
        return None
    e = max(a, b)
    return Decimal(f"{q.numerator * 10 ** e // q.denominator}E-{e}")


#: ``[[fill]align][sign][z][#][0][width][grouping]`` ``[.precision]`` ``[type]`` of a format spec
_SPEC = re.compile(r"(?P<head>.*?)(?:\.(?P<prec>\d+))?(?P<kind>[eEfFgGn%]?)", re.S)


class AlgebraicNumber(JsonDocument):
    """A real algebraic number: ``.exact``, ``.minpoly``, ``.interval``, ``.evalf(n)``, ``float()``.

    It behaves as a SymPy and a Python number:

    * ``sp.sympify(a)``, ``sp.Matrix([a])``, ``sp.sqrt(2) * a`` and ``sp.latex(a)`` use the exact
      expression (``_sympy_``).
    * **Result type of arithmetic** (``+ - * /``, both sides; ``**`` with an int exponent; ``-a``,
      ``abs(a)``): with an int, a Fraction or another AlgebraicNumber the result is an
      AlgebraicNumber, its minimal polynomial computed exactly (a resultant) and its root
      certified by the operands' isolating intervals.  With a sympy object (Rational included) it
      is the exact sympy expression, on both sides: sympy's own operators answer when sympy is on
      the left, and the right side matches them.  With a Python float it is a float, as for
      :class:`fractions.Fraction`.
    * Comparisons (``== < <= > >=``) with ints, Fractions, sympy numbers, AlgebraicNumbers and
      floats are exact; a float is compared through its binary value (``Fraction(f)`` is exact).
      ``sp.Rational(1, 16) == a`` holds when ``a`` is 1/16 (sympy converts ``a`` by ``_sympy_``);
      with another sympy expression on the left, sympy's ``==`` is structural (``a == e`` is not).
    * Truth value: False exactly for zero.
    * ``hash`` agrees with ``==``: a rational hashes as the equal Fraction, int and (when it is
      one) float.  (sympy's own Rational hashes differently from the equal Fraction, so no
      hash can agree with both.)
    * ``format(a, ".4f")`` and ``round(a, n)`` are correctly rounded (round half to even), decided
      exactly: ``round(a)`` is an int and ``round(a, n)`` a :class:`decimal.Decimal` with exactly
      ``n`` decimal places (``Decimal("1.4142")`` for ``sqrt(2)``, ``n = 4``), exact and printed as
      a paper's table prints it; ``math.floor``/``ceil``/``trunc``.

    Parameters
    ----------
    poly : flint.fmpz_poly or sympy polynomial in ``x``
        A nonconstant polynomial with integer (or rational) coefficients.
    index : int
        Which root: flint's ordering (real roots first, ascending) for an irreducible ``poly``,
        the index among its distinct real roots, ascending, otherwise.
    exact : sympy.Expr, optional
        A closed form of the root, returned by :attr:`exact` (otherwise radicals are sought,
        else a ``CRootOf``).

    Raises
    ------
    InputError
        ``poly`` is constant, ``index`` is out of range, or the root is not real.

    Examples
    --------
    ``sqrt(2)`` is the larger root of ``x^2 - 2``; ``sqrt(2) + sqrt(3)`` has the minimal
    polynomial ``x^4 - 10x^2 + 1`` (by hand: squaring ``x - sqrt(2) = sqrt(3)`` gives
    ``x^2 - 1 = 2 sqrt(2) x``, and squaring again gives it):

    >>> import sympy as sp
    >>> from fractions import Fraction
    >>> from symkf import AlgebraicNumber
    >>> x = sp.Symbol("x")
    >>> a = AlgebraicNumber(x**2 - 2, 1)
    >>> a.exact, a.minpoly.as_expr(), a * a == 2, a < Fraction(3, 2), format(a, ".4f")
    (sqrt(2), x**2 - 2, True, True, '1.4142')
    >>> lo, hi = a.interval
    >>> lo * lo <= 2 <= hi * hi
    True
    >>> AlgebraicNumber.from_expr(sp.sqrt(2) + sp.sqrt(3)).minpoly.as_expr()
    x**4 - 10*x**2 + 1
    >>> AlgebraicNumber(x**2 + 1, 0)
    Traceback (most recent call last):
    ...
    symkf.errors.InputError: root 0 of x^2 + 1 is not real
    """

    __slots__ = ("_poly", "_index", "_lo", "_hi", "_prec", "_exact")

    def __init__(self, poly: Any, index: int, exact: sp.Expr | None = None):
        """Root ``index`` of ``poly`` (flint's ordering: real roots first, ascending).

        ``poly`` may be a flint ``fmpz_poly`` or a sympy polynomial in ``x``.  A reducible
        ``poly`` is factored: ``index`` then counts its distinct real roots in ascending order
        (the same count for an irreducible one), and the number is stored with the minimal
        polynomial of that root, chosen by exact comparison of certified isolating intervals.
        """
        fpoly = _as_fmpz(poly)
        if fpoly.degree() < 1:
            raise InputError(f"{poly}: a constant polynomial has no roots")
        _, factors = fpoly.factor()
        if len(factors) == 1 and factors[0][1] == 1:
            if not 0 <= index < fpoly.degree():
                raise InputError(f"root {index} of {poly}: it has {fpoly.degree()} roots (index 0..)")
            self._setup(factors[0][0], index, exact)
            return
        reals = _real_roots(fpoly)
        if not 0 <= index < len(reals):
            raise InputError(f"root {index} of {poly}: it has {len(reals)} distinct real roots "
                             f"(index 0..{len(reals) - 1})")
        root = reals[index]
        self._setup(root._poly, root._index, exact)

    def _setup(self, poly: flint.fmpz_poly, index: int, exact: sp.Expr | None) -> None:
        self._poly = poly if poly.leading_coefficient() > 0 else -poly
        self._index = index
        self._exact = exact
        self._prec = 64
        ball = root_ball(self._poly, index, self._prec)
        if ball.imag != 0:
            raise InputError(f"root {index} of {self._poly} is not real")
        self._lo, self._hi = _arb_interval(ball.real)

    @classmethod
    def _irreducible(cls, poly: flint.fmpz_poly, index: int, exact: sp.Expr | None = None) -> "AlgebraicNumber":
        """Root ``index`` of ``poly``, known irreducible (a factor from flint): no re-factoring."""
        a = cls.__new__(cls)
        a._setup(poly, index, exact)
        return a

    # -- construction -----------------------------------------------------------
    @classmethod
    def from_expr(cls, expr: Any) -> "AlgebraicNumber":
        """The real algebraic number denoted by a sympy expression (or int / Fraction / string)."""
        if isinstance(expr, AlgebraicNumber):
            return expr
        q = _rational(expr)
        if q is None:
            # strings through the safe parser; floats (also inside sympy expressions) refused
            expr = expr if isinstance(expr, sp.Basic) and not expr.has(sp.Float) else to_exact(expr, "number")
            if expr.free_symbols:
                raise InputError(f"{expr}: has free symbols, not a number")
            q = expr if expr.is_Rational else None
        if q is not None:
            return cls._irreducible(flint.fmpz_poly([-int(q.p), int(q.q)]), 0, q)
        f, idx = root_of(expr)
        return cls._irreducible(f, idx, expr)

    @classmethod
    def from_root(cls, poly: Any, lo: Any, hi: Any, exact: sp.Expr | None = None) -> "AlgebraicNumber":
        """The unique real root of ``poly`` (integer or rational, sympy or flint) in ``[lo, hi]``."""
        lo, hi = to_rational(lo, "lo"), to_rational(hi, "hi")
        if exact is not None:
            exact = to_exact(exact, "exact")
        inside = [a for a in _real_roots(_as_fmpz(poly)) if a >= lo and a <= hi]  # exact: ours, not sympy's
        if len(inside) != 1:
            raise InputError(f"[{lo}, {hi}] holds {len(inside)} distinct real roots of {poly}, not one")
        inside[0]._exact = exact
        return inside[0]

    # -- the contract --------------------------------------------------------------
    @property
    def minpoly(self) -> sp.Poly:
        """The primitive integer minimal polynomial, as a sympy Poly in x."""
        return fmpz_to_sympy(self._poly)

    @property
    def is_rational(self) -> bool:
        """Whether the number is rational (minimal polynomial of degree 1)."""
        return self._poly.degree() == 1

    @property
    def exact(self) -> sp.Expr:
        """A sympy expression: radicals where found, otherwise a ``CRootOf``."""
        if self._exact is None:
            self._exact = self._closed_form()
        return self._exact

    def _closed_form(self) -> sp.Expr:
        c = [int(v) for v in reversed(self._poly.coeffs())]  # high -> low
        k = len(c) - 1
        if k == 1:
            return sp.Rational(-c[1], c[0])
        if all(v == 0 for v in c[1:-1]):  # binomial: a real k-th root
            base = sp.Rational(-c[-1], c[0])
            try:  # sympy pulls perfect powers out of the radicand by partial factoring
                radical = sp.root(abs(base), k)
            except ValueError:  # which fails on some large radicands ((4 + 10^-200)^(1/2), sympy 1.14)
                radical = sp.Pow(abs(base), sp.Rational(1, k), evaluate=False)
            for cand in (radical, -radical):
                if self._contains(cand):
                    return cand
        if k == 2:
            for r in sp.roots(self.minpoly, x):
                if r.is_real and self._contains(r):
                    return r
        if all(v == 0 for v in c[1::2]) and self._lo >= 0:  # p(x) = q(x^2): a square root
            # of the root of q at self^2, identified by its ball (not among all real roots of q:
            # 230 of them for |sin(2 pi/517)|, each isolated)
            f, index = identify(flint.fmpz_poly(c[::2][::-1]), lambda prec: self._ball(prec) ** 2, "square of a root",
                                real=True)
            return sp.sqrt(AlgebraicNumber._irreducible(f, index).exact)
        return sp.CRootOf(self.minpoly, self._index)   # from the Poly: its expression costs more at degree 2016

    def _contains(self, expr: sp.Expr) -> bool:
        v = sp.N(expr, 40)
        return bool(sp.im(v) == 0 or abs(sp.im(v)) < 1e-30) and bool(
            self._lo - sp.Rational(1, 10 ** 30) <= sp.re(v) <= self._hi + sp.Rational(1, 10 ** 30))

    @property
    def interval(self) -> tuple[Fraction, Fraction]:
        """Exact rational bounds ``(lo, hi)`` with ``lo <= self <= hi``."""
        return Fraction(int(self._lo.p), int(self._lo.q)), Fraction(int(self._hi.p), int(self._hi.q))

    def refine(self, width: Any) -> "AlgebraicNumber":
        """Shrink the isolating interval below ``width``; returns self."""
        width = to_rational(width, "width")
        if width <= 0:
            raise InputError(f"width: {width} is not positive")
        # the bits a ball that narrow needs, from the sizes of the numbers (never by computing 1/width)
        scale = max(abs(self._lo), abs(self._hi), sp.Integer(1))
        need = int(width.q).bit_length() - int(width.p).bit_length() + int(sp.ceiling(scale)).bit_length() + 8
        budget.check("max_precision", need, "width", "the bits of precision this width needs")
        while self._hi - self._lo > width:
            self._prec *= 2
            self._lo, self._hi = _arb_interval(root_ball(self._poly, self._index, self._prec).real)
        return self

    def evalf(self, n: int = 15) -> sp.Float:
        """``n`` significant digits, correctly rounded (half to even) from the isolating interval,
        refined until both ends round alike (a Float made from a rational at ``n`` digits rounds
        twice, through binary, and can end one unit off)."""
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
            raise InputError(f"n: expected a positive int number of digits, got {n!r}")
        n = int(n)
        budget.check("max_digits", n, "n", "the digits asked for")
        while True:
            ends = {_significant(Fraction(e), n) for e in ((self._value(),) if self.is_rational else self.interval)}
            if len(ends) == 1:
                mantissa, exponent = ends.pop()
                return sp.Float(f"{mantissa}e{exponent}", n)
            self.refine((self._hi - self._lo) / 2 ** 16)

    def __float__(self) -> float:
        return float(self.evalf(20))

    def _value(self) -> Fraction:
        """The value of a rational number (``is_rational``)."""
        c = self._poly.coeffs()
        return Fraction(-int(c[0]), int(c[1]))

    # -- SymPy protocol -------------------------------------------------------------
    def _sympy_(self) -> sp.Expr:
        return self.exact

    def _latex(self, printer: Any) -> str:
        return printer._print(self.exact)

    # -- exact comparisons ---------------------------------------------------------
    def _compare(self, other: Any) -> int | None:
        """Sign of ``self - other``; None when unordered (NaN).  TypeError for non-numbers."""
        if isinstance(other, float):
            if math.isnan(other):
                return None
            other = Fraction(other) if math.isfinite(other) else sp.oo if other > 0 else -sp.oo  # exact
        if isinstance(other, sp.Float):
            other = sp.Rational(other) if other.is_finite else sp.oo if other > 0 else -sp.oo  # exact
        if other is sp.nan:
            return None
        if other is sp.oo or other is -sp.oo:
            return -1 if other is sp.oo else 1
        q = _rational(other)
        if q is None and not isinstance(other, AlgebraicNumber):
            if not isinstance(other, sp.Expr) or other.free_symbols:
                raise TypeError(f"cannot compare an AlgebraicNumber with {type(other).__name__}")
            if outside(__name__):   # a user's sympy number: priced like its text before flint sees it
                price_sympy(other, "the number compared")
            q = other if other.is_Rational else None
        if q is not None:
            if self.is_rational:
                v = self._value()
                q = Fraction(int(q.p), int(q.q))
                return int(v > q) - int(v < q)
            while self._lo <= q <= self._hi:  # q is not a root: the minimal polynomial has degree > 1
                self.refine((self._hi - self._lo) / 4)
            return 1 if self._lo > q else -1
        o = AlgebraicNumber.from_expr(other)
        if self._poly == o._poly and self._index == o._index:
            return 0
        while not (self._hi < o._lo or o._hi < self._lo):
            self.refine((self._hi - self._lo) / 4)
            o.refine((o._hi - o._lo) / 4)
        return 1 if self._lo > o._hi else -1

    def _ordered(self, other: Any, test: Callable[[int], bool]) -> Any:
        try:
            s = self._compare(other)
        except BudgetError:   # priced and refused: said, not turned into "not comparable"
            raise
        except _INCOMPARABLE:
            return NotImplemented
        return False if s is None else test(s)

    def __eq__(self, other: object) -> bool:
        try:
            return self._compare(other) == 0
        except BudgetError:
            raise
        except _INCOMPARABLE:
            return NotImplemented

    def __lt__(self, other: Any) -> bool:
        return self._ordered(other, lambda s: s < 0)

    def __le__(self, other: Any) -> bool:
        return self._ordered(other, lambda s: s <= 0)

    def __gt__(self, other: Any) -> bool:
        return self._ordered(other, lambda s: s > 0)

    def __ge__(self, other: Any) -> bool:
        return self._ordered(other, lambda s: s >= 0)

    def __hash__(self) -> int:
        if self.is_rational:
            return hash(self._value())
        return hash((tuple(int(c) for c in self._poly.coeffs()), self._index))

    def __bool__(self) -> bool:
        return not (self.is_rational and self._value() == 0)

    # -- exact arithmetic ----------------------------------------------------------
    def _ball(self, prec: int) -> flint.acb:
        return root_ball(self._poly, self._index, prec)

    def _combine(self, other: "AlgebraicNumber", op: str) -> "AlgebraicNumber":
        """``self op other`` for ``op`` in ``+ *``: the factor of the resultant polynomial whose
        root meets the sum or product of the operands' certified balls."""
        if self.is_rational and other.is_rational:
            v = self._value() + other._value() if op == "+" else self._value() * other._value()
            return AlgebraicNumber.from_expr(v)
        if op == "*" and not (self and other):
            return AlgebraicNumber.from_expr(0)
        one = AlgebraicNumber.from_expr(1 if op == "*" else 0)   # the unit: no resultant of the degree of the other
        if self.is_rational and self == one or other.is_rational and other == one:
            return other if self.is_rational and self == one else self
        poly = (_sum_poly if op == "+" else _product_poly)(self._poly, other._poly)
        f, idx = identify(poly, lambda prec: self._ball(prec) + other._ball(prec) if op == "+"
                          else self._ball(prec) * other._ball(prec), lambda: f"{self} {op} {other}", real=True)
        exact = None
        if self._exact is not None and other._exact is not None and f.degree() > 1:
            exact = self._exact + other._exact if op == "+" else self._exact * other._exact
        return AlgebraicNumber._irreducible(f, idx, exact)

    def _reciprocal(self) -> "AlgebraicNumber":
        if not self:
            raise ZeroDivisionError("AlgebraicNumber division by zero")
        if self.is_rational:
            return AlgebraicNumber.from_expr(1 / self._value())
        rev = flint.fmpz_poly(list(reversed(self._poly.coeffs())))
        rev = rev if rev.leading_coefficient() > 0 else -rev
        known = _KNOWN_REAL_ROOTS.get(tuple(int(c) for c in self._poly.coeffs()))
        if known is not None:   # the reversed polynomial is irreducible, its real roots the reciprocals
            known_real_roots([rev], [lambda prec, s=s: 1 / s(prec) for s in known])
        f, idx = identify(rev, lambda prec: 1 / self._ball(prec), lambda: f"1/({self})", real=True)
        return AlgebraicNumber._irreducible(f, idx, None if self._exact is None else 1 / self._exact)

    def __neg__(self) -> "AlgebraicNumber":
        return self._combine(AlgebraicNumber.from_expr(-1), "*")

    def __pos__(self) -> "AlgebraicNumber":
        return self

    def __abs__(self) -> "AlgebraicNumber":
        return -self if self < 0 else self

    def _arith(self, other: Any, op: Callable[[Any, Any], Any], exact_op: Callable[["AlgebraicNumber", "AlgebraicNumber"], Any]) -> Any:
        """The documented result-type rule; ``op(self, other)`` on sympy / float values,
        ``exact_op`` on AlgebraicNumbers."""
        if isinstance(other, sp.Basic):
            return op(self.exact, other)
        if isinstance(other, float):
            return op(float(self), other)
        if isinstance(other, AlgebraicNumber):
            return exact_op(self, other)
        if isinstance(other, (numbers.Integral, Fraction)):  # int (bool too, as for Fraction), numpy ints
            return exact_op(self, AlgebraicNumber.from_expr(Fraction(int(other)) if isinstance(
                other, numbers.Integral) else other))
        return NotImplemented

    def __add__(self, other: Any) -> Any:
        return self._arith(other, operator.add, lambda a, b: a._combine(b, "+"))

    def __radd__(self, other: Any) -> Any:
        return self._arith(other, lambda a, b: b + a, lambda a, b: b._combine(a, "+"))

    def __sub__(self, other: Any) -> Any:
        return self._arith(other, operator.sub, lambda a, b: a._combine(-b, "+"))

    def __rsub__(self, other: Any) -> Any:
        return self._arith(other, lambda a, b: b - a, lambda a, b: b._combine(-a, "+"))

    def __mul__(self, other: Any) -> Any:
        return self._arith(other, operator.mul, lambda a, b: a._combine(b, "*"))

    def __rmul__(self, other: Any) -> Any:
        return self._arith(other, lambda a, b: b * a, lambda a, b: b._combine(a, "*"))

    def __truediv__(self, other: Any) -> Any:
        return self._arith(other, operator.truediv, lambda a, b: a._combine(b._reciprocal(), "*"))

    def __rtruediv__(self, other: Any) -> Any:
        return self._arith(other, lambda a, b: b / a, lambda a, b: b._combine(a._reciprocal(), "*"))

    def __pow__(self, k: Any) -> Any:
        """An AlgebraicNumber for an int ``k``; other exponents: ``sp.sympify(self) ** k``
        (a Python float exponent: a float)."""
        if not isinstance(k, numbers.Integral):
            if isinstance(k, Fraction):
                k = sp.Rational(k.numerator, k.denominator)
            return self._arith(k, operator.pow, lambda a, b: NotImplemented)
        k = int(k)
        budget.check("max_exponent", abs(k), "exponent", "the modulus of the integer exponent")
        if k < 0:
            return self._reciprocal() ** -k
        if self.is_rational:
            return AlgebraicNumber.from_expr(self._value() ** k)
        if k <= 1:
            return self if k == 1 else AlgebraicNumber.from_expr(1)
        c = [int(v) for v in self._poly.coeffs()]
        if k % 2 == 0 and not any(c[1::2]):   # p(x) = q(x^2): self^2 is a root of the irreducible q
            f, idx = identify(flint.fmpz_poly(c[::2]), lambda prec: self._ball(prec) ** 2, lambda: f"({self})^2",
                              real=True)
            return AlgebraicNumber._irreducible(f, idx, None if self._exact is None or f.degree() == 1
                                                else self._exact ** 2) ** (k // 2)
        f, idx = identify(_power_poly(self._poly, k), lambda prec: self._ball(prec) ** k, lambda: f"({self})^{k}",
                          real=True)
        return AlgebraicNumber._irreducible(f, idx, None if self._exact is None or f.degree() == 1
                                            else self._exact ** k)

    def __rpow__(self, base: Any) -> Any:
        """``base ** self``, generally transcendental: the exact sympy expression (float base: float)."""
        if isinstance(base, (numbers.Integral, Fraction)):
            base = to_exact(base, "base")
        return self._arith(base, lambda a, b: b ** a, lambda a, b: NotImplemented)

    # -- rounding and formatting -------------------------------------------------
    def _floor(self, scale: Fraction = Fraction(1), shift: Fraction = Fraction(0)) -> int:
        """``floor(self * scale + shift)`` exactly (``scale > 0``)."""
        if self.is_rational:
            return math.floor(self._value() * scale + shift)
        while True:  # irrational: never an integer, so the floors of the end points meet
            lo, hi = (math.floor(Fraction(e) * scale + shift) for e in self.interval)
            if lo == hi:
                return lo
            self.refine((self._hi - self._lo) / 4)

    def __floor__(self) -> int:
        return self._floor()

    def __ceil__(self) -> int:
        return -(-self)._floor()

    def __trunc__(self) -> int:
        return math.floor(self) if self >= 0 else math.ceil(self)

    def __int__(self) -> int:
        return self.__trunc__()

    def __round__(self, ndigits: int | None = None) -> int | Decimal:
        """The nearest integer (``round(a)``, an int) or the nearest multiple of ``10^-ndigits``
        (``round(a, n)``, a :class:`decimal.Decimal` with exactly ``n`` decimal places:
        ``round(sqrt(2), 4) == Decimal("1.4142")``), ties to even as Python's ``round``.  Decided
        exactly: a rational by its value (``round(1/16, 3)`` is ``0.062``), an irrational, which is
        never a tie, by isolating intervals narrowed until ``floor(10^n a + 1/2)`` is certain;
        never from a float.  The Decimal is built from that integer, so no context precision
        rounds it again."""
        scale = Fraction(10) ** (ndigits or 0)
        if self.is_rational:
            n = round(self._value() * scale)
        else:
            n = self._floor(scale, Fraction(1, 2))  # irrational: never a tie
        return n if ndigits is None else Decimal(f"{n}E{-ndigits}")

    def __format__(self, spec: str) -> str:
        """Correctly rounded decimal formatting (``e f g %`` and ``n`` types, width, sign, ...) as
        :class:`decimal.Decimal` formats (exponents ``e+0``, not float's ``e+00``); with no type and
        no precision, ``str(self)`` is formatted as text."""
        m = _SPEC.fullmatch(spec)
        if not spec or m is None or not (m["kind"] or m["prec"]):
            return format(str(self), spec)
        spec = f"{m['head']}.{m['prec'] or 6}{m['kind']}"
        if self.is_rational and (d := terminating_decimal(self._value())) is not None:
            return format(d, spec)
        while True:  # the end points' roundings agree once the interval is narrow (no ties)
            lo, hi = (format(terminating_decimal(e), spec) for e in self.interval)
            if lo == hi:
                return lo
            self.refine((self._hi - self._lo) / 2 ** 16)

    def to_dict(self, digits: int = 12) -> dict[str, Any]:
        """The JSON form of ``symkf critical --json``: the exact closed form, ``digits`` decimals,
        an isolating interval of width below ``10^-(digits + 2)`` and the minimal polynomial."""
        if isinstance(digits, bool) or not isinstance(digits, numbers.Integral) or digits < 1:
            raise InputError(f"digits: expected a positive int number of digits, got {digits!r}")
        budget.check("max_digits", int(digits), "digits", "the digits asked for")
        lo, hi = self.refine(sp.Rational(1, 10 ** (digits + 2))).interval
        return {"exact": str(self.exact), "decimal": str(self.evalf(digits)), "interval": [str(lo), str(hi)],
                "minpoly": str(self.minpoly.as_expr())}

    def __repr__(self) -> str:
        return f"AlgebraicNumber({self}, ≈{self.evalf(12)})"

    def exact_text(self) -> str:
        """The value as exact text: its closed form, or (degree above 4, none known yet) the root
        near its decimal of its whole minimal polynomial, as JSON documents carry it."""
        if self._exact is None and self._poly.degree() > 4:
            return f"[root ≈{self.evalf(10)} of {self.minpoly.as_expr()}]"
        return str(self.exact)

    def __str__(self) -> str:
        """:meth:`exact_text` for people: a minimal polynomial too long to read is named by its degree."""
        text = self.exact_text()
        if len(text) > 80 and text.startswith("[root"):
            return f"[root ≈{self.evalf(10)} of a degree-{self._poly.degree()} polynomial (.minpoly)]"
        return text

    def _repr_latex_(self) -> str:
        return f"${sp.latex(self.exact)} \\approx {self.evalf(10)}$"


def _real_roots(poly: flint.fmpz_poly) -> list[AlgebraicNumber]:
    """The distinct real roots of ``poly``, ascending, each with its minimal polynomial."""
    roots = []
    for f, _ in poly.factor()[1]:
        f = f if f.leading_coefficient() > 0 else -f
        n_real = sum(1 for r, _ in f.complex_roots() if r.imag == 0)
        roots.extend(AlgebraicNumber._irreducible(f, i) for i in range(n_real))
    return sorted(roots)


def real_from_ball(poly: flint.fmpz_poly, index: int) -> AlgebraicNumber:
    """Root ``index`` (flint's ordering) of the irreducible ``poly``, which must be real."""
    return AlgebraicNumber._irreducible(poly, index)


def _evaluator(poly: flint.fmpq_poly) -> Callable[[Callable[[], flint.arb], Fraction, int], flint.arb]:
    """``(ball, size, prec) -> poly(ball())`` for a real ball made by ``ball()`` with ``|x| <= size``,
    at a working precision above ``prec`` by the bits of ``sum_i |c_i| max(1, size)^i``
    (:func:`_working_precision`; the ball is made at that precision too: an exact rational point
    stays exact).  At ``prec`` alone, a margin of degree 744 with 1252-bit coefficients was never
    told from a threshold, and the ball of :func:`decreasing_root` stayed the whole interval: every
    factor's roots were isolated, 13 CPU-s for one of degree 248."""
    coeffs, work = poly.coeffs(), _working_precision(poly)

    def at(ball: Callable[[], flint.arb], size: Fraction, prec: int) -> flint.arb:
        return with_prec(work(size, prec), lambda: flint.arb_poly([flint.arb(c) for c in coeffs])(ball())
                         if coeffs else flint.arb(0))
    return at


def _working_precision(poly: flint.fmpq_poly) -> Callable[[Fraction, int], int]:
    """``(size, prec) ->`` ``prec`` plus the bits of ``sum_i |c_i| max(1, size)^i``: Horner's rounding
    errors in arb are relative to that sum, so at this precision ``poly(x)`` for ``|x| <= size`` is
    good to about ``2^-prec`` (beside the radius of ``x``)."""
    top = max((int(c.p).bit_length() - int(c.q).bit_length() for c in poly.coeffs() if c != 0), default=0)
    degree = max(poly.degree(), 0)

    def work(size: Fraction, prec: int) -> int:
        grow = max(0, size.numerator.bit_length() - size.denominator.bit_length() + 1)
        return prec + max(0, top + degree * grow + degree.bit_length()) + 16
    return work


def _point(x: Fraction) -> Callable[[], flint.arb]:
    return lambda: flint.arb(flint.fmpq(x.numerator, x.denominator))


def decreasing_root(poly: flint.fmpq_poly, value: AlgebraicNumber, lo: Fraction, hi: Fraction) -> AlgebraicNumber | None:
    """The root of ``poly(q) = value`` in ``[lo, hi)`` of a rational polynomial strictly decreasing
    there; None when ``poly(lo) < value`` or ``poly(hi) >= value`` (there is none).

    It is a root of ``mu(poly(q))`` (``mu`` the minimal polynomial of ``value``), identified by a
    certified ball: bisection of ``[lo, hi]`` keeps ``poly(a) >= value > poly(b)`` (signs decided in
    arb at the ball's precision, stopping where the balls cannot tell), so the root lies in ``[a,
    b]``; the other roots of ``mu(poly)`` there, where ``poly`` meets another conjugate of ``value``,
    are left outside the ball as its precision grows (:func:`identify`)."""
    def at(q: Fraction) -> Fraction:
        v = poly(flint.fmpq(q.numerator, q.denominator))
        return Fraction(int(v.p), int(v.q))
    if value > at(lo) or not value > at(hi):
        return None
    composed = _composed(value, poly)
    evaluate, size = _evaluator(poly), max(abs(lo), abs(hi))

    def sign(q: Fraction, prec: int) -> int:  # of poly(q) - value, 0 when the balls cannot tell
        v = evaluate(_point(q), size, prec) - value._ball(prec).real
        return 1 if v > 0 else -1 if v < 0 else 0

    def ball_at(prec: int) -> flint.acb:
        a, b = lo, hi
        for _ in range(prec + 8):
            mid = (a + b) / 2
            s = sign(mid, prec)
            if s == 0:
                break
            a, b = (mid, b) if s > 0 else (a, mid)
        return _interval_ball(a, b, prec)
    f, index = identify(composed.numer(), ball_at, "root of a decreasing polynomial", real=True)
    return AlgebraicNumber._irreducible(f, index)


def _composed(value: AlgebraicNumber, poly: flint.fmpq_poly) -> flint.fmpq_poly:
    """``mu(poly(q))``, ``mu`` the minimal polynomial of ``value``: it vanishes where ``poly`` meets
    ``value`` or one of its conjugates."""
    mu = [int(c) for c in value._poly.coeffs()]
    composed = flint.fmpq_poly([mu[-1]])
    for c in reversed(mu[:-1]):
        composed = composed * poly + c
    return composed


def _interval_ball(a: Fraction, b: Fraction, prec: int) -> flint.acb:
    return with_prec(prec, lambda: flint.acb(flint.arb(flint.fmpq(a.numerator, a.denominator)).union(
        flint.arb(flint.fmpq(b.numerator, b.denominator)))))


def unit_roots(poly: flint.fmpz_poly) -> list[tuple[Fraction, Fraction]]:
    """Isolating intervals ``[lo, hi]`` (dyadic rationals, ascending) of the real roots in the open
    interval ``(0, 1)`` of a squarefree integer polynomial, each holding exactly one root (``lo =
    hi`` for a rational root met exactly, else no root at either end): no complex root is isolated.

    Descartes' rule of signs with bisection (Collins and Akritas, "Polynomial real root isolation
    using Descartes' rule of signs", SYMSAC 1976): ``p_(c, k)(x) = 2^(k d) poly((x + c) / 2^k)``
    has its roots in ``(0, 1)`` where ``poly`` has them in ``(c / 2^k, (c + 1) / 2^k)``; the sign
    variations of ``(x + 1)^d p(1 / (x + 1))`` bound their number and equal it when they are 0 or
    1, and a squarefree polynomial's intervals reach 0 or 1 after finitely many halvings (Vincent's
    theorem).  A root at a midpoint is the constant term of the right half, taken out exactly."""
    if poly.degree() < 1:
        return []
    one = flint.fmpz_poly([1, 1])
    out = []

    def reversed_padded(p: flint.fmpz_poly, d: int) -> flint.fmpz_poly:
        coeffs = [int(c) for c in p.coeffs()] + [0] * (d + 1 - len(p.coeffs()))
        return flint.fmpz_poly(coeffs[::-1])

    top = poly
    while int(top.coeffs()[0]) == 0:   # roots at 0 lie outside the open interval
        top = flint.fmpz_poly([int(c) for c in top.coeffs()[1:]])
    # (c, k, p, whether the interval's left and right ends are roots: then it is halved further,
    # so that each interval given holds its root inside and none at an end)
    stack = [(0, 0, top, poly(0) == 0, poly(1) == 0)]
    while stack:
        c, k, p, left_root, right_root = stack.pop()
        d = p.degree()
        count = _sign_changes(reversed_padded(p, d)(one))
        if count == 0:
            continue
        if count == 1 and not (left_root or right_root):
            out.append((Fraction(c, 2 ** k), Fraction(c + 1, 2 ** k)))
            continue
        left = flint.fmpz_poly([int(a) << (d - i) for i, a in enumerate(p.coeffs())])   # 2^d p(x / 2)
        right = left(one)                                                               # 2^d p((x + 1) / 2)
        middle = int(right.coeffs()[0]) == 0
        if middle:   # the midpoint is a root
            out.append((Fraction(2 * c + 1, 2 ** (k + 1)),) * 2)
            right = flint.fmpz_poly([int(a) for a in right.coeffs()[1:]])
        stack += [(2 * c + 1, k + 1, right, middle, right_root), (2 * c, k + 1, left, left_root, middle)]
    return sorted(out)


def _sign_changes(p: flint.fmpz_poly) -> int:
    signs = [c > 0 for c in (int(v) for v in p.coeffs()) if c != 0]
    return sum(a != b for a, b in zip(signs, signs[1:]))


def root_between(poly: flint.fmpz_poly, lo: Fraction, hi: Fraction) -> AlgebraicNumber:
    """The root of the squarefree integer ``poly`` in ``[lo, hi]``, which holds exactly one
    (:func:`unit_roots`), identified by a ball from bisection on exact signs (:func:`narrowed`):
    only the roots of the factor that vanishes on the ball are isolated."""
    if lo == hi:
        return AlgebraicNumber.from_expr(sp.Rational(lo.numerator, lo.denominator))
    state = [lo, hi]

    def ball_at(prec: int) -> flint.acb:
        state[:] = narrowed(poly, *state, Fraction(1, 2 ** prec))
        return _interval_ball(*state, prec)
    f, index = identify(poly, ball_at, "root in an isolating interval")
    return AlgebraicNumber._irreducible(f, index)


def narrowed(poly: flint.fmpz_poly, lo: Fraction, hi: Fraction, width: Fraction) -> tuple[Fraction, Fraction]:
    """``[lo, hi]``, holding exactly one root of the squarefree ``poly``, halved on exact signs of
    ``poly`` until it is at most ``width`` wide (a point when a midpoint is the root)."""
    q = flint.fmpq_poly(poly)

    def sign(x: Fraction) -> int:
        v = q(flint.fmpq(x.numerator, x.denominator))
        return (v > 0) - (v < 0)
    s = sign(lo)
    while hi - lo > width:
        mid = (lo + hi) / 2
        t = sign(mid)
        if t == 0:
            return mid, mid
        lo, hi = (mid, hi) if t == s else (lo, mid)
    return lo, hi


def crossings_in_unit(poly: flint.fmpq_poly, value: AlgebraicNumber) -> list[tuple[flint.fmpz_poly, Fraction, Fraction]]:
    """Where ``poly(q)`` may meet ``value`` for ``q`` in ``(0, 1)``: the real roots there of
    ``mu(poly(q))`` (``mu`` the minimal polynomial of ``value``; a root may be where ``poly`` meets a
    conjugate), as ``(part, lo, hi)``: a squarefree part of it and an isolating interval of one of
    its roots (:func:`unit_roots`; :func:`root_between` makes it exact)."""
    composed = _composed(value, poly).numer()
    if composed.degree() < 1:
        return []
    return [(part, lo, hi) for part, _ in composed.factor_squarefree()[1] for lo, hi in unit_roots(part)]


def exceeds(poly: flint.fmpq_poly, value: AlgebraicNumber, lo: Fraction, hi: Fraction, prec: int = 64) -> bool:
    """Whether ``poly > value`` on all of ``[lo, hi]``, certified (False when the balls cannot tell):
    ``poly(m + t) = sum_k a_k t^k`` at the midpoint ``m`` in arb, and ``|t| <= r`` the half-width, so
    ``poly`` lies in ``a_0 +- sum_(k >= 1) |a_k| r^k`` there (evaluating the monomial form on the
    interval instead loses every bit to the cancellation of coefficients of 2^93 around 10^-15)."""
    mid, half = (lo + hi) / 2, (hi - lo) / 2
    coeffs = poly.coeffs()
    if not coeffs:
        return bool(0 > value)

    def enclosure() -> flint.arb:
        at_mid = flint.arb_poly([flint.arb(c) for c in coeffs])(flint.arb_poly([_point(mid)(), 1])).coeffs()
        r = _point(half)()
        spread = sum((abs(a) * r ** k for k, a in enumerate(at_mid) if k), flint.arb(0))
        return at_mid[0] + flint.arb(0, 1) * spread
    v = with_prec(_working_precision(poly)(max(abs(lo), abs(hi)), prec), enclosure)
    return bool(v > value._ball(prec).real)


def sign_at(poly: flint.fmpq_poly, x: AlgebraicNumber, value: AlgebraicNumber) -> int:
    """The sign (-1, 0, 1) of ``poly(x) - value``, exactly: 0 when ``x``'s minimal polynomial divides
    ``mu(poly)`` (``mu`` that of ``value``) and ``poly(x)`` is the root of ``mu`` that ``value`` is
    (:func:`identify`); otherwise the two differ, and balls of growing precision separate them."""
    evaluate, size = _evaluator(poly), max(abs(x.interval[0]), abs(x.interval[1]))
    if x.is_rational:
        v = poly(flint.fmpq(x._value().numerator, x._value().denominator))
        return -value._compare(Fraction(int(v.p), int(v.q)))
    composed = _composed(value, poly).numer()
    if composed.is_zero() or (composed % x._poly).is_zero():
        if value.is_rational:
            return 0
        f, index = identify(value._poly, lambda prec: flint.acb(evaluate(lambda: x._ball(prec).real, size, prec)),
                            "value at a root")
        if index == value._index:
            return 0
    prec = 64
    while True:
        v = evaluate(lambda: x._ball(prec).real, size, prec) - value._ball(prec).real
        if v > 0 or v < 0:
            return 1 if v > 0 else -1
        prec *= 2


def sign(expr: Any) -> int:
    """Exact sign (-1, 0, 1) of a real algebraic number given as a sympy expression."""
    expr = sympify(expr, "expr")
    if expr.is_Rational:
        return int(sp.sign(expr))
    if expr.free_symbols:
        raise InputError(f"{expr}: the sign of a symbolic expression is not determined")
    return AlgebraicNumber.from_expr(expr)._compare(0)

check_public(globals())
