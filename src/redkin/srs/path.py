"""Arm-angle control along a path of poses (paper 000 section 6.2.2).

For each pose the arm angle is either held fixed (``Gamma_0`` of the paper)
or chosen as the weighted optimum of [000 eq. 40] clamped to the feasible set
(``Gamma``).  A pose is reachable when the chosen arm angle satisfies every
joint limit, i.e. it lies in the feasible set.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose, check_vectors
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.srs._targets import as_geometry
from redkin.srs.branches import Branch
from redkin.srs.coefficients import coefficients_for
from redkin.srs.feasible import FeasibleArmAngles, feasible_from_coefficients
from redkin.srs.geometry import SRSGeometry
from redkin.srs.ik import theta_at
from redkin.srs.optimal import check_weights, default_target, maximiser, objective_coefficients, weighted_objective


@dataclass(frozen=True)
class ArmAnglePath:
    """Arm angles and joint values along a path.

    Attributes
    ----------
    psi : numpy.ndarray, shape (N,)
        Chosen arm angle per pose (the unclamped optimum where the feasible set is empty).
    q : numpy.ndarray, shape (N, 7)
        Joint values at ``psi``: the first waypoint's as :func:`redkin.srs.ik` gives them, each later one's
        inside the joint ranges nearest the waypoint before it (a range wider than ``2 pi`` holds some angles
        twice; an unlimited joint turns on without wrapping).
    reachable : numpy.ndarray of bool, shape (N,)
        ``psi`` satisfies every joint limit.
    feasible : list of FeasibleArmAngles
        Feasible sets per pose.
    """

    psi: np.ndarray
    q: np.ndarray
    reachable: np.ndarray
    feasible: list[FeasibleArmAngles]

    @property
    def first_unreachable(self) -> int | None:
        """Index of the first pose the path cannot reach, or ``None``."""
        bad = np.flatnonzero(~self.reachable)
        return int(bad[0]) if bad.size else None


def arm_angle_path(
    arm: SerialChain | SRSGeometry,
    poses: ArrayLike,
    branch: str | Branch = "+++",
    target: ArrayLike | None = None,
    weights: ArrayLike = (0.5, 0.5),
    fixed_psi: float | None = None,
) -> ArmAnglePath:
    """Choose the arm angle of each pose of a path and return the joint path.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
    poses : array_like, shape (N, 4, 4)
    branch : str or Branch
    target, weights
        As in :func:`redkin.srs.optimal_arm_angles`.
    fixed_psi : float, optional
        Hold the arm angle at this value instead of optimising it.
    """
    geometry = as_geometry(arm)
    chosen = geometry.table1_branch(branch)
    poses = check_pose(poses)
    if poses.ndim != 3:
        raise RedkinError(f"poses must have shape (N, 4, 4), got {poses.shape}")
    coefficients = coefficients_for(geometry, poses, chosen.elbow)
    feasible = list(feasible_from_coefficients(coefficients, chosen, geometry))
    if fixed_psi is not None:
        psi = np.full(len(poses), float(fixed_psi))
        reachable = np.array([bool(f.feasible.contains(fixed_psi)) for f in feasible])
    else:
        q_target = default_target(geometry) if target is None else check_vectors(target, 7, "target").reshape(7)
        shoulder, wrist = objective_coefficients(coefficients, geometry, q_target)
        combined = weighted_objective(shoulder, wrist, check_weights(weights))
        best = maximiser(combined[..., 0], combined[..., 1])  # [000 eq. 40]
        clamped = [f.feasible.nearest(p) for f, p in zip(feasible, best.tolist())]
        reachable = np.array([c is not None for c in clamped])
        psi = np.array([p if c is None else c for c, p in zip(clamped, best.tolist())])
    q = geometry.to_chain_q(theta_at(coefficients, psi, chosen))
    for k in range(1, len(q)):  # where a range holds an angle twice, the representative nearest the last waypoint
        q[k] = geometry.chain.nearest_in_range(q[k], near=q[k - 1])
    return ArmAnglePath(psi=psi, q=q, reachable=reachable, feasible=feasible)
