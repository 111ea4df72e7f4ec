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
