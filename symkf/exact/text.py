"""Exact numbers and polynomials as text for people: ``3√2/5 + 3√2/5 i``, ``x^4 + 1296/625``,
``the 2nd real root of x^3 - 2``, never SymPy's ``3*sqrt(2)/5``, ``x**4`` or ``CRootOf(...)``.

The exact values stay in the objects (``.exact``, ``.minpoly``, ``to_dict()``); these strings
only show them.  A closed form is shown when it is short and made of rationals, radicals,
``π`` and ``e^(...)``; otherwise a root is named by its approximate value and its polynomial.
"""

from __future__ import annotations

import re
from fractions import Fraction
from typing import Any

import flint
import sympy as sp
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.str import StrPrinter

from ..arguments import check_public
from ..errors import InputError
from .algebraic import AlgebraicNumber

#: longest closed form shown; a longer one is named by its value and polynomial
MAX_CLOSED_FORM = 40

_SHOWN = (sp.Add, sp.Mul, sp.Pow, sp.Number, sp.NumberSymbol, sp.core.numbers.ImaginaryUnit, sp.exp,
          sp.cos, sp.sin)


class _Printer(StrPrinter):
    """SymPy's string printer with mathematical notation: ``√``, ``^``, ``π``, ``i``, ``e^(...)``."""

    def _print_ImaginaryUnit(self, expr: Any) -> str:
        return "i"

    def _print_Pi(self, expr: Any) -> str:
        return "π"

    def _print_Exp1(self, expr: Any) -> str:
        return "e"

    def _print_exp(self, expr: Any) -> str:
        return f"e^({self._print(expr.args[0])})"

    def _print_Pow(self, expr: Any, rational: bool = False) -> str:
        base, power = expr.as_base_exp()
        shown = self.parenthesize(base, PRECEDENCE["Pow"], strict=True)
        if power == sp.S.Half:
            return f"√{shown}"
        if power == -sp.S.Half:
            return f"1/√{shown}"
        if power.is_Integer and power < 0:
            return f"1/{self._print(base ** -power)}" if power != -1 else f"1/{shown}"
        exponent = self._print(power)
        return f"{shown}^{exponent if power.is_Integer and power > 0 else f'({exponent})'}"


def _mathematical(text: str) -> str:
    """SymPy's ``*`` as juxtaposition after a number (``3√2``, ``2iπ``, ``256x``), else as ``·``."""
    text = re.sub(r"(?<=[\d)])\*(?=[√πi(ex])", "", text)
    return text.replace("*", "·").replace("i·π", "πi")


def _plain(expr: sp.Expr) -> str:
    return _mathematical(_Printer().doprint(expr))


def _closed(expr: sp.Expr) -> bool:
    return all(isinstance(node, _SHOWN) for node in sp.preorder_traversal(expr))


def number_text(expr: sp.Expr, limit: int = MAX_CLOSED_FORM) -> str | None:
    """The exact number ``expr`` in mathematical notation (a complex one as ``a + b i`` when its
    real and imaginary parts are radicals), or None when it has no closed form of at most
    ``limit`` characters made of rationals, radicals, ``π`` and ``e^(...)``."""
    if not _closed(expr):
        return None
    text = _plain(expr)
    if expr.is_extended_real is False:
        re_, im_ = sp.expand_complex(expr).as_real_imag()
        if _closed(re_) and _closed(im_) and not (re_.has(sp.exp) or im_.has(sp.exp, sp.cos, sp.sin)):
            imag = _plain(abs(im_)) if im_.is_extended_real else _plain(im_)
            imag = ("i" if imag == "1" else f"{imag}i" if imag.isdigit() else f"({imag})i" if re.search(r"[ +-]", imag)
                    else f"{imag} i")
            sign = "-" if (im_.is_extended_negative) else "+"
            text = f"{_plain(re_)} {sign} {imag}" if re_ != 0 else f"{'-' if sign == '-' else ''}{imag}"
    return text if len(text) <= limit else None


