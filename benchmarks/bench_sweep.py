"""Wall time of a family sweep: serial (baseline) against jobs=2 local processes.

Family: A = 2 R(pi/g), governing period g = 2..8, 1..2 identical sensors (14 members), the
critical common i.i.d. loss rate of each (examples/families/rotation-periods.toml, cut down).
Each timed run is a fresh interpreter (cold sympy and symkf caches for both modes, so forked
workers do not inherit a warm cache); only ``family.evaluate`` is timed.  Prints medians over
REPEATS runs and the ratio.  Usage: python benchmarks/bench_sweep.py [REPEATS] [JOBS]
"""

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FAMILY = """
[family]
kind = "rotation"
[grid]
period = { from = 2, to = 8 }
sensors = [1, 2]
[constants]
alpha = "2"
"""


def one(path: str, jobs: int) -> None:
    """Child mode: time one evaluation and print the seconds and a digest of the exact results."""
    from symkf.families import load_family
    family = load_family(path)
    start = time.perf_counter()
    out = family.evaluate(jobs=jobs)
    print(time.perf_counter() - start, "|".join(str(o.value.exact) for o in out))


def main(repeats: int, jobs: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "family.toml"
        path.write_text(FAMILY)
        times: dict[int, list[float]] = {1: [], jobs: []}
        digests = set()
        for _ in range(repeats):
            for j in (1, jobs):
                run = subprocess.run([sys.executable, __file__, "--one", str(path), str(j)],
                                     capture_output=True, text=True, check=True)
                seconds, digest = run.stdout.split()
                times[j].append(float(seconds))
                digests.add(digest)
    serial, parallel = statistics.median(times[1]), statistics.median(times[jobs])
    print(f"family: 2 R(pi/g), g = 2..8, 1..2 sensors (14 members); {repeats} runs each")
    print(f"serial          median {serial:7.2f} s   runs {[round(t, 2) for t in times[1]]}")
    print(f"jobs={jobs:<2d}         median {parallel:7.2f} s   runs {[round(t, 2) for t in times[jobs]]}")
    print(f"speed-up serial / jobs={jobs}: {serial / parallel:.2f}x   identical exact results: {len(digests) == 1}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--one"]:
        one(sys.argv[2], int(sys.argv[3]))
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 3, int(sys.argv[2]) if len(sys.argv) > 2 else 2)
