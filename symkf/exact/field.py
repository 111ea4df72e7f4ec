"""Number fields Q(theta) with fast exact arithmetic (python-flint).

``NumberField(generators)`` is ``Q(generators)`` presented as ``Q(theta)``:
the primitive element ``theta = sum k_i c_i h_i`` (``h_i`` the generator ``g_i``
without rational coefficients, ``g_i = a_i + b_i h_i``; ``c_i`` the least integer
making ``c_i h_i`` an algebraic integer; small integers ``k_i``) and every generator's
representation come from certified complex embeddings
(:mod:`symkf.exact.embedding`: Trager's norm for the primitive element, exact
interpolation over all embeddings for the representations), so nothing is
factored over a number field.  ``theta`` is an algebraic integer and
``modulus`` its monic minimal polynomial.  Elements are ``fmpq_poly`` reduced
modulo ``modulus``.  This mirrors sympy's ``polys/matrices`` layering: the
domain object is :class:`NumberField`, the representation ``fmpq_poly``, and
:mod:`symkf.exact.linalg` / :mod:`symkf.exact.nfpoly` the algorithms.

Every generator's representation ``p`` is certified twice: exactly
(``minpoly_g(p(theta)) = 0`` modulo ``modulus``) and by the root it denotes
(the ball of ``p(theta)`` meets the isolating ball of ``g`` and of no other
conjugate).
"""

from __future__ import annotations

from functools import lru_cache
from math import gcd
from typing import Any, Iterable, Sequence

import flint
import sympy as sp

from ..arguments import check_public
from ..errors import InputError
from .algebraic import with_prec, fmpz_to_sympy, identify, precision, root_ball, root_of
from .embedding import Integral, adjoin, integral_scale, interpolate, vanishes
from .numbers import sympify

Elem = flint.fmpq_poly

_NOT_ALGEBRAIC = (InputError, sp.polys.polyerrors.NotAlgebraic, sp.polys.polyerrors.PolynomialError,
                  NotImplementedError)


@lru_cache(maxsize=4096)
def _integral(expr: sp.Expr) -> tuple[Integral, int]:
    """``c * expr`` as an algebraic integer, with the least such ``c > 0``."""
    poly, idx = root_of(expr)
    c, monic = integral_scale(poly)
    _, index = identify(monic, lambda prec: c * root_ball(poly, idx, prec), lambda: f"{c} * ({expr})")
    return Integral.of(monic, index), c


def _compose(p: Elem, t: Elem, modulus: Elem) -> Elem:
    acc = flint.fmpq_poly([])
    for c in reversed(p.coeffs()):
        acc = (acc * t + c) % modulus
    return acc


def _rational(q: sp.Rational) -> Elem:
    return flint.fmpq_poly([flint.fmpq(int(q.p), int(q.q))])


def rational_value(a: Elem) -> flint.fmpq:
    """The rational an element of Q is (its constant coefficient)."""
    return a[0] if a.length() else flint.fmpq(0)


class _Presentation:
    """Mutable state shared by equal NumberFields: primitive element and converted elements.

    ``atoms`` are the elements represented directly (by interpolation); every other
    representation is field arithmetic on them.  ``certify`` proves each atom's
    representation is the intended root.
    """

    def __init__(self) -> None:
        self.prim: Integral | None = None
        self.theta: sp.Expr = sp.Integer(0)
        self.modulus = flint.fmpq_poly([0, 1])
        self.reps: dict[sp.Expr, Elem] = {}
        self.atoms: set[sp.Expr] = set()
        self.certified: set[sp.Expr] = set()
        self.root_order = 0  # m when theta is zeta_m = exp(2 pi i/m) (the cyclotomic presentation)

    def certify(self) -> None:
        """``minpoly(c a)`` vanishes at ``c rep(theta)`` exactly, and the ball of ``c rep(theta)``
        meets the isolating ball of ``c a`` and of no other conjugate: ``rep(theta) = a``."""
        for e in self.atoms - self.certified:
            beta, c = _integral(e)
            rep = self.reps[e] * c
            if not vanishes(beta.poly, rep, self.modulus) or \
                    identify(beta.poly, lambda prec: self._ball(rep, prec))[1] != beta.index:
                raise AssertionError(f"representation of {e} failed certification")  # pragma: no cover
            self.certified.add(e)

    def _ball(self, a: Elem, prec: int) -> flint.acb:
        t = self.prim.roots(prec)[self.prim.index]
        return with_prec(prec, lambda: flint.acb_poly([flint.acb(flint.arb(c)) for c in a.coeffs()])(t))


