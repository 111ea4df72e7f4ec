"""AlgebraicNumber (symkf.exact.algebraic) as a SymPy and Python number: exact arithmetic with
Python rationals and sympy expressions, symmetric equality, hashes that agree with it, correctly
rounded formatting, comparisons with floats by their binary value, certified roots.

The running example: r = critical_loss_rate of A = 2R(pi/2), C = [1 0], which is exactly 1/16
(Sui-You-Fu Theorem 4: one block, alpha = 2, governing period 2, margin alpha^4 eps = 1 at
eps = 1/16; proofs/sui_theorem12.py)."""

from __future__ import annotations

import math
import pickle
import sys
import time
from decimal import Decimal
from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf.errors import BudgetError, InputError
from symkf.exact.algebraic import AlgebraicNumber, root_ball, sign, x

from conftest import limited, refused_at_once

R = sp.Rational


@pytest.fixture(scope="module")
def r() -> AlgebraicNumber:
    value = sk.critical_loss_rate(sk.System([[0, -2], [2, 0]], [sk.Sensor([[1, 0]])]))
    assert value.is_rational and value.minpoly == sp.Poly(16 * x - 1, x)
    return value


SQRT2 = AlgebraicNumber.from_expr(sp.sqrt(2))
SQRT3 = AlgebraicNumber.from_expr(sp.sqrt(3))


# -- sympify, Matrix and sympy arithmetic stay exact -----------------------------------------------

def test_sympify_matrix_and_sympy_products_are_exact(r: AlgebraicNumber) -> None:
    assert sp.sympify(r) == R(1, 16) and isinstance(sp.sympify(r), sp.Rational)
    M = sp.Matrix([r])
    assert M[0, 0] == R(1, 16) and not M.has(sp.Float)
    assert sp.sqrt(2) * r == sp.sqrt(2) / 16 and not (sp.sqrt(2) * r).has(sp.Float)
    # an irrational one stays a radical, not a Float
    assert sp.sympify(SQRT2) == sp.sqrt(2)
    assert sp.sqrt(2) * SQRT2 == 2


# -- equality is symmetric -------------------------------------------------------------------------

def test_equality_symmetric(r: AlgebraicNumber) -> None:
    for q in (R(1, 16), Fraction(1, 16), 0.0625):
        assert r == q and q == r
    assert sp.Integer(1) != r and r != 1
    assert sp.sqrt(2) == SQRT2 and SQRT2 == sp.sqrt(2)
    # an equal value written differently: decided exactly (minimal polynomial), not structurally
    assert SQRT2 == sp.sqrt(8) / 2 and SQRT2 == 2 * sp.cos(sp.pi / 4)


# -- arithmetic on both sides, LaTeX, format, round, comparison with floats ------------------------

def test_arithmetic_with_python_rationals_gives_algebraic_numbers(r: AlgebraicNumber) -> None:
    for value, expected in ((1 - r, R(15, 16)), (2 * r, R(1, 8)), (r + 1, R(17, 16)), (r * 2, R(1, 8)),
                            (r - Fraction(1, 16), 0), (Fraction(1, 2) / r, 8), (r / 2, R(1, 32)),
                            (r ** 2, R(1, 256)), (r ** -1, 16), (-r, R(-1, 16)), (abs(-r), R(1, 16)),
                            (np.int64(3) * r, R(3, 16))):
        assert isinstance(value, AlgebraicNumber) and value == expected


def test_arithmetic_with_sympy_objects_gives_exact_sympy_expressions(r: AlgebraicNumber) -> None:
    # the one rule: a sympy operand on either side gives sympy's exact result
    for value, expected in ((sp.Integer(1) - r, R(15, 16)), (r - sp.Integer(1), R(-15, 16)),
                            (R(1, 2) * r, R(1, 32)), (r * R(1, 2), R(1, 32)),
                            (SQRT2 * sp.sqrt(2), 2), (sp.sqrt(3) + SQRT2, sp.sqrt(2) + sp.sqrt(3))):
        assert isinstance(value, sp.Expr) and value == expected
    assert isinstance(SQRT2 ** R(1, 2), sp.Expr) and SQRT2 ** R(1, 2) == 2 ** R(1, 4)


