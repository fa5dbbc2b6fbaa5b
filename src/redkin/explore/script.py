"""Style and script of the explorer page (kept in Python so that an installed package always carries them).

The script draws the numbers of the page's JSON and computes none of its
own beyond screen coordinates: an orthographic view of the posture (turned
by dragging), the curves of every joint over the redundancy parameter with
their limits, sets and marks, and the joint values at the slider's value.
The parameter's symbols, domain and ticks come from the JSON: the same
script draws the arm angle psi and q7.  Where a branch has no solution (its
joint values are ``null``) the curves break, and no posture is drawn.
"""

#: The layout the explorer shares with the playback page (:mod:`redkin.explore.playback`): the page, its controls,
#: the 3-D view, the joint table, the curves and the legend's keys.
PAGE_STYLE = """
*, *::before, *::after { box-sizing: border-box; }
html { -webkit-text-size-adjust: 100%; }
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; max-width: 68em; margin: 0 auto;
       padding: 0.5em clamp(0.6em, 3vw, 2em) 2em; color: #1d1d1d; line-height: 1.45; }
h1 { font-size: 1.35em; margin: 0.3em 0 0.1em; }
p.pose, p.note, figcaption, p.legend { font-size: 0.86em; color: #444; overflow-wrap: break-word; }
.controls { display: flex; flex-wrap: wrap; align-items: center; gap: 0.4em 1em; margin: 0.6em 0 0.2em; }
.controls select { max-width: 100%; font-size: 0.95em; }
.controls label { max-width: 100%; }
label.slider { display: flex; align-items: center; gap: 0.5em; flex: 1 1 16em; }
label.slider input { flex: 1 1 auto; min-width: 8em; }
output { font-variant-numeric: tabular-nums; font-weight: 600; min-width: 9em; }
.status { margin: 0.2em 0; font-size: 0.92em; }
.status .bad { color: #8a0000; font-weight: 600; }
.views { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
figure.view3d { margin: 0; flex: 1 1 18em; max-width: 30em; }
figure.view3d svg { width: 100%; height: auto; border: 1px solid #ccc; background: #fcfcfc; touch-action: none;
                    cursor: grab; display: block; }
.joints { flex: 1 1 16em; overflow-x: auto; }
table { border-collapse: collapse; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.2em 0.5em; text-align: left; }
thead th { background: #eee; }
.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td:first-child { white-space: nowrap; }
.curves svg { width: 100%; height: auto; display: block; margin: 0.15em 0; }
.k { display: inline-block; width: 1.4em; height: 0.7em; margin: 0 0.2em 0 0.6em; vertical-align: middle; }
.k.curve { border-top: 2px solid #111; height: 0; }
.k.limit { border-top: 2px dashed #c03030; height: 0; }
.k.cursor { border-top: 2px solid #888; height: 0; }
"""

STYLE = PAGE_STYLE + """
.marks { display: flex; flex-wrap: wrap; gap: 0.3em; margin: 0.3em 0 0.6em; }
.marks button { font-size: 0.8em; padding: 0.15em 0.5em; border: 1px solid #999; background: #f6f6f6;
                border-radius: 3px; cursor: pointer; }
.marks button.optimal { border-color: #d07000; }
.marks button.singular { border-color: #7a3db8; }
.marks button.feasible { border-color: #2864b4; }
td.out { color: #8a0000; font-weight: 600; }
.k.set-i { background: rgba(40, 160, 60, 0.25); }
.k.set { background: rgba(40, 100, 180, 0.25); }
.k.singular { border-top: 2px dashed #7a3db8; height: 0; }
.k.optimal { border-top: 2px solid #d07000; height: 0; }
.k.blocked { background: rgba(200, 60, 40, 0.3); }
"""

