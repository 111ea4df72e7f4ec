"""Shared timing helper of the benchmark scripts (imported from the script's own directory)."""

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
