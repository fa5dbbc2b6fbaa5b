"""The arm-angle explorer as one self-contained HTML page: the numbers as JSON, a small script that draws them.

The page loads nothing from anywhere: its style, script and data are inside
it, so it works from a file, offline, with no server.  The script only
draws: every angle, position, limit flag and special arm angle comes from
:func:`redkin.explore.data.explorer_data`, rounded to the digits it prints.
"""

from __future__ import annotations

import html
import json
from typing import Any

import numpy as np

from redkin.circle import ArcSet
from redkin.explore.data import BranchCurves, ExplorerData
from redkin.explore.script import SCRIPT, STYLE

#: Decimals of the printed angles in each unit (0.001 deg is about 2e-5 rad).
_DECIMALS = {"deg": 3, "rad": 5}
#: Decimals of the stored positions [m] (0.01 mm: far below a pixel).
_POSITION_DECIMALS = 5
#: A frame origin that moves less than this [m] over the arm angle is stored once.
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
    title = f"Arm-angle explorer: {data.robot}"
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>\n"
        f"<header><h1>{html.escape(title)}</h1><p class=\"pose\">{html.escape(_pose_text(data.pose))}</p></header>\n"
        f"{_BODY}\n<script id=\"explorer-data\" type=\"application/json\">{payload}</script>\n"
        f"<script>{SCRIPT}</script>\n</body></html>\n"
    )


_BODY = """<div class="controls">
<label>branch <select id="branch" aria-label="branch (signs of theta 2, 4, 6)"></select></label>
<label class="slider">ψ <input id="psi" type="range" min="0" max="1" step="1" value="0" aria-label="arm angle"></label>
<output id="psi-value" for="psi"></output>
</div>
<p id="status" class="status"></p>
<div id="marks" class="marks" aria-label="special arm angles"></div>
<div class="views">
<figure class="view3d"><svg id="arm-view" viewBox="-1.1 -1.1 2.2 2.2" role="img" aria-label="posture in 3-D"></svg>
<figcaption>Posture at the slider's ψ (drag to rotate). Grey: paths of the moving joints over ψ;
x red, y green, z blue; the target frame at the tool.</figcaption></figure>
<div class="joints"><table id="joints"><thead><tr><th>joint</th><th class="num">value</th><th class="num">lower</th>
<th class="num">upper</th><th>in limits</th></tr></thead><tbody></tbody></table></div>
</div>
<div id="curves" class="curves"></div>
<p class="legend"><span class="k curve"></span> θ<sub>i</sub>(ψ) <span class="k limit"></span> limits
<span class="k psi-i"></span> Ψ<sub>i</sub>: joint i within its limits <span class="k psi"></span> Ψ: all joints within
<span class="k singular"></span> singular ψ <span class="k optimal"></span> optimal ψ ([000 eq. 40])
<span class="k cursor"></span> the slider's ψ. Click a plot to move the slider there.</p>
<p class="note">Computed by redkin (paper 000's closed-form arm-angle IK and exact feasible sets); this page only draws
the numbers it holds: a dense grid of arm angles with the exact ends of every set merged in.</p>"""


def _pose_text(pose: np.ndarray) -> str:
    position = ", ".join(f"{v:.4g}" for v in pose[:3, 3])
    rotation = "; ".join(" ".join(f"{v + 0.0:.4g}" for v in row) for row in pose[:3, :3])
    return f"Tool pose: position ({position}) m, rotation [{rotation}] (rows)."


def _payload(data: ExplorerData, unit: str) -> dict[str, Any]:
    decimals = _DECIMALS[unit]

    def angle(values: Any) -> Any:
        array = np.degrees(values) if unit == "deg" else np.asarray(values, dtype=float)
        return (np.round(array, decimals) + 0.0).tolist()  # + 0.0: no -0

    def limit(value: float) -> float | None:
        return angle(value) if np.isfinite(value) else None

    return {
        "robot": data.robot,
        "unit": unit,
        "decimals": decimals,
        "half_turn": angle(np.pi),
        "joints": list(data.joint_names),
        "lower": [limit(v) for v in data.lower],
        "upper": [limit(v) for v in data.upper],
        "target": {"position": _positions(data.pose[:3, 3]), "axes": _positions(data.pose[:3, :3].T)},
        "initial": data.initial,
        "branches": [_branch(b, angle, decimals) for b in data.branches],
    }


def _branch(curves: BranchCurves, angle, decimals: int) -> dict[str, Any]:
    jumps = np.abs(np.diff(curves.q, axis=0)) > np.pi  # a wrapped joint value: the curve is not joined there
    return {
        "name": curves.branch,
        "label": f"{curves.branch}: Ψ = {_arcs_text(curves.feasible, angle, decimals)}",
        "psi": angle(curves.psi),
        "q": angle(curves.q.T),
        "breaks": [(np.flatnonzero(jumps[:, j]) + 1).tolist() for j in range(curves.q.shape[1])],
        "within": ["".join("1" if v else "0" for v in column) for column in curves.within.T],
        "feasible_at": "".join("1" if v else "0" for v in curves.feasible_at),
        "per_joint": [angle(curves.per_joint[j + 1].intervals) for j in range(curves.q.shape[1])],
        "feasible": angle(curves.feasible.intervals),
        "singular_everywhere": [name for name, every in (("shoulder", curves.singular.shoulder_everywhere),
                                                        ("wrist", curves.singular.wrist_everywhere)) if every],
        "marks": [{"kind": m.kind, "label": m.label, "index": m.index, "note": m.note} for m in curves.marks],
        "start": curves.start,
        "origins": [_origin(curves.origins[:, k]) for k in range(curves.origins.shape[1])],
    }


def _origin(path: np.ndarray) -> dict[str, list[float]]:
    """One frame origin over the grid: ``{"at": [x, y, z]}`` if it stays put, else
    ``{"path": [x0, y0, z0, x1, ...]}``."""
    if np.ptp(path, axis=0).max() < _FIXED_ORIGIN:
        return {"at": _positions(path[0])}
    return {"path": _positions(path.ravel())}


def _positions(values: np.ndarray) -> list:
    return (np.round(np.asarray(values, dtype=float), _POSITION_DECIMALS) + 0.0).tolist()


def _arcs_text(arcs: ArcSet, angle, decimals: int) -> str:
    if arcs.is_empty:
        return "empty (no feasible ψ)"
    if arcs.is_full:
        return "every ψ"
    return " ∪ ".join(f"[{lo:.{decimals}f}, {hi:.{decimals}f}]" for lo, hi in (angle(arc) for arc in arcs.arcs))
