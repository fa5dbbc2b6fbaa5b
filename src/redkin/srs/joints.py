"""Joint angles as functions of the arm angle: eqs. 13-15 and 17-19 of paper 000.

Every joint but the elbow is of one of two types (eqs. 21 and 22):

* tangent type (joints 1, 3, 5, 7): ``theta = atan2(sigma N(psi), sigma D(psi))``
  with ``N, D = (a sin psi + b cos psi + c)``;
* cosine type (joints 2, 6): ``cos theta = a sin psi + b cos psi + c``,
  ``theta = sigma acos(...)``;

where ``sigma`` is the branch sign of theta_2 (shoulder joints) or theta_6
(wrist joints).  For accuracy near ``theta_2 = 0`` the cosine-type joints
are evaluated as ``atan2(sigma hypot(N_1, D_1), cos theta)`` with the
numerator and denominator of the neighbouring tangent-type joint (their
squares sum to ``sin^2 theta``), which is the same function as
``sigma acos`` without its loss of digits near 0 and pi.

Entry indices refer to :attr:`ArmAngleCoefficients.entries`.
"""

from __future__ import annotations

import numpy as np

#: Joint numbers (1-based) whose angle depends on psi, in column order of the arrays below.
PSI_JOINTS = (1, 2, 3, 5, 6, 7)
# For each column of PSI_JOINTS: (numerator entry, factor, denominator entry, factor).
# Cosine-type columns store the cos entry as "denominator" and the
# neighbouring tangent joint's entries, squared and summed, give sin.
_NUM = np.array([1, 1, 4, 6, 6, 9])
_NUM_F = np.array([-1.0, -1.0, 1.0, 1.0, 1.0, 1.0])
_DEN = np.array([0, 2, 3, 5, 7, 8])
_DEN_F = np.array([-1.0, -1.0, -1.0, 1.0, 1.0, -1.0])
_IS_COS = np.array([False, True, False, False, True, False])


def entry_values(entries: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """The ten matrix entries at arm angles ``psi``: ``a sin psi + b cos psi + c``.

    ``entries`` has shape ``(..., 10, 3)``; ``psi`` broadcasts against ``(...)``
    (a trailing axis on ``psi`` evaluates several arm angles: pass
    ``entries[..., None, :, :]``).
    """
    s, c = np.sin(psi), np.cos(psi)
    return entries[..., 0] * s[..., None] + entries[..., 1] * c[..., None] + entries[..., 2]


def psi_joint_angles(values: np.ndarray, shoulder_sign: np.ndarray, wrist_sign: np.ndarray) -> np.ndarray:
    """Joints 1, 2, 3, 5, 6, 7 from the entry values ``(..., 10)`` and branch signs (eqs. 13-19).

    Returns shape ``(..., 6)`` in the order of :data:`PSI_JOINTS`.
    """
    sigma2 = np.asarray(shoulder_sign, dtype=float)
    sigma6 = np.asarray(wrist_sign, dtype=float)
    shape = np.broadcast_shapes(values.shape[:-1], sigma2.shape, sigma6.shape)
    values = np.broadcast_to(values, shape + values.shape[-1:])
    sigma = np.empty(shape + (6,))
    sigma[..., :3] = sigma2[..., None]
    sigma[..., 3:] = sigma6[..., None]
    num = values[..., _NUM] * _NUM_F
    den = values[..., _DEN] * _DEN_F
    num[..., _IS_COS] = np.hypot(values[..., [0, 5]], values[..., [1, 6]])  # |sin theta_2|, |sin theta_6|
    den[..., ~_IS_COS] *= sigma[..., ~_IS_COS]
    return np.arctan2(sigma * num, den)


def assemble_theta(theta4: np.ndarray, psi_joints: np.ndarray) -> np.ndarray:
    """The 7 DH angles from theta_4 ``(...)`` and the six psi-dependent joints ``(..., 6)``."""
    theta4 = np.broadcast_to(theta4, psi_joints.shape[:-1])
    return np.concatenate([psi_joints[..., :3], theta4[..., None], psi_joints[..., 3:]], axis=-1)


def limit_equation(entries: np.ndarray, column: int, limit: np.ndarray) -> np.ndarray:
    """Coefficients ``(p, q, r)`` of ``p sin psi + q cos psi + r = 0``, solved by theta(psi) = limit.

    Tangent type (eq. 21): ``N cos L - D sin L = 0`` (both ``theta = L`` and
    ``theta = L + pi``; the second kind of root only adds a harmless cut).
    Cosine type (eq. 22): ``a s + b c + c - cos L = 0`` (also catches
    ``theta = -L``, likewise harmless).

    ``entries`` ``(..., 10, 3)``, ``limit`` broadcastable to ``(...)``; returns ``(..., 3)``.
    """
    limit = np.asarray(limit, dtype=float)[..., None]
    if _IS_COS[column]:
        coefficient = entries[..., _DEN[column], :] * _DEN_F[column]
        offset = np.zeros(3)
        offset[2] = 1.0
        return coefficient - np.cos(limit) * offset
    numerator = entries[..., _NUM[column], :] * _NUM_F[column]
    denominator = entries[..., _DEN[column], :] * _DEN_F[column]
    return numerator * np.cos(limit) - denominator * np.sin(limit)


def sinusoid_roots(coefficients: np.ndarray, tolerance: float = 1e-12) -> np.ndarray:
    """Roots in ``[-pi, pi)`` of ``p sin psi + q cos psi + r = 0``; shape ``(..., 2)``, NaN where none.

    With ``rho = hypot(p, q)`` and ``phi = atan2(p, q)``, ``p s + q c = rho
    cos(psi - phi)``, so ``psi = phi +- acos(-r / rho)``.  Near tangency
    (``|r| <= rho (1 + tolerance)``) the double root is returned.
    """
    p, q, r = coefficients[..., 0], coefficients[..., 1], coefficients[..., 2]
    rho = np.hypot(p, q)
    scale = np.maximum(rho, np.abs(r))
    has = (rho > tolerance * np.maximum(scale, 1.0)) & (np.abs(r) <= rho * (1.0 + tolerance))
    with np.errstate(invalid="ignore", divide="ignore"):
        half = np.arccos(np.clip(-r / rho, -1.0, 1.0))
    phi = np.arctan2(p, q)
    roots = np.stack([phi - half, phi + half], axis=-1)
    roots = np.mod(roots + np.pi, 2.0 * np.pi) - np.pi
    return np.where(has[..., None], roots, np.nan)
