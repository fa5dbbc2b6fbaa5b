"""Exact measure of the feasible arm angles per pose and branch, and the per-position indices of a map.

For a pose and a branch the feasible set ``Psi`` ([000 eq. 30]) is a
union of closed arcs; its measure is the sum of their lengths, in radians
(``2 pi`` for a pose free over the whole circle, 0 where the pose is out of
reach or every arm angle violates a limit).  From the measures of one
position over a set of orientations:

* reachability index: the fraction of orientations with a non-empty set on
  some branch;
* redundancy index: the mean, over those reachable orientations, of the
  largest branch measure divided by ``2 pi`` (0 where none is reachable).
"""

from __future__ import annotations

import numpy as np

from redkin.circle import TWO_PI
from redkin.srs import BRANCHES, pose_from, reachable
from redkin.srs.feasible import feasible_pieces_all_branches
from redkin.srs.geometry import SRSGeometry

#: Poses per call of the feasible-set kernel, built per call: bounds the work arrays to tens of megabytes
#: however many poses a chunk holds.
_BATCH_POSES = 8192


def feasible_measures(geometry: SRSGeometry, positions: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """Measure of the feasible arm-angle set of every position-orientation pair on every branch.

    Parameters
    ----------
    geometry : SRSGeometry
        The arm (:func:`redkin.srs.srs_geometry`).
    positions : numpy.ndarray, shape (P, 3)
        Tool positions, metres.
    rotations : numpy.ndarray, shape (N, 3, 3)
        Tool orientations.

    Returns
    -------
    numpy.ndarray, shape (P, N, 8)
        Radians in ``[0, 2 pi]``, branches in the order of :data:`redkin.srs.BRANCHES`;
        0 out of reach.  A set counts only if :attr:`FeasiblePieces.nonempty` says so.
    """
    count = len(positions) * len(rotations)
    measure = np.zeros((count, len(BRANCHES)))
    for start in range(0, count, _BATCH_POSES):
        pair = np.arange(start, min(start + _BATCH_POSES, count))  # position-major, as the result
        batch = pose_from(positions[pair // len(rotations)], rotations[pair % len(rotations)])
        inside = np.flatnonzero(reachable(geometry, batch))
        if inside.size == 0:  # nothing in reach: the measures stay 0
            continue
        pieces = feasible_pieces_all_branches(geometry, batch[inside])  # (k, 8, 24), branches in BRANCHES order
        lengths = np.where(pieces.feasible, pieces.end - pieces.start, 0.0).sum(axis=-1)
        measure[start + inside] = np.where(pieces.nonempty, lengths, 0.0)
    return measure.reshape(len(positions), len(rotations), len(BRANCHES))


def reachability_index(measure: np.ndarray) -> np.ndarray:
    """Fraction of orientations with a feasible arm angle on some branch, ``(..., N, 8) -> (...)``."""
    return (measure > 0.0).any(axis=-1).mean(axis=-1)


def redundancy_index(measure: np.ndarray) -> np.ndarray:
    """Mean over reachable orientations of the largest branch measure / ``2 pi``, ``(..., N, 8) -> (...)``.

    0 where no orientation is reachable.
    """
    best = measure.max(axis=-1)
    count = (best > 0.0).sum(axis=-1)
    return np.where(count > 0, best.sum(axis=-1) / (TWO_PI * np.maximum(count, 1)), 0.0)
