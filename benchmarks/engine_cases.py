"""The systems of the exact-engine benchmark rows (:mod:`engine_rows`), shared by the benchmark scripts.

Each builder returns ``(System, loss)``; sizes are parameters so a script can sweep them.
Random data come from ``numpy.random.default_rng(seed)`` (fixed seeds: the same systems every run).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

import symkf as sk


def _rotation(angle: sp.Expr, scale: sp.Expr = 1) -> sp.Matrix:
    return scale * sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


def _sensors(rows: list[list[int]]) -> list[sk.Sensor]:
    return [sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)]


def _random_rows(rng: np.random.Generator, d: int, n: int) -> list[list[int]]:
    return [[int(v) for v in rng.integers(-2, 3, n)] for _ in range(d)]


def dense(n: int, d: int = 3, seed: int = 0) -> tuple[sk.System, sk.IID]:
    """Dense random integer A (entries -3..3) and d random integer sensor rows."""
    rng = np.random.default_rng(seed)
    A = [[int(v) for v in row] for row in rng.integers(-3, 4, (n, n))]
    return sk.System(A=A, sensors=_sensors(_random_rows(rng, d, n))), sk.IID(["1/10"] * d)


def rotation_stack(d: int = 3, seed: int = 0, hard: int = 0) -> tuple[sk.System, sk.IID]:
    """n = 8: rotations by pi/2, pi/3, pi/4, pi/6 scaled by 2, 3, 4, 5 (four moduli, four periods);
    ``hard=1``: by 2 pi/5, 2 pi/7, pi/4, pi/6 (entries from four different fields)."""
    angles = [2 * sp.pi / 5, 2 * sp.pi / 7, sp.pi / 4, sp.pi / 6] if hard else [sp.pi / 2, sp.pi / 3, sp.pi / 4, sp.pi / 6]
    blocks = [_rotation(a, k + 2) for k, a in enumerate(angles)]
    rng = np.random.default_rng(seed)
    return sk.System(A=sp.diag(*blocks), sensors=_sensors(_random_rows(rng, d, 8))), sk.IID(["1/10"] * d)


def rotation_block(k: int, d: int, seed: int = 0) -> tuple[sk.System, sk.IID]:
    """One eigen-block of modulus 2 and dimension 2k: rotations by pi/6, pi/3, pi/2 (first k), period 12."""
    blocks = [_rotation(sp.pi / 6, 2), _rotation(sp.pi / 3, 2), _rotation(sp.pi / 2, 2)][:k]
    rng = np.random.default_rng(seed)
    return sk.System(A=sp.diag(*blocks), sensors=_sensors(_random_rows(rng, d, 2 * k))), sk.IID(["1/10"] * d)


def near_unit_block(d: int) -> tuple[sk.System, sk.IID]:
    """One eigen-block of modulus 21/20 and dimension 4 (21/20 R(pi/3), 21/20 R(pi/4); period 24)
    with d random integer sensor rows, losses 1/10: bench_simulate's ``system(4, d)``."""
    rows = np.random.default_rng(400 + d).integers(-2, 3, (d, 4))
    rows[np.all(rows == 0, axis=1), 0] = 1
    A = sp.diag(_rotation(sp.pi / 3, sp.Rational(21, 20)), _rotation(sp.pi / 4, sp.Rational(21, 20)))
    return sk.System(A=A, sensors=_sensors([[int(v) for v in r] for r in rows])), sk.IID(["1/10"] * d)


def prime_rotation(p: int) -> tuple[sk.System, sk.IID]:
    """2 R(2 pi / p) with sensors x and y (the engine's field has degree 2(p - 1))."""
    return sk.System(A=_rotation(2 * sp.pi / p, 2), sensors=_sensors([[1, 0], [0, 1]])), sk.IID(["1/10"] * 2)


def many_sensors(d: int) -> tuple[sk.System, sk.IID]:
    """2 R(pi/12) with sensors [1, j] for j = 0..d-1 (the README example grown to d sensors)."""
    A = _rotation(sp.pi / 12, 2)
    return sk.System(A=A, sensors=_sensors([[1, j] for j in range(d)])), sk.IID(["1/2"] * d)


