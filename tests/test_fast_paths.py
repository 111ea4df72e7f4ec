"""Cross-checks between issue 18's fast paths and the reference implementations they replace."""

import itertools

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.exact.algebraic import sign
from symkf.model.loss import LossModel

q = sp.Symbol("q", positive=True)
INDEPENDENT = [
    sk.IID(["1/10", "1/3", "2/7"]),
    sk.IID(["0", "1", "1/2"]),
    sk.GilbertElliott(["1/10", "1/5", "1/7"], ["1/2", "1/3", "3/4"]),
    sk.GilbertElliott(["1/10", "0"], ["1/2", "1/3"], initial_received=["1", "1/9"]),
    sk.GilbertElliott(["1/10", "1/4"], [q, "1/3"]),
]


def _joint_positivity_failure(loss: LossModel) -> bool:
    """The reference: every transition of the joint 2^d-state chain, as LossModel checks it."""
    P = loss.chain.P
    return any(not P[r, s].free_symbols and sign(P[r, s]) <= 0
               for r, s in itertools.product(range(P.shape[0]), repeat=2))


@pytest.mark.parametrize("loss", INDEPENDENT, ids=repr)
def test_independent_sensors_agree_with_the_joint_chain(loss):
    assert loss.symbols == LossModel.symbols.fget(loss)
    if loss.bernoulli is None:  # i.i.d. losses need no positivity (Theorem 4)
        assert (loss.positivity_failure() is not None) == _joint_positivity_failure(loss)
    if loss.symbols:
        with pytest.raises(sk.SymkfError, match="have no value"):
            loss.numeric()
        return
    fast, ref = loss.numeric(), loss.chain.numeric()
    assert np.array_equal(fast[2], ref[2])
    # Kronecker products round each factor once: d factors, relative error below d ulp
    assert np.allclose(fast[0], ref[0], rtol=4e-16 * loss.d, atol=0)
    assert np.allclose(fast[1], ref[1], rtol=4e-16 * loss.d, atol=0)


# -- hyperplanes: flats grouped by lines mod p, against brute force over all (n-1)-subsets --------
from functools import partial  # noqa: E402

from hypothesis import given, settings, strategies as st  # noqa: E402

from symkf.engine import rows as obs  # noqa: E402
from symkf.engine.blocks import block_rows  # noqa: E402
from symkf.exact.field import NumberField, QQ_FIELD  # noqa: E402
from symkf.exact.linalg import nullspace_rows, rank_rows  # noqa: E402


def _brute_hyperplanes(K, vectors, n):
    """Every (n-1)-subset of exact rank n-1 spans a hyperplane; its members by exact dot products."""
    out = set()
    for combo in itertools.combinations(range(len(vectors)), n - 1):
        rows = [vectors[i] for i in combo]
        if rank_rows(K, rows, n) == n - 1:
            (h,) = nullspace_rows(K, rows, n)
            out.add(frozenset(i for i, v in enumerate(vectors) if K.dot(v, h).is_zero()))
    return out


@st.composite
def _vector_sets(draw):
    """Distinct nonzero integer vectors with entries in -2..2: many collinear and coplanar sets."""
    n = draw(st.integers(2, 4))
    vecs = draw(st.lists(st.tuples(*[st.integers(-2, 2)] * n).filter(any), min_size=n, max_size=9, unique=True))
    return n, vecs


def _field_vectors(K, vecs, twist):
    # over Q(sqrt 2) the second coordinate carries sqrt(2) times an integer: an irrational field
    s2 = K.convert(sp.sqrt(2)) if twist else None
    return [tuple(K.convert(a) if not (twist and k == 1) else K.mul(s2, K.convert(a)) for k, a in enumerate(v))
            for v in vecs]


_REDUCTION = obs._reduction


@pytest.mark.parametrize("start", [1 << 27, 3], ids=["large prime", "tiny primes: false zeros mod p"])
@pytest.mark.parametrize("twist", [False, True], ids=["QQ", "Q(sqrt2)"])
@settings(max_examples=40, deadline=None)
@given(data=_vector_sets())
def test_generator_hyperplanes_equal_brute_force(start, twist, data):
    n, vecs = data
    K = NumberField([sp.sqrt(2)]) if twist else QQ_FIELD
    vectors = obs._distinct(_field_vectors(K, vecs, twist))
    with pytest.MonkeyPatch.context() as mp:  # tiny primes force the exact fallbacks
        mp.setattr(obs, "_reduction", partial(_REDUCTION, start=start))
        found = obs._generator_hyperplanes(K, vectors, n)
    assert len(found) == len(set(found))
    if rank_rows(K, vectors, n) == n:
        assert set(found) == _brute_hyperplanes(K, vectors, n)


# -- element hyperplanes and outside counts against rank tests on every element set ---------------
from symkf.engine.search import outside_counts  # noqa: E402
from symkf.engine.stability import critical_loss_rate  # noqa: E402


def _random_system(n, d, seed):
    rng = np.random.default_rng(seed)
    A = [[int(v) for v in row] for row in rng.integers(-3, 4, (n, n))]
    return sk.System(A=A, sensors=[sk.Sensor(C=[[int(v) for v in rng.integers(-2, 3, n)]], name=f"s{j}")
                                   for j in range(d)])


