"""Joint angles as functions of the arm angle: eqs. 13-15 and 17-19 of paper 000.

Every joint but the elbow is of one of two types (eqs. 21 and 22):

* tangent type (joints 1, 3, 5, 7): ``theta = atan2(sigma N(psi), sigma D(psi))``
  with ``N, D = (a sin psi + b cos psi + c)``;
* cosine type (joints 2, 6): ``cos theta = a sin psi + b cos psi + c``,
  ``theta = sigma acos(...)``;

where ``sigma`` is the branch sign of theta_2 (shoulder joints) or theta_6
(wrist joints).  ``sigma = -1`` turns a tangent-type angle by ``pi`` and
negates a cosine-type one, so the angles are computed once for
``sigma = +1`` (:func:`positive_branch_angles`) and then signed
(:func:`apply_branch_signs`).  For accuracy near ``theta_2 = 0`` the
cosine-type joints are evaluated as ``atan2(hypot(N_1, D_1), cos theta)``
with the numerator and denominator of the neighbouring tangent-type joint
(their squares sum to ``sin^2 theta``): the same function as ``acos``
without its loss of digits near 0 and pi.  Likewise theta_3 (theta_7) is
read from the rotation left after joints 1-2 (5-6): ``0R3 = Rz(theta_1)
Ry(theta_2) Rz(theta_3) Rx(-pi/2)``, so ``theta_3 = atan2(p_2 . r_1, p_1 .
r_1)`` with ``p_k`` the columns of ``Rz(theta_1) Ry(theta_2)`` and ``r_1``
the first column of 0R3.  This equals eq. 15 wherever eq. 15 is defined and
stays exact at the singular arm angle (theta_2 = 0), where eq. 15 is 0/0
and only theta_1 + theta_3 is determined.

Entry indices refer to :attr:`ArmAngleCoefficients.entries`:
0 = 0R3[0,1] = -c1 s2, 1 = 0R3[1,1] = -s1 s2, 2 = 0R3[2,1] = -c2,
3 = 0R3[2,0] = -s2 c3, 4 = 0R3[2,2] = s2 s3, 5 = 4R7[0,2] = c5 s6,
6 = 4R7[1,2] = s5 s6, 7 = 4R7[2,2] = c6, 8 = 4R7[2,0] = -s6 c7,
9 = 4R7[2,1] = s6 s7, 10 = 0R3[0,0], 11 = 0R3[1,0], 12 = 4R7[0,0],
13 = 4R7[1,0].
"""

from __future__ import annotations

import numpy as np

