"""An n = 8 stack of four rotation blocks with four moduli, 3 sensors, critical loss rate
(target <= 2 CPU-s): rotations by pi/2, pi/3, pi/4, pi/6 (entries in Q(sqrt 2, sqrt 3)), and by
2 pi/5, 2 pi/7, pi/4, pi/6 (entries in four different fields: Q(zeta_20)^+, Q(zeta_28)^+, Q(sqrt 2),
Q(sqrt 3), whose compositum has degree 96).  Usage: python bench_rotation_stack.py [REPEATS]"""

import sys

from engine_rows import compare

compare("2R(t1) + 3R(t2) + 4R(t3) + 5R(t4), 3 sensors: critical_loss_rate", "critical",
        [("rotation_stack", [3, 0, 0], 2), ("rotation_stack", [3, 0, 1], 2)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3, baseline_cap=60)
