"""A timed path played back in the browser: one self-contained HTML page (``redkin path --playback``,
``redkin explore ROBOT --path RESULT.json``).

The page draws the arm moving along the trajectory (an orthographic view of its frame origins, turned by dragging,
with the tool's path traced), a time slider and a play button, and each joint's value and speed against time with
its position limits and speed limits, the reconfiguration stops shaded.  In a cell (issue 40) it draws the obstacles
and the arm's capsules too, and says how far the arm is from them at the slider's time.  As the explorer
(:mod:`redkin.explore.page`), it loads nothing: the numbers are JSON inside it, and the script computes nothing but
screen coordinates.  The trajectory is shown at :data:`FRAME_RATE` frames per second of its time (the samples in
between are the controller's, not the eye's), at most :data:`MAX_FRAMES` frames.
"""

from __future__ import annotations

import html
import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from redkin.chain import SerialChain
from redkin.collision.body import Body
from redkin.collision.scene import Scene
from redkin.errors import RedkinError
from redkin.explore.script import DRAG_SCRIPT, PAGE_STYLE

#: Frames of the page per second of the trajectory's time.
FRAME_RATE = 50.0
#: The most frames a page holds (a longer trajectory is shown at a lower frame rate).
MAX_FRAMES = 5000
#: Decimals of the stored positions [m], angles [rad] and times [s].
_DECIMALS = 5


@dataclass(frozen=True)
class StopSpan:
    """A reconfiguration stop on the time axis: from ``start`` to ``end`` seconds, and what it is in words."""

    start: float
    end: float
    text: str


def playback_html(chain: SerialChain, t: np.ndarray, q: np.ndarray, qd: np.ndarray,
                  stops: Sequence[StopSpan] = (), title: str = "", cell: tuple[Body, Scene] | None = None) -> str:
    """The playback page of a trajectory of ``chain``.

    Parameters
    ----------
    chain : SerialChain
        The arm (its frames, joint names, position and speed limits).
    t : numpy.ndarray, shape (M,)
        Seconds, increasing.
    q, qd : numpy.ndarray, shape (M, n)
        Joint values (rad) and speeds (rad/s) at ``t``.
    stops : sequence of StopSpan
        Spans to shade and name (the reconfiguration stops).
    title : str
        The page's heading (default: the robot's name and the duration).
    cell : (Body, Scene), optional
        The arm's body and a scene: the page draws the obstacles and the arm's capsules at each frame (red where a
        pair is within the margin) and says the least distance and its pair at the slider's time.

    Returns
    -------
    str
        A complete HTML document.

    Raises
    ------
    RedkinError
        For arrays of the wrong shape, not finite, or times not increasing.
    """
    t, q, qd = (np.asarray(v, dtype=float) for v in (t, q, qd))
    if t.ndim != 1 or len(t) == 0 or q.shape != (len(t), chain.n) or qd.shape != q.shape:
        raise RedkinError(f"a trajectory needs t (M,), q and qd (M, {chain.n}); got {t.shape}, {q.shape}, {qd.shape}")
    if not (np.isfinite(t).all() and np.isfinite(q).all() and np.isfinite(qd).all()):
        raise RedkinError("the trajectory's times, joint values and speeds must be finite")
    if np.any(np.diff(t) <= 0.0):
        raise RedkinError("the trajectory's times must increase")
    duration = float(t[-1] - t[0])
    frames = int(min(MAX_FRAMES, max(2, np.ceil(duration * FRAME_RATE) + 1)))
    shown = np.unique(np.r_[np.searchsorted(t, np.linspace(t[0], t[-1], frames)).clip(0, len(t) - 1), len(t) - 1])
    origins = chain.frames(q[shown])[..., :3, 3]
    heading = title or f"{chain.name}: a trajectory of {duration:.3f} s"
    data = _payload(chain, t[shown], q[shown], qd[shown], origins, stops)
    if cell is not None:
        data["cell"] = _cell(chain, q[shown], *cell)
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
        f"<title>{html.escape(heading)}</title><style>{_STYLE}</style></head><body>\n"
        f"<header><h1>{html.escape(heading)}</h1></header>\n{_BODY}\n"
        f"<script id=\"playback-data\" type=\"application/json\">{payload}</script>\n"
        f"<script>{DRAG_SCRIPT}</script>\n<script>{_SCRIPT}</script>\n</body></html>\n"
    )


