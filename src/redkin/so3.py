"""Rotations: elementary rotations, skew matrices, axis-angle, X-Y-Z fixed angles, unit quaternions, and the
rotation nearest to a matrix.

All functions are batched over leading axes and validate their input.
Axis-angle conversions lean on :class:`scipy.spatial.transform.Rotation`, imported when first used (0.2 s that
``redkin fk``, which prints a quaternion, does not pay).
Quaternions are written scalar first, ``(w, x, y, z)`` (as MuJoCo, Eigen's constructor and pytransform3d
write them; ROS and scipy write ``(x, y, z, w)``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import (
    _check_matrices,
    as_float_array,
    check_finite,
    check_quaternion,
    check_rotation,
    check_vectors,
)
from redkin.errors import RedkinError

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
        raise RedkinError("axis must be a non-zero vector")
    rotvec = u / norm * theta[..., None]
    from scipy.spatial.transform import Rotation

    flat = Rotation.from_rotvec(np.array(rotvec.reshape(-1, 3))).as_matrix()
    return flat.reshape(rotvec.shape[:-1] + (3, 3))


def matrix_to_axis_angle(rotation: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Axis (unit, shape ``(..., 3)``) and angle in ``[0, pi]`` of rotation matrices.

    For the identity the axis is ``[0, 0, 1]`` and the angle 0.
    """
    r = check_rotation(rotation)
    from scipy.spatial.transform import Rotation

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


def quaternion_to_matrix(quaternion: ArrayLike) -> np.ndarray:
    """Rotation matrices of unit quaternions ``(w, x, y, z)``, scalar first.

    ``R = I + 2 w [v x] + 2 [v x]^2`` with ``v = (x, y, z)`` (Hamilton's convention: the quaternion of a turn by
    ``a`` about the unit axis ``u`` is ``(cos(a/2), sin(a/2) u)``); ``q`` and ``-q`` give the same rotation.

    Parameters
    ----------
    quaternion : array_like, shape (..., 4)
        Quaternions of norm 1 within :data:`redkin._validation.ROTATION_TOLERANCE` (1e-6); they are normalised
        before use.

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)

    Raises
    ------
    ValueError
        For a wrong shape, NaN or infinity, or a norm farther from 1 than the tolerance.
    """
    q = check_quaternion(quaternion)
    if q.size:
        q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, v = q[..., 0, None, None], q[..., 1:]
    cross = skew(v)
    return np.eye(3) + 2.0 * w * cross + 2.0 * cross @ cross


#: An entry of a unit quaternion at most this far from zero is rounding (a rotation's matrix holds its entries to
#: about 1e-16): it does not choose between ``q`` and ``-q`` (:func:`matrix_to_quaternion`).
_QUATERNION_ROUNDING = 1e-14


def matrix_to_quaternion(rotation: ArrayLike) -> np.ndarray:
    """Unit quaternions ``(w, x, y, z)`` of rotation matrices, the inverse of :func:`quaternion_to_matrix`.

    Each entry times the quaternion is a row of sums of ``R``'s entries (``4 w q = (1 + tr R, R32 - R23, R13 - R31,
    R21 - R12)`` and three more); the row of the largest entry is used, which keeps every digit where ``w`` is
    small (Shepperd's method).  Of the two quaternions ``q`` and ``-q`` of a rotation, the one whose first entry
    beyond rounding (:data:`_QUATERNION_ROUNDING`) is positive is returned: ``w > 0``, except for a half turn
    (``w = 0`` up to rounding), where ``x`` (or ``y``, then ``z``) is positive, whatever sign the rounding gave ``w``.

    Parameters
    ----------
    rotation : array_like, shape (..., 3, 3)
        Rotation matrices (orthonormal with determinant +1 within
        :data:`redkin._validation.ROTATION_TOLERANCE`).

    Returns
    -------
    numpy.ndarray, shape (..., 4)
    """
    r = check_rotation(rotation)
    m = r.reshape(-1, 3, 3)
    (r11, r12, r13), (r21, r22, r23), (r31, r32, r33) = np.moveaxis(m, (1, 2), (0, 1))
    rows = np.stack([  # rows[k] = 4 q_k q
        np.stack([1.0 + r11 + r22 + r33, r32 - r23, r13 - r31, r21 - r12], axis=-1),
        np.stack([r32 - r23, 1.0 + r11 - r22 - r33, r12 + r21, r13 + r31], axis=-1),
        np.stack([r13 - r31, r12 + r21, 1.0 - r11 + r22 - r33, r23 + r32], axis=-1),
        np.stack([r21 - r12, r13 + r31, r23 + r32, 1.0 - r11 - r22 + r33], axis=-1),
    ], axis=1)
    index = np.arange(len(m))
    row = rows[index, np.argmax(rows[:, [0, 1, 2, 3], [0, 1, 2, 3]], axis=1)]
    q = row / np.linalg.norm(row, axis=-1, keepdims=True)
    lead = q[index, np.argmax(np.abs(q) > _QUATERNION_ROUNDING, axis=1)]
    q *= np.where(lead < 0.0, -1.0, 1.0)[:, None]
    return q.reshape(r.shape[:-2] + (4,))


def nearest_rotation(matrix: ArrayLike) -> np.ndarray:
    """The rotation nearest to each 3x3 matrix in the Frobenius norm.

    With the singular value decomposition ``M = U S V^T`` it is ``U diag(1, 1, d) V^T``, ``d = det(U V^T)``: the
    orthogonal factor of the polar decomposition of ``M``, made proper where that factor is a reflection (then the
    result is far from ``M``: callers that want no reflection check ``det M > 0`` first).  For a matrix a little off
    a rotation (rounded entries) it moves each entry by about as much as ``M M^T`` is off the identity.

    Parameters
    ----------
    matrix : array_like, shape (..., 3, 3)
        Finite matrices.  Where the rank is below 2 the nearest rotation is not unique, and one of them is returned.

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)
        Orthonormal matrices with determinant +1.
    """
    m = _check_matrices(matrix, 3, 3, "matrix")
    u, _, vt = np.linalg.svd(m)
    u[..., :, 2] *= np.sign(np.linalg.det(u @ vt))[..., None]
    return u @ vt
