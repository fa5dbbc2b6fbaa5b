"""Full inverse kinematics of the 8-DOF arm: hand pose + (psi, phi) -> every 8-joint solution.

The hand pose (frame E of Table 2.1, i.e. after the tool ``L4``) gives the
wrist ``W`` (origin of frame 6) and the rotation ``R8`` of frame 8.  Joints
1-5 come from :func:`~redkin.torso_arm.position_ik.position_ik` (4 branches),
joints 6-8 from ``R58 = R5^T R8`` (:func:`~redkin.torso_arm.wrist_ik.wrist_ik`,
2 branches): 8 solutions per pose, each marked within limits or not.  The
orientation may be given as a rotation matrix or as X-Y-Z fixed angles
``(alpha, beta, gamma)``, ``R = Rz(alpha) Ry(beta) Rx(gamma)`` [001 eq. 4.4].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import as_float_array, check_finite, check_rotation, check_vectors
from redkin.errors import RedkinError
from redkin.so3 import xyz_fixed_to_matrix
from redkin.torso_arm.branches import OK, POSITION_BRANCHES, STATUS_NAMES, WRIST_BRANCHES, wrap_to_limits
from redkin.torso_arm.elbow_angle import ElbowReference, as_reference
from redkin.torso_arm.geometry import MIRROR, TorsoArm
from redkin.torso_arm.position_ik import joints_from_points, solve_points
from redkin.torso_arm.shoulder_angle import theta1_from_shoulder_angle
from redkin.torso_arm.wrist_ik import wrist_ik

#: ``(theta_3 flag, theta_5 flag, sin theta_7 flag)`` of each of the 8 solutions, in order.
BRANCHES = tuple((f3, f5, f7) for f3, f5 in POSITION_BRANCHES for f7 in WRIST_BRANCHES)


@dataclass(frozen=True)
class IKSolution:
    """All 8-joint solutions for hand poses and redundancy parameters.

    Attributes
    ----------
    q : numpy.ndarray, shape (..., 8, 8)
        Solutions in the order of :data:`BRANCHES`; NaN where ``status != OK``.
    within_limits : numpy.ndarray of bool, shape (..., 8)
    wrist_singular : numpy.ndarray of bool, shape (..., 8)
        ``sin theta_7 = 0``: joints 6 and 8 aligned, theta_8 set to 0.
    status : numpy.ndarray of int, shape (...)
        See :data:`~redkin.torso_arm.branches.STATUS_NAMES`.
    """

    q: np.ndarray
    within_limits: np.ndarray
    wrist_singular: np.ndarray
    status: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """``status == OK``."""
        return self.status == OK

    def status_names(self) -> np.ndarray:
        """The status codes as words."""
        return np.vectorize(STATUS_NAMES.get, otypes=[object])(self.status)


def _hand_rotation(rotation: ArrayLike | None = None, angles: ArrayLike | None = None) -> np.ndarray:
    """A hand rotation from a matrix or from X-Y-Z fixed angles [001 eq. 4.4]; exactly one must be given."""
    if rotation is not None and angles is None:
        return check_rotation(rotation, "rotation")
    if angles is not None and rotation is None:
        return xyz_fixed_to_matrix(check_vectors(angles, 3, "angles"))
    raise RedkinError("give exactly one of rotation (3x3 matrix) or angles (alpha, beta, gamma)")


def ik(
    arm: TorsoArm,
    position: ArrayLike,
    shoulder_angle: ArrayLike,
    elbow_angle: ArrayLike,
    rotation: ArrayLike | None = None,
    angles: ArrayLike | None = None,
    reference: ElbowReference | str | ArrayLike | None = None,
) -> IKSolution:
    """Every 8-joint solution for hand poses at shoulder angle psi and elbow angle phi.

    Parameters
    ----------
    arm : TorsoArm
    position : array_like, shape (..., 3)
        Hand position (origin of frame E, after the tool) in metres.
    shoulder_angle, elbow_angle : array_like, shape (...)
        psi and phi in radians (see :func:`~redkin.torso_arm.position_ik.position_ik`).
    rotation : array_like, shape (..., 3, 3), optional
        Hand orientation as a rotation matrix ...
    angles : array_like, shape (..., 3), optional
        ... or as X-Y-Z fixed angles [001 eq. 4.4], radians.
    reference : optional
        Elbow-angle reference (default: theta_4 = 0 rule).

    Returns
    -------
    IKSolution
    """
    p = check_vectors(position, 3, "position")
    rot = _hand_rotation(rotation, angles)
    psi = as_float_array(shoulder_angle, "shoulder_angle")
    check_finite(psi, "shoulder_angle")
    phi = as_float_array(elbow_angle, "elbow_angle")
    check_finite(phi, "elbow_angle")
    ref = as_reference(reference)
    shape = np.broadcast_shapes(p.shape[:-1], rot.shape[:-2], psi.shape, phi.shape)
    p = np.broadcast_to(p, shape + (3,))
    rot = np.broadcast_to(rot, shape + (3, 3))
    if arm.side == "left":  # solve the mirror image: T_right = M T_left M
        p, rot, ref = p @ MIRROR, MIRROR @ rot @ MIRROR, ref.mirrored()
    right = arm.right_chain
    tool_inverse = np.linalg.inv(right.tool)
    rot8 = rot @ tool_inverse[:3, :3]
    wrist = p + np.einsum("...ij,j->...i", rot, tool_inverse[:3, 3])
    theta1, defined = theta1_from_shoulder_angle(np.broadcast_to(psi, shape), wrist)
    _, elbow, status, _ = solve_points(arm, wrist, theta1, defined, np.broadcast_to(phi, shape), ref)
    q5 = joints_from_points(arm, np.where(defined, theta1, 0.0), elbow, wrist)  # (..., 4, 5)
    padded = np.concatenate([q5, np.zeros(q5.shape[:-1] + (3,))], axis=-1)
    rot5 = right.frames(np.where(np.isfinite(padded), padded, 0.0))[..., 5, :3, :3]
    r58 = np.swapaxes(rot5, -1, -2) @ rot8[..., None, :, :]  # [001 eq. 4.8]
    q678, singular = wrist_ik(r58)  # (..., 4, 2, 3)
    q = np.concatenate([np.broadcast_to(q5[..., None, :], q5.shape[:-1] + (2, 5)), q678], axis=-1)
    q = q.reshape(shape + (8, 8))
    singular = np.broadcast_to(singular[..., None], shape + (4, 2)).reshape(shape + (8,))
    if arm.side == "left":
        q = q * np.array([-1.0] + [1.0] * 7)
    chain = arm.chain
    q = wrap_to_limits(chain, q)
    ok = status == OK
    q = np.where(ok[..., None, None], q, np.nan)
    limits = np.all((q >= chain.lower) & (q <= chain.upper), axis=-1) & ok[..., None]
    return IKSolution(q=q, within_limits=limits, wrist_singular=singular & ok[..., None], status=status)


def redundancy_parameters(
    arm: TorsoArm, q: ArrayLike, reference: ElbowReference | str | ArrayLike | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The shoulder angle psi and elbow angle phi of joint vectors (the inverse of the IK's inputs).

    Returns
    -------
    psi, phi : numpy.ndarray, shape (...)
        NaN where undefined (``W_y = 0``, or no elbow reference).
    defined : numpy.ndarray of bool, shape (...)
    """
    from redkin.torso_arm.elbow_angle import elbow_angle
    from redkin.torso_arm.geometry import ELBOW_FRAME, SHOULDER_FRAME, WRIST_FRAME
    from redkin.torso_arm.shoulder_angle import shoulder_angle

    chain = arm.chain
    q = chain.check_q(q)
    frames = chain.frames(q)
    shoulder, elbow, wrist = (arm.to_right(frames[..., k, :3, 3]) for k in (SHOULDER_FRAME, ELBOW_FRAME, WRIST_FRAME))
    theta1 = q[..., 0] if arm.side == "right" else -q[..., 0]
    ref = as_reference(reference)
    if arm.side == "left":
        ref = ref.mirrored()
    psi = shoulder_angle(theta1, wrist)
    phi, exists = elbow_angle(arm, shoulder, elbow, wrist, reference=ref)
    return psi, phi, np.isfinite(psi) & exists
