"""2R(2 pi/p) with sensors x and y, critical loss rate, p = 7 ... 401 (targets: p = 23 <= 1 CPU-s,
p = 97 <= 10 CPU-s, p = 401 <= 30 CPU-s within the default caps; the rows past p = 127 raise the
cyclotomic and angle caps on both sides, so that a baseline with lower caps runs them too).
Usage: python bench_prime_rotation.py [REPEATS]"""

import sys

from engine_rows import compare

raised = {"max_cyclotomic_degree": 4096, "max_angle_denominator": 4096}
compare("rotation by 2 pi / p, 2 sensors: critical_loss_rate", "critical",
        [("prime_rotation", [p], 1 if p <= 23 else 10) for p in (7, 13, 19, 23, 97)]
        + [("prime_rotation", [199], 30, raised), ("prime_rotation", [401], 30, raised)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 1, baseline_cap=120)
