"""Exact input through the one safe parser (symkf.exact.numbers): what it reads and what it refuses.

Strings of its grammar parse to the value sympy gives the same expression built from trusted
objects; any other string is an InputError.  Numbers whose evaluation would hang or take
gigabytes (huge exponents, angle denominators, nesting, degrees, digits, bit sizes) are refused
before they are evaluated, naming the cap and the option that raises it; floats are taken only
when their binary value is what they print as, otherwise refused naming the strings to pass.
Cases that once ran away run in a forked child under hard limits (conftest.limited)."""

from __future__ import annotations

import time
import warnings
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf import budget, cli
from symkf.errors import BudgetError, InexactInputError, InputError
from symkf.exact.numbers import expr_bits, parse_exact, to_exact

from conftest import limited, system_file

#: strings of the grammar, built from its pieces, each with the value sympy gives the same
#: expression built from trusted sympy objects (no string reaches sympy's own parser)
_ATOMS = st.one_of(st.integers(0, 10 ** 6).map(lambda k: (str(k), sp.Integer(k))),
                   st.sampled_from([("0.5", sp.Rational(1, 2)), ("1e-3", sp.Rational(1, 1000)),
                                    ("2.25", sp.Rational(9, 4)), (".75", sp.Rational(3, 4)), ("pi", sp.pi), ("I", sp.I)]),
                   st.fractions(min_value=-100, max_value=100, max_denominator=50).map(
                       lambda f: (f"({f})", sp.Rational(f.numerator, f.denominator))))
_OPS = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
        "/": lambda a, b: a / b if b != 0 else sp.zoo}


def _grow(children):
    return st.one_of(
        st.tuples(children, st.sampled_from(list(_OPS)), children).map(
            lambda t: (f"({t[0][0]}{t[1]}{t[2][0]})", _OPS[t[1]](t[0][1], t[2][1]))),
        children.map(lambda c: (f"sqrt({c[0]})", sp.sqrt(c[1]))),
        st.tuples(children, st.integers(-3, 3)).map(
            lambda t: (f"({t[0][0]})^{t[1]}", t[0][1] ** t[1] if t[0][1] != 0 or t[1] >= 0 else sp.zoo)),
        st.tuples(st.integers(-12, 12), st.integers(1, 12), st.sampled_from(["cos", "sin"])).map(
            lambda t: (f"{t[2]}({t[0]}*pi/{t[1]})", getattr(sp, t[2])(t[0] * sp.pi / t[1]))),
        st.tuples(st.integers(-12, 12), st.integers(1, 12)).map(
            lambda t: (f"exp({t[0]}*pi*I/{t[1]})", sp.exp(t[0] * sp.pi * sp.I / t[1]))))


GRAMMAR = st.recursive(_ATOMS, _grow, max_leaves=6)


@settings(max_examples=150, deadline=None)
@given(GRAMMAR)
def test_grammar_strings_parse_exactly_or_are_refused_cleanly(case):
    """Strings of the grammar give the same value as sympy's own evaluation of the same
    (trusted) expression, or a clear refusal: a budget cap or division by zero."""
    text, trusted = case
    try:
        value = parse_exact(text, "x")
    except BudgetError:
        return
    except InputError as exc:
        assert "division by zero" in str(exc) or "exponent" in str(exc), exc
        return
    if trusted.has(sp.zoo, sp.nan):
        return
    assert sp.simplify(value - trusted) == 0 or abs(complex(sp.N(value - trusted, 30))) < 1e-25


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("0123456789.+-*/^()eEjIpisqrtcoxn_,[]{}'\"=<>!@#$%&|~;: \\\n")),
               max_size=40))
def test_strings_outside_the_grammar_are_input_errors(text):
    """Any string: an exact value or InputError, nothing else escapes."""
    try:
        value = parse_exact(text, "x", symbols=True)
    except InputError:
        return
    assert isinstance(value, sp.Expr) and not value.has(sp.Float)


# -- caps on what a number may cost, checked before it is evaluated ---------------------------

