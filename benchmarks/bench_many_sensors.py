"""``symkf analyze FILE --json`` for 2R(pi/12) with d = 4, 10, 20, 50 sensors
[1, j] and i.i.d. loss 1/2 (target d = 20 <= 5 CPU-s).  Usage: python bench_many_sensors.py [REPEATS]"""

import sys

from engine_rows import compare

compare("symkf analyze, 2R(pi/12), d sensors [1, j]", "analyze",
        [("many_sensors", [d], 5) for d in (4, 10, 20, 50)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3, baseline_cap=60)
