"""Tests for symkf.network (seed 002: Quevedo, Ahlén, Johansson)."""

from __future__ import annotations

import itertools
import subprocess
import sys

import mpmath
import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from symkf.io import files
from symkf import stability
from symkf import budget
from symkf.errors import AssumptionError, BudgetError, InputError, ProbabilityError
from symkf.model.markov import MarkovLoss
from symkf.network import (MarkovNetworkState, Nakagami, NetworkLoss, PeriodicDynamics, Rayleigh, Rician,
                           SemiMarkovNetworkState, SensorTree, UserGain, full_rank_configurations,
                           full_rank_probability, full_rank_probability_of, induced_loss, is_up_set, nu,
                           observability_matrix, phi_symbol, rank_deficiency_probabilities,
                           rank_deficiency_probability_by_enumeration, spectral_norm_squared, success_probability,
                           theorem1, theorem2, threshold_success)
from conftest import ROOT

R = sp.Rational


# -- tree -------------------------------------------------------------------------------

def test_tree_paths_example1():
    # Fig. 2 / Example 1: Par(S4) = Par(S5) = S2, Node(Path(S7)) = {S7, S3, S1, S0}
    tree = SensorTree([0, 0, 1, 2, 2, 3, 3, 2])
    assert tree.parent(4) == tree.parent(5) == 2
    assert tree.path(7) == (7, 3, 1, 0)
    assert tree.edges(7) == (7, 3, 1)
    assert tree.children(3) == (6, 7)


def test_theta_is_product_over_path():
    tree = SensorTree({1: 0, 2: 1, 3: 2})
    for g in itertools.product((0, 1), repeat=3):
        assert tree.theta(g) == (g[0], g[0] * g[1], g[0] * g[1] * g[2])


@pytest.mark.parametrize("parents", [[1, 2, 1], [0, 5], [0, 2], [], [0, "1"]])
def test_bad_trees_are_refused(parents):
    with pytest.raises(InputError):
        SensorTree(parents)


# -- network states ---------------------------------------------------------------------

def test_state_validation():
    with pytest.raises(ProbabilityError, match="row 1 sums to"):
        MarkovNetworkState([["1/2", "1/3"], ["1/2", "1/2"]])
    with pytest.raises(ProbabilityError, match="holding"):
        SemiMarkovNetworkState([[1]], [{1: "1/2", 2: "1/3"}])
    with pytest.raises(InputError, match="positive integer"):
        SemiMarkovNetworkState([[1]], [{0: 1}])
    with pytest.raises(InputError, match="stationary"):
        MarkovNetworkState([[1, 0], [0, 1]])
    s = SemiMarkovNetworkState([[0, 1], [1, 0]], [[R(1, 5)] * 5, {7: 1}])
    assert s.sigma == 7 and s.psi(1, 3) == R(1, 5) and s.psi(1, 6) == 0
    assert list(s.initial) == [R(1, 2), R(1, 2)]


# -- fading (eqs. 7-10, footnote 5) -------------------------------------------------------

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


# -- the lifted loss chain ----------------------------------------------------------------

def _two_state():
    return MarkovNetworkState([["9/10", "1/10"], ["3/10", "7/10"]])


def test_markov_chain_matches_path_enumeration():
    tree = SensorTree([0, 1])
    phi = [["9/10", "1/5"], ["4/5", "1/2"]]
    loss = NetworkLoss(tree, _two_state(), phi)
    ch = loss.chain
    assert all(sp.simplify(sum(ch.P.row(r)) - 1) == 0 for r in range(len(ch.states)))
    st_ = loss.state
    law = {j: {t: p for t, p in loss.theta_law(j).items()} for j in (1, 2)}
    for seq in itertools.product(loss.theta_vectors, repeat=3):
        brute = sum(st_.initial[0, a - 1] * st_.p(a, b) * st_.p(b, c)
                    * law[a][seq[0]] * law[b][seq[1]] * law[c][seq[2]]
                    for a, b, c in itertools.product((1, 2), repeat=3))
        assert ch.sequence_probability(seq) == sp.nsimplify(brute)


