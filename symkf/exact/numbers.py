"""Exact scalars and matrices from user input, through one safe parser.

Accepted: ``int`` (and numpy integers), :class:`fractions.Fraction`, :class:`decimal.Decimal`,
strings, sympy expressions, and binary floats whose value is exactly the decimal they print
as (``2.0``, ``-1.5``, ``0.0625``: dyadic rationals).  Any other float (``0.1`` is
``3602879701896397/36028797018963968`` in binary) is refused unless ``rationalize`` says how
to read it:

* ``rationalize=True`` (or ``"decimal"``): the float's shortest decimal, exactly (0.1 -> 1/10);
* ``rationalize="nearby"``: a nearby exact constant q*c, q a rational with a small
  denominator and c in :data:`NEARBY_CONSTANTS` (sqrt(3), cos(pi/5), ...), within the relative
  tolerance :data:`NEARBY_TOLERANCE`; the decimal when none is that close.

Every conversion of one constructor call is reported in ONE warning (see
:func:`rationalization`).

A string is read by :func:`parse_exact`, a whitelist over Python's ``ast``: integers, decimals
(``"0.1"`` is exactly 1/10), ``+ - * /``, powers ``**``/``^`` with rational exponents,
``sqrt``, ``cbrt``, ``root(x, n)``, ``Rational(p, q)``, ``pi``, ``I``, ``E``, ``cos``/``sin``/``tan``
of rational multiples of ``pi`` and ``exp`` of rational multiples of ``pi*I``, and the symbols
the caller declares.  Nothing else (no attribute access, no other call, no ``eval``) is
accepted, and every size (exponents, digits, root indices, angle denominators, algebraic
degree, radical nesting) is checked against :mod:`symkf.budget` before sympy evaluates it.
"""

from __future__ import annotations

import ast
import contextlib
import contextvars
import functools
import math
import numbers
import os
import re
import sys
import warnings
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from typing import Any, Callable, Collection, Iterable, Iterator, Mapping, NamedTuple, Sequence

import sympy as sp

from ..arguments import LENGTHS, PRICERS, check_public, described, unpriced
from .. import budget
from ..errors import InexactInputError, InputError, ShapeError
from .blocks import diagonal_blocks

#: the names a string may use besides declared symbols: functions, then constants
FUNCTIONS = ("sqrt", "cbrt", "root", "Rational", "cos", "sin", "tan", "exp")
CONSTANTS = {"pi": sp.pi, "I": sp.I, "E": sp.E}
RESERVED = frozenset(FUNCTIONS) | frozenset(CONSTANTS)

_DECIMAL = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_SYMBOL = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,31}\Z")
_EXAMPLES = "forms like '5/4', '0.1', 'sqrt(3)/2', 'cos(pi/3)'"


#: the key of :class:`_Num` ``gens`` holding the order m of the cyclotomic field Q(zeta_m) that
#: contains every trigonometric constant and I (cos, sin, tan(p*pi/q), exp(p*pi*I/q) lie in Q(zeta_4q))
_CYCLOTOMIC = "cyclotomic order"


def _merge(*parts: dict) -> dict:
    out: dict = {}
    for gens in parts:
        for key, value in gens.items():
            out[key] = math.lcm(out.get(key, 1), value) if key == _CYCLOTOMIC else value
    return out


def _degree(gens: dict) -> int:
    """The degree bound: product of the radicals' bounds times phi(cyclotomic order)."""
    return _radical(gens) * int(sp.totient(gens.get(_CYCLOTOMIC, 1)))


def _radical(gens: dict) -> int:
    return math.prod(v for k, v in gens.items() if k != _CYCLOTOMIC)


