"""The explorer as one self-contained HTML page: the numbers as JSON, a small script that draws them.

The page loads nothing from anywhere: its style, script and data are inside
it, so it works from a file, offline, with no server.  The script only
draws: every angle, position, limit flag and special value comes from
:func:`redkin.explore.explorer_data`, rounded to the digits it prints, and
the redundancy parameter's name, domain, ticks and words come with them.
"""

from __future__ import annotations

import html
import json
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from redkin.arms import Parameter
from redkin.explore.curves import BranchCurves, ExplorerData

if TYPE_CHECKING:
    from redkin.explore.cell import BranchCell, CellView
from redkin.explore.script import DRAG_SCRIPT, SCRIPT, STYLE

#: Decimals of the printed angles in each unit (0.001 deg is about 2e-5 rad).
_DECIMALS = {"deg": 3, "rad": 5}
#: Decimals of the stored positions [m] (0.01 mm: far below a pixel).
_POSITION_DECIMALS = 5
#: A frame origin that moves less than this [m] over the parameter is stored once.
_FIXED_ORIGIN = 1e-9


def explorer_html(data: ExplorerData, degrees: bool = False) -> str:
    """The explorer page for ``data``, angles printed in degrees or radians.

    Parameters
    ----------
    data : ExplorerData
        From :func:`redkin.explore.explorer_data`.
    degrees : bool
        Print and plot every angle in degrees (else radians).

    Returns
    -------
    str
        A complete HTML document.
    """
    unit = "deg" if degrees else "rad"
    payload = json.dumps(_payload(data, unit), separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    title = f"{data.parameter.prefix} explorer: {data.robot}"
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>\n"
        f"<header><h1>{html.escape(title)}</h1><p class=\"pose\">{html.escape(_pose_text(data.pose))}</p></header>\n"
        f"{_body(data)}\n<script id=\"explorer-data\" type=\"application/json\">{payload}</script>\n"
        f"<script>{DRAG_SCRIPT}</script>\n<script>{SCRIPT}</script>\n</body></html>\n"
    )


def _body(data: ExplorerData) -> str:
    """The page's controls, views and legend, in the words of the data's parameter."""
    p = data.parameter
    symbol, sets, joint = (html.escape(text, quote=False) for text in (p.symbol, p.set_symbol, p.joint_symbol))
    legend = [f'<span class="k curve"></span> {joint}<sub>i</sub>({symbol}) <span class="k limit"></span> limits']
    if data.branches[0].per_joint is not None:
        legend.append(f'<span class="k set-i"></span> {sets}<sub>i</sub>: joint i within its limits')
    legend.append(f'<span class="k set"></span> {sets}: all joints within')
    if "singular" in data.kinds:
        legend.append(f'<span class="k singular"></span> singular {symbol}')
    legend.append(f'<span class="k optimal"></span> optimal {symbol} ({html.escape(p.optimum, quote=False)})')
    if data.cell is not None:
        legend.append(f'<span class="k blocked"></span> {symbol} removed by an obstacle or the arm\'s own links '
                      f'(margin {data.cell.margin:g} m)')
    legend.append(f'<span class="k cursor"></span> the slider\'s {symbol}. Click a plot to move the slider there.')
    remarks = "".join(f'\n<p class="note remark">{html.escape(text, quote=False)}</p>'
                      for text in (*data.remarks, data.opening) if text)
    return f"""<div class="controls">
<label>branch <select id="branch" aria-label="branch ({html.escape(p.branch_signs)})"></select></label>
<label class="slider">{symbol} <input id="parameter" type="range" min="0" max="1" step="1" value="0" \
aria-label="{html.escape(p.noun)}"></label>
<output id="parameter-value" for="parameter"></output>
</div>
<p id="status" class="status"></p>
<div id="marks" class="marks" aria-label="special {html.escape(p.plural)}"></div>
<div class="views">
<figure class="view3d"><svg id="arm-view" viewBox="-1.1 -1.1 2.2 2.2" role="img" aria-label="posture in 3-D"></svg>
<figcaption>Posture at the slider's {symbol} (drag to rotate). Grey: paths of the moving joints over {symbol};
x red, y green, z blue; the target frame at the tool.{_cell_caption(data)}</figcaption></figure>
<div class="joints"><table id="joints"><thead><tr><th>joint</th><th class="num">value</th><th class="num">lower</th>
<th class="num">upper</th><th>in limits</th></tr></thead><tbody></tbody></table></div>
</div>
<div id="curves" class="curves"></div>
<p class="legend">{chr(10).join(legend)}</p>
<p class="note">Computed by redkin ({html.escape(data.method, quote=False)}); this page only draws
the numbers it holds: a dense grid of {html.escape(p.plural, quote=False)} with the exact ends of every set merged
in.</p>{remarks}"""


