"""The reproduction report: sections of headings, text, tables, figures and linked pages, kept for HTML and JSON.

A paper module builds its section through a :class:`SectionWriter`; the
writer keeps the tables (for ``summary.json``), saves figures as PNG files
beside ``index.html`` and writes linked pages (the arm-angle explorers) and data files (``.npz``).
Paper values enter only as the "paper" side of a :class:`Comparison`.
"""

from __future__ import annotations

import json
import math
import re
import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np

from redkin.errors import RedkinError

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from redkin.reproduce.comparison import Comparison
from redkin.reproduce.page import render_page

#: Resolution of the report's PNG files: twice the 110 dpi at which the page shows them.
_FIGURE_DPI = 220
#: Pixels of a figure file per CSS pixel on the page.
_PIXEL_RATIO = 2


@dataclass(frozen=True)
class Figure:
    """A saved figure: its file, caption, detail and size on the page (CSS pixels)."""

    filename: str
    caption: str
    detail: str
    width: int
    height: int


@dataclass
class SectionWriter:
    """Collects one section's content; figures and linked pages go to ``figure_dir``."""

    key: str
    title: str
    reference: str
    figure_dir: Path
    progress_callback: Callable[[str, float, str], None] | None = None
    blocks: list[tuple[str, Any]] = field(default_factory=list)
    tables: dict[str, dict[str, Any]] = field(default_factory=dict)
    comparisons: dict[str, list[Comparison]] = field(default_factory=dict)
    figures: list[str] = field(default_factory=list)
    pages: list[str] = field(default_factory=list)
    data_files: list[str] = field(default_factory=list)

    def heading(self, title: str) -> None:
        """Start a subsection (listed in the table of contents)."""
        self.blocks.append(("heading", title))

    def text(self, paragraph: str) -> None:
        """A paragraph of plain text (a number printed as ``-0.0`` reads ``0.0``)."""
        self.blocks.append(("text", _no_negative_zero(paragraph)))

    def table(self, name: str, columns: Sequence[str], rows: Sequence[Sequence[Any]], caption: str = "",
              detail: str = "") -> None:
        """A table with a short caption and its detail in a note; its rows also go to ``summary.json``."""
        if name in self.tables:
            raise RedkinError(f"section {self.key} already has a table named {name!r}")
        clean_rows = [[_jsonable(v) for v in row] for row in rows]
        self.tables[name] = {"caption": caption, "detail": detail, "columns": list(columns), "rows": clean_rows}
        self.blocks.append(("table", name))

    def comparison(self, name: str, comparisons: Sequence[Comparison], caption: str = "", detail: str = "") -> None:
        """A paper-versus-ours table: both values, their difference and a verdict in words for every row."""
        rows = [[c.quantity, c.paper, c.ours, c.difference, c.verdict()] for c in comparisons]
        self.table(name, ["quantity", "paper", "ours", "ours - paper", "verdict"], rows, caption, detail)
        self.tables[name]["agreement"] = [c.agrees for c in comparisons]
        self.comparisons[name] = list(comparisons)

    def figure(self, fig: plt.Figure, name: str, caption: str = "", detail: str = "") -> Path:
        """Save a matplotlib figure as PNG at :data:`_FIGURE_DPI` beside the page and close it."""
        filename = f"{self.key}_{name}.png"
        path = self.figure_dir / filename
        fig.savefig(path, dpi=_FIGURE_DPI, bbox_inches="tight")
        plt.close(fig)
        width, height = _png_size(path)
        self.figures.append(filename)
        self.blocks.append(("figure", Figure(filename, caption, detail, math.ceil(width / _PIXEL_RATIO),
                                             math.ceil(height / _PIXEL_RATIO))))
        return path

    def page(self, name: str, content: str, label: str) -> Path:
        """Write a page (HTML) beside the report and link it with ``label``."""
        filename = f"{self.key}_{name}.html"
        path = self.figure_dir / filename
        path.write_text(content, encoding="utf-8")
        self.pages.append(filename)
        self.blocks.append(("page", (filename, label)))
        return path

    def data(self, name: str, arrays: dict[str, np.ndarray], label: str) -> Path:
        """Save ``arrays`` as a compressed ``.npz`` beside the report (``numpy.load`` reads it) and link it with
        ``label``."""
        filename = f"{self.key}_{name}.npz"
        path = self.figure_dir / filename
        np.savez_compressed(path, allow_pickle=True, **arrays)  # numpy's default, named: no array is called so
        self.data_files.append(filename)
        self.blocks.append(("page", (filename, label)))
        return path

    def progress(self, fraction: float, message: str = "") -> None:
        """Report progress of a long section (0 <= fraction <= 1)."""
        if self.progress_callback is not None:
            self.progress_callback(self.key, fraction, message)

    def counts(self) -> dict[str, int]:
        """Rows of the comparison tables that agree, differ, or have no printed value to compare."""
        verdicts = [ok for table in self.tables.values() for ok in table.get("agreement", [])]
        return {"agrees": verdicts.count(True), "differs": verdicts.count(False),
                "no_value": sum(ok is None for ok in verdicts)}

    def differing(self) -> list[tuple[str, int, Comparison]]:
        """``(table name, row index, comparison)`` of every row that differs, in page order."""
        return [(name, i, c) for name, rows in self.comparisons.items() for i, c in enumerate(rows)
                if c.agrees is False]

    def to_json(self) -> dict[str, Any]:
        return {
            "title": self.title,
            "reference": self.reference,
            "counts": self.counts(),
            "tables": self.tables,
            "figures": self.figures,
            "pages": self.pages,
            "data": self.data_files,
        }


def write_report(out_dir: Path, sections: Sequence[SectionWriter], title: str, build: dict[str, str]) -> None:
    """Write ``index.html`` and ``summary.json`` for the given sections; ``build`` is the date, version and commit."""
    (out_dir / "index.html").write_text(render_page(sections, title, build), encoding="utf-8")
    summary = {"title": title, "generated": build, "sections": {s.key: s.to_json() for s in sections}}
    (out_dir / "summary.json").write_text(json.dumps(summary, indent=2, allow_nan=False), encoding="utf-8")


#: A number that is a negative zero as printed (``-0``, ``-0.0``, ``-0.000``), not part of a longer number or a
#: difference (``x-0.5``).
_NEGATIVE_ZERO = re.compile(r"(?<![\w.)\]])-(0(?:\.0+)?)(?![\d.eE])")


def _no_negative_zero(text: str) -> str:
    """``text`` with every printed negative zero (``[18.6, -0.0]``) written as zero (``[18.6, 0.0]``)."""
    return _NEGATIVE_ZERO.sub(r"\1", text)


def _png_size(path: Path) -> tuple[int, int]:
    """Width and height in pixels of a PNG file, from its header."""
    with open(path, "rb") as handle:
        header = handle.read(24)
    return struct.unpack(">II", header[16:24])


def _jsonable(value: Any) -> Any:
    """Plain JSON values: numpy scalars to Python, non-finite floats to strings."""
    if hasattr(value, "item") and callable(value.item) and getattr(value, "ndim", 1) == 0:
        value = value.item()
    if isinstance(value, float):
        return value + 0.0 if math.isfinite(value) else str(value)  # + 0.0: no -0.0
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value
