"""Elements of several generators (sensors of several rows, Jordan chains): the critical common
loss rate and the i.i.d. verdict (losses 1/5) from the heaviest-hyperplane screen, against main,
which lists every hyperplane (its max_hyperplanes cap raised in both: past its default 300 000 main
refuses every row).  Rows: a planar constant-velocity model beside an oscillator with 3, 4, 6
scalar sensors (C(36, 5) to C(72, 5) hyperplanes), two-row sensors on a period-24 rotation block
(C(192, 3), C(366, 3)).
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
