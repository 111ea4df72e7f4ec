"""Reproduce the fusion paper (arXiv:2012.04896), Section 4 (inverted pendulum, 10 smart sensors, lossy channels).

Usage: python examples/fusion_pendulum.py [OUTDIR]   (writes the Fig. 2 / Fig. 3 PNGs to OUTDIR)
"""

import json
import sys

from symkf.fusion import reproduce_fusion_pendulum

if __name__ == "__main__":
    print(json.dumps(reproduce_fusion_pendulum(outdir=sys.argv[1] if len(sys.argv) > 1 else None), indent=2))
