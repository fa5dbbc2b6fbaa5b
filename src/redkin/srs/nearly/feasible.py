"""Feasible arm angles of a nearly S-R-S arm, read off its certified self-motion (docs/srs.md, "Feasible arm angles").

No closed form gives the arm angles where a joint of the real arm meets a
limit.  The pose's self-motion does: :func:`redkin.srs.nearly.self_motion.self_motions`
follows each of its curves with certified steps, each an arc of true
solutions on a known branch, within the limits, outside them, or (for a
stretch of arm angle at most :data:`redkin.srs.nearly._self_motion_kernels.RESOLUTION`
wide, where a limit or a branch boundary is crossed) not decided.  A
branch's feasible set is the union, over the runs of consecutive steps on
the branch within the limits, of the arm angles between the smallest and the
largest at the run's points (:func:`redkin.srs.nearly.self_motion.feasible_along`).

What is certified: every arm angle of the set has a solution of the branch
within the limits (a run is a continuous arc of such solutions, and the arm
angle takes every value between those at its points); an end of the set lies
within :data:`redkin.srs.nearly._self_motion_kernels.RESOLUTION` (or, at a fold,
within the last step's arm-angle bound) of the true end; nothing is sampled
in the arm angle, so no gap of the real arm is stepped over.  What is not: a
curve of the self-motion through none of the seeds (:data:`redkin.srs.nearly.self_motion.SEEDS`)
is not found, and a curve that could not be followed whole
(:attr:`NearlyFeasible.complete` false: a step at a singular configuration
that the certificate cannot take) adds only the arcs followed.

How far the real set lies from the neighbour's: where both arms have the
branch's solution at ``psi`` and they differ by at most ``d`` in every
joint, a real solution within the limits makes the neighbour's lie within
the limits loosened by ``d``, and a neighbour's solution within the limits
tightened by ``d`` makes the real one lie within the limits.  So the real
set lies between the neighbour's exact sets for the limits tightened and
loosened by ``d`` (:attr:`NearlyFeasible.inner`, :attr:`NearlyFeasible.outer`),
``d`` the largest difference over the curves' points on the branch, doubled,
plus 1e-6 rad (:attr:`NearlyFeasible.delta`: measured, not derived from the
offsets, which bound ``|q - q_N|`` only through the inverse of a Jacobian that
grows without bound near a singular wrist or shoulder).
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.circle import ArcSet
from redkin.errors import RedkinError
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.feasible import FeasibleArmAngles, feasible_arm_angles
from redkin.srs.geometry import srs_geometry
from redkin.srs.ik import reachable, solve
from redkin.srs.nearly.arm import NearlySRS
from redkin.srs.nearly.self_motion import SelfMotion, feasible_along, feasible_along_all, whole_self_motion


class NearlyFeasible:
    """The feasible arm angles of one pose and branch on a nearly S-R-S arm (module docstring).

    Attributes
    ----------
    feasible : ArcSet
        Arm angles where a solution of the branch lies within the limits, each certified.
    branch : Branch
    curves : tuple of SelfMotion
        The pose's self-motion it was read off (:func:`redkin.srs.nearly.self_motion.self_motions`).
    complete : bool
        Whether that self-motion was followed whole (:func:`redkin.srs.nearly.self_motion.whole_self_motion`); where
        not, ``feasible`` holds the arcs of the curves followed, each certified, and may miss others.
    """

    def __init__(self, arm: NearlySRS, pose: np.ndarray, branch: Branch, curves: tuple[SelfMotion, ...],
                 complete: bool, feasible: ArcSet | None = None) -> None:
        self._arm, self._pose = arm, pose
        self.branch = branch
        self.curves = curves
        self.complete = complete
        self.feasible = feasible_along(curves, branch) if feasible is None else feasible

    def __repr__(self) -> str:
        return f"NearlyFeasible(branch={self.branch}, feasible={self.feasible!r}, complete={self.complete})"

    @property
    def samples(self) -> int:
        """The points of the curves (every one a solution of the pose, certified)."""
        return sum(len(curve.psi) for curve in self.curves)

    @cached_property
    def delta(self) -> float:
        """The largest ``|q - q_N|`` [rad] between the real arm's solutions on the branch (the curves' points) and the
        neighbour's at the same arm angles, doubled, plus 1e-6 rad (module docstring); computed on first use."""
        row = BRANCHES.index(self.branch)
        points = [(curve.q[:-1][curve.branches == row], curve.psi[:-1][curve.branches == row]) for curve in self.curves]
        q = np.concatenate([p[0] for p in points]) if points else np.empty((0, 7))
        psi = np.concatenate([p[1] for p in points]) if points else np.empty(0)
        geometry = self._arm.geometry
        if psi.size == 0 or not reachable(geometry, self._pose):
            return 1e-6
        exact = solve(geometry, self._pose, psi, geometry.kernel_branch(self.branch))[:, 0]
        gaps = np.abs(np.mod(q - exact + np.pi, 2.0 * np.pi) - np.pi)
        return float(2.0 * np.nanmax(gaps) + 1e-6) if np.isfinite(gaps).any() else 1e-6

    @cached_property
    def inner(self) -> ArcSet:
        """The neighbour's exact feasible set [000 eqs. 20-30] for the limits tightened by :attr:`delta`; empty where
        the neighbour does not reach the pose."""
        tightened = _neighbour_sets(self._arm, self._pose, self.branch, -self.delta)
        return ArcSet.empty() if tightened is None else tightened.feasible

    @cached_property
    def outer(self) -> ArcSet:
        """The same for the limits loosened by :attr:`delta`; the whole circle where the neighbour does not reach the
        pose."""
        loosened = _neighbour_sets(self._arm, self._pose, self.branch, self.delta)
        return ArcSet.full() if loosened is None else loosened.feasible


def feasible_arm_angles_nearly(arm: NearlySRS, pose: ArrayLike, branch: str | Branch = "+++") -> NearlyFeasible:
    """The arm angles at which the real arm reaches ``pose`` on ``branch`` within its limits (module docstring).

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose) or branch.
    """
    label = parse_branch(branch)
    target = _one_pose(pose)
    return NearlyFeasible(arm, target, label, *whole_self_motion(arm, target))


def feasible_arm_angles_nearly_all(arm: NearlySRS, pose: ArrayLike) -> tuple[NearlyFeasible, ...]:
    """:func:`feasible_arm_angles_nearly` of every branch, in the order of :data:`redkin.srs.BRANCHES`, from one
    self-motion.

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose).
    """
    target = _one_pose(pose)
    curves, complete = whole_self_motion(arm, target)
    return tuple(NearlyFeasible(arm, target, branch, curves, complete, feasible)
                 for branch, feasible in zip(BRANCHES, feasible_along_all(curves), strict=True))


def _one_pose(pose: ArrayLike) -> np.ndarray:
    """One checked (4, 4) pose, C-contiguous."""
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    return target


def _neighbour_sets(arm: NearlySRS, pose: np.ndarray, label: Branch, change: float) -> FeasibleArmAngles | None:
    """The neighbour's exact feasible sets [000 eqs. 20-30] of the branch with its limits loosened by ``change``
    [rad] (tightened where negative); ``None`` where the neighbour does not reach the pose or a tightened joint's
    range closes."""
    neighbour = arm.neighbour
    lower, upper = neighbour.lower - change, neighbour.upper + change
    if np.any(lower > upper):
        return None
    geometry = srs_geometry(neighbour.with_limits(lower, upper))
    return feasible_arm_angles(geometry, pose, label) if reachable(geometry, pose) else None