def test_semi_markov_chain_matches_renewal_enumeration():
    q = [["1/4", "3/4"], ["2/3", "1/3"]]
    hold = [{1: "1/2", 2: "1/2"}, {1: "1/3", 3: "2/3"}]
    state = SemiMarkovNetworkState(q, hold, initial=["1/2", "1/2"])
    loss = NetworkLoss(SensorTree([0]), state, [["9/10", "1/5"]])
    horizon = 5

    def paths(prefix, prob, j):  # state paths of length horizon from jump instants
        if len(prefix) >= horizon:
            yield prefix[:horizon], prob
            return
        for d, pd in state.holding[j - 1].items():
            for j2 in (1, 2):
                yield from paths(prefix + [j] * d, prob * pd * state.qij(j, j2), j2)

    state_law: dict = {}
    for j0 in (1, 2):
        for path, p in paths([], state.initial[0, j0 - 1], j0):
            state_law[tuple(path)] = state_law.get(tuple(path), 0) + p
    law = {j: loss.theta_law(j) for j in (1, 2)}
    for seq in itertools.product(((1,), (0,)), repeat=horizon):
        brute = sum(p * sp.Mul(*[law[j][t] for j, t in zip(path, seq)]) for path, p in state_law.items())
        assert loss.chain.sequence_probability(seq) == sp.expand(brute)


def test_gilbert_elliott_lumping_and_induced_loss():
    tree = SensorTree([0])
    ge = NetworkLoss(tree, _two_state(), [[1, 0]])
    ml = induced_loss(ge)
    assert type(ml) is MarkovLoss
    assert ml.chain.P == sp.ImmutableMatrix([[R(9, 10), R(1, 10)], [R(3, 10), R(7, 10)]])
    hidden = NetworkLoss(tree, _two_state(), [["9/10", "1/5"]])
    with pytest.raises(AssumptionError, match="hidden-Markov"):
        hidden.as_markov_loss()
    assert induced_loss(hidden) is hidden
    semi = NetworkLoss(tree, _two_state().as_semi_markov(), [[1, 0]])
    with pytest.raises(AssumptionError, match="Assumption 1"):
        induced_loss(semi)
    with pytest.raises(AssumptionError, match="time-invariant"):
        induced_loss(hidden, PeriodicDynamics([[[2]], [[1]]], [[[1]]]))


def test_phi_validation():
    with pytest.raises(ProbabilityError):
        NetworkLoss(SensorTree([0]), _two_state(), [["3/2", 0]])
    with pytest.raises(InputError, match="rows"):
        NetworkLoss(SensorTree([0, 0]), _two_state(), [[1, 0]])


# -- J, Pr{r = 1}, nu, Theorem 1 ------------------------------------------------------------

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


# -- semi-Markov: O, varrho, mu, Theorem 2 ----------------------------------------------------

def test_observability_matrix_shape_and_phi():
    dyn = PeriodicDynamics([[[1, 1], [0, 1]], [[2, 0], [0, 1]]], [[[1, 0]]])
    O = observability_matrix(dyn, [(1,), (1,), (0,)], k=1)
    # Phi(2, 1) = A(1) = [[2, 0], [0, 1]]; Phi(3, 1) = A(2) A(1) = A(0) A(1)
    assert O == sp.Matrix([[1, 0], [2, 0], [0, 0]])


@settings(max_examples=12, deadline=None)
@given(st.lists(st.integers(-2, 2), min_size=4, max_size=4),
       st.sampled_from([R(1, 3), R(1, 2), R(9, 10)]), st.integers(0, 1))
