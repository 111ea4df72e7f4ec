"""Sufficient conditions for Markov network states (symkf.network.conditions; Quevedo et al.,
Sec. V-VI): the full-rank configurations J of Example 3 by exact rank and by the rule, relays,
Pr{r = 1} without listing J against the sum over J, nu_i against the lifted chain, and Theorem 1
by hand (i.i.d., Gilbert-Elliott, periodic A, symbols, irrational norms, quadrature bounds)."""

from __future__ import annotations

import itertools

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from symkf import budget
from symkf.errors import BudgetError, InputError
from symkf.network import (
    MarkovNetworkState,
    NetworkLoss,
    PeriodicDynamics,
    Rayleigh,
    SensorTree,
    full_rank_configurations,
    full_rank_probability,
    full_rank_probability_of,
    is_up_set,
    nu,
    phi_symbol,
    success_probability,
    theorem1,
    threshold_success,
)

R = sp.Rational


def _two_state():
    return MarkovNetworkState([["9/10", "1/10"], ["3/10", "7/10"]])


def test_example3_configurations_rank_and_rule_agree():
    from symkf.network.reproduce import EXAMPLE3_J, example3_dynamics, example3_tree
    tree = example3_tree()
    assert full_rank_configurations(tree, example3_dynamics()) == EXAMPLE3_J
    assert is_up_set(EXAMPLE3_J)
    assert not is_up_set(((0, 1),))
    with pytest.raises(InputError, match="exactly one"):
        full_rank_configurations(tree)


def test_relay_nodes_never_add_rank():
    # S2 is a relay (C = 0) carrying S3: J = {gamma1 = 1} or {gamma2 = gamma3 = 1}
    tree = SensorTree([0, 0, 2])
    dyn = PeriodicDynamics([[1]], [[[1]], [[0]], [[2]]])
    J = full_rank_configurations(tree, dyn)
    assert set(J) == {g for g in itertools.product((0, 1), repeat=3) if g[0] or (g[1] and g[2])}


def test_full_rank_probability_without_listing_is_the_sum_over_J():
    # Example 3's tree and a relay: the depth-first recursion over spans against the listed J
    from symkf.network.reproduce import example3_dynamics, example3_tree
    for tree, dyn in ((example3_tree(), example3_dynamics()),
                      (SensorTree([0, 0, 2]), PeriodicDynamics([[1]], [[[1]], [[0]], [[2]]]))):
        phi = [sp.Symbol(f"p{m}") for m in range(1, tree.M + 1)]
        listed = full_rank_probability(full_rank_configurations(tree, dyn), phi)
        assert sp.expand(full_rank_probability_of(tree, dyn, phi) - listed) == 0


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6).flatmap(lambda M: st.tuples(
    st.tuples(*[st.integers(0, m - 1) for m in range(1, M + 1)]),            # parents: a random tree
    st.lists(st.lists(st.lists(st.integers(-2, 2), min_size=3, max_size=3), min_size=0, max_size=2),
             min_size=M, max_size=M),                                        # 0-2 rows per sensor
    st.lists(st.sampled_from([R(1, 3), R(1, 2), R(4, 5), sp.S.One, sp.S.Zero]), min_size=M, max_size=M))),
    st.booleans())
def test_full_rank_probability_of_random_trees(case, sqrt2):
    # independent check: J listed by the exact rank of every C(theta), then summed; sensors of
    # zero, one and two rows (relays, parallel rows), entries in Q or Q(sqrt 2)
    parents, blocks, phi = case
    tree = SensorTree(list(parents))
    scale = sp.sqrt(2) if sqrt2 else 1
    C = [sp.Matrix(b) * scale if b else sp.zeros(1, 3) for b in blocks]
    dyn = PeriodicDynamics(sp.eye(3), C)
    listed = full_rank_probability(full_rank_configurations(tree, dyn), phi)
    assert sp.nsimplify(full_rank_probability_of(tree, dyn, phi) - listed) == 0


def test_link_probabilities_of_the_wrong_length_are_refused():
    # one probability for two links: the listed sum zipped it away (an answer of 3/2), the
    # recursion indexed past it (IndexError)
    tree, dyn = SensorTree([0, 0]), PeriodicDynamics([[1]], [[[1]], [[2]]])
    J = full_rank_configurations(tree, dyn)
    for call in (lambda: full_rank_probability(J, [R(1, 2)]), lambda: full_rank_probability_of(tree, dyn, [R(1, 2)])):
        with pytest.raises(InputError, match=r"phi: 1 link probabilities for a (vector|tree) of 2"):
            call()
    assert full_rank_probability(J, [R(1, 2)] * 2) == full_rank_probability_of(tree, dyn, [R(1, 2)] * 2) == R(3, 4)


