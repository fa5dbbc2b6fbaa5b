"""The figures that README.md and docs/chains.md quote about start-up and the test suite, measured on this machine.

Run:  python benchmarks/docs_figures.py [--repeat N] [--suite] [--json]

Each figure is measured in new processes, and every compile in a fresh, empty
``NUMBA_CACHE_DIR`` (a temporary folder, removed afterwards):

1. **Compiling every kernel**: :func:`redkin.warm_up.warm_up` (what
   ``redkin compile`` runs), timed by ``benchmarks/cold_start.py``'s
   :func:`cold_start.run` from before ``import redkin`` to the end, wall and
   CPU seconds; then the same process again on the cache it filled (loading).
2. **The chain's kernels alone**: ``benchmarks/bench_chain.py``'s first calls
   (FK, Jacobian and frames of the PA10-7C and the Panda, one configuration
   and a batch of 1000), in a fresh cache.
3. **A cold first command**: ``redkin fk pa10-7c 0 0 0 0 0 0 0`` and
   ``redkin arm-angles franka-fr3 ...`` (the pose of a configuration within
   the FR3's limits), each in a fresh cache.
4. **A warm ``redkin fk``**: the same fk command ``--repeat`` times (default 7)
   on the cache the cold one filled: median and least wall seconds.
5. With ``--suite``, **the test suite**, the README's two commands
   ``python -m pytest`` and ``python -m pytest -m "not slow"`` (with
   ``-p no:cacheprovider``, so the order is not the last run's, and ``-rfEs``,
   so that the failed tests are named beside the counts), from the
   repository root in the ambient environment (its own ``NUMBA_CACHE_DIR`` or
   none), after ``redkin compile --quiet`` (whose seconds are listed: about a
   second when the cache was warm already).  Each suite takes about ten minutes
   on 2 cores, so it is opt-in.

Processes are timed from outside (wall: the parent's clock around the
process; CPU: user + system seconds of the process and its children, from
``getrusage``), except figure 1 and 2's in-process seconds, which start
before ``import redkin``.  The machine may be shared: the output states the
load average before each figure and at the end, and the CPU seconds, which
other load disturbs less than the wall seconds.  ``--json`` prints the figures
and the machine as JSON instead of the markdown table.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import bench_chain  # benchmarks/ (the script's folder is on sys.path)
import cold_start
from timing import load_average, machine_lines

ROOT = Path(__file__).resolve().parents[1]
#: The warm and cold ``redkin fk`` of the docs: the PA10-7C at its zero configuration.
FK = ("fk", "pa10-7c", "0", "0", "0", "0", "0", "0", "0")
#: A configuration within the FR3's limits whose pose the cold ``redkin arm-angles`` asks about.
FR3_Q = ("0.3", "-0.4", "0.2", "-2.0", "0.1", "1.8", "0.7")


@dataclass(frozen=True)
class Figure:
    """One row of the table: what, the value measured, how, and the 1-minute load average when it started."""

    figure: str
    value: str
    how: str
    load: float


@dataclass(frozen=True)
class Process:
    """One finished process: its wall and CPU seconds (children included), exit code and output."""

    wall: float
    cpu: float
    returncode: int
    stdout: str
    stderr: str


@dataclass(frozen=True)
class PytestSummary:
    """pytest's last line: the count of each outcome (``passed``, ``deselected``, ...) and the seconds it states."""

    counts: dict[str, int]
    seconds: float

    def text(self) -> str:
        """The counts as pytest prints them, e.g. ``"1290 passed, 55 deselected, 1 warning"``."""
        return ", ".join(f"{count} {word[:-1] if count == 1 and word in ('warnings', 'errors') else word}"
                         for word, count in self.counts.items())


def run_process(argv: Sequence[str], cache: str | None = None, cwd: Path | None = None,
                check: bool = True) -> Process:
    """Run ``argv`` to its end and time it from outside.

    Parameters
    ----------
    argv : sequence of str
        The command.
    cache : str, optional
        ``NUMBA_CACHE_DIR`` for the process; by default the ambient environment's.
    cwd : Path, optional
        Its working folder (default: this one).
    check : bool
        Stop the script with the process's stderr when it exits with a non-zero code.

    Returns
    -------
    Process
        Wall seconds (the parent's clock), CPU seconds (user + system of the process and every child it waited
        for, from ``getrusage(RUSAGE_CHILDREN)``), the exit code and the output.
    """
    env = dict(os.environ) if cache is None else dict(os.environ, NUMBA_CACHE_DIR=cache)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(list(argv), env=env, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if check and result.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} exited with {result.returncode}:\n{result.stderr}")
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    return Process(wall, cpu, result.returncode, result.stdout, result.stderr)


