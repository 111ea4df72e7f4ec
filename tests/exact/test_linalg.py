"""Exact linear algebra (symkf.exact.linalg) over Q and number fields: ranks against the SVD where
it is well conditioned and where it is not, against sympy's DomainMatrix over Q(sqrt 2, sqrt 3);
solve_rows and normal_of against sympy and the nullspace."""


import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from sympy.polys.matrices import DomainMatrix

from symkf.exact.field import NumberField
from symkf.exact.linalg import krylov_rank, rank


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


@settings(max_examples=20)
@given(st.sampled_from([[], [sp.sqrt(2)], [sp.sqrt(2), sp.sqrt(3)], [sp.cos(2 * sp.pi / 7)]]),
       st.integers(1, 5), st.integers(0, 10 ** 6))
def test_solve_rows_against_sympy(gens, n, seed):
    """``solve_rows`` (the regular representation, flint's rational solve): the residual ``G x - b``
    vanishes in K's own arithmetic, and ``x`` agrees with sympy's ``LUsolve`` in floats; entries
    drawn from the field with large rational coefficients."""
    from random import Random

    from symkf.exact.linalg import solve_rows
    rng = Random(seed)
    K = NumberField(gens)

    def draw() -> sp.Expr:
        return sp.Rational(rng.randint(-10 ** 30, 10 ** 30), rng.randint(1, 10 ** 30)) + sum(
            sp.Rational(rng.randint(-9, 9), rng.randint(1, 9)) * g for g in gens)
    G = sp.Matrix(n, n, lambda i, j: draw() if rng.random() < 0.8 else 0) + sp.eye(n) * 10 ** 31
    b = sp.Matrix(n, 1, lambda i, j: draw())
    rows = [[K.convert(v) for v in G.row(i)] for i in range(n)]
    rhs = [K.convert(v) for v in b]
    x = solve_rows(K, rows, rhs)
    assert all((K.dot(r, x) - c).is_zero() for r, c in zip(rows, rhs))
    want = G.evalf(50).LUsolve(b.evalf(50))
    assert all(abs(complex(sp.N(K.to_sympy(a), 30)) - complex(w)) < 1e-20 for a, w in zip(x, want))


@settings(max_examples=25)
@given(st.sampled_from([[], [sp.sqrt(2)], [sp.sqrt(2), sp.sqrt(3)], [sp.cos(2 * sp.pi / 7)]]),
       st.integers(2, 9), st.booleans(), st.integers(0, 10 ** 6))
def test_normal_of_is_the_nullspace_up_to_a_scalar(gens, n, dependent, seed):
    """``normal_of`` (signed maximal minors up to MINORS_MAX columns, an echelon form beyond and
    over Q) against ``nullspace_rows``: orthogonal to every row, parallel to the nullspace's
    vector, and zero exactly when the rows are dependent (the last a combination of two others)."""
    from random import Random

    from symkf.exact.linalg import normal_of, nullspace_rows, rank_rows
    rng = Random(seed)
    K = NumberField(gens)

    def draw() -> sp.Expr:
        if rng.random() < 0.3:
            return sp.Integer(0)
        return sp.Rational(rng.randint(-9, 9), rng.randint(1, 4)) + sum(rng.randint(-3, 3) * g for g in gens)
    rows = [[K.convert(draw()) for _ in range(n)] for _ in range(n - 1)]
    if dependent and n > 2:
        a, b = K.convert(draw()), K.convert(draw())
        rows[-1] = [(K.mul(a, x) + K.mul(b, y)) % K.modulus for x, y in zip(rows[0], rows[1])]
    h = normal_of(K, rows, n)
    assert all(K.dot(r, h).is_zero() for r in rows)
    if rank_rows(K, rows, n) < n - 1:
        assert all(x.is_zero() for x in h)
        return
    (g,) = nullspace_rows(K, rows, n)
    assert any(not x.is_zero() for x in h)
    assert all((K.mul(h[i], g[j]) - K.mul(h[j], g[i])).is_zero() for i in range(n) for j in range(i))


