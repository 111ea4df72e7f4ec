"""The cost of a listed hyperplane's margin (``budget.COSTS["margin"]`` and ``["symbolic margin"]``): per
row, the critical recovery rate's list step (route ``flint``, :func:`symkf.engine.recovery.listed_margins`:
every hyperplane listed, its margin polynomial built in flint, the distinct ones kept) or the symbolic
stable set's margins (route ``sympy``, :func:`symkf.engine.region.ge_margins`), timed on its own in a fresh
interpreter, beside the price (``BlockRows.listing_estimate`` margins at the route's unit, plus the
listing's ``hyperplane degree`` units) and the ratio measured / priced, which should stay within 3x
either way.  Rows: blocks of
dimension 4 (period 24 over a field of degree 8, period 35 over one of degree 48) and 6 (period 12),
sensors of one row and of two.
Usage: python bench_margin_cost.py [ROW[:ROUTE] ...]   (default: every row in flint but ``six``, about
15 CPU-s; ``period35-d2:sympy`` about 7 CPU-s)"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: row -> (system builder, its arguments, fail rates)
ROWS = {
    "period24-d4": ("bench_markov_search.system", [4], ["3/5", "1/2", "3/5", "9/10"]),
    "period24-d6": ("bench_markov_search.seeded", [6], ["1/10"] * 6),
    "period35-d2": ("bench_margin_cost.rotations_5_7", [2], ["1/10", "1/5"]),
    "period35-d3": ("bench_margin_cost.rotations_5_7", [3], ["1/10", "1/5", "3/10"]),
    "two-row-d4": ("engine_cases.two_row_rotations_ge", [4], None),
    "six": ("bench_markov_search.six", [], ["1/2", "1/2", "3/10"]),
}


def rotations_5_7(d: int):
    """2R(2 pi/5) + 2R(2 pi/7): one eigen-block of period 35 over a field of degree 48, seen by d
    sensors in general position (rows of seed 35)."""
    import numpy as np
    import sympy as sp
    import symkf as sk

    def rotation(q):
        return 2 * sp.Matrix([[sp.cos(2 * sp.pi / q), -sp.sin(2 * sp.pi / q)], [sp.sin(2 * sp.pi / q), sp.cos(2 * sp.pi / q)]])
    rows = np.random.default_rng(35).integers(1, 4, (d, 4)) * np.array([1, -1, 1, -1])
    return sk.System(A=sp.diag(rotation(5), rotation(7)),
                     sensors=[sk.Sensor(C=[[int(v) for v in r]], name=f"s{j + 1}") for j, r in enumerate(rows)])


def _child(row: str, route: str) -> None:
    sys.path[:0] = [str(HERE.parent), str(HERE)]
    import importlib
    import sympy as sp
    import symkf as sk
    from symkf import budget
    from symkf.engine import recovery, search
    from symkf.engine.blocks import block_rows
    name, args, fail = ROWS[row]
    module, fn = name.rsplit(".", 1)
    built = getattr(importlib.import_module(module), fn)(*args)
    system = built[0] if isinstance(built, tuple) else built
    fail = [sp.Rational(f) for f in (fail or built[1].fail)]
    brs = block_rows(system)
    margins = sum(br.listing_estimate()[0] for br in brs)
    listing = sum(br.listing_estimate()[0] * br.K.degree for br in brs)
    start = time.process_time()
    with budget.limits(max_work=10 ** 9):
        if route == "flint":
            out = recovery.listed_margins(system, fail, None, None)
        else:   # the symbolic margins in sympy (symkf.engine.region.ge_margins), one per hyperplane
            from symkf.engine.region import ge_margins
            q = sp.Symbol("q", positive=True)
            out = [(None, ge_margins(system, sk.GilbertElliott(fail, [q] * system.d)))]
    cpu = time.process_time() - start
    listed = sum(len(search.listed_hyperplanes(br)) for br in brs)
    unit = "margin" if route == "flint" else "symbolic_margin"
    priced = budget.seconds(**{unit: margins}, hyperplane_degree=listing)
    print(json.dumps({"row": row, "cpu": cpu, "estimated": margins, "listed": listed,
                      "rates": sum(len(r) for _, r in out), "priced": priced,
                      "us_per_margin": 1e6 * cpu / margins}))


def main(rows: list[str]) -> None:
    import subprocess
    print(f"{'row':<14}{'route':<7}{'margins':>10}{'listed':>10}{'CPU s':>8}{'priced s':>10}{'ratio':>7}{'us/margin':>11}")
    for row, route in (r.split(":") if ":" in r else (r, "flint") for r in rows):
        out = subprocess.run([sys.executable, __file__, "--child", row, route], capture_output=True, text=True)
        if out.returncode:
            print(f"{row:<14}{route:<7} failed: {(out.stderr.strip().splitlines() or ['?'])[-1]}")
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{row:<14}{route:<7}{r['estimated']:>10}{r['listed']:>10}{r['cpu']:>8.2f}{r['priced']:>10.2f}"
              f"{r['cpu'] / r['priced']:>7.2f}{r['us_per_margin']:>11.1f}", flush=True)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        _child(sys.argv[2], sys.argv[3])
    else:
        main(sys.argv[1:] or [r for r in ROWS if r != "six"])
