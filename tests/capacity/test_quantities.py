"""Transmission capacity, Mahler measure and the critical capacities (symkf.capacity.quantities;
Yang et al., eq. 11, Remark 1, eqs. 16 and 29): values by hand, the Mahler measure against mpmath
and the quadratic formula, its degree capped."""

from __future__ import annotations

import math

import pytest
import sympy as sp
from hypothesis import example, given, settings
from hypothesis import strategies as st

from symkf import IID, GilbertElliott, budget
from symkf.capacity import critical_capacities, individual_capacities, mahler_measure, snr, transmission_capacity
from symkf.errors import AssumptionError, BudgetError

R = sp.Rational


def test_capacity_values_and_remark1():
    loss = IID(["1/4", "1/9"])
    assert sp.simplify(transmission_capacity(loss) - sp.log(6)) == 0
    assert snr(loss) == (3, 8)
    for q, C in zip(snr(loss), individual_capacities(loss)):
        assert sp.simplify(sp.log(1 + q) / 2 - C) == 0            # eq. 11 form = Remark 1 form
    assert transmission_capacity(IID(["0", "1/2"])) == sp.oo
    assert transmission_capacity(IID(["1"])) == 0


def test_capacity_refuses_other_loss_models():
    # one error type per failure (symkf.model.loss.checked): a theorem for Bernoulli losses only
    with pytest.raises(AssumptionError, match="i.i.d.") as info:
        transmission_capacity(GilbertElliott(fail=["1/2"], recover=["1/2"]))
    assert "Yang et al." in str(info.value) and "What applies instead: symkf.stability (exact" in str(info.value)


@pytest.mark.parametrize("A, M", [
    ([[0, -2], [2, 0]], 4), ([[2, 0], [0, R(1, 2)]], 2), ([[R(5, 4), 0], [1, R(11, 10)]], R(11, 8)),
    ([[2, 0], [0, 2]], 4), ([[R(1, 2), 1], [0, R(-1, 3)]], 1), ([[1, 1], [1, 0]], (1 + sp.sqrt(5)) / 2),
    ([[1, 1], [-1, 1]], 2), ([[0, 0], [0, 0]], 1)])
def test_mahler_measure_exact(A, M):
    assert mahler_measure(A) == M


NINTH = sp.Matrix([[0, 0, -1], [1, 0, 3], [0, 1, 0]])   # companion of x^3 - 3x + 1: 2 cos(2 pi j/9), j = 1, 2, 4


def test_mahler_measure_of_some_conjugate_roots():
    """By hand: the roots 2 cos(2 pi/9), 2 cos(8 pi/9) lie outside the unit circle and
    2 cos(4 pi/9) inside; their product is -1, so ``M = 1/(2 cos(4 pi/9))``; a double block squares it."""
    M = 1 / (2 * sp.cos(4 * sp.pi / 9))
    assert mahler_measure(NINTH) == M
    assert mahler_measure(sp.diag(NINTH, NINTH)) == M ** 2
    assert mahler_measure(sp.diag(NINTH, sp.Matrix([[2, 1], [0, 2]]))) == 4 * M


@settings(max_examples=30, deadline=None)
@given(st.integers(3, 6).flatmap(lambda n: st.lists(st.lists(st.integers(-3, 3), min_size=n, max_size=n),
                                                     min_size=n, max_size=n)))
def test_mahler_measure_against_mpmath(rows):
    """The product of conjugate roots (one compound polynomial per minimal polynomial) against
    mpmath's eigenvalues at 60 digits (no shared code: QR iterations on the matrix)."""
    import mpmath
    with mpmath.workdps(60):
        values = mpmath.eig(mpmath.matrix(rows), left=False, right=False)
        expected = mpmath.fprod(max(1, abs(v)) for v in values)
        got = mahler_measure(rows)
        assert abs(mpmath.mpf(got.refine(sp.Rational(1, 10 ** 50)).interval[0].numerator)
                   / got.refine(sp.Rational(1, 10 ** 50)).interval[0].denominator - expected) < mpmath.mpf(10) ** -25


def test_mahler_measure_degree_is_capped():
    """x^3 (x - 5)(x - 6) + 1 is irreducible with two roots outside the unit circle: their
    product has degree C(5, 2) = 10."""
    A = sp.Matrix([[0, 0, 0, 0, -1], [1, 0, 0, 0, 0], [0, 1, 0, 0, 0], [0, 0, 1, 0, -30], [0, 0, 0, 1, 11]])
    assert mahler_measure(A).minpoly.degree() == 10
    with budget.limits(max_compound_degree=9), pytest.raises(BudgetError, match="max_compound_degree"):
        mahler_measure(A)


def test_critical_capacities():
    assert critical_capacities([[0, -2], [2, 0]]) == (sp.log(2), sp.log(4))
    assert critical_capacities([[0, 1], [0, 0]])[0] == -sp.oo


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(-3, 3), min_size=4, max_size=4))
@example([3, 2, -2, -1])   # a random run: a double eigenvalue 1, which LAPACK returns as 1 +- 2e-8
def test_mahler_measure_matches_the_quadratic_formula(entries):
    """Against the eigenvalues ``(t +- sqrt(t^2 - 4 det)) / 2`` from the exact integer discriminant
    (complex pairs: ``|lambda|^2 = det``), not LAPACK's, which at a Jordan block err by sqrt(eps)."""
    a, b, c, d = entries
    t, det = a + d, a * d - b * c
    disc = t * t - 4 * det
    moduli = [math.sqrt(det)] * 2 if disc < 0 else [abs(t + s * math.sqrt(disc)) / 2 for s in (1, -1)]
    expected = math.prod(max(1.0, m) for m in moduli)
    assert float(mahler_measure([entries[:2], entries[2:]])) == pytest.approx(expected, rel=1e-12)
