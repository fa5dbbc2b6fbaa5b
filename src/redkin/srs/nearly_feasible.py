"""Feasible arm angles of a nearly S-R-S arm: where the real arm's polished solution stays within its limits.

On the real arm the joint values at an arm angle, ``q(psi)``, are the
polished solutions of :func:`redkin.srs.nearly.ik`; no closed form gives the
arm angles where a joint meets a limit.  They differ from the exact
neighbour's ``q_N(psi)`` [000 eqs. 13-19] by a small amount ``delta``, so a
real arc of feasible arm angles lies inside the neighbour's arcs for limits
loosened by ``delta`` ([000 eqs. 20-30] on the neighbour).  The set is found
in three steps:

1. the polished solutions on a uniform grid of arm angles give ``delta``
   (the largest ``|q - q_N|`` met, doubled, plus 1e-6 rad);
2. the endpoints and midpoints of the neighbour's arcs for limits loosened
   by ``delta`` join the grid, so that every neighbour arc, however narrow,
   holds a sample;
3. where feasibility changes between neighbouring samples, bisection on the
   polished solutions locates the arm angle of the change to
   1e-10 rad, on its feasible side.

What is certified: every arm angle of the returned set that a sample or an
endpoint holds has a certified solution within the limits.  What is not: an
arc of the real arm narrower than the grid that no neighbour arc (with the
measured ``delta``) announces, which needs ``delta`` to under-estimate the
true difference; the doubling is the margin.  A polish that does not settle
counts as infeasible.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.circle import ArcSet
from redkin.errors import RedkinError
from redkin.srs.branches import Branch, parse_branch
from redkin.srs.feasible import feasible_arm_angles
from redkin.srs.geometry import srs_geometry
from redkin.srs.ik import solve
from redkin.srs.nearly import NearlySRS, ik

#: Arm angles of the uniform grid.
_SAMPLES = 720
#: Width [rad] below which a change of feasibility is located.
_ENDPOINT_TOLERANCE = 1e-10


class NearlyFeasible(NamedTuple):
    """The feasible arm angles of one pose and branch on a nearly S-R-S arm.

    Attributes
    ----------
    feasible : ArcSet
        Arm angles where the branch's certified solution lies within the limits.
    branch : Branch
    delta : float
        The joint difference [rad] allowed between the real arm and its neighbour (module docstring, step 1).
    samples : int
        Arm angles at which the real arm was solved, the bisections included.
    """

    feasible: ArcSet
    branch: Branch
    delta: float
    samples: int


def feasible_arm_angles_nearly(arm: NearlySRS, pose: ArrayLike, branch: str | Branch = "+++",
                               samples: int = _SAMPLES) -> NearlyFeasible:
    """The arm angles at which the real arm reaches ``pose`` on ``branch`` within its limits (module docstring).

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose) or branch, or fewer than 8 samples.
    """
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
    if samples < 8:
        raise RedkinError(f"samples must be at least 8, got {samples}")
    label = parse_branch(branch)
    grid = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    q, good = _solved(arm, pose, grid, label)
    delta = _delta(arm, pose, grid, q, good, label)
    psi = np.unique(np.concatenate([grid, _announced(arm, pose, label, delta)]))
    q, good = _solved(arm, pose, psi, label)
    count = len(psi)
    changes = np.flatnonzero(good != np.roll(good, -1))  # between psi[k] and psi[k + 1] (cyclic)
    if changes.size == 0:
        return NearlyFeasible(ArcSet.full() if good[0] else ArcSet.empty(), label, delta, count)
    low = psi[changes]
    high = np.where(changes + 1 < len(psi), psi[(changes + 1) % len(psi)], psi[0] + 2.0 * np.pi)
    low_good = good[changes]
    while np.max(high - low) > _ENDPOINT_TOLERANCE:
        middle = 0.5 * (low + high)
        _, inside = _solved(arm, pose, middle, label)
        count += len(middle)
        same = inside == low_good
        low, high = np.where(same, middle, low), np.where(same, high, middle)
    edge = np.where(low_good, low, high)  # each change located on its feasible side
    starts = edge[~low_good]  # feasibility begins where the low side is infeasible
    ends = edge[low_good]
    order = np.argsort(np.concatenate([starts, ends]) % (2.0 * np.pi))
    marks = np.concatenate([starts, ends])[order]
    kinds = np.concatenate([np.ones(len(starts)), np.zeros(len(ends))])[order]
    first = int(np.argmax(kinds == 1.0))
    marks, kinds = np.roll(marks, -first), np.roll(kinds, -first)
    arcs = [(float(marks[k]), float(marks[k + 1])) for k in range(0, len(marks) - 1, 2)]
    return NearlyFeasible(ArcSet(arcs), label, delta, count)


def _solved(arm: NearlySRS, pose: np.ndarray, psi: np.ndarray, label: Branch) -> tuple[np.ndarray, np.ndarray]:
    """The branch's certified solutions at arm angles ``psi`` (M,): joint values (M, 7) and whether each exists
    within the limits."""
    result = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, label)
    return result.q[:, 0], result.within_limits[:, 0]


def _delta(arm: NearlySRS, pose: np.ndarray, grid: np.ndarray, q: np.ndarray, good: np.ndarray,
           label: Branch) -> float:
    """The largest ``|q - q_N|`` [rad] of the certified solutions on the grid, doubled, plus 1e-6 rad."""
    from redkin.srs.ik import reachable

    found = np.flatnonzero(np.any(q != 0.0, axis=-1))
    if found.size == 0 or not reachable(arm.geometry, pose):
        return 1e-6
    exact = solve(arm.geometry, pose, grid[found], arm.geometry.kernel_branch(label))[:, 0]
    difference = np.abs(np.angle(np.exp(1j * (q[found] - exact))))
    return float(2.0 * difference.max() + 1e-6)


def _announced(arm: NearlySRS, pose: np.ndarray, label: Branch, delta: float) -> np.ndarray:
    """The endpoints and midpoints of the neighbour's feasible arcs of each joint with its limits loosened by
    ``delta`` (module docstring, step 2); none where the neighbour does not reach the pose."""
    from redkin.srs.ik import reachable

    loose = arm.neighbour.with_limits(arm.neighbour.lower - delta, arm.neighbour.upper + delta)
    geometry = srs_geometry(loose)
    if not reachable(geometry, pose):
        return np.empty(0)
    result = feasible_arm_angles(geometry, pose, label)
    points = []
    for arcs in (*result.per_joint.values(), result.feasible):
        for start, end in arcs.arcs:
            width = (end - start) % (2.0 * np.pi)
            points += [start, end, start + 0.5 * width]
    return np.angle(np.exp(1j * np.array(points))) if points else np.empty(0)
