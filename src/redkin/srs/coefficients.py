"""The arm-angle parametrisation of paper 000 section 3: eqs. 4-19.

For a target pose (frame 7 in frame 0, Table 1 form) and the sign of the
elbow angle, :func:`arm_angle_coefficients` returns the constant matrices of

* eq. 12: ``0R3(psi) = A_s sin psi + B_s cos psi + C_s``
* eq. 16: ``4R7(psi) = A_w sin psi + B_w cos psi + C_w``

with ``A_s = [u x] R3o``, ``B_s = -[u x]^2 R3o`` and ``C_s = u u^T R3o``
(the transcription prints ``C_s`` garbled; ``I + [u x]^2 = u u^T`` for a unit
``u``), ``A_w = 3R4^T A_s^T 0R7`` etc., where ``u`` is the unit
shoulder-to-wrist vector and ``R3o = 0R3`` on the reference plane
``theta_3 = 0``.  ``psi`` is a right-handed rotation of the arm plane about
``u`` (eq. 6).

Reference plane (eq. 7 with ``theta_3 = 0``): at ``theta_3 = 0``,
``0R3 = Rz(theta_1) Rx(-pi/2) Rz(theta_2)`` and
``x_sw = [c1 w, s1 w, z]`` with ``(w, -z)`` = ``(v_x, v_y)`` turned by
``theta_2``, ``v = (d_ew s4, -(d_se + d_ew c4))``.  We take
``theta_1o = atan2(y_sw, x_sw)`` (so ``w >= 0``) and, when the wrist lies
on the joint-1 axis, ``theta_1o = 0`` (end of section 3.3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Relative distance of the wrist from the joint-1 axis below which the wrist counts as on it.
AXIS_TOLERANCE = 1e-12
#: Slack on ``|cos theta_4| <= 1`` (eq. 11) absorbed as rounding before a pose counts as unreachable.
REACH_TOLERANCE = 1e-9

# rows of 0R3 / 4R7 whose entries give the joint angles (eqs. 13-15, 17-19):
# 0R3[0,1] = -c1 s2, 0R3[1,1] = -s1 s2, 0R3[2,1] = -c2, 0R3[2,0] = -s2 c3, 0R3[2,2] = s2 s3
# 4R7[0,2] = c5 s6, 4R7[1,2] = s5 s6, 4R7[2,2] = c6, 4R7[2,0] = -s6 c7, 4R7[2,1] = s6 s7
SHOULDER_ENTRIES = ((0, 1), (1, 1), (2, 1), (2, 0), (2, 2))
WRIST_ENTRIES = ((0, 2), (1, 2), (2, 2), (2, 0), (2, 1))


@dataclass(frozen=True)
class ArmAngleCoefficients:
    """Eq. 12 and eq. 16 coefficients for a batch of poses and elbow signs.

    Attributes
    ----------
    theta4 : numpy.ndarray, shape (...)
        Elbow angle (eq. 11), independent of psi.
    shoulder : numpy.ndarray, shape (..., 3, 3, 3)
        ``[A_s, B_s, C_s]`` stacked on axis -3 (eq. 12).
    wrist : numpy.ndarray, shape (..., 3, 3, 3)
        ``[A_w, B_w, C_w]`` stacked on axis -3 (eq. 16).
    entries : numpy.ndarray, shape (..., 10, 3)
        The ``(a, b, c)`` of the ten matrix entries the joint angles are read
        from: 0R3 at :data:`SHOULDER_ENTRIES`, then 4R7 at :data:`WRIST_ENTRIES`.
    u_sw : numpy.ndarray, shape (..., 3)
        Unit shoulder-to-wrist vector.
    reference : numpy.ndarray, shape (..., 3, 3)
        ``0R3`` on the reference plane (``psi = 0``).
    """

    theta4: np.ndarray
    shoulder: np.ndarray
    wrist: np.ndarray
    entries: np.ndarray
    u_sw: np.ndarray
    reference: np.ndarray


def shoulder_to_wrist(geometry, position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """``x_sw = x_7 - l_bs - R_7 l_wt`` (eq. 4), batched."""
    x_sw = position - rotation[..., :, 2] * geometry.d_wt
    x_sw = x_sw.copy()
    x_sw[..., 2] -= geometry.d_bs
    return x_sw


def elbow_cosine(geometry, x_sw: np.ndarray) -> np.ndarray:
    """``cos theta_4`` of eq. 11 (not clipped)."""
    squared = np.einsum("...i,...i->...", x_sw, x_sw)
    return (squared - geometry.d_se**2 - geometry.d_ew**2) / (2.0 * geometry.d_se * geometry.d_ew)


def unreachable_message(geometry, x_sw: np.ndarray, cos4: np.ndarray) -> str | None:
    """A one-line message for the first pose whose wrist is out of reach, or ``None``."""
    bad = np.abs(cos4) > 1.0 + REACH_TOLERANCE
    if not np.any(bad):
        return None
    index = np.unravel_index(int(np.argmax(bad)), bad.shape)
    distance = float(np.linalg.norm(x_sw[index]))
    where = f" (pose {tuple(int(i) for i in index)} of {int(bad.sum())} unreachable)" if bad.ndim else ""
    return (
        f"unreachable position: shoulder-wrist distance {distance:.6g} m must lie in "
        f"[{abs(geometry.d_se - geometry.d_ew):.6g}, {geometry.d_se + geometry.d_ew:.6g}] m{where}"
    )


def reference_rotation(geometry, x_sw: np.ndarray, theta4: np.ndarray) -> np.ndarray:
    """``0R3`` on the reference plane ``theta_3 = 0`` (eq. 7, section 3.3), batched."""
    s4, c4 = np.sin(theta4), np.cos(theta4)
    vx = geometry.d_ew * s4
    vy = -(geometry.d_se + geometry.d_ew * c4)
    w = np.hypot(x_sw[..., 0], x_sw[..., 1])
    on_axis = w <= AXIS_TOLERANCE * (geometry.d_se + geometry.d_ew)
    theta1 = np.where(on_axis, 0.0, np.arctan2(x_sw[..., 1], x_sw[..., 0]))
    w = np.where(on_axis, 0.0, w)
    theta2 = np.arctan2(-x_sw[..., 2], w) - np.arctan2(vy, vx)
    c1, s1, c2, s2 = np.cos(theta1), np.sin(theta1), np.cos(theta2), np.sin(theta2)
    # Rz(theta1) Rx(-pi/2) Rz(theta2)
    rot = np.empty(theta4.shape + (3, 3))
    rot[..., 0, 0] = c1 * c2
    rot[..., 0, 1] = -c1 * s2
    rot[..., 0, 2] = -s1
    rot[..., 1, 0] = s1 * c2
    rot[..., 1, 1] = -s1 * s2
    rot[..., 1, 2] = c1
    rot[..., 2, 0] = -s2
    rot[..., 2, 1] = -c2
    rot[..., 2, 2] = 0.0
    return rot


def elbow_rotation(theta4: np.ndarray) -> np.ndarray:
    """``3R4 = Rz(theta4) Rx(pi/2)`` (eq. 3 with Table 1), batched."""
    c4, s4 = np.cos(theta4), np.sin(theta4)
    rot = np.zeros(theta4.shape + (3, 3))
    rot[..., 0, 0] = c4
    rot[..., 0, 2] = s4
    rot[..., 1, 0] = s4
    rot[..., 1, 2] = -c4
    rot[..., 2, 1] = 1.0
    return rot


def arm_angle_coefficients(
    geometry, position: np.ndarray, rotation: np.ndarray, elbow_sign: np.ndarray | int
) -> ArmAngleCoefficients:
    """Coefficients of eqs. 12 and 16 for validated targets of frame 7 in frame 0.

    Parameters
    ----------
    geometry : SRSGeometry
    position : numpy.ndarray, shape (..., 3)
    rotation : numpy.ndarray, shape (..., 3, 3)
    elbow_sign : int or numpy.ndarray broadcastable to the batch shape
        Sign of theta_4 (+1 or -1).

    Raises
    ------
    ValueError
        If a wrist position is out of reach (eq. 11 has no solution).
    """
    x_sw = shoulder_to_wrist(geometry, position, rotation)
    cos4 = elbow_cosine(geometry, x_sw)
    message = unreachable_message(geometry, x_sw, cos4)
    if message:
        raise ValueError(message)
    shape = np.broadcast_shapes(cos4.shape, np.shape(elbow_sign))
    cos4 = np.broadcast_to(cos4, shape)
    x_sw = np.broadcast_to(x_sw, shape + (3,))
    rotation = np.broadcast_to(rotation, shape + (3, 3))
    theta4 = np.asarray(elbow_sign) * np.arccos(np.clip(cos4, -1.0, 1.0))  # eq. 11
    norm = np.linalg.norm(x_sw, axis=-1, keepdims=True)
    u = x_sw / norm
    reference = reference_rotation(geometry, x_sw, theta4)
    skew = np.zeros(shape + (3, 3))
    skew[..., 0, 1], skew[..., 0, 2] = -u[..., 2], u[..., 1]
    skew[..., 1, 0], skew[..., 1, 2] = u[..., 2], -u[..., 0]
    skew[..., 2, 0], skew[..., 2, 1] = -u[..., 1], u[..., 0]
    a_s = skew @ reference
    outer = u[..., :, None] * u[..., None, :]
    c_s = outer @ reference
    b_s = reference - c_s  # -[u x]^2 R3o = (I - u u^T) R3o
    shoulder = np.stack([a_s, b_s, c_s], axis=-3)
    r34_t = np.swapaxes(elbow_rotation(theta4), -1, -2)[..., None, :, :]
    wrist = r34_t @ np.swapaxes(shoulder, -1, -2) @ rotation[..., None, :, :]  # eq. 16
    rows_s = [i for i, _ in SHOULDER_ENTRIES]
    cols_s = [j for _, j in SHOULDER_ENTRIES]
    rows_w = [i for i, _ in WRIST_ENTRIES]
    cols_w = [j for _, j in WRIST_ENTRIES]
    entries = np.concatenate(
        [shoulder[..., rows_s, cols_s], wrist[..., rows_w, cols_w]], axis=-1
    )  # (..., 3, 10)
    return ArmAngleCoefficients(
        theta4=theta4,
        shoulder=shoulder,
        wrist=wrist,
        entries=np.swapaxes(entries, -1, -2),
        u_sw=u,
        reference=reference,
    )
