"""2R(2 pi/m) with sensors x and y, critical loss rate, m = 7 ... 1601 (targets: m = 23 <= 1 CPU-s,
m = 97 <= 10 CPU-s, m = 401 <= 30 CPU-s, m = 1601 <= 20 CPU-s and 600 MB, all within the default
caps; main refused m >= 797 at its defaults, so the rows m >= 199 also run with the cyclotomic and
angle caps raised on both sides, where main's time is measured).
Usage: python bench_prime_rotation.py [REPEATS]"""

import sys

from engine_rows import compare

raised = {"max_cyclotomic_degree": 4096, "max_angle_denominator": 4096}
compare("rotation by 2 pi / m, 2 sensors: critical_loss_rate", "critical",
        [("prime_rotation", [p], 1 if p <= 23 else 10) for p in (7, 13, 19, 23, 97)]
        + [("prime_rotation", [m], 20) for m in (401, 797, 1601)]
        + [("prime_rotation", [m], 20, raised) for m in (199, 401, 797, 1601)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 1, baseline_cap=200)
