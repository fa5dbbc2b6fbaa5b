"""The (waypoint, parameter) plane of a path: the exact feasible pieces of every waypoint and branch (of the arm
angle, or of q7 on a Franka-class arm), in a cell the certified collision-free ones and the stretches the obstacles
remove, for the figures of :mod:`redkin.plot.paths` and anyone who wants to see where a path can go."""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.franka.geometry import FrankaGeometry
from redkin.paths.arm_family import path_family
from redkin.paths.collision_family import collision_free_family
from redkin.srs.branches import BRANCHES
from redkin.srs.feasible import FeasiblePieces
from redkin.srs.geometry import SRSGeometry
from redkin.srs.nearly import NearlySRS

if TYPE_CHECKING:  # the cell's types: read where one is given
    from redkin.collision.body import Body
    from redkin.collision.scene import Scene


def feasible_along_path(arm: SerialChain | SRSGeometry | FrankaGeometry | NearlySRS, poses: ArrayLike,
                        srs_tolerance: float | None = None, body: Body | None = None,
                        scene: Scene | None = None) -> FeasiblePieces:
    """The feasible arm angles [000 eq. 30] of every waypoint on the eight branches, as pieces ``(N, 8, 24)``; on
    a Franka-class arm the feasible values of q7 [F8]-[F9] (``(N, 8, K)``); on a nearly S-R-S arm (within
    ``srs_tolerance``, :func:`redkin.paths.family.path_family`) the real arm's certified sets
    (:func:`redkin.srs.feasible_arm_angles_nearly`, ``(N, 8, K)``).  In the cell of the arm's ``body`` and
    ``scene``, those pieces cut to the certified collision-free sets (what ``resolve_path(..., body=, scene=)``
    searches).

    Unlike :func:`redkin.srs.feasible_pieces_all_branches`, a pose out of the arm's reach is not an error: its
    row has no feasible piece (``feasible`` false, NaN ends), as no arm angle reaches it.

    Parameters
    ----------
    arm : SerialChain, SRSGeometry, FrankaGeometry or NearlySRS
    poses : array_like, shape (N, 4, 4)
    srs_tolerance : float, optional
    body, scene : Body and Scene, optional
        The cell (both or neither).

    Returns
    -------
    FeasiblePieces
        ``arc_set((k, b))`` is the feasible set of waypoint ``k`` on branch ``redkin.srs.BRANCHES[b]`` (of the arm
        angle).
    """
    family = path_family(arm, srs_tolerance, body, scene)
    return family.pieces(_checked(poses))  # a pose out of reach has no solution at any parameter: no feasible piece


class Removed(NamedTuple):
    """A stretch ``[start, end]`` of one waypoint's parameter that the cell removes from a branch's limit-feasible
    set (``start > end`` through +-pi for an arm angle), and its cause in words: ``"<link> meets <obstacle>"`` (or
    another link of the body), or ``"undecided"`` (a sliver next to a singular value, or a distance grazing the
    margin)."""

    start: float
    end: float
    cause: str


def removed_along_path(arm: SerialChain | SRSGeometry | FrankaGeometry | NearlySRS, poses: ArrayLike, body: Body,
                       scene: Scene, srs_tolerance: float | None = None) -> list[list[list[Removed]]]:
    """Per waypoint of ``poses`` ``(N, 4, 4)`` and branch (in the order of :data:`redkin.srs.BRANCHES`), the stretches
    of the redundancy parameter that the cell of ``body`` and ``scene`` removes from the limit-feasible set, each
    named by the pair that blocks it (:func:`redkin.collision.free_sets_of`'s ``blocked``, without the stretches the
    limits remove); empty where the limits leave nothing (a pose out of reach among them).  :func:`cell_along_path`
    gives them with the collision-free pieces, from one computation of the sets.

    Raises
    ------
    RedkinError
        For malformed poses, and what :func:`redkin.collision.free_sets_of` refuses (a body on another chain).
    """
    return cell_along_path(arm, poses, body, scene, srs_tolerance).removed


class InCell(NamedTuple):
    """A path's waypoints in a cell (:func:`cell_along_path`): the collision-free pieces ``free`` (what
    :func:`feasible_along_path` gives with the cell) and the stretches the cell removes (:func:`removed_along_path`)."""

    free: FeasiblePieces
    removed: list[list[list[Removed]]]


def cell_along_path(arm: SerialChain | SRSGeometry | FrankaGeometry | NearlySRS, poses: ArrayLike, body: Body,
                    scene: Scene, srs_tolerance: float | None = None) -> InCell:
    """:func:`feasible_along_path` in the cell of ``body`` and ``scene`` and :func:`removed_along_path`, from one
    computation of each waypoint's certified sets (what ``redkin path --scene --plot`` draws).

    Raises
    ------
    RedkinError
        As :func:`removed_along_path`.
    """
    from redkin.collision.arm_angle_free import COLLISION, LIMIT

    poses = _checked(poses)
    free, some, found = collision_free_family(path_family(arm, srs_tolerance), body, scene).pieces_with_causes(poses)
    removed: list[list[list[Removed]]] = [[[] for _ in BRANCHES] for _ in poses]
    rows = {str(branch): row for row, branch in enumerate(BRANCHES)}
    for k, sets in zip(some.tolist(), found, strict=True):
        for label, stretches in zip(sets.branches, sets.blocked, strict=True):
            removed[k][rows[label]] = [
                Removed(stretch.start, stretch.end,
                        f"{stretch.link} meets {stretch.against}" if stretch.cause == COLLISION else "undecided")
                for stretch in stretches if stretch.cause != LIMIT]
    return InCell(free, removed)


def _checked(poses: ArrayLike) -> np.ndarray:
    """The waypoints ``(N, 4, 4)``, N >= 1, checked."""
    poses = check_pose(poses, "poses")
    if poses.ndim != 3 or poses.shape[0] == 0:
        raise RedkinError(f"poses must have shape (N, 4, 4) with N >= 1, got shape {poses.shape}")
    return poses
