"""Semi-Markov network states (symkf.network.semi_markov; Quevedo et al., Sec. VII): the observability
matrix, the rank-deficiency probabilities by dynamic programming against enumeration, Theorem 2
against Theorem 1 and against its printed mu, the exact verdict on semi-Markov states by hand,
and Theorem 2's conservatism against the exact verdict on the plant of Sec. VII-C."""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf.engine.stability import stability
from symkf.errors import AssumptionError
from symkf.network import (
    MarkovNetworkState,
    NetworkLoss,
    PeriodicDynamics,
    SemiMarkovNetworkState,
    SensorTree,
    observability_matrix,
    rank_deficiency_probabilities,
    rank_deficiency_probability_by_enumeration,
    theorem1,
    theorem2,
)

R = sp.Rational


def _two_state():
    return MarkovNetworkState([["9/10", "1/10"], ["3/10", "7/10"]])


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


# -- the exact verdict on semi-Markov network states ------------------------------------------

def system(A, *Cs):
    return sk.System(A=A, sensors=[sk.Sensor(C=C) for C in Cs])


def semi_markov_loss(phi, q=(("1/2", "1/2"), ("1/2", "1/2")), holding=None, initial=None):
    from symkf.network import NetworkLoss, SensorTree
    from symkf.network.reproduce import VIIC_HOLDING
    from symkf.network.state import SemiMarkovNetworkState
    state = SemiMarkovNetworkState([list(r) for r in q], holding or VIIC_HOLDING, initial=initial)
    return NetworkLoss(SensorTree([0]), state, [list(phi)])


VIIC = system([["5/4", 0], [1, "11/10"]], [[1, 1]])


def test_semi_markov_decided_by_hand():
    # holding time exactly 2 in both states, next state uniform: states come in aligned pairs,
    # i.i.d.; state 1 loses each packet with probability 1/2, state 2 never.  "All lost" over
    # 2m steps has probability (1/2 * 1/4)^m, so rho = 8^(-1/2) and the margins are
    # alpha^2 / (2 sqrt 2): 25 sqrt(2)/64 and 121 sqrt(2)/400.  (Refused with exit 3 before: the
    # holding counter's count-down makes most transitions of the lifted chain 0.)
    v = stability(VIIC, semi_markov_loss(["1/2", "1"], holding=[{2: 1}, {2: 1}]))
    assert [m.exact for m in v.margins] == [25 * sp.sqrt(2) / 64, 121 * sp.sqrt(2) / 400]
    assert "irreducible lifted chain" in v.assumptions[-1]
    # the Sec. VII-C instance (phi = 19/20 in both states): theta is i.i.d. with loss 1/20, so
    # the margins are (25/16)/20 = 5/64 and (121/100)/20 = 121/2000
    assert [m.exact for m in stability(VIIC, semi_markov_loss(["19/20", "19/20"])).margins] == \
        [R(5, 64), R(121, 2000)]


def test_semi_markov_reducible_chain_is_refused():
    loss = semi_markov_loss(["1/2", "1/3"], q=((1, 0), (0, 1)), holding=[{2: 1}, {1: "1/2", 3: "1/2"}],
                            initial=["1/2", "1/2"])
    with pytest.raises(sk.errors.AssumptionError, match="not irreducible"):
        stability(VIIC, loss)


@pytest.mark.parametrize("phi2, exact_bracket, theorem2_bracket", [
    # common phi: theta i.i.d., exact critical phi = 1 - 16/25 = 9/25 (margin exactly 1 at 9/25)
    ("same", ("9/25", "37/100"), ("89/100", "9/10")),
    ("1", ("1/5", "21/100"), ("85/100", "86/100")),
    ("1/2", ("1/4", "27/100"), None),  # Theorem 2 fails even at phi_{1|1} = 1
])
def test_theorem2_conservatism_on_viic(phi2, exact_bracket, theorem2_bracket):
    """docs/quevedo.md: the exact verdict against Theorem 2 (corrected) on Sec. VII-C, varying phi_{1|1}."""
    from symkf.network.dynamics import PeriodicDynamics
    from symkf.network.semi_markov import theorem2
    dyn = PeriodicDynamics(VIIC.A, [VIIC.sensors[0].C])

    def loss(p):
        return semi_markov_loss([p, p if phi2 == "same" else phi2])
    lo, hi = exact_bracket
    assert not stability(VIIC, loss(lo)).stable and stability(VIIC, loss(hi)).stable
    if theorem2_bracket is None:
        assert not theorem2(loss("1"), dyn).holds
    else:
        lo, hi = theorem2_bracket
        assert not theorem2(loss(lo), dyn).holds and theorem2(loss(hi), dyn).holds
