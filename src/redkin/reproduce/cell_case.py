"""The models section's worked cell (issue 40): an iiwa14 reaching past a post into a shelf.

The tool moves along a straight line into a shelf, held horizontal.  The path that keeps the joints farthest from
their limits runs the forearm through a post; in the cell, the certified collision-free arm angles
(:func:`redkin.collision.collision_free_arm_angles`) leave that path out, and the path resolved inside them swings
the elbow around the post, with every step between waypoints proved clear (:mod:`redkin.paths.clear_steps`).  The
body is four capsules chosen for this example, not the maker's geometry.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from redkin.arms import arm
from redkin.circle import arc_length
from redkin.collision import BodyCapsule, Scene, body_of, clearance, collision_free_arm_angles, primitives
from redkin.models import kuka_iiwa14
from redkin.paths import PathResult, cell_along_path, line, resolve_path
from redkin.plot.arm import draw_arm_3d, set_equal_3d
from redkin.plot.paths import path_plane_figure
from redkin.reproduce.report import SectionWriter

#: The tool's rotation along the line: its z axis horizontal, along +x (reaching into the shelf).
_ROTATION = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
#: Where the line starts and ends (metres, base frame), and the spacing of its waypoints.
_START, _END, _SPACING = [0.6, -0.15, 0.5], [0.85, 0.2, 0.5], 0.02
#: The largest move of each joint between waypoints (radians).
_MAX_STEP = 0.15
#: The body: capsules on the iiwa14's upper arm (frame 3) and forearm (frame 4), a ball at the wrist (frame 5's origin)
#: and a capsule on the hand (frame 7); the wrist and the hand, two joints apart, touch across the wrist and are not
#: checked against each other.
_BODY = (BodyCapsule("upper arm", 3, [0, 0, -0.2], [0, 0, 0], 0.07),
         BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.07),
         BodyCapsule("wrist", 5, [0, 0, 0], [0, 0, 0], 0.07),
         BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.1], 0.05))
#: The cell: a post beside the line (its two ends and radius), the shelf's two boards around the line's end and the
#: table the arm stands on (each box's centre and edge lengths), metres.
_POST = ([0.33, -0.26, 0.0], [0.33, -0.26, 1.1], 0.04)
_BOXES = {"shelf board": ([0.95, 0.2, 0.36], [0.3, 0.5, 0.02]),
          "shelf top": ([0.95, 0.2, 0.66], [0.3, 0.5, 0.02]),
          "table": ([0.6, 0.0, -0.05], [1.6, 1.6, 0.1])}
_MARGIN = 0.01


def cell(chain=None):
    """The case's chain, body, scene and waypoints."""
    chain = kuka_iiwa14() if chain is None else chain
    shapes = [primitives.capsule(*_POST)] + [primitives.box(*box) for box in _BOXES.values()]
    scene = Scene(("post", *_BOXES), np.stack(shapes), _MARGIN)
    poses = line(_pose(_START), _pose(_END), step=_SPACING)
    return chain, body_of(list(_BODY), chain, ignore=[("wrist", "hand")]), scene, poses


def _pose(position: list[float]) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = _ROTATION, position
    return pose


