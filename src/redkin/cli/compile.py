"""``redkin compile``: compile every kernel now (for a Docker image, a cluster's workers), and say where they went."""

from __future__ import annotations

import argparse
import os
import sys
import time

from redkin.cli.common import print_json
from redkin.errors import RedkinError
from redkin.warm_up import SECTION_NAMES


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "compile",
        help="compile and cache every kernel now (once per install and machine; NUMBA_CACHE_DIR chooses where)",
        description="Call every compiled path once, so that later processes load the kernels from numba's cache "
                    "instead of compiling them (a few minutes on a 2-core machine the first time, the kernels counted "
                    "on stderr as they compile; about 1 s when everything is cached already). Set NUMBA_CACHE_DIR to "
                    "put the cache in one shared folder (a read-only install, Dask workers); see docs/chains.md.",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    parser.add_argument("--processes", type=int, metavar="N",
                        help="compile in N processes at once, each taking the next section as it finishes one "
                             "(default: one per core this process may use; 1: this process, with its compile "
                             "progress)")
    parser.add_argument("--json", action="store_true", help="print the sections' seconds and the cache as JSON")
    parser.add_argument("--section", action="append", choices=SECTION_NAMES, metavar="NAME",
                        help="compile only this section (repeat for more): " + ", ".join(SECTION_NAMES))
    parser.add_argument("--background", action="store_true",
                        help="what a command that ran as Python starts so that later runs are compiled: quiet, in "
                             "one process at a low priority, and nothing at all while another 'redkin compile' of "
                             "the same cache runs (docs/chains.md); REDKIN_BACKGROUND_COMPILE=0 stops commands "
                             "from starting it")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from redkin.cli.background_compile import NICENESS, compile_lock

    processes = 1 if args.background else args.processes
    if processes is not None and processes < 1:
        raise RedkinError(f"--processes must be at least 1, got {processes}")
    with compile_lock() as held:
        if args.background:
            if not held:  # another compile of this cache runs (or the lock cannot be taken): leave it the work
                return 0
            if hasattr(os, "nice"):
                os.nice(NICENESS)
            args.quiet = True
        return _compile(args, processes)


def _compile(args: argparse.Namespace, processes: int | None) -> int:
    """Compile the sections ``args`` name (all by default) in ``processes`` processes, saying what it did."""
    from redkin._compiled import cache_directory, default_threads, set_compile_notice
    from redkin.warm_up import warm_up

    processes = default_threads() if processes is None else processes
    if args.quiet:  # else the sections' lines, and redkin._compiled's count of the kernels within them
        set_compile_notice(False)
    compiled: list[str] = []

    def progress(section: str) -> None:
        if not args.quiet:
            print(f"compiling: {section}...", file=sys.stderr, flush=True)

    start = time.perf_counter()
    times = warm_up(progress, processes, compiled.append, args.section)
    cache = cache_directory()
    if args.json:
        print_json({"sections": [{"name": name, "wall_s": wall, "cpu_s": cpu} for name, wall, cpu in times],
                    "kernels_compiled": len(compiled), "processes": processes,
                    "wall_s": time.perf_counter() - start, "cache": cache,
                    "units": {"wall_s": "s", "cpu_s": "s"}})
        return 0
    for name, wall, _ in times:
        print(f"{name:<14} {wall:6.1f} s")
    total = time.perf_counter() - start
    what = f"compiled {len(compiled)} kernels" if compiled else "every kernel was cached already"
    where = f" in {processes} processes" if processes > 1 else ""
    print(f"{what}{where} in {total:.1f} s; cache: {cache}")
    return 0