@pytest.mark.parametrize("size", [40, 131])
def test_pivots_by_schur_complements_are_the_pivots(size):
    # schur_positive (halves, flint's certified solve and product) against elimination entry by entry,
    # on balls of the same exact matrices: positive definite, a last pivot negative, a leading minor
    # zero (both leave it open on balls of nonzero radius: None), at and above SCHUR_BLOCK
    import flint

    from symkf.exact.linalg import SCHUR_BLOCK, pivots_positive, schur_positive
    from symkf.exact.algebraic import with_prec
    X = np.random.default_rng(size).normal(size=(size, size))
    A = X @ X.T / size + np.eye(size) / 20
    negative, singular = A.copy(), A.copy()
    negative[-1, -1] -= np.linalg.eigvalsh(A)[-1] * size
    singular[:2, :] = A[0]
    singular[:, :2] = singular[:, :1]
    for M, expected in ((A, True), (negative, False), (singular, None)):
        exact = [[flint.fmpq(int(round(v * 2 ** 40)), 2 ** 40) for v in row] for row in M]
        balls = lambda: [[flint.arb(x) + flint.arb(0, 2.0 ** -200) for x in row] for row in exact]
        assert with_prec(256, lambda: schur_positive(balls())) is expected
        assert with_prec(256, lambda: pivots_positive(balls())) is expected
    assert size <= SCHUR_BLOCK or size > 2 * SCHUR_BLOCK


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(-3, 3), min_size=9, max_size=9), st.lists(st.integers(-3, 3), min_size=9, max_size=9))
def test_field_pivots_decide_positive_definiteness_as_sylvester(a, b):
    """The exact pivots over Q(sqrt 2) (the LMI's last resort, when no certified ball decides a
    pivot's sign: an element of Q(cos 2 pi/401) cancels by 10^500 at 256 bits) against Sylvester's
    leading minors in sympy, on M = X X^T + shift (sometimes singular or indefinite)."""
    from symkf.exact import linalg
    from symkf.exact.field import NumberField
    r2 = sp.sqrt(2)
    X = sp.Matrix(3, 3, [u + v * r2 for u, v in zip(a, b)])
    M = X * X.T - (sum(abs(u) for u in a) % 4) * sp.eye(3)
    K = NumberField([r2])
    want = all(sp.nsimplify(sp.expand(M[:k, :k].det())) > 0 for k in range(1, 4))
    assert linalg._field_pivots_positive(K, [[K.convert(sp.expand(v)) for v in M.row(i)] for i in range(3)]) == want


@pytest.mark.parametrize("A, C, expected", [
    ([[2, 0], [0, 3]], [[1, 1]], 2),                        # distinct eigenvalues, both seen
    ([[2, 0], [0, 2]], [[1, 1]], 1),                        # 2 I: C A = 2 C, one direction only
    ([[1, 1, 0], [0, 1, 0], [0, 0, sp.Rational(1, 2)]], [[0, 1, 0]], 1),   # sees only the chain's end: C A = C
    ([[0, 1, 0], [0, 0, 1], [1, -2, 3]], [[1, 0, 0]], 3),   # companion form: C, CA, CA^2 the unit rows
    # over Q(sqrt 2): C = (sqrt 2, 1) is a left eigenvector of A (C A = (1 + sqrt 2) C), one direction;
    # with C = (1, 0) the rows (1, 0) and (1, 1) are independent
    ([[1, 1], [2, 1]], [[sp.sqrt(2), 1]], 1),
    ([[1, 1], [2, 1]], [[1, 0]], 2),
    ([[sp.sqrt(2), 1], [0, sp.sqrt(2)]], [[0, 1]], 1),     # a Jordan chain seen only at its end
])
def test_krylov_rank_is_the_rank_of_the_stacked_powers(A, C, expected):
    """The rank of col{C, CA, ..., CA^(n-1)} by hand, and as the sympy matrix of the powers gives it."""
    A, C = sp.Matrix(A), sp.Matrix(C)
    assert krylov_rank(A, C) == expected == rank(sp.Matrix.vstack(*[C * A ** k for k in range(A.rows)]))