def test_full_rank_probability_is_refused_before_it_starts():
    # 40 scalar sensors of a 6-state system: up to sum_{k<6} C(41, k + 1) = 5.4 million spans
    dyn = PeriodicDynamics(sp.eye(6), [[[1, m, m ** 2, m ** 3, m ** 4, m ** 5]] for m in range(40)])
    with pytest.raises(BudgetError, match="max_span_states"):
        full_rank_probability_of(SensorTree([0] * 40), dyn, [R(1, 2)] * 40)
    with pytest.raises(BudgetError, match="max_patterns"):
        full_rank_configurations(SensorTree([0] * 40), dyn)
    with budget.limits(max_span_states=10 ** 7):
        assert budget.LIMITS.max_span_states == 10 ** 7


def test_full_rank_probability_of_sensors_in_general_position():
    # 16 Vandermonde rows in dimension 4 (every 4 independent): Pr{r = 1} = P(Binomial(16, p) >= 4)
    p = sp.Symbol("p")
    dyn = PeriodicDynamics(sp.eye(4), [[[1, m, m ** 2, m ** 3]] for m in range(16)])
    exact = sum(sp.binomial(16, k) * p ** k * (1 - p) ** (16 - k) for k in range(4, 17))
    assert sp.expand(full_rank_probability_of(SensorTree([0] * 16), dyn, [p] * 16) - exact) == 0


def test_theorem1_iid_and_gilbert_elliott_by_hand():
    dyn = PeriodicDynamics([[2, 0], [0, R(1, 2)]], [[[1, 0], [0, 1]]])
    iid = theorem1(NetworkLoss(SensorTree([0]), MarkovNetworkState([[1]]), [["7/8"]]), dyn)
    assert iid.rho == R(1, 2) and iid.holds  # (1 - 7/8) * 4
    ge = theorem1(NetworkLoss(SensorTree([0]), _two_state(), [[1, 0]]), dyn)
    assert ge.nu == (R(1, 10), R(7, 10)) and ge.rho == R(14, 5) and ge.holds is False


def test_theorem1_periodic_A_and_symbolic():
    dyn = PeriodicDynamics([[[3]], [[1]]], [[[1]]])
    t = theorem1(NetworkLoss(SensorTree([0]), MarkovNetworkState([[1]]), [["15/16"]]), dyn)
    assert t.rho == R(9, 16) and t.holds and len(t.lhs) == 2
    sym = theorem1(NetworkLoss(SensorTree([0]), MarkovNetworkState([[1]]), "symbols"), dyn)
    assert sym.rho is None and sym.holds is None
    assert sp.Lt(9 * (1 - phi_symbol(1, 1)), 1) in sym.condition


def test_theorem1_irrational_norm_is_exact():
    A = [[1, 1], [0, 1]]  # ||A||^2 = (3 + sqrt 5)/2
    dyn = PeriodicDynamics(A, [[[1, 0], [0, 1]]])
    t = theorem1(NetworkLoss(SensorTree([0]), MarkovNetworkState([[1]]), [["3/5"]]), dyn)
    assert sp.simplify(t.rho.exact - R(2, 5) * (3 + sp.sqrt(5)) / 2) == 0
    assert t.holds is False  # 2/5 * 2.618 = 1.047


def test_theorem1_with_quadrature_uses_lower_bounds():
    phi = success_probability(Rayleigh(10), threshold_success(1), breakpoints=[1])  # exp(-1/10)
    dyn = PeriodicDynamics([[3]], [[[1]]])
    t = theorem1(NetworkLoss(SensorTree([0]), MarkovNetworkState([[1]]), [[phi]]), dyn)
    assert t.certified_by_bounds and t.holds  # 9 (1 - 0.9048) = 0.857
    assert t.nu[0] == 1 - phi.lower


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from([0, R(1, 4), R(1, 2), R(3, 4), 1]), min_size=6, max_size=6))
def test_nu_equals_one_step_probability_from_chain(values):
    # nu_i = Pr{C(k) rank deficient | Xi(k-1) = i} from the lifted chain, independently
    tree = SensorTree([0, 1, 1])
    dyn = PeriodicDynamics([[1, 0], [0, 1]], [[[1, 0]], [[0, 1]], [[1, 1]]])
    phi = [values[0:2], values[2:4], values[4:6]]
    loss = NetworkLoss(tree, _two_state(), phi)
    J = full_rank_configurations(tree, dyn)
    nus = nu(loss, J)
    ch = loss.chain
    deficient = [dyn.n > sp.Matrix(dyn.C_of(t)).rank() for t in ch.emit]
    for i in (1, 2):
        rows = [r for r, s in enumerate(ch.states) if s[0] == i]
        for r in rows:
            direct = sum(ch.P[r, s] for s in range(len(ch.states)) if deficient[s])
            assert sp.simplify(direct - nus[i - 1]) == 0
