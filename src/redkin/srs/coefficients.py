"""The arm-angle parametrisation of paper 000 section 3: eqs. 4-19.

For a target pose (frame 7 in frame 0, Table 1 form) and the sign of the
elbow angle, :func:`arm_angle_coefficients` returns the constant coefficients of

* eq. 12: ``0R3(psi) = A_s sin psi + B_s cos psi + C_s``
* eq. 16: ``4R7(psi) = A_w sin psi + B_w cos psi + C_w``

with ``A_s = [u x] R3o``, ``B_s = -[u x]^2 R3o`` and ``C_s = u u^T R3o``
(the transcription prints ``C_s`` garbled; ``I + [u x]^2 = u u^T`` for a unit
``u``), ``A_w = 3R4^T A_s^T 0R7`` etc., where ``u`` is the unit
shoulder-to-wrist vector and ``R3o = 0R3`` on the reference plane
``theta_3 = 0``.  ``psi`` is a right-handed rotation of the arm plane about
``u`` (eq. 6).

Only the entries that the joint angles are read from are needed, and each
is a bilinear form ``x^T R_psi y`` with Rodrigues' ``R_psi`` (eq. 6), so
(:func:`rodrigues_coefficients`)
``x^T R_psi y = sin psi x.(u x y) + cos psi (x.y - (x.u)(u.y)) + (x.u)(u.y)``:
an entry ``(i, j)`` of ``0R3`` has ``x = e_i`` and ``y = R3o e_j``; an entry
``(i, j)`` of ``4R7 = 3R4^T 0R3^T 0R7`` has ``x = 0R7 e_j`` and
``y = R3o 3R4 e_i``.  This is eqs. 12 and 16 evaluated entry by entry,
without forming the 3x3x3 stacks.

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
# plus 0R3[0,0], 0R3[1,0] and 4R7[0,0], 4R7[1,0], which complete the first
# columns used to read theta_3 and theta_7 robustly (see redkin.srs.joints)
SHOULDER_ENTRIES = ((0, 1), (1, 1), (2, 1), (2, 0), (2, 2))
WRIST_ENTRIES = ((0, 2), (1, 2), (2, 2), (2, 0), (2, 1))
SHOULDER_EXTRA = ((0, 0), (1, 0))
WRIST_EXTRA = ((0, 0), (1, 0))


@dataclass(frozen=True)
class ArmAngleCoefficients:
    """Eq. 12 and eq. 16 coefficients for a batch of poses and elbow signs.

    Attributes
    ----------
    theta4 : numpy.ndarray, shape (...)
        Elbow angle (eq. 11), independent of psi.
    entries : numpy.ndarray, shape (..., 14, 3)
        ``(a, b, c)`` with ``entry = a sin psi + b cos psi + c`` of the
        matrix entries the joint angles are read from: 0R3 at
        :data:`SHOULDER_ENTRIES` (``a_s32`` is ``entries[..., 2, 0]``), 4R7 at
        :data:`WRIST_ENTRIES` (``a_w33`` is ``entries[..., 7, 0]``), then 0R3
        at :data:`SHOULDER_EXTRA` and 4R7 at :data:`WRIST_EXTRA`.
    u_sw : numpy.ndarray, shape (..., 3)
        Unit shoulder-to-wrist vector.
    reference : numpy.ndarray, shape (..., 3, 3)
        ``0R3`` on the reference plane (``psi = 0``).
    elbow : numpy.ndarray, shape (..., 3, 3)
        ``3R4`` (depends on theta_4 only).
    rotation : numpy.ndarray, shape (..., 3, 3)
        Target ``0R7``.
    """

    theta4: np.ndarray
    entries: np.ndarray
    u_sw: np.ndarray
    reference: np.ndarray
    elbow: np.ndarray
    rotation: np.ndarray

    def expand(self) -> "ArmAngleCoefficients":
        """The same coefficients with a new batch axis of length 1 at the end."""
        return ArmAngleCoefficients(
            theta4=self.theta4[..., None],
            entries=self.entries[..., None, :, :],
            u_sw=self.u_sw[..., None, :],
            reference=self.reference[..., None, :, :],
            elbow=self.elbow[..., None, :, :],
            rotation=self.rotation[..., None, :, :],
        )


def rodrigues_coefficients(x: np.ndarray, y: np.ndarray, u: np.ndarray) -> np.ndarray:
    """``(a, b, c)`` with ``x^T R_psi y = a sin psi + b cos psi + c`` (eq. 6), shape ``(..., 3)``.

    ``x``, ``y`` and ``u`` (unit axis) have shape ``(..., 3)`` and broadcast.
    """
    xu = np.einsum("...i,...i->...", x, u)
    uy = np.einsum("...i,...i->...", u, y)
    a = np.einsum("...i,...i->...", x, np.cross(u, y))
    c = xu * uy
    b = np.einsum("...i,...i->...", x, y) - c
    return np.stack([a, b, c], axis=-1)


def shoulder_to_wrist(geometry, position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """``x_sw = x_7 - l_bs - R_7 l_wt`` (eq. 4), batched."""
    x_sw = position - rotation[..., :, 2] * geometry.d_wt
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
    where = f" (pose {tuple(int(i) for i in index)}; {int(bad.sum())} unreachable)" if bad.ndim else ""
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


_S_ROWS = np.array([i for i, _ in SHOULDER_ENTRIES + SHOULDER_EXTRA])
_S_COLS = np.array([j for _, j in SHOULDER_ENTRIES + SHOULDER_EXTRA])
_W_ROWS = np.array([i for i, _ in WRIST_ENTRIES + WRIST_EXTRA])
_W_COLS = np.array([j for _, j in WRIST_ENTRIES + WRIST_EXTRA])
# order of the entries array: 5 shoulder, 5 wrist, 2 shoulder extra, 2 wrist extra
_ORDER = np.r_[0:5, 7:12, 5:7, 12:14]


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
    theta4 = np.asarray(elbow_sign) * np.arccos(np.clip(cos4, -1.0, 1.0))  # eq. 11
    shape = theta4.shape
    x_sw = np.broadcast_to(x_sw, shape + (3,))
    rotation = np.broadcast_to(rotation, shape + (3, 3))
    u = x_sw / np.sqrt(np.einsum("...i,...i->...", x_sw, x_sw))[..., None]
    reference = reference_rotation(geometry, x_sw, theta4)
    elbow = elbow_rotation(theta4)
    basis = np.eye(3)
    # eq. 12 entry (i, j): e_i^T R_psi (R3o e_j); eq. 16 entry (i, j): (0R7 e_j)^T R_psi (R3o 3R4 e_i)
    x = np.concatenate(
        [np.broadcast_to(basis[_S_ROWS], shape + (7, 3)), np.swapaxes(rotation, -1, -2)[..., _W_COLS, :]], axis=-2
    )
    wrist_y = np.swapaxes(reference @ elbow, -1, -2)[..., _W_ROWS, :]
    y = np.concatenate([np.swapaxes(reference, -1, -2)[..., _S_COLS, :], wrist_y], axis=-2)
    entries = rodrigues_coefficients(x[..., _ORDER, :], y[..., _ORDER, :], u[..., None, :])
    return ArmAngleCoefficients(
        theta4=theta4, entries=entries, u_sw=u, reference=reference, elbow=elbow, rotation=rotation
    )