def redkin_command(*args: str) -> list[str]:
    """``redkin ARGS`` through the console script installed beside this Python (no shell shim in between)."""
    script = Path(sys.executable).with_name("redkin")
    return [str(script) if script.exists() else shutil.which("redkin") or "redkin", *args]


def parse_pytest_summary(output: str) -> PytestSummary:
    """The counts and seconds of pytest's summary line, the last line of ``output`` that holds one.

    Parameters
    ----------
    output : str
        pytest's standard output, e.g. ending in ``"1290 passed, 55 deselected, 3 warnings in 452.12s (0:07:32)"``
        (with ``-q``) or ``"=== 2 failed, 10 passed in 3.01s ==="``.

    Returns
    -------
    PytestSummary
        The counts in pytest's order, singular words made plural (``1 warning`` counts as ``warnings``).

    Raises
    ------
    ValueError
        When no line of ``output`` is a summary line.
    """
    pattern = re.compile(r"^=*\s*((?:\d+ [a-z]+(?:, )?)+) in ([0-9.]+)s\b")
    for line in reversed(output.splitlines()):
        match = pattern.match(line.strip())
        if match:
            counts = {}
            for part in match.group(1).split(", "):
                count, word = part.split(" ")
                counts[{"warning": "warnings", "error": "errors"}.get(word, word)] = int(count)
            return PytestSummary(counts, float(match.group(2)))
    tail = output.strip().splitlines()[-1:] or ["(no output)"]
    raise ValueError(f"output: expected a pytest summary line such as '10 passed in 1.00s', "
                     f"received one ending {tail[0]!r}")


def _load() -> float:
    return os.getloadavg()[0]


def compile_figures() -> list[Figure]:
    """Figure 1: every kernel compiled in a fresh cache (``cold_start.run``), then loaded from it."""
    load = _load()
    with tempfile.TemporaryDirectory() as cache:
        cold = cold_start.run(cache)[-1]
        warm = cold_start.run(cache)[-1]
    how = "`cold_start.run`: `warm_up()` (= `redkin compile`) in a new process, from before `import redkin`"
    return [Figure("compiling every kernel, fresh NUMBA_CACHE_DIR",
                   f"{cold[1]:.0f} s wall, {cold[2]:.0f} s CPU", how, load),
            Figure("the same calls, loaded from that cache", f"{warm[1]:.1f} s wall, {warm[2]:.1f} s CPU",
                   "the same process again on the cache it filled", _load())]


def chain_figures() -> list[Figure]:
    """Figure 2: the chain's kernels alone, compiled in a fresh cache, then loaded from it."""
    load = _load()
    runs = []
    with tempfile.TemporaryDirectory() as cache:
        for _ in range(2):
            process = run_process([sys.executable, "-c", bench_chain.FIRST_CALLS], cache)
            runs.append((process, float(process.stdout.split()[-1])))
    how = ("`bench_chain.FIRST_CALLS`: import, FK, Jacobian and frames of the PA10-7C and the Panda, one "
           "configuration and a batch of 1000; in-process seconds from before `import redkin` (whole process)")
    (cold, cold_inside), (warm, warm_inside) = runs
    return [Figure("the chain's kernels alone, fresh NUMBA_CACHE_DIR",
                   f"{cold_inside:.1f} s wall ({cold.wall:.1f} s process), {cold.cpu:.1f} s CPU", how, load),
            Figure("the same calls, loaded from that cache",
                   f"{warm_inside:.2f} s wall ({warm.wall:.2f} s process), {warm.cpu:.2f} s CPU",
                   "the same process again on the cache it filled", load)]


