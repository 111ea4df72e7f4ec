"""One eigen-block of modulus 2 and dimension 4 (rotations by pi/6, pi/3; period 12)
with d = 2, 4, 6, 8 sensors (target d = 8 <= 2 CPU-s), and of dimension 6 (pi/6, pi/3, pi/2) with
3 sensors (target <= 10 CPU-s); critical loss rate.  Usage: python bench_rotation_block.py [REPEATS]"""

import sys

from engine_rows import compare

compare("4- and 6-dim blocks of period 12: critical_loss_rate", "critical",
        [("rotation_block", [2, 2], 2), ("rotation_block", [2, 4], 2), ("rotation_block", [2, 6], 2),
         ("rotation_block", [2, 8], 2), ("rotation_block", [3, 3], 10)],
        repeats=int(sys.argv[1]) if len(sys.argv) > 1 else 3)
