"""The inverse of arm-angle IK: the arm angle and branch of a joint vector [000 eqs. 5-8]."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.srs._rotations import group_rotations
from redkin.srs._targets import as_geometry
from redkin.srs.branches import branch_of_theta
from redkin.srs.coefficients import arm_angle_coefficients
from redkin.srs.geometry import SRSGeometry


@dataclass(frozen=True)
class ArmAngleState:
    """Arm angle and branch of joint vectors.

    Attributes
    ----------
    psi : numpy.ndarray, shape (...)
        Arm angle in ``[-pi, pi]``.
    branch : numpy.ndarray of int, shape (..., 3)
        Signs of theta_2, theta_4 (of ``theta_4 - phi`` on an offset elbow), theta_6 (zero counts as +).
    """

    psi: np.ndarray
    branch: np.ndarray

    def branch_strings(self) -> np.ndarray:
        """Branches as strings such as ``"+-+"``."""
        chars = np.where(self.branch > 0, "+", "-")
        return np.apply_along_axis(lambda row: "".join(row), -1, chars) if chars.ndim > 1 else np.array("".join(chars))


def arm_angle_of(arm: SerialChain | SRSGeometry, q: ArrayLike) -> ArmAngleState:
    """Arm angle and branch of joint vectors ``q`` ``(..., 7)``.

    ``0R3 = R_psi 0R3o`` [000 eq. 8], so ``R_psi = 0R3 0R3o^T`` and ``psi`` is its
    angle about the shoulder-to-wrist axis: ``sin psi = u . vee(R_psi -
    R_psi^T) / 2``, ``cos psi = (trace R_psi - 1) / 2``.
    """
    geometry = as_geometry(arm)
    q = geometry.chain.check_q(q)
    theta = geometry.theta_of_q(q)
    branch = branch_of_theta(theta, geometry.elbow_equation.phase)  # Table 1 signs
    frame = arm_angle_coefficients(geometry, geometry.chain.fk(q), branch[..., 1])
    rotation = group_rotations(geometry, q)[0] @ np.swapaxes(frame.reference, -1, -2)
    u = frame.u_sw
    vee = np.stack(
        [rotation[..., 2, 1] - rotation[..., 1, 2], rotation[..., 0, 2] - rotation[..., 2, 0],
         rotation[..., 1, 0] - rotation[..., 0, 1]],
        axis=-1,
    )
    sin_psi = 0.5 * np.einsum("...i,...i->...", u, vee)
    cos_psi = 0.5 * (np.trace(rotation, axis1=-2, axis2=-1) - 1.0)
    return ArmAngleState(psi=np.arctan2(sin_psi, cos_psi), branch=branch * np.array(geometry.branch_senses))
