"""The windowed hyperplane screen (hyperplane_screen.stages with cycles: every cycle a stage, greedy
bases drawn from a window after the anchor, its length from the pigeonhole bound on a seeded lower
bound) against the plain screen (stages by orbits, every basis), on configurations with a phase
shift built mod p: points ``v_j * omega^(e t)`` for ``t`` in ``Z/g``, with weights per cycle."""

import math

import numpy as np
import sympy
from hypothesis import given, settings, strategies as st

from symkf.engine import hyperplane_screen as hs



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


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10 ** 6))
def test_windowed_screen_finds_what_the_plain_screen_finds(seed):
    """Same heaviest weight, same hyperplanes at it (up to the shift), and the windowed plan's
    work estimate bounds what its search does (C(W, n - 4) passes of at most W C incidences)."""
    X, weights, cycles = _configuration(seed)
    n = X.shape[1]
    if _rank(X) < n:
        return
    plain = _plain(X, weights, cycles)
    screen = hs.Screen(1e-9 * (1 + weights.sum()))
    hs.seed(X, weights, P, cycles, screen)
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
    assert counted[0] <= hs.work(X, P, plan, cap=0)
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
    hs.seed(X, weights, p, cycles, screen)
    assert screen.best >= 63
    windowed = hs.stages(X, weights, p, cycles, set(), screen.bar, cycles)
    plain = hs.stages(X, weights, p, cycles, set(), screen.bar)
    assert all(s.window is not None and s.window < 60 for s in windowed)
    assert 100 * hs.work(X, p, windowed, cap=0) < hs.work(X, p, plain, cap=0)
