"""Sweeps in parallel: target ``--jobs 2`` >= 1.7x serial on 2 cores for a family of >= 8 members.

Family: A = 2 R(pi/g) for the primes g = 59..97 (8 members, cyclotomic degree 2(g - 1) up to
192) with three sensors [1, 0], [0, 1], [1, 1], the critical common i.i.d. loss rate of each:
members take 0.5 to 1.5 CPU-s, so the sweep measures the work, not the workers' fixed cost.
Each timed run is a fresh interpreter (cold sympy and symkf caches for both modes); only
``family.evaluate`` is timed.  The fixed cost of the parallel mode is measured on its own with
a family of trivial members (A = 2, one sensor).  Prints medians over REPEATS runs of wall time
and of CPU time (parent plus workers) and their ratios: on a machine whose cores are busy with
other work the wall-clock gain shrinks, the CPU ratio shows the overhead of the parallel mode
itself.  Usage: python benchmarks/bench_sweep.py [REPEATS] [JOBS]   (about 1 minute with 3 repeats)
"""

import os
import resource
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
period = [59, 61, 67, 71, 73, 79, 83, 97]
[constants]
alpha = "2"
[[sensors]]
C = [["1", "0"]]
[[sensors]]
C = [["0", "1"]]
[[sensors]]
C = [["1", "1"]]
"""

TRIVIAL = """
[family]
[grid]
a = { from = 2, to = 9 }
[system]
A = [["a"]]
[[sensors]]
C = [["1"]]
"""


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the pool's workers)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def one(path: str, jobs: int) -> None:
    """Child mode: time one evaluation; print wall and CPU seconds and a digest of the exact results."""
    from symkf.io.families import load_family
    family = load_family(path)
    start, cpu = time.perf_counter(), _cpu()
    out = family.evaluate(jobs=jobs)
    print(time.perf_counter() - start, _cpu() - cpu, "|".join(str(o.value.exact) for o in out))


def _measure(text: str, repeats: int, jobs: int) -> tuple[dict, dict, bool]:
    """Wall and CPU seconds of ``repeats`` serial and ``jobs`` runs (alternating), and whether the
    exact results agree."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "family.toml"
        path.write_text(text)
        times: dict[int, list[float]] = {1: [], jobs: []}
        cpus: dict[int, list[float]] = {1: [], jobs: []}
        digests = set()
        for _ in range(repeats):
            for j in (1, jobs):
                run = subprocess.run([sys.executable, __file__, "--one", str(path), str(j)],
                                     capture_output=True, text=True, check=True)
                seconds, cpu, digest = run.stdout.split()
                times[j].append(float(seconds))
                cpus[j].append(float(cpu))
                digests.add(digest)
    return times, cpus, len(digests) == 1


def main(repeats: int, jobs: int) -> None:
    med = statistics.median
    times, cpus, same = _measure(TRIVIAL, repeats, jobs)
    print(f"fixed cost of jobs={jobs} (8 trivial members): wall {med(times[jobs]) - med(times[1]):+.2f} s, "
          f"CPU {med(cpus[jobs]) - med(cpus[1]):+.2f} s over serial ({med(times[1]):.2f} s wall, "
          f"{med(cpus[1]):.2f} s CPU)")
    times, cpus, same = _measure(FAMILY, repeats, jobs)
    serial, parallel = med(times[1]), med(times[jobs])
    print(f"family: 2 R(pi/g), g = 59..97 prime, three sensors (8 members); {repeats} runs each")
    for j, name in ((1, "serial"), (jobs, f"jobs={jobs}")):
        print(f"{name:8s} wall median {med(times[j]):7.2f} s  runs {[round(t, 2) for t in times[j]]}"
              f"   CPU median {med(cpus[j]):7.2f} s")
    print(f"wall speed-up serial / jobs={jobs}: {serial / parallel:.2f}x (target >= 1.7x on {jobs} idle cores)   "
          f"CPU ratio jobs={jobs} / serial: {med(cpus[jobs]) / med(cpus[1]):.2f}   "
          f"identical exact results: {same}   (machine load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--one"]:
        one(sys.argv[2], int(sys.argv[3]))
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 3, int(sys.argv[2]) if len(sys.argv) > 2 else 2)
