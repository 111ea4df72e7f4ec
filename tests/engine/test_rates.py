"""Decay rates and the M matrix (symkf.engine.rates; Sui-You-Fu eqs. 33-36, Theorem 9).

``u M^N v = P(R_{Ng})`` exactly against enumeration of every loss pattern (eq. 35), the
enumeration refused above its cap, and the hyperplane rate equal to the spectral radius of the
full M (eq. 36) under i.i.d. and Gilbert-Elliott losses.  The screened searches for the largest
rate are checked against listing every hyperplane in tests/engine/test_search.py."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf.engine.blocks import block_rows
from symkf.engine.rates import m_matrix, probability_rank_deficient
from symkf.engine.search import block_rate
from symkf.exact.algebraic import AlgebraicNumber
from symkf.exact.numbers import sympify as exact

#: 2R(pi/2), C = [1 0]
QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
#: the plant of Quevedo et al., Sec. VII-C: two real blocks 5/4 and 11/10
LOWER_TRIANGULAR = sk.System(A=[["5/4", 0], [1, "11/10"]], sensors=[sk.Sensor(C=[[1, 1]])])
TWO = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])
MARKOV = sk.MarkovLoss({(1,): {(1,): "2/3", (0,): "1/3"}, (0,): {(1,): "1/4", (0,): "3/4"}})
MARKOV2 = sk.MarkovLoss({((1,), (1,)): {(1,): "1/2", (0,): "1/2"}, ((1,), (0,)): {(1,): "1/3", (0,): "2/3"},
                         ((0,), (1,)): {(1,): "3/4", (0,): "1/4"}, ((0,), (0,)): {(1,): "1/5", (0,): "4/5"}},
                        order=2)


@pytest.mark.parametrize("system,loss", [
    (QUARTER_TURN, sk.IID(["1/3"])), (QUARTER_TURN, sk.GilbertElliott(["1/4"], ["1/2"])), (QUARTER_TURN, MARKOV),
    (QUARTER_TURN, MARKOV2), (LOWER_TRIANGULAR, sk.GilbertElliott(["1/5"], ["2/3"])),
    (TWO, sk.IID(["1/3", "1/2"])), (TWO, sk.GilbertElliott(["1/4", "1/3"], ["1/2", "1/5"])),
])
def test_eq35_against_enumeration(system, loss):
    """u M^N v = P(R_{Ng}(i)) exactly, per block, including multi-block and order-2 Markov."""
    for i, br in enumerate(block_rows(system)):
        M, _ = m_matrix(br, loss)
        v = sp.Matrix([1] + [0] * (M.shape[0] - 1))
        for N in range(0, 9 // (br.class_period * system.d) + 2):
            if br.class_period * N * system.d > 12:
                break
            assert sp.expand(sum(M ** N * v)) == probability_rank_deficient(system, loss, br.class_period * N)[i]


def test_enumeration_is_capped_by_max_patterns():
    """TWO (class period 2), N = 4 steps: 2^(2 * 4) = 256 patterns, refused under max_patterns = 128
    naming the cap; at 256 the enumeration runs and matches eq. 35, u M^2 v."""
    from symkf import budget
    from symkf.errors import BudgetError
    loss = sk.IID(["1/3", "1/2"])
    with budget.limits(max_patterns=128), pytest.raises(BudgetError, match=r"is 256, above the cap 128; .*--max-patterns"):
        probability_rank_deficient(TWO, loss, 4)
    (br,) = block_rows(TWO)
    M, _ = m_matrix(br, loss)
    with budget.limits(max_patterns=256):
        assert probability_rank_deficient(TWO, loss, 4) == (sp.expand(sum(M ** 2 * sp.Matrix([1] + [0] * (M.shape[0] - 1)))),)


def _float_spectral_radius(M):
    import numpy as np
    return max(abs(np.linalg.eigvals(np.array(M.evalf().tolist(), dtype=float)))) if M.shape[0] else 0.0


@settings(max_examples=12, deadline=None)
@given(st.sampled_from([(1, 4), (1, 3), (1, 6)]), st.lists(st.integers(-2, 2), min_size=4, max_size=4),
       st.lists(st.sampled_from(["1/5", "1/3", "1/2"]), min_size=2, max_size=2))
def test_hyperplane_rate_equals_spectral_radius_of_full_m(angle, c, losses):
    A = sp.Matrix([[sp.cos(2 * sp.pi * angle[0] / angle[1]), -sp.sin(2 * sp.pi * angle[0] / angle[1])],
                   [sp.sin(2 * sp.pi * angle[0] / angle[1]), sp.cos(2 * sp.pi * angle[0] / angle[1])]])
    C1, C2 = [c[:2]], [c[2:]]
    if C1 == [[0, 0]] or C2 == [[0, 0]]:
        return
    S = sk.System(A=A, sensors=[sk.Sensor(C=C1), sk.Sensor(C=C2)])
    loss = sk.IID(losses)
    (br,) = block_rows(S)
    M, _ = m_matrix(br, loss)
    assert abs(float(AlgebraicNumber.from_expr(block_rate(br, loss).per_period)) - _float_spectral_radius(M)) < 1e-9


def _float_radius(M):
    return max(abs(np.linalg.eigvals(np.array(M.evalf().tolist(), dtype=float)))) if M.shape[0] else 0.0


@settings(max_examples=8, deadline=None)
@given(st.sampled_from([(1, 4), (1, 3), (1, 2)]), st.sampled_from(["3/2", "5/4", 2]),
       st.lists(st.integers(-2, 2), min_size=2, max_size=2).filter(lambda v: v != [0, 0]),
       st.lists(st.sampled_from(["1/5", "1/3", "1/2", "3/4"]), min_size=4, max_size=4))
def test_ge_hyperplane_rate_equals_spectral_radius_of_full_m(angle, scale, c, params):
    # angle pi makes A a multiple of I: unobservable unless c is independent of [1, 0]
    assume(angle != (1, 2) or c[1] != 0)
    t = 2 * sp.pi * angle[0] / angle[1]
    A = exact(scale) * sp.Matrix([[sp.cos(t), -sp.sin(t)], [sp.sin(t), sp.cos(t)]])
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[c])])
    loss = sk.GilbertElliott(params[:2], params[2:])
    (br,) = block_rows(S)
    M, _ = m_matrix(br, loss)
    assert abs(float(AlgebraicNumber.from_expr(block_rate(br, loss).per_period)) - _float_radius(M)) < 1e-9


def test_the_run_length_gain_is_taken_over_the_words_a_hyperplane_may_hold():
    """Gilbert-Elliott, fail 1/10, recover 1/2 (lost state z): ``a_l = (P^l)_(z, z)`` is 1/2, 3/10,
    11/50, 47/250, 219/1250, 1063/6250; any word length gives ``kappa = 1 / a_1 = 2`` (the lost-run
    bound's ``-log max a_l`` alike), words of at most 5 ``kappa = (a_6 / a_1^6)^(1/5) = 1.612``,
    with ``C = g log a_1`` either way."""
    from symkf.engine.rates import FactorRates
    rates = FactorRates(sk.GilbertElliott(["1/10"], ["1/2"]).factors[0], 315)
    C, b = rates.gain_bound(5)
    assert C == pytest.approx(315 * np.log(0.5), rel=1e-9) and b[0] == pytest.approx(np.log(2), rel=1e-9)
    C, b = rates.gain_bound(5, longest=5)
    assert C == pytest.approx(315 * np.log(0.5), rel=1e-9)
    assert b[0] == pytest.approx(np.log(float(sp.Rational(1063, 6250) * 2 ** 6)) / 5, rel=1e-9)
    assert rates.gain_bound(5, longest=315)[1] == rates.gain_bound(5)[1]   # no shorter than the period
