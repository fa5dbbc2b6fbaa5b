"""``redkin reproduce``: recompute every paper's figures and tables, paper value beside ours.

Each section lives in its own module that defines ``SECTION``, a
:class:`Section`.  :data:`SECTION_MODULES` lists them in report order, each
with its key; a paper module adds itself by appending one line there.

This package's own module imports no section and no plotting, so that
``redkin reproduce --help`` lists the keys without importing matplotlib or the
kernels: :func:`run` imports them.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from redkin._validation import check_output_directory
from redkin.errors import RedkinError
from redkin.reproduce.provenance import build_info

if TYPE_CHECKING:
    from redkin.reproduce.report import SectionWriter

#: Modules defining ``SECTION``, in the order of the report, and the key of each section on the command line
#: (``redkin reproduce 000``); a section takes its key from here (:func:`section_key`).
SECTION_MODULES = {
    "redkin.reproduce.paper_000": "000",
    "redkin.reproduce.paper_001": "001",
    "redkin.reproduce.paper_003": "003",
    "redkin.reproduce.paper_004": "004",
    "redkin.reproduce.workspace_section": "workspace",
    "redkin.reproduce.models_section": "models",
}

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
    """Keys accepted by :func:`run`, in report order (no section is imported)."""
    return list(SECTION_MODULES.values())


def section_key(module: str) -> str:
    """The key of the section that ``module`` (its ``__name__``) defines."""
    return SECTION_MODULES[module]


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
    from redkin.reproduce.report import SectionWriter, write_report  # matplotlib: only when a report is made

    available = {s.key: s for s in sections()}
    chosen = list(available) if not keys else list(keys)
    unknown = [k for k in chosen if k not in available]
    if unknown:
        raise RedkinError(f"unknown section {unknown[0]!r}: expected one of {', '.join(available)}")
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
