"""Exact scalars and matrices from user input.

Accepted: ``int``, :class:`fractions.Fraction`, strings such as ``"5/4"``,
``"sqrt(3)/2"`` or ``"cos(pi/3)"``, and sympy expressions.  A Python ``float``
is refused (its binary value is almost never what the user meant) unless
``rationalize=True``, in which case its shortest decimal representation is
taken exactly and a warning says so.
"""

from __future__ import annotations

import math
import re
import warnings
from fractions import Fraction
from typing import Any, Sequence

import sympy as sp
from sympy.parsing.sympy_parser import parse_expr

from ..errors import InexactInputError, InputError, ShapeError

# Only these names may appear in a string entry; anything else is refused
# before sympy evaluates the text.
_ALLOWED_NAMES = {
    "sqrt": sp.sqrt, "root": sp.root, "cbrt": sp.cbrt,
    "cos": sp.cos, "sin": sp.sin, "tan": sp.tan, "exp": sp.exp,
    "pi": sp.pi, "I": sp.I, "E": sp.E, "Rational": sp.Rational,
}
_TOKEN = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
_CHARS = re.compile(r"^[0-9A-Za-z_+\-*/^()., ]*$")

#: bounds on the size of a number, checked before sympy evaluates a string ("9^9^9" has
#: 370 million digits and would hang)
MAX_EXPONENT = 10 ** 4
MAX_DIGITS = 1000


def _check_size(expr: sp.Expr, text: str, entry: str) -> None:
    """Every power of the unevaluated ``expr``, innermost first, must have an exponent of
    modulus at most MAX_EXPONENT and a value of at most MAX_DIGITS decimal digits."""
    for node in sp.postorder_traversal(expr):
        if node.is_Pow or node is expr:
            try:
                e = abs(complex(sp.N(node.exp, 15))) if node.is_Pow else 1.0
                b = abs(complex(sp.N(node.base if node.is_Pow else node, 15)))
            except (TypeError, ValueError):
                continue
            if not e <= MAX_EXPONENT or (b > 0 and not e * abs(math.log10(b)) <= MAX_DIGITS):
                raise InputError(f"{entry}: {text!r} is too large to evaluate exactly "
                                 f"(exponents up to {MAX_EXPONENT}, values up to {MAX_DIGITS} digits)")


def _parse_string(text: str, entry: str, symbols: bool) -> sp.Expr:
    if not text.strip():
        raise InputError(f"{entry}: empty string is not a number")
    if len(text) > 500 or not _CHARS.match(text):
        raise InputError(f"{entry}: {text!r} is not an exact number expression "
                         "(use forms like '5/4', 'sqrt(3)/2', 'cos(pi/3)')")
    local: dict[str, Any] = dict(_ALLOWED_NAMES)
    for name in _TOKEN.findall(text):
        if name in local:
            continue
        if not symbols:
            raise InputError(f"{entry}: unknown name {name!r} in {text!r}; only numbers and "
                             f"{', '.join(sorted(_ALLOWED_NAMES))} are allowed here")
        local[name] = sp.Symbol(name, positive=True)
    source = text.replace("^", "**")
    names = {"Integer": sp.Integer, "Float": sp.Float, "Rational": sp.Rational, "Symbol": sp.Symbol,
             "Pow": sp.Pow, "Mul": sp.Mul, "Add": sp.Add, "__builtins__": {}}
    try:
        if "**" in source:
            _check_size(parse_expr(source, local_dict=local, global_dict=names, evaluate=False), text, entry)
        value = parse_expr(source, local_dict=local, global_dict=names)
    except InputError:
        raise
    except Exception as exc:  # sympy raises many types on malformed text
        raise InputError(f"{entry}: cannot parse {text!r} ({type(exc).__name__})") from None
    if not isinstance(value, sp.Expr):
        raise InputError(f"{entry}: {text!r} is not a number")
    if value.has(sp.Float):
        raise InexactInputError(f"{entry}: {text!r} contains a decimal point; write the exact "
                                f"rational instead (for example {_suggest(text)!r})")
    return value


def _suggest(text: str) -> str:
    try:
        return str(Fraction(text))
    except (ValueError, ZeroDivisionError):
        return "p/q"


