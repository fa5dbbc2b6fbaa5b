"""Position inverse kinematics of joints 1-5 from the wrist and (psi, phi) (chapter 3, thesis 001).

Steps (right arm; the left arm is solved as its mirror image):

1. theta_1 from the shoulder angle psi (:mod:`redkin.torso_arm.shoulder_angle`).
2. The elbow ``E`` from the elbow angle phi (:mod:`redkin.torso_arm.elbow_angle`).
3. The joints from the points ``S``, ``E``, ``W`` -- repaired forms of sections 3.4.2-3.4.5:

   * theta_5 [001 eq. 3.19]: ``sin(theta_5 + delta) = k = (l^2 - L1^2 - l_ew^2) / (2 L1 l_ew)``
     has two roots, ``asin(k) - delta`` and ``pi - asin(k) - delta`` (the
     thesis keeps only the first).
   * theta_3 [001 eq. 3.22]: with ``u' = Ry(-theta_1) (E - S) / L1 = (s3, c2 c3, s2 c3)``
     [001 eqs. 3.15-3.17], ``sin(theta_3) = u'_x``; both ``asin`` and ``pi - asin``
     lie in the range -5..185 deg, so a branch flag picks ``sgn(cos theta_3)``.
   * theta_2 ([001 eqs. 3.20-3.24], repaired): ``theta_2 = atan2(sgn(c3) u'_z, sgn(c3) u'_y)``,
     no division by ``sin(theta_1)`` or ``cos(theta_3)``.
   * theta_4 ([001 eqs. 3.25-3.26] replaced): in frame 3 the forearm is
     ``f3 = (m s4, c, m c4)`` with ``m = L3 c5 - L2 s5 = l_ew cos(theta_5 + delta)``,
     so ``theta_4 = atan2(sgn(m) f3_x, sgn(m) f3_z)`` over the full circle
     ([001 eq. 3.26] forced ``|theta_4| <= 90`` deg against the +-150 deg limit;
     [001 eq. 3.25] mixes lengths and ratios and divides by ``cos theta_3``).

Every input is batched over leading axes (broadcast together).
"""

from __future__ import annotations

from dataclasses import dataclass
from math import atan2, cos, hypot, pi, sin

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel, run_batch
from redkin._validation import as_float_array, check_finite, check_vectors
from redkin.torso_arm._kernel_tools import cross, dot, flat, norm, row, scale, shoulder_point, sub, turn_y
from redkin.torso_arm.branches import (
    NO_REFERENCE,
    OK,
    POSITION_BRANCHES,
    SHOULDER_UNDEFINED,
    STATUS_NAMES,
    UNREACHABLE,
    wrap_to_limits,
)
from redkin.torso_arm.elbow_angle import (
    ElbowCircle,
    ElbowReference,
    as_reference,
    elbow_circle,
    elbow_position,
    reference_direction,
)
from redkin.torso_arm.geometry import TorsoArm
from redkin.torso_arm.shoulder_angle import theta1_from_shoulder_angle


@kernel
def joints_one(theta1, elbow, wrist, L0, L1, delta, out):
    """Joints 1-5 of every position branch for right-arm points (repaired sections 3.4.2-3.4.5,
    [001 eqs. 3.15-3.26]).

    ``elbow``, ``wrist`` (3-tuples) lie on a valid posture; ``out`` (4, 5)
    receives one row per branch of :data:`POSITION_BRANCHES`, angles in ``(-pi, pi]``.
    """
    shoulder = shoulder_point(L0, theta1)
    upper = turn_y(-theta1, scale(sub(elbow, shoulder), 1.0 / L1))  # u' = Ry(-theta_1) (E - S) / L1
    forearm = turn_y(-theta1, sub(wrist, elbow))
    # [001 eqs. 3.18, 3.19] as atan2: sin(theta_5 + delta) = (f . u) / l_ew, |cos(theta_5 + delta)| = |f x u| / l_ew
    asin_k = atan2(dot(forearm, upper), norm(cross(forearm, upper)))
    asin_3 = atan2(upper[0], hypot(upper[1], upper[2]))  # [001 eq. 3.22] as atan2
    for k3 in range(2):  # the order of POSITION_BRANCHES: theta_3 flag outer, theta_5 flag inner
        flag3 = 1.0 - 2.0 * k3
        theta3 = asin_3 if flag3 > 0 else pi - asin_3  # [001 eq. 3.22] + second branch
        theta2 = atan2(flag3 * upper[2], flag3 * upper[1])  # [001 eq. 3.24], repaired
        c2, s2, c3, s3 = cos(theta2), sin(theta2), cos(theta3), sin(theta3)
        f3x = c3 * forearm[0] - s3 * c2 * forearm[1] - s2 * s3 * forearm[2]
        f3z = -s2 * forearm[1] + c2 * forearm[2]
        for k5 in range(2):
            flag5 = 1.0 - 2.0 * k5
            b = 2 * k3 + k5
            out[b, 0], out[b, 1], out[b, 2] = theta1, theta2, theta3
            out[b, 3] = atan2(flag5 * f3x, flag5 * f3z)  # replaces [001 eqs. 3.25-3.26]; sgn(m) = flag5
            out[b, 4] = asin_k - delta if flag5 > 0 else pi - asin_k - delta  # [001 eq. 3.19] + second branch