def test_arithmetic_of_irrationals_is_certified() -> None:
    # (sqrt2 + sqrt3)^2 = 5 + 2 sqrt6, so ((t^2 - 5)/2)^2 = 6: t^4 - 10 t^2 + 1 (by hand)
    s = SQRT2 + SQRT3
    assert s.minpoly == sp.Poly(x ** 4 - 10 * x ** 2 + 1, x)
    assert 3.14626 < float(s) < 3.14627  # 1.41421... + 1.73205...
    assert SQRT3 - SQRT2 > 0 and SQRT2 - SQRT3 < 0
    assert SQRT2 * SQRT3 == sp.sqrt(6) and SQRT2 / SQRT3 == sp.sqrt(6) / 3
    assert SQRT2 * SQRT2 == 2 and (SQRT2 * SQRT2).is_rational
    assert SQRT2 ** 3 == 2 * sp.sqrt(2) and SQRT2 ** -2 == R(1, 2)
    assert 1 / SQRT2 == sp.sqrt(2) / 2
    cbrt = AlgebraicNumber.from_expr(sp.cbrt(2))
    assert cbrt ** 3 == 2 and cbrt ** 2 == sp.cbrt(4)
    with pytest.raises(ZeroDivisionError):
        SQRT2 / (SQRT2 - SQRT2)


def test_floats_mix_as_with_fraction(r: AlgebraicNumber) -> None:
    # arithmetic with a float gives a float (as Fraction does); nothing is rationalized
    assert isinstance(r + 0.5, float) and r + 0.5 == 0.5625
    assert isinstance(0.5 * SQRT2, float)


def test_latex(r: AlgebraicNumber) -> None:
    assert sp.latex(r) == r"\frac{1}{16}"
    assert sp.latex(SQRT2) == r"\sqrt{2}"
    assert sp.latex(sp.Matrix([[SQRT2]])) == sp.latex(sp.Matrix([[sp.sqrt(2)]]))


def test_format_is_correctly_rounded(r: AlgebraicNumber) -> None:
    assert f"{r:.4f}" == "0.0625" and f"{r:.3f}" == "0.062"  # exact tie: half to even, as float
    assert f"{r:.2%}" == "6.25%" and f"{r:>8.2f}" == "    0.06"
    assert f"{r}" == "1/16" and f"{r:>6}" == "  1/16"
    # 3/20 = 0.15 exactly, a decimal tie: half to even gives 0.2 (the float 0.15 would give 0.1)
    assert f"{AlgebraicNumber.from_expr(R(3, 20)):.1f}" == "0.2"
    # sqrt(2) = 1.41421356237309504880168872...
    assert f"{SQRT2:.20f}" == "1.41421356237309504880"
    assert f"{-SQRT2:.3e}" == "-1.414e+0"


def test_round_and_floor(r: AlgebraicNumber) -> None:
    # 1/16 = 0.0625, a tie at 3 places: half to even gives 0.062
    assert round(r, 3) == Decimal("0.062") and str(round(r, 3)) == "0.062"
    assert round(r) == 0 and isinstance(round(r), int)
    assert round(SQRT2) == 1 and isinstance(round(SQRT2), int)
    assert (math.floor(SQRT2), math.ceil(SQRT2), math.trunc(-SQRT2), int(-SQRT2)) == (1, 2, -1, -1)
    assert round(AlgebraicNumber.from_expr(R(5, 2))) == 2 and round(AlgebraicNumber.from_expr(R(7, 2))) == 4


def test_round_to_places_is_an_exact_decimal_with_that_many_places(r: AlgebraicNumber) -> None:
    # sqrt(2) = 1.41421356237309504880168872420969807856967187537694...
    assert isinstance(round(SQRT2, 4), Decimal) and str(round(SQRT2, 4)) == "1.4142"
    assert str(round(-SQRT2, 2)) == "-1.41" and str(round(r, 6)) == "0.062500"
    # 40 places, past Decimal's default 28-digit context: still exact
    assert str(round(SQRT2, 40)) == "1.4142135623730950488016887242096980785697"
    # 3/20 = 0.15 exactly: half to even gives 0.2 (the float 0.15 = 0.1499999... would give 0.1)
    assert str(round(AlgebraicNumber.from_expr(R(3, 20)), 1)) == "0.2"
    # 0.00005 + sqrt(2) 10^-30, irrational and just above a tie at 4 places: rounds up
    near_tie = AlgebraicNumber.from_expr(R(5, 10 ** 5) + sp.sqrt(2) / 10 ** 30)
    assert str(round(near_tie, 4)) == "0.0001"
    assert str(round(AlgebraicNumber.from_expr(R(5, 10 ** 5)), 4)) == "0.0000"  # the exact tie: to even
    assert round(AlgebraicNumber.from_expr(R(1234)), -2) == 1200
    assert (math.floor(SQRT2), math.ceil(SQRT2), math.trunc(-SQRT2), int(-SQRT2)) == (1, 2, -1, -1)
    assert round(AlgebraicNumber.from_expr(R(5, 2))) == 2 and round(AlgebraicNumber.from_expr(R(7, 2))) == 4


