"""Issue 18, row 5: 2R(2 pi/p) with sensors x and y, critical loss rate, p = 7, 13, 19, 23, 97
(targets: p = 23 <= 1 CPU-s, p = 97 <= 10 CPU-s).  Usage: python bench_prime_rotation.py [REPEATS]"""

import sys

from engine_rows import compare

compare("rotation by 2 pi / p, 2 sensors: critical_loss_rate", "critical",
        [("prime_rotation", [p], 1 if p <= 23 else 10) for p in (7, 13, 19, 23, 97)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3, baseline_cap=60)
