"""Which joint makes a waypoint impossible: from the exact per-joint sets, or from the closest pair of
configurations across a step."""

from __future__ import annotations

from collections import Counter

import numpy as np

from redkin.circle import TWO_PI, ArcSet
from redkin.paths.graph import Arm
from redkin.srs.branches import BRANCHES
from redkin.srs.feasible import feasible_arm_angles
from redkin.srs.geometry import SRSGeometry


def empty_blocker(geometry: SRSGeometry, pose: np.ndarray) -> tuple[int | None, dict[str, int | None]]:
    """The joint that empties the feasible set of ``pose`` [000 eq. 30], on most branches, and per branch.

    On each branch the blocking joint is the first (in the order 1..7) whose own set [000 eq. 29] is empty,
    else the first whose set empties the intersection of the sets of the joints before it.  ``None`` for a
    branch whose sets all overlap (emptied by the rounding guard of the samples alone).
    """
    per_branch: dict[str, int | None] = {}
    for branch in BRANCHES:
        sets = feasible_arm_angles(geometry, pose, branch).per_joint
        blocker: int | None = next((joint for joint in range(1, 8) if sets[joint].is_empty), None)
        if blocker is None:
            running = ArcSet.full()
            for joint in range(1, 8):
                running = running.intersection(sets[joint])
                if running.is_empty:
                    blocker = joint
                    break
        per_branch[str(branch)] = blocker
    counts = Counter(blocker for blocker in per_branch.values() if blocker is not None)
    most = min(counts, key=lambda j: (-counts[j], j)) if counts else None
    return most, per_branch


def step_blocker(arm: Arm, before: np.ndarray, after: np.ndarray) -> tuple[int, float]:
    """The joint that must move most, relative to its bound, between the closest pair of ``before`` (R, 7) and
    ``after`` (M, 7) (closest: the least largest relative move, :func:`_closest_pair`), and how far it moves there
    (radians)."""
    first, second = _closest_pair(arm, np.asarray(before, dtype=float), np.asarray(after, dtype=float))
    d = arm.moves(before[first], after[second])
    joint = int(np.argmax(d / arm.step))
    return joint + 1, float(d[joint])


def _closest_pair(arm: Arm, before: np.ndarray, after: np.ndarray) -> tuple[int, int]:
    """The rows of ``before`` (R, n) and ``after`` (M, n) whose largest move relative to ``arm.step`` is least: each
    row's nearest neighbour in that distance (the maximum norm of the moves over the bounds) from a k-d tree of
    ``after``, periodic on the joints that turn without end (a graph's waypoint may hold a million nodes: comparing
    every pair took hours)."""
    from scipy.spatial import cKDTree

    bounded = np.isfinite(arm.step)
    step = np.where(bounded, arm.step, 1.0)
    both = np.concatenate([before, after])
    scaled = np.where(bounded, (both - both.min(axis=0)) / step, 0.0)
    # on a joint that turns without end the box is its turn; elsewhere wide enough that no image comes nearer
    box = np.where(arm.circle & bounded, TWO_PI / step, 2.0 * scaled.max(axis=0) + 1.0)
    scaled = np.where(arm.circle, scaled % box, scaled)
    scaled = np.where(scaled >= box, 0.0, scaled)  # x % box rounded up to box
    distance, index = cKDTree(scaled[len(before):], boxsize=box).query(scaled[:len(before)], k=1, p=np.inf)
    first = int(np.argmin(distance))
    return first, int(index[first])