def test_comparison_with_float_uses_its_binary_value(r: AlgebraicNumber) -> None:
    assert r < 0.1 and 0.1 > r and r <= 0.0625 and r >= 0.0625
    # the double nearest sqrt(2) is 1.41421356237309514547..., above sqrt(2) = 1.41421356237309504880...
    near = 1.4142135623730951
    assert SQRT2 < near and SQRT2 != near and near > SQRT2
    assert float(SQRT2) == near  # float() still rounds to nearest
    # 0.1 is 3602879701896397/2^55, just above 1/10
    tenth = AlgebraicNumber.from_expr(R(1, 10))
    assert tenth < 0.1 and tenth != 0.1 and tenth == Fraction(1, 10)
    assert SQRT2 < math.inf and SQRT2 > -math.inf
    nan = math.nan
    assert not (SQRT2 < nan or SQRT2 > nan or SQRT2 <= nan or SQRT2 >= nan or SQRT2 == nan)
    assert SQRT2 < sp.Float("1.41421356237309504880168872420969808", 40)


# -- hashes agree with equality --------------------------------------------------------------------

def test_hash_agrees_with_equality(r: AlgebraicNumber) -> None:
    assert hash(r) == hash(Fraction(1, 16)) == hash(0.0625)
    assert len({r, Fraction(1, 16), 0.0625}) == 1
    assert hash(AlgebraicNumber.from_expr(3)) == hash(3) and len({AlgebraicNumber.from_expr(3), 3}) == 1
    # equal irrationals built differently hash alike
    other = AlgebraicNumber(x ** 2 - 2, 1)
    assert other == SQRT2 and hash(other) == hash(SQRT2) and len({other, SQRT2}) == 1
    assert hash(SQRT2) != hash(-SQRT2)


# -- a reducible defining polynomial is factored, never a hang -------------------------------------

def test_reducible_polynomial_is_factored() -> None:
    one = AlgebraicNumber(x ** 2 - 1, 1)  # real roots -1 < 1: index 1 is 1
    assert one == 1 and one.is_rational and one.minpoly == sp.Poly(x - 1, x)
    assert AlgebraicNumber(x ** 2 - 1, 0) == -1
    # (x^2 - 2)(x - 1)^2 (x^2 + 1): distinct real roots -sqrt2 < 1 < sqrt2
    p = (x ** 2 - 2) * (x - 1) ** 2 * (x ** 2 + 1)
    assert [AlgebraicNumber(p, i) for i in range(3)] == [-sp.sqrt(2), 1, sp.sqrt(2)]
    assert AlgebraicNumber(p, 2).minpoly == sp.Poly(x ** 2 - 2, x)
    assert AlgebraicNumber(2 * x - 2, 0) == 1  # content removed


def test_bad_polynomials_are_refused() -> None:
    with pytest.raises(InputError, match="3 distinct real roots"):
        AlgebraicNumber((x ** 2 - 2) * (x - 1) * (x ** 2 + 1), 3)
    with pytest.raises(InputError, match="not real"):
        AlgebraicNumber(x ** 2 + 1, 0)
    with pytest.raises(InputError, match="constant"):
        AlgebraicNumber(sp.Integer(3) + 0 * x, 0)
    with pytest.raises(InputError, match="rational coefficients"):
        AlgebraicNumber(sp.sqrt(2) * x - 1, 0)
    with pytest.raises(InputError, match="is not exact"):
        AlgebraicNumber.from_expr(0.1)
    with pytest.raises(InputError, match="Float"):
        AlgebraicNumber.from_expr(sp.sqrt(2) * sp.Float(0.5))
    assert not AlgebraicNumber.from_expr(0) and AlgebraicNumber.from_expr(sp.sqrt(2) - 1)


def test_pickle_and_set_membership_survive_arithmetic() -> None:
    s = SQRT2 + 1
    assert pickle.loads(pickle.dumps(s)) == s
    assert AlgebraicNumber.from_expr(1 + sp.sqrt(2)) in {s}  # built by sympy's minimal_polynomial