@lru_cache(maxsize=128)
def _presentation(generators: tuple[sp.Expr, ...]) -> _Presentation:
    state = _Presentation()
    _start_cyclotomic(state, generators)
    for g in generators:
        _add_generator(state, g)
    state.certify()
    return state


def _root_of_unity_atoms(generators: Sequence[sp.Expr]) -> dict[sp.Expr, sp.Rational]:
    """``exp(i pi r)``, ``cos(pi r)``, ``sin(pi r)`` (``r`` rational) and ``I`` in the generators, with ``r``
    (``I`` as ``exp(i pi/2)``; ``sin`` records ``r`` and needs ``I`` too)."""
    atoms: dict[sp.Expr, sp.Rational] = {}
    for g in generators:
        for a in sp.preorder_traversal(g):
            if a is sp.I:
                atoms[a] = sp.Rational(1, 2)
            elif isinstance(a, (sp.exp, sp.cos, sp.sin)):
                r = a.args[0] / (sp.I * sp.pi if isinstance(a, sp.exp) else sp.pi)
                if r.is_Rational:
                    atoms[a] = r
    return atoms


def _start_cyclotomic(state: _Presentation, generators: Sequence[sp.Expr]) -> None:
    """Present the field by a root of unity when the generators' roots of unity, cosines and
    sines generate all of ``Q(zeta_m)`` or its real subfield ``Q(zeta_m)^+``: the cyclotomic
    polynomial (or the minimal polynomial of ``2 cos(2 pi/m)``) has tiny coefficients, where the
    generic primitive element of a degree-2(p-1) field has huge ones, slowing its arithmetic by
    orders of magnitude.  With ``zeta = exp(2 pi i/m)`` every atom is ``zeta^k`` or
    ``cos(2 pi k/m)`` (``sin(2 pi k/m) = cos(2 pi (m/4 - k)/m)``, ``i = zeta^(m/4)``); the atoms
    generate the fixed field of ``H = {a : sigma_a fixes them}`` (``sigma_a: zeta -> zeta^a``),
    read off the exponents: ``zeta^k`` is fixed iff ``a k = k``, a cosine iff ``a k = +-k`` (mod m).
    Representations are exact by Euler's formula and Chebyshev's ``2 cos(k x) = V_k(2 cos x)``.
    Radicals that generate a whole ``Q(zeta_n)^+`` or ``Q(zeta_n)`` (:func:`_cyclotomic_radicals`:
    sympy writes ``cos(2 pi/5)`` as ``(sqrt 5 - 1)/4``) are atoms ``2 cos(2 pi/n)`` or ``zeta_n``
    too, represented by their polynomial in that atom.
    Any other ``H`` (a smaller field), and other generators, go the generic way."""
    if not _root_of_unity_atoms(generators):
        return
    radicals = _cyclotomic_radicals(generators)  # their own atoms (i in i sqrt 3) are not generators
    atoms = _root_of_unity_atoms([g for g in generators if _core(g) not in radicals])
    m = 4
    for a, r in atoms.items():
        m = int(sp.ilcm(m, (r / 2).q))
    for n, _, _ in radicals.values():
        m = int(sp.ilcm(m, n))
    powers = {a: int(r * m / 2) for a, r in atoms.items() if not isinstance(a, (sp.cos, sp.sin))}
    cosines = {a: int(r * m / 2) if isinstance(a, sp.cos) else m // 4 - int(r * m / 2)
               for a, r in atoms.items() if isinstance(a, (sp.cos, sp.sin))}
    exponents = [*powers.values(), *(m // n for n, real, _ in radicals.values() if not real)]
    cosine_exponents = [*cosines.values(), *(m // n for n, real, _ in radicals.values() if real)]
    H = [a for a in range(1, m) if gcd(a, m) == 1
         and all((a - 1) * k % m == 0 for k in exponents)
         and all((a - 1) * k % m == 0 or (a + 1) * k % m == 0 for k in cosine_exponents)]
    if not atoms or m <= 4 or H not in ([1], [1, m - 1]):
        return
    state.prim, state.modulus, state.theta = _cyclotomic_generator(m, H == [1, m - 1])
    state.root_order = m if H == [1] else 0
    t = flint.fmpq_poly([0, 1])
    if H == [1]:
        def cos2(k: int) -> Elem:  # 2 cos(2 pi k/m) = zeta^k + zeta^-k
            return _power(t, k % m, state.modulus) + _power(t, -k % m, state.modulus)
        for a, k in powers.items():
            state.reps[a] = _power(t, k % m, state.modulus)
    else:
        def cos2(k: int) -> Elem:
            k %= m
            return _lucas(min(k, m - k), t, state.modulus)
    for a, k in cosines.items():
        state.reps[a] = cos2(k) / 2
    for h, (n, real, p) in radicals.items():
        atom = cos2(m // n) if real else _power(t, m // n, state.modulus)
        state.reps[h] = _compose(p, atom, state.modulus)
        state.atoms.add(h)  # certified with the others: not by Euler's formula


def _lucas(k: int, t: Elem, modulus: Elem) -> Elem:
    """``V_k(t)`` modulo ``modulus`` (``V_0 = 2``, ``V_1 = t``, ``V_(j+1) = t V_j - V_(j-1)``: at
    ``t = 2 cos x``, ``V_k = 2 cos(k x)``) by the ladder ``V_2j = V_j^2 - 2``,
    ``V_(2j+1) = V_j V_(j+1) - t``: O(log k) products, where the table of all ``V_k`` up to
    ``m/2`` held ``m/2`` elements of degree ``phi(m)/2`` (memory growing as ``m^2``)."""
    a, b = flint.fmpq_poly([2]), t  # (V_j, V_(j+1)), j = 0
    for bit in bin(k)[2:]:
        if bit == "1":
            a, b = (a * b - t) % modulus, (b * b - 2) % modulus
        else:
            a, b = (a * a - 2) % modulus, (a * b - t) % modulus
    return a


def _cyclotomic_generator(m: int, real: bool) -> tuple[Integral, Elem, sp.Expr]:
    """``zeta_m = exp(2 pi i/m)`` (or ``2 cos(2 pi/m)`` when ``real``) as an :class:`Integral`, its
    minimal polynomial and sympy expression."""
    if real:
        poly = flint.fmpz_poly.cos_minpoly(m)
        theta, ball = 2 * sp.cos(2 * sp.pi / m), lambda: flint.acb(2 * flint.arb(flint.fmpq(2, m)).cos_pi())
    else:
        poly = flint.fmpz_poly.cyclotomic(m)
        theta, ball = sp.exp(2 * sp.pi * sp.I / m), lambda: flint.acb(flint.arb(flint.fmpq(2, m))).exp_pi_i()
    _, index = identify(poly, lambda prec: with_prec(prec, ball), str(theta))
    return Integral.of(poly, index), flint.fmpq_poly(poly), theta


def _cyclotomic_radicals(generators: Sequence[sp.Expr]) -> dict[sp.Expr, tuple[int, bool, Elem]]:
    """The cores ``h`` (:func:`_core`) of generators without trigonometric atoms that generate a
    whole cyclotomic field: per ``h``, ``(n, real, p)`` with ``h = p(2 cos(2 pi/n))`` (``real``,
    ``Q(h) = Q(zeta_n)^+``) or ``h = p(zeta_n)`` (``Q(h) = Q(zeta_n)``); such as sympy's
    ``sqrt(5)`` in ``cos(2 pi/5) = (sqrt 5 - 1)/4`` and ``sqrt(sqrt(5)/8 + 5/8) = sin(2 pi/5)``.

    The candidates are the ``n`` (not 2 mod 4) with ``phi(n) = 2 deg h`` (real ``h``) or
    ``phi(n) = deg h`` whose primes all divide the discriminant of ``h``'s minimal polynomial: each ramifies in ``Q(zeta_n)^+`` (its inertia group
    ``{a = 1 mod n/p^k}`` has ``phi(p^k)`` elements and lies in ``{+-1}`` only for ``n`` = 3, 4, where
    the degree is 1), and the field discriminant divides the polynomial's.  Membership is then
    decided exactly in the small field (:func:`_member`: ``Q(zeta_n, h)`` has the degree of
    ``Q(zeta_n)``), at a cost below that of deciding it in the whole field."""
    out: dict[sp.Expr, tuple[int, bool, Elem]] = {}
    for g in generators:
        h = _core(g)
        if h in out or h.has(sp.exp, sp.cos, sp.sin, sp.tan) or h.is_real is None:
            continue
        try:
            beta, _ = _integral(h)
        except _NOT_ALGEBRAIC:
            continue
        if beta.degree < 2:
            continue
        # sympy's discriminant: python-flint 0.7's fmpz_poly (our floor) has none
        disc = int(fmpz_to_sympy(beta.poly).discriminant())
        real = bool(h.is_real)
        target = 2 * beta.degree if real else beta.degree
        primes = [d + 1 for d in sp.divisors(target) if sp.isprime(d + 1) and disc % (d + 1) == 0]
        for n in _with_totient(target, primes):
            small = _Presentation()
            small.prim, small.modulus, small.theta = _cyclotomic_generator(n, real)
            p = _member(small, h)
            if p is not None:
                out[h] = (n, real, p)
                break
    return out


def _with_totient(t: int, primes: Sequence[int]) -> list[int]:
    """The ``n`` not 2 mod 4 with ``phi(n) = t`` whose prime factors are among ``primes``, ascending
    (``phi(q^k) = (q - 1) q^(k - 1)`` per prime power, multiplicative)."""
    out = []

    def extend(n: int, rest: int, i: int) -> None:
        if rest == 1:
            if n % 4 != 2:
                out.append(n)
            return
        for j in range(i, len(primes)):
            q = primes[j]
            if rest % (q - 1):
                continue
            n_q, rest_q = n * q, rest // (q - 1)
            while True:
                extend(n_q, rest_q, j + 1)
                if rest_q % q:
                    break
                n_q, rest_q = n_q * q, rest_q // q
    extend(1, t, 0)
    return sorted(out)


def _add_generator(state: _Presentation, g: sp.Expr) -> None:
    if state.prim is not None and _express(state, g) is not None:
        return
    core = _core(g)  # Q(theta, g) = Q(theta, core); _express has tried core already
    beta, c = _integral(core)
    if state.prim is None:
        state.prim, state.modulus, state.theta = beta, flint.fmpq_poly(beta.poly), c * core
        state.reps[core] = flint.fmpq_poly([0, flint.fmpq(1, c)])
    else:
        adj = adjoin(state.prim, beta)
        modulus = flint.fmpq_poly(adj.prim.poly)
        old = interpolate(adj.prim.poly, lambda prec: (lambda v: (v[0], v[2]))(adj.values(prec)))
        state.reps = {e: _compose(p, old, modulus) for e, p in state.reps.items()}
        state.reps[core] = (flint.fmpq_poly([0, 1]) - adj.k * old) / c
        state.prim, state.modulus, state.theta = adj.prim, modulus, c * core + adj.k * state.theta
        state.root_order = 0
    state.atoms.add(core)
    _express(state, g)


def _affine(g: sp.Expr) -> tuple[sp.Rational, sp.Rational, sp.Expr]:
    """``(a, b, h)`` with ``g = a + b h``, ``a``, ``b`` rational: ``g`` and ``h`` generate the same field."""
    m1, h = g.as_coeff_Mul()
    a, h = h.as_coeff_Add()
    m2, h = h.as_coeff_Mul()
    return m1 * a, m1 * m2, h


def _core(g: sp.Expr) -> sp.Expr:
    return _affine(g)[2]


def _member(state: _Presentation, expr: sp.Expr) -> Elem | None:
    """``expr`` in ``Q(theta)``, or None when it is not in the field (exact: degree of ``Q(theta, expr)``)."""
    try:
        beta, c = _integral(expr)
    except _NOT_ALGEBRAIC:
        return None
    d = state.prim.degree
    if d % beta.degree:
        return None
    adj = adjoin(state.prim, beta)
    if adj.prim.degree != d:
        return None
    at = sorted(adj.pairs, key=lambda ij: ij[1])  # embedding j of Q(theta) sends beta to beta_i
    rep = interpolate(state.prim.poly, lambda prec: (state.prim.roots(prec), [beta.roots(prec)[i] for i, _ in at]))
    state.atoms.add(expr)
    return rep / c


def _express(state: _Presentation, expr: sp.Expr) -> Elem | None:
    """``expr`` in ``Q(theta)`` through sums, products and integer powers of known parts,
    else as one algebraic number; None when it is not in the field."""
    if expr.is_Rational:
        return _rational(expr)
    hit = state.reps.get(expr)
    if hit is not None:
        return hit
    out = None
    if expr.is_Add or expr.is_Mul:
        parts = [_express(state, a) for a in expr.args]
        if all(p is not None for p in parts):
            out = parts[0]
            for p in parts[1:]:
                out = (out + p if expr.is_Add else out * p) % state.modulus
    elif expr.is_Pow and expr.exp.is_Integer:
        base = _express(state, expr.base)
        if base is not None and not base.is_zero():
            e = int(expr.exp)
            out = _power(base if e > 0 else _inverse(base, state.modulus), abs(e), state.modulus)
    if out is None:
        a, b, core = _affine(expr)
        if core == expr:
            out = _member(state, expr)
        else:  # expr is in the field iff its core is
            h = _express(state, core)
            out = None if h is None else (h * _rational(b) + _rational(a)) % state.modulus
    if out is not None:
        state.reps[expr] = out
    return out


def _inverse(a: Elem, modulus: Elem) -> Elem:
    if a.is_zero():
        raise ZeroDivisionError("inverse of zero in a number field")
    g, s, _ = a.xgcd(modulus)
    return (s / g) % modulus


def _power(a: Elem, k: int, modulus: Elem) -> Elem:
    out = flint.fmpq_poly([1])
    base = a % modulus
    while k:
        if k & 1:
            out = (out * base) % modulus
        base = (base * base) % modulus
        k >>= 1
    return out


class NumberField:
    """The field ``Q(generators)`` as ``Q(theta)``; ``QQ`` when every generator is rational."""

    def __init__(self, generators: Iterable[sp.Expr] = ()):
        gens = []
        for g in generators:
            g = sympify(g, "generators")
            if not g.is_Rational and g not in gens:
                gens.append(g)
        self.generators = tuple(gens)
        try:
            self._state = _presentation(self.generators)
        except _NOT_ALGEBRAIC as exc:
            raise InputError(f"cannot build the number field of {gens}: {exc}") from None
        self.modulus = self._state.modulus
        self.degree = self.modulus.degree()

    @property
    def is_rational(self) -> bool:
        return self.degree == 1

    @property
    def theta(self) -> sp.Expr:
        """The primitive element as a sympy expression (an algebraic integer)."""
        return self._state.theta

    @property
    def theta_index(self) -> int:
        """``theta`` as a root of ``modulus``, in flint's ``complex_roots`` ordering."""
        return self._state.prim.index if self._state.prim else 0

    def theta_ball(self, prec: int) -> flint.acb:
        """Certified isolating ball of ``theta`` at ``prec`` bits."""
        prec = precision(prec)
        return self._state.prim.roots(prec)[self.theta_index] if self._state.prim else flint.acb(0)

    def real_balls(self, M: Sequence[Sequence[Elem]], prec: int, accuracy: int | None = None) -> list[list[flint.arb]]:
        """Certified real balls (``prec`` bits) of the real elements of the matrix ``M``: their values
        at the embedding ``theta``, ``sum_k c_k Re(theta^k)`` (a real element's imaginary parts cancel),
        one ball matrix product per power in flint (an acb polynomial evaluated per entry is one
        Python call per entry, a large share of the bounds atlas at many sensors).  With
        ``accuracy``, ``prec`` is doubled until every ball has that many correct bits relative to
        its midpoint (for nonzero elements; 1 bit excludes 0): over Q(theta) of degree 1440 the
        terms cancel by 10^500."""
        def balls(prec: int) -> list[list[flint.arb]]:
            rows, cols = len(M), len(M[0]) if M else 0
            power, out = flint.acb(1), flint.arb_mat(rows, cols)
            theta = None if self.is_rational else self.theta_ball(prec)
            for k in range(self.degree):
                if k:
                    power *= theta
                out += flint.arb_mat(flint.fmpq_mat(rows, cols, [a[k] for row in M for a in row])) * power.real
            return out.tolist()
        out = with_prec(prec, lambda: balls(prec))
        while accuracy is not None and any(b.rel_accuracy_bits() < accuracy for row in out for b in row):
            prec *= 2
            out = with_prec(prec, lambda: balls(prec))
        return out

    def __repr__(self) -> str:
        if self.is_rational:
            return "QQ"
        return f"Q(theta), theta = {self.theta}, minpoly of degree {self.degree}"

    # -- conversion -------------------------------------------------------------
    def convert(self, expr: Any) -> Elem:
        """The element of this field equal to ``expr`` (raises if it is not in the field)."""
        expr = sympify(expr, "expr")
        if expr.is_Rational:
            return _rational(expr)
        out = _express(self._state, expr) if not self.is_rational else _member_of_q(expr)
        if out is None:
            raise InputError(f"{expr} is not in the number field {self}")
        self._state.certify()
        return out

    def to_sympy(self, a: Elem) -> sp.Expr:
        coeffs = [sp.Rational(int(c.p), int(c.q)) for c in a.coeffs()]
        return sp.expand(sum(c * self.theta ** i for i, c in enumerate(coeffs))) if coeffs else sp.Integer(0)

    def matrix(self, M: sp.MatrixBase) -> list[list[Elem]]:
        return [[self.convert(M[i, j]) for j in range(M.shape[1])] for i in range(M.shape[0])]

    # -- arithmetic -------------------------------------------------------------
    def mul(self, a: Elem, b: Elem) -> Elem:
        return (a * b) % self.modulus

    def inv(self, a: Elem) -> Elem:
        return _inverse(a, self.modulus)

    def pow(self, a: Elem, k: int) -> Elem:
        return _power(a, k, self.modulus)

    @property
    def root_order(self) -> int:
        """``m`` when ``theta`` is the root of unity ``zeta_m = exp(2 pi i/m)`` (the cyclotomic
        presentation), else 0."""
        return self._state.root_order

    def root_exponent(self, a: Elem) -> int | None:
        """``k`` (``0 <= k < m``) with ``a = theta^k`` when ``theta = zeta_m`` (:attr:`root_order`) and
        ``a`` is a root of unity (every one in ``Q(zeta_m)`` is a power of ``zeta_m``: ``m`` is even),
        else None: read off the argument of ``a(zeta_m)`` (a ball) and confirmed exactly."""
        m = self.root_order
        if not m:
            return None
        prec = 64 + 2 * max((int(abs(c.p)).bit_length() + int(c.q).bit_length() for c in a.coeffs()), default=0)
        value = with_prec(prec, lambda: flint.acb_poly([flint.acb(flint.arb(c)) for c in a.coeffs()])(
            flint.acb(flint.arb(flint.fmpq(2, m))).exp_pi_i()))
        turn = with_prec(prec, lambda: value.arg() * m / (2 * flint.arb.pi()))  # k, if a is zeta_m^k
        if not turn.rad() < 0.25:
            return None
        k = round(float(turn.mid())) % m
        return k if self.times_root_power(flint.fmpq_poly([1]), k) == a % self.modulus else None

    def times_root_power(self, a: Elem, k: int) -> Elem:
        """``a theta^k`` for ``theta = zeta_m`` (:attr:`root_order`; ``k`` any integer): a shift of
        ``a``'s coefficients by ``k mod m`` and one reduction, where ``theta^k`` as an element costs
        ``log k`` products of dense polynomials of degree ``phi(m)``."""
        m = self.root_order
        if not m:
            raise InputError(f"times_root_power: theta of {self} is no root of unity")
        return a.left_shift(k % m) % self.modulus

    def dot(self, u: Sequence[Elem], v: Sequence[Elem]) -> Elem:
        acc = flint.fmpq_poly([])
        for a, b in zip(u, v):
            acc += a * b
        return acc % self.modulus

    def vecmat(self, v: Sequence[Elem], M: Sequence[Sequence[Elem]]) -> list[Elem]:
        """The row vector ``v M`` (``v`` of length ``len(M)``, ``M`` a non-empty matrix of this field)."""
        if not M or len(v) != len(M) or any(len(row) != len(M[0]) for row in M):
            raise InputError(f"vecmat: v of length {len(v)} and a matrix of {len(M)} rows of one length do not fit")
        return [self.dot(v, [row[j] for row in M]) for j in range(len(M[0]))]


def _member_of_q(expr: sp.Expr) -> Elem | None:
    """A rational number written as an irrational-looking expression (``sqrt(4)/2`` is folded by
    sympy, ``cos(pi/3)`` too; others are decided by the degree of the minimal polynomial)."""
    try:
        poly, _ = root_of(expr)
    except _NOT_ALGEBRAIC:
        return None
    if poly.degree() != 1:
        return None
    c = poly.coeffs()
    return flint.fmpq_poly([flint.fmpq(-int(c[0]), int(c[1]))])


QQ_FIELD = NumberField()

check_public(globals())
