"""The exact engine per diagonal block of A (issue 18): eigenvalues, PBH and the modal form in
each block's own field, and the moduli of eigenvalues without resultants where they are known."""

import flint
import pytest
import sympy as sp

import symkf as sk
from conftest import rotation
from symkf.errors import UnobservableError
from symkf.exact.spectral import _abs_poly, _resultant_y, _cosine_order, diagonal_blocks, eigen_blocks, eigenvalues
from symkf.exact.algebraic import identify, real_from_ball


def test_diagonal_blocks_are_the_components_of_the_pattern():
    # states 0, 2 coupled, 1 alone, 3 - 4 coupled one way only
    A = sp.Matrix([[1, 0, 2, 0, 0], [0, 3, 0, 0, 0], [4, 0, 5, 0, 0], [0, 0, 0, 6, 7], [0, 0, 0, 0, 8]])
    assert sorted(diagonal_blocks(A)) == [[0, 2], [1], [3, 4]]


def test_four_field_stack_is_the_minimum_over_its_blocks():
    """Rotations by 2pi/5, 2pi/7, pi/4, pi/6 scaled 2..5 (moduli differ, so each block is its own
    eigen-block): i.i.d. stability needs every block's margin below 1, so the stack's critical
    common loss rate is the least of the four one-block systems' (sensor rows restricted to the
    block's columns), each decided by the unchanged single-block path."""
    angles = [2 * sp.pi / 5, 2 * sp.pi / 7, sp.pi / 4, sp.pi / 6]
    rows = [[1, 0, -2, 1, 0, 2, 1, -1], [0, 1, 1, 0, 2, -1, 0, 1], [1, 1, 0, 0, 1, 0, -1, 2]]
    A = sp.diag(*[rotation(a, k + 2) for k, a in enumerate(angles)])
    S = sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows])
    parts = [sk.critical_loss_rate(sk.System(A=rotation(a, k + 2), sensors=[
        sk.Sensor(C=[r[2 * k:2 * k + 2]]) for r in rows if any(r[2 * k:2 * k + 2])])).exact
        for k, a in enumerate(angles)]
    assert sk.critical_loss_rate(S).exact == min(parts, key=lambda v: float(v))


def test_an_eigenvalue_of_two_blocks_is_tested_jointly():
    """diag(R, R), R = 2R(pi/3): each eigenvalue is in both blocks (multiplicity 2).  The sensor
    [1, 0, 1, 0] sees each block's eigenvectors, but not v = (u, -u) for an eigenvector u of R:
    C v = u_1 - u_1 = 0, so (A, C) is not detectable (|lambda| = 2).  Two sensors [1, 0, 0, 0] and
    [0, 0, 1, 0] see every eigenvector (u_1 != 0 for both eigenvectors of a rotation)."""
    R = rotation(sp.pi / 3, 2)
    A = sp.diag(R, R)
    assert sorted(e.multiplicity for e in eigenvalues(A)) == [2, 2]
    with pytest.raises(UnobservableError, match="not seen by any sensor"):
        sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0, 1, 0]])])
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0, 0, 0]]), sk.Sensor(C=[[0, 0, 1, 0]])])
    assert S.observable


@pytest.mark.parametrize("A, modulus", [
    ([[-3]], 3),                                  # real: |lambda| = -lambda
    ([["cos(pi/7)"]], sp.cos(sp.pi / 7)),         # real, degree 3
    ([[1, -1], [1, 1]], sp.sqrt(2)),             # 1 +- i: lambda conj(lambda) = 2
    ([[1, -2], [1, 1]], sp.sqrt(3)),             # 1 +- i sqrt 2: 3
    ([[0, 0, 2], [1, 0, 0], [0, 1, 0]], sp.cbrt(2)),  # x^3 - 2: |lambda|^2 = 2^(2/3) irrational: resultant
])
def test_moduli_agree_with_the_resultant(A, modulus):
    """Each eigenvalue's modulus (fast path or not) is the root of the resultant Res_y(f(y),
    y^d f(z^2/y)) that the ball |lambda| picks, as of the power-sum polynomial spectral._abs_poly,
    and equals the value derived by hand."""
    for ev in eigenvalues(A):
        f = tuple(int(c) for c in ev.minpoly.coeffs())
        d = len(f) - 1
        resultant = _resultant_y(f, {(d - k, 2 * k): c for k, c in enumerate(f) if c})
        ball = lambda prec: flint.acb(abs(ev.ball(prec)))  # noqa: E731
        poly, idx = identify(resultant, ball, "modulus")
        assert identify(_abs_poly(f), ball, "modulus") == (poly, idx)
        assert ev.modulus == real_from_ball(poly, idx)
        if abs(complex(ev.ball(64).mid())) > 1e-9 and abs(abs(complex(ev.ball(64).mid())) - float(modulus)) < 1e-9:
            assert ev.modulus == modulus


def test_rotation_by_2pi_97_has_modulus_2():
    (block,) = eigen_blocks(rotation(2 * sp.pi / 97, 2))
    assert block.modulus == 2 and block.period == 97


def test_cosine_order():
    """2 cos(2 pi/7) has minimal polynomial x^3 + x^2 - 2x - 1, so cos(2 pi/7) has 8x^3 + 4x^2 - 4x - 1
    (m = 7); the roots +-sqrt 2 of x^2 - 2 exceed 1, no cosines; 2x^2 - 1 has the roots
    +-cos(pi/4) = cos(2 pi k/8), k = 1, 3 (m = 8)."""
    assert _cosine_order(flint.fmpz_poly([-1, -4, 4, 8])) == 7
    assert _cosine_order(flint.fmpz_poly([-2, 0, 1])) == 0
    assert _cosine_order(flint.fmpz_poly([-1, 0, 2])) == 8


@pytest.mark.full
def test_rotations_in_three_cyclotomic_fields_critical_loss_rate():
    """diag(2R(2 pi/5), 2R(2 pi/7), 2R(2 pi/9)): one eigen-block of modulus 2, period 315, two
    sensors whose rows are parallel on the 2R(2 pi/9) coordinates.  A normal h on those coordinates
    has c_j A^k h = 2^k c_j^(9) R^k h^(9) = 0 at one residue k mod 9 (9 is odd: the angles 2 pi k / 9
    are distinct mod pi) for both sensors: 35 + 35 = 70 of the 630 elements.  With that heaviest
    weight the critical common loss rate is 2^(-2 * 315 / (630 - 70)) = 2^(-9/8); the screen without
    windows (9.3e9 incidences, its cap raised) gave the same in 3660 CPU-s."""
    A = sp.diag(*(rotation(2 * sp.pi / q, 2) for q in (5, 7, 9)))
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[2, 1, 0, -1, -1, -2]]), sk.Sensor(C=[[-2, -2, -2, 2, 1, 2]])])
    assert sp.simplify(sk.critical_loss_rate(S).exact - 2 ** sp.Rational(-9, 8)) == 0