def test_arithmetic_keeps_the_primitive_minimal_polynomial() -> None:
    """sqrt(2) / 2 is a root of 4x^2 - 2, a resultant flint need not factor (its roots are known):
    stored with that content, 2 + sqrt(2) / 2 hashed apart from the same number read from sympy, and
    comparing the two refined their overlapping intervals forever."""
    half = Fraction(1, 2) * SQRT2
    built, read = 2 + half, AlgebraicNumber.from_expr(2 + sp.sqrt(2) / 2)
    assert half.minpoly == sp.Poly(2 * x ** 2 - 1, x) and built.minpoly == read.minpoly == sp.Poly(2 * x ** 2 - 8 * x + 7, x)
    assert hash(built) == hash(read) and built == read and len({built, read}) == 1


@settings(max_examples=60, deadline=None)
@given(st.fractions(max_denominator=50), st.fractions(max_denominator=50))
def test_rational_arithmetic_matches_fraction(p: Fraction, q: Fraction) -> None:
    a, b = AlgebraicNumber.from_expr(p), AlgebraicNumber.from_expr(q)
    assert a + b == p + q and a - q == p - q and p * b == p * q and hash(a * b) == hash(p * q)
    assert (a < b) == (p < q) and (a == b) == (p == q)
    if q:
        assert a / b == p / q


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 7), st.integers(2, 7), st.fractions(min_value=-3, max_value=3, max_denominator=9))
@example(4, 2, Fraction(1, 2))   # found by a random run: 2 + sqrt(2) / 2 kept the content of 4x^2 - 2
def test_irrational_arithmetic_matches_sympy(m: int, n: int, q: Fraction) -> None:
    """sqrt(m) + q sqrt(n) and sqrt(m) * sqrt(n): certified roots against sympy's minimal polynomials."""
    a, b = AlgebraicNumber.from_expr(sp.sqrt(m)), AlgebraicNumber.from_expr(sp.sqrt(n))
    expr = sp.sqrt(m) + R(q.numerator, q.denominator) * sp.sqrt(n)
    s = a + q * b
    assert s.minpoly == sp.Poly(sp.minimal_polynomial(expr, x), x)
    assert s == expr and abs(float(s) - float(expr)) < 1e-12
    assert a * b == sp.sqrt(m * n)


@settings(max_examples=40, deadline=None)
@given(st.integers(5, 97).filter(lambda m: sp.totient(m) >= 4),
       st.fractions(min_value=-3, max_value=3, max_denominator=7),
       st.fractions(min_value=-4, max_value=4, max_denominator=5).filter(bool),
       st.sampled_from(["alpha + beta 2cos", "sin^2", "cos(2 pi/m)"]))
def test_the_roots_of_a_shifted_scaled_cosine_are_known_in_flints_order(m, alpha, beta, form):
    """The minimal polynomial (sympy's) of alpha + beta 2 cos(2 pi/m), of sin^2(2 pi/m) = (1 - cos(4
    pi/m)) / 2 or of cos(2 pi/m): its roots are given without isolation, in the order and within the
    balls of flint's own isolation (an independent computation of the same roots)."""
    from symkf.exact.algebraic import _complex_roots, _known_roots, sympy_to_fmpz
    t = 2 * sp.pi / m
    expr = {"alpha + beta 2cos": R(alpha.numerator, alpha.denominator) + R(beta.numerator, beta.denominator) * 2 * sp.cos(t),
            "sin^2": sp.sin(t) ** 2, "cos(2 pi/m)": sp.cos(t)}[form]
    p = sympy_to_fmpz(sp.Poly(sp.minimal_polynomial(expr, x), x))
    coeffs = tuple(int(c) for c in p.coeffs())
    if p.degree() < 2:
        assert _known_roots(coeffs) is None
        return
    assert _known_roots(coeffs) is not None
    known = _complex_roots(coeffs, 64)
    isolated = [r for r, _ in p.complex_roots()]
    assert len(known) == len(isolated) == p.degree()
    assert all(k.overlaps(r) for k, r in zip(known, isolated))


@pytest.mark.parametrize("m", [3, 5, 8, 9, 13, 21])
@pytest.mark.parametrize("c", [R(3, 2), R(2, 5), sp.Integer(2)])
def test_the_roots_of_a_scaled_root_of_unity_are_known(m, c):
    """The minimal polynomial (sympy's) of c exp(2 pi i/m), c rational, non-monic for c = 3/2 and 2/5:
    its roots c exp(2 pi i j/m), gcd(j, m) = 1, are given without isolation, each within the ball of
    exactly one root of flint's own isolation; for non-monic ones in flint's order (conjugate pairs
    by increasing imaginary part, then real part), which isolation gave them before."""
    from symkf.exact.algebraic import _complex_roots, _known_roots, sympy_to_fmpz
    p = sympy_to_fmpz(sp.Poly(sp.minimal_polynomial(c * sp.exp(2 * sp.pi * sp.I / m), x), x))
    coeffs = tuple(int(v) for v in p.coeffs())
    assert _known_roots(coeffs) is not None
    isolated = [r for r, _ in p.complex_roots()]
    hits = [[i for i, r in enumerate(isolated) if k.overlaps(r)] for k in _complex_roots(coeffs, 64)]
    assert sorted(hits) == [[i] for i in range(p.degree())]
    if c.q > 1:
        assert hits == [[i] for i in range(p.degree())]


