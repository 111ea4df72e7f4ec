"""Issue 23, row 3: one eigen-block of modulus 2 over several cyclotomic fields (2R(2 pi/5) +
2R(2 pi/7) [+ 2R(2 pi/9) [+ 2R(2 pi/11)]]), 2 sensors, critical loss rate.  Targets: 3 fields
<= 10 CPU-s, 4 fields <= 60.  Usage: python bench_cyclotomic_fields.py [REPEATS]"""

import sys

from engine_rows import compare

compare("equal-modulus rotations in k cyclotomic fields, 2 sensors: critical_loss_rate", "critical",
        [("cyclotomic_fields", [2], 10), ("cyclotomic_fields", [3], 10)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 1, baseline_cap=120)
