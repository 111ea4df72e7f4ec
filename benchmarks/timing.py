"""Shared timing helpers of the benchmark scripts (imported from the script's own directory)."""

import resource
import statistics
import time


def median_time(fn, repeats: int = 3) -> float:
    """Median wall time in seconds of ``repeats`` calls of ``fn()``."""
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def median_cpu(fn, repeats: int = 3) -> float:
    """Median CPU seconds (``time.process_time``) of ``repeats`` calls of ``fn(r)``, r = 0..repeats-1."""
    times = []
    for r in range(repeats):
        t = time.process_time()
        fn(r)
        times.append(time.process_time() - t)
    return statistics.median(times)


def peak_rss_mb() -> float:
    """Peak resident set size of this process so far, MB."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def run_child_rows(script: str, rows: list[str]) -> dict[str, dict]:
    """Run ``python script --child ROW`` for each row in a fresh interpreter, print the table of CPU
    seconds, peak MB and the rest of each child's JSON line, and return the parsed lines by row."""
    import json
    import subprocess
    import sys
    print(f"{'row':<14}{'CPU s':>9}{'peak MB':>10}  answer")
    found = {}
    for row in rows:
        out = subprocess.run([sys.executable, script, "--child", row], capture_output=True, text=True)
        if out.returncode:
            print(f"{row:<14} failed: {out.stderr.strip().splitlines()[-1]}")
            continue
        res = found[row] = json.loads(out.stdout.strip().splitlines()[-1])
        rest = {k: v for k, v in res.items() if k not in ("row", "cpu", "rss_mb")}
        print(f"{row:<14}{res['cpu']:>9.2f}{res['rss_mb']:>10.0f}  {rest}", flush=True)
    return found