def _payload(chain: SerialChain, t: np.ndarray, q: np.ndarray, qd: np.ndarray, origins: np.ndarray,
             stops: Sequence[StopSpan]) -> dict[str, Any]:
    def rounded(values: Any) -> Any:
        return (np.round(np.asarray(values, dtype=float), _DECIMALS) + 0.0).tolist()

    def finite(values: np.ndarray) -> list:
        return [None if not np.isfinite(v) else round(float(v), _DECIMALS) for v in values]

    return {"robot": chain.name, "joints": list(chain.joint_names), "t": rounded(t - t[0]), "q": rounded(q.T),
            "qd": rounded(qd.T), "origins": rounded(origins), "tool": rounded(origins[:, -1]),
            "lower": finite(chain.lower), "upper": finite(chain.upper), "speed": finite(chain.velocity),
            "stops": [{"start": round(s.start - float(t[0]), _DECIMALS), "end": round(s.end - float(t[0]), _DECIMALS),
                       "text": s.text} for s in stops]}


def _cell(chain: SerialChain, q: np.ndarray, body: Body, scene: Scene) -> dict[str, Any]:
    """The cell at the page's frames ``q``: the obstacles to draw, the body's capsules at each frame (their ends, flat
    ``(F * M * 6)``), and the least distance over the checked pairs with the pair that has it."""
    from redkin.collision.body import capsule_ends, posed
    from redkin.collision.clearance import least_pair, pair_table
    from redkin.explore.cell import obstacle_drawing

    table, pairs = pair_table(chain, body, scene, q)
    ends = capsule_ends(posed(body, chain.frames(q)))
    least, closest = least_pair(table)
    return {"obstacles": [obstacle_drawing(name, row) for name, row in zip(scene.names, scene.shapes, strict=True)],
            "links": list(body.link), "radii": [float(r) for r in body.radius], "margin": float(scene.margin),
            "pairs": [list(pair) for pair in pairs.names],
            "capsules": (np.round(ends.ravel(), _DECIMALS) + 0.0).tolist(),
            "distance": [None if not np.isfinite(d) else round(float(d), _DECIMALS) for d in least],
            "closest": [int(k) for k in closest]}


_BODY = """<div class="controls">
<button id="play" type="button">Play</button>
<label class="slider">t <input id="time" type="range" min="0" value="0" step="1" aria-label="time"></label>
<output id="time-value"></output></div>
<p id="status" class="status"></p>
<div class="views"><figure class="view3d"><svg id="arm-view" viewBox="-1 -1 2 2"></svg>
<figcaption>The arm at the slider's time (drag to turn the view); grey: the tool's path; in a cell, the obstacles
in grey and the arm's capsules in blue (red: within the margin).</figcaption></figure>
<div class="joints"><table id="joints"><thead><tr><th>joint</th><th>q [rad]</th><th>qd [rad/s]</th></tr></thead>
<tbody></tbody></table></div></div>
<section class="curves" id="curves"></section>
<p class="legend"><span class="k curve"></span>q(t) <span class="k speed"></span>qd(t)
<span class="k limit"></span>limits (position; speed dashed thin) <span class="k stop"></span>reconfiguration stop
<span class="k cursor"></span>the slider's time</p>"""

_STYLE = PAGE_STYLE + """
.status { min-height: 1.4em; }
.k.speed { border-top: 2px solid #2864b4; height: 0; }
.k.stop { background: rgba(208, 112, 0, 0.25); }
"""