ROT = sp.Matrix([[sp.cos(sp.pi / 3), -sp.sin(sp.pi / 3)], [sp.sin(sp.pi / 3), sp.cos(sp.pi / 3)]])
SYSTEMS = [
    lambda: sk.System(A=2 * ROT, sensors=[sk.Sensor(C=[[1, 0]], name="x"), sk.Sensor(C=[[1, 1]], name="y")]),
    lambda: sk.System(A=sp.diag(2 * ROT, 2), sensors=[sk.Sensor(C=[[1, 0, 1]], name="x"),
                                                      sk.Sensor(C=[[0, 1, 0], [0, 0, 1]], name="y")]),
    lambda: _random_system(3, 2, 1),
    lambda: _random_system(4, 2, 5),
]


@pytest.mark.parametrize("make", SYSTEMS, ids=["R(pi/3)", "R(pi/3)+2, two-row sensor", "dense 3x3", "dense 4x4"])
def test_hyperplanes_are_the_maximal_deficient_element_sets(make):
    for br in block_rows(make()):
        E = len(br.elements)
        if E > 12:
            continue
        deficient = [frozenset(s) for k in range(E + 1) for s in itertools.combinations(range(E), k)
                     if br.deficient(frozenset(s))]
        maximal = {s for s in deficient if not any(s < t for t in deficient)}
        assert set(br.hyperplanes) == maximal
        counts = {tuple(sum(1 for e in range(E) if br.elements[e].sensor == j and e not in H)
                        for j in range(1 + max(e.sensor for e in br.elements))) for H in br.hyperplanes}
        assert set(outside_counts(br)) == counts


@pytest.mark.parametrize("seed", [1, 5, 11])
def test_conjugate_pair_in_q_lambda_equals_the_full_field(seed):
    """A complex pair of a real system, worked in Q(lambda) (conjugating its second class), gives the
    same element hyperplanes and critical value as in Q(lambda, conj lambda)."""
    fast = _random_system(4, 2, seed)
    pairs = [br for br in block_rows(fast) if obs.is_conjugate_pair(fast, br.block)]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(obs, "is_conjugate_pair", lambda system, block: False)
        slow = _random_system(4, 2, seed)
        reference = [(br.hyperplanes, br.K.degree) for br in block_rows(slow)]
        assert critical_loss_rate(slow) == critical_loss_rate(fast)
    assert [br.hyperplanes for br in block_rows(fast)] == [h for h, _ in reference]
    assert pairs and all(br.K.degree < max(k for _, k in reference) for br in pairs)


@pytest.mark.full  # about 5 CPU-s on the shared machine
def test_critical_recovery_with_eight_gilbert_elliott_sensors():
    """Eight independent channels: per-sensor factors (no 2^8-state chain); the certificate inside
    critical_recovery_rate evaluates verdicts at rationals with huge numerators (margins as roots
    of q x^g - p, where sympy's root overflowed a float).  Checked again here on both sides."""
    from symkf.engine.stability import stability
    from symkf.engine.recovery import critical_recovery_rate
    rows = [[1, 0], [0, 1], [1, 1], [1, -1], [2, 1], [1, 2], [2, -1], [1, -2]]
    system = sk.System(A=2 * ROT, sensors=[sk.Sensor(C=[r], name=f"s{j}") for j, r in enumerate(rows)])
    fail = ["1/10"] * 8
    qc = critical_recovery_rate(system, fail)
    lo, hi = qc.refine(sp.Rational(1, 10 ** 6)).interval
    assert 0 < lo and hi < 1
    assert stability(system, sk.GilbertElliott(fail, [sp.Rational(hi) + sp.Rational(1, 10 ** 5)] * 8)).stable
    assert not stability(system, sk.GilbertElliott(fail, [sp.Rational(lo) - sp.Rational(1, 10 ** 5)] * 8)).stable


def test_twenty_sensors_decided_within_the_default_budget():
    # A = 2R(pi/2) (g = 2, alpha^(2g) = 16), sensors C_k = [1, k], k = 0..d-1.  The rows
    # [1, j] and C_k A ∝ [k, -1] are pairwise non-parallel (jk = -1 has no solution in
    # non-negative integers), so every hyperplane holds one of the 2d elements and
    # rho^g = eps^(2d - 1): margin^2 = 16 eps^(2d-1), critical eps = 2^(-4/(2d-1)).
    d = 20
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, k]], name=f"s{k}") for k in range(d)])
    v = sk.stability(S, sk.IID(["1/2"] * d))
    assert v.margins[0] == sp.sqrt(2) / 2 ** 18
    assert sk.critical_loss_rate(S) == sp.Integer(2) ** sp.Rational(-4, 2 * d - 1)
    # Gilbert-Elliott (fail 1/10, recover 1/2), states (received, lost), D = diag(0, 1): a sensor
    # lost at both phases has tr (P D)^2 = (1 - r)^2 = 1/4; the one kept at one phase has
    # tr(P D P) = 1/20 + 1/4 = 3/10, so margin^2 = 16 (1/4)^19 3/10 and margin = sqrt(30)/(10 2^17)
    ge = sk.stability(S, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d))
    assert ge.margins[0] == sp.sqrt(30) / (10 * 2 ** 17)
