"""Gilbert-Elliott verdict for 2R(pi/3) (period 6) with d = 2..16 random sensors
(targets: d = 8 <= 2 CPU-s, d = 16 <= 5 CPU-s).  Usage: python bench_gilbert_elliott.py [REPEATS]"""

import sys

from engine_rows import compare

compare("Gilbert-Elliott (fail 1/10, recover 1/2), period 6: stability", "stability",
        [("gilbert_elliott", [d], 2 if d <= 8 else 5) for d in (2, 4, 6, 8, 16)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3, baseline_cap=60)
