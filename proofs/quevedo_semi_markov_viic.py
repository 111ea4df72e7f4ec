"""Quevedo-Ahlén-Johansson, Sec. VII-C: the semi-Markov example's claims.

Claims, for A = [[5/4, 0], [1, 11/10]], C1 = [1 1], holding times uniform on
1..5 (state 1) and 1..7 (state 2):
(a) [C1; C1 A^r] is invertible for r = 1..6;
(b) hence varrho(k_l) = 0 iff at most one packet arrives in the holding period;
(c) mu_i(k_l, 1) = 1 and eq. (34): Pr{sum gamma <= 1 | Xi = j, Delta = delta}
    = (1 - phi_{1|j})^delta + delta (1 - phi_{1|j})^(delta-1) phi_{1|j};
(d) the displayed condition after (34) equals (32) with (31) as printed.

Method: (a) exact determinants; (b) exhaustive over all 2^delta gamma sequences,
delta <= 7, exact ranks; (c) symbolic identity from symkf's dynamic programme
over row spaces, cross-checked by enumeration for delta <= 5; (d) symbolic
identity in phi_{1|1}, phi_{1|2}, q11, q21 with exact ||A^delta||^2.

Finding: (a)-(d) hold.  (The condition itself inherits the slip of eq. (31),
see quevedo_theorem2_counterexample.py; symkf reports both forms.)
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from symkf.network.reproduce import reproduce_quevedo_semi_markov  # noqa: E402


def main() -> bool:
    checks = reproduce_quevedo_semi_markov(simulate=False)["checks"]
    for claim, value in checks.items():
        print(("PASS" if value else "FAIL") + f": {claim}")
    ok = all(checks.values())
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)
