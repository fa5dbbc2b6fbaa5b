"""Exact measure of the feasible redundancy parameter per pose and branch, and the per-position indices of a map.

For a pose and a branch the feasible set (the arm angles of [000 eq. 30] on an S-R-S arm, the values of q7 of
[F8]-[F9] on a Franka-class arm; :meth:`redkin.Arm.feasible`) is a union of closed arcs; its measure is the sum of
their lengths, in radians (the parameter's whole range -- ``2 pi`` for the arm angle, joint 7's range for q7 -- for
a pose free over all of it, 0 where the pose is out of reach or every value violates a limit).  From the measures of
one position over a set of orientations:

* reachability index: the fraction of orientations with a non-empty set on
  some branch;
* redundancy index: the mean, over those reachable orientations, of the
  largest branch measure divided by the parameter's whole range (0 where none is reachable).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from redkin.arms import Arm
from redkin.circle import TWO_PI
from redkin.errors import RedkinError
from redkin.srs import pose_from
from redkin.srs.feasible import PIECE_TOLERANCE

if TYPE_CHECKING:
    from redkin.collision import Body, Scene

    #: The arm's body and a scene.
    Cell = tuple[Body, Scene]

#: Poses per call of the feasible-set kernel, built per call: bounds the work arrays to tens of megabytes
#: however many poses a chunk holds.
_BATCH_POSES = 8192


def feasible_measures(arm: Arm, positions: np.ndarray, rotations: np.ndarray, cell: Cell | None = None) -> np.ndarray:
    """Measure of the feasible set of the redundancy parameter of every position-orientation pair on every branch.

    Parameters
    ----------
    arm : Arm
        An arm with exact feasible sets (S-R-S, offset elbow, the Franka class; :func:`redkin.arm`).
    positions : numpy.ndarray, shape (P, 3)
        Tool positions, metres.
    rotations : numpy.ndarray, shape (N, 3, 3)
        Tool orientations.
    cell : (Body, Scene), optional
        The arm's body and a scene: the measure is then of the certified collision-free sets (S-R-S and offset-elbow
        arms; :meth:`redkin.Arm.feasible` with ``body`` and ``scene``), within the limits and the scene's margin
        from every obstacle and between the body's links.

    Returns
    -------
    numpy.ndarray, shape (P, N, B)
        Radians in ``[0, whole_range(arm)]``, branches in the order of ``arm.branches``; 0 out of reach, and where
        the set is shorter than :data:`redkin.srs.feasible.PIECE_TOLERANCE`.
    """
    count = len(positions) * len(rotations)
    measure = np.zeros((count, len(arm.branches)))
    for start in range(0, count, _BATCH_POSES):
        pair = np.arange(start, min(start + _BATCH_POSES, count))  # position-major, as the result
        poses = pose_from(positions[pair // len(rotations)], rotations[pair % len(rotations)])
        sets = arm.feasible(poses) if cell is None else arm.feasible(poses, body=cell[0], scene=cell[1])
        lengths = np.where(sets.feasible, sets.end - sets.start, 0.0).sum(axis=-1)
        measure[pair] = np.where(lengths > PIECE_TOLERANCE, lengths, 0.0)
    return measure.reshape(len(positions), len(rotations), len(arm.branches))


def whole_range(arm: Arm) -> float:
    """The length of the redundancy parameter's range, radians: ``2 pi`` for the arm angle, joint 7's range (at most
    the parameter's domain) for q7; the measure of a pose free over all of it."""
    if arm.parameter is None:
        raise RedkinError(f"{arm.chain.name!r} has no redundancy parameter ({arm.reason})")
    low, high = arm.parameter.domain
    return float(high - low)


def reachability_index(measure: np.ndarray) -> np.ndarray:
    """Fraction of orientations with a feasible arm angle on some branch, ``(..., N, 8) -> (...)``."""
    return (measure > 0.0).any(axis=-1).mean(axis=-1)


def redundancy_index(measure: np.ndarray, whole: float = TWO_PI) -> np.ndarray:
    """Mean over reachable orientations of the largest branch measure / ``whole`` (the parameter's whole range,
    :func:`whole_range`), ``(..., N, B) -> (...)``.

    0 where no orientation is reachable.
    """
    best = measure.max(axis=-1)
    count = (best > 0.0).sum(axis=-1)
    return np.where(count > 0, best.sum(axis=-1) / (whole * np.maximum(count, 1)), 0.0)
