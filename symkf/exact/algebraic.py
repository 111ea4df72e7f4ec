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

from fractions import Fraction
import copyreg
from functools import lru_cache, total_ordering
from typing import Any, Callable

import flint
import sympy as sp

from ..errors import InputError

x = sp.Symbol("x")


def _rational(q: Any) -> sp.Rational | None:
    if isinstance(q, bool):
        return None
    if isinstance(q, int):
        return sp.Integer(q)
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
    p = poly if isinstance(poly, sp.Poly) else sp.Poly(poly, x)
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


def _with_prec(prec: int, fn: Callable[[], Any]) -> Any:
    old = flint.ctx.prec
    flint.ctx.prec = prec
    try:
        return fn()
    finally:
        flint.ctx.prec = old


def root_ball(poly: flint.fmpz_poly, index: int, prec: int) -> flint.acb:
    """Certified isolating ball of root ``index`` of ``poly`` (flint's ordering) at ``prec`` bits."""
    return _complex_roots(tuple(int(c) for c in poly.coeffs()), prec)[index]


@lru_cache(maxsize=512)
def _complex_roots(coeffs: tuple[int, ...], prec: int) -> tuple[flint.acb, ...]:
    # isolating all roots dominates (degree 2(p-1) for a rotation by 2 pi/p); callers ask root by root
    return _with_prec(prec, lambda: tuple(r for r, _ in flint.fmpz_poly(list(coeffs)).complex_roots()))


def _arb_interval(b: flint.arb) -> tuple[sp.Rational, sp.Rational]:
    m, e = b.mid().man_exp()
    r, f = b.rad().man_exp()
    mid = sp.Integer(int(m)) * sp.Integer(2) ** int(e)
    rad = sp.Integer(int(r)) * sp.Integer(2) ** int(f)
    return mid - rad, mid + rad


def identify(poly: flint.fmpz_poly, ball_at: Callable[[int], flint.acb],
             what: str = "number") -> tuple[flint.fmpz_poly, int]:
    """The irreducible factor of ``poly`` with a root in the ball, and that root's index.

    ``ball_at(prec)`` returns a certified acb ball for the number at ``prec``
    bits.  The answer is the unique root, over all factors, whose isolating
    ball meets it; precision grows until exactly one does.
    """
    factors = [f if f.leading_coefficient() > 0 else -f for f, _ in poly.factor()[1] if f.degree() > 0]
    for prec in (64, 128, 256, 512, 1024, 4096):
        def hits() -> list[tuple[flint.fmpz_poly, int]]:
            z = ball_at(prec)
            # isolate roots only of the factors that can vanish on the ball: root isolation dominates
            return [(f, i) for f in factors if f(z).contains(0)
                    for i, r in enumerate(_complex_roots(tuple(int(c) for c in f.coeffs()), prec)) if r.overlaps(z)]
        found = _with_prec(prec, hits)
        if len(found) == 1:
            return found[0]
    raise InputError(f"cannot identify the {what} among the roots of {poly}")  # pragma: no cover


def crootof_ball(expr: sp.CRootOf) -> flint.acb:
    """A ball holding sympy's isolating interval (exact rationals) of a ``CRootOf``: no refinement,
    which for high degrees costs far more than isolating the roots again in flint."""
    iv = expr._get_interval()
    (xlo, xhi), (ylo, yhi) = ((iv.a, iv.b), (0, 0)) if expr.is_real else ((iv.ax, iv.bx), (iv.ay, iv.by))

    def arb(lo: sp.Rational, hi: sp.Rational) -> flint.arb:
        return flint.arb(flint.fmpq(int(lo.p), int(lo.q))).union(flint.arb(flint.fmpq(int(hi.p), int(hi.q))))
    return flint.acb(arb(sp.Rational(xlo), sp.Rational(xhi)), arb(sp.Rational(ylo), sp.Rational(yhi)))


def expr_ball(expr: sp.Expr, prec: int) -> flint.acb:
    """A ball around the value of the sympy number ``expr`` at about ``prec`` bits (sympy's evalf;
    for a ``CRootOf``, its isolating interval, which separates it from the other roots)."""
    if isinstance(expr, sp.CRootOf):
        return crootof_ball(expr)
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
    poly = _root_of_unity_poly(expr)
    if poly is None:
        poly = sympy_to_fmpz(sp.Poly(sp.minimal_polynomial(expr, x), x))
    return identify(poly, lambda prec: expr_ball(expr, prec), f"root denoted by {expr}")


def _root_of_unity_poly(expr: sp.Expr) -> flint.fmpz_poly | None:
    """An integer polynomial vanishing at ``exp(i pi r)``, ``cos(pi r)``, ``sin(pi r)`` (``r``
    rational), from flint's cyclotomic and ``2 cos(2 pi k/n)`` minimal polynomials; else None."""
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


