"""The one timing rule of the benchmark scripts: the best of several rounds (the least disturbed by other load)."""

from __future__ import annotations

import datetime
import os
import platform
import subprocess
import time
from collections.abc import Callable, Sequence
from pathlib import Path

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


def load_average() -> str:
    """The machine's load average over 1, 5 and 15 minutes, as a benchmark's output states it."""
    return ", ".join(f"{value:.2f}" for value in os.getloadavg())


def machine_lines(packages: Sequence[str]) -> list[str]:
    """The head of a benchmark's output: the date, redkin's commit, the CPU and Python, the versions of
    ``packages`` (distribution names; "absent" where not installed), redkin's threads and the load average."""
    from importlib.metadata import PackageNotFoundError, version

    from redkin import thread_count

    try:
        cpu = next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                   if line.startswith("model name"))
    except (OSError, StopIteration):
        cpu = platform.processor() or "unknown"
    versions = []
    for package in packages:
        try:
            versions.append(f"{package} {version(package)}")
        except PackageNotFoundError:
            versions.append(f"{package} absent")
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                cwd=Path(__file__).resolve().parent, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    return [f"- {datetime.datetime.now().isoformat(timespec='minutes')}, redkin at {commit}: {cpu}, "
            f"{os.cpu_count()} cores, Python {platform.python_version()}",
            f"- {', '.join(versions)}; redkin threads {thread_count()}",
            f"- load average at start (1, 5, 15 min): {load_average()}"]
