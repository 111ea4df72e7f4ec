"""Reproduce Quevedo, Ahlén, Johansson: `symkf reproduce quevedo-robot`.

Usage: python examples/quevedo_robot.py [OUTDIR]   (prints the JSON report; writes the figure to OUTDIR)
"""

import json
import sys

from symkf.network.reproduce import reproduce_quevedo_robot

if __name__ == "__main__":
    report = reproduce_quevedo_robot(sys.argv[1] if len(sys.argv) > 1 else None)
    print(json.dumps(report, indent=2))
    raise SystemExit(0 if all(report["checks"].values()) else 1)