@kernel
def _joint_batch(start, stop, theta1, elbow, wrist, L0, L1, delta, out):
    """:func:`joints_one` for each item: ``theta1`` (N,), ``elbow``, ``wrist`` (N, 3) -> ``out`` (N, 4, 5)."""
    for i in range(start, stop):
        joints_one(theta1[i], row(elbow, i), row(wrist, i), L0, L1, delta, out[i])


def joints_from_points(arm: TorsoArm, theta1: np.ndarray, elbow: np.ndarray, wrist: np.ndarray) -> np.ndarray:
    """Joints 1-5 of every position branch for right-arm points (repaired sections 3.4.2-3.4.5,
    [001 eqs. 3.15-3.26]).

    Parameters
    ----------
    theta1 : numpy.ndarray, shape (...)
    elbow, wrist : numpy.ndarray, shape (..., 3)
        Points on a valid posture (``|E - S| = L1``, ``|W - E| = l_ew``); trusted.

    Returns
    -------
    numpy.ndarray, shape (..., 4, 5)
        Branches in the order of :data:`POSITION_BRANCHES`, angles in ``(-pi, pi]``.
    """
    shape, (t1, E, W) = flat((theta1, 0), (elbow, 1), (wrist, 1))
    out = np.empty((t1.shape[0], len(POSITION_BRANCHES), 5))
    run_batch(_joint_batch, t1.shape[0], t1, E, W, arm.L0, arm.L1, arm.delta, out)
    return out.reshape(shape + out.shape[1:])


@dataclass(frozen=True)
class PositionSolution:
    """Joints 1-5 for wrist positions and redundancy parameters.

    Attributes
    ----------
    q : numpy.ndarray, shape (..., 4, 5)
        One row per branch of :data:`POSITION_BRANCHES` (theta_3 flag,
        theta_5 flag), radians, each angle in ``(-pi, pi]`` or shifted by
        ``2 pi`` into its limits.  NaN where ``status != OK``.
    within_limits : numpy.ndarray of bool, shape (..., 4)
        Whether each branch respects the joint limits of joints 1-5.
    status : numpy.ndarray of int, shape (...)
        :data:`~redkin.torso_arm.branches.STATUS_NAMES`: ok, unreachable,
        no reference (elbow angle cannot be measured), shoulder angle undefined.
    shoulder, elbow, wrist : numpy.ndarray, shape (..., 3)
        The points of the posture in this side's world (NaN where not ok).
    """

    q: np.ndarray
    within_limits: np.ndarray
    status: np.ndarray
    shoulder: np.ndarray
    elbow: np.ndarray
    wrist: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """``status == OK``."""
        return self.status == OK

    def status_names(self) -> np.ndarray:
        """The status codes as words."""
        return np.vectorize(STATUS_NAMES.get, otypes=[object])(self.status)


def solve_points(
    arm: TorsoArm,
    wrist_right: np.ndarray,
    theta1: np.ndarray,
    theta1_defined: np.ndarray,
    phi: np.ndarray,
    reference: ElbowReference,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, ElbowCircle]:
    """Right-arm elbow points and status for given theta_1 (internal step shared by the map code)."""
    shoulder = arm.shoulder(np.where(theta1_defined, theta1, 0.0))
    circle = elbow_circle(arm, shoulder, wrist_right)
    e1, has_reference = reference_direction(arm, circle, reference)
    elbow = elbow_position(circle, e1, phi)
    status = np.full(circle.length.shape, OK)
    status = np.where(~has_reference, NO_REFERENCE, status)
    status = np.where(~circle.reachable, UNREACHABLE, status)
    status = np.where(~theta1_defined, SHOULDER_UNDEFINED, status)
    return shoulder, elbow, status, circle


