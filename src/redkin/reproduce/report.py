"""The reproduction report: sections of text, tables and figures, written as HTML and JSON.

A paper module builds its section through a :class:`SectionWriter`; the
writer keeps the tables (for ``summary.json``) and saves figures as PNG files
beside ``index.html``.  Paper values enter only as the "paper" column of a
:class:`Comparison`; the verdict column says in words whether ours agrees.
"""

from __future__ import annotations

import html
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


@dataclass(frozen=True)
class Comparison:
    """One printed number of a paper beside ours.

    Parameters
    ----------
    quantity : str
        What is compared, e.g. ``"Psi_2 upper bound [deg]"``.
    paper : float, str or None
        The value printed in the paper (``None`` if the paper prints none).
    ours : float, str or None
        Our recomputed value.
    tolerance : float
        Largest difference counted as agreement (e.g. half the last printed digit).
    note : str
        Explanation, required in spirit whenever the values disagree.
    """

    quantity: str
    paper: float | str | None
    ours: float | str | None
    tolerance: float = 0.0
    note: str = ""

    def __post_init__(self) -> None:
        if isinstance(self.tolerance, bool) or not isinstance(self.tolerance, (int, float)) or self.tolerance < 0:
            raise ValueError(f"tolerance of {self.quantity!r} must be a number >= 0, got {self.tolerance!r}")

    @property
    def agrees(self) -> bool | None:
        """True/False for two numbers or two words (equal words agree), None otherwise."""
        if isinstance(self.paper, str) and isinstance(self.ours, str):
            return self.paper == self.ours
        if not (_is_number(self.paper) and _is_number(self.ours)):
            return None
        return abs(float(self.paper) - float(self.ours)) <= self.tolerance + 1e-12

    def verdict(self) -> str:
        """The comparison in words."""
        agrees = self.agrees
        if agrees is None:
            base = "not comparable as numbers" if self.paper is not None else "paper prints no value"
        elif agrees:
            base = "agrees" if self.tolerance == 0 else f"agrees (within {self.tolerance:g})"
        elif isinstance(self.ours, str):
            base = "DIFFERS"
        else:
            base = f"DIFFERS by {float(self.ours) - float(self.paper):+.6g}"
        return f"{base}; {self.note}" if self.note else base


@dataclass
class SectionWriter:
    """Collects one section's content; figures go to ``figure_dir``."""

    key: str
    title: str
    reference: str
    figure_dir: Path
    progress_callback: Callable[[str, float, str], None] | None = None
    blocks: list[tuple[str, Any]] = field(default_factory=list)
    tables: dict[str, dict[str, Any]] = field(default_factory=dict)
    figures: list[str] = field(default_factory=list)

    def text(self, paragraph: str) -> None:
        """A paragraph of plain text."""
        self.blocks.append(("text", paragraph))

    def table(self, name: str, columns: Sequence[str], rows: Sequence[Sequence[Any]], caption: str = "") -> None:
        """A table; its rows also go to ``summary.json`` under ``name``."""
        if name in self.tables:
            raise ValueError(f"section {self.key} already has a table named {name!r}")
        clean_rows = [[_jsonable(v) for v in row] for row in rows]
        self.tables[name] = {"caption": caption, "columns": list(columns), "rows": clean_rows}
        self.blocks.append(("table", name))

    def comparison(self, name: str, comparisons: Sequence[Comparison], caption: str = "") -> None:
        """A paper-versus-ours table with a verdict in words for every row."""
        rows = [[c.quantity, c.paper, c.ours, c.verdict()] for c in comparisons]
        self.table(name, ["quantity", "paper", "ours", "verdict"], rows, caption)
        self.tables[name]["agreement"] = [c.agrees for c in comparisons]

    def figure(self, fig: "plt.Figure", name: str, caption: str = "") -> Path:
        """Save a matplotlib figure as PNG beside the page and close it."""
        filename = f"{self.key}_{name}.png"
        path = self.figure_dir / filename
        fig.savefig(path, dpi=110, bbox_inches="tight")
        plt.close(fig)
        self.figures.append(filename)
        self.blocks.append(("figure", (filename, caption)))
        return path

    def progress(self, fraction: float, message: str = "") -> None:
        """Report progress of a long section (0 <= fraction <= 1)."""
        if self.progress_callback is not None:
            self.progress_callback(self.key, fraction, message)

    # ------------------------------------------------------------ rendering
    def to_json(self) -> dict[str, Any]:
        return {
            "title": self.title,
            "reference": self.reference,
            "tables": self.tables,
            "figures": self.figures,
        }

    def to_html(self) -> str:
        parts = [
            f'<section id="{html.escape(self.key)}">',
            f"<h2>{html.escape(self.title)}</h2>",
            f'<p class="ref">{html.escape(self.reference)}</p>',
        ]
        for kind, content in self.blocks:
            if kind == "text":
                parts.append(f"<p>{html.escape(content)}</p>")
            elif kind == "figure":
                filename, caption = content
                parts.append(
                    f'<figure><img src="{html.escape(filename)}" alt="{html.escape(caption)}">'
                    f"<figcaption>{html.escape(caption)}</figcaption></figure>"
                )
            else:
                parts.append(_table_html(self.tables[content]))
        parts.append("</section>")
        return "\n".join(parts)


PAGE_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; line-height: 1.45; color: #222; }
h1 { border-bottom: 2px solid #444; }
h2 { margin-top: 2.5em; border-bottom: 1px solid #aaa; }
p.ref { font-style: italic; color: #555; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #eee; }
td.differs { background: #fde2e2; }
td.agrees { background: #e2f5e2; }
caption { caption-side: top; text-align: left; font-weight: bold; padding-bottom: 0.3em; }
figure { margin: 1em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { color: #444; font-size: 0.9em; }
nav li { margin: 0.2em 0; }
"""


def write_report(out_dir: Path, sections: Sequence[SectionWriter], title: str) -> None:
    """Write ``index.html`` and ``summary.json`` for the given sections."""
    nav = "".join(f'<li><a href="#{html.escape(s.key)}">{html.escape(s.title)}</a></li>' for s in sections)
    body = "\n".join(s.to_html() for s in sections)
    page = (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        f"<title>{html.escape(title)}</title><style>{PAGE_STYLE}</style></head><body>"
        f"<h1>{html.escape(title)}</h1><nav><ul>{nav}</ul></nav>\n{body}\n</body></html>\n"
    )
    (out_dir / "index.html").write_text(page, encoding="utf-8")
    summary = {"title": title, "sections": {s.key: s.to_json() for s in sections}}
    (out_dir / "summary.json").write_text(json.dumps(summary, indent=2, allow_nan=False), encoding="utf-8")


def _table_html(table: dict[str, Any]) -> str:
    agreement = table.get("agreement")
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in table["columns"])
    rows = []
    for i, row in enumerate(table["rows"]):
        cells = []
        for j, value in enumerate(row):
            css = ""
            if agreement is not None and j == len(row) - 1 and agreement[i] is not None:
                css = ' class="agrees"' if agreement[i] else ' class="differs"'
            cells.append(f"<td{css}>{html.escape(_format(value))}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    caption = f"<caption>{html.escape(table['caption'])}</caption>" if table["caption"] else ""
    return f"<table>{caption}<thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _jsonable(value: Any) -> Any:
    """Plain JSON values: numpy scalars to Python, non-finite floats to strings."""
    if hasattr(value, "item") and callable(value.item) and getattr(value, "ndim", 1) == 0:
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value


def _format(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list):
        return "[" + ", ".join(_format(v) for v in value) + "]"
    return str(value)
