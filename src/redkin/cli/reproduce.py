"""``redkin reproduce``: the report of every paper, or of the chosen sections."""

from __future__ import annotations

import argparse
import sys

from redkin import reproduce
from redkin.cli.common import add_force_flag, output_directory, plural
from redkin.errors import RedkinError


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "reproduce",
        help="recompute the papers' figures and tables into DIR/index.html and DIR/summary.json",
    )
    parser.add_argument("papers", nargs="*", metavar="PAPER",
                        help=f"sections to run (default all): {', '.join(reproduce.section_keys())}")
    parser.add_argument("--out", default="report", metavar="DIR", help="output directory (default: report)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    add_force_flag(parser)
    parser.set_defaults(handler=run)


def _progress(key: str, fraction: float, message: str) -> None:
    if not sys.stderr.isatty():  # logs get one line at the start and end of a section
        if message in ("start", "done"):  # the two calls made by reproduce.run
            sys.stderr.write(f"[{key}] {message}\n")
        return
    width = 30
    filled = int(round(width * max(0.0, min(1.0, fraction))))
    end = "\n" if fraction >= 1.0 else ""
    sys.stderr.write(f"\r[{key:>6}] [{'#' * filled}{'.' * (width - filled)}] {100 * fraction:5.1f}% "
                     f"{message[:40]:<40}{end}")
    sys.stderr.flush()


#: The files of a report that mark a folder as holding one (``--force`` replaces them).
_REPORT_FILES = ("index.html", "summary.json")


def run(args: argparse.Namespace) -> int:
    known = reproduce.section_keys()
    unknown = [key for key in args.papers if key not in known]
    if unknown:  # before the folder is looked at: a misspelt section is the first thing to say
        raise RedkinError(f"unknown section {unknown[0]!r}: expected one of {', '.join(known)}")
    output_directory(args.out, "--out", _REPORT_FILES, args.force)
    if args.quiet:  # else redkin._compiled counts the kernels a fresh install compiles (for minutes) on stderr: on a
        from redkin._compiled import set_compile_notice  # terminal over the progress bar, which goes on below

        set_compile_notice(False)
    writers = reproduce.run(args.out, args.papers, progress=None if args.quiet else _progress)
    differing = sum(
        1
        for w in writers.values()
        for table in w.tables.values()
        for ok in table.get("agreement", [])
        if ok is False
    )
    print(f"wrote {args.out}/index.html and {args.out}/summary.json ({plural(len(writers), 'section')}, "
          f"{plural(differing, 'paper value')} that we do not reproduce"
          + {0: ")", 1: ", explained in the report)"}.get(differing, ", each explained in the report)"))
    return 0
