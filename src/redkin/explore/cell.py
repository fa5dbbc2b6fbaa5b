"""The explorer in a cell (issue 40): the obstacles, the arm's body at every grid value, its least distance and the
certified collision-free arm angles, for the page to draw beside the limit sets.

The numbers come from :func:`redkin.collision.collision_free_set` (the free intervals of the arm angle, or of q7 on
the Franka class, and the cause of every stretch removed) and :func:`redkin.collision.clearance.pair_table` (the
distances at the grid's joint values); the page computes none of its own.  S-R-S, offset-elbow and Franka-class
arms, as the free sets.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin.arms.front_door import Arm
from redkin.collision.arm_angle_free import COLLISION, LIMIT
from redkin.collision.body import Body, capsule_ends, posed
from redkin.collision.clearance import checked_pairs, least_pair, pair_table
from redkin.collision.free_sets import collision_free_set
from redkin.collision.primitives import BOX, CAPSULE, PLANE, SPHERE
from redkin.collision.scene import Scene
from redkin.explore.curves import BranchCurves


@dataclass(frozen=True)
class BranchCell:
    """One branch in the cell, on its grid.

    Attributes
    ----------
    free : numpy.ndarray, shape (K, 2)
        The certified collision-free arcs (``start > end`` through the ends of the domain).
    blocked : tuple of (float, float, str)
        Every stretch the obstacles (or the body's own links) remove, or that stays undecided, with its cause in
        words; the stretches the joint limits remove are the limit sets' gaps.
    capsules : numpy.ndarray, shape (G, M, 2, 3)
        The body's capsules (their segments' ends) at each grid value [m]; NaN where the branch has no solution.
    distance : numpy.ndarray, shape (G,)
        The least signed distance over the checked pairs at each grid value [m]; NaN where no solution.
    closest : numpy.ndarray of int, shape (G,)
        The pair that has it (index into :attr:`CellView.pairs`); -1 where no solution.
    """

    free: np.ndarray
    blocked: tuple[tuple[float, float, str], ...]
    capsules: np.ndarray
    distance: np.ndarray
    closest: np.ndarray


@dataclass(frozen=True)
class CellView:
    """The cell of an explorer page: the obstacles to draw, the body's links and radii, the checked pairs, the
    margin, and each branch in it (in the order of the page's branches)."""

    obstacles: tuple[dict, ...]
    links: tuple[str, ...]
    radii: np.ndarray
    pairs: tuple[tuple[str, str], ...]
    margin: float
    branches: tuple[BranchCell, ...]
    source: str


def cell_view(arm: Arm, pose: np.ndarray, body: Body, scene: Scene, curves: tuple[BranchCurves, ...]) -> CellView:
    """The cell at ``pose`` on the grids of ``curves`` (one per branch of ``arm``).

    Raises
    ------
    RedkinError
        For an arm of a class without certified collision-free sets (named), or a body on frames the chain does not
        have.
    """
    free = collision_free_set(arm, pose, body, scene, [c.branch for c in curves])
    cells = []
    for b, branch in enumerate(curves):
        q = np.where(branch.exists[:, None], branch.q, 0.0)
        table, _ = pair_table(arm.chain, body, scene, q)
        capsules = capsule_ends(posed(body, arm.chain.frames(q)))
        capsules[~branch.exists] = np.nan
        least, nearest = least_pair(table)
        distance, closest = np.where(branch.exists, least, np.nan), np.where(branch.exists, nearest, -1)
        blocked = tuple((stretch.start, stretch.end, _cause(stretch)) for stretch in free.blocked[b]
                        if stretch.cause != LIMIT)
        arcs = free.free[b]
        cells.append(BranchCell(arcs.bounds.copy(), blocked, capsules, distance, closest))
    return CellView(tuple(obstacle_drawing(name, row) for name, row in zip(scene.names, scene.shapes, strict=True)),
                    tuple(body.link), np.asarray(body.radius, dtype=float), tuple(checked_pairs(body, scene).names),
                    float(scene.margin), tuple(cells), scene.source)


def clearest(cell: CellView, curves: tuple[BranchCurves, ...], parameter, initial: int,
             opening: str) -> tuple[int, int, str]:
    """Where a page in a cell opens without a branch or a configuration asked for: the grid value, among those in a
    branch's collision-free set, at which the body keeps farthest from the obstacles and its own links; the branch,
    the index and the sentence saying so (``initial``'s start and ``opening`` where no branch has a free value)."""
    best: tuple[float, int, int] | None = None
    for k, (branch, inside) in enumerate(zip(curves, cell.branches, strict=True)):
        free = branch.exists & branch.feasible_at & _in_arcs(branch.values, inside.free)
        if free.any():
            place = int(np.argmax(np.where(free, inside.distance, -np.inf)))
            if best is None or inside.distance[place] > best[0]:
                best = (float(inside.distance[place]), k, place)
    if best is None:
        return initial, curves[initial].start, (f"{opening} No branch has a collision-free {parameter.symbol} on the "
                                                "grid at this pose.")
    distance, k, place = best
    pair = cell.pairs[int(cell.branches[k].closest[place])] if cell.pairs else ("", "")
    return k, place, (f"Opened where the arm keeps farthest from the obstacles among the collision-free "
                      f"{parameter.plural} of every branch: branch {curves[k].branch}, {distance:.4f} m ({pair[0]} and "
                      f"{pair[1]}).")


def _in_arcs(values: np.ndarray, arcs: np.ndarray) -> np.ndarray:
    """Which values lie in the arcs ``(K, 2)`` (``start > end``: through the ends of the domain)."""
    inside = np.zeros(values.shape, dtype=bool)
    for lo, hi in arcs.tolist():
        inside |= ((values >= lo) & (values <= hi)) if lo <= hi else ((values >= lo) | (values <= hi))
    return inside


def _cause(stretch) -> str:
    """A removed stretch's cause in words."""
    if stretch.cause == COLLISION:
        return f"{stretch.link} meets {stretch.against}"
    return "undecided (next to a singular value, or a distance grazing the margin)"


def obstacle_drawing(name: str, row: np.ndarray) -> dict:
    """What a page (the explorer, the playback) draws of one obstacle: a ball's centre, a capsule's ends, a box's
    eight corners, a plane's point and normal, with the radius."""
    kind = int(row[0])
    if kind in (SPHERE, CAPSULE):
        return {"name": name, "kind": "capsule", "ends": [row[2:5].tolist(), row[5:8].tolist()],
                "radius": float(row[1])}
    if kind == BOX:
        rotation = row[8:17].reshape(3, 3)
        signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
        corners = row[2:5] + (signs * row[5:8]) @ rotation.T
        return {"name": name, "kind": "box", "corners": corners.tolist()}
    assert kind == PLANE
    return {"name": name, "kind": "plane", "point": row[2:5].tolist(), "normal": row[5:8].tolist()}
