"""Issue 2: exact input, eigen-blocks, periods, exact ranks (hand-derived values)."""

from fractions import Fraction
from math import gcd

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st
from sympy.polys.matrices import DomainMatrix

import symkf as sk
from symkf.errors import InexactInputError, ShapeError, SymkfError, UnobservableError, NotPositiveDefiniteError
from symkf.exact.algebraic import AlgebraicNumber, sign
from symkf.exact.linalg import rank
from symkf.engine.rows import modal_form, project
from symkf.engine.blocks import block_deficient
from symkf.engine.blocks import block_rows
from symkf.exact.spectral import eigen_blocks


def rotation(alpha, angle):
    c, s = sp.cos(angle), sp.sin(angle)
    return [[alpha * c, -alpha * s], [alpha * s, alpha * c]]


@pytest.mark.parametrize("m,k", [(m, k) for m in range(1, 13) for k in range(m) if gcd(k, m) == 1])
def test_rotation_periods(m, k):
    # eigenvalues 2 exp(+-2 pi i k/m): tau = m, governing period = order of exp(4 pi i k/m)
    (block,) = eigen_blocks(rotation(2, 2 * sp.pi * k / m)) if m > 2 else (None,)
    if m <= 2:  # R(0) = I, R(pi) = -I are 1x1-repeated: one block, scalar
        (block,) = eigen_blocks(rotation(2, 2 * sp.pi * k / m))
        assert block.governing_period == 1 and block.period == m
        return
    assert block.modulus == 2
    assert block.period == m
    assert block.governing_period == m // gcd(m, 2)


def test_diagonal_sign_flip():
    for A in ([[1, 0], [0, -1]], [[2, 0], [0, -2]]):
        (b,) = eigen_blocks(A)
        assert (b.period, b.governing_period) == (2, 2)


def test_aperiodic_rotation_has_proof():
    (b,) = eigen_blocks([["3/5", "-4/5"], ["4/5", "3/5"]])
    assert b.period is None and b.governing_period is None
    assert "25*x**2 + 14*x + 25" in b.proof and "not cyclotomic" in b.proof


def test_seed002_two_blocks():
    blocks = eigen_blocks([["5/4", 0], [1, "11/10"]])
    assert [b.modulus for b in blocks] == [sp.Rational(5, 4), sp.Rational(11, 10)]
    assert all(b.period == 1 and b.governing_period == 1 for b in blocks)


def test_design_example_periods():
    (b,) = eigen_blocks([[0, -2], [2, 0]])
    assert (b.period, b.governing_period) == (4, 2)
    assert set(b.eigenvalues) == {2 * sp.I, -2 * sp.I}


def test_golden_ratio_blocks_and_sign_period():
    hi, lo = eigen_blocks([[1, 1], [1, 0]])
    assert hi.modulus == (1 + sp.sqrt(5)) / 2 and lo.modulus == (sp.sqrt(5) - 1) / 2
    assert (lo.period, lo.governing_period) == (2, 1)  # negative real eigenvalue


def test_modal_form_is_exact():
    A = sp.Matrix(rotation(1, sp.pi / 6))
    (b,) = eigen_blocks(A)
    K, T, diag = modal_form(A, b)
    Ak = K.matrix(A)
    for i in range(2):
        for c in range(2):
            lhs = K.dot(Ak[i], [T[r][c] for r in range(2)])
            assert lhs == K.mul(T[i][c], diag[c])


def test_bad_inputs_raise_named_errors():
    (cv,) = eigen_blocks([[1, 1], [0, 1]])  # constant velocity: one Jordan chain, accepted (issue 14)
    assert cv.defective and cv.members[0].geometric == 1 and cv.members[0].multiplicity == 2
    with pytest.raises(InexactInputError, match=r"A\[0\]\[1\].*'1/10'"):
        sk.System(A=[[1, 0.1], [0, 1]], sensors=[sk.Sensor(C=[[1, 0]])])
    with pytest.raises(ShapeError, match="A: must be square"):
        sk.System(A=[[1, 0, 0], [0, 1, 0]], sensors=[sk.Sensor(C=[[1, 0, 0]])])
    with pytest.raises(UnobservableError, match="eigenvalue 3"):
        sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 0]])])
    with pytest.raises(NotPositiveDefiniteError, match="R"):
        sk.Sensor(C=[[1, 0]], R=[[-1]])
    with pytest.raises(SymkfError, match="unknown name"):
        sk.Sensor(C=[["__import__", 0]])


def test_rationalize_converts_and_warns():
    with pytest.warns(UserWarning, match="1/10"):
        S = sk.System(A=[[1, 0.1], [0, 2]], sensors=[sk.Sensor(C=[[1, 1]])], rationalize=True)
    assert S.A[0, 1] == sp.Rational(1, 10)


def test_exact_inputs_accepted():
    S = sk.System(A=[[Fraction(1, 2), "sqrt(3)/2"], ["-sqrt(3)/2", "cos(pi/3)"]], sensors=[sk.Sensor(C=[[1, 0]])])
    assert S.A[1, 1] == sp.Rational(1, 2)


