"""Critical common i.i.d. loss rate of a dense random integer A (6x6 to 32x32; 3 random integer
sensors).  Targets: 8x8 <= 5 CPU-s, 12x12 <= 30 CPU-s, 24x24 <= 30 CPU-s, 32x32 <= 120 CPU-s
(``max_dimension`` raised on both sides, so that a baseline with a lower cap runs them too).
Usage: python bench_dense.py [REPEATS]"""

import sys

from engine_rows import compare

big = {"max_dimension": 64}
compare("dense random integer A, 3 sensors: critical_loss_rate", "critical",
        [("dense", [6, 3], 5), ("dense", [8, 3], 5), ("dense", [12, 3], 30), ("dense", [16, 3], 30),
         ("dense", [20, 3], 30, big), ("dense", [24, 3], 30, big), ("dense", [32, 3], 120, big)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 1, baseline_cap=120)
