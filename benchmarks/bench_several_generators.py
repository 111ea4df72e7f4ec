"""Elements of several generators (sensors of several rows, Jordan chains) against main, the
max_hyperplanes cap raised in both (past its default 300 000 the old listing refused every row).

* The heaviest-hyperplane screen: the critical common loss rate and the i.i.d. verdict (losses 1/5)
  for a planar constant-velocity model beside an oscillator with 3, 4, 6 scalar sensors (C(36, 5)
  to C(72, 5) hyperplanes), two-row sensors on a period-24 rotation block (C(192, 3), C(366, 3)).
* The listing through the elements' flats: Gilbert-Elliott verdicts (fail 1/10, recover 1/2) and
  the critical recovery rate of two-row sensors on the period-24 block, d = 2, 3, 4, 8.

Usage: python bench_several_generators.py [REPEATS [CAP]]"""

import sys

from engine_rows import compare

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
cap = float(sys.argv[2]) if len(sys.argv) > 2 else 120
listing = {"max_hyperplanes": 10 ** 9}
for what, words in (("critical", "critical_loss_rate"), ("stability", "stability(S, IID(1/5))")):
    compare(f"elements of several generators: {words}", what,
            [("tracker_oscillator", [3], 30, listing), ("tracker_oscillator", [4], 30, listing),
             ("tracker_oscillator", [6], 30, listing), ("two_row_rotations", [4], 30, listing),
             ("two_row_rotations", [8], 30, listing)],
            repeats=repeats, baseline_cap=cap, cap=cap)
for what, words in (("stability", "stability(S, GilbertElliott(1/10, 1/2))"),
                    ("recovery", "critical_recovery_rate(S, fail=1/10)")):
    compare(f"two-row sensors, period 24: {words}", what,
            [("two_row_rotations_ge", [d], 30, listing) for d in (2, 3, 4, 8)],
            repeats=repeats, baseline_cap=cap, cap=cap)
