"""Eigen-blocks, periods, aperiodicity proofs and the modal form.

Sui-You-Fu Assumptions 1, 3 and 5 group the eigenvalues of a diagonalizable
``A`` into eigen-blocks of common modulus ``alpha_i``.  For each block two
periods matter:

* the papers' period ``tau``: least ``tau`` with ``A_i^tau = alpha_i^tau I``;
* the governing period ``g``: least ``k`` with ``A_i^k`` a scalar multiple of
  ``I``.  Rows ``C A^k`` and ``C A^(k+g)`` restricted to the block are then
  parallel, so ``g`` (not ``tau``) decides the rank of the regression matrix
  (eq. 14); ``g`` divides ``tau``.

Both are exact: the eigenvalues are algebraic numbers identified by their
minimal polynomial over Q and a certified isolating ball (python-flint arb);
``lambda_a / lambda_b`` is a root of unity iff its minimal polynomial is
cyclotomic, which ``fmpz_poly.is_cyclotomic`` decides (a root of unity of
degree ``d`` has order ``m`` with ``phi(m) = d``, finitely many by the totient
bound).  ``None`` means aperiodic and comes with that proof.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
from fractions import Fraction
from functools import cached_property, lru_cache
from math import gcd
from typing import Any, Sequence

import flint
import sympy as sp

from ..arguments import check_public, outside
from .algebraic import (AlgebraicNumber, FlintRoot, _arb_interval, _complex_roots, _factors, _known_roots, _subset_product_poly,
                        precision, with_prec, fmpz_to_sympy, identify, known_real_roots, real_from_ball, real_sign, root_ball,
                        root_of, sympy_to_fmpz)
from . import nfpoly
from .field import Elem, NumberField, rational_value
from .blocks import diagonal_blocks
from .linalg import field_of, rank, rank_rows
from .. import budget
from ..errors import InputError, ShapeError
from ..output import JsonDocument
from .numbers import to_exact_matrix
from .text import approximate, number_text, poly_text, root_text

x, y, z = sp.symbols("x y z")


def _lcm(a: int, b: int) -> int:
    return a * b // gcd(a, b)


_YZ = flint.fmpz_mpoly_ctx.get(("y", "z"), "lex")


def _resultant_y(f: tuple[int, ...], g_terms: dict[tuple[int, int], int]) -> flint.fmpz_poly:
    """``Res_y(f(y), g(y, z))`` as a polynomial in ``z`` (python-flint)."""
    fy = _YZ.from_dict({(k, 0): c for k, c in enumerate(f) if c})
    gyz = _YZ.from_dict(g_terms)
    res = fy.resultant(gyz, "y")
    coeffs: dict[int, int] = {}
    for (_, k), c in res.to_dict().items():
        coeffs[k] = int(c)
    return flint.fmpz_poly([coeffs.get(k, 0) for k in range(max(coeffs) + 1)])


@lru_cache(maxsize=512)
def _ratio_poly(fa: tuple[int, ...], fb: tuple[int, ...]) -> flint.fmpz_poly:
    """A polynomial whose roots include every ratio ``root(fa) / root(fb)``: Res_y(fb(y), fa(z y))."""
    return _resultant_y(fb, {(k, k): c for k, c in enumerate(fa) if c})


@lru_cache(maxsize=512)
def _abs_poly(f: tuple[int, ...]) -> flint.fmpz_poly:
    """Roots include ``|lambda|`` for every root of the real ``f`` (degree d, leading coefficient
    a): ``H(a^2 x^2)`` with ``H`` the polynomial of the products ``mu_i mu_j``, i <= j, of the
    roots ``mu = a lambda`` of the monic integer ``a^(d-1) f(x/a)``, among them ``a^2 lambda
    conj(lambda)`` (and ``a^2 lambda^2`` for a real root).  ``H`` comes from power sums (Newton's
    identities, exact integers: ``sum_(i<=j) (mu_i mu_j)^k = (p_k^2 + p_2k) / 2``), of degree
    ``d(d+1)/2``; the resultant ``Res_y(f(y), y^d f(x^2/y))`` of degree ``2 d^2`` costs far more."""
    d, lead = len(f) - 1, f[-1]
    c = [f[k] * lead ** (d - 1 - k) for k in range(d)] + [1]
    D = d * (d + 1) // 2
    p = [d] + [0] * (2 * D)  # power sums of the mu
    for k in range(1, 2 * D + 1):
        p[k] = -sum(c[d - i] * p[k - i] for i in range(1, min(k - 1, d) + 1)) - (k * c[d - k] if k <= d else 0)
    s = [0] + [(p[k] * p[k] + p[2 * k]) // 2 for k in range(1, D + 1)]
    e = [1] + [0] * D  # elementary symmetric functions of the products (Newton)
    for k in range(1, D + 1):
        e[k] = sum((-1) ** (i - 1) * e[k - i] * s[i] for i in range(1, k + 1)) // k
    coeffs = [0] * (2 * D + 1)
    for j in range(D + 1):  # H = sum_j (-1)^(D-j) e_(D-j) z^j at z = a^2 x^2
        coeffs[2 * j] = (-1) ** (D - j) * e[D - j] * lead ** (2 * j)
    return flint.fmpz_poly(coeffs)


@lru_cache(maxsize=64)
def _pair_modulus_poly(f: tuple[int, ...]) -> flint.fmpz_poly | None:
    """``M(x) = G(x^2)``, ``G`` the polynomial of the products ``lambda_i lambda_j`` (i < j) of the
    roots of the irreducible ``f``: its roots include ``|lambda| = sqrt(lambda conj(lambda))`` for
    every non-real root.  ``G`` comes from certified balls (:func:`~symkf.exact.algebraic.
    _subset_product_poly`, k = 2, scaled by the leading coefficient), and the real roots of every
    irreducible factor of ``M`` are recorded (:func:`~symkf.exact.algebraic.known_real_roots`) from
    the roots of ``f`` alone: when ``M`` is squarefree its roots ``+-sqrt(lambda_i lambda_j)`` are
    distinct, so ``lambda_i lambda_j`` is real exactly when complex conjugation maps the pair
    ``{i, j}`` to itself (a conjugate pair, or two real roots), and the real roots of ``M`` are the
    ``+-sqrt`` of those products that are positive.  Naming ``|lambda|`` then needs no isolation of
    the ``d(d - 1)`` complex roots of ``M`` (of degree 4032 for a dense 64 x 64 A).  None when ``M``
    is not squarefree (products that coincide: rotations) or a real root's factor is not decided."""
    d, c = len(f) - 1, abs(f[-1])
    bits = (d - 1) * with_prec(64, lambda: sum(((1 + abs(c * r)).log() for r in _complex_roots(f, 64)), flint.arb(0))
                                / flint.arb(2).log())
    budget.check("max_modulus_bits", (d * (d - 1) + 1) * math.ceil(float(bits.upper())), "A",
                 f"the bit size (d(d - 1) + 1 coefficients of at most (d - 1) sum log2(1 + |c lambda_i|) bits) of "
                 f"the polynomial of the products of pairs of conjugate eigenvalues of degree d = {d}")
    g = [int(v) * c ** (2 * k) for k, v in enumerate(_subset_product_poly(f, 2).coeffs())]  # G(c^2 z)
    content = math.gcd(*g)
    M = flint.fmpz_poly([g[k // 2] // content if k % 2 == 0 else 0 for k in range(2 * len(g) - 1)])
    factors = _factors(tuple(int(v) for v in M.coeffs()))
    if sum(h.degree() for h in factors) != M.degree():
        return None
    roots = lambda prec: _complex_roots(f, prec)  # noqa: E731
    conj = _conjugates(f)
    if conj is None:
        return None
    sources, products = [], []
    for i in range(d):
        for j in range(i + 1, d):
            if conj[i] == j:   # lambda_i conj(lambda_i) = |lambda_i|^2 > 0
                size = lambda prec, i=i: abs(roots(prec)[i])  # noqa: E731
                products.append(lambda prec, size=size: size(prec) ** 2)
            elif conj[i] == i and conj[j] == j:
                products.append(lambda prec, i=i, j=j: roots(prec)[i].real * roots(prec)[j].real)
                if real_sign(products[-1]) < 0:
                    continue
                size = lambda prec, i=i, j=j: (abs(roots(prec)[i]) * abs(roots(prec)[j])).sqrt()  # noqa: E731
            else:
                continue
            sources += [size, lambda prec, size=size: -size(prec)]
    # the factors of G: q(x^2) for an even factor q(x^2) of M, else F(x) F(-x) for a pair F(x), +-F(-x) of them
    halves = {}
    for h in factors:
        c = [int(v) for v in (h if not any(int(v) for v in h.coeffs()[1::2]) else
                              h * flint.fmpz_poly([(-1) ** k * int(v) for k, v in enumerate(h.coeffs())])).coeffs()]
        q = flint.fmpz_poly(c[::2])
        q = q / q.content()
        q = q if q.leading_coefficient() > 0 else -q
        halves[tuple(int(v) for v in q.coeffs())] = q
    if not known_real_roots(list(halves.values()), products):
        return None
    return M if known_real_roots(factors, sources) else None


def _conjugates(f: tuple[int, ...]) -> list[int] | None:
    """For each root of ``f`` (flint's ordering) the index of its complex conjugate: itself for a
    real root (flint isolates real roots with an exactly zero imaginary part), else the one root
    whose isolating ball meets the conjugate ball."""
    for prec in (64, 256, 1024, 4096):
        roots = _complex_roots(f, prec)
        conj = []
        for r in roots:
            hits = [k for k, s in enumerate(roots) if s.overlaps(r.conjugate())] if r.imag != 0 else [len(conj)]
            if len(hits) != 1:
                break
            conj.append(hits[0])
        else:
            return conj
    return None


def _negated_index(f: flint.fmpz_poly, index: int) -> int:
    """Index of ``-r`` among the roots of ``f(-x)`` for the real root ``r`` of index ``index`` of
    ``f``: flint lists real roots first, ascending, so negation reverses them."""
    reals = sum(1 for r in _complex_roots(tuple(int(c) for c in f.coeffs()), 64) if r.imag == 0)
    return reals - 1 - index


def _rational_norm(lam: "Eigenvalue") -> Fraction | None:
    """``rho = lambda conj(lambda)`` when it is rational and ``x^d f(rho/x)`` is proportional to the
    minimal polynomial ``f`` (all conjugates then pair as ``mu, rho/mu``, e.g. ``r zeta`` with
    ``r^2`` rational); else None.  Exact: the coefficients ``a_k rho^k = c a_(d-k)`` make
    ``rho/lambda`` a root of ``f``, and its certified ball meets the isolating ball of
    ``conj(lambda)`` only, so ``rho/lambda = conj(lambda)``."""
    a = [int(c) for c in lam.minpoly.coeffs()]
    d = len(a) - 1
    if a[0] == 0:
        return None
    c = Fraction(a[0], a[d])
    num, den = (c * c).numerator, (c * c).denominator
    p, exact_p = sp.integer_nthroot(num, d)
    q, exact_q = sp.integer_nthroot(den, d)
    if not (exact_p and exact_q):
        return None
    for sign in (1, -1) if d % 2 == 0 else (1,):
        rho = Fraction(int(p), int(q)) * sign
        if rho > 0 and all(a[k] * rho ** k == c * a[d - k] for k in range(d + 1)):
            break
    else:
        return None
    for prec in (64, 256, 1024):
        roots = _complex_roots(tuple(a), prec)
        image = with_prec(prec, lambda: flint.acb(rho.numerator) / flint.acb(rho.denominator) / roots[lam.root_index])
        conj = roots[lam.root_index].conjugate()
        hits = [i for i, r in enumerate(roots) if r.overlaps(image)]
        if len(hits) == 1:
            return rho if [i for i, r in enumerate(roots) if r.overlaps(conj)] == hits else None
    return None


@dataclass(frozen=True, eq=False)
class Eigenvalue:
    """An eigenvalue: root ``root_index`` of the irreducible ``minpoly`` (over Q)."""

    minpoly: flint.fmpz_poly
    root_index: int
    multiplicity: int
    geometric: int | None = None  # dimension of the eigenspace; None: equal to ``multiplicity``

    @property
    def defective(self) -> bool:
        """Whether the eigenvalue has Jordan chains (fewer eigenvectors than its multiplicity)."""
        return self.geometric is not None and self.geometric < self.multiplicity

    @property
    def is_zero(self) -> bool:
        """Whether the eigenvalue is 0 (minimal polynomial x)."""
        return self.minpoly.degree() == 1 and self.minpoly.coeffs()[0] == 0

    @cached_property
    def expr(self) -> sp.Expr:
        """The eigenvalue as an exact sympy expression: a rational, a quadratic radical,
        ``exp(2 pi i k/m)``, ``cos(2 pi k/m)`` or ``alpha exp(2 pi i k/m)`` (periodic) when it has
        that closed form, else a :class:`~symkf.exact.algebraic.FlintRoot` (root ``root_index`` of
        ``minpoly`` in flint's ordering; a ``CRootOf`` would cost sympy's root isolation, slow
        at degree 32, and its index cannot be read off flint's balls: sympy orders its complex
        roots by the corners of its own isolating rectangles).  Also the generator a number
        field adjoins for it (:mod:`symkf.engine.rows`)."""
        f = self.minpoly
        if f.degree() <= 2 or f.is_cyclotomic() or _cosine_order(f):
            return _nice_expr(f, self.root_index)
        m, _ = self.phase
        if m is None:
            return FlintRoot(f, self.root_index)
        if m <= 2:   # real: +-alpha, without sympy evaluating alpha (a CRootOf: its real roots isolated)
            return self.modulus.exact if m == 1 else -self.modulus.exact
        # lambda = alpha exp(2 pi i k/m): k from the ball of m arg(lambda) / (2 pi)
        ball = root_ball(f, self.root_index, 128)
        lo, hi = _arb_interval(with_prec(128, lambda: ball.arg() * m / (2 * flint.arb.pi())))
        near = range(math.floor(lo), math.ceil(hi) + 1) if hi - lo < 1 else range(m)
        return _match(ball, [self.modulus.exact * sp.exp(2 * sp.pi * sp.I * sp.Rational(j % m, m)) for j in near])

    @cached_property
    def phase(self) -> tuple[int | None, "RatioEvidence"]:
        """:func:`_phase_order`: the order of ``lambda / |lambda|`` as a root of unity, with its proof."""
        return _phase_order(self)

    def ball(self, prec: int) -> flint.acb:
        """A certified complex ball (flint ``acb``) around the eigenvalue at ``prec`` bits."""
        return root_ball(self.minpoly, self.root_index, precision(prec))

    @property
    def key(self) -> tuple[tuple[int, ...], int]:
        """The eigenvalue as a hashable key: (minimal polynomial coefficients, root index)."""
        return eigenvalue_key(self.minpoly, self.root_index)

    @property
    def is_real(self) -> bool:
        """Whether the eigenvalue is real (flint isolates the real roots of an integer polynomial
        with an exactly zero imaginary part)."""
        return self.ball(64).imag == 0

    @property
    def label(self) -> str:
        """The eigenvalue for people: its closed form when short (``-3√2/5 + 3√2/5 i``), else its
        approximate value and monic minimal polynomial (``root ≈ 1.26 of x^3 - 2``)."""
        return number_text(self.expr) or root_text(self.minpoly, approximate(self.ball(64)))

    @cached_property
    def modulus(self) -> AlgebraicNumber:
        """``|lambda|`` exactly: ``+-lambda`` for a real eigenvalue, ``sqrt(rho)`` when
        ``lambda conj(lambda) = rho`` is rational (:func:`_rational_norm`), else a root of the
        polynomial of the products of pairs of roots (:func:`_pair_modulus_poly`, degree
        ``d(d - 1)`` for ``d = deg lambda``, its real roots read off the roots of the minimal
        polynomial) or, when such products coincide, of :func:`_abs_poly` (degree ``d(d + 1)``,
        every root isolated)."""
        if self.is_zero:
            return AlgebraicNumber.from_expr(sp.Integer(0))
        f = self.minpoly
        ball = self.ball(64)
        if self.is_real:
            g = f if ball.real > 0 else flint.fmpz_poly([(-1) ** k * int(c) for k, c in enumerate(f.coeffs())])
            return real_from_ball(g if g.leading_coefficient() > 0 else -g, self.root_index if ball.real > 0
                                  else _negated_index(f, self.root_index))
        rho = _rational_norm(self)
        if rho is not None:
            return AlgebraicNumber(flint.fmpz_poly([-rho.numerator, 0, rho.denominator]), 1)
        coeffs = tuple(int(c) for c in f.coeffs())
        size = lambda prec: flint.acb(abs(self.ball(prec)))  # noqa: E731
        pairs = _pair_modulus_poly(coeffs)
        if pairs is not None:
            return real_from_ball(*identify(pairs, size, "modulus", real=True))
        d, b = len(coeffs) - 1, max(abs(c).bit_length() for c in coeffs)
        D = d * (d + 1) // 2
        budget.check("max_modulus_bits", (2 * D + 1) * D * b, "A", f"the bit size (2 D + 1 coefficients of about "
                     f"D b bits, D = d(d+1)/2) of the polynomial giving |lambda| for an eigenvalue of degree d = {d} "
                     f"with b = {b}-bit coefficients")
        poly, idx = identify(_abs_poly(coeffs), size, "modulus")
        return real_from_ball(poly, idx)

    def __repr__(self) -> str:
        jordan = f", eigenvectors={self.geometric}" if self.defective else ""
        return f"Eigenvalue({self.expr}, multiplicity={self.multiplicity}{jordan})"


@dataclass(frozen=True)
class RatioEvidence:
    """Why ``num / den`` (or ``num / conj(den)``) is, or is not, a root of unity of order ``order``;
    the ratio's minimal polynomial is found when first asked for (an aperiodicity decided by
    :func:`_arg_denominator` needs none)."""

    num: "Eigenvalue"
    den: "Eigenvalue"
    conj_den: bool
    order: int | None
    known: flint.fmpz_poly | None = None

    @cached_property
    def minpoly(self) -> flint.fmpz_poly:
        """The ratio's minimal polynomial over Q."""
        if self.known is not None:
            return self.known
        fa, fb = (tuple(int(c) for c in e.minpoly.coeffs()) for e in (self.num, self.den))
        return identify(_ratio_poly(fa, fb), self.ball, "eigenvalue ratio")[0]

    def ball(self, prec: int) -> flint.acb:
        """A certified ball around the ratio at ``prec`` bits."""
        prec = precision(prec)
        d = self.den.ball(prec)
        return with_prec(prec, lambda: self.num.ball(prec) / (d.conjugate() if self.conj_den else d))

    def __str__(self) -> str:
        label = f"({self.num.label})/{'conj' if self.conj_den else ''}({self.den.label})"
        if self.order:
            return f"{label} has minimal polynomial Phi_{self.order}, a primitive {self.order}-th root of unity"
        d = self.num.minpoly.degree() * self.den.minpoly.degree()
        t = with_prec(256, lambda: self.ball(256).arg() / (2 * flint.arb.pi()))
        lo, hi = (Fraction(int(v.p), int(v.q)) for v in _arb_interval(t))
        if self.known is None and d > budget.LIMITS.max_proof_resultant_degree and _least_denominator(lo, hi) > 2 * d * d:
            return (f"{label} has arg/(2 pi) in {t.str(20)} (certified), an interval "
                    f"holding no fraction of denominator <= 2 d^2 = {2 * d * d}, while a root of unity of degree "
                    f"<= d = {d} has order <= 2 d^2, so it is not a root of unity (aperiodic)")
        return (f"{label} has modulus 1 and minimal polynomial {poly_text(self.minpoly, monic=False)}, "
                "which is not cyclotomic, so it is not a root of unity (aperiodic)")


def root_of_unity_order(num: Eigenvalue, den: Eigenvalue, conj_den: bool = False) -> RatioEvidence:
    """Order of ``num / den`` (or ``num / conj(den)``) as a root of unity, with its proof.

    ``.order`` is None when the ratio is not a root of unity; ``str()`` of the result is the proof.
    """
    if num.is_real and den.is_real and num.modulus == den.modulus:  # num/den = +-1, no resultant
        sign = 1 if (num.ball(64).real > 0) == (den.ball(64).real > 0) else -1
        return RatioEvidence(num, den, conj_den, 1 if sign > 0 else 2, flint.fmpz_poly([-sign, 1]))
    evidence = RatioEvidence(num, den, conj_den, None)
    q = _arg_denominator(evidence.ball, num.minpoly.degree() * den.minpoly.degree())
    if q == 0:
        return evidence
    if q is not None and _equal_powers(num.minpoly, den.minpoly, q):
        return RatioEvidence(num, den, conj_den, q, flint.fmpz_poly.cyclotomic(q))
    return RatioEvidence(num, den, conj_den, int(evidence.minpoly.is_cyclotomic()) or None, evidence.minpoly)


def _arg_denominator(ball_at, degree: int) -> int | None:
    """For the number in the balls ``ball_at(prec)``, algebraic of degree at most ``degree``: 0 when
    it is proved not a root of unity without its minimal polynomial (a resultant of that degree),
    else the least denominator q of a fraction in the certified interval of ``arg / (2 pi)`` (its
    order if it is a root of unity; None when undecided).  A primitive m-th root of unity has
    degree ``phi(m) >= sqrt(m/2)``, so ``m <= 2 degree^2``, and ``arg / (2 pi)`` is a fraction of
    denominator m: none up to that bound in the interval proves the number no root of unity; and
    no fraction of denominator below q there means no order below q."""
    bound, q = 2 * degree * degree, None
    for prec in (64, 128, 256):
        z = ball_at(prec)
        if z.contains(0):
            continue
        t = with_prec(prec, lambda: z.arg() / (2 * flint.arb.pi()))
        lo, hi = (Fraction(int(v.p), int(v.q)) for v in _arb_interval(t))
        q = _least_denominator(lo, hi)
        if q > bound:
            return 0
    return q


def _equal_powers(fa: flint.fmpz_poly, fb: flint.fmpz_poly, q: int) -> bool:
    """Whether ``x^q`` is one rational constant modulo both ``fa`` and ``fb``: then every root of
    either has the same q-th power, and every ratio of two of them (or of one and a conjugate)
    is a q-th root of unity (``2 exp(2 pi i k/m)``: ``x^m = 2^m``), exactly."""
    powers = []
    for f in (fa, fb):
        f = flint.fmpq_poly(f)
        out, base, e = flint.fmpq_poly([1]), flint.fmpq_poly([0, 1]) % f, q
        while e:
            if e & 1:
                out = out * base % f
            base = base * base % f
            e >>= 1
        if out.degree() > 0:
            return False
        powers.append(out)
    return powers[0] == powers[1]


def _least_denominator(lo: Fraction, hi: Fraction) -> int:
    """The least q such that some p/q lies in [lo, hi] (exact continued fractions): with the
    fractions of the interval written ``(p1 x + p0) / (q1 x + q0)``, x in [a, b], an integer x
    there gives the least denominator at ``x = ceil(a)``; else ``x = floor(a) + 1/y``."""
    q0, q1, a, b = 1, 0, lo, hi
    while True:
        f = math.floor(a)
        if f == a or f + 1 <= b:
            return q1 * math.ceil(a) + q0
        q0, q1, a, b = q1, f * q1 + q0, 1 / (b - f), 1 / (a - f)


def _phase_order(lam: Eigenvalue) -> tuple[int | None, RatioEvidence]:
    """Order of ``lambda / |lambda|`` as a root of unity (the papers' tau for one eigenvalue)."""
    proof = root_of_unity_order(lam, lam, conj_den=True)  # (lambda/|lambda|)^2 = lambda/conj(lambda)
    m = proof.order
    if m is None:
        return None, proof
    if m % 2 == 0:
        return 2 * m, proof
    # m odd: u = lambda/|lambda| has u^m = +-1; the sign of lambda^m decides
    old = flint.ctx.prec
    flint.ctx.prec = 128
    try:
        power = lam.ball(128) ** m
    finally:
        flint.ctx.prec = old
    return (m if power.real > 0 else 2 * m), proof


@dataclass(frozen=True, eq=False)
class EigenBlock(JsonDocument):
    """The eigenvalues of ``A`` of one modulus ``alpha_i`` (Assumption 3)."""

    modulus: AlgebraicNumber
    members: tuple[Eigenvalue, ...]
    period: int | None             # the papers' tau (the public name; also ``.tau``)
    governing_period: int | None   # g: least k with A_i^k a scalar multiple of I
    evidence: tuple[tuple[str, Any], ...] = field(repr=False)  # (claim, its RatioEvidence or text)
    classes: tuple[tuple[int, ...], ...] = field(repr=False)
    class_period: int = field(repr=False)

    @cached_property
    def proof(self) -> str:
        """Why the periods are what they are (formatted on first use: it prints eigenvalues)."""
        return "; ".join(f"{claim}: {why}" if claim else str(why) for claim, why in self.evidence)

    @property
    def tau(self) -> int | None:
        """The papers' tau (``period`` is the same value under its public name)."""
        return self.period

    @property
    def eigenvalues(self) -> tuple[sp.Expr, ...]:
        """Exact eigenvalues, repeated by multiplicity."""
        return tuple(e.expr for e in self.members for _ in range(e.multiplicity))

    @property
    def size(self) -> int:
        """``n_i``, the dimension of the block."""
        return sum(e.multiplicity for e in self.members)

    @property
    def defective(self) -> bool:
        """Whether some eigenvalue of the block has Jordan chains."""
        return any(e.defective for e in self.members)

    @property
    def is_stable(self) -> bool:
        """``alpha_i < 1``: the block's modes decay without measurements and never decide stability."""
        return self.modulus < 1

    @property
    def is_periodic(self) -> bool:
        """Whether the block has a governing period (some power of it is a scalar multiple of I)."""
        return self.governing_period is not None

    def to_dict(self) -> dict[str, Any]:
        """The block of ``symkf analyze --json``: modulus and eigenvalues exact (as text) and as
        10-digit decimals with their degrees, the periods (null when aperiodic), their proof and
        whether the block has Jordan chains."""
        return {"modulus": self.modulus.exact_text(), "modulus_decimal": str(self.modulus.evalf(10)),
                "modulus_degree": self.modulus.minpoly.degree(),
                "eigenvalues": [str(e) for e in self.eigenvalues],
                "eigenvalues_decimal": [str(sp.N(e, 10)) for e in self.eigenvalues],
                "eigenvalue_degrees": [e.minpoly.degree() for e in self.members for _ in range(e.multiplicity)],
                "tau": self.tau, "governing_period": self.governing_period, "proof": self.proof,
                "jordan_chains": self.defective}

    def eigenvalue_words(self, shown: int | None = None) -> str:
        """The eigenvalues for people: each distinct one once (:attr:`Eigenvalue.label`) with its
        algebraic multiplicity, ``1 (×2)``, and its eigenvectors when fewer; the first ``shown``."""
        def one(e: Eigenvalue) -> str:
            times = "" if e.multiplicity == 1 else f" (×{e.multiplicity}" + (
                f", {e.geometric} eigenvector{'s' if e.geometric != 1 else ''})" if e.defective else ")")
            return e.label + times
        words = [one(e) for e in self.members[:shown]]
        if shown is not None and len(self.members) > shown:
            words.append(f"and {len(self.members) - shown} more (.eigenvalues)")
        return ", ".join(words)

    @property
    def modulus_words(self) -> str:
        """The modulus for people: its closed form (``√5/2 + 3/2``), else its decimal and minimal
        polynomial (``root ≈ 1.324717957 of x^3 - x - 1``)."""
        m = self.modulus
        return number_text(m.exact) or root_text(sympy_to_fmpz(m.minpoly), str(m.evalf(10)))

    def __repr__(self) -> str:
        """``EigenBlock(modulus 6/5; eigenvalues 1/2 + √3/2 i, 1 (×2); τ = 6, governing period 3)``:
        :meth:`eigenvalue_words`, the first :data:`SHOWN_EIGENVALUES` distinct eigenvalues."""
        periods = (f"τ = {self.tau}" if self.tau is not None else "aperiodic (no τ)") + ", governing period " + (
            str(self.governing_period) if self.governing_period is not None else "none")
        return (f"EigenBlock(modulus {self.modulus_words}; eigenvalues {self.eigenvalue_words(SHOWN_EIGENVALUES)}; "
                f"{periods})")


    def _repr_latex_(self) -> str:
        """The block for a notebook: its modulus, the first :data:`SHOWN_EIGENVALUES` distinct
        eigenvalues with their multiplicities (a root without a short closed form by its decimal)."""
        def one(e: Eigenvalue) -> str:
            shown = sp.latex(e.expr) if number_text(e.expr) is not None else rf"\approx {sp.latex(sp.N(e.expr, 6))}"
            return shown + (rf"\ (\times {e.multiplicity})" if e.multiplicity > 1 else "")
        values = r",\ ".join(one(e) for e in self.members[:SHOWN_EIGENVALUES])
        more = rf",\ \ldots\ ({len(self.members) - SHOWN_EIGENVALUES}\text{{ more}})" \
            if len(self.members) > SHOWN_EIGENVALUES else ""
        modulus = (f"= {sp.latex(self.modulus.exact)}" if number_text(self.modulus.exact) else
                   rf"\approx {self.modulus.evalf(10)}")
        period = (rf"g = {self.governing_period}" if self.governing_period is not None else r"\text{aperiodic}")
        return rf"$|\lambda| {modulus}:\quad \lambda \in \{{{values}{more}\}},\quad {period}$"


#: distinct eigenvalues an EigenBlock's repr lists
SHOWN_EIGENVALUES = 6


# -- eigenvalues ------------------------------------------------------------------
def _nice_expr(f: flint.fmpz_poly, idx: int) -> sp.Expr:
    """The closed form of root ``idx`` of the irreducible ``f`` of degree at most 2, cyclotomic or
    of a cosine (:func:`_cosine_order`): a rational, a quadratic radical, ``exp(2 pi i k/m)`` or
    ``cos(2 pi k/m)``, the choice among the roots checked against the certified ball of the root."""
    p = fmpz_to_sympy(f)
    if p.degree() == 1:
        return -p.nth(0) / p.nth(1)
    target = root_ball(f, idx, 128)
    m = int(f.is_cyclotomic())
    if m:
        cands = [sp.exp(2 * sp.pi * sp.I * sp.Rational(k, m)) for k in range(m) if gcd(k, m) == 1]
    elif p.degree() == 2:
        cands = list(sp.roots(p, x))
    else:
        m = _cosine_order(f)
        cands = [sp.cos(2 * sp.pi * sp.Rational(k, m)) for k in range(m // 2 + 1) if gcd(k, m) == 1]
    return _match(target, cands)


def _cosine_order(f: flint.fmpz_poly) -> int:
    """``m`` when the roots of ``f`` are the ``cos(2 pi k/m)``, ``gcd(k, m) = 1`` (then ``2 x`` is a
    root of the minimal polynomial ``g`` of ``2 cos(2 pi/m)`` and ``x^d g(x + 1/x)`` is the
    cyclotomic ``Phi_m``), else 0: such eigenvalues get their trigonometric form, which
    :class:`~symkf.exact.field.NumberField` presents cheaply by ``2 cos(2 pi/m)``."""
    d = f.degree()
    c = [int(v) for v in f.coeffs()]
    known = _known_roots(tuple(c))  # recognised in closed form without the degree-2d polynomial below
    if known and known[0][:3] == ("cos", 0, Fraction(1, 2)):
        return known[0][4]
    if c[d] & (c[d] - 1):  # the leading coefficient of a cosine's polynomial is a power of 2
        return 0
    g = [c[k] * 2 ** (d - k) for k in range(d + 1)]  # 2^d f(x/2), monic times c[d]
    if any(v % c[d] for v in g):
        return 0
    g = [v // c[d] for v in g]
    t = flint.fmpz_poly([1, 0, 1])  # x^2 + 1: x^d g(x + 1/x) = sum g_k (x^2 + 1)^k x^(d - k), by Horner
    h = flint.fmpz_poly([g[d]])
    for k in range(d - 1, -1, -1):
        h = h * t + flint.fmpz_poly([0] * (d - k) + [g[k]])
    return int(h.is_cyclotomic())


def _match(target: flint.acb, cands: list[sp.Expr]) -> sp.Expr:
    """The candidate (exact, distinct closed forms) whose value lies in the certified ball ``target``."""
    for c in cands:
        v = complex(c.evalf(40))
        tol = 1e-10 * (1 + abs(v))  # float rounding of v, far below root separation
        if target.overlaps(flint.acb(flint.arb(v.real, tol), flint.arb(v.imag, tol))):
            return c
    raise AssertionError(f"no exact form matches {target}")  # pragma: no cover


def _factor_charpoly(A: sp.MatrixBase, K: NumberField) -> list[tuple[list[Elem], int, list[tuple[flint.fmpz_poly, int]]]]:
    """Irreducible factors ``h`` of the characteristic polynomial over K with multiplicity,
    each with its roots as (Q-minimal polynomial, root index)."""
    if K.is_rational:
        # through the field's conversion: an entry may be rational without being written as one
        chi = flint.fmpq_mat([[rational_value(a) for a in row] for row in K.matrix(A)]).charpoly()
        out = []
        for f, e in chi.factor()[1]:
            fz = flint.fmpz_poly([int(c) for c in (f * f.denom()).coeffs()])
            fz = fz if fz.leading_coefficient() > 0 else -fz
            h = [flint.fmpq_poly([c]) for c in f.coeffs()]
            out.append((h, e, [(fz, i) for i in range(fz.degree())]))
        return out
    if A.is_upper or A.is_lower:
        return _triangular_factors(A, K)
    theta_poly = flint.fmpz_poly([int(c) for c in K.modulus.coeffs()])  # monic integral theta
    out = []
    for coeffs, e in nfpoly.factor(K, nfpoly.charpoly(K, K.matrix(A))):
        known = nfpoly.unit_root_minpoly(K, coeffs)
        candidates = [known] if known is not None else [g.numer() // g.numer().content()
                                                        for g, _ in nfpoly.norm(K, coeffs).factor()[1]]
        candidates = [g if g.leading_coefficient() > 0 else -g for g in candidates]
        roots = [(g, i) for g in candidates for i in range(g.degree())]
        # the roots of the irreducible h are deg h distinct roots of its norm (or of the minimal
        # polynomial they share), never excluded: once exactly deg h remain, they are h's (the others
        # are excluded at the least precision)
        for prec in (64, 256, 1024):
            balls = _coefficient_balls(coeffs, theta_poly, K.theta_index, prec)
            isolated = {id(g): _complex_roots(tuple(int(c) for c in g.coeffs()), prec) for g in candidates}
            roots = [(g, i) for g, i in roots if _maybe_root(balls, isolated[id(g)][i], prec)]
            if len(roots) == len(coeffs) - 1:
                break
        if len(roots) != len(coeffs) - 1:
            raise RuntimeError("eigenvalue selection failed")  # pragma: no cover
        out.append((coeffs, e, roots))
    return out


def _triangular_factors(A: sp.MatrixBase, K: NumberField) -> list[tuple[list[Elem], int, list[tuple[flint.fmpz_poly, int]]]]:
    """:func:`_factor_charpoly` of a triangular ``A``: the factors ``x - a`` of its diagonal entries,
    each root known by the entry's own minimal polynomial (:func:`~symkf.exact.algebraic.root_of`),
    with no norm over K (Trager's norm of ``x - sin(2 pi/517)`` over its degree-460 field is
    slow)."""
    entries: dict[tuple, list] = {}
    for v in A.diagonal():
        a = K.convert(v)
        entry = entries.setdefault(tuple(a.coeffs()), [a, v, 0])
        entry[2] += 1
    return [([-a, flint.fmpq_poly([1])], e, [root_of(v)]) for a, v, e in entries.values()]


def _maybe_root(h: list[flint.acb], r: flint.acb, prec: int) -> bool:
    """False when interval arithmetic at ``prec`` bits proves h(r) != 0 for the number in the root's
    isolating ball ``r`` (``h``: balls of the coefficients at ``theta``, :func:`_coefficient_balls`);
    True otherwise."""
    return with_prec(prec, lambda: sum((c * r ** k for k, c in enumerate(h)), flint.acb(0)).contains(0))


def _coefficient_balls(h: list[Elem], mpoly: flint.fmpz_poly, t_idx: int, prec: int) -> list[flint.acb]:
    """Balls of the coefficients of ``h`` (polynomials in ``theta``) at ``prec`` bits."""
    theta = root_ball(mpoly, t_idx, prec)
    return with_prec(prec, lambda: [flint.acb_poly([flint.acb(flint.arb(c)) for c in a.coeffs()])(theta) for a in h])


def _poly_at(K: NumberField, Ak: list[list[Elem]], h: list[Elem]) -> list[list[Elem]]:
    """``h(A)`` over K by Horner (``h`` from the constant coefficient up); over Q in flint's rational
    matrices (a dense 40 x 40 A: the entries' dot products in Python cost seconds)."""
    n = len(Ak)
    if K.is_rational:
        M = flint.fmpq_mat([[rational_value(a) for a in row] for row in Ak])
        H = flint.fmpq_mat(n, n)
        for c in reversed(h):
            H = H * M
            for i in range(n):
                H[i, i] += rational_value(c)
        return [[flint.fmpq_poly([H[i, j]]) for j in range(n)] for i in range(n)]
    H = [[h[-1] if i == j else flint.fmpq_poly([]) for j in range(n)] for i in range(n)]
    for c in reversed(h[:-1]):
        H = [[(K.dot(H[i], [Ak[k][j] for k in range(n)]) + (c if i == j else 0)) % K.modulus
              for j in range(n)] for i in range(n)]
    return H


def _geometric_multiplicities(A: sp.MatrixBase, K: NumberField, factors) -> list[int | None]:
    """Per factor ``h`` of the characteristic polynomial with multiplicity ``e > 1``, the dimension
    of each root's eigenspace, ``(n - rank h(A)) / deg h``; None for simple factors."""
    n = A.shape[0]
    Ak = K.matrix(A)
    return [None if e == 1 else (n - rank_rows(K, _poly_at(K, Ak, h), n)) // (len(h) - 1)
            for h, e, _ in factors]


def eigenvalue_key(f: flint.fmpz_poly, i: int) -> tuple[tuple[int, ...], int]:
    """Root ``i`` (flint's ordering) of the irreducible ``f`` as a hashable key."""
    return tuple(int(c) for c in f.coeffs()), i


def eigenvalues(A: Any) -> list[Eigenvalue]:
    """The distinct eigenvalues of ``A`` with multiplicities, exactly (A need not be diagonalizable).

    Parameters
    ----------
    A : matrix-like
        A square matrix with exact entries (see :mod:`symkf.exact.numbers`).

    Returns
    -------
    list of Eigenvalue
        Each a root of an irreducible integer polynomial (``.minpoly``, ``.root_index``), with
        its algebraic ``.multiplicity``, exact ``.expr`` and ``.modulus``.

    Raises
    ------
    ShapeError
        ``A`` is not square.
    InputError
        An entry is not an exact number.

    Examples
    --------
    The Jordan block ``[[1, 1], [0, 1]]`` has the double eigenvalue 1:

    >>> import symkf as sk
    >>> [(e.expr, e.multiplicity) for e in sk.eigenvalues([[1, 1], [0, 1]])]
    [(1, 2)]
    """
    A = sp.Matrix(to_exact_matrix(A, "A"))
    return _eigenvalues(A)


def _eigenvalues(A: sp.Matrix, jordan: bool = False) -> list[Eigenvalue]:
    """The eigenvalues of ``A``, block by block (:func:`diagonal_blocks`); an eigenvalue of several
    blocks has the sum of their (algebraic and geometric) multiplicities."""
    if A.shape[0] != A.shape[1]:
        raise ShapeError(f"A: must be square, got {A.shape[0]}x{A.shape[1]}")
    found: dict[tuple[tuple[int, ...], int], list] = {}
    for index in diagonal_blocks(A):
        for f, i, e, geo in _block_spectrum(sp.ImmutableMatrix(A.extract(index, index)), jordan):
            entry = found.setdefault(eigenvalue_key(f, i), [f, i, 0, 0])
            entry[2] += e
            entry[3] += e if geo is None else geo
    return [Eigenvalue(f, i, e, None if geo == e else geo) for f, i, e, geo in found.values()]


@lru_cache(maxsize=256)
def _block_spectrum(sub: sp.ImmutableMatrix, jordan: bool) -> tuple[tuple[flint.fmpz_poly, int, int, int | None], ...]:
    """(minimal polynomial, root index, multiplicity, eigenspace dimension or None) of each
    eigenvalue of one diagonal block, in the field of its entries."""
    K = field_of(sub)
    factors = factors_in(sub, K)
    geometric = _geometric_multiplicities(sub, K, factors) if jordan else [None] * len(factors)
    return tuple((f, i, e, geo) for (_, e, roots), geo in zip(factors, geometric) for f, i in roots)


def factors_in(A: sp.MatrixBase, K: NumberField) -> tuple:
    """:func:`_factor_charpoly` of ``A`` over ``K``, cached (the spectrum, the PBH test and the
    modal form of one diagonal block factor over the same field)."""
    if not isinstance(K, NumberField):
        raise InputError(f"K: expected a symkf NumberField, got {type(K).__name__}")
    # symkf's own calls hold exact matrices already: converting each entry again costs seconds at n = 64
    A = sp.ImmutableMatrix(A) if isinstance(A, sp.MatrixBase) and not outside(__name__) else to_exact_matrix(A, "A")
    return _factors_over(A, K.generators)


@lru_cache(maxsize=256)
def _factors_over(A: sp.ImmutableMatrix, generators: tuple[sp.Expr, ...]) -> tuple:
    return tuple(_factor_charpoly(A, NumberField(generators)))


def support(A: sp.MatrixBase, members: Sequence[Eigenvalue]) -> list[int]:
    """The coordinates of the diagonal blocks of ``A`` that have one of ``members`` as an
    eigenvalue: the eigenvectors of ``members`` vanish outside them."""
    keys = {e.key for e in members}
    return sorted(i for index in diagonal_blocks(A)
                  if keys & {eigenvalue_key(f, j) for f, j, _, _ in _block_spectrum(sp.ImmutableMatrix(A.extract(index, index)), True)}
                  for i in index)


def unseen(A: sp.MatrixBase, C: sp.MatrixBase) -> frozenset[tuple[tuple[int, ...], int]]:
    """The eigenvalues of ``A`` with an eigenvector in ``ker C`` (PBH), as keys (minimal polynomial
    coefficients, root index).

    Per diagonal block ``A_b`` (columns ``C_b``), in the field K of the entries of ``A_b`` and
    ``C_b``: the roots of an irreducible factor ``h`` over K of the characteristic polynomial are
    conjugate over K, so all or none are unseen, and some is iff ``ker h(A_b)`` meets the
    unobservable subspace ``ker col{C_b, C_b A_b, ..., C_b A_b^(n_b - 1)}`` (A_b-invariant):
    iff ``rank col{h(A_b), C_b, ..., C_b A_b^(n_b - 1)} < n_b``.  An eigenvalue seen in each of
    several blocks may still be unseen jointly; it is tested on the whole of ``A`` and ``C``."""
    out: set = set()
    blocks_of: dict = {}
    for index in diagonal_blocks(A):
        sub, Cb = A.extract(index, index), C.extract(list(range(C.rows)), index)
        K = field_of(sub, Cb)
        Ak = K.matrix(sub)
        rows = K.matrix(Cb)
        observability = []
        for _ in range(len(index)):
            observability += rows
            rows = [K.vecmat(r, Ak) for r in rows]
        for h, _, roots in factors_in(sub, K):
            keys = [eigenvalue_key(f, i) for f, i in roots]
            if rank_rows(K, _poly_at(K, Ak, h) + observability, len(index)) < len(index):
                out.update(keys)
            for k in keys:
                blocks_of[k] = blocks_of.get(k, 0) + 1
    for k, count in blocks_of.items():
        if count > 1 and k not in out:
            lam = Eigenvalue(flint.fmpz_poly(list(k[0])), k[1], 1).expr
            if rank(sp.Matrix.vstack(A - lam * sp.eye(A.shape[0]), C)) < A.shape[0]:
                out.add(k)
    return frozenset(out)


def eigen_blocks(A: Any) -> tuple[EigenBlock, ...]:
    """The eigen-blocks of ``A``, by decreasing modulus (Assumption 3).

    ``A`` need not be diagonalizable: each eigenvalue records the dimension of
    its eigenspace (``Eigenvalue.geometric``), and blocks with Jordan chains say
    so (``EigenBlock.defective``).  Zero eigenvalues form a block of modulus 0.

    Parameters
    ----------
    A : matrix-like
        A square matrix with exact entries.

    Returns
    -------
    tuple of EigenBlock
        Each with the exact ``.modulus`` ``alpha_i``, ``.eigenvalues``, the papers' period
        ``.period`` (``tau``: least ``tau`` with ``A_i^tau = alpha_i^tau I``), the
        ``.governing_period`` (least ``k`` with ``A_i^k`` a scalar multiple of ``I``) and the
        ``.proof`` of both; a period is ``None`` only when aperiodicity is proved.

    Raises
    ------
    ShapeError
        ``A`` is not square.
    InputError
        An entry is not an exact number.

    Examples
    --------
    ``A = 2R(pi/2)`` has eigenvalues ``+-2i``, one block of modulus 2.  By hand:
    ``A^2 = -4I`` is a scalar multiple of ``I`` (governing period 2) and ``A^4 = 16I = 2^4 I``
    is the first power equal to ``alpha^k I`` (``tau = 4``):

    >>> import symkf as sk
    >>> (block,) = sk.eigen_blocks([[0, -2], [2, 0]])
    >>> block.modulus.exact, block.eigenvalues, block.period, block.governing_period
    (2, (2*I, -2*I), 4, 2)

    Blocks come by decreasing modulus:

    >>> [b.modulus.exact for b in sk.eigen_blocks([["1/2", 0], [0, 2]])]
    [2, 1/2]
    """
    A = sp.Matrix(to_exact_matrix(A, "A"))
    evs = _eigenvalues(A, jordan=True)
    groups: list[list[Eigenvalue]] = []
    for ev in evs:
        for g in groups:
            if g[0].modulus == ev.modulus:
                g.append(ev)
                break
        else:
            groups.append([ev])
    groups.sort(key=lambda g: g[0].modulus, reverse=True)
    return tuple(_block(g) for g in groups)


def _block(members: list[Eigenvalue]) -> EigenBlock:
    if members[0].is_zero:  # A_i is nilpotent: A_i^k = 0 = 0^k I once k reaches the longest chain
        return EigenBlock(members[0].modulus, tuple(members), 1, 1, (("", "A_i is nilpotent (eigenvalue 0)"),),
                          ((0,),), 1)
    proofs = []
    tau: int | None = 1
    for ev in members:
        m, proof = ev.phase
        if m is None:
            tau = None
            proofs.append(("tau", proof))
            break
        tau = _lcm(tau, m)
    # classes: eigenvalues whose ratios are roots of unity; the class period makes A^k scalar per class
    classes: list[list[int]] = []
    orders: dict[tuple[int, int], int] = {}
    aperiodic_proof = None
    for i, ev in enumerate(members):
        for cl in classes:
            proof = root_of_unity_order(ev, members[cl[0]])
            m = proof.order
            if m is not None:
                cl.append(i)
                orders[(cl[0], i)] = m
                break
            aperiodic_proof = aperiodic_proof or proof
        else:
            classes.append([i])
    class_period = 1
    for m in orders.values():
        class_period = _lcm(class_period, m)
    governing = class_period if len(classes) == 1 else None
    if governing is None:
        proofs.append(("governing period", aperiodic_proof))
    elif tau is not None:
        proofs.append(("", f"A_i^{governing} is a scalar multiple of I and A_i^{tau} = alpha^{tau} I"))
    return EigenBlock(members[0].modulus, tuple(members), tau, governing, tuple(proofs),
                      tuple(tuple(c) for c in classes), class_period)

def spectral_radius(A: Any) -> AlgebraicNumber:
    """``rho(A)`` exactly (the largest eigenvalue modulus, from :func:`eigenvalues`)."""
    return max(ev.modulus for ev in eigenvalues(A))

check_public(globals())