@pytest.mark.parametrize("expr", [sp.root(2, 3), sp.sqrt(2) + sp.sqrt(3), 2 * sp.cos(2 * sp.pi / 7) + sp.sqrt(2),
                                  sp.cos(2 * sp.pi / 7) ** 2 + 3 * sp.cos(2 * sp.pi / 7)])
def test_other_polynomials_are_isolated(expr):
    """No shortcut for polynomials whose roots are not alpha + beta 2 cos(2 pi j/m), among them one
    of Q(cos(2 pi/7)) itself: c^2 + 3c = 1/2 + 3 cos(2 pi/7) + cos(4 pi/7) / 2 is no multiple of
    one conjugate (2 c^2 + c = 1/2 - cos(6 pi/7) is, and is recognised)."""
    from symkf.exact.algebraic import _known_roots, sympy_to_fmpz
    p = sympy_to_fmpz(sp.Poly(sp.minimal_polynomial(expr, x), x))
    assert _known_roots(tuple(int(c) for c in p.coeffs())) is None


def test_triangular_eigenvalues_need_no_norm():
    """A triangular A over a cyclotomic field: the eigenvalues are its diagonal entries, found by
    their own minimal polynomials (cos(pi/211) has degree 105) with no norm over the field, and the
    degree cap is the field's, not a generic extension's (420 = 105 x 2 x 2 was refused at 64)."""
    S = sk.System(A=[["cos(pi/211)", "1"], ["0", "2"]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]])])
    eigenvalues = [e for b in S.eigen_blocks() for e in b.members]
    assert sorted(e.minpoly.degree() for e in eigenvalues) == [1, 105]
    assert sorted(float(b.modulus) for b in S.eigen_blocks()) == pytest.approx([math.cos(math.pi / 211), 2.0], abs=1e-15)
    # the mode of 2 (eigenvector (1, 2 - cos(pi/211))) is seen by both sensors, so it grows only
    # when both are lost: margin 2^2 * (1/2)^2 = 1, not stable; the mode of cos(pi/211) (eigenvector
    # (1, 0)) is seen by s1 alone: cos(pi/211)^2 * 1/2
    v = sk.stability(S, sk.IID(["1/2", "1/2"]))
    assert not v.stable and 1 in v.margins
    assert sorted(map(float, v.margins)) == pytest.approx([math.cos(math.pi / 211) ** 2 / 2, 1.0], abs=1e-15)


def test_margin_of_a_sine_entry_is_a_known_cosine_image():
    """A = sin(2 pi/517) (degree 230; its square's polynomial isolated all 230 roots twice, once for
    the margin's closed form and once for its product with the loss rate): the margin sin^2 / 2 =
    (1 - cos(4 pi/517)) / 4 is recognised as alpha + beta 2 cos(2 pi j/517) with alpha = 1/4,
    beta = -1/8, and its value is right."""
    from symkf.exact.algebraic import _known_roots
    v = sk.stability(sk.System(A=[["sin(2*pi/517)"]], sensors=[sk.Sensor(C=[[1]])]), sk.IID(["1/2"]))
    margin = v.margins[0]
    assert v.stable and margin.minpoly.degree() == 230
    kind, alpha, beta, _, m = _known_roots(tuple(int(c) for c in reversed(margin.minpoly.all_coeffs())))[0]
    assert (kind, alpha, beta, m) == ("cos", Fraction(1, 4), Fraction(-1, 8), 517)
    assert float(margin) == pytest.approx(math.sin(2 * math.pi / 517) ** 2 / 2, rel=1e-13)


def test_algebraic_number_comparisons_are_exact():
    a = AlgebraicNumber.from_expr(sp.root(sp.Rational(16, 25), 3))
    assert a.minpoly.as_expr() == 25 * sp.Symbol("x") ** 3 - 16
    lo, hi = a.interval
    assert lo <= Fraction(86177, 100000) <= hi or hi < Fraction(86178, 100000)
    assert a < 1 and a > Fraction(1, 2)
    assert sign(sp.sqrt(2) + sp.sqrt(3) - sp.sqrt(5 + 2 * sp.sqrt(6))) == 0
    assert sign(sp.sqrt(2) - sp.Rational(99, 70)) == -1


