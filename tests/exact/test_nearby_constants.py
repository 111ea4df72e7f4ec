"""rationalize="nearby" (symkf.exact.numbers): floats recognised as the exact constants they round.

Cosines and sines of pi k/m (m <= 60) are recognised, a rotation pair jointly, a block is never
half recognised, one warning lists every change, and a float recognised as nothing falls back to
its shortest decimal and says so."""

from __future__ import annotations

import math
import warnings

import mpmath
import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.exact.numbers import NEARBY_TOLERANCE, _nearby, to_exact

R = sp.Rational

MODULI = (1, 2, sp.Rational(1, 2), sp.Rational(3, 2), sp.Rational(5, 4))


def _scan(moduli, denominators) -> tuple[int, int]:
    """(values, recognised correctly) over a cos(pi k/m), a sin(pi k/m), 0 < k < m coprime."""
    mpmath.mp.dps = 40
    total = right = 0
    for a in moduli:
        for m in denominators:
            for k in range(1, m):
                if math.gcd(k, m) != 1:
                    continue
                for fn, mfn in ((math.cos, mpmath.cos), (math.sin, mpmath.sin)):
                    x = float(a) * fn(math.pi * k / m)
                    truth = mpmath.mpf(a.p if hasattr(a, "p") else a) / (a.q if hasattr(a, "q") else 1) * \
                        mfn(mpmath.pi * k / m)
                    if x == 0 or abs(truth) < 1e-30:
                        continue
                    total += 1
                    got = _nearby(x)
                    right += got is not None and abs(mpmath.mpf(str(sp.N(got, 40))) - truth) < mpmath.mpf(10) ** -30
    return total, right


def test_scan_of_cosines_and_sines_fast_sample():
    total, right = _scan((2, sp.Rational(3, 2)), (7, 14, 36, 60))
    assert total == right == 160


@pytest.mark.full
def test_scan_of_cosines_and_sines_to_60():
    """Every cosine and sine of pi k/m to m <= 60, five moduli (recognition once missed 6 960 of
    them to m <= 36, against 918 recognised)."""
    total, right = _scan(MODULI, range(2, 61))
    assert total == right == 11_005


def _rotation(r: float, t: float) -> np.ndarray:
    return np.array([[r * math.cos(t), -r * math.sin(t)], [r * math.sin(t), r * math.cos(t)]])


def test_float_rotation_by_2pi_over_7_gets_its_exact_critical_rate():
    """Before: cos(2 pi/7) recognised, sin(2 pi/7) not; the mixed matrix gave ~0.25 and called
    the loss 21/100 stable.  The rotation's rate is 2^(-7/3) ~ 0.1984."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        S = sk.System(A=_rotation(2, 2 * math.pi / 7), sensors=[sk.Sensor(C=[[1, 0]])], rationalize="nearby")
    assert sk.critical_loss_rate(S) == sp.Integer(2) ** sp.Rational(-7, 3)
    assert not sk.stability(S, sk.IID(["21/100"])).stable
    assert "(7,) with the recognised constants, (None,) with the plain decimals" in str(caught[0].message)


def test_rotation_by_pi_over_8_is_recognised():
    S = sk.System(A=_rotation(1, math.pi / 8), sensors=[sk.Sensor(C=[[1, 0]])], rationalize="nearby")
    assert S.A == sp.Matrix([[sp.cos(sp.pi / 8), -sp.sin(sp.pi / 8)], [sp.sin(sp.pi / 8), sp.cos(sp.pi / 8)]])
    assert sk.eigen_blocks(S.A)[0].governing_period == 8


def test_a_block_is_never_half_recognised_and_the_warning_names_both_periods():
    A = [[2 * math.cos(2 * math.pi / 7), 0.3], [0.123456789, 1.1]]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]])], rationalize="nearby")
    assert all(e.is_Rational for e in S.A)          # read as decimals, all of it
    message = str(caught[0].message)
    assert "only 1 of the 2 inexact floats of its diagonal block rows 1-2 are near constants" in message
    assert "with the constants recognised in part (not taken)" in message and "with the plain decimals" in message
    # a separate block is read on its own: the 1x1 block 2 cos(2 pi/7) is recognised whole
    S = sk.System(A=[[2 * math.cos(2 * math.pi / 7), 0.0], [0.0, 0.123456789]], sensors=[sk.Sensor(C=[[1, 1]])],
                  rationalize="nearby")
    assert S.A[0, 0] == 2 * sp.cos(2 * sp.pi / 7) and S.A[1, 1] == sp.Rational(123456789, 10 ** 9)


def test_recognition_is_cheap():
    import time
    start = time.process_time()
    for i in range(200):
        _nearby(0.123456789 + i * 1e-7)
    assert time.process_time() - start < 1.0



def float_rotation(scale: float, angle: float) -> np.ndarray:
    return scale * np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])


def test_nearby_constants_recognise_a_float_rotation_with_one_warning():
    """1.5 R(pi/6) in float64: entries 1.299038105676658 = 3 sqrt(3)/4 and 0.7499999999999999 = 3/4
    within 1e-12.  With the plain decimals the block is aperiodic (critical rate 1/alpha^2 =
    4/9 = 0.4444, a jump under rounding); recognised, the governing period is 6 and the rate is
    the exact 0.3779 of 1.5 R(pi/6).  ONE warning lists the 4 changes and says the periods differ."""
    A = float_rotation(1.5, np.pi / 6)
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
