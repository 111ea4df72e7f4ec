"""symkf's extension of Sui-You-Fu to Jordan chains, singular A and detectable pairs.

Claim (docs/sui.md, "Beyond Sui-You-Fu"): for an eigen-block with Jordan chains the decay rate
``rho_i`` of ``P(R_N(i))`` is ``max_H rho_H`` over the hyperplanes of the generators
``C_j A^r B_c^s T_c`` (``B_c = A^g / c_c - I``), so stability is ``alpha_i^2 rho_i < 1`` as in
Theorems 4 and 7; modes with ``|lambda| < 1`` are set aside.

Method: (1) enumeration on the raw ``O_N`` by :mod:`symkf.engine.oracle` (no engine code): for losses
``eps_j = x^(w_j)`` the least lost weight ``L(N)`` of a deficient pattern has slope
``L(N + G) - L(N) = G e`` where the engine says ``rho = x^e``, on a family of defective, marginal,
singular and detectable systems; (2) exact ``P(R_N)`` of the constant-velocity tracker and of the
Jordan block ``[[6/5, 1], [0, 6/5]]`` (``C = [1 0]``) against the hand formula ``P(at most one
reception) = eps^N + N (1 - eps) eps^(N - 1)``; (3) simulation: ``divergence_test`` on the Jordan
block at ``eps = 3/5`` (margin ``108/125``, stable) and ``19/25`` (margin ``684/625``, unstable),
fixed seeds.  Status: checked.
"""

from __future__ import annotations

import sys
from fractions import Fraction
from math import lcm
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

import symkf as sk  # noqa: E402
from symkf.engine.search import outside_counts  # noqa: E402
from symkf.numeric.montecarlo import divergence_test  # noqa: E402
from symkf.engine.blocks import block_rows  # noqa: E402
from symkf.engine.oracle import RawRegression, decay_slope, iid_probability  # noqa: E402

R = sp.Rational
JORDAN_ROTATION = [[0, -2, 1, 0], [2, 0, 0, 1], [0, 0, 0, -2], [0, 0, 2, 0]]  # 2R(pi/2) with a chain

# (name, A, sensors' C, unstable subspace U (None: all), weights w_j, horizon N)
FAMILY = [
    ("constant velocity", [[1, 1], [0, 1]], [[[1, 0]]], None, (1,), 5),
    ("constant acceleration", [[1, 1, 0], [0, 1, 1], [0, 0, 1]], [[[1, 0, 0]]], None, (1,), 6),
    ("CV, position and velocity", [[1, 1], [0, 1]], [[[1, 0]], [[0, 1]]], None, (1, 2), 4),
    ("Jordan 6/5", [[R(6, 5), 1], [0, R(6, 5)]], [[[1, 0]]], None, (1,), 5),
    ("Jordan -2 (tau 2, g 1)", [[-2, 1], [0, -2]], [[[1, 1]]], None, (1,), 5),
    ("Jordan rotation, g = 2", JORDAN_ROTATION, [[[1, 0, 0, 0]]], None, (1,), 6),
    ("Jordan rotation, two sensors", JORDAN_ROTATION, [[[1, 0, 0, 0]], [[1, 0, 1, 0]]], None, (1, 2), 5),
    ("stable Jordan beside 2", [[2, 0, 0], [0, R(1, 2), 1], [0, 0, R(1, 2)]], [[[1, 1, 0]]],
     [[1], [0], [0]], (1,), 5),
    ("delayed output", [[2, 0], [1, 0]], [[[1, 0]]], [[2], [1]], (1,), 5),
    ("diag(2, 0)", [[2, 0], [0, 0]], [[[1, 1]]], [[1], [0]], (1,), 5),
    ("aperiodic Jordan rotation 2 R(theta), cos theta = 3/5", [[R(6, 5), R(-8, 5), 1, 0], [R(8, 5), R(6, 5), 0, 1],
                                                          [0, 0, R(6, 5), R(-8, 5)], [0, 0, R(8, 5), R(6, 5)]],
     [[[1, 0, 0, 0]]], None, (1,), 6),
    ("Jordan chain of 2 beside -2 (class period 2)", [[2, 1, 0], [0, 2, 0], [0, 0, -2]], [[[1, 0, 1]]], None, (1,), 6),
    ("unstable chain beside a nilpotent one", [[R(3, 2), 1, 0, 0], [0, R(3, 2), 0, 0], [0, 0, 0, 1],
                                               [0, 0, 0, 0]], [[[1, 0, 1, 0]]],
     [[1, 0], [0, 1], [0, 0], [0, 0]], (1,), 5),
]


def engine_exponent(S: sk.System, weights: tuple[int, ...]) -> Fraction:
    return min(Fraction(sum(w * k for w, k in zip(weights, ks)), br.class_period)
               for br in block_rows(S) if not br.block.is_stable for ks in outside_counts(br))


def main() -> bool:
    ok = True
    for name, A, Cs, U, w, N in FAMILY:
        S = sk.System(A=A, sensors=[sk.Sensor(C=C) for C in Cs])
        G = lcm(*(br.class_period for br in block_rows(S) if not br.block.is_stable))
        e = engine_exponent(S, w)
        slopes = decay_slope(A, Cs, w, N, G, U)
        good = slopes == (G * e, G * e)
        ok &= good
        print(f"{'ok ' if good else 'BAD'} {name}: engine rho = x^{e}, oracle slopes of L(N) over {G} steps {slopes}")
    eps = sp.Symbol("eps", positive=True)
    for A in ([[1, 1], [0, 1]], [[R(6, 5), 1], [0, R(6, 5)]]):
        for N in (4, 6, 8):
            P = RawRegression(A, [[[1, 0]]], N).probability(iid_probability([eps]))
            good = P == sp.expand(eps ** N + N * (1 - eps) * eps ** (N - 1))
            ok &= good
        print(f"{'ok ' if good else 'BAD'} A = {A}: P(R_N) = P(at most one reception), N = 4, 6, 8")
    S = sk.System(A=[["6/5", 1], [0, "6/5"]], sensors=[sk.Sensor(C=[[1, 0]])])
    for eps_value, expected in (("3/5", "stable"), ("19/25", "unstable")):
        verdicts = [divergence_test(S, sk.IID([eps_value]), seed=10 * s).verdict for s in range(5)]
        good = verdicts == [expected] * 5 and sk.stability(S, sk.IID([eps_value])).stable == (expected == "stable")
        ok &= good
        print(f"{'ok ' if good else 'BAD'} Jordan 6/5 at eps = {eps_value}: simulation {verdicts}, exact {expected}")
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
