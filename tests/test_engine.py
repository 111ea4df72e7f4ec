"""Issue 3: M matrix against enumeration (eq. 35), decay rates (eq. 36), verdicts, critical values."""

import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

import symkf as sk
from symkf.engine.rates import m_matrix, probability_rank_deficient
from symkf.engine.search import block_rate
from symkf.exact.algebraic import AlgebraicNumber
from symkf.engine.blocks import block_rows
from symkf.engine.stability import critical_alpha, critical_loss_rate, stability
from symkf.engine.recovery import critical_recovery_rate

DESIGN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
SEED002 = sk.System(A=[["5/4", 0], [1, "11/10"]], sensors=[sk.Sensor(C=[[1, 1]])])
TWO = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])
MARKOV = sk.MarkovLoss({(1,): {(1,): "2/3", (0,): "1/3"}, (0,): {(1,): "1/4", (0,): "3/4"}})
MARKOV2 = sk.MarkovLoss({((1,), (1,)): {(1,): "1/2", (0,): "1/2"}, ((1,), (0,)): {(1,): "1/3", (0,): "2/3"},
                         ((0,), (1,)): {(1,): "3/4", (0,): "1/4"}, ((0,), (0,)): {(1,): "1/5", (0,): "4/5"}},
                        order=2)


@pytest.mark.parametrize("system,loss", [
    (DESIGN, sk.IID(["1/3"])), (DESIGN, sk.GilbertElliott(["1/4"], ["1/2"])), (DESIGN, MARKOV),
    (DESIGN, MARKOV2), (SEED002, sk.GilbertElliott(["1/5"], ["2/3"])),
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


def test_design_example_critical_is_one_sixteenth():
    eps = critical_loss_rate(DESIGN)
    assert eps.exact == sp.Rational(1, 16)
    assert not stability(DESIGN, sk.IID(["1/16"])).stable  # margin exactly 1 is not stable
    assert stability(DESIGN, sk.IID(["1/17"])).stable


def test_seed002_critical_is_16_25():
    assert critical_loss_rate(SEED002) == sp.Rational(16, 25)
    v = stability(SEED002, sk.IID(["16/25"]))
    assert not v.stable and v.limiting_block == 0 and v.theorem.startswith("Theorem 7")


@pytest.mark.parametrize("A,rho2", [([[2, 0], [0, "3/2"]], 4), ([[0, -3], [3, 0]], 9), ([["1/2", 1], [0, 2]], 4)])
def test_sinopoli_single_invertible_sensor(A, rho2):
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0], [0, 1]])])
    assert critical_loss_rate(S) == sp.Rational(1, rho2)


def test_two_sensor_values_by_hand():
    # four distinct directions over the governing period 2: three elements must be lost together
    assert critical_loss_rate(TWO).exact == 2 ** sp.Rational(-4, 3)
    assert critical_loss_rate(TWO, "s1", others=[0, "1/2"]) == sp.Rational(1, 4)
    assert critical_loss_rate(TWO, ray=[1, 2]) == sp.Rational(1, 4)
    assert critical_alpha(DESIGN, sk.IID(["1/16"])) == 2


def test_aperiodic_rotation_critical_is_sinopoli_bound():
    S = sk.System(A=[["9/10", "-6/5"], ["6/5", "9/10"]], sensors=[sk.Sensor(C=[[1, 0]])])
    assert critical_loss_rate(S) == sp.Rational(4, 9)
    # Markov losses on the aperiodic block (issue 14): rows C A^k, C A^l are independent for k != l
    # (sin((l - k) theta) != 0, theta/pi irrational), so R_N = {at most one reception}, of rate
    # P(stay lost) = 1 - recover.  alpha^2 = 9/4: margin 9/4 * 1/2 = 9/8, critical recovery 5/9.
    v = stability(S, sk.GilbertElliott(["1/4"], ["1/2"]))
    assert not v.stable and v.margins[0] == sp.Rational(9, 8)
    assert critical_recovery_rate(S, ["1/4"]) == sp.Rational(5, 9)


def test_certified_on_both_sides():
    eps = critical_loss_rate(TWO)
    lo, hi = eps.refine(sp.Rational(1, 10 ** 8)).interval
    assert stability(TWO, sk.IID([lo - sp.Rational(1, 10 ** 9)] * 2)).stable
    assert not stability(TWO, sk.IID([hi] * 2)).stable


def test_positivity_is_checked_for_markov():
    with pytest.raises(sk.SymkfError, match="Assumption 2"):
        stability(DESIGN, sk.GilbertElliott(["1/4"], [1]))


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


@settings(max_examples=10, deadline=None)
@given(st.lists(st.integers(-2, 2), min_size=2, max_size=2).filter(lambda v: v != [0, 0]),
       st.sampled_from([(0, -2, 2, 0), ("1", "-1", "1", "1"), ("3/2", 0, 0, "-3/2")]))
def test_adding_a_sensor_never_destabilises(extra, a):
    A = [[a[0], a[1]], [a[2], a[3]]]
    base = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]])])
    more = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]]), sk.Sensor(C=[extra])])
    assert critical_loss_rate(more) >= critical_loss_rate(base)


def test_critical_rate_monotone_in_alpha():
    values = [critical_loss_rate(sk.System(A=[[0, -a], [a, 0]], sensors=[sk.Sensor(C=[[1, 0]])]))
              for a in (2, 3, 4)]
    assert values[0] > values[1] > values[2]
