"""Rotations: elementary rotations, skew matrices, axis-angle and X-Y-Z fixed angles.

All functions are batched over leading axes and validate their input.
Axis-angle conversions lean on :class:`scipy.spatial.transform.Rotation`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial.transform import Rotation

from redkin._validation import as_float_array, check_finite, check_rotation, check_vectors

#: Below this value of ``cos(beta)`` the X-Y-Z fixed angles are in gimbal lock.
_GIMBAL_LOCK_TOLERANCE = 1e-9


def _elementary(angle: ArrayLike, axis: int) -> np.ndarray:
    theta = as_float_array(angle, "angle")
    check_finite(theta, "angle")
    c, s = np.cos(theta), np.sin(theta)
    out = np.zeros(theta.shape + (3, 3))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    out[..., axis, axis] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(angle: ArrayLike) -> np.ndarray:
    """Rotation about x by ``angle`` (radians), ``Rx`` of [001 eq. 4.3]; shape ``angle.shape + (3, 3)``."""
    return _elementary(angle, 0)


def rot_y(angle: ArrayLike) -> np.ndarray:
    """Rotation about y by ``angle`` (radians), ``Ry`` of [001 eq. 4.2]; shape ``angle.shape + (3, 3)``."""
    return _elementary(angle, 1)


def rot_z(angle: ArrayLike) -> np.ndarray:
    """Rotation about z by ``angle`` (radians), ``Rz`` of [001 eq. 4.1]; shape ``angle.shape + (3, 3)``."""
    return _elementary(angle, 2)


def skew(vector: ArrayLike) -> np.ndarray:
    """The cross-product matrix ``[v x]`` of vectors of shape ``(..., 3)``.

    ``skew(u) @ w == cross(u, w)``; used in [000 eq. 6].
    """
    v = check_vectors(vector, 3, "vector")
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def axis_angle_to_matrix(axis: ArrayLike, angle: ArrayLike) -> np.ndarray:
    """Rodrigues' formula ``I + sin(a)[u x] + (1 - cos(a))[u x]^2`` [000 eq. 6].

    Parameters
    ----------
    axis : array_like, shape (..., 3)
        Rotation axes; they are normalised, and must not be zero.
    angle : array_like, shape (...)
        Right-handed rotation angles in radians.

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)
    """
    u = check_vectors(axis, 3, "axis")
    theta = as_float_array(angle, "angle")
    check_finite(theta, "angle")
    norm = np.linalg.norm(u, axis=-1, keepdims=True)
    if np.any(norm < 1e-12):
        raise ValueError("axis must be a non-zero vector")
    rotvec = u / norm * theta[..., None]
    flat = Rotation.from_rotvec(np.array(rotvec.reshape(-1, 3))).as_matrix()
    return flat.reshape(rotvec.shape[:-1] + (3, 3))


def matrix_to_axis_angle(rotation: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Axis (unit, shape ``(..., 3)``) and angle in ``[0, pi]`` of rotation matrices.

    For the identity the axis is ``[0, 0, 1]`` and the angle 0.
    """
    r = check_rotation(rotation)
    flat = Rotation.from_matrix(r.reshape(-1, 3, 3)).as_rotvec()
    angle = np.linalg.norm(flat, axis=-1)
    axis = np.where(angle[:, None] > 1e-12, flat / np.maximum(angle, 1e-300)[:, None], [0.0, 0.0, 1.0])
    return axis.reshape(r.shape[:-2] + (3,)), angle.reshape(r.shape[:-2])


def xyz_fixed_to_matrix(angles: ArrayLike) -> np.ndarray:
    """X-Y-Z fixed angles ``(alpha, beta, gamma)`` to ``Rz(alpha) Ry(beta) Rx(gamma)``.

    This is [001 eq. 4.4]: rotate about the fixed x axis by gamma,
    then the fixed y axis by beta, then the fixed z axis by alpha.
    """
    a = check_vectors(angles, 3, "angles")
    return rot_z(a[..., 0]) @ rot_y(a[..., 1]) @ rot_x(a[..., 2])


def matrix_to_xyz_fixed(rotation: ArrayLike) -> np.ndarray:
    """Inverse of :func:`xyz_fixed_to_matrix`: angles ``(alpha, beta, gamma)``.

    ``beta`` lies in ``[-pi/2, pi/2]``.  At gimbal lock (``cos beta`` below
    :data:`_GIMBAL_LOCK_TOLERANCE`) only ``alpha -/+ gamma`` is defined; then
    ``alpha = 0`` is returned.
    """
    r = check_rotation(rotation)
    cos_beta = np.hypot(r[..., 0, 0], r[..., 1, 0])
    beta = np.arctan2(-r[..., 2, 0], cos_beta)
    regular = cos_beta > _GIMBAL_LOCK_TOLERANCE
    alpha = np.where(regular, np.arctan2(r[..., 1, 0], r[..., 0, 0]), 0.0)
    # In gimbal lock R = Ry(beta) Rx(gamma) with alpha = 0: gamma from the second column.
    gamma_locked = np.arctan2(-r[..., 1, 2], r[..., 1, 1])
    gamma = np.where(regular, np.arctan2(r[..., 2, 1], r[..., 2, 2]), gamma_locked)
    return np.stack([alpha, beta, gamma], axis=-1)