def gilbert_elliott(d: int, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """2 R(pi/3) (period 6) with d random integer sensor rows, fail 1/10, recover 1/2."""
    rng = np.random.default_rng(seed)
    rows = []
    while len(rows) < d:
        r = [int(v) for v in rng.integers(-2, 3, 2)]
        if any(r):
            rows.append(r)
    system = sk.System(A=_rotation(sp.pi / 3, 2), sensors=_sensors(rows))
    return system, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d)


def cyclotomic_fields(k: int, seed: int = 0) -> tuple[sk.System, sk.IID]:
    """One eigen-block of modulus 2 over k cyclotomic fields: 2R(2 pi/5), 2R(2 pi/7), 2R(2 pi/9),
    2R(2 pi/11), 2R(2 pi/13) (the first k), with 2 random integer sensor rows (``bench_cyclotomic_fields.py``)."""
    blocks = [_rotation(2 * sp.pi / q, 2) for q in (5, 7, 9, 11, 13)][:k]
    rng = np.random.default_rng(seed)
    return sk.System(A=sp.diag(*blocks), sensors=_sensors(_random_rows(rng, 2, 2 * k))), sk.IID(["1/10"] * 2)


def cyclotomic_fields_ge(k: int, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """:func:`cyclotomic_fields` under Gilbert-Elliott channels (fail 1/10, recover 1/2 each)."""
    system, _ = cyclotomic_fields(k, seed)
    return system, sk.GilbertElliott(["1/10"] * 2, ["1/2"] * 2)


def tracker_oscillator(d: int, seed: int = 0) -> tuple[sk.System, sk.IID]:
    """A planar constant-velocity model at modulus 2 beside an oscillator of the same modulus,
    diag(J_2(2), J_2(2), 2R(pi/3)) (one 6-dim eigen-block with Jordan chains, period 6), with d
    random integer scalar sensors, losses 1/5."""
    J = sp.Matrix([[2, 1], [0, 2]])
    rng = np.random.default_rng(seed)
    return (sk.System(A=sp.diag(J, J, _rotation(sp.pi / 3, 2)), sensors=_sensors(_random_rows(rng, d, 6))),
            sk.IID(["1/5"] * d))


def two_row_rotations(d: int, seed: int = 0) -> tuple[sk.System, sk.IID]:
    """The 4-dim block diag(2R(pi/6), 2R(pi/4)) (period 24) with d random integer sensors of two
    rows each, losses 1/5."""
    rng = np.random.default_rng(seed)
    sensors = [sk.Sensor(C=_random_rows(rng, 2, 4), name=f"s{j + 1}") for j in range(d)]
    return (sk.System(A=sp.diag(_rotation(sp.pi / 6, 2), _rotation(sp.pi / 4, 2)), sensors=sensors),
            sk.IID(["1/5"] * d))


def two_row_rotations_ge(d: int, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """:func:`two_row_rotations` under Gilbert-Elliott channels (fail 1/10, recover 1/2 each)."""
    system, _ = two_row_rotations(d, seed)
    return system, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d)


def dense_ge(n: int, d: int = 3, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """:func:`dense` under Gilbert-Elliott channels (fail 1/10, recover 1/2 each): irrational moduli."""
    system, _ = dense(n, d, seed)
    return system, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d)


def tracker_oscillator_ge(d: int, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """:func:`tracker_oscillator` under Gilbert-Elliott channels (fail 1/10, recover 1/2 each)."""
    system, _ = tracker_oscillator(d, seed)
    return system, sk.GilbertElliott(["1/10"] * d, ["1/2"] * d)


def multi_row_six(d: int, rows: int = 2, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """The 6-dim block diag(2R(pi/6), 2R(pi/4), 2R(pi/3)) (period 24) with d random integer sensors of
    ``rows`` rows each, on Gilbert-Elliott channels (fail 1/10, recover 1/2 each)."""
    rng = np.random.default_rng(seed)
    sensors = [sk.Sensor(C=_random_rows(rng, rows, 6), name=f"s{j + 1}") for j in range(d)]
    A = sp.diag(_rotation(sp.pi / 6, 2), _rotation(sp.pi / 4, 2), _rotation(sp.pi / 3, 2))
    return sk.System(A=A, sensors=sensors), sk.GilbertElliott(["1/10"] * d, ["1/2"] * d)


def multi_row_eight(d: int, rows: int = 2, seed: int = 0) -> tuple[sk.System, sk.GilbertElliott]:
    """The 8-dim block diag(2R(pi/6), 2R(pi/4), 2R(pi/3), 2R(pi/2)) (period 24) with d random integer
    sensors of ``rows`` rows each, on Gilbert-Elliott channels (fail 1/10, recover 1/2 each)."""
    rng = np.random.default_rng(seed)
    sensors = [sk.Sensor(C=_random_rows(rng, rows, 8), name=f"s{j + 1}") for j in range(d)]
    A = sp.diag(*[_rotation(a, 2) for a in (sp.pi / 6, sp.pi / 4, sp.pi / 3, sp.pi / 2)])
    return sk.System(A=A, sensors=sensors), sk.GilbertElliott(["1/10"] * d, ["1/2"] * d)


PAIR = {(1, 1): {(1, 1): "4/5", (1, 0): "1/20", (0, 1): "1/20", (0, 0): "1/10"},
        (1, 0): {(1, 1): "1/2", (1, 0): "1/5", (0, 1): "1/10", (0, 0): "1/5"},
        (0, 1): {(1, 1): "1/2", (1, 0): "1/10", (0, 1): "1/5", (0, 0): "1/5"},
        (0, 0): {(1, 1): "2/5", (1, 0): "1/10", (0, 1): "1/10", (0, 0): "2/5"}}


def correlated_pairs(d: int, seed: int = 0) -> tuple[sk.System, sk.Independent]:
    """The 4-dim block diag(2R(pi/6), 2R(pi/4)) (period 24) with d random integer sensor rows in d/2
    pairs, each pair on a bursty shared channel of its own (a joint Markov chain, :data:`PAIR`)."""
    rng = np.random.default_rng(seed)
    A = sp.diag(_rotation(sp.pi / 6, 2), _rotation(sp.pi / 4, 2))
    return (sk.System(A=A, sensors=_sensors(_random_rows(rng, d, 4))),
            sk.Independent([sk.MarkovLoss(PAIR) for _ in range(d // 2)]))


def radical_matrix(seed: int, n: int = 6, density: float = 0.7) -> sp.Matrix:
    """A non-negative n x n matrix over Q(sqrt 2, sqrt 3, sqrt 5): each entry is 0 (probability
    1 - density) or ``a + b sqrt 2 + c sqrt 3 + d sqrt 5`` with ``a`` in 0..3, ``b, c, d`` in
    {-1, -1/2, 0, 1/2, 1} (their conjugates may be negative), redrawn until it is >= 1/100."""
    rng = np.random.default_rng(seed)
    roots = (sp.sqrt(2), sp.sqrt(3), sp.sqrt(5))
    halves = [sp.Rational(k, 2) for k in range(-2, 3)]

    def entry() -> sp.Expr:
        if rng.random() >= density:
            return sp.Integer(0)
        while True:
            v = int(rng.integers(0, 4)) + sum(halves[int(rng.integers(0, 5))] * r for r in roots)
            if v.evalf(30) >= sp.Rational(1, 100):
                return v
    return sp.Matrix(n, n, [entry() for _ in range(n * n)])


def radical_perron(seed: int, n: int = 6) -> tuple[sp.Matrix, None]:
    """:func:`radical_matrix` as a benchmark case (a matrix, no loss model): its Perron root."""
    return radical_matrix(seed, n), None


def two_rotations(d: int, seed: int = 0) -> tuple[sk.System, sk.IID]:
    """One eigen-block of modulus 2 and dimension 4, diag(2R(pi/6), 2R(pi/4)) (period 24), with d
    random non-zero integer sensor rows and losses 1/10 (``bench_heaviest_hyperplane.py``: d up to 128)."""
    rows = np.random.default_rng(600 + seed).integers(-2, 3, (d, 4))
    rows[np.all(rows == 0, axis=1), 0] = 1
    A = sp.diag(_rotation(sp.pi / 6, 2), _rotation(sp.pi / 4, 2))
    return sk.System(A=A, sensors=_sensors([[int(v) for v in r] for r in rows])), sk.IID(["1/10"] * d)
