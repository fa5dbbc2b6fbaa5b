"""``redkin reproduce``: recompute every paper's figures and tables, paper value beside ours.

Each section lives in its own module that defines ``SECTION``, a
:class:`Section`.  :data:`SECTION_MODULES` lists them in report order; a paper
module adds itself by appending one line there.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from redkin._validation import check_output_directory
from redkin.reproduce.provenance import build_info
from redkin.reproduce.report import SectionWriter, write_report

#: Modules defining ``SECTION``, in the order of the report.
SECTION_MODULES = [
    "redkin.reproduce.paper_000",
    "redkin.reproduce.paper_001",
    "redkin.reproduce.paper_003",
    "redkin.reproduce.paper_004",
    "redkin.reproduce.workspace_section",
    "redkin.reproduce.models_section",
]

_REPORT_TITLE = "redkin: reproduction of the papers"


@dataclass(frozen=True)
class Section:
    """One section of the report.

    Parameters
    ----------
    key : str
        Short name used on the command line (``"000"``, ``"models"``, ...).
    title : str
        Heading of the section.
    reference : str
        Full reference of the paper.
    build : callable
        ``build(writer)`` fills a :class:`SectionWriter`.
    """

    key: str
    title: str
    reference: str
    build: Callable[[SectionWriter], None]


def sections() -> list[Section]:
    """All registered sections, in report order."""
    return [importlib.import_module(name).SECTION for name in SECTION_MODULES]


def section_keys() -> list[str]:
    """Keys accepted by :func:`run`."""
    return [s.key for s in sections()]


def run(
    out_dir: str | Path,
    keys: Sequence[str] | None = None,
    progress: Callable[[str, float, str], None] | None = None,
) -> dict[str, SectionWriter]:
    """Build the chosen sections (default all, in report order) and write ``index.html`` and ``summary.json``.

    Raises
    ------
    ValueError
        For an unknown section key or an output directory that cannot be
        written (checked before any section runs).
    """
    available = {s.key: s for s in sections()}
    chosen = list(available) if not keys else list(keys)
    unknown = [k for k in chosen if k not in available]
    if unknown:
        raise ValueError(f"unknown section {unknown[0]!r}: expected one of {', '.join(available)}")
    out = check_output_directory(out_dir, "--out")
    writers: dict[str, SectionWriter] = {}
    for key in chosen:
        section = available[key]
        writer = SectionWriter(section.key, section.title, section.reference, out, progress)
        writer.progress(0.0, "start")
        section.build(writer)
        writer.progress(1.0, "done")
        writers[key] = writer
    write_report(out, list(writers.values()), _REPORT_TITLE, build_info())
    return writers
