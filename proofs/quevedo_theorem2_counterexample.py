"""Quevedo-Ahlén-Johansson, Theorem 2 (eq. 32) with mu_i from eq. (31): a counterexample.

Claim (Theorem 2): under Assumptions 2-3 with Delta_l <= sigma, if
max_i sum_delta mu_i(delta) sum_j psi_j(delta) q_ij ||Phi(k_l + delta, k_l)||^2 <= rho^sigma
for some rho in [0, 1), with mu_i(delta) = sum_j q_ij Pr{varrho = 0 | Xi(k_l) = j, Delta_l = delta}
(last line of eq. 31), the Kalman filter is exponentially bounded.

The slip: (31) replaces Pr{Xi(k_l) = j | Xi(k_l - 1) = i, Delta_l = delta} by q_ij,
but Delta_l is drawn from psi_{Xi(k_l)} (eq. 27), so this conditional law is
q_ij psi_j(delta) / sum_j' q_ij' psi_j'(delta).  Lemma 4's bound then reads
sum_delta sum_j q_ij psi_j(delta) pi_j(delta) ||Phi||^2, pi_j(delta) = Pr{varrho = 0 | Xi(k_l) = j, Delta_l = delta}.

Counterexample (scalar, exact): x(k+1) = (6/5) x(k) + w, y = x + v, Q = R = P0 = 1,
two network states with q_ij = 1/2, psi_1 = point mass at 1, psi_2 = point mass at 2
(sigma = 2), phi_{1|1} = 1 (always received), phi_{1|2} = 0 (never received),
Xi(0) from the stationary law (1/2, 1/2).
  * (32) as printed: lhs = a^2/4 + a^4/4 = 549/625 = rho^2 with rho = sqrt(549)/25 < 1.
  * corrected: lhs = a^4/2 = 648/625 > 1.
  * Truth: with probability (1/2)^m the first m jumps all enter state 2, no packet
    arrives in [0, 2m - 1] and P(2m | 2m-1) >= a^(4m) P0, so
    E tr P(2m | 2m-1) >= (a^4/2)^m = (648/625)^m -> infinity: not exponentially bounded.

Method: the two left-hand sides by symkf.network.theorem2 (exact, both forms)
and by hand; the lower bound is checked against the exact mean E P(k | k-1),
computed by exact rational enumeration of every network path up to k = 14.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf.network import NetworkLoss, PeriodicDynamics, SemiMarkovNetworkState, SensorTree, theorem2  # noqa: E402

a = sp.Rational(6, 5)


def model() -> tuple[NetworkLoss, PeriodicDynamics]:
    state = SemiMarkovNetworkState([["1/2", "1/2"], ["1/2", "1/2"]], [{1: 1}, {2: 1}])
    return NetworkLoss(SensorTree([0]), state, [[1, 0]]), PeriodicDynamics([[a]], [[[1]]])


def exact_mean_P(loss: NetworkLoss, horizon: int) -> list[sp.Rational]:
    """E P(k | k-1), k = 0..horizon-1, by exact enumeration over the lifted chain."""
    ch = loss.chain
    dist = {(s, sp.Integer(1)): ch.initial[0, s] for s in range(len(ch.states)) if ch.initial[0, s] != 0}
    means = []
    for _ in range(horizon):
        means.append(sum(p * P for (s, P), p in dist.items()))
        nxt: dict = {}
        for (s, P), p in dist.items():
            gamma = ch.emit[s][0]
            P1 = a ** 2 * P + 1 - (a ** 2 * P ** 2 / (P + 1) if gamma else 0)
            for s2 in range(len(ch.states)):
                if ch.P[s, s2] != 0:
                    nxt[(s2, P1)] = nxt.get((s2, P1), 0) + p * ch.P[s, s2]
        dist = nxt
    return means


def main() -> bool:
    loss, dyn = model()
    t2 = theorem2(loss, dyn)
    printed = sp.simplify(t2.lhs_paper[(1, 0)])
    corrected = sp.simplify(t2.lhs[(1, 0)])
    ok = printed == a ** 2 / 4 + a ** 4 / 4 == sp.Rational(549, 625) and t2.holds_paper is True
    print(("PASS" if ok else "FAIL") + f": (32) as printed gives {printed} < 1 (Theorem 2 would apply)")
    ok2 = corrected == a ** 4 / 2 == sp.Rational(648, 625) and t2.holds is False
    print(("PASS" if ok2 else "FAIL") + f": corrected left-hand side {corrected} > 1")
    means = exact_mean_P(loss, 15)
    bound_ok = all(means[2 * m] >= (a ** 4 / 2) ** m for m in range(1, 8))
    print(("PASS" if bound_ok else "FAIL") + ": E P(2m|2m-1) >= (648/625)^m for m = 1..7 (exact)")
    growing = all(means[k + 2] > means[k] for k in range(4, 12))
    print(("PASS" if growing else "FAIL") + f": E P(k|k-1) keeps growing: "
          + ", ".join(f"{float(v):.4g}" for v in means[::2]))
    result = ok and ok2 and bound_ok and growing
    print("PASS" if result else "FAIL")
    return result


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
