"""Quevedo-Ahlén-Johansson, Example 3: the set J and Pr{r(k) = 1 | Xi = j}.

Claim: for the tree of Fig. 4 (S1, S2 -> S0; S3 -> S1; S4, S5 -> S2) and the
rule "C(k) is full rank iff at least three of y1..y5 reach the gateway",
r(k) = 1 iff gamma(k) lies in the printed nine-vector set J, and
Pr{r = 1 | Xi = j} is the printed nine-term polynomial in phi_{1|j}..phi_{5|j}.

Method: exhaustive check over all 32 link-outcome vectors, twice: with the
rule on theta (Remark 2: theta_m = product of gamma over Edge(Path(S_m))), and
with the exact rank of C(k) (eq. 14) for C_m = [1, m, m^2] (n = 3; any three
rows are independent, so the rank realises the rule).  The polynomial is
compared with the sum over J as a symbolic identity (sympy expand).

Finding: J and the polynomial are as printed.  (Fig. 4's caption says
"M = 6 nodes": that counts the gateway; M = 5 sensors.)
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf.network import MarkovNetworkState, NetworkLoss, full_rank_configurations, full_rank_probability
from symkf.network.reproduce import EXAMPLE3_J, example3_dynamics, example3_printed_polynomial, example3_tree  # noqa: E402


def main() -> bool:
    tree = example3_tree()
    by_rule = full_rank_configurations(tree, rule=lambda theta: sum(theta) >= 3)
    by_rank = full_rank_configurations(tree, example3_dynamics())
    ok = by_rule == EXAMPLE3_J and by_rank == EXAMPLE3_J
    print(("PASS" if ok else "FAIL") + f": J has {len(by_rank)} vectors, printed J has {len(EXAMPLE3_J)}")
    for j in (1, 2):
        loss = NetworkLoss(tree, MarkovNetworkState([["1/2", "1/2"], ["1/2", "1/2"]]), "symbols")
        diff = sp.expand(full_rank_probability(by_rank, list(loss.phi.col(j - 1))) - example3_printed_polynomial(j))
        print(("PASS" if diff == 0 else "FAIL") + f": Pr{{r = 1 | Xi = {j}}} equals the printed polynomial")
        ok &= diff == 0
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
