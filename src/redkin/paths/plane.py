"""The (waypoint, parameter) plane of a path: the exact feasible pieces of every waypoint and branch (of the arm
angle, or of q7 on a Franka-class arm), for the figures of :mod:`redkin.plot.paths` and anyone who wants to see
where a path can go."""

from __future__ import annotations

from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.franka.geometry import FrankaGeometry
from redkin.paths.arm_family import path_family
from redkin.srs.feasible import FeasiblePieces
from redkin.srs.geometry import SRSGeometry
from redkin.srs.nearly import NearlySRS


def feasible_along_path(arm: SerialChain | SRSGeometry | FrankaGeometry | NearlySRS, poses: ArrayLike,
                        srs_tolerance: float | None = None) -> FeasiblePieces:
    """The feasible arm angles [000 eq. 30] of every waypoint on the eight branches, as pieces ``(N, 8, 24)``; on
    a Franka-class arm the feasible values of q7 [F8]-[F9] (``(N, 8, K)``); on a nearly S-R-S arm (within
    ``srs_tolerance``, :func:`redkin.paths.family.path_family`) the real arm's certified sets
    (:func:`redkin.srs.feasible_arm_angles_nearly`, ``(N, 8, K)``).

    Unlike :func:`redkin.srs.feasible_pieces_all_branches`, a pose out of the arm's reach is not an error: its
    row has no feasible piece (``feasible`` false, NaN ends), as no arm angle reaches it.

    Parameters
    ----------
    arm : SerialChain, SRSGeometry, FrankaGeometry or NearlySRS
    poses : array_like, shape (N, 4, 4)
    srs_tolerance : float, optional

    Returns
    -------
    FeasiblePieces
        ``arc_set((k, b))`` is the feasible set of waypoint ``k`` on branch ``redkin.srs.BRANCHES[b]`` (of the arm
        angle).
    """
    family = path_family(arm, srs_tolerance)
    poses = check_pose(poses, "poses")
    if poses.ndim != 3 or poses.shape[0] == 0:
        raise RedkinError(f"poses must have shape (N, 4, 4) with N >= 1, got shape {poses.shape}")
    return family.pieces(poses)  # a pose out of reach has no solution at any parameter: no feasible piece
