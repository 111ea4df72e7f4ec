"""Inputs that mean what users write (issue 15, item 2): one test per bullet."""

from __future__ import annotations

import warnings
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.io import files
from symkf.errors import InexactInputError, InputError
from symkf.exact.numbers import NEARBY_TOLERANCE, to_exact

R = sp.Rational


def rotation(scale: float, angle: float) -> np.ndarray:
    return scale * np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])


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


def test_one_dimensional_numpy_C_is_a_row():
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=np.array([1, 0]))])
    assert S.sensors[0].C == sp.Matrix([[1, 0]])
    assert sk.critical_loss_rate(S) == R(1, 16)  # 2R(pi/2), C = [1 0]: 1/16 (issue 15)


@pytest.mark.parametrize("text, value", [("0.0625", R(1, 16)), ("0.1", R(1, 10)), ("-1.5e-2", R(-3, 200)),
                                         (".5", R(1, 2)), ("2.", 2)])
def test_decimal_text_is_exact(text, value):
    assert to_exact(text, "x") == value


def test_toml_decimal_is_exact(tmp_path):
    """tomllib reads 0.1 with parse_float=Decimal: exactly 1/10, no float in between."""
    path = tmp_path / "s.toml"
    path.write_text('[system]\nA = [[0, -2], [2, 0]]\n[[sensors]]\nC = [[1, 0]]\n[loss]\nkind = "iid"\nloss = [0.1]\n')
    system, loss = files.load(path)
    assert loss.loss == (R(1, 10),)
    assert to_exact(Decimal("0.1"), "x") == R(1, 10) and to_exact(Fraction(1, 10), "x") == R(1, 10)


@pytest.mark.parametrize("build", [
    lambda r: sk.IID([0.1, 0.2], rationalize=r),
    lambda r: sk.GilbertElliott([0.1], [0.3], rationalize=r),
    lambda r: sk.MarkovLoss({(1,): {(1,): 0.9, (0,): 0.1}, (0,): {(1,): 0.3, (0,): 0.7}}, rationalize=r),
])
def test_rationalize_exists_on_every_loss_constructor(build):
    """The refusal names rationalize; every loss constructor takes it (it was a TypeError)."""
    with pytest.raises(InexactInputError, match="rationalize"):
        build(False)
    with pytest.warns(UserWarning, match="shortest decimal") as record:
        model = build(True)
    assert len(record) == 1 and model.chain.P.has(sp.Float) is False


def test_rationalize_iid_gives_the_decimals():
    with pytest.warns(UserWarning):
        assert sk.IID([0.1, 0.25], rationalize=True).loss == (R(1, 10), R(1, 4))


def test_nearby_constants_recognise_a_float_rotation_with_one_warning():
    """1.5 R(pi/6) in float64: entries 1.299038105676658 = 3 sqrt(3)/4 and 0.7499999999999999 = 3/4
    within 1e-12.  With the plain decimals the block is aperiodic (critical rate 1/alpha^2 =
    4/9 = 0.4444, the jump of issue 15); recognised, the governing period is 6 and the rate is
    the exact 0.3779 of 1.5 R(pi/6).  ONE warning lists the 4 changes and says the periods differ."""
    A = rotation(1.5, np.pi / 6)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        S = sk.System(A, [sk.Sensor(C=np.array([1.0, 0.0]))], rationalize="nearby")
    assert len(caught) == 1
    message = str(caught[0].message)
    assert "4 float(s) rationalized" in message and "3*sqrt(3)/4" in message
    assert "(6,) with the recognised constants, (None,) with the plain decimals (they DIFFER, so the critical values may too" in message
    exact = sk.System([[R(3, 4) * sp.sqrt(3), R(-3, 4)], [R(3, 4), R(3, 4) * sp.sqrt(3)]], [sk.Sensor(C=[[1, 0]])])
    assert S.A == exact.A
    assert sk.critical_loss_rate(S) == sk.critical_loss_rate(exact)
    assert abs(float(sk.critical_loss_rate(S)) - 0.3779) < 1e-4
    with pytest.warns(UserWarning, match="shortest decimal"):
        plain = sk.System(A, [sk.Sensor(C=[[1, 0]])], rationalize=True)
    assert sk.critical_loss_rate(plain) != sk.critical_loss_rate(S)
    assert abs(float(sk.critical_loss_rate(plain)) - 4 / 9) < 1e-9


def test_nearby_falls_back_to_the_decimal_and_says_so():
    """0.123456789 is no small-denominator multiple of a listed constant within the tolerance."""
    with pytest.warns(UserWarning, match=r"0.123456789 -> 123456789/1000000000 \(shortest decimal\)"):
        assert to_exact(0.123456789, "x", rationalize="nearby") == R(123456789, 10 ** 9)
    assert NEARBY_TOLERANCE == 1e-12


def test_zeros_and_exact_floats_are_not_reported():
    """Issue 15: one warning per entry, zeros included; now exact floats are not changes."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sk.System(np.array([[0.0, -2.0], [2.0, 0.0]]), [sk.Sensor(C=[[1.0, 0.0]])], rationalize=True)
    assert caught == []


def test_an_entry_rational_in_value_but_not_in_form():
    """(1/2 + sqrt 5/2)^2 - sqrt 5/2 + 5/2 is 4: the field of the entries is Q, and the entry is
    read through the field's conversion (a TypeError from sympy's Rational before)."""
    four = "-sqrt(5)/2 + 5/2 + (1/2 + sqrt(5)/2)**2"
    assert [(e.expr, e.multiplicity) for e in sk.eigenvalues([[four, 0], [0, 1]])] == [(4, 1), (1, 1)]
    written = sk.System([[four, 1], [0, 3]], [sk.Sensor([[1, 0]])])
    plain = sk.System([[4, 1], [0, 3]], [sk.Sensor([[1, 0]])])
    assert sk.critical_loss_rate(written) == sk.critical_loss_rate(plain) == sp.Rational(1, 16)


PUBLIC_CALLABLES = sorted(name for name in dir(sk) if not name.startswith("_") and callable(getattr(sk, name))
                          and not isinstance(getattr(sk, name), type(sk)) and name != "SymkfError")


@pytest.mark.parametrize("name", PUBLIC_CALLABLES)
def test_calls_that_do_not_fit_a_signature_are_argument_errors(name):
    # Python's TypeError for a missing, unknown or repeated argument becomes symkf's ArgumentError
    # (still a TypeError), naming the function and the signature it takes
    from symkf.errors import ArgumentError
    fn = getattr(sk, name)
    with pytest.raises(ArgumentError) as unknown:
        fn(not_an_argument_of_any_symkf_function=1)
    assert isinstance(unknown.value, TypeError) and isinstance(unknown.value, sk.SymkfError)
    assert str(unknown.value).startswith(f"{name}(" if not isinstance(fn, type) else f"{name}.__init__(self")


def test_mappings_are_checked_key_by_key_and_value_by_value():
    # a dict argument was checked only for being a mapping: its keys and values reached the
    # function (span_key(basis={'a': 'b'}) raised AttributeError: found by the payload walk)
    import flint
    from symkf.exact.linalg import span_key
    with pytest.raises(InputError, match=r"span_key: argument 'basis' must be a mapping of an int to a list or tuple "
                                         r"of a fmpq_poly, got dict"):
        span_key({"a": "b"})
    with pytest.raises(InputError, match="mapping of an int"):
        span_key({0: ["__import__('os')"]})
    assert span_key({0: [flint.fmpq_poly([1]), flint.fmpq_poly([0, 2])]}) == ((0, ((1, 1), (1, 0, 2))),)
