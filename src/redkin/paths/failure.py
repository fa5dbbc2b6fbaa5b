"""Which joint makes a waypoint impossible: from the exact per-joint sets, or from the closest pair of
configurations across a step."""

from __future__ import annotations

from collections import Counter

import numpy as np

from redkin.circle import ArcSet
from redkin.paths import _dp_kernels
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
    ``after`` (M, 7) (closest: the least largest relative move, :func:`redkin.paths._dp_kernels.closest_pair`), and
    how far it moves there (radians)."""
    first, second, _ = _dp_kernels.closest_pair(np.ascontiguousarray(before, dtype=float),
                                                np.ascontiguousarray(after, dtype=float),
                                                np.ascontiguousarray(arm.step), np.ascontiguousarray(arm.circle))
    d = arm.moves(before[first], after[second])
    joint = int(np.argmax(d / arm.step))
    return joint + 1, float(d[joint])