def test_dp_matches_enumeration(a, p, phase):
    A1 = [[a[0], a[1]], [a[2], a[3]]]
    dyn = PeriodicDynamics([A1, [[1, 1], [0, 1]]], [[[1, 0]], [[0, 1]]])
    loss = NetworkLoss(SensorTree([0, 1]), MarkovNetworkState([[1]]), [[p], ["3/4"]])
    dp = rank_deficiency_probabilities(loss, dyn, 1, 3, phase)
    for d in (1, 2, 3):
        assert dp[d - 1] == rank_deficiency_probability_by_enumeration(loss, dyn, 1, d, phase)


@pytest.mark.parametrize("phase", [0, 1])
def test_dp_matches_enumeration_over_a_number_field(phase):
    # A(0) a rotation by pi/4 (entries in Q(sqrt 2)), A(1) a shear: the spans live in Q(sqrt 2)
    c = sp.sqrt(2) / 2
    dyn = PeriodicDynamics([[[c, -c], [c, c]], [[1, 1], [0, 1]]], [[[1, 0]], [[1, 1]]])
    loss = NetworkLoss(SensorTree([0, 1]), MarkovNetworkState([[1]]), [[R(1, 2)], ["3/4"]])
    dp = rank_deficiency_probabilities(loss, dyn, 1, 3, phase)
    assert [dp[d - 1] for d in (1, 2, 3)] == [rank_deficiency_probability_by_enumeration(loss, dyn, 1, d, phase)
                                              for d in (1, 2, 3)]


def test_theorem2_reduces_to_theorem1_for_unit_holding():
    tree = SensorTree([0, 1])
    dyn = PeriodicDynamics([[R(6, 5), 1], [0, R(1, 2)]], [[[1, 0]], [[0, 1]]])
    phi = [["9/10", "1/5"], ["4/5", "1/2"]]
    t1 = theorem1(NetworkLoss(tree, _two_state(), phi), dyn)
    t2 = theorem2(NetworkLoss(tree, _two_state().as_semi_markov(), phi), dyn)
    for i in (1, 2):
        assert sp.simplify(t2.lhs[(i, 0)] - t1.lhs[(i, 0)]) == 0
        assert sp.simplify(t2.lhs_paper[(i, 0)] - t1.lhs[(i, 0)]) == 0
    assert t2.holds == t2.holds_paper == t1.holds


def test_theorem2_mu_definition_vs_printed():
    loss = NetworkLoss(SensorTree([0]), SemiMarkovNetworkState([["1/2", "1/2"]] * 2, [{1: 1}, {2: 1}]), [[1, 0]])
    t2 = theorem2(loss, PeriodicDynamics([[R(6, 5)]], [[[1]]]))
    # Given Delta = 1 (2) the entered state must be 1 (2): mu = (pi_1(1), pi_2(2)) = (0, 1);
    # the last line of (31) averages with q instead: (1/2, 1/2)
    assert t2.mu[(1, 0)] == (0, 1)
    assert t2.mu_paper[(1, 0)] == (R(1, 2), R(1, 2))
    assert t2.holds_paper is True and t2.holds is False
    with pytest.raises(AssumptionError, match="Assumption 3"):
        theorem2(NetworkLoss(SensorTree([0]), _two_state(), [[1, 0]]), PeriodicDynamics([[2]], [[[1]]]))


def test_spectral_norm_squared_against_numpy():
    np = pytest.importorskip("numpy")
    for M in ([[R(5, 4), 0], [1, R(11, 10)]], [[0, -2], [2, 0]], [[1, 2, 0], [0, 1, 3], [1, 0, 1]]):
        v = spectral_norm_squared(sp.Matrix(M))
        assert abs(float(v) - np.linalg.norm(np.array(M, dtype=float), 2) ** 2) < 1e-10


# -- reproductions (the proofs run in tests/test_proofs.py) -------------------------------------------------------------------

