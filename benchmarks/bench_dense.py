"""Issues 18 and 23, row 1: critical common i.i.d. loss rate of a dense random integer A (6x6 to
32x32; 3 random integer sensors).  Issue 18's targets: 8x8 <= 5 CPU-s, 12x12 <= 30 CPU-s; issue
23's: 24x24 <= 30 CPU-s, 32x32 <= 120 CPU-s (past main's max_dimension 16: caps raised for both).
Usage: python bench_dense.py [REPEATS]"""

import sys

from engine_rows import compare

big = {"max_dimension": 64}
compare("dense random integer A, 3 sensors: critical_loss_rate", "critical",
        [("dense", [6, 3], 5), ("dense", [8, 3], 5), ("dense", [12, 3], 30), ("dense", [16, 3], 30),
         ("dense", [20, 3], 30, big), ("dense", [24, 3], 30, big), ("dense", [32, 3], 120, big)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 1, baseline_cap=120)
