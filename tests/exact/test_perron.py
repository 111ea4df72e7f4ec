"""Exact Perron roots (symkf.exact.perron, used by symkf.engine.rates.perron_root) against independent methods."""

import flint
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf.io import files
from symkf.engine.rates import perron_root, restricted_transfer
from symkf import examples
from symkf.exact import perron, perron_field
from symkf.exact.algebraic import AlgebraicNumber
from symkf.engine.blocks import block_rows
from conftest import ROOT

R = sp.Rational
ENTRIES = [R(0), R(0), R(0), R(1, 2), R(1, 3), R(3, 4), R(1), R(2), R(7, 5)]


def sympy_spectral_radius(M: sp.Matrix) -> sp.Expr:
    """Independent of flint: sympy's own real-root isolation of the characteristic polynomial."""
    roots = sp.Poly(M.charpoly(sp.Symbol("x")).as_expr(), sp.Symbol("x")).real_roots()
    return max(roots, default=sp.Integer(0))


@st.composite
def nonnegative(draw):
    n = draw(st.integers(1, 5))
    return sp.Matrix(n, n, [draw(st.sampled_from(ENTRIES)) for _ in range(n * n)])


@settings(max_examples=150, deadline=None)
@given(nonnegative())
def test_perron_root_agrees_with_sympy_real_roots(M):
    assert sp.simplify(perron_root(M) - sympy_spectral_radius(M)) == 0


@settings(max_examples=60, deadline=None)
@given(nonnegative(), st.integers(1, 3))
def test_duplicated_states_keep_the_root(M, k):
    # lifting every state into k copies that share its row (columns split evenly) is M kron (J/k):
    # its non-zero spectrum is M's, which the row merging must recover
    lifted = sp.kronecker_product(M, sp.ones(k, k) / k)
    assert sp.simplify(perron_root(lifted) - perron_root(M)) == 0


def test_hand_derived_roots():
    # identical rows [a b; a b] = (1,1)^T (a b): non-zero eigenvalue a + b
    assert perron_root(sp.Matrix([[R(1, 3), R(1, 2)], [R(1, 3), R(1, 2)]])) == R(5, 6)
    # block triangular: the larger diagonal block (two components, no cycle between them)
    assert perron_root(sp.Matrix([[R(1, 2), 1], [0, R(3, 4)]])) == R(3, 4)
    # a 2-cycle with weights 1/2 and 1: rho^2 = 1/2
    assert perron_root(sp.Matrix([[0, 1], [R(1, 2), 0]])) == sp.sqrt(2) / 2
    # nilpotent (no cycle): 0
    assert perron_root(sp.Matrix([[0, 1, 5], [0, 0, 1], [0, 0, 0]])) == 0
    rows = {0: {1: flint.fmpq(1)}, 1: {2: flint.fmpq(1)}, 2: {0: flint.fmpq(1, 8)}}  # 3-cycle, product 1/8
    assert perron.perron_root(rows, 3) == R(1, 2)
    assert sorted(map(sorted, perron.strongly_connected_components(rows | {3: {0: flint.fmpq(1)}}, 4))) == [
        [0, 1, 2], [3]]


def test_robot_transfers_against_lapack():
    # Example 4's robot (560 lifted states): every restricted transfer's exact Perron root against
    # the largest eigenvalue modulus from LAPACK on the dense float matrix
    system, loss = files.load(examples.system("network/quevedo-robot"))
    checked = 0
    for br in block_rows(system):
        for H in br.hyperplanes:
            M = restricted_transfer(br, H, loss)
            lapack = max(abs(np.linalg.eigvals(np.array([[float(x) for x in row] for row in M.tolist()]))))
            assert abs(float(perron_root(M)) - lapack) < 1e-9
            checked += 1
    assert checked >= 2


Q = sp.sqrt(2) / 2  # an algebraic probability: the matrix's entries lie in Q(sqrt(2))


def test_algebraic_entries_hand_derived():
    # [[q, q], [q, 0]]: x^2 - q x - 1/2 = 0, x = (q + sqrt(q^2 + 2)) / 2 = (sqrt(2) + sqrt(10)) / 4
    assert sp.simplify(perron_root(sp.Matrix([[Q, Q], [Q, 0]])) - (sp.sqrt(2) + sp.sqrt(10)) / 4) == 0
    # [[0, 1], [1 - q, 0]]: rho = sqrt(1 - q) = 0.541; the norm (x^2 - 1 + q)(x^2 - 1 - q) also has the
    # conjugate's root sqrt(1 + q) = 1.307, which is not an eigenvalue and must not be taken
    assert sp.simplify(perron_root(sp.Matrix([[0, 1], [1 - Q, 0]])) - sp.sqrt(1 - Q)) == 0
    # a self-loop of weight q beside a transient state: rho = q (sympy's path used to give 1/2 here)
    assert perron_root(sp.Matrix([[0, Q], [0, Q]])) == Q


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 3).flatmap(lambda n: st.lists(st.sampled_from([R(0), Q, 1 - Q, R(1, 2), 1 + Q]),
                                                    min_size=n * n, max_size=n * n)))
def test_algebraic_entries_against_lapack(entries):
    n = int(len(entries) ** 0.5)
    M = sp.Matrix(n, n, entries)
    lapack = max(abs(np.linalg.eigvals(np.array(M.evalf(20), dtype=float))))
    assert abs(float(perron_root(M)) - lapack) < 1e-9


