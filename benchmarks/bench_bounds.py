"""``symkf.bounds``, the atlas of the field's published bounds beside the exact critical value
(its LMI bisection with exact certificates, Theorem 5's Mahler measures), on systems of the
sizes users bring: a dense random integer 8-state A with 8 sensors (i.i.d. losses 1/5), and a
planar tracker beside an oscillator of the same modulus with 16 sensors.  CPU seconds and peak
RSS of fresh interpreters against main (``engine_rows.compare``; ``SYMKF_BASELINE=DIR`` for a
fixed checkout of main), the exact rows' digests compared.  The 120 CPU-s per atlas printed as
each row's target is this benchmark's own.
Usage: python bench_bounds.py [REPEATS [CAP]]"""

import sys

from engine_rows import compare

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 1
cap = float(sys.argv[2]) if len(sys.argv) > 2 else 300
compare("symkf.bounds: the published bounds' atlas", "bounds",
        [("dense", [8, 8], 120), ("tracker_oscillator", [16], 120)],
        repeats=repeats, baseline_cap=cap, cap=cap)