@pytest.mark.parametrize("text, cap", [
    ("exp(2*pi*I/99991)", "max_angle_denominator"),
    ("sqrt(" * 20 + "2" + ")" * 20, "max_nesting"),
    ("root(2, 99999)", "max_degree"),
    ("root(2, 10**12)", "max_degree"),
    ("cos(pi/1000000007)", "max_angle_denominator"),
    ("+".join(f"sqrt({p})" for p in (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37)), "max_degree"),
    ("9^9^9", "max_exponent"),
    ("1e999999", "max_digits"),
])
def test_pathological_numbers_are_refused_at_once_naming_the_option(text, cap):
    """Each of these ran past 85 CPU-s, to gigabytes, or aborted the interpreter inside FLINT."""
    for call in (lambda: sk.IID([text]), lambda: sk.System(A=[[text]], sensors=[sk.Sensor(C=[[1]])])):
        with pytest.raises(BudgetError, match=budget.OPTIONS[cap]):
            call()


def test_long_number_text_is_refused_naming_the_cap_and_its_option():
    """"1+1+...+1" with 501 ones is 1001 characters: above max_number_length (1000) before it is
    parsed; with the cap raised it parses to 501."""
    text = "+".join(["1"] * 501)
    with pytest.raises(BudgetError, match=r"x: the length of the number's text \(characters\) is 1001, "
                                          r"above the cap 1000; .*max_number_length=.*--max-number-length"):
        parse_exact(text, "x")
    with budget.limits(max_number_length=1001):
        assert parse_exact(text, "x") == 501


def test_sympy_input_is_budgeted_too():
    with pytest.raises(BudgetError, match="--max-angle-denominator"):
        sk.System(A=[[sp.cos(sp.pi / 1000000007)]], sensors=[sk.Sensor(C=[[1]])])


def test_not_algebraic_loss_is_an_input_error():
    """cos(pi*sqrt(2)) is transcendental: refused by the parser, in a loss as in A."""
    for call in (lambda: sk.IID(["cos(pi*sqrt(2))"]), lambda: sk.System(A=[["cos(pi*sqrt(2))"]], sensors=[sk.Sensor(C=[[1]])])):
        with pytest.raises(InputError, match="rational multiple of pi"):
            call()


@pytest.mark.parametrize("value", ["9^9^9", "2**(10**6)", "(10**999)**2", 10 ** 1200])
def test_oversized_numbers_refused_before_evaluation(value):
    with pytest.raises(sk.SymkfError, match=r"A\[0\]\[0\]: .* above the cap \d+; raise it with"):
        sk.System(A=[[value]], sensors=[sk.Sensor(C=[[1]])])


HUGE_ENTRIES = ["1e-400", "(1+10**-999)**10000", "2*cos(pi/180)**9999", "2**-1074"]


def _rotation_file(tmp_path, entry: str):
    path = tmp_path / "rot.toml"
    path.write_text(f'[system]\nA = [["{entry}", "-2"], ["2", "{entry}"]]\n[[sensors]]\nC = [["1", "1"]]\n'
                    '[loss]\nkind = "iid"\nloss = ["1/2"]\n')
    return path


@pytest.mark.parametrize("entry", HUGE_ENTRIES)
def test_entries_of_huge_bit_size_refused_at_once_naming_file_and_cap(tmp_path, entry):
    for path in (system_file(tmp_path, entry), _rotation_file(tmp_path, entry)):
        code, err = limited(cli.main, ["critical", str(path)])
        assert code == 2 and err.count("\n") == 1, err
        assert str(path) in err and "--max-bits" in err and "bit size" in err, err


def test_a_loss_of_huge_bit_size_is_refused(tmp_path):
    path = system_file(tmp_path, "2", loss="(1-10**-999)**10000")
    code, err = limited(cli.main, ["analyze", str(path)])
    assert code == 2 and str(path) in err and "--max-bits" in err, err
    with pytest.raises(BudgetError, match="--max-bits"):
        sk.IID(["(1-10**-999)**10000"])


