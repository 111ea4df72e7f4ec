"""Regression rows, rank deficiency and projection (symkf.engine.rows; Sui-You-Fu eqs. 14-17,
Algorithm 1).

The modal form is exact; projecting a pattern onto one period of the governing period decides
rank deficiency for every pattern; the hyperplanes of the generators found through lines mod p
equal brute force over every (n-1)-subset (also with tiny primes, whose false zeros force the
exact fallbacks), are the maximal deficient element sets, and a conjugate pair worked in
Q(lambda) gives what the full field Q(lambda, conj lambda) gives."""

import itertools
from functools import partial

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from conftest import library, limited, rotation
from symkf.engine import rows as obs
from symkf.engine.blocks import block_deficient, block_rows
from symkf.engine.search import outside_counts
from symkf.engine.rows import modal_form, project
from symkf.engine.stability import critical_loss_rate
from symkf.exact.field import QQ_FIELD, NumberField
from symkf.exact.linalg import nullspace_rows, rank_rows
from symkf.exact.spectral import eigen_blocks


def rotation_entries(alpha, angle):
    c, s = sp.cos(angle), sp.sin(angle)
    return [[alpha * c, -alpha * s], [alpha * s, alpha * c]]


def test_modal_form_is_exact():
    A = sp.Matrix(rotation_entries(1, sp.pi / 6))
    (b,) = eigen_blocks(A)
    K, T, diag = modal_form(A, b)
    Ak = K.matrix(A)
    for i in range(2):
        for c in range(2):
            lhs = K.dot(Ak[i], [T[r][c] for r in range(2)])
            assert lhs == K.mul(T[i][c], diag[c])


@pytest.mark.parametrize("A,Cs", [
    ([[0, -2], [2, 0]], [[[1, 0]]]),
    (rotation_entries(1, sp.pi / 3), [[[1, 0]], [[1, 1]]]),
    ([["5/4", 0], [1, "11/10"]], [[[1, 1]]]),
])
def test_projection_decides_rank_for_every_pattern(A, Cs):
    """Algorithm 1 with the governing period: O_N^i deficient iff the projected pattern is."""
    import itertools
    S = sk.System(A=A, sensors=[sk.Sensor(C=C) for C in Cs])
    brs = block_rows(S)
    N = max(br.class_period for br in brs) + 2
    for pattern in itertools.product(itertools.product((1, 0), repeat=S.d), repeat=N):
        direct = block_deficient(S, pattern)
        for br, flag in zip(brs, direct):
            proj = project(pattern, br.class_period)
            idx = frozenset(br.elements.index(e) for e in proj)
            assert br.deficient(idx) == flag


# -- hyperplanes of the generators: flats grouped by lines mod p, against brute force --------------

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


# -- element hyperplanes and outside counts against rank tests on every element set ----------------

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


def test_the_generators_of_each_phase_span_the_class_parts_of_C_A_to_the_phase_T():
    """The generators of element (j, r), computed when asked (by index, by iteration, and mod p
    from the base generators and the step), span the class parts of C_j A^r T (A^r T = T D^r):
    a 4-dim block of period 12 with a sensor of two rows (two generators per class) and one of one."""
    S = sk.System(A=sp.diag(rotation(sp.pi / 6), rotation(sp.pi / 3)),
                  sensors=[sk.Sensor(C=[[1, 0, 2, 0], [0, 1, -1, 1]]), sk.Sensor(C=[[1, 1, 0, 3]])])
    (br,) = block_rows(S)
    K, n, g = br.K, br.size, br.class_period
    assert isinstance(br.generators, obs.PhaseGenerators) and g == 12
    iterated = list(br.generators)
    Ak, Ar = K.matrix(S.A), K.matrix(sp.eye(4))
    class_of = [c for c, members in enumerate(br.block.classes) for m in members]
    for r in range(g):
        for j, sensor in enumerate(S.sensors):
            e = br.elements.index(obs.Element(j, r))
            gens = br.generators[e]
            assert gens == iterated[e] and len(gens) == br.counts[e]
            rows = [K.vecmat(K.vecmat(row, Ar), br.T) for row in K.matrix(sensor.C)]
            parts = [[a if class_of[k] == c else 0 * a for k, a in enumerate(row)]
                     for c in range(len(br.block.classes)) for row in rows]
            assert rank_rows(K, list(gens), n) == rank_rows(K, parts, n) == rank_rows(K, [*gens, *parts], n)
        Ar = [K.vecmat(row, Ak) for row in Ar]
    points = br._points(range(len(br.elements)))
    assert obs._reduction(K, points) == obs._reduction(K, list(points))


def _rotation_critical(m: int) -> None:
    S = sk.System(A=rotation(2 * sp.pi / m), sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]])])
    # no two of the 2m elements' rows are parallel: the heaviest line holds one, 2m - 1 lie outside
    assert sk.critical_loss_rate(S).exact == sp.Integer(2) ** sp.Rational(-2 * m, 2 * m - 1)


