"""The report as one HTML page: the summary of what reproduces first, then every section, readable on a phone.

Verdicts carry a mark and words (✓ agrees, ✗ DIFFERS), never colour alone.
A comparison table prints each note once, under the table, and its rows
point to it; the summary links every row that differs with its one-line
reason.  Tables scroll inside their own box, figures are shown at half their
pixel size (sharp on high-density screens) and link to the full-size file.
"""

from __future__ import annotations

import html
import re
from collections import Counter
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

from redkin.reproduce.comparison import Comparison, Note, is_number
from redkin.reproduce.numbers import column_format, fixed, general, printed_decimals, text

if TYPE_CHECKING:  # pragma: no cover
    from redkin.reproduce.report import Figure, SectionWriter

STYLE = """
*, *::before, *::after { box-sizing: border-box; }
html { -webkit-text-size-adjust: 100%; }
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; max-width: 72em; margin: 0 auto;
       padding: 0.5em clamp(0.75em, 4vw, 2.5em) 3em; line-height: 1.5; color: #1d1d1d; }
h1 { font-size: 1.6em; border-bottom: 2px solid #444; margin-bottom: 0.2em; }
h2 { margin-top: 2.2em; border-bottom: 1px solid #999; }
h3 { margin-top: 1.8em; }
h2, h3 { scroll-margin-top: 0.5em; }
p, li, figcaption { overflow-wrap: break-word; }
p.meta { color: #555; font-size: 0.9em; margin-top: 0; }
p.ref { font-style: italic; color: #555; }
p.top { text-align: right; font-size: 0.85em; margin: 0.5em 0 0; }
nav ul { padding-left: 1.2em; margin: 0.2em 0; }
nav li { margin: 0.15em 0; }
.scroll { overflow-x: auto; max-width: 100%; margin: 0.4em 0; -webkit-overflow-scrolling: touch; }
table { border-collapse: collapse; font-size: 0.88em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.55em; text-align: left; vertical-align: top; }
thead th { background: #eee; }
th.num, td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.verdict { white-space: nowrap; }
td.agrees { background: #eaf6ea; }
td.differs { background: #fde4e4; }
td.differs strong { color: #8a0000; }
tr:target td, tr:target th { outline: 2px solid #d08000; }
.block { margin: 1.2em 0; }
.caption { font-weight: 600; margin: 0 0 0.2em; }
.note, ol.notes { font-size: 0.88em; color: #333; }
ol.notes { margin: 0.3em 0; padding-left: 1.8em; }
figure { margin: 1.2em 0; }
figure img { max-width: 100%; height: auto; border: 1px solid #ddd; display: block; }
figcaption { margin-top: 0.3em; }
table.counts td, table.counts th { padding: 0.3em 0.8em; }
ul.differs li { margin: 0.35em 0; }
p.explore a { font-weight: 600; }
"""


def render_page(sections: Sequence[SectionWriter], title: str, build: dict[str, str]) -> str:
    """The whole report page: header, summary, contents and the sections."""
    ids = _Anchors()
    bodies = [_section_html(s, ids) for s in sections]
    meta = (f"Generated {html.escape(build['date'])} · redkin {html.escape(build['version'])} · commit "
            f"<code>{html.escape(build['commit'])}</code> · every table's rows: "
            "<a href=\"summary.json\">summary.json</a>")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>\n"
        f"<header id=\"top\"><h1>{html.escape(title)}</h1><p class=\"meta\">{meta}</p></header>\n"
        f"{_summary_html(sections)}\n{_contents_html(sections, ids)}\n" + "\n".join(bodies) + "\n</body></html>\n"
    )


class _Anchors:
    """Unique element ids, and the subsection headings of each section for the contents."""

    def __init__(self) -> None:
        self.used: set[str] = set()
        self.headings: dict[str, list[tuple[str, str]]] = {}

    def new(self, *parts: str) -> str:
        base = "-".join(re.sub(r"[^A-Za-z0-9]+", "-", p).strip("-").lower() for p in parts if p)
        anchor, k = base, 2
        while anchor in self.used:
            anchor, k = f"{base}-{k}", k + 1
        self.used.add(anchor)
        return anchor


def _row_id(section: str, table: str, index: int) -> str:
    """Element id of row ``index`` (from 0) of a table: the summary's links point there."""
    return f"{section}-{table}-{index + 1}".replace("_", "-").lower()


