"""Theorem 12 of Sui-You-Fu as printed and corrected: `symkf reproduce sui-theorem12`.

Usage: python examples/sui_theorem12.py [OUTDIR]   (prints the JSON report; writes the figure to OUTDIR)
Its checks (the corrected statement) are all true; where the printed statement fails, the
report lists a discrepancy with the printed and the computed critical loss rate.
"""

import json
import sys

from symkf.engine.second_order import reproduce_sui_theorem12

if __name__ == "__main__":
    report = reproduce_sui_theorem12(sys.argv[1] if len(sys.argv) > 1 else None)
    print(json.dumps(report, indent=2))
    raise SystemExit(0 if all(report["checks"].values()) else 1)