@pytest.mark.parametrize("value", [Fraction(1, 10 ** 400), Decimal("1e-400"), 2 ** 1074, sp.Rational(1, 2 ** 1074),
                                   sp.Pow(sp.Rational(11, 10), 10 ** 4, evaluate=False), sp.cos(sp.pi / 180) ** 9999,
                                   1e-300])
def test_every_input_form_is_measured(value):
    """Fractions, Decimals, ints, the shortest decimal of a float and sympy numbers given directly
    meet the same cap (an unevaluated sympy power is bounded, never built)."""
    with pytest.raises(BudgetError, match=r"A\[0\]\[0\]: the bit size .* above the cap 768"):
        sk.System(A=[[value]], sensors=[sk.Sensor(C=[[1]])], rationalize=True)


def test_height_bounds_follow_the_weil_height_rules():
    """Exact for rationals, |p/q| h(x) for powers, sums add one bit, trigonometric constants 2."""
    assert expr_bits(sp.Rational(3, 1024)) == 10
    assert expr_bits(sp.Pow(2, -1074, evaluate=False)) == 1074
    assert expr_bits(sp.sqrt(2)) == 0.5
    assert expr_bits(sp.cos(sp.pi / 180) ** 10) == 20
    with pytest.raises(BudgetError, match="is 1074, above the cap 768"):
        parse_exact("2**-1074", "x")
    with budget.limits(max_bits=2000):            # raised, the number is served
        assert parse_exact("2**-1074", "x") == sp.Rational(1, 2 ** 1074)


def test_sizes_under_the_cap_still_run():
    """A rotation block with an entry 10^-200 (665 bits, under the cap): decided exactly."""
    S = sk.System(A=[["1e-200", -2], [2, "1e-200"]], sensors=[sk.Sensor(C=[[1, 1]])])
    assert not sk.stability(S, sk.IID(["1/2"])).stable


# -- floats: exact when their binary value is what they print as -------------------------------

R = sp.Rational


def test_numpy_float64_refused_naming_entry_and_alternatives():
    """np.float64(0.1) was a raw ValueError ('Invalid literal for Fraction: np.float64(0.1)')."""
    with pytest.raises(InexactInputError) as info:
        sk.IID([np.float64(0.1)])
    text = str(info.value)
    assert text.startswith("loss[0]: the float 0.1 is not exact")
    assert "'0.1'" in text and "'1/10'" in text and "IID(..., rationalize=...)" in text and "'nearby'" in text


def test_integral_and_dyadic_numpy_floats_are_exact():
    """np.diag([2, -1.5, .5]): 2.0, -1.5 and 0.5 are binary floats whose value is exactly the
    decimal they print as, so nothing is guessed."""
    S = sk.System(A=np.diag([2, -1.5, .5]), sensors=[sk.Sensor(C=np.ones((1, 3)))])
    assert S.A == sp.diag(2, R(-3, 2), R(1, 2))
    assert to_exact(np.int64(7), "x") == 7 and to_exact(np.float32(0.25), "x") == R(1, 4)


@pytest.mark.parametrize("text, value", [("0.0625", R(1, 16)), ("0.1", R(1, 10)), ("-1.5e-2", R(-3, 200)),
                                         (".5", R(1, 2)), ("2.", 2)])
def test_decimal_text_is_exact(text, value):
    assert to_exact(text, "x") == value