def _summary_html(sections: Sequence[SectionWriter]) -> str:
    compared = [s for s in sections if s.comparisons]
    rows: list[str] = []
    totals: Counter[str] = Counter()
    for s in compared:
        counts = s.counts()
        totals.update(counts)
        cells = "".join(f'<td class="num" data-count="{k}">{counts[k]}</td>' for k in ("agrees", "differs", "no_value"))
        rows.append(f'<tr data-section="{html.escape(s.key)}"><th><a href="#{html.escape(s.key)}" '
                    f'title="{html.escape(s.title)}">{html.escape(_short(s.title))}</a></th>{cells}</tr>')
    total_cells = "".join(f'<td class="num">{totals[k]}</td>' for k in ("agrees", "differs", "no_value"))
    counts_table = (
        '<div class="scroll"><table class="counts" id="counts"><thead><tr><th>section</th>'
        '<th class="num">✓ agree</th><th class="num">✗ differ</th><th class="num">– no printed value</th></tr>'
        f"</thead><tbody>{''.join(rows)}</tbody><tfoot><tr><th>all</th>{total_cells}</tr></tfoot></table></div>"
    )
    items = []
    for s in compared:
        for name, index, c in s.differing():
            where = _short(s.tables[name]["caption"] or name)
            note = c.explanation
            reason = note.reason if note is not None else "no reason given"
            values = f"paper: {_paper_cell(c)}; ours: {_ours_cell(c)}"
            items.append(f'<li><a href="#{_row_id(s.key, name, index)}">{html.escape(_short(s.title))}, '
                         f"{html.escape(where)}: {html.escape(c.quantity)}</a> <strong>✗ DIFFERS</strong> "
                         f"({html.escape(values)}): {html.escape(reason)}</li>")
    differs = (f'<ul class="differs" id="differs">{"".join(items)}</ul>' if items
               else '<p id="differs">Every printed value is reproduced.</p>')
    return (
        '<section id="summary"><h2>Summary: what reproduces</h2>'
        f"<p>Of the values the papers print, <strong>{totals['agrees']} {_verb(totals['agrees'], 'agree')}</strong> "
        f"with ours and <strong>{totals['differs']} {_verb(totals['differs'], 'differ')}</strong>"
        + {0: "", 1: ", for a reason given below"}.get(totals["differs"], ", each for a reason given below")
        + f"; {totals['no_value']} {'row' if totals['no_value'] == 1 else 'rows'} of ours "
        f"{'has' if totals['no_value'] == 1 else 'have'} no printed value to compare.</p>"
        f"{counts_table}<h3 id=\"summary-differs\">What does not reproduce, and why</h3>{differs}</section>"
    )


def _verb(count: int, verb: str) -> str:
    """The verb agreeing with ``count`` values: ``1 agrees``, ``2 agree``."""
    return verb + "s" if count == 1 else verb


def _short(title: str) -> str:
    """The part of a title before its colon: ``"Paper 000"``, ``"Section 6.2.2"``, ``"Fig. 6"``."""
    return title.split(":")[0].strip()


def _contents_html(sections: Sequence[SectionWriter], ids: _Anchors) -> str:
    entries = ['<li><a href="#summary">Summary: what reproduces</a></li>']
    for s in sections:
        subsections = "".join(f'<li><a href="#{anchor}">{html.escape(title)}</a></li>'
                              for anchor, title in ids.headings.get(s.key, []))
        entries.append(f'<li><a href="#{html.escape(s.key)}">{html.escape(s.title)}</a>'
                       + (f"<ul>{subsections}</ul>" if subsections else "") + "</li>")
    return f'<nav aria-label="Contents"><h2>Contents</h2><ul>{"".join(entries)}</ul></nav>'


def _section_html(writer: SectionWriter, ids: _Anchors) -> str:
    ids.used.add(writer.key)
    parts = [f'<section id="{html.escape(writer.key)}">', f"<h2>{html.escape(writer.title)}</h2>",
             f'<p class="ref">{html.escape(writer.reference)}</p>']
    headings = ids.headings.setdefault(writer.key, [])
    for kind, content in writer.blocks:
        if kind == "heading":
            anchor = ids.new(writer.key, content)
            headings.append((anchor, content))
            if len(headings) > 1:
                parts.append(_TOP)
            parts.append(f'<h3 id="{anchor}">{html.escape(content)}</h3>')
        elif kind == "text":
            parts.append(f"<p>{html.escape(content)}</p>")
        elif kind == "figure":
            parts.append(_figure_html(content))
        elif kind == "page":
            filename, label = content
            parts.append(f'<p class="explore"><a href="{html.escape(filename)}">{html.escape(label)}</a></p>')
        elif content in writer.comparisons:
            parts.append(_comparison_html(writer.key, content, writer.tables[content], writer.comparisons[content]))
        else:
            parts.append(_table_html(writer.tables[content]))
    parts += [_TOP, "</section>"]
    return "\n".join(parts)


_TOP = '<p class="top"><a href="#top">↑ back to top</a></p>'


def _figure_html(figure: Figure) -> str:
    name = html.escape(figure.filename)
    detail = f'<p class="note">{html.escape(figure.detail)}</p>' if figure.detail else ""
    return (f'<figure><a href="{name}"><img src="{name}" width="{figure.width}" height="{figure.height}" '
            f'alt="{html.escape(figure.caption)}"></a><figcaption><span class="caption">{html.escape(figure.caption)}'
            f'</span> <a href="{name}">(full size)</a></figcaption>{detail}</figure>')


