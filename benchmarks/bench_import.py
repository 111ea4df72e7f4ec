"""Import cost of symkf against sympy, each measured in a fresh interpreter.

Usage: python benchmarks/bench_import.py [--repeats N]

Every case runs in its own subprocess (nothing cached in ``sys.modules``), the cases interleaved
round by round so that load on the machine hits them alike; each prints its own CPU seconds
(``time.process_time``) and wall seconds for the timed statement. Reported: medians and the ratio
to ``import sympy`` measured in the same run. ``import symkf`` loads only ``symkf.errors``
(every public name is lazy); the first use of the core (``symkf.stability``: sympy, numpy,
python-flint and symkf's exact engine) is reported beside it, since that is what a real call pays.
Profile a case with ``python -X importtime -c "import symkf; symkf.stability"``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys

CASES = {
    "import sympy": "import sympy",
    "import symkf": "import symkf",
    "import symkf; symkf.System": "import symkf; symkf.System",
    "import symkf; symkf.stability (core)": "import symkf; symkf.stability",
    "import symkf; every public name": "import symkf; [getattr(symkf, n) for n in symkf.__all__]",
}

TIMER = """
import time, json
c, w = time.process_time(), time.perf_counter()
{stmt}
print(json.dumps([time.process_time() - c, time.perf_counter() - w]))
"""


def measure(stmt: str) -> tuple[float, float]:
    out = subprocess.run([sys.executable, "-c", TIMER.format(stmt=stmt)], capture_output=True, text=True,
                         check=True).stdout
    cpu, wall = json.loads(out.splitlines()[-1])
    return cpu, wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    samples: dict[str, list[tuple[float, float]]] = {name: [] for name in CASES}
    for _ in range(args.repeats):
        for name, stmt in CASES.items():
            samples[name].append(measure(stmt))
    base_cpu = statistics.median(c for c, _ in samples["import sympy"])
    base_wall = statistics.median(w for _, w in samples["import sympy"])
    print(f"{'case':40} {'CPU s':>8} {'ratio':>6} {'wall s':>8} {'ratio':>6}   (medians of {args.repeats})")
    for name, runs in samples.items():
        cpu = statistics.median(c for c, _ in runs)
        wall = statistics.median(w for _, w in runs)
        print(f"{name:40} {cpu:8.3f} {cpu / base_cpu:6.2f} {wall:8.3f} {wall / base_wall:6.2f}")


if __name__ == "__main__":
    main()