def to_exact(value: Any, entry: str, *, rationalize: bool = False,
             symbols: bool = False) -> sp.Expr:
    """Return ``value`` as an exact sympy number; ``entry`` names it in errors.

    With ``symbols=True`` free symbols are allowed (loss probabilities may be
    symbolic); otherwise the result must be an algebraic number.
    """
    if isinstance(value, bool):
        raise InputError(f"{entry}: {value!r} is a bool, not a number")
    if isinstance(value, int):
        if value.bit_length() > 3.33 * MAX_DIGITS:
            raise InputError(f"{entry}: integer with more than {MAX_DIGITS} digits")
        out: sp.Expr = sp.Integer(value)
    elif isinstance(value, Fraction):
        out = sp.Rational(value.numerator, value.denominator)
    elif isinstance(value, float):
        if not rationalize:
            raise InexactInputError(
                f"{entry}: float {value!r} is not exact; pass the string "
                f"{str(Fraction(repr(value))) if value == value and abs(value) != float('inf') else 'p/q'!r} "
                "or a Fraction, or set rationalize=True")
        if value != value or value in (float("inf"), float("-inf")):
            raise InputError(f"{entry}: {value!r} is not a finite number")
        out = sp.Rational(repr(value))
        warnings.warn(f"{entry}: float {value!r} taken as the rational {out}", stacklevel=3)
    elif isinstance(value, str):
        out = _parse_string(value, entry, symbols)
    elif isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr):
            raise InputError(f"{entry}: {value!r} is not a number")
        if value.has(sp.Float):
            if not rationalize:
                raise InexactInputError(f"{entry}: {value} contains a sympy Float; give it exactly "
                                        "or set rationalize=True")
            value = sp.nsimplify(value, rational=True)
        out = value
    elif hasattr(value, "dtype") and getattr(value, "shape", None) == ():  # numpy scalar
        return to_exact(value.item(), entry, rationalize=rationalize, symbols=symbols)
    else:
        raise InputError(f"{entry}: {type(value).__name__} {value!r} is not an exact number "
                         "(give an int, Fraction, string like '5/4', or sympy expression)")
    if out.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise InputError(f"{entry}: {value!r} is not a finite number")
    if out.free_symbols and not symbols:
        raise InputError(f"{entry}: symbol(s) {sorted(map(str, out.free_symbols))} are not "
                         "allowed here; give a number")
    if not out.free_symbols and out.is_algebraic is False:
        raise InputError(f"{entry}: {out} is transcendental; symkf needs algebraic numbers "
                         "to decide exactly")
    return out


def to_exact_matrix(rows: Any, entry: str, *, rationalize: bool = False,
                    shape: tuple[int | None, int | None] = (None, None)) -> sp.ImmutableMatrix:
    """Return a rectangular exact matrix; ``shape`` entries that are not None are enforced."""
    if isinstance(rows, sp.MatrixBase):
        rows = rows.tolist()
    elif hasattr(rows, "tolist"):
        rows = rows.tolist()
    if isinstance(rows, (str, bytes)) or not isinstance(rows, Sequence) or len(rows) == 0:
        raise ShapeError(f"{entry}: expected a non-empty list of rows, got {type(rows).__name__}")
    if not all(isinstance(r, Sequence) and not isinstance(r, (str, bytes)) for r in rows):
        raise ShapeError(f"{entry}: expected a list of rows (a list of lists)")
    width = len(rows[0])
    if width == 0 or any(len(r) != width for r in rows):
        raise ShapeError(f"{entry}: rows have lengths {[len(r) for r in rows]}; "
                         "all rows must have the same non-zero length")
    want_r, want_c = shape
    if want_r is not None and len(rows) != want_r or want_c is not None and width != want_c:
        raise ShapeError(f"{entry}: shape {len(rows)}x{width}, expected "
                         f"{want_r if want_r is not None else 'any'}x{want_c if want_c is not None else 'any'}")
    return sp.ImmutableMatrix([[to_exact(v, f"{entry}[{i}][{j}]", rationalize=rationalize)
                                for j, v in enumerate(r)] for i, r in enumerate(rows)])
