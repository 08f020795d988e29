"""Timing helper shared by the benchmark scripts."""

import time


def best_of(fn, repeat=3):
    """Smallest wall-clock time of ``repeat`` calls of ``fn`` and the last
    result: one run's time on a shared 2-core machine varies by up to 2x
    for sub-second work."""
    best, out = float('inf'), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out