def algebraic_text(value: AlgebraicNumber, digits: int = 6) -> str:
    """A real algebraic number for people: ``2``, ``9/8 ≈ 1.125``, ``10^(2/5)·11^(3/5)/11 ≈ 0.962594``, or, with
    no short closed form, ``the 1st real root of 726x^5 - 1815x^4 + 1210x^3 - 100 (≈ 0.692198)``;
    a rational too long to read, ``a fraction ≈ 0.958833``."""
    closed = number_text(value.exact)
    decimal = format(value, f".{digits}g")
    if "." in decimal and "e" not in decimal:  # Decimal's g keeps trailing zeros: 1.36350
        decimal = decimal.rstrip("0").rstrip(".")
    if value.is_rational:  # a long fraction reads as its decimal (the JSON keeps it exact)
        return closed if closed == decimal else f"{closed} ≈ {decimal}" if closed else f"a fraction ≈ {decimal}"
    if closed is not None:
        return f"{closed} ≈ {decimal}"
    poly = value.minpoly
    below = poly.count_roots(None, sp.Rational(value.interval[0]))  # the interval isolates the root
    return f"the {ordinal(below + 1)} real root of {poly_text(poly, monic=False)} (≈ {decimal})"


def printed_text(sympy_text: str) -> str:
    """SymPy's printed form of a number or a polynomial (as JSON carries it) for people:
    ``2**(7/15)/2`` as ``2^(7/15)/2``, ``256*x**15 - 1`` as ``256x^15 - 1``, other products with ``·``."""
    if not isinstance(sympy_text, str):
        raise InputError(f"sympy_text: expected a string, got {type(sympy_text).__name__}")
    return _mathematical(sympy_text.replace("**", "^"))


def poly_text(poly: flint.fmpz_poly | sp.Poly, var: str = "x", monic: bool = True) -> str:
    """The polynomial in ``var`` as ``x^4 + 1296/625`` (made monic unless ``monic=False``)."""
    coeffs = ([Fraction(int(c)) for c in poly.coeffs()] if isinstance(poly, flint.fmpz_poly)
              else [Fraction(int(c.p), int(c.q)) for c in map(sp.Rational, reversed(poly.all_coeffs()))])
    lead = coeffs[-1] if monic else 1
    terms = []
    for k in range(len(coeffs) - 1, -1, -1):
        c = coeffs[k] / lead
        if c == 0:
            continue
        power = "" if k == 0 else var if k == 1 else f"{var}^{k}"
        size = abs(c)
        number = str(size) if (size != 1 or not power) else ""
        if number and power and size.denominator != 1:
            number = f"({number})"
        terms.append(("-" if c < 0 else "+", number + power))
    if not terms:
        return "0"
    first_sign, first = terms[0]
    return " ".join([("-" if first_sign == "-" else "") + first] + [f"{s} {t}" for s, t in terms[1:]])


#: longest polynomial written out in a root's name; a longer one is named by its degree
MAX_POLY_TEXT = 60


def root_text(poly: flint.fmpz_poly, value: str) -> str:
    """``root ≈ 1.26 of x^3 - 2``: a root named by its approximate ``value`` and its (monic)
    polynomial, or the polynomial's degree when it is longer than :data:`MAX_POLY_TEXT`."""
    shown = poly_text(poly)
    return f"root ≈ {value} of " + (shown if len(shown) <= MAX_POLY_TEXT else f"a degree-{poly.degree()} polynomial")


def approximate(ball: flint.acb, digits: int = 4) -> str:
    """``0.8485+0.8485i`` or ``1.26``: the midpoint of a complex ball to ``digits`` significant digits."""
    v = complex(float(ball.real.mid()), float(ball.imag.mid()))
    return f"{v.real:.{digits}g}" if ball.imag == 0 else f"{v.real:.{digits}g}{v.imag:+.{digits}g}i"


def ordinal(k: int) -> str:
    """``1st``, ``2nd``, ``3rd``, ``4th``, ``11th``, ``22nd``."""
    suffix = "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")
    return f"{k}{suffix}"


check_public(globals())
