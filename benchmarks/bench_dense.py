"""Critical common i.i.d. loss rate of a dense random integer A (6x6 to 64x64; 3 random integer
sensors).  Targets: 8x8 <= 5 CPU-s, 12x12 <= 30 CPU-s, 24x24 <= 30 CPU-s, 32x32 <= 120 CPU-s, 48x48 <= 20
CPU-s and 64x64 <= 60 CPU-s.  Rows with ``big`` caps raise ``max_dimension`` and ``max_modulus_bits`` on
both sides, so that a baseline with lower caps runs them too (main: 48x48 in about 75 CPU-s, 64x64
past the 120 CPU-s limit); the last two rows run at the default caps, which main refuses.
Usage: python bench_dense.py [REPEATS]"""

import sys

from engine_rows import compare

big = {"max_dimension": 64, "max_modulus_bits": 2 ** 40}
compare("dense random integer A, 3 sensors: critical_loss_rate", "critical",
        [("dense", [6, 3], 5), ("dense", [8, 3], 5), ("dense", [12, 3], 30), ("dense", [16, 3], 30),
         ("dense", [20, 3], 30, big), ("dense", [24, 3], 30, big), ("dense", [32, 3], 120, big),
         ("dense", [40, 3], 60, big), ("dense", [48, 3], 20, big), ("dense", [64, 3], 60, big),
         ("dense", [48, 3], 20), ("dense", [64, 3], 60)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 1, baseline_cap=120)