_SCRIPT = r"""
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("playback-data").textContent);
  const NS = "http://www.w3.org/2000/svg";
  const W = 640, H = 110, LEFT = 56, RIGHT = 10, TOP = 8, BOTTOM = 20;
  const slider = document.getElementById("time"), play = document.getElementById("play");
  const view3d = document.getElementById("arm-view");
  const last = D.t.length - 1, duration = D.t[last];
  const view = { az: 0.8, el: 0.45 };
  let index = 0, timer = null, cursors = [];
  slider.max = String(last);

  function node(name, attrs, parent) {
    const e = document.createElementNS(NS, name);
    for (const key in attrs) e.setAttribute(key, attrs[key]);
    if (parent) parent.appendChild(e);
    return e;
  }
  const all = D.origins.flat();
  if (D.cell) for (const o of D.cell.obstacles) {
    if (o.kind === "capsule") all.push(...o.ends);
    else if (o.kind === "box") all.push(...o.corners);
  }
  const centre = [0, 1, 2].map(i => 0.5 * (Math.min(...all.map(p => p[i])) + Math.max(...all.map(p => p[i]))));
  function project(p) {  // orthographic, about the centre of everything the arm sweeps
    const ca = Math.cos(view.az), sa = Math.sin(view.az), ce = Math.cos(view.el), se = Math.sin(view.el);
    const px = p[0] - centre[0], py = p[1] - centre[1], pz = p[2] - centre[2];
    const x = ca * px - sa * py, y = sa * px + ca * py;
    return [x, -(ce * pz - se * y)];
  }
  const reach = Math.max(1e-3, ...all.map(p => Math.hypot(p[0] - centre[0], p[1] - centre[1], p[2] - centre[2])));
  view3d.setAttribute("viewBox", [-1.15 * reach, -1.15 * reach, 2.3 * reach, 2.3 * reach].join(" "));
  const stroke = (reach / 120).toFixed(5);
  const points = list => list.map(p => project(p).join(",")).join(" ");
  const draw = cellDrawing(node, points, radius => Math.max(2 * radius, reach / 200), reach / 200);
  function tooClose() {
    const d = D.cell.distance[index];
    return d !== null && d < D.cell.margin ? D.cell.pairs[D.cell.closest[index]] : null;
  }
  function drawCell() {
    const g = node("g", { id: "cell" }, view3d), count = D.cell.links.length, c = D.cell.capsules;
    draw.obstacles(g, D.cell.obstacles);
    const close = tooClose();
    for (let m = 0; m < count; m++) {
      const at = 6 * (index * count + m), hit = close !== null && close.indexOf(D.cell.links[m]) >= 0;
      draw.capsule(g, c.slice(at, at + 3), c.slice(at + 3, at + 6), D.cell.radii[m],
                   hit ? "rgba(200,40,40,0.6)" : "rgba(31,78,154,0.3)", hit ? "body hit" : "body");
    }
  }
  function cellStatus() {
    return distanceWords(D.cell.distance[index], D.cell.pairs[D.cell.closest[index]] || ["", ""], D.cell.margin);
  }

  function drawArm() {
    view3d.textContent = "";
    if (D.cell) drawCell();
    node("polyline", { points: points(D.tool), fill: "none", stroke: "#aaa", "stroke-width": stroke,
                       id: "tool-path" }, view3d);
    const pts = D.origins[index].map(project);
    node("polyline", { id: "arm", points: pts.map(p => p.join(",")).join(" "), fill: "none", stroke: "#1d1d1d",
                       "stroke-width": 3 * stroke, "stroke-linejoin": "round" }, view3d);
    for (const p of pts) node("circle", { cx: p[0], cy: p[1], r: 2.5 * stroke, fill: "#2864b4" }, view3d);
  }
  function stopAt(t) { return D.stops.find(s => t >= s.start - 1e-9 && t <= s.end + 1e-9); }
  function update() {
    const t = D.t[index];
    document.getElementById("time-value").textContent = t.toFixed(3) + " / " + duration.toFixed(3) + " s";
    const stop = stopAt(t), status = document.getElementById("status");
    status.textContent = (stop ? "Stopped: " + stop.text : "") + (D.cell ? cellStatus() : "");
    status.classList.toggle("bad", Boolean(D.cell) && tooClose() !== null);
    const rows = document.querySelectorAll("#joints tbody tr");
    rows.forEach((row, j) => {
      row.children[1].textContent = D.q[j][index].toFixed(3);
      row.children[2].textContent = D.qd[j][index].toFixed(3);
    });
    const x = LEFT + (W - LEFT - RIGHT) * (duration > 0 ? t / duration : 0);
    for (const c of cursors) { c.setAttribute("x1", x); c.setAttribute("x2", x); }
    drawArm();
  }
  function curves() {
    const host = document.getElementById("curves"), body = document.querySelector("#joints tbody");
    D.joints.forEach((name, j) => {
      const tr = document.createElement("tr");
      tr.innerHTML = "<td></td><td class='num value'></td><td class='num value'></td>";
      tr.children[0].textContent = name;
      body.appendChild(tr);
      const values = D.q[j].concat(D.qd[j]);
      for (const v of [D.lower[j], D.upper[j], D.speed[j], D.speed[j] === null ? null : -D.speed[j]])
        if (v !== null) values.push(v);
      const lo = Math.min(...values), hi = Math.max(...values), span = hi - lo || 1;
      const sx = t => LEFT + (W - LEFT - RIGHT) * (duration > 0 ? t / duration : 0);
      const sy = v => TOP + (H - TOP - BOTTOM) * (hi - v) / span;
      const svg = node("svg", { viewBox: `0 0 ${W} ${H}`, role: "img", "aria-label": name + " against time" }, host);
      for (const s of D.stops)
        node("rect", { x: sx(s.start), y: TOP, width: Math.max(1, sx(s.end) - sx(s.start)), height: H - TOP - BOTTOM,
                       fill: "rgba(208,112,0,0.25)", class: "stop" }, svg);
      for (const [v, width] of [[D.lower[j], 1.5], [D.upper[j], 1.5], [D.speed[j], 0.8],
                                [D.speed[j] === null ? null : -D.speed[j], 0.8]])
        if (v !== null) node("line", { x1: LEFT, x2: W - RIGHT, y1: sy(v), y2: sy(v), stroke: "#c03030",
                                       "stroke-dasharray": "5 3", "stroke-width": width }, svg);
      for (const [series, color] of [[D.q[j], "#111"], [D.qd[j], "#2864b4"]])
        node("polyline", { points: series.map((v, k) => sx(D.t[k]) + "," + sy(v)).join(" "), fill: "none",
                           stroke: color, "stroke-width": 1.5 }, svg);
      const label = node("text", { x: 4, y: TOP + 12, "font-size": 12 }, svg);
      label.textContent = name;
      for (const [v, y] of [[hi, TOP + 26], [lo, H - BOTTOM - 2]]) {
        const tick = node("text", { x: 4, y: y, "font-size": 10, fill: "#555" }, svg);
        tick.textContent = v.toFixed(2);
      }
      cursors.push(node("line", { y1: TOP, y2: H - BOTTOM, stroke: "#888", "stroke-width": 1.5 }, svg));
    });
  }
  function step() {
    if (index >= last) { stopPlaying(); return; }
    index += 1;
    slider.value = String(index);
    update();
  }
  function stopPlaying() { if (timer !== null) clearInterval(timer); timer = null; play.textContent = "Play"; }
  play.addEventListener("click", () => {
    if (timer !== null) { stopPlaying(); return; }
    if (index >= last) index = 0;
    play.textContent = "Pause";
    timer = setInterval(step, 1000 * (duration > 0 ? duration / Math.max(1, last) : 0.02));
  });
  slider.addEventListener("input", () => { index = Number(slider.value); update(); });
  turnByDragging(view3d, view, drawArm);
  curves();
  update();
})();
"""
