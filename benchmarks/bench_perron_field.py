"""Exact Perron roots of 6 x 6 non-negative matrices over Q(sqrt 2, sqrt 3, sqrt 5)
(:func:`engine_cases.radical_matrix`, seeds 0..), through ``symkf.engine.rates.perron_root``.
Target: <= 1 CPU-s each.  Usage: python bench_perron_field.py [SEEDS [REPEATS [BASELINE_CAP]]]"""

import sys

from engine_rows import compare

seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 5
compare("Perron roots of 6 x 6 matrices over Q(sqrt 2, sqrt 3, sqrt 5)", "perron",
        [("radical_perron", [s], 1) for s in range(seeds)],
        repeats=int(sys.argv[2]) if len(sys.argv) > 2 else 1,
        baseline_cap=float(sys.argv[3]) if len(sys.argv) > 3 else 60)