def _block(caption: str, table: str, notes: str) -> str:
    head = f'<p class="caption">{html.escape(caption)}</p>' if caption else ""
    return f'<div class="block">{head}<div class="scroll">{table}</div>{notes}</div>'


def _table_html(table: dict[str, Any]) -> str:
    columns, rows = table["columns"], table["rows"]
    formats = [column_format([row[j] for row in rows]) for j in range(len(columns))]
    numeric = [bool(rows) and sum(is_number(row[j]) for row in rows) * 2 >= len(rows) for j in range(len(columns))]
    head = "".join(f'<th{_NUM if numeric[j] else ""}>{html.escape(str(c))}</th>' for j, c in enumerate(columns))
    body = "".join(
        "<tr>"
        + "".join(f'<td{_NUM if is_number(v) else ""}>{html.escape(formats[j](v))}</td>' for j, v in enumerate(row))
        + "</tr>"
        for row in rows
    )
    detail = f'<p class="note">{html.escape(table["detail"])}</p>' if table["detail"] else ""
    return _block(table["caption"], f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>", detail)


_NUM = ' class="num"'
_UNIT = re.compile(r"\s*\[([^\]]+)\]")


def _shared_unit(comparisons: Sequence[Comparison]) -> str | None:
    """The unit every row's quantity names in brackets, if they all name the same one."""
    units = {match.group(1) if (match := _UNIT.search(c.quantity)) else None for c in comparisons}
    return units.pop() if len(units) == 1 and None not in units else None


def _decimals(c: Comparison) -> int:
    """Decimals for ours and the difference: one more than the paper prints (rows with a numeric paper value only)."""
    return printed_decimals(cast(float, c.paper)) + 1


def _paper_cell(c: Comparison) -> str:
    return fixed(float(c.paper), printed_decimals(c.paper)) if is_number(c.paper) else text(c.paper)


def _ours_cell(c: Comparison) -> str:
    if is_number(c.ours):
        return fixed(float(c.ours), _decimals(c)) if is_number(c.paper) else general(float(c.ours))
    return text(c.ours)


def _comparison_html(section: str, name: str, table: dict[str, Any], comparisons: Sequence[Comparison]) -> str:
    table_id = f"{section}-{name}".replace("_", "-").lower()
    unit = _shared_unit(comparisons)
    suffix = f" [{unit}]" if unit else ""
    tolerances = Counter(c.tolerance for c in comparisons if is_number(c.paper) and is_number(c.ours))
    usual = tolerances.most_common(1)[0][0] if tolerances else 0.0
    notes: dict[Note, int] = {}
    body = []
    for index, c in enumerate(comparisons):
        note = c.explanation
        marker = ""
        if note is not None:
            number = notes.setdefault(note, len(notes) + 1)
            marker = f' <a href="#{table_id}-note-{number}" aria-label="note {number}">[{number}]</a>'
        quantity = _UNIT.sub("", c.quantity, count=1).strip() if unit else c.quantity
        difference = fixed(c.difference, _decimals(c), sign=True) if c.difference is not None else "–"
        body.append(
            f'<tr id="{_row_id(section, name, index)}"><td>{html.escape(quantity)}</td>'
            f"<td{_NUM}>{html.escape(_paper_cell(c))}</td><td{_NUM}>{html.escape(_ours_cell(c))}</td>"
            f"<td{_NUM}>{html.escape(difference)}</td>{_verdict_cell(c, usual, marker)}</tr>"
        )
    head = (f"<th>quantity</th><th{_NUM}>paper{suffix}</th><th{_NUM}>ours{suffix}</th>"
            f"<th{_NUM}>Δ = ours − paper{suffix}</th><th>verdict</th>")
    rule = f"✓ agrees: |Δ| ≤ {usual:g}" + (" unless the row states another tolerance" if len(tolerances) > 1 else "")
    listed = "".join(f'<li id="{table_id}-note-{number}"><strong>{html.escape(note.reason)}</strong>'
                     + (f": {html.escape(note.detail)}" if note.detail else "") + "</li>"
                     for note, number in notes.items())
    detail = f'<p class="note">{html.escape(table["detail"])}</p>' if table["detail"] else ""
    footer = (detail + (f'<p class="note">{html.escape(rule)}.</p>' if tolerances else "")
              + (f'<ol class="notes">{listed}</ol>' if listed else ""))
    return _block(table["caption"], f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>",
                  footer)


def _verdict_cell(c: Comparison, usual: float, marker: str) -> str:
    """The verdict as a mark and words (bold for a difference), then the row's note marker."""
    agrees = c.agrees
    if agrees:
        within = f" (within {c.tolerance:g})" if c.tolerance not in (usual, 0.0) else ""
        return f'<td class="verdict agrees">✓ agrees{within}{marker}</td>'
    if agrees is False:
        return f'<td class="verdict differs">✗ <strong>DIFFERS</strong>{marker}</td>'
    return f'<td class="verdict">– {html.escape(c.outcome())}{marker}</td>'