@pytest.mark.parametrize("call, cap", [
    (lambda a, e: e.ball(sys.maxsize), "max-precision"),            # flint segfaulted
    (lambda a, e: e.ball(2 ** 40), "max-precision"),                 # hung past Ctrl-C
    (lambda a, e: root_ball(e.minpoly, e.root_index, 10 ** 30), "max-precision"),   # OverflowError
    (lambda a, e: a ** 10 ** 30, "max-exponent"),                    # ignored Ctrl-C
    (lambda a, e: AlgebraicNumber.from_expr(sp.Rational(3, 2)) ** 10 ** 9, "max-exponent"),   # 29 s, 1 GB
    (lambda a, e: a.evalf(10 ** 7), "max-digits"),                   # hung
    (lambda a, e: a.refine(sp.Rational(1, 10 ** 10 ** 6)), "max-bits"),          # priced as an argument
])
def test_precision_exponents_and_digits_are_priced_before_flint_is_asked(call, cap):
    a = AlgebraicNumber.from_expr(sp.sqrt(2))
    e = sk.eigenvalues([[0, -2], [2, 0]])[0]
    start = time.process_time()
    with pytest.raises(BudgetError, match=f"--{cap}"):
        call(a, e)
    assert time.process_time() - start < 1


#: the sum of the square roots of the first ten primes: degree 2^10 = 1024
PRIMES_SUM = sum(sp.sqrt(p) for p in [2, 3, 5, 7, 11, 13, 17, 19, 23, 29])


@pytest.mark.parametrize("call", [
    lambda: AlgebraicNumber.from_expr(PRIMES_SUM),
    lambda: AlgebraicNumber.from_expr(sp.Rational(1, 2)) < PRIMES_SUM,
    lambda: AlgebraicNumber.from_expr(2 ** sp.Rational(1, 61) * 3 ** sp.Rational(1, 59)),   # degree 3599
], ids=["from_expr", "comparison", "product of indices 61 and 59"])
def test_a_sympy_number_of_high_degree_is_refused_before_its_minimal_polynomial(call):
    # reached sympy's minimal_polynomial, which never ended (degree 1024)
    code, err = limited(refused_at_once, call, "max_degree")
    assert code == 0 and "algebraic degree (bound)" in err, err


def test_products_of_radicals_of_one_index_pass_the_boundary():
    # 2^(2/9) 3^(7/9) is the ninth root of 2^2 3^7 (degree 9, though its two radicals' field has 81),
    # a critical value 2^(17/64)/2 a 64th root; both pass at the default caps, as symkf's results do
    r = AlgebraicNumber.from_expr(2 ** sp.Rational(2, 9) * 3 ** sp.Rational(7, 9))
    assert r.minpoly == sp.Poly(x ** 9 - 2 ** 2 * 3 ** 7, x)
    assert AlgebraicNumber.from_expr(2 ** sp.Rational(17, 64) / 2).minpoly == sp.Poly(2 ** 47 * x ** 64 - 1, x)
    eps = sk.critical_loss_rate(sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])]))
    assert AlgebraicNumber.from_expr(eps.exact) == eps and eps < eps.exact * 2   # 2^(2/3)/4 back in


def test_a_root_of_a_long_polynomial_prints_its_degree_not_the_polynomial():
    x = sp.Symbol("x")
    long = AlgebraicNumber.from_root(sp.Poly(3 ** 200 * x ** 9 - 1, x), 0, 1)   # 3^(-200/9), no short form kept
    short = AlgebraicNumber.from_root(sp.Poly(x ** 5 - x - 1, x), 1, 2)
    assert str(long) == f"[root ≈{long.evalf(10)} of a degree-9 polynomial (.minpoly)]"
    assert str(short) == f"[root ≈{short.evalf(10)} of x**5 - x - 1]"


# -- real roots known without isolation ------------------------------------------------------------

