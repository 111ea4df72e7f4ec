"""Exact numbers and polynomials as text for people (symkf/exact/text.py)."""

import flint
import sympy as sp

from symkf.exact.text import algebraic_text, approximate, number_text, ordinal, poly_text


def test_complex_radical_is_shown_as_real_and_imaginary_parts():
    # (6/5) e^(3 i pi/4) = (6/5)(-sqrt(2)/2 + i sqrt(2)/2) = -3 sqrt(2)/5 + 3 sqrt(2)/5 i
    assert number_text(6 * sp.exp(3 * sp.I * sp.pi / 4) / 5) == "-3√2/5 + 3√2/5 i"
    assert number_text(sp.exp(-sp.I * sp.pi / 3)) == "1/2 - √3/2 i"
    assert number_text(-2 * sp.I) == "-2i"


def test_closed_forms_use_mathematical_notation():
    assert number_text(sp.sqrt(10) / 25) == "√10/25"
    assert number_text(2 ** sp.Rational(1, 3)) == "2^(1/3)"
    assert number_text(sp.exp(2 * sp.pi * sp.I / 7)) == "e^(2πi/7)"  # cos(2 pi/7) has no real radical


def test_long_or_unshown_forms_give_none():
    x = sp.Symbol("x")
    assert number_text(sp.CRootOf(x ** 5 - x - 1, 0)) is None
    assert number_text(sp.sqrt(2) + sp.sqrt(3) + sp.sqrt(5) + sp.sqrt(7) + sp.sqrt(11) + sp.sqrt(13), limit=20) is None


def test_polynomial_text_is_monic_with_carets():
    assert poly_text(flint.fmpz_poly([1296, 0, 0, 0, 625])) == "x^4 + 1296/625"
    assert poly_text(flint.fmpz_poly([2, 3, 5])) == "x^2 + (3/5)x + 2/5"
    assert poly_text(flint.fmpz_poly([2, 3, 5]), monic=False) == "5x^2 + 3x + 2"
    x = sp.Symbol("x")
    assert poly_text(sp.Poly(x ** 6 - 2 * x ** 5 - x + 1, x)) == "x^6 - 2x^5 - x + 1"


def test_approximate_value_and_ordinals():
    assert approximate(flint.acb(flint.arb("0.848528137"), flint.arb("-0.848528137"))) == "0.8485-0.8485i"
    assert [ordinal(k) for k in (1, 2, 3, 4, 11, 12, 13, 21, 102, 111)] == [
        "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "102nd", "111th"]


def test_algebraic_numbers_read_as_closed_form_and_decimal_or_as_a_named_root():
    from symkf.exact.algebraic import AlgebraicNumber
    x = sp.Symbol("x")
    A = AlgebraicNumber.from_expr
    assert algebraic_text(A(sp.Integer(1))) == "1" and algebraic_text(A(sp.Rational(9, 8))) == "9/8 ≈ 1.125"
    assert algebraic_text(A(10 ** sp.Rational(2, 5) * 11 ** sp.Rational(3, 5) / 11)) == "10^(2/5)·11^(3/5)/11 ≈ 0.962594"
    # 16x^4 - 60x^3 + 88x^2 - 60x + 15 is 15, -1 and 23 at x = 0, 1, 2: one real root in (0, 1), one in (1, 2)
    p = 16 * x ** 4 - 60 * x ** 3 + 88 * x ** 2 - 60 * x + 15
    assert algebraic_text(A(sp.CRootOf(p, 1))) == "the 2nd real root of 16x^4 - 60x^3 + 88x^2 - 60x + 15 (≈ 1.3635)"
    assert algebraic_text(A(sp.Rational(10 ** 40 + 1, 10 ** 40))) == "a fraction ≈ 1"