#: Joint numbers (1-based) whose angle depends on psi, in column order of the arrays below.
PSI_JOINTS = (1, 2, 3, 5, 6, 7)
# Per column of PSI_JOINTS: numerator entry/factor and denominator entry/factor
# (eqs. 13, 15, 17, 19).  Cosine-type columns (eqs. 14, 18) keep cos theta as
# the "denominator"; their numerator (|sin theta|) is the hypot of two entries.
_NUM = np.array([1, 1, 4, 6, 6, 9])
_NUM_F = np.array([-1.0, -1.0, 1.0, 1.0, 1.0, 1.0])
_DEN = np.array([0, 2, 3, 5, 7, 8])
_DEN_F = np.array([-1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
IS_COSINE = np.array([False, True, False, False, True, False])
_TANGENT_COLUMNS = np.flatnonzero(~IS_COSINE)


def entry_values(entries: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """The matrix entries at arm angles ``psi``: ``a sin psi + b cos psi + c``.

    ``entries`` has shape ``(..., 14, 3)``; ``psi`` broadcasts against ``(...)``.
    """
    psi = np.asarray(psi, dtype=float)[..., None]
    return entries[..., 0] * np.sin(psi) + entries[..., 1] * np.cos(psi) + entries[..., 2]


def _third_angle(first: np.ndarray, second: np.ndarray, column: np.ndarray) -> np.ndarray:
    """theta_3 (or theta_7) from theta_1, theta_2 (theta_5, theta_6) and the first column of 0R3 (4R7)."""
    c1, s1, c2, s2 = np.cos(first), np.sin(first), np.cos(second), np.sin(second)
    along_p1 = c1 * c2 * column[0] + s1 * c2 * column[1] - s2 * column[2]
    along_p2 = -s1 * column[0] + c1 * column[1]
    return np.arctan2(along_p2, along_p1)


def positive_branch_angles(values: np.ndarray) -> np.ndarray:
    """Joints 1, 2, 3, 5, 6, 7 for ``sigma_2 = sigma_6 = +1`` from the entry values ``(..., 14)``."""
    theta1 = np.arctan2(-values[..., 1], -values[..., 0])  # eq. 13
    theta2 = np.arctan2(np.hypot(values[..., 0], values[..., 1]), -values[..., 2])  # eq. 14
    theta3 = _third_angle(theta1, theta2, (values[..., 10], values[..., 11], values[..., 3]))  # eq. 15
    theta5 = np.arctan2(values[..., 6], values[..., 5])  # eq. 17
    theta6 = np.arctan2(np.hypot(values[..., 5], values[..., 6]), values[..., 7])  # eq. 18
    theta7 = _third_angle(theta5, theta6, (values[..., 12], values[..., 13], values[..., 8]))  # eq. 19
    return np.stack([theta1, theta2, theta3, theta5, theta6, theta7], axis=-1)


def apply_branch_signs(angles: np.ndarray, shoulder_sign, wrist_sign) -> np.ndarray:
    """Angles of the branch ``(sigma_2, sigma_6)`` from those of ``(+1, +1)`` (eqs. 13-19).

    A tangent-type angle with ``sigma = -1`` is ``atan2(-N, -D)``, i.e. turned
    by ``pi``; a cosine-type one is negated.  Signs broadcast against ``(...)``.
    """
    sigma2 = np.asarray(shoulder_sign, dtype=float)
    sigma6 = np.asarray(wrist_sign, dtype=float)
    shape = np.broadcast_shapes(angles.shape[:-1], sigma2.shape, sigma6.shape)
    negative = np.empty(shape + (6,), dtype=bool)
    negative[..., :3] = (sigma2 < 0)[..., None]
    negative[..., 3:] = (sigma6 < 0)[..., None]
    turned = np.where(angles > 0.0, angles - np.pi, angles + np.pi)
    flipped = np.where(IS_COSINE, -angles, turned)
    return np.where(negative, flipped, angles)


def psi_joint_angles(values: np.ndarray, shoulder_sign, wrist_sign) -> np.ndarray:
    """Joints 1, 2, 3, 5, 6, 7, shape ``(..., 6)``, from entry values and branch signs (eqs. 13-19)."""
    return apply_branch_signs(positive_branch_angles(values), shoulder_sign, wrist_sign)


def assemble_theta(theta4: np.ndarray, psi_joints: np.ndarray) -> np.ndarray:
    """The 7 DH angles from theta_4 ``(...)`` and the six psi-dependent joints ``(..., 6)``."""
    theta4 = np.broadcast_to(theta4, psi_joints.shape[:-1])
    return np.concatenate([psi_joints[..., :3], theta4[..., None], psi_joints[..., 3:]], axis=-1)


def limit_equations(entries: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Coefficients ``(p, q, r)`` of ``p sin psi + q cos psi + r = 0`` solved where theta(psi) is a limit.

    Tangent type (eq. 21 with ``theta = L``): ``N cos L - D sin L = 0`` (also
    true where ``theta = L + pi``, which only adds a harmless cut).  Cosine
    type (eq. 22): ``a s + b c + c - cos L = 0`` (also true where
    ``theta = -L``, likewise harmless).

    ``entries`` ``(..., 14, 3)``; ``lower``/``upper`` ``(6,)`` DH limits of the
    columns of :data:`PSI_JOINTS`.  Returns ``(..., 6, 2, 3)`` (lower, upper).
    """
    limits = np.stack([lower, upper], axis=-1)  # (6, 2)
    cos_l, sin_l = np.cos(limits)[..., None], np.sin(limits)[..., None]
    num = (entries[..., _NUM, :] * _NUM_F[:, None])[..., None, :]  # (..., 6, 1, 3)
    den = (entries[..., _DEN, :] * _DEN_F[:, None])[..., None, :]
    tangent = num * cos_l - den * sin_l
    e3 = np.array([0.0, 0.0, 1.0])
    cosine = den - cos_l * e3
    return np.where(IS_COSINE[:, None, None], cosine, tangent)


def sinusoid_roots(coefficients: np.ndarray, tolerance: float = 1e-12) -> np.ndarray:
    """Roots in ``[-pi, pi)`` of ``p sin psi + q cos psi + r = 0``; shape ``(..., 2)``, NaN where none.

    With ``rho = hypot(p, q)`` and ``phi = atan2(p, q)``, ``p s + q c = rho
    cos(psi - phi)``, so ``psi = phi +- acos(-r / rho)``.  Near tangency
    (``|r| <= rho (1 + tolerance)``) the double root is returned.
    """
    p, q, r = coefficients[..., 0], coefficients[..., 1], coefficients[..., 2]
    rho = np.hypot(p, q)
    has = (rho > tolerance * np.maximum(np.abs(r), 1.0)) & (np.abs(r) <= rho * (1.0 + tolerance))
    with np.errstate(invalid="ignore", divide="ignore"):
        half = np.arccos(np.clip(-r / rho, -1.0, 1.0))
    phi = np.arctan2(p, q)[..., None]
    roots = phi + np.stack([-half, half], axis=-1)
    roots = np.mod(roots + np.pi, 2.0 * np.pi) - np.pi
    return np.where(has[..., None], roots, np.nan)