#: How both pages (the explorer, and the playback page of :mod:`redkin.explore.playback`) turn their 3-D view (a drag
#: across turns it about the vertical, a drag up or down tilts it; the page's script calls ``turnByDragging``) and
#: draw a cell's obstacles and the arm's capsules (``cellDrawing``) and word the least distance (``distanceWords``).
DRAG_SCRIPT = r"""
"use strict";
function turnByDragging(svg, view, redraw) {
  let drag = null;
  svg.addEventListener("pointerdown", e => {
    drag = [e.clientX, e.clientY];
    svg.setPointerCapture(e.pointerId);
  });
  svg.addEventListener("pointermove", e => {
    if (!drag) return;
    view.az -= 0.01 * (e.clientX - drag[0]);
    view.el = Math.max(-1.5, Math.min(1.5, view.el + 0.01 * (e.clientY - drag[1])));
    drag = [e.clientX, e.clientY];
    redraw();
  });
  const stop = () => { drag = null; };
  svg.addEventListener("pointerup", stop);
  svg.addEventListener("pointercancel", stop);
}

// How both pages draw a cell (issue 40): a capsule as a thick round-capped segment, an obstacle as a grey
// capsule or a box's twelve edges.  node(name, attrs, parent) makes an SVG element, points(list) projects 3-D points
// to an SVG points attribute, widthOf(radius) is a capsule's stroke width and edge a box edge's.
function cellDrawing(node, points, widthOf, edge) {
  const BOX_EDGES = [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]];
  function capsule(g, a, b, radius, colour, cls) {
    node("polyline", { class: cls, points: points([a, b]), stroke: colour, "stroke-width": widthOf(radius),
                       fill: "none", "stroke-linecap": "round" }, g);
  }
  function obstacles(g, list) {
    for (const o of list) {
      if (o.kind === "capsule") capsule(g, o.ends[0], o.ends[1], o.radius, "rgba(110,110,110,0.45)", "obstacle");
      else if (o.kind === "box") {
        for (const [i, j] of BOX_EDGES) {
          node("polyline", { class: "obstacle", points: points([o.corners[i], o.corners[j]]), stroke: "#777",
                             "stroke-width": edge, fill: "none" }, g);
        }
      }
    }
  }
  return { capsule: capsule, obstacles: obstacles };
}

// The status words of the least distance d (metres; null: no pair to check) and its pair, against the margin.
function distanceWords(d, pair, margin) {
  if (d === null) return " No pair to check.";
  if (d < 0) return " " + pair[0] + " meets " + pair[1] + " (" + d.toFixed(4) + " m).";
  if (d < margin) return " " + pair[0] + " is within the margin of " + pair[1] + " (" + d.toFixed(4) + " m).";
  return " Clear of the obstacles: the least distance is " + d.toFixed(4) + " m (" + pair[0] + " and " + pair[1]
    + ").";
}
"""