def position_ik(
    arm: TorsoArm,
    wrist: ArrayLike,
    shoulder_angle: ArrayLike,
    elbow_angle: ArrayLike,
    reference: ElbowReference | str | ArrayLike | None = None,
) -> PositionSolution:
    """Joints 1-5 from the wrist position and the shoulder and elbow angles (chapter 3).

    Parameters
    ----------
    arm : TorsoArm
        The arm (right or left) and its lengths and limits.
    wrist : array_like, shape (..., 3)
        Wrist position ``W`` (origin of frame 6) in the base frame, metres.
    shoulder_angle : array_like, shape (...)
        psi in radians (signed, :func:`~redkin.torso_arm.shoulder_angle.shoulder_angle`).
    elbow_angle : array_like, shape (...)
        phi in radians, right-handed about the shoulder->wrist axis.
    reference : ElbowReference, "theta4", "vector" or 3-vector, optional
        Where phi = 0 (default: the thesis's theta_4 = 0 rule).

    Returns
    -------
    PositionSolution
        All four branches; unreachable wrists, missing references and
        undefined shoulder angles are reported in ``status``.  For the left
        arm, psi, phi and the reference are those of the mirror image.
    """
    w, psi, phi, ref = _prepare(arm, wrist, shoulder_angle, "shoulder_angle", elbow_angle, reference)
    theta1, defined = theta1_from_shoulder_angle(psi, w)
    return _finish(arm, w, theta1, defined, phi, ref)


def position_ik_from_theta1(
    arm: TorsoArm,
    wrist: ArrayLike,
    theta1: ArrayLike,
    elbow_angle: ArrayLike,
    reference: ElbowReference | str | ArrayLike | None = None,
) -> PositionSolution:
    """As :func:`position_ik` but with the torso angle theta_1 given instead of psi."""
    w, t1, phi, ref = _prepare(arm, wrist, theta1, "theta1", elbow_angle, reference)
    if arm.side == "left":
        t1 = -t1
    return _finish(arm, w, t1, np.ones(t1.shape, bool), phi, ref)


def _prepare(arm: TorsoArm, wrist, first, first_name: str, elbow_angle, reference):
    """Validate and broadcast the wrist, the first redundancy parameter and phi; mirror for the left arm."""
    w = check_vectors(wrist, 3, "wrist")
    first = as_float_array(first, first_name)
    check_finite(first, first_name)
    phi = as_float_array(elbow_angle, "elbow_angle")
    check_finite(phi, "elbow_angle")
    ref = as_reference(reference)
    shape = np.broadcast_shapes(w.shape[:-1], first.shape, phi.shape)
    w = np.broadcast_to(arm.to_right(w), shape + (3,))
    if arm.side == "left":
        ref = ref.mirrored()
    return w, np.broadcast_to(first, shape), np.broadcast_to(phi, shape), ref


def _finish(arm: TorsoArm, w: np.ndarray, theta1: np.ndarray, defined: np.ndarray, phi: np.ndarray,
            ref: ElbowReference) -> PositionSolution:
    shoulder, elbow, status, _ = solve_points(arm, w, theta1, defined, phi, ref)
    q = joints_from_points(arm, np.where(defined, theta1, 0.0), elbow, w)
    if arm.side == "left":
        q = q * np.array([-1.0, 1.0, 1.0, 1.0, 1.0])
    chain = arm.chain
    q = wrap_to_limits(chain, q, slice(0, 5))
    ok = status == OK
    q = np.where(ok[..., None, None], q, np.nan)
    limits = np.all((q >= chain.lower[:5]) & (q <= chain.upper[:5]), axis=-1) & ok[..., None]
    bad = ~ok[..., None]
    return PositionSolution(
        q=q,
        within_limits=limits,
        status=status,
        shoulder=np.where(bad, np.nan, arm.from_right(shoulder)),
        elbow=np.where(bad, np.nan, arm.from_right(elbow)),
        wrist=np.array(arm.from_right(w)),
    )
