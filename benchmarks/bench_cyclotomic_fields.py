"""One eigen-block of modulus 2 over several cyclotomic fields (2R(2 pi/5) +
2R(2 pi/7) [+ 2R(2 pi/9) [+ 2R(2 pi/11)]]), 2 sensors: critical loss rate and the i.i.d. verdict
(losses 1/10).  Targets: 3 fields <= 10 CPU-s, 4 fields <= 60.  The rows past 2 fields run
until ``CAP`` CPU seconds (default 120) on both sides.
Usage: python bench_cyclotomic_fields.py [REPEATS [CAP]]"""

import sys

from engine_rows import compare

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
cap = float(sys.argv[2]) if len(sys.argv) > 2 else 120
for what, words in (("critical", "critical_loss_rate"), ("stability", "stability(S, IID(1/10))")):
    compare(f"equal-modulus rotations in k cyclotomic fields, 2 sensors: {words}", what,
            [("cyclotomic_fields", [2], 10), ("cyclotomic_fields", [3], 10), ("cyclotomic_fields", [4], 60)],
            repeats=repeats, baseline_cap=cap, cap=cap)
