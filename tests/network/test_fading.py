"""Link success probabilities from fading channels (symkf.network.fading; Quevedo et al., Sec. III,
eqs. 7-10, footnote 5) against closed forms: Rayleigh thresholds, retransmissions, saturated
channel inversion, Nakagami and Rician gains, a user's gain; the quadrature's error bound widens at
a jump it is not told about."""

from __future__ import annotations

import mpmath
import pytest
import sympy as sp

from symkf.errors import InputError
from symkf.network import Nakagami, Rayleigh, Rician, UserGain, success_probability, threshold_success

R = sp.Rational


def _close(sp_value, exact: float, tol: float = 1e-12) -> bool:
    return sp_value.lower <= sp.nsimplify(exact + tol) and sp_value.upper >= sp.nsimplify(exact - tol)


def test_rayleigh_threshold_closed_form():
    # Pr{h u >= tau} = exp(-tau / (u mean)) for an exponential power gain
    r = success_probability(Rayleigh(2), threshold_success(3), kappa=R(3, 2), breakpoints=[2])
    assert abs(float(r.value) - float(mpmath.exp(-1))) < 1e-18
    assert r.lower <= r.value <= r.upper and r.upper - r.lower < R(1, 10 ** 15)


@pytest.mark.full
def test_unannounced_jump_widens_the_error():
    # a jump the quadrature is not told about widens the reported error instead of hiding it
    blind = success_probability(Rayleigh(2), threshold_success(3), kappa=R(3, 2), breakpoints=[1])
    assert blind.quadrature_error > 1e-4 and _close(blind, float(mpmath.exp(-1)))


def test_retransmissions_closed_form():
    # f(s) = 1 - exp(-s), Rayleigh mean mu: E[1 - exp(-L h)] = 1 - 1/(1 + L mu)
    f = lambda s, b: 1 - mpmath.exp(-s)  # noqa: E731
    for L in (1, 2, 3):
        r = success_probability(Rayleigh(3), f, attempts=L)
        assert abs(float(r.value) - (1 - 1 / (1 + 3 * L))) < 1e-15


def test_saturated_channel_inversion():
    # u = min(K/h, umax), f = 1{s >= tau} with K >= tau: success iff h >= tau / umax
    K, umax, tau = 4, 2, 3
    r = success_probability(Rayleigh(1), threshold_success(tau), kappa=lambda h: min(K / h, umax) if h else umax,
                            breakpoints=[R(3, 2), 2])
    assert abs(float(r.value) - float(mpmath.exp(-R(3, 2)))) < 1e-15


def test_nakagami_and_rician_against_closed_forms():
    scipy_stats = pytest.importorskip("scipy.stats")
    r = success_probability(Nakagami(2, 3), threshold_success(1), breakpoints=[1])
    assert abs(float(r.value) - float(mpmath.gammainc(2, R(2, 3), mpmath.inf, regularized=True))) < 1e-15
    K, w, tau = 3, 2, 1
    r = success_probability(Rician(K, w), threshold_success(tau), breakpoints=[tau])
    assert abs(float(r.value) - scipy_stats.ncx2.sf(2 * (K + 1) * tau / w, 2, 2 * K)) < 1e-12
    # Rician with K = 0 is Rayleigh
    r0 = success_probability(Rician(0, 2), threshold_success(1), breakpoints=[1])
    assert abs(float(r0.value) - float(mpmath.exp(-R(1, 2)))) < 1e-15


def test_user_gain_and_bad_f():
    g = UserGain(lambda h: mpmath.exp(-h), lambda H: mpmath.exp(-H))
    r = success_probability(g, threshold_success(1), breakpoints=[1])
    assert abs(float(r.value) - float(mpmath.exp(-1))) < 1e-15
    with pytest.raises(InputError, match=r"\[0, 1\]"):
        success_probability(g, lambda s, b: 2)
    with pytest.raises(InputError, match="attempts"):
        success_probability(g, threshold_success(1), attempts=0)