@total_ordering
class AlgebraicNumber:
    """A real algebraic number: ``.exact``, ``.minpoly``, ``.interval``, ``.evalf(n)``, ``float()``.

    Comparisons with ints, Fractions, sympy numbers and other AlgebraicNumbers are exact.
    """

    __slots__ = ("_poly", "_index", "_lo", "_hi", "_prec", "_exact")

    def __init__(self, poly: flint.fmpz_poly, index: int, exact: sp.Expr | None = None):
        self._poly = poly if poly.leading_coefficient() > 0 else -poly
        self._index = index
        self._exact = exact
        self._prec = 64
        ball = root_ball(self._poly, index, self._prec)
        if ball.imag != 0:
            raise InputError(f"root {index} of {self._poly} is not real")
        self._lo, self._hi = _arb_interval(ball.real)

    # -- construction -----------------------------------------------------------
    @classmethod
    def from_expr(cls, expr: Any) -> "AlgebraicNumber":
        """The real algebraic number denoted by a sympy expression (or int / Fraction / string)."""
        if isinstance(expr, AlgebraicNumber):
            return expr
        q = _rational(expr)
        if q is None:
            expr = sp.sympify(expr)
            if expr.free_symbols:
                raise InputError(f"{expr}: has free symbols, not a number")
            q = expr if expr.is_Rational else None
        if q is not None:
            return cls(flint.fmpz_poly([-int(q.p), int(q.q)]), 0, q)
        f, idx = root_of(expr)
        return cls(f, idx, expr)

    @classmethod
    def from_root(cls, poly: Any, lo: Any, hi: Any, exact: sp.Expr | None = None) -> "AlgebraicNumber":
        """The unique real root of ``poly`` (integer or rational, sympy or flint) in ``[lo, hi]``."""
        fpoly = poly if isinstance(poly, flint.fmpz_poly) else sympy_to_fmpz(poly)
        lo, hi = sp.Rational(lo), sp.Rational(hi)
        found = []
        for f, _ in fpoly.factor()[1]:
            f = f if f.leading_coefficient() > 0 else -f
            n_real = sum(1 for r, _ in f.complex_roots() if r.imag == 0)
            for i in range(n_real):
                a = cls(f, i)
                if a >= lo and a <= hi:
                    found.append(a)
        distinct = []
        for a in found:
            if all(a != b for b in distinct):
                distinct.append(a)
        if len(distinct) != 1:
            raise InputError(f"[{lo}, {hi}] holds {len(distinct)} distinct real roots of {poly}, not one")
        distinct[0]._exact = exact
        return distinct[0]

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
            for cand in (sp.root(abs(base), k), -sp.root(abs(base), k)):
                if self._contains(cand):
                    return cand
        if k == 2:
            for r in sp.roots(self.minpoly, x):
                if r.is_real and self._contains(r):
                    return r
        if all(v == 0 for v in c[1::2]) and self._lo >= 0:  # p(x) = q(x^2): a square root
            inner = AlgebraicNumber.from_root(sp.Poly(c[::2], x), self._lo ** 2, self._hi ** 2)
            return sp.sqrt(inner.exact)
        return sp.CRootOf(self.minpoly.as_expr(), x, self._index)

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
        width = sp.Rational(width)
        while self._hi - self._lo > width:
            self._prec *= 2
            self._lo, self._hi = _arb_interval(root_ball(self._poly, self._index, self._prec).real)
        return self

    def evalf(self, n: int = 15) -> sp.Float:
        """``n`` significant digits from an interval refined far below ``10^-n`` relative width."""
        if self.is_rational:
            return sp.Float(self._lo, n)
        scale = max(abs(self._lo), abs(self._hi), sp.Rational(1, 10 ** 6))
        self.refine(scale / 10 ** (n + 6))
        return sp.Float((self._lo + self._hi) / 2, n)

    def __float__(self) -> float:
        return float(self.evalf(20))

    # -- exact comparisons ---------------------------------------------------------
    def _compare(self, other: Any) -> int:
        q = _rational(other)
        if q is None and not isinstance(other, AlgebraicNumber):
            o = sp.sympify(other)
            q = o if o.is_Rational else None
        if q is not None:
            if self.is_rational:
                v = sp.Rational(-int(self._poly.coeffs()[0]), int(self._poly.coeffs()[1]))
                return int(bool(v > q)) - int(bool(v < q))
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

    def __eq__(self, other: object) -> bool:
        try:
            return self._compare(other) == 0
        except (InputError, TypeError, sp.SympifyError):
            return NotImplemented

    def __lt__(self, other: Any) -> bool:
        return self._compare(other) < 0

    def __hash__(self) -> int:
        return hash((str(self._poly), self._index))

    def __repr__(self) -> str:
        return f"AlgebraicNumber({self}, ≈{self.evalf(12)})"

    def __str__(self) -> str:
        if self._exact is None and self._poly.degree() > 4:
            return f"[root ≈{self.evalf(10)} of {self.minpoly.as_expr()}]"
        return str(self.exact)

    def _repr_latex_(self) -> str:
        return f"${sp.latex(self.exact)} \\approx {self.evalf(10)}$"


def real_from_ball(poly: flint.fmpz_poly, index: int) -> AlgebraicNumber:
    """Root ``index`` (flint's ordering) of the irreducible ``poly``, which must be real."""
    return AlgebraicNumber(poly, index)


def sign(expr: Any) -> int:
    """Exact sign (-1, 0, 1) of a real algebraic number given as a sympy expression."""
    expr = sp.sympify(expr)
    if expr.is_Rational:
        return int(sp.sign(expr))
    if expr.free_symbols:
        raise InputError(f"{expr}: the sign of a symbolic expression is not determined")
    return AlgebraicNumber.from_expr(expr)._compare(0)