def test_the_critical_rate_of_the_rotation_by_2_pi_over_797_takes_32_mb():
    """2R(2 pi/797): 1594 elements over a field of degree 1592.  Its rows are computed when asked
    and its heaviest lines counted from their members, so the critical rate fits in 32 MB beyond
    the parent's memory (stored, the rows and the lines' boolean rows over every element took
    memory growing as m^2: 64 MB here, 250 MB at m = 1601)."""
    code, err = limited(library, lambda: _rotation_critical(797), memory=32 * 1024 ** 2)
    assert code == 0, err


def test_normal_of_a_hyperplane_is_its_exact_normal_and_none_for_a_spanning_set():
    """diag(2R(pi/3), 2R(pi/2)) with one sensor (1, 0, 1, 0): period 12 over Q(zeta_12), one
    generator per element.  Every hyperplane's normal (by minors from generators independent mod
    p) is orthogonal to all its generators and spans the nullspace of an echelon form, and its
    image mod p in state coordinates vanishes where T times it does; the elements together span
    K^4: no normal."""
    A = sp.diag(sp.Matrix(rotation_entries(2, sp.pi / 3)), sp.Matrix(rotation_entries(2, sp.pi / 2)))
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0, 1, 0]])])
    (br,) = block_rows(S)
    K, n = br.K, br.size
    for H in br.hyperplanes:
        gens = [v for e in sorted(H) for v in br.generators[e]]
        normal = br.normal(H)
        assert all(K.dot(v, normal).is_zero() for v in gens)
        (exact,) = nullspace_rows(K, gens, n)
        assert rank_rows(K, [normal, exact], n) == 1
        _, u = br.state_normal_mod_p(H)
        assert [x != 0 for x in u.tolist()] == [not K.dot(row, normal).is_zero() for row in br.T]
    spanning = frozenset(e for e, gs in enumerate(br.generators) if gs)
    assert rank_rows(K, [v for e in spanning for v in br.generators[e]], n) == n
    assert br.normal(spanning) is None and br.state_normal_mod_p(spanning) is None


def test_a_hyperplane_holds_at_most_n_minus_one_consecutive_phases_of_a_sensor_seeing_every_mode():
    """diag(2R(pi/6), 2R(pi/4)) (n = 4, period 24): the row (1, 0, 1, 0) meets all four eigenvectors, so
    four consecutive phases span K^4 (a Vandermonde matrix in the eigenvalue ratios, times its
    nonzero coordinates) and a hyperplane holds at most 3 of them; the row (1, 0, 0, 0) sees one
    rotation only, and the hyperplane of the other's coordinates holds all its phases."""
    A = sp.diag(rotation(sp.pi / 6, 2), rotation(sp.pi / 4, 2))
    (br,) = block_rows(sk.System(A=A, sensors=[sk.Sensor(C=[[1, 0, 1, 0]]), sk.Sensor(C=[[1, 0, 0, 0]])]))
    assert br.longest_run(0) == 3 and br.longest_run(1) is None
    held = [H for H in br.hyperplanes if all(e in H for e, el in enumerate(br.elements) if el.sensor == 1)]
    assert held and max(_longest_cyclic_run(H, br, 0) for H in br.hyperplanes) == 3


def _longest_cyclic_run(H, br, sensor):
    phases = {br.elements[e].phase for e in H if br.elements[e].sensor == sensor}
    g = br.class_period
    return max((next(k for k in range(g + 1) if (r + k) % g not in phases or k == g)
                for r in phases if (r - 1) % g not in phases), default=0)


def test_eigenvector_of_a_plane_block_is_a_row_of_the_adjugate():
    """2 R(2 pi/7) - lam I at lam = 2 exp(2 pi i/7) over Q(zeta_28): the adjugate's row (-q, p) of
    the rows (p, q), (r, s) is (2 sin(2 pi/7), 2 cos(2 pi/7) - lam), and A v = lam v exactly; with a
    zero first row the second gives (s, -r); the zero matrix has none."""
    c, s = sp.cos(2 * sp.pi / 7), sp.sin(2 * sp.pi / 7)
    K = NumberField([c, s, sp.exp(2 * sp.pi * sp.I / 7)])
    A = K.matrix(2 * sp.Matrix([[c, -s], [s, c]]))
    lam = K.convert(2 * sp.exp(2 * sp.pi * sp.I / 7))
    M = [[(A[i][j] - lam) % K.modulus if i == j else A[i][j] for j in range(2)] for i in range(2)]
    (v,) = obs._plane_eigenvector(K, M)
    assert v == [-M[0][1], M[0][0]] and not v[0].is_zero()
    assert K.vecmat(v, [list(col) for col in zip(*A)]) == [K.mul(lam, a) for a in v]   # A v = lam v
    assert K.convert(2 * s) == v[0] and K.convert(2 * c - 2 * sp.exp(2 * sp.pi * sp.I / 7)) == v[1]
    zero, one = K.convert(0), K.convert(1)
    assert obs._plane_eigenvector(K, [[zero, zero], [one, K.convert(-3)]]) == [[K.convert(-3), K.convert(-1)]]
    assert obs._plane_eigenvector(K, [[zero, zero], [zero, zero]]) is None
