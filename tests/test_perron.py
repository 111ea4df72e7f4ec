"""Exact Perron roots (symkf.exact.perron, used by symkf.decay.perron_root) against independent methods."""

import flint
import numpy as np
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf import files
from symkf.decay import perron_root, restricted_transfer
from symkf import examples
from symkf.exact import perron
from symkf.observability import block_rows

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


@settings(derandomize=True, max_examples=150, deadline=None)
@given(nonnegative())
def test_perron_root_agrees_with_sympy_real_roots(M):
    assert sp.simplify(perron_root(M) - sympy_spectral_radius(M)) == 0


@settings(derandomize=True, max_examples=60, deadline=None)
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
            lapack = max(abs(np.linalg.eigvals(np.array(M.evalf(20), dtype=float))))
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


@settings(derandomize=True, max_examples=40, deadline=None)
@given(st.integers(2, 3).flatmap(lambda n: st.lists(st.sampled_from([R(0), Q, 1 - Q, R(1, 2), 1 + Q]),
                                                    min_size=n * n, max_size=n * n)))
def test_algebraic_entries_against_lapack(entries):
    n = int(len(entries) ** 0.5)
    M = sp.Matrix(n, n, entries)
    lapack = max(abs(np.linalg.eigvals(np.array(M.evalf(20), dtype=float))))
    assert abs(float(perron_root(M)) - lapack) < 1e-9
