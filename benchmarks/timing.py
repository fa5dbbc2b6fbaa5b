"""The one timing rule of the benchmark scripts: the best of several rounds (the least disturbed by other load)."""

from __future__ import annotations

import time
from typing import Callable


def best_time(function: Callable[[], object], repeat: int = 7, number: int = 1) -> float:
    """Seconds per call: the best of ``repeat`` rounds, each the mean of ``number`` calls, after one warm-up call."""
    function()
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        best = min(best, (time.perf_counter() - start) / number)
    return best