def command_figures(repeat: int) -> list[Figure]:
    """Figures 3 and 4: ``redkin fk`` and ``redkin arm-angles`` cold (each in a fresh cache), ``redkin fk`` warm."""
    figures = []
    with tempfile.TemporaryDirectory() as cache:
        load = _load()
        cold = run_process(redkin_command(*FK), cache)
        figures.append(Figure(f"cold `redkin {' '.join(FK)}`, fresh NUMBA_CACHE_DIR",
                              f"{cold.wall:.1f} s wall, {cold.cpu:.1f} s CPU", "one process", load))
        pose = run_process(redkin_command("fk", "franka-fr3", *FR3_Q), cache).stdout.strip().splitlines()[-1]
        load = _load()
        warm = [run_process(redkin_command(*FK), cache) for _ in range(repeat)]
        walls = [process.wall for process in warm]
        figures.append(Figure(f"warm `redkin {' '.join(FK)}`",
                              f"median {statistics.median(walls):.2f} s, least {min(walls):.2f} s wall "
                              f"(CPU median {statistics.median(p.cpu for p in warm):.2f} s)",
                              f"{repeat} processes on the cache the cold one filled", load))
    with tempfile.TemporaryDirectory() as cache:
        load = _load()
        arm_angles = run_process(redkin_command("arm-angles", "franka-fr3", *pose.split()), cache)
        figures.append(Figure("cold `redkin arm-angles franka-fr3 --position ... --quat ...`, fresh NUMBA_CACHE_DIR",
                              f"{arm_angles.wall:.1f} s wall, {arm_angles.cpu:.1f} s CPU",
                              f"one process; the pose of q = ({', '.join(FR3_Q)})", load))
    return figures


def suite_figures() -> list[Figure]:
    """Figure 5: the README's two test commands on a warm cache, after ``redkin compile --quiet``."""
    load = _load()
    compiled = run_process(redkin_command("compile", "--quiet"), cwd=ROOT)
    figures = [Figure("`redkin compile --quiet` before the suites (ambient cache)",
                      f"{compiled.wall:.1f} s wall, {compiled.cpu:.1f} s CPU",
                      "about 1 s: the cache was warm; minutes: it was not", load)]
    for label, extra in (("the whole suite", ()), ('without the slow tests (`-m "not slow"`)', ("-m", "not slow"))):
        load = _load()
        process = run_process([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rfEs", *extra],
                              cwd=ROOT, check=False)
        summary = parse_pytest_summary(process.stdout)
        failed = [line.split()[1] for line in process.stdout.splitlines() if line.startswith(("FAILED ", "ERROR "))]
        command = "python -m pytest -p no:cacheprovider -rfEs" + (' -m "not slow"' if extra else "")
        figures.append(Figure(f"{label}, warm cache", f"{process.wall:.0f} s wall, {process.cpu:.0f} s CPU; "
                              f"{summary.text()}" + (f" ({', '.join(failed)})" if failed else ""),
                              f"`{command}` from the repository root (pytest says {summary.seconds:.0f} s)", load))
    return figures


def table(figures: Sequence[Figure]) -> list[str]:
    """The figures as a markdown table."""
    lines = ["| figure | value | how measured | load (1 min) at start |", "|---|---|---|---|"]
    return lines + [f"| {f.figure} | {f.value} | {f.how} | {f.load:.2f} |" for f in figures]


def main(argv: Sequence[str] | None = None) -> list[Figure]:
    """Measure the figures (the suites with ``--suite``), print them and return them."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="warm `redkin fk` processes (default 7)")
    parser.add_argument("--suite", action="store_true", help="also time the test suite twice (about 20 min)")
    parser.add_argument("--json", action="store_true", help="print JSON instead of the markdown table")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error(f"--repeat must be at least 1, received {args.repeat}")
    machine = machine_lines(("numpy", "numba", "pytest"))
    if not args.json:
        print("\n".join(machine) + "\n", flush=True)
    figures = []
    for measure in (compile_figures, chain_figures, lambda: command_figures(args.repeat),
                    *([suite_figures] if args.suite else [])):
        figures += measure()
        print(f"measured: {figures[-1].figure}: {figures[-1].value}", file=sys.stderr, flush=True)
    end = f"- load average at the end (1, 5, 15 min): {load_average()}"
    if args.json:
        print(json.dumps({"machine": [*machine, end], "figures": [asdict(f) for f in figures]}, indent=1))
    else:
        print("\n".join([*table(figures), "", end]))
    return figures


if __name__ == "__main__":
    main()