@pytest.mark.parametrize("p, k, irreducible", [
    ([-2, 0, 1], 3, True),       # x^6 - 2
    ([-8, 1], 3, False),         # x^3 - 8 = (x - 2)(x^2 + 2x + 4): 8 is a cube
    ([-8, 0, 1], 3, False),      # x^6 - 8 = (x^2 - 2)(x^4 + 2x^2 + 4): 2 sqrt 2 = sqrt(2)^3
    ([-2, 0, 1], 2, True),       # x^4 - 2
    ([-9, 1], 2, False),         # x^2 - 9: 9 is a square
    ([1, -6, 1], 2, False),      # x^4 - 6x^2 + 1 = (x^2 - 2x - 1)(x^2 + 2x - 1): 3 + 2 sqrt 2 = (1 + sqrt 2)^2
    ([-2, 0, 1], 4, False),      # 4 | k: not decided this way (x^4 + 4 = (x^2 + 2x + 2)(x^2 - 2x + 2))
    ([-5, 1, 0, 1], 15, True),   # x^45 + x^15 - 5
])
def test_binomial_irreducibility_is_proved_only_where_flint_finds_one_factor(p, k, irreducible):
    """Capelli's criterion, proved mod primes: True only for an irreducible p(x^k), as flint's
    factorisation confirms, and True for the irreducible ones above (a prime proves it)."""
    from symkf.exact.algebraic import _binomial_irreducible
    p = flint.fmpz_poly(p)
    coeffs = [0] * (k * p.degree() + 1)
    for i, c in enumerate(p.coeffs()):
        coeffs[k * i] = int(c)
    flint_says = len(flint.fmpz_poly(coeffs).factor()[1]) == 1
    assert _binomial_irreducible(p, k) == irreducible
    assert not irreducible or flint_says


def test_known_real_roots_sort_into_their_factors_with_flint_indices(monkeypatch):
    """Sources for the real roots of (x^2 - 2)(x^2 - 3)(x^3 - 5), given shuffled, give each factor its
    roots in flint's order, and root_ball and identify(real=True) name them as isolation does."""
    from symkf.exact import algebraic
    monkeypatch.setattr(algebraic, "_KNOWN_REAL_ROOTS", {})
    factors = [flint.fmpz_poly([-2, 0, 1]), flint.fmpz_poly([-3, 0, 1]), flint.fmpz_poly([-5, 0, 0, 1])]
    root = lambda v: lambda prec: flint.arb(v).sqrt() if v > 0 else -flint.arb(-v).sqrt()  # noqa: E731
    sources = [root(-3), root(2), lambda prec: flint.arb(5).root(3), root(3), root(-2)]
    assert algebraic.known_real_roots(factors, sources)
    assert abs(float(root_ball(factors[1], 0, 64).real.mid()) + 3 ** 0.5) < 1e-15
    assert abs(float(root_ball(factors[0], 1, 64).real.mid()) - 2 ** 0.5) < 1e-15
    product = factors[0] * factors[1] * factors[2]
    for f, i in [(factors[1], 0), (factors[0], 1), (factors[2], 0)]:
        isolated = algebraic._complex_roots(tuple(int(c) for c in f.coeffs()), 64)[i]
        assert algebraic.identify(product, lambda prec, b=isolated: b, real=True) == (f, i)


def test_real_kth_root_of_a_known_root_matches_isolation(monkeypatch):
    """The cube root of root 1 of x^3 - 3x + 1 (three real roots) and the square roots of its
    positive roots: named from the roots of p alone, the same polynomial and index as identify finds
    by isolating every root of p(x^k)."""
    from symkf.exact import algebraic
    monkeypatch.setattr(algebraic, "_KNOWN_REAL_ROOTS", {})
    p = flint.fmpz_poly([1, -3, 0, 1])
    isolated = algebraic._complex_roots((1, -3, 0, 1), 64)
    algebraic.known_real_roots([p], [lambda prec, b=b: b.real for b in isolated])
    for i, k in [(0, 3), (1, 3), (2, 2), (1, 2)]:
        gamma = AlgebraicNumber._irreducible(p, i)
        ball = lambda prec: flint.acb(abs(gamma._ball(prec).real).root(k) * (1 if gamma > 0 or k % 2 == 0 else -1))  # noqa: E731
        coeffs = [0] * (3 * k + 1)
        for j, c in enumerate(p.coeffs()):
            coeffs[k * j] = int(c)
        expected = algebraic.identify(flint.fmpz_poly(coeffs), ball)
        assert algebraic.real_kth_root(gamma, k, ball, "root") == expected


