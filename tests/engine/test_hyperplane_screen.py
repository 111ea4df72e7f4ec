"""The hyperplane screen mod p (symkf.engine.hyperplane_screen): the windowed screen against the
plain one, its work estimate against the work it does, and the cap on that estimate.

The windowed screen (stages with cycles: every cycle a stage, greedy bases drawn from a window
after the anchor, its length from the pigeonhole bound on a seeded lower bound) is checked
against the plain screen (stages by orbits, every basis) on configurations with a phase shift
built mod p: points ``v_j * omega^(e t)`` for ``t`` in ``Z/g``, with weights per cycle."""

from __future__ import annotations

import math
import re
import resource

import numpy as np
import pytest
import sympy
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf import budget, cli
from symkf.engine import hyperplane_screen as hs
from symkf.errors import BudgetError

from conftest import limited, rotation


def _field(order: int, start: int) -> tuple[int, int]:
    """A prime ``p = 1 mod order`` above ``start`` and an element of order ``order`` mod p."""
    p = next(q for q in range(start - start % order + 1, 10 ** 9, order) if sympy.isprime(q))
    root = next(x for x in range(2, p) if all(pow(x, (p - 1) // q, p) != 1 for q in sympy.primefactors(p - 1)))
    return p, pow(root, (p - 1) // order, p)


P, OMEGA = _field(420, 10 ** 6)  # 420 = lcm of the periods below


def _configuration(seed: int):
    rng = np.random.default_rng(seed)
    g = int(rng.choice([6, 12, 15, 21]))
    n, d = int(rng.integers(4, 7)), int(rng.integers(1, 4))
    omega = pow(OMEGA, 420 // g, P)
    half = [int(rng.integers(1, g)) for _ in range(n // 2)]  # conjugate pairs omega^(+-e), as rotations give
    exponents = np.array([*half, *[g - e for e in half], *([0] if n % 2 else [])])
    rows = rng.integers(-2, 3, (d, n)) % P
    rows[rng.random((d, n)) < 0.25] = 0  # unseen coordinates: heavier hyperplanes
    rows[rows.sum(axis=1) == 0, 0] = 1
    phases = np.array([[pow(omega, int(e) * t, P) for e in exponents] for t in range(g)], dtype=np.int64)
    X = np.concatenate([rows[j][None, :] * phases % P for j in range(d)])
    cycles = [list(range(j * g, (j + 1) * g)) for j in range(d)]
    weights = np.repeat(rng.choice([1.0, 1.0, 2.0, 0.5], d), g)
    return X, weights, cycles


def _hyperplane_orbits(screen: hs.Screen, X: np.ndarray, cycles, n: int) -> set:
    """The kept sets of rank n - 1 (hyperplanes, not lower flats) up to the phase shift."""
    g, out = len(cycles[0]), set()
    for S in screen.kept:
        if _rank(X[sorted(S)]) < n - 1:
            continue
        out.add(min(tuple(sorted((e // g) * g + (e % g + s) % g for e in S)) for s in range(g)))
    return out


def _rank(Y: np.ndarray) -> int:
    import flint
    return flint.nmod_mat(Y.tolist(), P).rank()


def _plain(X, weights, cycles):
    screen = hs.Screen(1e-9 * (1 + weights.sum()))
    assert hs.search(X, weights, P, hs.stages(X, weights, P, [sorted(c) for c in cycles], set(), -np.inf), screen)
    return screen


def _class_work(X, p, plan):
    """hyperplane_screen.work counted from every stage's classes: under a cap just below the bound
    from the stages' point counts (under a lower cap it stops at the first stage past it)."""
    from symkf.engine import hyperplane_screen as hs
    return hs.work(X, p, plan, cap=hs.work(X, p, plan, cap=10 ** 30) - 1)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_windowed_screen_finds_what_the_plain_screen_finds(seed):
    """Same heaviest weight, same hyperplanes at it (up to the shift), and the windowed plan's
    work estimate bounds what its search does (C(W, n - 4) passes, C(W, n - 3) flats each against at
    most C classes)."""
    X, weights, cycles = _configuration(seed)
    n = X.shape[1]
    if _rank(X) < n:
        return
    plain = _plain(X, weights, cycles)
    screen = hs.Screen(1e-9 * (1 + weights.sum()))
    hs.lower_bound(X, weights, P, cycles, screen)
    plan = hs._windowed(X, weights, P, cycles, screen.bar)
    if plan is None:  # no window shorter than the cycle: stages() keeps the plain plan
        return
    counted, inner = [0], hs._lines_through_points

    def counting(reps, *args):
        counted[0] += min(args[-1], len(reps)) * len(reps) + hs.PASS
        return inner(reps, *args)
    hs._lines_through_points = counting
    try:
        assert hs.search(X, weights, P, plan, screen)
    finally:
        hs._lines_through_points = inner
    assert counted[0] <= _class_work(X, P, plan)
    assert math.isclose(screen.best, plain.best, rel_tol=0, abs_tol=1e-9)
    assert _hyperplane_orbits(screen, X, cycles, n) == _hyperplane_orbits(plain, X, cycles, n)


def test_windows_shorten_the_search_on_a_heavy_coset():
    """Exponents of diag(2R(2 pi/5), 2R(2 pi/7), 2R(2 pi/9)) in Z/315 (omega^63, omega^45,
    omega^35 and their inverses) with 2 sensors, mod a prime = 1 mod 315: a normal on the first
    two coordinates holds the 63 points of a coset of 5 Z/315 for each sensor, so the seeds bound
    the heaviest weight by >= 63 and the window is a few dozen positions; the estimated work falls
    more than 100-fold, and the search still returns a hyperplane at least that heavy."""
    p, omega = _field(315, 10 ** 8)
    exponents = [63, 315 - 63, 45, 315 - 45, 35, 315 - 35]
    rows = np.array([[1, 2, -1, 1, 2, 1], [2, -1, 1, 1, -2, 1]]) % p
    phases = np.array([[pow(omega, e * t, p) for e in exponents] for t in range(315)], dtype=np.int64)
    X = np.concatenate([row[None, :] * phases % p for row in rows])
    cycles, weights = [list(range(315)), list(range(315, 630))], np.ones(630)
    screen = hs.Screen(1e-9 * 631)
    hs.lower_bound(X, weights, p, cycles, screen)
    assert screen.best >= 63
    windowed = hs.stages(X, weights, p, cycles, set(), screen.bar, cycles)
    plain = hs.stages(X, weights, p, cycles, set(), screen.bar)
    assert all(s.window is not None and s.window < 60 for s in windowed)
    assert 100 * _class_work(X, p, windowed) < _class_work(X, p, plain)


# -- the work estimate and its cap --------------------------------------------------------------

def _screen_config(n: int, count: int, seed: int = 0, p: int = 10007):
    import numpy as np
    rng = np.random.default_rng(seed)
    return rng.integers(0, p, (count, n)).astype(np.int64), p


@pytest.mark.parametrize("n, count", [(4, 30), (5, 16), (6, 12)])
def test_screen_work_estimate_bounds_the_search(monkeypatch, n, count):
    """hyperplane_screen.work bounds what search does: per call of _lines_through_points with C
    classes, C(C, 2) incidences plus one pass, counted here by wrapping it; equality at n = 4
    (no deeper quotient merges classes, weights 0 prune nothing), and the bound from the stages'
    point counts is never below the one from their classes; once the count passes the cap it stops."""
    import math

    from symkf.engine import hyperplane_screen as hs
    X, p = _screen_config(n, count)
    orbits = [[i] for i in range(count)]
    counted = [0]
    inner = hs._lines_through_points

    def counting(reps, *args):
        counted[0] += math.comb(len(reps), 2) + hs.PASS
        return inner(reps, *args)
    monkeypatch.setattr(hs, "_lines_through_points", counting)
    import numpy as np
    plan = hs.stages(X, np.zeros(count), p, orbits, set(), -np.inf)
    assert hs.search(X, np.zeros(count), p, plan, hs.Screen(1e-9))
    rough = hs.work(X, p, plan, cap=10 ** 30)
    exact = _class_work(X, p, plan)
    assert counted[0] <= exact <= rough
    if n == 4:
        assert counted[0] == exact
    # under a cap the classes pass at once, the count stops at the first stage: a lower bound above it
    first = hs.work(X, p, plan[:1], cap=0)
    assert 0 < first == hs.work(X, p, plan, cap=0) <= exact


def _rotation_pair(rows):
    c6, s6, c3, s3 = sp.cos(sp.pi / 6), sp.sin(sp.pi / 6), sp.cos(sp.pi / 3), sp.sin(sp.pi / 3)
    A = sp.diag(2 * sp.Matrix([[c6, -s6], [s6, c6]]), 2 * sp.Matrix([[c3, -s3], [s3, c3]]))
    return sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows])


def test_screen_work_refused_up_front_naming_the_cap():
    """One 4-dim eigen-block of modulus 2 (period 12) with 3 sensors: 36 elements, 3 orbits; the
    screen's estimate (its points classified, sum C(C, 2) + 10^4 incidences per stage) is above a
    cap of 1 CPU-ms, so the decay rate is refused before the screen runs (under the default cap it runs: tests/engine/test_heaviest_hyperplane.py)."""
    S = _rotation_pair([[1, 0, 1, 0], [0, 1, 1, 1], [1, 2, 0, 1]])
    with budget.limits(max_work=1):
        with pytest.raises(BudgetError, match=r"eigen-block of modulus 2: the estimated work of the hyperplane "
                                              r"screen \(36 elements in dimension 4, 3 orbits.*--max-work"):
            sk.stability(S, sk.IID(["1/10"] * 3))
    assert sk.stability(S, sk.IID(["1/10"] * 3)).stable


def _eight_rotations_file(tmp_path):
    """Eight 2R(pi/97) blocks (one 16-dim eigen-block: every eigenvalue 2 exp(+-i pi/97), each
    eight times) with 64 Gilbert-Elliott sensors, random rows in -3..3 (fixed seed)."""
    import random
    rng = random.Random(0)
    c, s = "2*cos(pi/97)", "2*sin(pi/97)"
    A = [["0"] * 16 for _ in range(16)]
    for b in range(8):
        i = 2 * b
        A[i][i], A[i][i + 1], A[i + 1][i], A[i + 1][i + 1] = c, f"-{s}", s, c
    rows = "\n".join("[[sensors]]\nC = [[" + ", ".join(f'"{rng.randint(-3, 3)}"' for _ in range(16)) + "]]"
                     for _ in range(64))
    fail = ", ".join(f'"{rng.randint(1, 9)}/10"' for _ in range(64))
    recover = ", ".join(f'"{rng.randint(1, 9)}/10"' for _ in range(64))
    path = tmp_path / "eight.toml"
    path.write_text("[system]\nA = [" + ", ".join("[" + ", ".join(f'"{v}"' for v in r) + "]" for r in A) + "]\n"
                    + rows + f'\n[loss]\nkind = "gilbert-elliott"\nfail = [{fail}]\nrecover = [{recover}]\n')
    return path


@pytest.mark.full
def test_eight_identical_rotation_blocks_refused_naming_the_screen_cap(tmp_path):
    """This ran past 120 CPU-s in the screen's 13-level flat recursion (6208 elements in
    dimension 16, 64 orbits: about 10^42 incidences, and the Markov search's two screens are priced
    together); now refused once the block's elements are
    reduced mod p (about 6 CPU-s, 4 of them the exact generators C_j T D^r over Q(zeta_388))."""
    path = _eight_rotations_file(tmp_path)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    code, err = limited(cli.main, ["analyze", str(path)])
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert code == 2 and err.count("\n") == 1, err
    assert "6208 elements in dimension 16, 64 orbits" in err and "2 such screens" in err and "--max-work" in err, err
    # about 10^36 CPU-s counted over every stage; the count stops once past the cap (a lower bound)
    assert int(re.search(r"is about 10\^(\d+) CPU-s", err).group(1)) >= 30, err
    assert after.ru_utime - before.ru_utime < 15


@pytest.mark.full
def test_rotations_in_three_cyclotomic_fields_critical_loss_rate():
    """diag(2R(2 pi/5), 2R(2 pi/7), 2R(2 pi/9)): one eigen-block of modulus 2, period 315, two
    sensors whose rows are parallel on the 2R(2 pi/9) coordinates.  A normal h on those coordinates
    has c_j A^k h = 2^k c_j^(9) R^k h^(9) = 0 at one residue k mod 9 (9 is odd: the angles 2 pi k / 9
    are distinct mod pi) for both sensors: 35 + 35 = 70 of the 630 elements.  With that heaviest
    weight the critical common loss rate is 2^(-2 * 315 / (630 - 70)) = 2^(-9/8); the screen without
    windows (9.3e9 incidences, its cap raised) gave the same in 3660 CPU-s."""
    A = sp.diag(*(rotation(2 * sp.pi / q, 2) for q in (5, 7, 9)))
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[2, 1, 0, -1, -1, -2]]), sk.Sensor(C=[[-2, -2, -2, 2, 1, 2]])])
    assert sp.simplify(sk.critical_loss_rate(S).exact - 2 ** sp.Rational(-9, 8)) == 0


def test_windowed_stage_work_counts_its_flats_against_every_class():
    """A stage of C = 100 classes at n = 6 with a window of 10: its greedy bases are increasing
    chains of 3 window classes, C(10, 3) = 120 flats each against at most 100 classes, and
    C(10, 2) = 45 vectorised passes; at n = 4 one pass of 10 flats.  Without a window the chains
    run over all classes: C(100, 4) incidences and C(100, 2) passes."""
    assert hs._stage_work(100, 6, 10) == 120 * 100 + 45 * hs.PASS
    assert hs._stage_work(100, 4, 10) == 10 * 100 + hs.PASS
    assert hs._stage_work(100, 6) == math.comb(100, 4) + math.comb(100, 2) * hs.PASS


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 40), st.integers(1, 4), st.sampled_from([2, 5, 7, 10007, (1 << 27) + 29]), st.randoms())
def test_groups_of_residue_rows_are_numpys_unique_rows(rows, width, p, rnd):
    """The packed lexsort gives np.unique's first rows and groups (rows drawn with repeats)."""
    Y = np.array([[rnd.randrange(min(p, 3)) if rnd.random() < 0.5 else rnd.randrange(p) for _ in range(width)]
                  for _ in range(rows)], dtype=np.int64)
    Y = np.concatenate([Y, Y[::2]])
    _, first, inverse = np.unique(Y, axis=0, return_index=True, return_inverse=True)
    got_first, got_inverse = hs._groups(Y, p)
    assert got_first.tolist() == first.tolist() and got_inverse.tolist() == inverse.ravel().tolist()


@settings(max_examples=30, deadline=None)
@given(st.integers(2, 60), st.integers(0, 3), st.floats(0.5, 4.0), st.randoms())
def test_lines_above_a_finite_bar_are_every_line_that_reaches_it(count, planted, floor, rnd):
    """In the plane F_p^3 (classes: distinct projective points, lines through a point b among the
    later classes), the sets kept at a finite bar (the heavy buckets only grouped) are those of
    every line through some b that weighs at least the bar, found by brute force (collinear iff
    the 3 x 3 determinant vanishes mod p); lines with many points are planted, and with few
    classes the buckets (key mod 2^k, above the classes' count) collide."""
    p = 10007
    points = {(1, 0, 0), (0, 1, 0), *(_canonical([rnd.randrange(p) for _ in range(3)], p) for _ in range(count))} - {None}
    for _ in range(planted):   # the points of a line through two of them
        u, v = (np.array(rnd.choice(sorted(points))) for _ in range(2))
        points |= {_canonical(((s * u + v) % p).tolist(), p) for s in rnd.sample(range(p), 5)} - {None}
    reps = np.array(sorted(points), dtype=np.int64)
    C = len(reps)
    w = np.array([rnd.choice([0.0, 0.5, 1.0, 1.5]) for _ in range(C)])
    lim = rnd.randint(1, C)
    screen = hs.Screen(1e-9, floor, strict=True)
    hs._lines_through_points(reps, w, np.arange(C), [np.array([c]) for c in range(C)], [], 0.0, p, screen, lim)
    expected = set()
    for b in range(lim):
        later = list(range(b + 1, C))
        while later:
            c = later[0]
            line = [d for d in later if _det(*(reps[i].tolist() for i in (b, c, d))) % p == 0]
            later = [d for d in later if d not in line]
            if w[b] + w[line].sum() >= floor - 1e-9:
                expected.add(frozenset([b, *line]))
        if b == C - 1 and w[b] >= floor - 1e-9:
            expected.add(frozenset([b]))
    assert set(screen.kept) == expected


def _canonical(v: list[int], p: int) -> tuple[int, ...] | None:
    """The representative of the projective point of ``v`` with first nonzero coordinate 1 (None for 0)."""
    lead = next((a for a in v if a % p), None)
    return None if lead is None else tuple(a * pow(lead, -1, p) % p for a in v)


def _det(u: list[int], v: list[int], x: list[int]) -> int:
    return u[0] * (v[1] * x[2] - v[2] * x[1]) - u[1] * (v[0] * x[2] - v[2] * x[0]) + u[2] * (v[0] * x[1] - v[1] * x[0])


@pytest.mark.parametrize("size", [1, 999, 1000, 2570, 40 * 64 ** 2 + 7])
def test_inverses_mod_p_by_powers_and_by_batches_of_runs(size):
    """Every entry times its inverse is 1 mod p, below the batch trick's threshold (1000 entries),
    at it, at the screens' 2570 and past 64 runs; a 2-d shape is kept."""
    p = (1 << 27) + 29
    y = np.random.default_rng(size).integers(1, p, size)
    assert (y * hs.inverses(y, p) % p == 1).all()
    Y = np.stack([y, y[::-1]])
    assert hs.inverses(Y, p).shape == Y.shape and (Y * hs.inverses(Y, p) % p == 1).all()
