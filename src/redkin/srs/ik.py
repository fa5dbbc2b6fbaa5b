"""Arm-angle inverse kinematics of S-R-S arms (paper 000 section 3.3, eqs. 11-19).

Given a pose and an arm angle ``psi``, each of the eight branches (signs of
theta_2, theta_4, theta_6) has exactly one joint vector.  Everything is
batched over leading axes of the pose.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.srs.branches import BRANCHES, Branch
from redkin.srs.coefficients import (
    ArmAngleCoefficients,
    arm_angle_coefficients,
    arm_angle_frame,
    elbow_cosine,
    entries_at,
    shoulder_to_wrist,
    unreachable,
)
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.srs.joints import (
    apply_branch_signs,
    assemble_theta,
    branch_sign_arrays,
    branch_signs,
    entry_values,
    positive_branch_angles,
    psi_joint_angles,
)

# (sigma_2, sigma_6) of the branches indexed (i2, i4, i6) as in BRANCHES (s2 slowest), elbow axis left free
_ALL_BRANCH_SIGNS = branch_sign_arrays(np.array([[b.shoulder, b.wrist] for b in BRANCHES]).reshape(2, 2, 2, 2)[:, :1])
_ELBOW_SIGNS = np.array([1, -1])
from redkin.validation import as_float_array, check_finite, check_pose


def as_geometry(arm: "SerialChain | SRSGeometry") -> SRSGeometry:
    """An :class:`SRSGeometry` from a chain (checked) or a geometry (as is)."""
    return arm if isinstance(arm, SRSGeometry) else srs_geometry(arm)


def prepare_targets(geometry: SRSGeometry, pose: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Validate target poses and return frame-7 positions and rotations in frame 0 (Table 1 form)."""
    local = geometry.to_table1_pose(check_pose(pose))
    return local[..., :3, 3], local[..., :3, :3]


def reachable(arm: "SerialChain | SRSGeometry", pose: ArrayLike) -> np.ndarray:
    """Which target poses put the wrist within reach of the elbow (eq. 11 has a solution).

    The arm-angle functions raise ``ValueError`` for a batch holding an
    unreachable pose; filter the batch with this mask first, e.g.
    ``ok = reachable(arm, poses); q = ik(arm, poses[ok], psi)``.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
    pose : array_like, shape (..., 4, 4)

    Returns
    -------
    numpy.ndarray of bool, shape (...)
        True where ``|x_sw|`` lies in ``[|d_se - d_ew|, d_se + d_ew]``, or for an
        offset elbow in ``[sqrt(C - R), sqrt(C + R)]`` (with the rounding slack
        :data:`redkin.srs.coefficients.REACH_TOLERANCE` on ``cos(theta_4 - phi)``).
    """
    geometry = as_geometry(arm)
    position, rotation = prepare_targets(geometry, pose)
    _, cosine = elbow_cosine(geometry, shoulder_to_wrist(geometry, position, rotation))
    return ~unreachable(cosine)


def check_psi(psi: ArrayLike) -> np.ndarray:
    """Arm angles as a finite float array."""
    array = as_float_array(psi, "psi")
    check_finite(array, "psi")
    return array


def coefficients_for(
    arm: "SerialChain | SRSGeometry", pose: ArrayLike, elbow_sign: "int | np.ndarray"
) -> ArmAngleCoefficients:
    """Eq. 12 and eq. 16 coefficients of validated poses ``(..., 4, 4)`` for an elbow sign."""
    geometry = as_geometry(arm)
    position, rotation = prepare_targets(geometry, pose)
    return arm_angle_coefficients(geometry, position, rotation, elbow_sign)


def theta_at(coefficients: ArmAngleCoefficients, psi: np.ndarray, branch: Branch) -> np.ndarray:
    """The 7 DH angles at arm angles ``psi`` for one branch (eqs. 11, 13-15, 17-19)."""
    values = entry_values(coefficients.entries, psi)
    psi_joints = psi_joint_angles(values, branch_signs(branch.shoulder, branch.wrist))
    return assemble_theta(coefficients.theta4, psi_joints)


def ik(
    arm: "SerialChain | SRSGeometry",
    pose: ArrayLike,
    psi: ArrayLike,
    branch: "str | Branch" = "+++",
) -> np.ndarray:
    """Joint values reaching ``pose`` with arm angle ``psi`` on one branch.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
        An S-R-S arm in paper 000 Table 1 form (base, tool, offsets and signs allowed).
    pose : array_like, shape (..., 4, 4)
        Target poses of the tool in the base frame.
    psi : array_like, broadcastable to the batch shape
        Arm angles in radians (right-handed about shoulder -> wrist, eq. 6).
    branch : str or Branch
        Signs of theta_2, theta_4, theta_6, e.g. ``"+-+"``.

    Returns
    -------
    numpy.ndarray, shape (..., 7)
        Joint values ``q`` of the chain (each wrapped into its limit range
        when a multiple of 2 pi gets it there, else into ``[-pi, pi)``).
        They may violate the limits: see :func:`redkin.srs.feasible_arm_angles`.

    Raises
    ------
    ValueError
        For a malformed pose or psi, or a wrist position out of reach.
    """
    geometry = as_geometry(arm)
    chosen = geometry.table1_branch(branch)
    psi = check_psi(psi)
    position, rotation = prepare_targets(geometry, pose)
    frame = arm_angle_frame(geometry, position, rotation, chosen.elbow)
    psi_joints = psi_joint_angles(entries_at(frame, psi), branch_signs(chosen.shoulder, chosen.wrist))
    return geometry.to_chain_q(assemble_theta(frame.theta4, psi_joints))


def ik_all_branches(arm: "SerialChain | SRSGeometry", pose: ArrayLike, psi: ArrayLike) -> np.ndarray:
    """Joint values of all eight branches, shape ``(..., 8, 7)`` in the order of :data:`BRANCHES`.

    ``psi`` broadcasts against the batch shape of ``pose``.  See :func:`ik`.
    Both elbow signs share the shoulder-wrist geometry; each gives the
    ``sigma_2 = sigma_6 = +1`` angles once, and the other three branches of
    that elbow sign follow by :func:`redkin.srs.joints.apply_branch_signs`.
    """
    geometry = as_geometry(arm)
    psi = check_psi(psi)
    position, rotation = prepare_targets(geometry, pose)
    frame = arm_angle_frame(geometry, position[..., None, :], rotation[..., None, :, :], _ELBOW_SIGNS)  # (..., 2)
    positive = positive_branch_angles(entries_at(frame, psi[..., None]))  # (..., 2, 6) over the elbow sign
    psi_joints = apply_branch_signs(positive[..., None, :, None, :], _ALL_BRANCH_SIGNS)  # (..., 2, 2, 2, 6)
    theta = assemble_theta(frame.theta4[..., None, :, None], psi_joints).reshape(psi_joints.shape[:-4] + (8, 7))
    if geometry.branch_senses != (1, 1, 1):  # Table 1 order -> the order of the branches in the chain's senses
        theta = theta[..., geometry.branch_order, :]
    return geometry.to_chain_q(theta)
