"""Singular arm angles of the shoulder (theta_2 = 0 or pi) and the wrist (theta_6 = 0 or pi): paper 000 section 5.1.

Shoulder: ``cos theta_2 = -(a s + b c + c_s32)`` [000 eq. 14] equals 1 somewhere
only if ``a^2 + b^2 - (c_s32 + 1)^2 = 0`` ([000 eq. 31]; the left side is never
positive), and then at the single arm angle with ``(sin psi, cos psi) =
-(a, b) / (c_s32 + 1)``, which is [000 eq. 32] ``psi = 2 atan(a / (b - c_s32 -
1))`` written so that it also holds at ``psi = +-pi``.  Wrist likewise with
``cos theta_6 = a s + b c + c_w33`` [000 eq. 18]: [000 eq. 33] ``a^2 + b^2 - (c_w33 -
1)^2 = 0`` and [000 eq. 34].  When ``a = b = 0`` and the constant is 1, every arm
angle is singular (the wrist lies on the joint-1 axis with the arm
stretched, or the mirror case at the wrist).

``theta_2 = +-pi`` (``theta_6 = +-pi``) is singular too: axes 1 and 3 (5 and 7) lie on one line,
antiparallel, and only ``theta_1 - theta_3`` is fixed.  The paper leaves it out; it is the same
equations with ``cos theta_2 = -1``, i.e. the constant ``c_s32 - 1`` in place of ``c_s32 + 1``
(``c_w33 + 1`` in place of ``c_w33 - 1``), and it is where a maker's zero pose often puts the arm:
the Kinova Gen3's ``q_2 = 0`` and ``q_6 = 0`` are ``theta = pi`` of its Table 1 form.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.srs._targets import as_geometry
from redkin.srs.branches import Branch
from redkin.srs.coefficients import ArmAngleCoefficients, coefficients_for
from redkin.srs.geometry import SRSGeometry

#: Default tolerance on the residuals of [000 eqs. 31, 33].
SINGULAR_TOLERANCE = 1e-9


@dataclass(frozen=True)
class SingularArmAngles:
    """Singular arm angles of one pose and elbow sign.

    Attributes
    ----------
    shoulder, wrist : tuple of float
        Arm angles at which theta_2 = 0 [000 eq. 32] or pi, theta_6 = 0 [000 eq. 34] or pi, sorted; empty if
        none.
    shoulder_everywhere, wrist_everywhere : bool
        Every arm angle is singular.
    shoulder_coefficients, wrist_coefficients : tuple of float
        ``(a_s32, b_s32, c_s32)`` and ``(a_w33, b_w33, c_w33)``.
    shoulder_residual, wrist_residual : float
        Left sides of [000 eqs. 31, 33], or of their counterparts for theta = pi where those are nearer zero
        (never positive; zero at a singularity).
    tolerance : float
    """

    shoulder: tuple[float, ...]
    wrist: tuple[float, ...]
    shoulder_everywhere: bool
    wrist_everywhere: bool
    shoulder_coefficients: tuple[float, float, float]
    wrist_coefficients: tuple[float, float, float]
    shoulder_residual: float
    wrist_residual: float
    tolerance: float


def _singular_angles(a: float, b: float, constants: tuple[float, float],
                     tolerance: float) -> tuple[tuple[float, ...], bool, float]:
    """Roots of ``a s + b c + constant = 0`` where ``a^2 + b^2 = constant^2`` [000 eqs. 31-34], for each of the two
    constants (theta = 0 and theta = pi): the arm angles, sorted, whether every arm angle is a root, and the
    residual nearer zero."""
    angles: list[float] = []
    everywhere = False
    residuals = []
    for constant in constants:
        residual = a * a + b * b - constant * constant
        residuals.append(residual)
        if abs(residual) > tolerance:
            continue
        if abs(constant) <= tolerance:
            everywhere = True
        else:
            angles.append(float(np.arctan2(-a / constant, -b / constant)))
    return tuple(sorted(angles)), everywhere, max(residuals)


def _singular_from_coefficients(
    coefficients: ArmAngleCoefficients, tolerance: float = SINGULAR_TOLERANCE
) -> SingularArmAngles:
    """[000 eqs. 31-34] from precomputed coefficients of one pose, for theta = 0 and theta = pi."""
    s = coefficients.shoulder[:, 2, 1]  # 0R3[2,1] = -cos theta_2
    w = coefficients.wrist[:, 2, 2]  # 4R7[2,2] = cos theta_6
    shoulder = (float(s[0]), float(s[1]), float(s[2]))
    wrist = (float(w[0]), float(w[1]), float(w[2]))
    # [000 eqs. 31-32]: cos theta_2 = 1 and -1
    s_angles, s_all, s_res = _singular_angles(shoulder[0], shoulder[1], (shoulder[2] + 1.0, shoulder[2] - 1.0),
                                              tolerance)
    # [000 eqs. 33-34]: cos theta_6 = 1 and -1
    w_angles, w_all, w_res = _singular_angles(wrist[0], wrist[1], (wrist[2] - 1.0, wrist[2] + 1.0), tolerance)
    return SingularArmAngles(
        shoulder=s_angles,
        wrist=w_angles,
        shoulder_everywhere=s_all,
        wrist_everywhere=w_all,
        shoulder_coefficients=shoulder,
        wrist_coefficients=wrist,
        shoulder_residual=s_res,
        wrist_residual=w_res,
        tolerance=tolerance,
    )


def singular_arm_angles(
    arm: SerialChain | SRSGeometry,
    pose: ArrayLike,
    branch: str | Branch = "+++",
    tolerance: float = SINGULAR_TOLERANCE,
) -> SingularArmAngles:
    """Shoulder and wrist singular arm angles of one pose [000 eqs. 31-34]: theta_2 (theta_6) at 0 or pi.

    Only the elbow sign of ``branch`` matters (theta_2 = 0 or pi and theta_6 = 0 or pi are
    shared by both signs of theta_2 and theta_6).

    Raises
    ------
    ValueError
        For a malformed, batched or unreachable pose, or a negative tolerance.
    """
    geometry = as_geometry(arm)
    if not (np.isfinite(tolerance) and tolerance >= 0):
        raise RedkinError(f"tolerance must be a finite number >= 0, got {tolerance!r}")
    pose = np.asarray(pose, dtype=float)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must have shape (4, 4), got {pose.shape}")
    coefficients = coefficients_for(geometry, pose, geometry.table1_branch(branch).elbow)
    return _singular_from_coefficients(coefficients, tolerance)
