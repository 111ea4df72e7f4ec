"""Write LaTeX (booktabs) tables of exact critical loss rates and of the example verdicts.

Usage: python examples/critical_table.py [OUT.tex] [--family FAMILY.toml] [--jobs N] [--scheduler ADDRESS]

The default family is the shipped rotation-periods (A = 2 R(pi/g), governing period
g = 2..12, 1..4 identical sensors; ``symkf table rotation-periods`` prints the same table);
--jobs N evaluates its members in N processes.  OUT.tex holds two ``table`` environments;
``\\input`` it in a document that loads booktabs.
"""

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from symkf import examples, output  # noqa: E402
from symkf.reports.tables import family_table, verdict_table  # noqa: E402

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="critical_table.tex")
    parser.add_argument("--family", default=str(examples.family("rotation-periods")))
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://host:8786")
    args = parser.parse_args()
    # symkf's writer, checked before the work: atomic, never over the family file nor through a link
    target = output.plan(args.out, "OUT.tex", inputs=[args.family])
    family = family_table(args.family, jobs=args.jobs, scheduler=args.scheduler)
    verdicts = verdict_table(jobs=args.jobs, scheduler=args.scheduler)
    out = target.put_text(family.to_latex() + "\n" + verdicts.to_latex())
    print(family)
    print()
    print(verdicts)
    print(f"\nwrote {out.resolve()} (needs \\usepackage{{booktabs}})")
