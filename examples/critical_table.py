"""Write the LaTeX (booktabs) table of a family's exact critical loss rates.

Usage: python examples/critical_table.py [OUT.tex] [--family FAMILY.toml] [--jobs N] [--scheduler ADDRESS]

The default family is the shipped rotation-periods (A = 2 R(pi/g), governing period
g = 2..12, 1..4 identical sensors); the table is the one ``symkf table rotation-periods
--latex OUT.tex`` writes.  --jobs N evaluates its members in N processes.  ``\\input`` OUT.tex
in a document that loads booktabs.
"""

import argparse

from symkf import examples, output
from symkf.reports.tables import family_table

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="critical_table.tex")
    parser.add_argument("--family", default=str(examples.family("rotation-periods")))
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://host:8786")
    args = parser.parse_args()
    # symkf's writer, checked before the work: atomic, never over the family file nor through a link
    target = output.plan(args.out, "OUT.tex", inputs=[args.family])
    table = family_table(args.family, jobs=args.jobs, scheduler=args.scheduler)
    out = target.put_text(table.to_latex())
    print(table)
    print(f"\nwrote {out.resolve()} (needs \\usepackage{{booktabs}})")