def _cell_caption(data: ExplorerData) -> str:
    """The 3-D view's words for the cell, if any."""
    if data.cell is None:
        return ""
    source = f" ({html.escape(data.cell.source, quote=False)})" if data.cell.source else ""
    return (f" Grey: the obstacles{source}; translucent blue: the arm's capsules, red where a pair is closer than "
            "the margin.")


def _pose_text(pose: np.ndarray) -> str:
    position = ", ".join(f"{v:.4g}" for v in pose[:3, 3])
    rotation = "; ".join(" ".join(f"{v + 0.0:.4g}" for v in row) for row in pose[:3, :3])
    return f"Tool pose: position ({position}) m, rotation [{rotation}] (rows)."


def _payload(data: ExplorerData, unit: str) -> dict[str, Any]:
    decimals = _DECIMALS[unit]

    def angle(values: Any) -> Any:
        """Angles in the page's unit, rounded to its digits; ``None`` for NaN (no solution there)."""
        array = np.degrees(values) if unit == "deg" else np.asarray(values, dtype=float)
        return _nullable(np.round(array, decimals) + 0.0)  # + 0.0: no -0

    def limit(value: float) -> float | None:
        return angle(value) if np.isfinite(value) else None

    p = data.parameter
    return {
        "robot": data.robot,
        "unit": unit,
        "decimals": decimals,
        "half_turn": angle(np.pi),
        "parameter": {"name": p.name, "symbol": p.symbol, "set": p.set_symbol, "noun": p.noun,
                      "joint": p.joint_symbol, "domain": angle(p.domain), "ticks": _ticks(p.domain, unit, angle)},
        "joints": list(data.joint_names),
        "lower": [limit(v) for v in data.lower],
        "upper": [limit(v) for v in data.upper],
        "target": {"position": _positions(data.pose[:3, 3]), "axes": _positions(data.pose[:3, :3].T)},
        "base": _positions(next(b.origins[b.exists][0, 0] for b in data.branches if b.exists.any())),
        "initial": data.initial,
        "branches": [_branch(b, p, angle, decimals) | ({} if data.cell is None else
                                                        {"cell": _branch_cell(data.cell.branches[k], p, angle)})
                     for k, b in enumerate(data.branches)],
        "cell": None if data.cell is None else _cell(data.cell),
    }


def _cell(cell: CellView) -> dict[str, Any]:
    """The cell's obstacles, links, radii, pairs and margin, positions rounded to the page's digits."""
    obstacles = []
    for obstacle in cell.obstacles:
        shown = dict(obstacle)
        for key in ("ends", "corners", "point", "normal"):
            if key in shown:
                shown[key] = _positions(np.asarray(shown[key], dtype=float))
        obstacles.append(shown)
    return {"obstacles": obstacles, "links": list(cell.links), "radii": _positions(cell.radii),
            "pairs": [list(pair) for pair in cell.pairs], "margin": cell.margin, "source": cell.source}


def _branch_cell(cell: BranchCell, parameter: Parameter, angle) -> dict[str, Any]:
    """One branch in the cell: its free and blocked intervals of the domain (each blocked one with its cause), the
    body's capsule ends at every grid value (``null`` where no solution), the least distance (``null`` where no
    solution or no pair to check) and the pair."""
    domain = parameter.domain
    blocked = [[*angle(piece), text] for lo, hi, text in cell.blocked
               for piece in _intervals(np.array([[lo, hi]]), domain)]
    distance = np.where(np.isfinite(cell.distance), cell.distance, np.nan)  # inf: no pair to check (null, as none)
    return {"free": angle(_intervals(cell.free, domain)), "blocked": blocked,
            "capsules": _positions(cell.capsules.ravel()), "distance": _positions(distance),
            "closest": cell.closest.tolist()}


