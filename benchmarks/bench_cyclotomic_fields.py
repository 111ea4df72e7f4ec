"""One eigen-block of modulus 2 over several cyclotomic fields (2R(2 pi/5) +
2R(2 pi/7) [+ 2R(2 pi/9) [+ 2R(2 pi/11) [+ 2R(2 pi/13)]]]), 2 sensors: critical loss rate and the
i.i.d. verdict (losses 1/10), and the verdict of three fields under Gilbert-Elliott channels (fail
1/10, recover 1/2).  Targets: 3 fields <= 10 CPU-s, 4 fields <= 60, 5 fields <= 30 (and 1 GB), three
fields under Gilbert-Elliott <= 30, all at the default caps.  The rows past 2 fields run until
``CAP`` CPU seconds (default 120) on both sides.
Usage: python bench_cyclotomic_fields.py [REPEATS [CAP]]"""

import sys

from engine_rows import compare

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
cap = float(sys.argv[2]) if len(sys.argv) > 2 else 120
rows = [("cyclotomic_fields", [2], 10), ("cyclotomic_fields", [3], 10), ("cyclotomic_fields", [4], 60)]
compare("equal-modulus rotations in k cyclotomic fields, 2 sensors: critical_loss_rate", "critical",
        rows + [("cyclotomic_fields", [5], 30)], repeats=repeats, baseline_cap=cap, cap=cap)
compare("equal-modulus rotations in k cyclotomic fields, 2 sensors: stability(S, IID(1/10))", "stability",
        rows, repeats=repeats, baseline_cap=cap, cap=cap)
compare("equal-modulus rotations in 3 cyclotomic fields, 2 sensors: stability(S, GilbertElliott(1/10, 1/2))",
        "stability", [("cyclotomic_fields_ge", [3], 30)], repeats=repeats, baseline_cap=cap, cap=cap)