def test_reproduce_example3():
    from symkf.network.reproduce import reproduce_quevedo_example3
    out = reproduce_quevedo_example3()
    assert all(out["checks"].values()), out["checks"]
    assert out["results"]["configurations"][0] == [0, 1, 0, 1, 1] and len(out["results"]["configurations"]) == 9


def test_reproduce_semi_markov_exact_part():
    from symkf.network.reproduce import reproduce_quevedo_semi_markov
    out = reproduce_quevedo_semi_markov(simulate=False)
    assert all(out["checks"].values()), out["checks"]
    w = out["results"]["witness_q_half"]
    assert w["holds_as_printed"] is True and w["holds_corrected"] is False


@pytest.mark.full
def test_reproduce_robot_and_examples_scripts(tmp_path):
    from symkf.network.reproduce import reproduce_quevedo_robot
    out = reproduce_quevedo_robot(str(tmp_path))
    assert all(out["checks"].values()), out["checks"]
    # exact margins of the 21/20 and 1 blocks: Perron roots of the 560-state lifted chain restricted
    # to "S1 and S4 lost" and "S1, S3, S4 lost" (cross-checked against LAPACK in tests/exact/test_perron.py)
    exact = out["results"]["exact_verdict"]
    assert exact["stable"] is True and exact["margin_minpoly_degrees"] == [56, 56]
    assert [round(float(m[0]), 6) for m in exact["margins"]] == [0.153956, 0.091163]
    assert (tmp_path / "quevedo_robot.png").exists()
    for name in ("quevedo_example3", "quevedo_robot"):
        run = subprocess.run([sys.executable, str(ROOT / "examples" / f"{name}.py")], capture_output=True,
                             text=True, cwd=ROOT)
        assert run.returncode == 0, run.stderr


def test_simulation_bounded_where_theorem2_holds():
    pytest.importorskip("symkf.numeric.montecarlo")
    from symkf.network.reproduce import VIIC_A, VIIC_C1, viic_simulation
    results, bounded = viic_simulation(PeriodicDynamics(VIIC_A, [VIIC_C1]))
    assert bounded
    stable = results["phi = 19/20 (both states)"]
    assert stable["corrected_condition_holds"] and stable["mean_trace_k300_400"] < 10
    assert results["phi = 3/10 (both states)"]["corrected_condition_holds"] is False


def _robot_with_growth(tmp_path, a: str):
    text = (ROOT / "symkf/io/examples/systems/network/quevedo-robot.toml").read_text()
    path = tmp_path / "robot.toml"
    path.write_text(text.replace('A = [["21/20"', f'A = [["{a}"'))
    return files.load(path)


def test_robot_exact_critical_growth(tmp_path):
    # A = [[a, 1/10], [0, 1]]: the a-mode's eigenvector (1, 0) is seen by S1 and S4 only, for every
    # a != 1, so its rate rho_0 (chain restricted to "S1 and S4 lost", 560 lifted states) does not
    # depend on a and the filter is stable iff a^2 rho_0 < 1: a < rho_0^(-1/2) = 2.67603...
    # (the 1-mode's margin is 0.0912 or 0.1396, far below 1)
    system, loss = files.load(ROOT / "symkf/io/examples/systems/network/quevedo-robot.toml")
    rho0 = stability(system, loss).margins[0] / R(441, 400)
    assert 2.67602 < float(rho0) ** -0.5 < 2.67603
    assert stability(*_robot_with_growth(tmp_path, "267/100")).stable
    assert not stability(*_robot_with_growth(tmp_path, "268/100")).stable


@pytest.mark.full
def test_robot_theorem2_critical_growth(tmp_path):
    # Theorem 2 (corrected) on the same family: holds up to a = 2.17, fails from 2.18 (docs/quevedo.md)
    for a, holds in (("217/100", True), ("218/100", False)):
        system, loss = _robot_with_growth(tmp_path, a)
        dyn = PeriodicDynamics(system.A, [s.C for s in system.sensors])
        assert theorem2(loss, dyn).holds is holds
