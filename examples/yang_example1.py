"""Yang et al., Example 1 (Fig. 2): G_k <= E[P_k^-] <= V_k for n = 2, N = 8.

Usage: python examples/yang_example1.py [--paths M] [--outdir DIR]
"""

import argparse
import json

from symkf.capacity import reproduce_yang_example1

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paths", type=int, default=20_000)
    parser.add_argument("--outdir", default=None)
    args = parser.parse_args()
    out = reproduce_yang_example1(args.outdir, paths=args.paths)
    print(json.dumps(out, indent=2))
    raise SystemExit(0 if all(out["checks"].values()) else 1)
