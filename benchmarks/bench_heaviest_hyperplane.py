"""I.i.d. verdict for one eigen-block of modulus 21/20 and dimension 4 (period 24)
with d = 4 ... 128 sensors (3072 elements at d = 128; about C(3072, 3) hyperplanes, so enumerating
them is out of reach): the decay rate needs only the heaviest hyperplanes (BlockRows.heaviest), and
the critical common loss rate only those holding the most elements (equal weights).
Targets: d = 64 <= 10 CPU-s, d = 128 <= 60 CPU-s and 1 GB.
Usage: python bench_heaviest_hyperplane.py [REPEATS]"""

import sys

from engine_rows import compare

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
compare("4-dim block of modulus 21/20, period 24: stability under i.i.d. losses 1/10", "stability",
        [("near_unit_block", [4], 2), ("near_unit_block", [8], 2), ("near_unit_block", [12], 10),
         ("near_unit_block", [16], 10)], repeats=repeats, baseline_cap=60)
compare("the same block: critical common i.i.d. loss rate", "critical",
        [("near_unit_block", [8], 2), ("near_unit_block", [16], 10), ("near_unit_block", [32], 10),
         ("near_unit_block", [64], 10), ("near_unit_block", [128], 60, {"max_sensors": 128})],
        repeats=repeats, baseline_cap=120)