SCRIPT = r"""
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("explorer-data").textContent);
  const P = D.parameter;
  const NS = "http://www.w3.org/2000/svg";
  const W = 640, H = 128, LEFT = 56, RIGHT = 10, TOP = 8, BOTTOM = 22;
  const slider = document.getElementById("parameter");
  const select = document.getElementById("branch");
  const view3d = document.getElementById("arm-view");
  const half = D.half_turn;
  const low = P.domain[0], high = P.domain[1];
  const view = { az: 0.8, el: 0.45 };
  let branch = D.branches[D.initial];
  let index = branch.start;
  let cursors = [];

  function node(name, attrs, parent) {
    const e = document.createElementNS(NS, name);
    for (const key in attrs) e.setAttribute(key, attrs[key]);
    if (parent) parent.appendChild(e);
    return e;
  }
  function fmt(v) { return v === null ? "none" : v.toFixed(D.decimals); }
  function angleText(v) { return fmt(v) + " " + D.unit; }
  function nearest(values, v) {
    let lo = 0, hi = values.length - 1;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (values[mid] <= v) lo = mid; else hi = mid; }
    return Math.abs(values[hi] - v) < Math.abs(values[lo] - v) ? hi : lo;
  }
  function pointAt(o, i) {
    if (o.at) return o.at;
    return o.path[3 * i] === null ? null : [o.path[3 * i], o.path[3 * i + 1], o.path[3 * i + 2]];
  }
  function solved(b, i) { return b.exists[i] === "1"; }

  // ---- the 3-D view: orthographic, turned by dragging
  const bounds = (function () {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    function add(p) { for (let k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], p[k]); hi[k] = Math.max(hi[k], p[k]); } }
    for (const b of D.branches) for (const o of b.origins) {
      if (o.at) add(o.at);
      else for (let i = 0; i < o.path.length; i += 3) if (o.path[i] !== null) add(o.path.slice(i, i + 3));
    }
    add(D.target.position);
    if (D.cell) for (const o of D.cell.obstacles) {
      if (o.kind === "capsule") o.ends.forEach(add);
      else if (o.kind === "box") o.corners.forEach(add);
    }
    const centre = lo.map((v, k) => (v + hi[k]) / 2);
    const radius = Math.max(0.05, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
    return { centre: centre, radius: radius };
  })();
  function project(p) {
    const ca = Math.cos(view.az), sa = Math.sin(view.az), ce = Math.cos(view.el), se = Math.sin(view.el);
    const x = p[0] - bounds.centre[0], y = p[1] - bounds.centre[1], z = p[2] - bounds.centre[2];
    const right = -sa * x + ca * y, up = -se * (ca * x + sa * y) + ce * z;
    return [right / bounds.radius, -up / bounds.radius];
  }
  function points(list) { return list.map(p => project(p).map(v => v.toFixed(4)).join(",")).join(" "); }
  function drawAxes(group, origin, axes, length, width) {
    const colours = ["#d03030", "#20a040", "#2060d0"];
    axes.forEach((axis, k) => {
      const end = origin.map((v, c) => v + length * axis[c]);
      node("polyline", { points: points([origin, end]), stroke: colours[k], "stroke-width": width, fill: "none" },
           group);
    });
  }
  function drawView() {
    view3d.textContent = "";
    const g = node("g", { "stroke-linecap": "round", "stroke-linejoin": "round" }, view3d);
    drawAxes(g, D.base, [[1, 0, 0], [0, 1, 0], [0, 0, 1]], 0.3 * bounds.radius, 0.012);
    for (const o of branch.origins) {
      if (!o.path) continue;
      let path = [];
      const flush = () => {
        if (path.length > 1) {
          node("polyline", { class: "locus", points: points(path), stroke: "#b8b8b8", "stroke-width": 0.008,
                             fill: "none" }, g);
        }
        path = [];
      };
      for (let i = 0; i < o.path.length; i += 3) {
        if (o.path[i] === null) flush(); else path.push(o.path.slice(i, i + 3));
      }
      flush();
    }
    drawAxes(g, D.target.position, D.target.axes, 0.18 * bounds.radius, 0.014);
    if (D.cell) drawObstacles(g);
    if (!solved(branch, index)) return;
    if (D.cell) drawBody(g);
    const frames = branch.origins.map(o => pointAt(o, index));
    node("polyline", { id: "arm", points: points(frames), stroke: "#1f4e9a", "stroke-width": 0.03, fill: "none" }, g);
    for (const p of frames) {
      const s = project(p);
      node("circle", { cx: s[0].toFixed(4), cy: s[1].toFixed(4), r: 0.022, fill: "#fff", stroke: "#1f4e9a",
                       "stroke-width": 0.01 }, g);
    }
  }
  // ---- the cell: obstacles in grey, the arm's capsules at the slider's value (red where a pair is too close)
  const draw = cellDrawing(node, points, radius => Math.max(2 * radius / bounds.radius, 0.004), 0.006);
  function drawObstacles(g) { draw.obstacles(g, D.cell.obstacles); }
  function tooClose() {
    const d = branch.cell.distance[index];
    return d !== null && d < D.cell.margin ? D.cell.pairs[branch.cell.closest[index]] : null;
  }
  function drawBody(g) {
    const count = D.cell.links.length, c = branch.cell.capsules, close = tooClose();
    for (let m = 0; m < count; m++) {
      const at = 6 * (index * count + m);
      if (c[at] === null) continue;
      const hit = close !== null && close.indexOf(D.cell.links[m]) >= 0;
      draw.capsule(g, c.slice(at, at + 3), c.slice(at + 3, at + 6), D.cell.radii[m],
                   hit ? "rgba(200,40,40,0.6)" : "rgba(31,78,154,0.3)", hit ? "body hit" : "body");
    }
  }
  function cellStatus() {
    if (!D.cell || !solved(branch, index)) return null;
    const value = branch.values[index];
    const d = branch.cell.distance[index], pair = D.cell.pairs[branch.cell.closest[index]] || ["", ""];
    const free = branch.cell.free.some(([lo, hi]) => lo <= value && value <= hi);
    const cause = branch.cell.blocked.find(([lo, hi]) => lo <= value && value <= hi);
    const span = document.createElement("span");
    span.className = "cell" + (d !== null && d < D.cell.margin ? " bad" : "");
    const where = free ? " " + P.symbol + " is in the collision-free set." : cause ? " Removed: " + cause[2] + "."
      : "";
    span.textContent = distanceWords(d, pair, D.cell.margin) + (d === null ? "" : where);
    return span;
  }
  turnByDragging(view3d, view, drawView);

  // ---- the curves of every joint over the parameter
  function niceStep(span) {
    const raw = span / 4, power = Math.pow(10, Math.floor(Math.log10(raw)));
    for (const m of [1, 2, 5, 10]) if (m * power >= raw) return m * power;
    return 10 * power;
  }
  function xOf(v) { return LEFT + (v - low) / (high - low) * (W - LEFT - RIGHT); }
  function buildCurves() {
    const box = document.getElementById("curves");
    box.textContent = "";
    cursors = [];
    D.joints.forEach((name, j) => {
      const q = branch.q[j];
      const shown = q.filter(v => v !== null);
      let ymin = Math.min.apply(null, shown), ymax = Math.max.apply(null, shown);
      if (D.lower[j] !== null) ymin = Math.min(ymin, D.lower[j]);
      if (D.upper[j] !== null) ymax = Math.max(ymax, D.upper[j]);
      if (!isFinite(ymin) || !isFinite(ymax)) { ymin = -half; ymax = half; }
      const pad = Math.max(0.06 * (ymax - ymin), half / 36);
      ymin -= pad; ymax += pad;
      const yOf = v => TOP + (ymax - v) / (ymax - ymin) * (H - TOP - BOTTOM);
      const svg = node("svg", { viewBox: "0 0 " + W + " " + H, class: "curve", "data-joint": j + 1,
                                role: "img", "aria-label": "joint " + (j + 1) + " over the " + P.noun }, box);
      const plotTop = TOP, plotHeight = H - TOP - BOTTOM;
      function band(intervals, colour, cls) {
        for (const [lo, hi] of intervals) {
          const attrs = { x: xOf(lo), y: plotTop, width: Math.max(xOf(hi) - xOf(lo), 0.8), height: plotHeight,
                          fill: colour };
          if (cls) attrs.class = cls;
          node("rect", attrs, svg);
        }
      }
      if (branch.per_joint !== null) band(branch.per_joint[j], "rgba(40,160,60,0.22)");
      band(branch.feasible, "rgba(40,100,180,0.22)");
      if (branch.cell) band(branch.cell.blocked.map(b => [b[0], b[1]]), "rgba(200,60,40,0.3)", "blocked");
      node("rect", { x: LEFT, y: plotTop, width: W - LEFT - RIGHT, height: plotHeight, fill: "none",
                     stroke: "#999" }, svg);
      const step = niceStep(ymax - ymin);
      for (let t = Math.ceil(ymin / step) * step; t <= ymax; t += step) {
        node("line", { x1: LEFT - 4, x2: LEFT, y1: yOf(t), y2: yOf(t), stroke: "#666" }, svg);
        const label = node("text", { x: LEFT - 6, y: yOf(t) + 4, "text-anchor": "end", "font-size": 11 }, svg);
        label.textContent = Math.abs(t) < step / 1e6 ? "0" : +t.toPrecision(6);
      }
      for (const [v, text] of P.ticks) {
        node("line", { x1: xOf(v), x2: xOf(v), y1: plotTop + plotHeight, y2: plotTop + plotHeight + 4,
                       stroke: "#666" }, svg);
        const label = node("text", { x: xOf(v), y: H - 5, "text-anchor": "middle", "font-size": 11 }, svg);
        label.textContent = text;
      }
      const title = node("text", { x: 6, y: plotTop + plotHeight / 2, "font-size": 12, "font-weight": 600 }, svg);
      title.textContent = P.joint + (j + 1);
      for (const limit of [D.lower[j], D.upper[j]]) {
        if (limit === null) continue;
        node("line", { x1: LEFT, x2: W - RIGHT, y1: yOf(limit), y2: yOf(limit), stroke: "#c03030",
                       "stroke-dasharray": "6 4", "stroke-width": 1.2 }, svg);
      }
      for (const mark of branch.marks) {
        if (mark.kind === "feasible") continue;
        const x = xOf(branch.values[mark.index]);
        node("line", { x1: x, x2: x, y1: plotTop, y2: plotTop + plotHeight, "stroke-width": 1.4,
                       stroke: mark.kind === "singular" ? "#7a3db8" : "#d07000",
                       "stroke-dasharray": mark.kind === "singular" ? "3 3" : "none", class: mark.kind }, svg);
      }
      const starts = [0].concat(branch.breaks[j], [q.length]);
      for (let s = 0; s + 1 < starts.length; s++) {
        let segment = [];
        const flush = () => {
          if (segment.length) node("polyline", { points: segment.join(" "), fill: "none", stroke: "#111",
                                                 "stroke-width": 1.4 }, svg);
          segment = [];
        };
        for (let i = starts[s]; i < starts[s + 1]; i++) {
          if (q[i] === null) { flush(); continue; }
          segment.push(xOf(branch.values[i]).toFixed(2) + "," + yOf(q[i]).toFixed(2));
        }
        flush();
      }
      const line = node("line", { y1: plotTop, y2: plotTop + plotHeight, stroke: "#777", "stroke-width": 1.4 }, svg);
      const dot = node("circle", { r: 3.5, fill: "#1f4e9a" }, svg);
      cursors.push({ line: line, dot: dot, yOf: yOf, q: q });
      svg.addEventListener("click", e => {
        const box = svg.getBoundingClientRect();
        const x = (e.clientX - box.left) / box.width * W;
        setIndex(nearest(branch.values, low + (x - LEFT) / (W - LEFT - RIGHT) * (high - low)));
      });
    });
  }

  // ---- marks, joint table, status
  function buildMarks() {
    const box = document.getElementById("marks");
    box.textContent = "";
    for (const mark of branch.marks) {
      const button = document.createElement("button");
      button.type = "button";
      button.className = mark.kind;
      button.textContent = mark.label + ": " + angleText(branch.values[mark.index]);
      button.addEventListener("click", () => setIndex(mark.index));
      box.appendChild(button);
    }
  }
  function drawJoints() {
    const body = document.querySelector("#joints tbody");
    body.textContent = "";
    const here = solved(branch, index);
    D.joints.forEach((name, j) => {
      const row = document.createElement("tr");
      const inside = branch.within[j][index] === "1";
      const flag = here ? (inside ? "✓ yes" : "✗ no") : "—";
      const cells = [[name, ""], [here ? fmt(branch.q[j][index]) : "—", "num value"], [fmt(D.lower[j]), "num"],
                     [fmt(D.upper[j]), "num"], [flag, here && !inside ? "out" : ""]];
      for (const [text, cls] of cells) {
        const cell = document.createElement("td");
        cell.textContent = text;
        if (cls) cell.className = cls;
        row.appendChild(cell);
      }
      body.appendChild(row);
    });
    document.querySelector("#joints thead th:nth-child(2)").textContent = "value [" + D.unit + "]";
  }
  function drawStatus() {
    const status = document.getElementById("status");
    status.textContent = "";
    const inSet = document.createElement("span");
    const feasible = branch.feasible_at[index] === "1";
    inSet.textContent = P.symbol + (feasible ? " ∈ " : " ∉ ") + P.set + ". ";
    if (!feasible) inSet.className = "bad";
    status.appendChild(inSet);
    const joints = document.createElement("span");
    if (solved(branch, index)) {
      const outside = D.joints.filter((_, j) => branch.within[j][index] !== "1");
      joints.textContent = outside.length ? outside.join(", ") + " beyond the limits."
        : "Every joint within its limits.";
      if (outside.length) joints.className = "bad";
    } else {
      joints.textContent = "Branch " + branch.name + " has no solution at this " + P.noun + ".";
      joints.className = "bad";
    }
    status.appendChild(joints);
    const cell = cellStatus();
    if (cell) status.appendChild(cell);
    const notes = branch.marks.filter(m => m.index === index && m.note).map(m => " " + m.label + ": " + m.note + ".");
    for (const note of branch.notes) notes.push(" " + note);
    for (const note of notes) status.appendChild(document.createTextNode(note));
  }
  function setIndex(i) {
    index = Math.max(0, Math.min(branch.values.length - 1, i));
    slider.value = index;
    document.getElementById("parameter-value").textContent = P.symbol + " = " + angleText(branch.values[index]);
    for (const c of cursors) {
      const x = xOf(branch.values[index]);
      c.line.setAttribute("x1", x); c.line.setAttribute("x2", x);
      const y = c.q[index];
      c.dot.setAttribute("visibility", y === null ? "hidden" : "visible");
      c.dot.setAttribute("cx", x); c.dot.setAttribute("cy", y === null ? 0 : c.yOf(y));
    }
    drawView();
    drawJoints();
    drawStatus();
  }
  function setBranch(k) {
    const value = branch.values[index];
    branch = D.branches[k];
    slider.max = branch.values.length - 1;
    buildCurves();
    buildMarks();
    setIndex(nearest(branch.values, value));
  }

  D.branches.forEach((b, k) => {
    const option = document.createElement("option");
    option.value = k;
    option.textContent = b.label;
    select.appendChild(option);
  });
  select.value = D.initial;
  select.addEventListener("change", () => setBranch(+select.value));
  slider.addEventListener("input", () => setIndex(+slider.value));
  slider.max = branch.values.length - 1;
  buildCurves();
  buildMarks();
  setIndex(branch.start);
})();
"""
