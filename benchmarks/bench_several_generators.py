"""Elements of several generators (sensors of several rows, Jordan chains) and dense systems under
Gilbert-Elliott channels, against main (``SYMKF_BASELINE=DIR`` for an older checkout), the
listing's cap raised in both (``max_hyperplanes`` of a baseline, past its default 300 000 the listing
refused most rows; ``max_work`` here).

* i.i.d.: the critical common loss rate for a planar constant-velocity model beside an oscillator
  (one 6-dim block, Jordan chains) with 8, 16, 32 scalar sensors, and two-row sensors on the
  period-24 block diag(2R(pi/6), 2R(pi/4)) with 16, 64.
* Gilbert-Elliott verdicts (fail 1/10, recover 1/2): two-row sensors on that block, d = 8, 16, 64;
  the tracker beside the oscillator, d = 8, 16; two-row sensors on a 6-dim block of period 24,
  d = 8, 32, and on an 8-dim one, d = 4.
* The critical recovery rate (fail 1/10): two-row sensors, d = 4, 8, 16; the tracker, d = 8, 16;
  dense random integer A (irrational moduli) with n = 8, d = 3 / 8 and n = 12, d = 3.

Target (this machine, 2 cores): every row <= 10 CPU-s and <= 500 MB.
Usage: python bench_several_generators.py [REPEATS [CAP]]"""

import sys

from engine_rows import compare

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
cap = float(sys.argv[2]) if len(sys.argv) > 2 else 120
listing = {"max_hyperplanes": 10 ** 9, "max_work": 10 ** 7}
compare("elements of several generators: critical_loss_rate", "critical",
        [("tracker_oscillator", [d], 10, listing) for d in (8, 16, 32)]
        + [("two_row_rotations", [d], 10, listing) for d in (16, 64)], repeats=repeats, baseline_cap=cap, cap=cap)
compare("elements of several generators: stability(S, GilbertElliott(1/10, 1/2))", "stability",
        [("two_row_rotations_ge", [d], 10, listing) for d in (8, 16, 64)]
        + [("tracker_oscillator_ge", [d], 10, listing) for d in (8, 16)]
        + [("multi_row_six", [d], 10, listing) for d in (8, 32)] + [("multi_row_eight", [4], 10, listing)],
        repeats=repeats, baseline_cap=cap, cap=cap)
compare("critical_recovery_rate(S, fail=1/10)", "recovery",
        [("two_row_rotations_ge", [d], 10, listing) for d in (4, 8, 16)]
        + [("tracker_oscillator_ge", [d], 10, listing) for d in (8, 16)]
        + [("dense_ge", [n, d], 10, listing) for n, d in ((8, 3), (8, 8), (12, 3))],
        repeats=repeats, baseline_cap=cap, cap=cap)
