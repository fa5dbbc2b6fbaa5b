"""The one timing rule of the benchmark scripts: the best of several rounds (the least disturbed by other load)."""

from __future__ import annotations

import time
from collections.abc import Callable

#: Length of a round in :func:`best_time_short_rounds`: short enough that some rounds run undisturbed.
ROUND_SECONDS = 0.01


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


def best_time_short_rounds(function: Callable[[], object], repeat: int = 20) -> float:
    """Seconds per call as :func:`best_time`, with rounds of about :data:`ROUND_SECONDS` whatever one call costs.

    For comparisons: two libraries timed in rounds of the same length are
    equally exposed to other jobs on the machine (a long round is rarely
    undisturbed, a short one often is).
    """
    function()
    start = time.perf_counter()
    function()
    once = time.perf_counter() - start
    return best_time(function, repeat, max(1, round(ROUND_SECONDS / once)))
