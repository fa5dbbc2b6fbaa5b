"""``redkin reproduce``: the report of every paper, or of the chosen sections."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from redkin import reproduce
from redkin.cli.common import add_force_flag, output_directory, plural


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
    if not message.startswith("compiling "):
        _last_section.update(key=key, fraction=fraction)
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


_last_section: dict[str, Any] = {"key": "", "fraction": 0.0}


def _compiling(kernel: str) -> None:
    """Progress while a kernel compiles (:func:`redkin._compiled.on_compile`): the notice once, on a line of its own
    (not inside the bar), then the bar names each kernel as it compiles."""
    from redkin._compiled import COMPILE_NOTICE, cache_directory

    terminal = sys.stderr.isatty()
    if not _last_section.get("noticed"):
        _last_section["noticed"] = True
        sys.stderr.write(("\n" if terminal and _last_section["key"] else "") + COMPILE_NOTICE.format(
            cache=cache_directory()) + "\n")
    if terminal:
        _progress(_last_section["key"], _last_section["fraction"], f"compiling {kernel.rsplit('.', 1)[-1]}")


#: The files of a report that mark a folder as holding one (``--force`` replaces them).
_REPORT_FILES = ("index.html", "summary.json")


def run(args: argparse.Namespace) -> int:
    known = reproduce.section_keys()
    unknown = [key for key in args.papers if key not in known]
    if unknown:  # before the folder is looked at: a misspelt section is the first thing to say
        raise ValueError(f"unknown section {unknown[0]!r}: expected one of {', '.join(known)}")
    output_directory(args.out, "--out", _REPORT_FILES, args.force)
    from redkin._compiled import on_compile, set_compile_notice

    remove = None
    set_compile_notice(False)  # said here instead, where it does not break the progress line
    if not args.quiet:  # a fresh install compiles for tens of seconds inside a section: the progress names each kernel
        remove = on_compile(_compiling)
    try:
        writers = reproduce.run(args.out, args.papers, progress=None if args.quiet else _progress)
    finally:
        if remove is not None:
            remove()
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