def check_degree(generic: bool, degree: int, entry: str, what: str) -> None:
    """The cost model of number fields (:mod:`symkf.budget`): a field built generically (radicals,
    or eigenvalues in an extension of the entries' field: sympy's ``minimal_polynomial``,
    Trager's norm, whose cost explodes with the degree) is capped by ``max_degree``; one inside a
    cyclotomic field (trigonometric constants and ``I`` alone, presented by ``zeta_m`` or
    ``2 cos(2 pi/m)`` with cheap arithmetic, :mod:`symkf.exact.field`) by ``max_cyclotomic_degree``,
    at a quarter of its degree."""
    if generic:
        budget.check("max_degree", degree, entry, f"the algebraic degree (bound) of {what}")
    else:
        # one cyclotomic field, no compositum: its work (a rotation block's spectrum without Trager's
        # norm, symkf.exact.nfpoly) per degree is a quarter of that of the compositum of several
        # parts, which the same cap bounds in symkf.engine.cylinders (2R(2 pi/2039), degree 4072:
        # 7.6 CPU-s, 500 MB, about what 2R(2 pi/509) of degree 1016 cost before)
        budget.check("max_cyclotomic_degree", -(-degree // 4), entry,
                     f"a quarter of the cyclotomic degree (bound) {degree} of {what}")


@unpriced
def rational_bits(r: sp.Rational | Fraction) -> float:
    """The height in bits of a rational ``p/q`` in lowest terms: ``log2 max(|p|, q)``, the bits of the
    larger of its numerator and denominator (2^-1074: 1074)."""
    p, q = (r.p, r.q) if isinstance(r, sp.Rational) else (r.numerator, r.denominator)
    return math.log2(max(abs(p), q))


def check_bits(bits: float, entry: str, what: str | Callable[[], str]) -> None:
    """Refuse a number whose bit size (height bound) exceeds ``max_bits``, before it is built."""
    budget.check("max_bits", math.ceil(bits), entry,
                 lambda: f"the bit size (height bound) of {what if isinstance(what, str) else what()}")


#: height bounds in bits of the trigonometric constants: cos t = (z + 1/z)/2 with z a root of unity
#: (height 0), and h(x + y) <= h(x) + h(y) + 1, h(x y) <= h(x) + h(y); tan = sin/cos
_ANGLE_BITS = {"cos": 2, "sin": 2, "tan": 4, "exp": 0}


@dataclass(frozen=True)
class _Num:
    """A parsed value with what bounds its cost: ``gens`` maps each radical to a bound on its
    degree over Q, and :data:`_CYCLOTOMIC` to the order of a cyclotomic field holding its
    trigonometric constants (:func:`_degree` bounds the value's degree); ``depth`` is the
    nesting of radicals; ``bits`` bounds its absolute logarithmic height in bits (exact for a
    rational; :func:`check_bits`), known before the value is evaluated."""

    expr: sp.Expr
    gens: dict = field(default_factory=dict)
    depth: int = 0
    bits: float = 0.0


class _Parser:
    def __init__(self, text: str, entry: str, symbols: bool | Collection[str]):
        self.text, self.entry, self.symbols = text, entry, symbols

    def fail(self, why: str) -> InputError:
        return InputError(f"{self.entry}: {why} in {self.text!r} (an exact number is written in {_EXAMPLES})")

    def parse(self) -> sp.Expr:
        source = self.text.replace("^", "**")
        try:
            tree = ast.parse(source.strip(), mode="eval")
        except (SyntaxError, ValueError, MemoryError, RecursionError):
            raise self.fail("not a well-formed expression") from None
        self.source = source.strip()
        try:
            return self.node(tree.body).expr
        except RecursionError:
            raise self.fail("nested too deeply") from None

    def node(self, n: ast.AST) -> _Num:
        if isinstance(n, ast.Constant):
            return self.constant(n)
        if isinstance(n, ast.Name):
            return self.name(n.id)
        if isinstance(n, ast.UnaryOp) and isinstance(n.op, (ast.UAdd, ast.USub)):
            x = self.node(n.operand)
            return _Num(-x.expr if isinstance(n.op, ast.USub) else x.expr, x.gens, x.depth, x.bits)
        if isinstance(n, ast.BinOp) and isinstance(n.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
            a, b = self.node(n.left), self.node(n.right)
            if isinstance(n.op, ast.Div) and b.expr == 0:
                raise self.fail("division by zero")
            op = {ast.Add: sp.Add, ast.Sub: lambda x, y: x - y, ast.Mult: sp.Mul,
                  ast.Div: lambda x, y: x / y}[type(n.op)]
            # Weil heights: h(x +- y) <= h(x) + h(y) + 1 bit, h(x y), h(x / y) <= h(x) + h(y)
            bits = a.bits + b.bits + isinstance(n.op, (ast.Add, ast.Sub))
            check_bits(bits, self.entry, repr(self.text))
            return self.combine(op(a.expr, b.expr), a, b, bits=bits)
        if isinstance(n, ast.BinOp) and isinstance(n.op, ast.Pow):
            return self.power(self.node(n.left), self.node(n.right).expr)
        if isinstance(n, ast.Call):
            return self.call(n)
        raise self.fail(f"{type(n).__name__.lower()} is not allowed")

    def constant(self, n: ast.Constant) -> _Num:
        if isinstance(n.value, bool) or not isinstance(n.value, (int, float)):
            raise self.fail(f"literal {n.value!r} is not allowed")
        text = (ast.get_source_segment(self.source, n) or "").replace("_", "")
        if not _DECIMAL.fullmatch(text):
            raise self.fail(f"the literal {text!r} is not a decimal number")
        mantissa, _, exponent = text.lower().partition("e")
        digits = len(mantissa.replace(".", "").lstrip("0"))
        budget.check("max_digits", digits + abs(int(exponent or 0)), self.entry,
                     f"the number of digits of the literal {text[:20]!r}")
        value = Fraction(text)
        check_bits(rational_bits(value), self.entry, f"the literal {text[:20]!r}")
        return _Num(sp.Rational(value), bits=rational_bits(value))

    def name(self, name: str) -> _Num:
        if name in CONSTANTS:
            return _Num(CONSTANTS[name], {_CYCLOTOMIC: 4} if name == "I" else {})
        if name in FUNCTIONS:
            raise self.fail(f"{name} is a function; call it, e.g. {name}(2)")
        declared = self.symbols is True and _SYMBOL.match(name) or \
            not isinstance(self.symbols, bool) and name in self.symbols
        if not declared:
            allowed = "numbers and " + ", ".join(sorted(RESERVED))
            if not isinstance(self.symbols, bool) and self.symbols:
                allowed += ", and the symbols " + ", ".join(sorted(self.symbols))
            raise self.fail(f"unknown name {name!r} (only {allowed} are allowed here)")
        return _Num(sp.Symbol(name, positive=True))

    def combine(self, expr: sp.Expr, *parts: _Num, gen: tuple[Any, int] | None = None,
                depth: int = 0, bits: float = 0.0) -> _Num:
        gens = _merge(*(p.gens for p in parts))
        if expr.is_Rational:   # evaluated already: its exact size replaces the bound
            bits = rational_bits(expr)
        if gen is not None and not (expr.is_Rational or expr.free_symbols):
            gens = _merge(gens, {gen[0]: gen[1]})
        # one trigonometric constant (times and plus rationals) is cheap; sums and products of
        # several, and radicals, need sympy's minimal_polynomial
        check_degree(_radical(gens) > 1 or field_cost([expr]).atoms > 1, _degree(gens), self.entry, repr(self.text))
        return _Num(expr, gens, max([depth, *(p.depth for p in parts)]), bits)

    def power(self, base: _Num, exp: sp.Expr) -> _Num:
        if not exp.is_Rational:
            raise self.fail(f"the exponent {exp} is not a rational number")
        budget.check("max_exponent", abs(exp.p), self.entry, f"the exponent in {self.text!r}")
        if exp.q > 1:
            budget.check("max_degree", exp.q, self.entry, f"the root index in {self.text!r}")
            budget.check("max_nesting", base.depth + 1, self.entry, f"the radical nesting of {self.text!r}")
        if base.expr == 0 and exp < 0:
            raise self.fail("division by zero")
        # the height of x^(p/q) is |p/q| h(x): its size, not its magnitude ((1 + 10^-999)^10000 is
        # near 1 and has 33 million bits), known before sympy evaluates the power
        bits = float(abs(exp)) * base.bits
        check_bits(bits, self.entry, f"a power in {self.text!r}")
        value = base.expr ** exp
        if exp.q == 1:
            return self.combine(value, base, bits=bits)
        degree = exp.q * _degree(base.gens)
        return self.combine(value, gen=(value, degree), depth=base.depth + 1, bits=bits)

    def call(self, n: ast.Call) -> _Num:
        name = n.func.id if isinstance(n.func, ast.Name) else None
        if name not in FUNCTIONS:
            raise self.fail("only the calls " + ", ".join(FUNCTIONS) + " are allowed")
        arity = {"root": 2, "Rational": 2}.get(name, 1)
        if n.keywords or len(n.args) != arity:
            raise self.fail(f"{name} takes {arity} positional argument{'s' * (arity > 1)}")
        args = [self.node(a) for a in n.args]
        if name in ("sqrt", "cbrt"):
            return self.power(args[0], sp.Rational(1, 2 if name == "sqrt" else 3))
        if name in ("root", "Rational"):
            k = args[1].expr
            if not k.is_Integer or k == 0 or name == "root" and k < 1 or not args[0].expr.is_Integer \
                    and name == "Rational":
                raise self.fail(f"{name} needs {'an integer index' if name == 'root' else 'two integers'}")
            return self.power(args[0], 1 / k) if name == "root" else \
                _Num(args[0].expr / k, bits=rational_bits(args[0].expr / k))
        return self.angle(name, args[0])

    def angle(self, name: str, arg: _Num) -> _Num:
        fn = getattr(sp, name)
        if arg.expr.free_symbols:
            return _Num(fn(arg.expr), arg.gens, arg.depth, arg.bits)
        unit = sp.pi * sp.I if name == "exp" else sp.pi
        r = sp.expand(arg.expr / unit)
        if not r.is_Rational:
            raise self.fail(f"the argument of {name} must be a rational multiple of "
                            f"{'pi*I' if name == 'exp' else 'pi'}, got {arg.expr}")
        budget.check("max_angle_denominator", r.q, self.entry, f"the denominator of the angle in {self.text!r}")
        return self.combine(fn(r * unit), arg, gen=(_CYCLOTOMIC, 4 * r.q), depth=arg.depth, bits=_ANGLE_BITS[name])


def parse_exact(text: str, entry: str, *, symbols: bool | Collection[str] = ()) -> sp.Expr:
    """The exact sympy value of the string ``text``; ``entry`` names it in errors.

    ``symbols`` declares the free symbols allowed: a collection of names, or True for any
    identifier (loss probabilities may be symbolic).  Symbols are positive.  The value may be
    transcendental (``"pi/5"``, an angle); :func:`to_exact` refuses that where a number must be
    algebraic.
    """
    if not isinstance(text, str):
        raise InputError(f"{entry}: expected a string, got {type(text).__name__}")
    if not text.strip():
        raise InputError(f"{entry}: empty string is not a number")
    budget.check("max_number_length", len(text), entry, "the length of the number's text (characters)")
    if not text.isascii():   # Python reads identifiers after NFKC: a lookalike would become sqrt or I
        bad = next(c for c in text if not c.isascii())
        raise InputError(f"{entry}: {bad!r} (U+{ord(bad):04X}) at position {text.index(bad)} is not ASCII; numbers "
                         "are read from ASCII text only (lookalike characters are refused, not guessed)")
    return _Parser(text, entry, symbols).parse()


# ---- conversion of floats ------------------------------------------------------------------

#: relative tolerance of ``rationalize="nearby"``: float64 results of a few operations on exact
#: constants lie within a few ulps (2.2e-16 each)
NEARBY_TOLERANCE = 1e-12
#: the largest denominator of the rational factor q of a nearby constant q*c
NEARBY_DENOMINATOR = 120
#: the radicals c of ``rationalize="nearby"``: square roots of square-free integers up to 30
NEARBY_CONSTANTS: tuple[sp.Expr, ...] = (
    sp.Integer(1), *(sp.sqrt(k) for k in (2, 3, 5, 6, 7, 10, 11, 13, 14, 15, 17, 19, 21, 22, 23, 26, 29, 30)))
_NEARBY_VALUES = tuple(float(c) for c in NEARBY_CONSTANTS)
#: the largest denominator M of an angle pi k/M whose cosine ``"nearby"`` recognises: the sine of
#: pi k/m is the cosine of pi (m - 2k)/(2m), so every cosine and sine of an angle pi k/m with
#: m <= 60 is covered (cos(pi k/M) for M in 1, 2, 3, 4, 6 is rational or q sqrt(2), q sqrt(3))
NEARBY_ANGLE_DENOMINATOR = 120
#: the largest denominator of the rational factor q of a nearby cosine q cos(pi k/M)
NEARBY_COSINE_DENOMINATOR = 12


@functools.lru_cache(maxsize=1)
def _cosines() -> tuple[Any, tuple[tuple[int, int], ...]]:
    """cos(pi k/M) as floats with their (k, M), 0 < 2k < M <= :data:`NEARBY_ANGLE_DENOMINATOR`,
    gcd(k, M) = 1, M not in 1, 2, 3, 4, 6 (about 2 200 values; built at the first use, in ms)."""
    import numpy as np
    angles = tuple((k, M) for M in range(5, NEARBY_ANGLE_DENOMINATOR + 1) if M != 6
                   for k in range(1, (M + 1) // 2) if 2 * k < M and math.gcd(k, M) == 1)
    return np.cos(np.pi * np.array([k / M for k, M in angles])), angles


def _nearby(x: float) -> sp.Expr | None:
    """The simplest q*c within :data:`NEARBY_TOLERANCE` of ``x`` (smallest denominator, then
    numerator; radicals before cosines), c a radical of :data:`NEARBY_CONSTANTS` or a cosine
    cos(pi k/M) (:func:`_cosines`), or None."""
    import numpy as np
    if x == 0:
        return sp.Integer(0)
    tol = NEARBY_TOLERANCE * abs(x)
    best: tuple[int, int, int, sp.Expr] | None = None
    for c, cf in zip(NEARBY_CONSTANTS, _NEARBY_VALUES):
        q = Fraction(x / cf).limit_denominator(NEARBY_DENOMINATOR)
        if abs(float(q) * cf - x) <= tol:
            key = (q.denominator, abs(q.numerator), 0)
            if best is None or key < best[:3]:
                best = (*key, sp.Rational(q.numerator, q.denominator) * c)
    values, angles = _cosines()
    t = x / values
    for den in range(1, NEARBY_COSINE_DENOMINATOR + 1):
        if best is not None and best[0] <= den:
            break
        num = np.rint(t * den)
        hits = np.flatnonzero((num != 0) & (np.abs(num / den * values - x) <= tol))
        if hits.size:
            i = int(hits[np.argmin(np.abs(num[hits]))])
            k, M = angles[i]
            best = (den, int(abs(num[i])), 1, sp.Rational(int(num[i]), den) * sp.cos(sp.pi * k / M))
    return None if best is None else best[3]


def _nearby_rotation(a: float, b: float) -> tuple[sp.Expr, sp.Expr] | None:
    """Exact ``(r cos t, r sin t)`` for the float pair ``(a, b)`` of a scaled rotation, recognised
    jointly: ``r^2 = a^2 + b^2`` a rational with a small denominator, ``t = atan2(b, a)`` a rational
    multiple of pi with denominator at most :data:`NEARBY_ANGLE_DENOMINATOR`, and both entries
    within :data:`NEARBY_TOLERANCE` (relative to r) of the exact values; or None."""
    r2 = a * a + b * b
    R2 = Fraction(r2).limit_denominator(NEARBY_DENOMINATOR)
    turn = Fraction(math.atan2(b, a) / math.pi).limit_denominator(NEARBY_ANGLE_DENOMINATOR)
    if R2 == 0 or abs(float(R2) - r2) > 2 * NEARBY_TOLERANCE * r2 or \
            abs(float(turn) * math.pi - math.atan2(b, a)) > NEARBY_TOLERANCE * max(1.0, abs(math.atan2(b, a))):
        return None
    r, angle = sp.sqrt(sp.Rational(R2.numerator, R2.denominator)), sp.pi * sp.Rational(turn.numerator, turn.denominator)
    exact = (r * sp.cos(angle), r * sp.sin(angle))
    tol = NEARBY_TOLERANCE * math.sqrt(r2)
    return exact if all(abs(float(e) - f) <= tol for e, f in zip(exact, (a, b))) else None


@dataclass
class _Conversions:
    """The floats converted inside one :func:`rationalization` block."""

    what: str
    changes: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    #: matrices whose diagonal blocks ``"nearby"`` recognised only in part, as that partial
    #: reading (by entry name): they were read as decimals instead
    partial: dict = field(default_factory=dict)


_ACTIVE: contextvars.ContextVar[_Conversions | None] = contextvars.ContextVar("symkf_rationalize", default=None)


@contextlib.contextmanager
def rationalization(what: str) -> Iterator[_Conversions]:
    """Collect the floats rationalized inside the block and warn ONCE, listing them, when it
    ends.  Nested blocks join the outermost (one constructor, one warning); ``notes`` appended
    to the yielded record (e.g. a comparison of periods) are added to the warning."""
    outer = _ACTIVE.get()
    if outer is not None:
        yield outer
        return
    record = _Conversions(what)
    token = _ACTIVE.set(record)
    try:
        yield record
    finally:
        _ACTIVE.reset(token)
    if record.changes:
        shown = "; ".join(f"{e}: {x!r} -> {v} ({how})" for e, x, v, how in record.changes[:12])
        more = f"; and {len(record.changes) - 12} more" if len(record.changes) > 12 else ""
        warnings.warn(f"{what}: {len(record.changes)} float(s) rationalized: {shown}{more}. Periods and "
                      "critical values can jump under rounding" + "".join(f"; {n}" for n in record.notes),
                      stacklevel=_caller_level())


def _caller_level() -> int:
    """The ``stacklevel`` that points a warning at the caller's line: the first frame outside
    symkf, contextlib and dataclass-generated ``__init__`` code (``System(...)``)."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    frame, level = sys._getframe(1), 1
    while frame is not None and (frame.f_code.co_filename.startswith(package) or
                                 frame.f_code.co_filename in ("<string>", contextlib.__file__)):
        frame, level = frame.f_back, level + 1
    return level


def _binary(value: float) -> str:
    """The binary value of a finite float: its fraction when short, else ``m * 2^e`` with m odd
    (5e-324 is 2^-1074, whose fraction has 752 digits)."""
    text = str(Fraction(value))
    if len(text) <= 40:
        return text
    m, q = value.as_integer_ratio()
    e = -(q.bit_length() - 1) if q > 1 else (m & -m).bit_length() - 1
    m = m >> e if e > 0 else m
    return f"2^{e}" if m == 1 else f"{m} * 2^{e}"


def _float(value: float, entry: str, rationalize: bool | str) -> sp.Expr:
    if not math.isfinite(value):
        raise InputError(f"{entry}: {value!r} is not a finite number")
    decimal = Fraction(repr(value))
    if decimal == Fraction(value):  # the printed decimal is the binary value: nothing to guess
        return sp.Rational(decimal.numerator, decimal.denominator)
    if rationalize not in (True, "decimal", "nearby"):
        active = _ACTIVE.get()
        where = f"{active.what}(..., rationalize=...)" if active else "rationalize=..."
        if rationalize is not False:
            raise InputError(f"{entry}: rationalize={rationalize!r}; expected False, True, 'decimal' or 'nearby'")
        exact = [repr(repr(value))] + ([repr(str(decimal))] if len(str(decimal)) <= 40 else [])
        raise InexactInputError(
            f"{entry}: the float {value!r} is not exact (its binary value is {_binary(value)}); give "
            f"the string {' or '.join(exact)}, a Fraction or Decimal, or pass "
            f"{where} with True (its shortest decimal) or 'nearby' (a nearby exact constant such as "
            "sqrt(3)/2)")
    out = _nearby(value) if rationalize == "nearby" else None
    how = f"nearby constant within {NEARBY_TOLERANCE:g}" if out is not None else "shortest decimal"
    if out is None:
        check_bits(rational_bits(decimal), entry, f"the decimal {repr(value)!r}")
        out = sp.Rational(decimal.numerator, decimal.denominator)
    with rationalization(entry) as record:
        record.changes.append((entry, value, out, how))
    return out


def sympify(value: Any, entry: str = "value") -> sp.Basic:
    """One number from outside as a sympy object, without sympy's own ``sympify`` (which
    evaluates strings as Python, also inside tuples, dicts and sets, and calls ``str`` of unknown
    objects): a sympy object is kept, an object with ``_sympy_`` (an AlgebraicNumber) gives its
    sympy value, a string goes through :func:`parse_exact` and any other number through
    :func:`to_exact` (transcendental values allowed).  Containers and other objects are refused
    with an :class:`InputError` naming ``entry``."""
    if isinstance(value, sp.Basic):
        return value
    convert = getattr(type(value), "_sympy_", None)
    if convert is not None:
        out = convert(value)
        if isinstance(out, sp.Basic):
            return out
    return to_exact(value, entry, algebraic=False)


def to_rational(value: Any, entry: str) -> sp.Rational:
    """``value`` (an int, Fraction, exact float, string such as ``"1/3"``, sympy Rational, ...)
    as a sympy Rational; anything else is an :class:`InputError` naming ``entry``."""
    out = sympify(value, entry)
    if not isinstance(out, sp.Rational):
        raise InputError(f"{entry}: expected a rational number, got {described(value)}")
    return out


def as_matrix(value: Any, entry: str) -> sp.Matrix:
    """A sympy matrix as it is (its entries are sympy objects already); anything else, e.g. rows
    of user entries, through :func:`to_exact_matrix` (sympy's Matrix would parse strings)."""
    return sp.Matrix(value if isinstance(value, sp.MatrixBase) else to_exact_matrix(value, entry))


class FieldCost(NamedTuple):
    """Bounds on the field generated by some numbers, for :func:`check_degree`."""

    #: product of the degrees of the distinct radicals (index q; nested ones counted separately)
    radical: int
    #: degree of the cyclotomic field Q(zeta_m) holding the trigonometric constants and I (m the lcm of the bounds 4q)
    cyclotomic: int
    #: the same for the real subfield Q(zeta_m)^+ when every number is real
    own: int
    #: distinct trigonometric constants, exponentials and I
    atoms: int


@unpriced
def field_cost(exprs: Iterable[sp.Expr]) -> FieldCost:
    """The :class:`FieldCost` of the sympy numbers ``exprs`` (as sympy evaluated them: cos(pi/5)
    is a radical)."""
    gens: dict = {}
    atoms: set = set()
    real = True
    for expr in exprs:
        nodes = sp.preorder_traversal(expr)
        for node in nodes:
            if node.is_Pow and node.exp.is_Rational and node.exp.q > 1:
                gens = _merge(gens, {(node.base, node.exp.q): node.exp.q})
                real = real and node.base.is_nonnegative is True
            elif node is sp.I:
                gens, real = _merge(gens, {_CYCLOTOMIC: 4}), False
                atoms.add(node)
            elif isinstance(node, (sp.cos, sp.sin, sp.tan, sp.exp)):
                r = node.args[0] / (sp.pi * sp.I if isinstance(node, sp.exp) else sp.pi)
                if r.is_Rational:
                    gens = _merge(gens, {_CYCLOTOMIC: 4 * r.q})
                    real = real and not isinstance(node, sp.exp)
                    atoms.add(node)
                    nodes.skip()  # the I of exp(p pi I/q) is part of the constant
    cyclotomic = int(sp.totient(gens.get(_CYCLOTOMIC, 1)))
    return FieldCost(_radical(gens), cyclotomic, cyclotomic // 2 if real and cyclotomic > 1 else cyclotomic,
                     len(atoms))


@unpriced
def radical_degree(expr: sp.Basic) -> int | None:
    """An upper bound on the degree over Q of the sympy number ``expr``, from its tree: 1 for a
    rational; ``q`` for ``b^(p/q)``, ``b`` rational (a root of ``x^q - b^p``), ``q d`` for an
    algebraic ``b`` of degree ``d``; ``lcm(q_i)`` for a product ``c prod b_i^(p_i/q_i)`` of
    radicals of rationals (its ``lcm``-th power is rational: radicals of one index combine) times
    the bounds of its other factors; the product of its terms' bounds for a sum (the degree of a
    compositum is at most the product of the degrees); ``phi(4q)`` for ``cos``, ``sin``, ``tan``
    of ``p pi/q`` and ``exp(p pi I/q)`` (they lie in Q(zeta_4q)), 2 for I.  None when ``expr``
    holds anything else (a symbol, pi, E).  Often far below :func:`field_cost`'s bound, the
    product over all its distinct radicals: ``2^(2/9) 3^(7/9)`` has 9 here, 81 there."""
    if expr.is_Rational:
        return 1
    if expr is sp.I:
        return 2
    if isinstance(expr, (sp.cos, sp.sin, sp.tan, sp.exp)):
        r = expr.args[0] / (sp.pi * sp.I if isinstance(expr, sp.exp) else sp.pi)
        return int(sp.totient(4 * r.q)) if r.is_Rational else None
    if expr.is_Pow and expr.exp.is_Rational:
        base = radical_degree(expr.base)
        return None if base is None else base * int(expr.exp.q)
    if expr.is_Mul or expr.is_Add:
        index, bound = 1, 1
        for arg in expr.args:
            if expr.is_Mul and arg.is_Pow and arg.base.is_Rational and arg.exp.is_Rational:
                index = math.lcm(index, int(arg.exp.q))   # a radical of a rational: combined by index
                continue
            part = radical_degree(arg)
            if part is None:
                return None
            bound *= part
        return index * bound
    return None


@unpriced
def expr_bits(expr: sp.Basic) -> float:
    """A bound on the height in bits of a sympy number, by the parser's rules: exact for a
    rational, ``|p/q| h(x)`` for ``x**(p/q)`` (an unevaluated power is bounded, not built), sums
    ``h(x_1) + ... + h(x_k) + log2 k``, products the sum of the heights."""
    if expr.is_Rational:
        return rational_bits(expr)
    if expr.is_Pow and expr.exp.is_Rational:
        return float(abs(expr.exp)) * expr_bits(expr.base)
    if isinstance(expr, (sp.cos, sp.sin, sp.tan, sp.exp)) and not expr.args[0].free_symbols:
        return _ANGLE_BITS[type(expr).__name__]
    parts = sum(expr_bits(a) for a in expr.args)
    return parts + math.log2(len(expr.args)) if expr.is_Add else parts


def _nesting(expr: sp.Basic) -> int:
    """The nesting depth of radicals (``sqrt(2 + sqrt(3))``: 2), as the parser counts it."""
    inner = max((_nesting(a) for a in expr.args), default=0)
    return inner + 1 if expr.is_Pow and expr.exp.is_Rational and expr.exp.q > 1 else inner


def _check_sympy(expr: sp.Basic, entry: str, degree: bool = True) -> None:
    """The budget checks of the parser, applied to a sympy expression given directly: its size,
    height, exponents, root indices, angles, radical nesting and (``degree``) the degree bound of
    its field."""
    if not isinstance(expr, sp.Basic) or isinstance(expr, sp.Symbol):
        return
    if isinstance(expr, sp.Rational):
        check_bits(rational_bits(expr), entry, "a sympy rational")
        return
    budget.check("max_number_length", sp.count_ops(expr, visual=False) + len(expr.atoms()), entry,
                 "the size (operations and atoms) of the sympy expression")
    check_bits(expr_bits(expr), entry, lambda: f"the sympy number {str(expr)[:40]}")
    for node in sp.preorder_traversal(expr):
        if node.is_Pow and node.exp.is_Rational:
            budget.check("max_exponent", abs(node.exp.p), entry, lambda: f"an exponent of {expr}")
            budget.check("max_degree", node.exp.q, entry, lambda: f"a root index of {expr}")
        elif isinstance(node, (sp.cos, sp.sin, sp.tan, sp.exp)) and not node.args[0].free_symbols:
            r = node.args[0] / (sp.pi * sp.I if isinstance(node, sp.exp) else sp.pi)
            if r.is_Rational:
                budget.check("max_angle_denominator", r.q, entry, lambda: f"the denominator of an angle of {expr}")
    budget.check("max_nesting", _nesting(expr), entry, "the nesting depth of radicals")
    if degree:
        cost = field_cost([expr])
        check_degree(cost.radical > 1, cost.radical * cost.cyclotomic, entry, f"the sympy number {str(expr)[:40]}")


def price_sympy(expr: sp.Basic, entry: str) -> None:
    """A sympy argument of a call from outside symkf, priced like the same number as text
    (registered in :data:`symkf.arguments.PRICERS`; matrices entry by entry), and its degree: the
    lesser of :func:`field_cost`'s bound (the field of all its radicals, which :func:`to_exact`
    prices where a number enters a model) and :func:`radical_degree` (the number's own: a product
    of radicals of one index, as symkf's own exact results are, stays far below the field's
    bound), capped as :func:`check_degree` says before sympy's ``minimal_polynomial`` meets it
    (a sum of the square roots of the first ten primes has degree 1024: that call never ended)."""
    if isinstance(expr, sp.Expr) and expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise InputError(f"{entry}: {str(expr)[:60]} is not a finite number (symkf's exact numbers are algebraic)")
    if isinstance(expr, sp.Expr) and not expr.free_symbols:
        _check_sympy(expr, entry, degree=False)
        if isinstance(expr, sp.Rational):
            return
        cost = field_cost([expr])
        degree = min(cost.radical * cost.cyclotomic, radical_degree(expr) or math.inf)
        check_degree(cost.radical > 1 or cost.atoms > 1, degree, entry, f"the sympy number {str(expr)[:40]}")


PRICERS.append((sp.Basic, price_sympy))
LENGTHS.append(lambda length, entry: budget.check("max_priced_items", length, entry,
                                                  "the number of sympy numbers of the list"))


def to_exact(value: Any, entry: str, *, rationalize: bool | str = False,
             symbols: bool | Collection[str] = (), algebraic: bool = True) -> sp.Expr:
    """Return ``value`` as an exact sympy number; ``entry`` names it in errors.

    ``symbols`` declares the free symbols a string may use (see :func:`parse_exact`); without
    them the result must be a number, algebraic unless ``algebraic=False`` (an angle such as
    ``pi/5``).  ``rationalize`` reads binary floats (module docstring).
    """
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        raise InputError(f"{entry}: {value!r} is a bool, not a number")
    if hasattr(value, "dtype") and getattr(value, "shape", None) == ():  # numpy scalar or 0-d array
        value = value.item()
    if isinstance(value, numbers.Integral):
        value = int(value)
        budget.check("max_digits", math.ceil(value.bit_length() * math.log10(2)), entry,
                     "the number of digits (about) of an integer")
        check_bits(value.bit_length(), entry, "an integer")
        out: sp.Expr = sp.Integer(value)
    elif isinstance(value, (Fraction, Decimal)):
        if isinstance(value, Decimal) and not value.is_finite():
            raise InputError(f"{entry}: {value} is not a finite number")
        if isinstance(value, Decimal):
            digits, exponent = len(value.as_tuple().digits), value.as_tuple().exponent
            budget.check("max_digits", digits + abs(exponent), entry, "the number of digits of a decimal")
            check_bits(max(digits + exponent, -exponent) * math.log2(10), entry, "a decimal")
        f = Fraction(value)
        check_bits(rational_bits(f), entry, f"the {type(value).__name__}")
        out = sp.Rational(f.numerator, f.denominator)
    elif isinstance(value, numbers.Real) and not isinstance(value, sp.Basic):
        out = _float(float(value), entry, rationalize)
    elif isinstance(value, str):
        out = parse_exact(value, entry, symbols=symbols)
    elif isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr):
            raise InputError(f"{entry}: {value!r} is not a number")
        if value.has(sp.Float):
            if not rationalize:
                raise InexactInputError(f"{entry}: {value} contains a sympy Float; give it exactly "
                                        "or set rationalize=True")
            value = value.xreplace({f: sp.Rational(str(f)) for f in value.atoms(sp.Float)})
        _check_sympy(value, entry)
        out = value
    else:
        raise InputError(f"{entry}: {described(value)} is not an exact number "
                         "(give an int, Fraction, Decimal, a string like '5/4' or '0.1', or a sympy expression)")
    if isinstance(out, sp.Rational):   # finite, algebraic, no symbol: only its size is left to check
        budget.check("max_digits", _digits(out), entry, "the number of digits (about) of a rational in its value")
        return out
    if out.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise InputError(f"{entry}: {described(value)} is not a finite number")
    # what the parser's estimates let through is measured once evaluated: no later conversion
    # to text (Python's limit follows max_digits) meets a longer integer
    budget.check("max_digits", max((_digits(r) for r in out.atoms(sp.Rational)), default=0), entry,
                 "the number of digits (about) of a rational in its value")
    if out.free_symbols and not symbols:
        raise InputError(f"{entry}: symbol(s) {sorted(map(str, out.free_symbols))} are not "
                         "allowed here; give a number")
    if algebraic and not out.free_symbols and out.is_algebraic is False:
        raise InputError(f"{entry}: {out} is transcendental; symkf needs algebraic numbers "
                         "to decide exactly")
    return out


def _digits(r: sp.Rational) -> int:
    return math.ceil(max(int(r.p).bit_length(), int(r.q).bit_length()) * math.log10(2))


def substitution(values: Mapping[Any, Any], entry: str, known: Collection[sp.Symbol] = ()) -> dict[sp.Symbol, sp.Expr]:
    """``values`` of a ``subs`` call with symbol keys (a Symbol, or a name: the symbol of that name
    among ``known``, else a positive symbol) and exact values (strings through :func:`parse_exact`):
    nothing reaches sympy's own string parsing."""
    if not isinstance(values, Mapping):
        raise InputError(f"{entry}: expected a mapping symbol -> value, got {type(values).__name__}")
    out = {}
    for key, value in values.items():
        if isinstance(key, str):
            if not _SYMBOL.match(key) or key in RESERVED:
                raise InputError(f"{entry}: {key!r} is not a symbol name")
            key = next((s for s in known if s.name == key), sp.Symbol(key, positive=True))
        elif not isinstance(key, sp.Symbol):
            raise InputError(f"{entry}: key {key!r} is not a symbol")
        out[key] = to_exact(value, f"{entry}[{key}]", symbols=True)
    return out


def to_exact_matrix(rows: Any, entry: str, *, rationalize: bool | str = False,
                    shape: tuple[int | None, int | None] = (None, None),
                    vector: str | None = None) -> sp.ImmutableMatrix:
    """Return a rectangular exact matrix; ``shape`` entries that are not None are enforced.

    A flat list or 1-D array is refused, or read as one row when ``vector == "row"`` (a sensor's
    C) and as one column when ``vector == "column"`` (an actuator's B).  Each dimension is
    checked against ``symkf.budget`` (``max_dimension``) before any entry is converted.
    """
    if isinstance(rows, sp.MatrixBase) or hasattr(rows, "tolist"):
        rows = rows.tolist()
    if isinstance(rows, (str, bytes)) or not isinstance(rows, Sequence) or len(rows) == 0:
        raise ShapeError(f"{entry}: expected a non-empty list of rows, got {type(rows).__name__}")
    if vector in ("row", "column") and not any(isinstance(r, Sequence) and not isinstance(r, (str, bytes))
                                               for r in rows):
        rows = [rows] if vector == "row" else [[v] for v in rows]
    budget.check("max_dimension", len(rows), entry, "the number of rows")
    if not all(isinstance(r, Sequence) and not isinstance(r, (str, bytes)) for r in rows):
        raise ShapeError(f"{entry}: expected a list of rows (a list of lists)")
    width = len(rows[0])
    budget.check("max_dimension", width, entry, "the number of columns")
    if width == 0 or any(len(r) != width for r in rows):
        raise ShapeError(f"{entry}: rows have lengths {[len(r) for r in rows]}; "
                         "all rows must have the same non-zero length")
    want_r, want_c = shape
    if want_r is not None and len(rows) != want_r or want_c is not None and width != want_c:
        raise ShapeError(f"{entry}: shape {len(rows)}x{width}, expected "
                         f"{want_r if want_r is not None else 'any'}x{want_c if want_c is not None else 'any'}")
    with rationalization(entry) as record:
        start = len(record.changes)
        pairs = _rotation_pairs(rows, entry, record) if rationalize == "nearby" else {}
        cells = [[pairs[i, j] if (i, j) in pairs else to_exact(v, f"{entry}[{i}][{j}]", rationalize=rationalize)
                  for j, v in enumerate(r)] for i, r in enumerate(rows)]
        if rationalize == "nearby":
            _whole_blocks(cells, entry, record, start)
        M = sp.ImmutableMatrix(cells)
    if not M.is_square:
        cost = field_cost(M)
        check_degree(cost.radical > 1 or cost.atoms > 1, cost.radical * cost.cyclotomic, entry, "its entries' field")
        return M
    # the engine decides each diagonal block of A in the field of its entries; the eigenvalue of a
    # 1x1 block of one trigonometric constant, or of a scaled rotation r R(t), stays in the
    # cyclotomic field Q(zeta_m) with a rational or real modulus; other eigenvalues lie in a
    # generic extension of degree <= the block's size, and a complex one's modulus needs a resultant
    for index in diagonal_blocks(M):
        sub = M.extract(index, index)
        cost = field_cost(sub)
        if cost.radical == 1 and cost.atoms <= 1 and len(index) == 1 and \
                (cost.own < cost.cyclotomic or _unit_multiple(sub[0, 0])):
            check_degree(False, cost.own, entry, f"its entry {_rows(index)}")
        elif cost.radical == 1 and len(index) == 2 and _scaled_rotation(sub):
            check_degree(False, cost.cyclotomic, entry, f"the eigenvalues of its rotation block {_rows(index)}")
        elif sub.is_upper or sub.is_lower:  # the eigenvalues are the diagonal entries, in their field
            check_degree(cost.radical > 1 or cost.atoms > 1, cost.radical * cost.cyclotomic, entry,
                         f"the eigenvalues (the diagonal entries) of its triangular block {_rows(index)}")
        else:
            check_degree(True, cost.radical * cost.cyclotomic * len(index), entry,
                         f"the eigenvalues of its diagonal block {_rows(index)} (entries' field times size {len(index)})")
    return M


def _is_float(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (numbers.Integral, sp.Basic, Fraction, Decimal))


def _rotation_pairs(rows: Sequence[Sequence[Any]], entry: str, record: _Conversions) -> dict[tuple[int, int], sp.Expr]:
    """Entries of float rotation blocks ``[[a, -b], [b, a]]`` (rows and columns ``i, j``) recognised
    jointly as ``r R(t)`` (:func:`_nearby_rotation`), recorded as changes: the sine is never read
    apart from its cosine."""
    out: dict[tuple[int, int], sp.Expr] = {}
    n = len(rows)
    for i in range(n):
        for j in range(i + 1, n):
            if any((p, q) in out for p in (i, j) for q in (i, j)):
                continue
            a, mb, b, d = rows[i][i], rows[i][j], rows[j][i], rows[j][j]
            if not all(_is_float(v) and math.isfinite(v) for v in (a, mb, b, d)) or a != d or mb != -b or b == 0 \
                    or all(Fraction(repr(float(v))) == Fraction(float(v)) for v in (a, b)):
                continue
            found = _nearby_rotation(float(a), float(b))
            if found is None:
                continue
            c, s = found
            how = f"rotation pair (r cos t, r sin t) within {NEARBY_TOLERANCE:g}"
            for (p, q), value, exact in (((i, i), a, c), ((i, j), mb, -s), ((j, i), b, s), ((j, j), d, c)):
                out[p, q] = exact
                record.changes.append((f"{entry}[{p}][{q}]", value, exact, how))
    return out


def _whole_blocks(cells: list[list[sp.Expr]], entry: str, record: _Conversions, start: int) -> None:
    """Never a block half recognised: in each diagonal block of a square matrix (the whole matrix
    otherwise), unless ``"nearby"`` recognised every float that is not exact, or none, its
    recognised floats are read as decimals too, and a note says so (the partial reading is kept in
    ``record.partial`` for the comparison of periods)."""
    where = {}
    for k, (name, value, out, how) in enumerate(record.changes[start:], start):
        i, j = (int(x) for x in name[len(entry) + 1:-1].split("]["))
        if how == "shortest decimal" or out != Fraction(repr(float(value))):   # 0.3 -> 3/10 is neutral
            where[i, j] = (k, value, how != "shortest decimal")
    partial = sp.ImmutableMatrix(cells)
    square = len(cells) == len(cells[0])
    blocks = diagonal_blocks(partial) if square else [list(range(len(cells)))]
    for index in blocks:
        inside = {ij: w for ij, w in where.items() if ij[0] in index and (ij[1] in index or not square)}
        recognised = [ij for ij, w in inside.items() if w[2]]
        if 0 < len(recognised) < len(inside):
            for i, j in recognised:
                k, value, _ = inside[i, j]
                decimal = Fraction(repr(float(value)))
                cells[i][j] = sp.Rational(decimal.numerator, decimal.denominator)
                record.changes[k] = (record.changes[k][0], value, cells[i][j], "shortest decimal")
            record.partial[entry] = partial
            place = f"its diagonal block {_rows(index)}" if square else "its entries"
            record.notes.append(f"{entry}: only {len(recognised)} of the {len(inside)} inexact floats of {place} "
                                "are near constants, so none is taken (a block is read one way): all are read as "
                                "decimals")


def _unit_multiple(v: sp.Expr) -> bool:
    """Whether ``v`` is a rational times a root of unity (``I``, ``exp(p pi I/q)``): its modulus is
    rational, where another complex number of degree d needs a resultant of degree 2 d^2."""
    return all(f is sp.I or isinstance(f, sp.exp) for f in sp.Mul.make_args(v.as_coeff_Mul()[1]) if f != 1)


def _scaled_rotation(M: sp.MatrixBase) -> bool:
    """Whether ``M = [[a, -b], [b, a]]`` with ``a = +-r cos t``, ``b = +-r sin t`` (``r`` rational;
    sympy writes cos(96 pi/97) as -cos(pi/97)): eigenvalues ``a +- i b`` of rational modulus ``|r|``."""
    (r, c), (s, t) = M[0, 0].as_coeff_Mul(), M[1, 0].as_coeff_Mul()
    if M[1, 1] != M[0, 0] or M[0, 1] != -M[1, 0]:
        return False
    return abs(r) == abs(s) and isinstance(c, sp.cos) and isinstance(t, sp.sin) and c.args == t.args


def _rows(index: list[int]) -> str:
    """Rows/columns ``index`` of a diagonal block, 1-based, e.g. ``rows 3-4``."""
    runs = ", ".join(f"{a + 1}" if a == b else f"{a + 1}-{b + 1}" for a, b in _runs(index))
    return f"row{'s' * (len(index) > 1)} {runs}"


def _runs(index: list[int]) -> list[tuple[int, int]]:
    out: list[list[int]] = []
    for i in index:
        if out and out[-1][1] == i - 1:
            out[-1][1] = i
        else:
            out.append([i, i])
    return [(a, b) for a, b in out]


def decimal_matrix(rows: Any, entry: str) -> sp.ImmutableMatrix:
    """``rows`` with every float read as its shortest decimal, silently: the reading that
    ``rationalize="nearby"`` is compared against."""
    token = _ACTIVE.set(_Conversions(entry))
    try:
        return to_exact_matrix(rows, entry, rationalize=True)
    finally:
        _ACTIVE.reset(token)

check_public(globals())