def cell_case(writer: SectionWriter) -> None:
    """The sets at the middle waypoint beside the limit sets, and two paths: the joint limits alone, and the cell."""
    chain, body, scene, poses = cell()
    middle = len(poses) // 2
    writer.heading("kuka-iiwa14 in a cell (beyond the papers)")
    writer.text(
        f"An iiwa14 reaches past a post into a shelf: the tool moves {len(poses)} waypoints along a straight line "
        f"from {_START} to {_END} m, held horizontal, each joint moving at most {np.degrees(_MAX_STEP):.1f} deg "
        "between waypoints. The cell holds a post (a capsule of radius 0.04 m), the shelf's two boards and the table "
        f"(boxes), with a margin of {_MARGIN} m; the arm's body is three capsules and a ball chosen for this "
        "example (upper arm, forearm, wrist and hand), not the maker's geometry. redkin computes, per branch, the arm "
        "angles at which every capsule keeps the margin from every obstacle, certified (docs/collisions.md), and "
        "resolves the path "
        "inside them with every step between waypoints proved clear. No paper treats obstacles: this is redkin's own "
        "extension (issue 40), with nothing to compare."
    )
    free = collision_free_arm_angles(arm(chain), poses[middle], body, scene)
    rows = []
    for label, limits, clear in zip(free.branches, free.limits, free.free, strict=True):
        rows.append([label, _arcs_text(limits), _arcs_text(clear), _width(limits), _width(clear)])
    writer.table("cell_sets", ["branch", "within the limits [deg]", "collision-free [deg]", "width [deg]",
                               "free width [deg]"], rows,
                 caption=f"kuka-iiwa14 in the cell, waypoint {middle}: each branch's arm angles within the joint "
                         "limits and the certified collision-free ones",
                 detail="redkin.collision.collision_free_arm_angles: every arm angle of a free arc keeps every "
                        f"capsule {_MARGIN} m from every obstacle within the limits, ends located to 1e-6 rad. "
                        "An arc through +-180 deg is written start..end with start > end.")
    paths = {"joint limits only": resolve_path(chain, poses, _MAX_STEP),
             "in the cell": resolve_path(chain, poses, _MAX_STEP, body=body, scene=scene)}
    writer.table("cell_paths", ["path", "status", "branches", "least distance [m]", "closest pair",
                                "clearance from the limits [deg]", "steps proved clear", "total motion [deg]"],
                 [_path_row(name, result, chain, body, scene) for name, result in paths.items()],
                 caption="kuka-iiwa14 in the cell: the path of the joint limits alone against the paths in the cell",
                 detail="Least distance: the smallest signed distance between a body capsule and an obstacle over the "
                        "waypoints (negative: they overlap), measured at the path's joint values. The first path "
                        "ignores the cell; the second keeps as far from the joint limits as the cell allows. Steps "
                        "proved clear: redkin.collision.step_clearance of the joint values moving linearly between "
                        "waypoints.")
    writer.text(_paths_text(chain, body, scene, paths))
    writer.figure(_sets_figure(free, middle, paths), "cell_sets",
                  f"kuka-iiwa14 in the cell: the arm angles of each branch at waypoint {middle}",
                  "Light: within the joint limits; dark: also collision-free. The marks are the paths' arm angles at "
                  "that waypoint, on their own branch.")
    writer.figure(_scene_figure(chain, poses, paths, middle), "cell_arm",
                  f"kuka-iiwa14 in the cell at waypoint {middle}: the path of the joint limits alone and the path "
                  "in the cell", "The post is drawn as its axis, the boards as their outlines; the table is left out.")
    in_cell = cell_along_path(chain, poses, body, scene)
    writer.figure(path_plane_figure(in_cell.free, paths["in the cell"], exact=False,
                                    title=f"kuka-iiwa14: {len(poses)} waypoints in the cell", removed=in_cell.removed),
                  "cell_path_plane", "kuka-iiwa14 in the cell: the path through each branch's collision-free arm "
                                     "angles along the line",
                  "What redkin path --scene --plot draws: per branch, the certified collision-free arm angles of "
                  "every waypoint shaded, each stretch the cell removes from the limit-feasible ones coloured by the "
                  "pair that blocks it (redkin.paths.cell_along_path), and the path in the cell through them.")


def _arcs_text(arcs) -> str:
    """Arcs in degrees, ``start..end`` each, or ``none``."""
    if not len(arcs.bounds):
        return "none"
    return ", ".join(f"{np.degrees(lo):.1f}..{np.degrees(hi):.1f}" for lo, hi in arcs.bounds.tolist())


def _width(arcs) -> float:
    """The total width of arcs [deg]."""
    return float(np.degrees(sum(arc_length(start, end) for start, end in arcs.bounds.tolist())))


def _failure(result: PathResult) -> str:
    """A failed path's line."""
    assert result.failure is not None
    return result.failure.message


def _path_row(name: str, result: PathResult, chain, body, scene) -> list:
    """One row of the paths' table."""
    if not result.ok:
        return [name, _failure(result), None, None, None, None, None, None]
    measured = clearance(chain, body, scene, result.q)
    worst = int(np.argmin(measured.distance))
    steps = result.steps
    proved = "not checked" if steps is None else f"{int(steps.certified.sum())} of {len(steps.certified)}"
    return [name, result.status, " ".join(sorted(set(result.branch))), float(measured.distance[worst]),
            f"{measured.link[worst]} - {measured.against[worst]}", float(np.degrees(result.clearance)), proved,
            float(np.degrees(result.motion))]