def test_algebraic_number_comparisons_are_exact():
    a = AlgebraicNumber.from_expr(sp.root(sp.Rational(16, 25), 3))
    assert a.minpoly.as_expr() == 25 * sp.Symbol("x") ** 3 - 16
    lo, hi = a.interval
    assert lo <= Fraction(86177, 100000) <= hi or hi < Fraction(86178, 100000)
    assert a < 1 and a > Fraction(1, 2)
    assert sign(sp.sqrt(2) + sp.sqrt(3) - sp.sqrt(5 + 2 * sp.sqrt(6))) == 0
    assert sign(sp.sqrt(2) - sp.Rational(99, 70)) == -1


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 6), st.integers(1, 5), st.data())
def test_exact_rank_agrees_with_svd_when_well_conditioned(rows, cols, data):
    M = np.array(data.draw(st.lists(st.lists(st.integers(-3, 3), min_size=cols, max_size=cols),
                                    min_size=rows, max_size=rows)))
    s = np.linalg.svd(M.astype(float), compute_uv=False)
    numeric = int((s > 1e-9 * max(1.0, s.max(initial=0))).sum())
    # well conditioned: no singular value in the grey zone
    if np.all((s < 1e-12) | (s > 1e-6)):
        assert rank(sp.Matrix(M.tolist())) == numeric


def test_floating_rank_wrong_exact_rank_right():
    big = 10 ** 16
    M = sp.Matrix([[1, big, 0], [0, 1, 1], [1, big + 1, 1]])  # row 3 = row 1 + row 2: rank 2
    assert rank(M) == 2
    assert np.linalg.matrix_rank(np.array(M.tolist(), dtype=float)) != 2  # SVD says 1


def test_rank_over_number_field():
    c, s = sp.cos(sp.pi / 12), sp.sin(sp.pi / 12)
    A = sp.Matrix([[c, -s], [s, c]])
    rows = sp.Matrix.vstack(sp.Matrix([[1, 0]]), sp.Matrix([[1, 0]]) * A ** 12)
    assert rank(rows) == 1  # A^12 = -I
    assert rank(sp.Matrix.vstack(rows, sp.Matrix([[1, 0]]) * A)) == 2



SQRT_FIELD = sp.QQ.algebraic_field(sp.sqrt(2), sp.sqrt(3))


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 4), st.integers(1, 4), st.integers(0, 3), st.data())
def test_rank_over_number_field_matches_sympy_domain_matrix(cols, free, dependent, data):
    """Elimination in Q(sqrt2 + sqrt3) against sympy's DomainMatrix over the same field, on
    matrices with planted dependencies (rows that are K-combinations of earlier rows)."""
    entry = st.sampled_from([0, 1, -2, sp.sqrt(2), sp.sqrt(3) / 2, 1 + sp.sqrt(6), sp.sqrt(2) - sp.sqrt(3)])
    rows = [[data.draw(entry) for _ in range(cols)] for _ in range(free)]
    for _ in range(dependent):
        coef = [data.draw(entry) for _ in rows]
        rows.append([sp.expand(sum(c * r[j] for c, r in zip(coef, rows))) for j in range(cols)])
    M = sp.Matrix(rows)
    expected = DomainMatrix.from_Matrix(M).convert_to(SQRT_FIELD).rank()
    assert rank(M) == expected


@pytest.mark.parametrize("A,Cs", [
    ([[0, -2], [2, 0]], [[[1, 0]]]),
    (rotation(1, sp.pi / 3), [[[1, 0]], [[1, 1]]]),
    ([["5/4", 0], [1, "11/10"]], [[[1, 1]]]),
])
def test_projection_decides_rank_for_every_pattern(A, Cs):
    """Algorithm 1 with the governing period: O_N^i deficient iff the projected pattern is."""
    import itertools
    S = sk.System(A=A, sensors=[sk.Sensor(C=C) for C in Cs])
    brs = block_rows(S)
    N = max(br.class_period for br in brs) + 2
    for pattern in itertools.product(itertools.product((1, 0), repeat=S.d), repeat=N):
        direct = block_deficient(S, pattern)
        for br, flag in zip(brs, direct):
            proj = project(pattern, br.class_period)
            idx = frozenset(br.elements.index(e) for e in proj)
            assert br.deficient(idx) == flag


@pytest.mark.parametrize("value", ["9^9^9", "2**(10**6)", "(10**999)**2", 10 ** 1200])
def test_oversized_numbers_refused_before_evaluation(value):
    with pytest.raises(sk.SymkfError, match=r"A\[0\]\[0\]: .* above the cap \d+; raise it with"):
        sk.System(A=[[value]], sensors=[sk.Sensor(C=[[1]])])


def test_exact_objects_and_errors_pickle():
    """Plain pickle carries algebraic numbers, systems (without their derived cache), verdicts and
    symkf errors exactly: what process pools, Dask and users' multiprocessing need."""
    import pickle
    from symkf.errors import AssumptionError
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    eps = sk.critical_loss_rate(S)                       # fills S's cache with flint objects
    assert pickle.loads(pickle.dumps(eps)) == sp.Rational(1, 16)
    S2 = pickle.loads(pickle.dumps(S))
    assert S2 == S and S2._cache == {} and sk.critical_loss_rate(S2) == eps
    v = pickle.loads(pickle.dumps(sk.stability(S, sk.IID(["1/20"]))))
    assert v.stable and v.margins[0] == AlgebraicNumber.from_expr(2 * sp.sqrt(5) / 5)
    e = pickle.loads(pickle.dumps(AssumptionError("x", assumption="A1", applies_instead="f")))
    assert (type(e), str(e), e.assumption, e.applies_instead) == \
        (AssumptionError, "A1 fails: x. What applies instead: f", "A1", "f")