def _branch(curves: BranchCurves, parameter: Parameter, angle, decimals: int) -> dict[str, Any]:
    jumps = np.abs(np.diff(curves.q, axis=0)) > np.pi  # a wrapped joint value: the curve is not joined there
    domain = parameter.domain
    return {
        "name": curves.branch,
        "label": f"{curves.branch}: {parameter.set_symbol} = {_arcs_text(curves, parameter, angle, decimals)}",
        "values": angle(curves.values),
        "q": angle(curves.q.T),
        "breaks": [(np.flatnonzero(jumps[:, j]) + 1).tolist() for j in range(curves.q.shape[1])],
        "exists": _flags(curves.exists),
        "within": [_flags(column) for column in curves.within.T],
        "feasible_at": _flags(curves.feasible_at),
        "per_joint": None if curves.per_joint is None else [angle(_intervals(arcs, domain))
                                                            for arcs in curves.per_joint],
        "feasible": angle(_intervals(curves.arcs, domain)),
        "notes": list(curves.notes),
        "marks": [{"kind": m.kind, "label": m.label, "index": m.index, "note": m.note} for m in curves.marks],
        "start": curves.start,
        "origins": [_origin(curves.origins[:, k], curves.exists) for k in range(curves.origins.shape[1])],
    }


def _flags(values: np.ndarray) -> str:
    return "".join("1" if v else "0" for v in values)


def _intervals(arcs: np.ndarray, domain: tuple[float, float]) -> np.ndarray:
    """Arcs ``[start, end]`` as intervals of the domain: an arc through its ends (``start > end``) in two."""
    pieces = [(lo, hi) for lo, hi in arcs if lo <= hi]
    pieces += [piece for lo, hi in arcs if lo > hi for piece in ((lo, domain[1]), (domain[0], hi))]
    return np.asarray(pieces, dtype=float).reshape(-1, 2)


def _ticks(domain: tuple[float, float], unit: str, angle) -> list[list[Any]]:
    """``[value, label]`` of the x axis: multiples of the largest of pi, pi/2, pi/4 that gives at least five
    within the domain, labelled in degrees or as fractions of pi."""
    low, high = domain
    for parts in (1, 2, 4):
        first, last = math.ceil(low * parts / np.pi - 1e-9), math.floor(high * parts / np.pi + 1e-9)
        if last - first >= 4:
            break
    ticks = []
    for k in range(first, last + 1):
        value = angle(k * np.pi / parts)
        ticks.append([value, f"{value:g}" if unit == "deg" else _pi_fraction(k, parts)])
    return ticks


def _pi_fraction(numerator: int, denominator: int) -> str:
    """``numerator * pi / denominator`` as a label: ``0``, ``π``, ``-π/2``, ``3π/4``."""
    if numerator == 0:
        return "0"
    common = math.gcd(numerator, denominator)
    top, bottom = numerator // common, denominator // common
    text = {1: "π", -1: "-π"}.get(top, f"{top}π")
    return text if bottom == 1 else f"{text}/{bottom}"


def _origin(path: np.ndarray, exists: np.ndarray) -> dict[str, list]:
    """One frame origin over the grid: ``{"at": [x, y, z]}`` if it stays put wherever the branch has a solution,
    else ``{"path": [x0, y0, z0, x1, ...]}`` with ``null`` where it has none."""
    shown = path[exists]
    if len(shown) and np.ptp(shown, axis=0).max() < _FIXED_ORIGIN:
        return {"at": _positions(shown[0])}
    return {"path": _positions(path.ravel())}


def _positions(values: np.ndarray) -> list:
    return _nullable(np.round(np.asarray(values, dtype=float), _POSITION_DECIMALS) + 0.0)


def _nullable(array: np.ndarray) -> Any:
    """``array.tolist()`` with ``None`` for NaN (JSON's ``null``)."""
    if np.isnan(array).any():
        return np.where(np.isnan(array), np.asarray(None, dtype=object), array.astype(object)).tolist()
    return array.tolist()


def _arcs_text(curves: BranchCurves, parameter: Parameter, angle, decimals: int) -> str:
    if not len(curves.arcs):
        return f"empty (no feasible {parameter.symbol})"
    if curves.full:
        return f"every {parameter.symbol}"
    return " ∪ ".join(f"[{lo:.{decimals}f}, {hi:.{decimals}f}]" for lo, hi in (angle(arc) for arc in curves.arcs))