def _paths_text(chain, body, scene: Scene, paths: dict[str, PathResult]) -> str:
    """What the two paths do, in words, from their measured distances."""
    plain, inside = paths.values()
    if not (plain.ok and inside.ok):
        return "; ".join(f"{name}: {_failure(result)}" for name, result in paths.items() if not result.ok)
    hit = clearance(chain, body, scene, plain.q)
    worst = int(np.argmin(hit.distance))
    kept = clearance(chain, body, scene, inside.q)
    least = int(np.argmin(kept.distance))
    turned = np.degrees(np.abs(np.angle(np.exp(1j * (inside.psi - plain.psi))))).max()
    return (f"Without the cell the path {'runs' if hit.distance[worst] < 0 else 'keeps'} its {hit.link[worst]} "
            f"{'into' if hit.distance[worst] < 0 else 'clear of'} the {hit.against[worst]} (signed distance "
            f"{hit.distance[worst]:.3f} m at waypoint {worst}). In the cell the path runs on branch "
            f"{' then '.join(dict.fromkeys(inside.branch))} and its arm angle differs from the first path's by up "
            f"to {turned:.1f} deg: the elbow swings around the post. Its least distance, {kept.distance[least]:.3f} "
            f"m ({kept.link[least]} and {kept.against[least]}, waypoint {least}), is at least the margin, every "
            "step between waypoints is proved clear, and its clearance from the joint limits is "
            f"{np.degrees(inside.clearance):.2f} deg against {np.degrees(plain.clearance):.2f} deg without the cell.")


def _sets_figure(free, middle: int, paths: dict[str, PathResult]) -> plt.Figure:
    """Per branch, the limit arcs and the free arcs as bars over the arm angle, and each path's arm angle."""
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    for row, (limits, clear) in enumerate(zip(free.limits, free.free, strict=True)):
        for arcs, color, height in ((limits, "0.82", 0.7), (clear, "C0", 0.4)):
            for lo, hi in arcs.bounds.tolist():
                pieces = [(lo, hi)] if hi >= lo else [(lo, np.pi), (-np.pi, hi)]
                for a, b in pieces:
                    ax.barh(row, np.degrees(b - a), left=np.degrees(a), height=height, color=color)
    for (name, result), marker in zip(paths.items(), ("x", "o"), strict=True):
        if result.ok:
            ax.plot(np.degrees(result.psi[middle]), free.branches.index(result.branch[middle]), marker, color="C3",
                    markerfacecolor="none", markersize=8, label=name)
    ax.set_yticks(range(len(free.branches)), free.branches)
    ax.set_xlim(-180, 180)
    ax.set_xlabel("arm angle psi [deg]")
    ax.set_ylabel("branch")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=2, fontsize=8)
    return fig


def _scene_figure(chain, poses: np.ndarray, paths: dict[str, PathResult], middle: int) -> plt.Figure:
    """The arm at the middle waypoint on both paths, the post and the boards, and the tool's line."""
    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(111, projection="3d")
    points = [poses[:, :3, 3]]
    for (name, result), color in zip(paths.items(), ("C3", "C0"), strict=True):
        if result.ok:
            draw_arm_3d(ax, chain, result.q[middle], color=color, label=name)
            points.append(chain.frames(result.q[middle])[:, :3, 3])
    ax.plot(*poses[:, :3, 3].T, "k:", label="tool line")
    ax.plot(*np.array(_POST[:2]).T, color="0.3", linewidth=4, label="post")
    points.append(np.array(_POST[:2]))
    for name, (centre, size) in _BOXES.items():
        if name.startswith("shelf"):
            x, y, z = centre
            dx, dy, dz = np.array(size) / 2
            outline = np.array([[x - dx, x + dx, x + dx, x - dx, x - dx], [y - dy, y - dy, y + dy, y + dy, y - dy],
                                [z + dz] * 5])
            ax.plot(*outline, color="0.5")
            points.append(outline.T)
    set_equal_3d(ax, np.concatenate(points))
    ax.legend(loc="upper left", fontsize=8)
    return fig
