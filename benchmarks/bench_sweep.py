"""Wall time of a family sweep: serial (baseline) against jobs=2 local processes.

Family: A = 2 R(pi/g), governing period g = 2..10, one sensor C = [1, 0] (9 members, every A
distinct, so the serial run gains nothing from symkf's caches), the critical common i.i.d. loss
rate of each (a column of symkf/examples/families/rotation-periods.toml).
Each timed run is a fresh interpreter (cold sympy and symkf caches for both modes, so forked
workers do not inherit a warm cache); only ``family.evaluate`` is timed.  Prints medians over
REPEATS runs of wall time and of CPU time (parent plus workers) and their ratios: on a machine
whose cores are busy with other work the wall-clock gain shrinks, the CPU ratio shows the
overhead of the parallel mode itself.  Usage: python benchmarks/bench_sweep.py [REPEATS] [JOBS]
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
period = { from = 2, to = 10 }
[constants]
alpha = "2"
"""


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the pool's workers)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def one(path: str, jobs: int) -> None:
    """Child mode: time one evaluation; print wall and CPU seconds and a digest of the exact results."""
    from symkf.families import load_family
    family = load_family(path)
    start, cpu = time.perf_counter(), _cpu()
    out = family.evaluate(jobs=jobs)
    print(time.perf_counter() - start, _cpu() - cpu, "|".join(str(o.value.exact) for o in out))


def main(repeats: int, jobs: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "family.toml"
        path.write_text(FAMILY)
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
    serial, parallel = statistics.median(times[1]), statistics.median(times[jobs])
    print(f"family: 2 R(pi/g), g = 2..10, one sensor (9 members); {repeats} runs each")
    for j, name in ((1, "serial"), (jobs, f"jobs={jobs}")):
        print(f"{name:8s} wall median {statistics.median(times[j]):7.2f} s  runs {[round(t, 2) for t in times[j]]}"
              f"   CPU median {statistics.median(cpus[j]):7.2f} s")
    print(f"wall speed-up serial / jobs={jobs}: {serial / parallel:.2f}x   CPU ratio jobs={jobs} / serial: "
          f"{statistics.median(cpus[jobs]) / statistics.median(cpus[1]):.2f}   identical exact results: "
          f"{len(digests) == 1}   (machine load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--one"]:
        one(sys.argv[2], int(sys.argv[3]))
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 3, int(sys.argv[2]) if len(sys.argv) > 2 else 2)