def test_zeros_and_exact_floats_are_not_reported():
    """rationalize=True once warned for every entry, zeros included; exact floats are not changes,
    so nothing is reported."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sk.System(np.array([[0.0, -2.0], [2.0, 0.0]]), [sk.Sensor(C=[[1.0, 0.0]])], rationalize=True)
    assert caught == []


def test_inexact_float_message_is_short():
    """5e-324 is 2^-1074: its fraction has 752 digits, once printed twice in the message; now the
    entry, the float, its binary value as a power of two and the string to pass instead."""
    from fractions import Fraction
    with pytest.raises(InexactInputError) as info:
        sk.IID([5e-324])
    text = str(info.value)
    assert text.startswith("loss[0]: the float 5e-324 is not exact (its binary value is 2^-1074); "
                           "give the string '5e-324',") and len(text) < 300, text
    assert Fraction(5e-324) == Fraction(1, 2 ** 1074)
    with pytest.raises(InexactInputError, match=r"A\[0\]\[0\]: .* is 1681218273811815 \* 2\^946\)"):
        sk.System(A=[[1e300]], sensors=[sk.Sensor(C=[[1]])])
    assert Fraction(1e300) == 1681218273811815 * 2 ** 946
    with pytest.raises(InexactInputError, match=r"3602879701896397/36028797018963968\); give the string '0.1' or '1/10'"):
        sk.IID([0.1])


@pytest.mark.parametrize("text", ["ｓｑｒｔ(2)", "Ⅰ", "1/２", "sqrt(2)\u200b"])
def test_lookalike_unicode_is_refused_not_normalised(text):
    with pytest.raises(InputError, match="is not ASCII"):
        parse_exact(text, "x")


@pytest.mark.parametrize("make, cap", [
    (lambda: sk.IID([sum(sp.sqrt(p) for p in [2, 3, 5, 7, 11, 13, 17, 19, 23, 29]) / 1000, "1/10"]), "max-degree"),
    (lambda: sk.IID([sp.Pow(10, 10 ** 10, evaluate=False), "1/10"]), "max-bits"),
    (lambda: sk.IID([2 ** sp.Rational(1, 10 ** 9) / 2, "1/10"]), "max-degree"),
    (lambda: sk.System(A=[[sp.sqrt(2 + sp.sqrt(2 + sp.sqrt(2 + sp.sqrt(2 + sp.sqrt(2)))))]], sensors=[sk.Sensor(C=[[1]])]),
     "max-nesting"),
    (lambda: sk.AlgebraicNumber.from_expr(sp.cos(sp.pi / 10 ** 9)), "max-angle-denominator"),
    (lambda: sk.AlgebraicNumber.from_expr(sp.Pow(10, 10 ** 10, evaluate=False)), "max-bits"),
    (lambda: sk.AlgebraicNumber.from_expr(sp.Rational(1, 16)) == sp.cos(sp.pi / 10 ** 9), "max-angle-denominator"),
    (lambda: sk.AlgebraicNumber.from_expr(sp.Rational(1, 16)) < sp.cos(sp.pi / 10 ** 9), "max-angle-denominator"),
])
def test_a_sympy_object_is_priced_like_its_text(make, cap):
    # each hung for minutes in sympy or aborted the process in flint; the same value as a string was refused
    start = time.process_time()
    with pytest.raises(sk.SymkfError, match=f"--{cap}"):
        make()
    assert time.process_time() - start < 1


@pytest.mark.parametrize("expr, bound", [
    (sp.Rational(3, 7), 1),
    (2 ** sp.Rational(2, 9) * 3 ** sp.Rational(7, 9), 9),                 # (2^2 3^7)^(1/9)
    (2 ** sp.Rational(1, 6) * 3 ** sp.Rational(1, 4), 12),                # lcm(6, 4): its 12th power is rational
    (sp.sqrt(2) + sp.sqrt(3), 4),                                         # a sum: the product of its terms'
    (sum(sp.sqrt(p) for p in [2, 3, 5, 7, 11, 13, 17, 19, 23, 29]), 1024),
    (sp.sqrt(2 + sp.sqrt(3)), 4),                                         # nested: 2 x 2
    (sp.cos(sp.pi / 5) * sp.I, 4),                                        # sympy's (1 + sqrt 5)/4 times I: 2 x 2
    (sp.cos(sp.pi / 7) + sp.I, 24),                                       # phi(28) x 2
    (sp.pi + 1, None),
])
def test_the_degree_bound_of_a_number_by_hand(expr, bound):
    from symkf.exact.numbers import radical_degree
    assert radical_degree(expr) == bound
