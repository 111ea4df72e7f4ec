"""The atlas figure of docs/bounds.md: every applicable published result and the exact critical
loss of ``A = 2 R(theta)``, ``C = [1 0]`` against the rotation angle ``theta = pi p/q``.

Usage: ``python examples/bounds_atlas_figure.py OUT.png [--max-denominator Q] [--lmi-steps N] [--force]``
(needs the ``plot`` extra).  The file is written atomically (``symkf.output``).
"""

from __future__ import annotations

import argparse

from symkf import output
from symkf.bounds.figure import atlas_figure, rotation_family


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--max-denominator", type=int, default=6)
    p.add_argument("--lmi-steps", type=int, default=5)
    p.add_argument("--force", action="store_true")
    args = p.parse_args()
    target = output.plan(args.out, "OUT", force=args.force)
    fig = atlas_figure(rotation_family(2, args.max_denominator), lmi_steps=args.lmi_steps)
    print(f"wrote {target.put_figure(fig, dpi=110)}")


if __name__ == "__main__":
    main()
