"""Issue 18, row 1: critical common i.i.d. loss rate of a dense random integer A (8x8, 10x10, 12x12;
3 random integer sensors).  Targets: 8x8 <= 5 CPU-s, 12x12 <= 30 CPU-s.  Usage: python bench_dense.py [REPEATS]"""

import sys

from engine_rows import compare

compare("dense random integer A, 3 sensors: critical_loss_rate", "critical",
        [("dense", [6, 3], 5), ("dense", [8, 3], 5), ("dense", [10, 3], 30), ("dense", [12, 3], 30)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3, baseline_cap=60)