def test_decreasing_root_of_a_high_power_is_isolated_by_a_narrow_ball(monkeypatch) -> None:
    """``(1 - q)^200 = 2^-48`` on ``[0, 1)``: ``q = 1 - 2^(-6/25)`` (by hand).  The coefficients
    ``C(200, k)`` reach 2^196 while the values near the root are 2^-48: the bisection must decide
    signs above that cancellation, so the ball handed to the identification is narrow (a ball of
    the whole interval isolates the roots of every factor of the composed polynomial, degrees 25,
    25, 50 and 100)."""
    import flint
    from symkf.exact import algebraic
    widths = []
    identify = algebraic.identify

    def watched(poly, ball_at, what="number", **flags):
        widths.append(float(ball_at(64).real.rad()))
        return identify(poly, ball_at, what, **flags)
    monkeypatch.setattr(algebraic, "identify", watched)
    poly = flint.fmpq_poly([1, -1]) ** 200
    root = algebraic.decreasing_root(poly, AlgebraicNumber.from_expr(sp.Rational(1, 2 ** 48)), Fraction(0), Fraction(1))
    assert root == AlgebraicNumber.from_expr(1 - sp.Integer(2) ** sp.Rational(-6, 25))
    assert widths and widths[0] < 2.0 ** -50


def test_unit_roots_isolate_the_roots_in_the_open_unit_interval() -> None:
    """``(2x - 1)(3x - 1)(x^2 - 2)(5x^2 - 5x + 1) x (x - 1)``: in (0, 1) the roots 1/3, 1/2 (met
    exactly at a midpoint) and ``(5 -+ sqrt 5)/10`` (by hand: ~0.276 and ~0.724); 0, 1 and
    ``sqrt 2`` lie outside.  Each interval holds its root and is made exact by root_between."""
    import flint
    from symkf.exact.algebraic import root_between, unit_roots
    poly = math.prod((flint.fmpz_poly(c) for c in ([-1, 2], [-1, 3], [-2, 0, 1], [1, -5, 5], [0, 1], [-1, 1])),
                     start=flint.fmpz_poly([1]))
    brackets = unit_roots(poly)
    want = [(5 - sp.sqrt(5)) / 10, sp.Rational(1, 3), sp.Rational(1, 2), (5 + sp.sqrt(5)) / 10]
    assert len(brackets) == 4 and (Fraction(1, 2), Fraction(1, 2)) in brackets
    for (lo, hi), root in zip(brackets, want):
        assert lo <= root <= hi and root_between(poly, lo, hi) == AlgebraicNumber.from_expr(root)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(-12, 12), min_size=3, max_size=10))
def test_unit_roots_find_every_real_root_in_the_unit_interval(coeffs) -> None:
    # against the real roots of flint's isolation of every complex root, factor by factor
    import flint
    from symkf.exact.algebraic import _real_roots, root_between, unit_roots
    poly = flint.fmpz_poly(coeffs)
    if poly.degree() < 1:
        return
    for f, _ in poly.factor()[1]:
        want = [r for r in _real_roots(f) if 0 < r < 1]
        assert [root_between(f, lo, hi) for lo, hi in unit_roots(f)] == want


def test_sign_at_an_algebraic_point_is_exact() -> None:
    """``2x^2 - 1`` at ``x = sqrt(2)/2`` is 0; ``x`` at it equals ``sqrt(2)/2`` and not
    ``-sqrt(2)/2`` (a conjugate: both roots of the minimal polynomial of the value); ``3x^2``
    exceeds 1 there, and over an interval around 3/10 ``3 (1 - x)^96 ~ 4.04e-15`` exceeds 10^-16
    but not 10^-14 (its coefficients reach 2^93: the interval is bounded through the Taylor form)."""
    import flint
    from symkf.exact.algebraic import exceeds, sign_at
    x = AlgebraicNumber.from_expr(sp.sqrt(2) / 2)
    one, half = AlgebraicNumber.from_expr(1), AlgebraicNumber.from_expr(sp.sqrt(2) / 2)
    assert sign_at(flint.fmpq_poly([-1, 0, 2]), x, AlgebraicNumber.from_expr(0)) == 0
    assert sign_at(flint.fmpq_poly([0, 1]), x, half) == 0
    assert sign_at(flint.fmpq_poly([0, 1]), x, AlgebraicNumber.from_expr(-sp.sqrt(2) / 2)) == 1
    assert sign_at(flint.fmpq_poly([0, 0, 3]), x, one) == 1 and sign_at(flint.fmpq_poly([0, 0, 1]), x, one) == -1
    p = flint.fmpq_poly([1, -1]) ** 96 * 3
    lo, hi = Fraction(3, 10), Fraction(3, 10) + Fraction(1, 2 ** 40)
    assert exceeds(p, AlgebraicNumber.from_expr(sp.Rational(1, 10 ** 16)), lo, hi)
    assert not exceeds(p, AlgebraicNumber.from_expr(sp.Rational(1, 10 ** 14)), lo, hi)
