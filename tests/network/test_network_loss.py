"""The packet-loss process of a sensor tree over a network-state channel (symkf.network.loss): its
lifted chain against enumeration of state paths (Markov) and of renewals (semi-Markov), lumped to
a MarkovLoss when theta is itself first-order Markov, link probabilities validated."""

from __future__ import annotations

import itertools

import pytest
import sympy as sp

from symkf.errors import AssumptionError, InputError, ProbabilityError
from symkf.model.markov import MarkovLoss
from symkf.network import (
    MarkovNetworkState,
    NetworkLoss,
    PeriodicDynamics,
    SemiMarkovNetworkState,
    SensorTree,
    induced_loss,
)

R = sp.Rational


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
