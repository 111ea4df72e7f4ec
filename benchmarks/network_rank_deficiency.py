"""Speed of pi_j(delta) = Pr{O(k + delta - 1, k) rank deficient | Xi = j} (Quevedo et al., Theorem 2).

symkf's dynamic programme over exact row spaces against the brute-force
enumeration of every theta sequence (baseline), in the same process.
Prints median seconds over repeats and the ratio.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from symkf.network import (MarkovNetworkState, NetworkLoss, PeriodicDynamics, SensorTree,
                           rank_deficiency_probabilities, rank_deficiency_probability_by_enumeration)
from timing import median_time  # noqa: E402


def main() -> None:
    dyn = PeriodicDynamics([["5/4", 0], [1, "11/10"]], [[[1, 1]], [[0, 1]]])
    loss = NetworkLoss(SensorTree([0, 1]), MarkovNetworkState([[1]]), [["9/10"], ["1/2"]])
    print("delta  dp_median_s  enumeration_median_s  ratio")
    for delta in (3, 4, 5, 6):
        dp = median_time(lambda: rank_deficiency_probabilities(loss, dyn, 1, delta))
        en = median_time(lambda: rank_deficiency_probability_by_enumeration(loss, dyn, 1, delta))
        print(f"{delta:5d}  {dp:11.4f}  {en:20.4f}  {en / dp:6.1f}")


if __name__ == "__main__":
    main()
