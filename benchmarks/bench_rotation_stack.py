"""Issue 18, row 2: n = 8 stack of four rotation blocks with four moduli, 3 sensors, critical loss rate
(target <= 2 CPU-s).  Usage: python bench_rotation_stack.py [REPEATS]"""

import sys

from engine_rows import compare

compare("2R(pi/2) + 3R(pi/3) + 4R(pi/4) + 5R(pi/6), 3 sensors: critical_loss_rate", "critical",
        [("rotation_stack", [3], 2)], repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3)