def _radical_matrix(seed, n):
    """The benchmarks' deterministic generator (non-negative, over Q(sqrt 2, sqrt 3, sqrt 5))."""
    import sys
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        from engine_cases import radical_matrix
    finally:
        sys.path.pop(0)
    return radical_matrix(seed, n)


def _norm_by_sympy(M: sp.Matrix) -> sp.Poly:
    """Independent of flint and of symkf.exact.field: the entries as polynomials in the primitive
    element theta = sqrt 2 + sqrt 3 + sqrt 5 (sympy's to_number_field), det(x I - M(t)) over Q[t, x],
    and the norm as the resultant with theta's minimal polynomial m(t)."""
    t, x = sp.symbols("t x")
    theta = sp.sqrt(2) + sp.sqrt(3) + sp.sqrt(5)
    m = sp.minimal_polynomial(theta, t)
    reps = {r: sp.Poly(sp.to_number_field(r, theta).coeffs(), t).as_expr() for r in (sp.sqrt(2), sp.sqrt(3), sp.sqrt(5))}
    assert all(sp.simplify(e.subs(t, theta) - r) == 0 for r, e in reps.items())
    chi = sp.expand((x * sp.eye(M.shape[0]) - M.subs(reps)).det(method="berkowitz"))
    return sp.Poly(sp.resultant(sp.Poly(m, t, x), sp.Poly(sp.rem(chi, m, t), t, x), t), x)


@pytest.mark.parametrize("seed", range(3))
def test_radical_entries_against_sympy_norm_and_lapack(seed):
    # 3 x 3 over Q(sqrt 2, sqrt 3, sqrt 5): the root's minimal polynomial is the one factor of the
    # independently computed norm with a root at LAPACK's spectral radius, and the values agree
    M = _radical_matrix(seed, 3)
    lapack = max(abs(np.linalg.eigvals(np.array(M.evalf(30), dtype=float))))
    root = AlgebraicNumber.from_expr(perron_root(M))
    x = sp.Symbol("x")
    factors = [sp.Poly(f, x) for f, _ in sp.factor_list(_norm_by_sympy(M).as_expr(), x)[1]
               if any(abs(complex(r) - lapack) < 1e-9 for r in sp.Poly(f, x).nroots(n=30))]
    assert len(factors) == 1 and factors[0].monic() == root.minpoly.monic()
    assert abs(float(root) - lapack) < 1e-9 * lapack


@pytest.mark.parametrize("seed", range(6))
def test_radical_6x6_roots_by_the_norm_enclosure(seed):
    # 6 x 6 (the benchmark's size): the enclosure singles out one root of the degree-48 norm (the
    # fast path applies), which is LAPACK's spectral radius and a root of chi_M itself
    M = _radical_matrix(seed, 6)
    root = perron_field.field_perron_root(M)
    assert root is not None
    lapack = max(abs(np.linalg.eigvals(np.array(M.evalf(30), dtype=float))))
    assert abs(float(root) - lapack) < 1e-9 * lapack
    # an eigenvalue of M itself, not of a conjugate matrix: det(rho I - M) at rho to 60 digits is ~0
    # (a conjugate's root would leave it far from 0), and the minimal polynomial divides the norm
    lo, hi = root.refine(sp.Rational(1, 10 ** 60)).interval
    rho = sp.Float(sp.Rational(lo.numerator, lo.denominator), 80)
    assert abs((rho * sp.eye(6) - M.evalf(80)).det(method="berkowitz")) < 1e-40
    K = perron_field.field_of(M)
    norm = perron_field.norm_charpoly(K, K.matrix(M))
    assert norm.degree() == 48 and norm % flint.fmpz_poly([int(c) for c in reversed(root.minpoly.all_coeffs())]) == 0


def test_norm_charpoly_is_the_norm_of_chi():
    # 2 x 2 over Q(sqrt 2): [[q, 1], [1, 0]] with q = sqrt 2: chi = x^2 - q x - 1, its conjugate
    # x^2 + q x - 1, product x^4 - 4 x^2 + 1 (by hand)
    K = perron_field.field_of(sp.Matrix([[sp.sqrt(2)]]))
    M = K.matrix(sp.Matrix([[sp.sqrt(2), 1], [1, 0]]))
    assert perron_field.norm_charpoly(K, M) == flint.fmpz_poly([1, 0, -4, 0, 1])


def test_norm_dimension_is_capped_by_max_norm_dimension():
    # [[sqrt 2, 1], [1, 0]]: n = 2 states over Q(sqrt 2) (d = 2), a rational norm matrix of size
    # n d = 4; chi = x^2 - sqrt 2 x - 1, Perron root (sqrt 2 + sqrt 6)/2 by hand.  Under a cap of 3
    # it is refused by perron_root itself (not passed on to the costlier fallback over K)
    from symkf import budget
    from symkf.errors import BudgetError
    M = sp.Matrix([[sp.sqrt(2), 1], [1, 0]])
    with budget.limits(max_norm_dimension=3):
        with pytest.raises(BudgetError, match=r"an irreducible block of 2 chain states: the size n d of the rational "
                                              r"matrix of its norm \(n = 2 states, entries in a field of degree "
                                              r"d = 2\) is 4, above the cap 3; .*--max-norm-dimension"):
            perron_root(M)
    with budget.limits(max_norm_dimension=4):
        assert sp.simplify(perron_root(M) - (sp.sqrt(2) + sp.sqrt(6)) / 2) == 0
