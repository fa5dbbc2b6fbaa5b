"""The arm-angle parametrisation of paper 000 section 3: eqs. 4-19.

For a target pose (frame 7 in frame 0, Table 1 form) and the sign of the
elbow angle, :func:`arm_angle_coefficients` returns the constant coefficient
matrices of

* eq. 12: ``0R3(psi) = A_s sin psi + B_s cos psi + C_s``
* eq. 16: ``4R7(psi) = A_w sin psi + B_w cos psi + C_w``

with ``A_s = [u x] R3o``, ``B_s = -[u x]^2 R3o`` and ``C_s = u u^T R3o``
(the transcription prints ``C_s`` garbled; ``I + [u x]^2 = u u^T`` for a unit
``u``, so ``B_s = (I - u u^T) R3o``), and ``A_w = 3R4^T A_s^T 0R7`` etc.
(``4R7 = 3R4^T 0R3^T 0R7``), where ``u`` is the unit shoulder-to-wrist vector
and ``R3o = 0R3`` on the reference plane ``theta_3 = 0``.  ``psi`` is a
right-handed rotation of the arm plane about ``u`` (Rodrigues, eq. 6:
``R_psi = sin psi [u x] + cos psi (I - u u^T) + u u^T``).

Eqs. 12 and 16 are linear in the three Rodrigues terms ``[u x]``,
``I - u u^T`` and ``u u^T``, so :func:`rotation_terms` computes them for
any weights of these terms: the identity gives the coefficient matrices,
``(sin psi, cos psi, 1)`` gives ``0R3`` and ``4R7`` at ``psi`` -- one
implementation for both.

Reference plane (eq. 7 with ``theta_3 = 0``): at ``theta_3 = 0``,
``0R3 = Rz(theta_1) Rx(-pi/2) Rz(theta_2)`` and
``x_sw = [c1 w, s1 w, z]`` with ``(w, -z)`` = ``(v_x, v_y)`` turned by
``theta_2``, ``v = (d_ew s4, -(d_se + d_ew c4))`` (with an offset elbow
``v = (a_3 + a_4 c4 + d_ew s4, -d_se + a_4 s4 - d_ew c4)``).  We take
``theta_1o = atan2(y_sw, x_sw)`` (so ``w >= 0``) and, when the wrist lies
on the joint-1 axis, ``theta_1o = 0`` (end of section 3.3).

The joint angles are read from 14 entries of ``0R3`` and ``4R7``
(:data:`ENTRY_LAYOUT`, in the order used by :mod:`redkin.srs.joints`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Relative distance of the wrist from the joint-1 axis below which the wrist counts as on it.
AXIS_TOLERANCE = 1e-12
#: Slack on ``|cos theta_4| <= 1`` (eq. 11) absorbed as rounding before a pose counts as unreachable.
REACH_TOLERANCE = 1e-9

#: The entries the joint angles are read from, per group (0R3 for the shoulder,
#: 4R7 for the wrist): ``(matrix, row, column, factor)`` for the slots
#: ``x, y, z, r0, r1, r2, t`` of :mod:`redkin.srs.joints`.  Shoulder:
#: ``x = -0R3[0,1] = c1 s2``, ``y = -0R3[1,1] = s1 s2``, ``z = -0R3[2,1] = c2``,
#: ``r = 0R3[:,0]`` (``r2 = -s2 c3``), ``t = 0R3[2,2] = s2 s3`` (section 3.3);
#: wrist: ``x = 4R7[0,2] = c5 s6``, ``y = 4R7[1,2] = s5 s6``, ``z = 4R7[2,2] = c6``,
#: ``r = 4R7[:,0]`` (``r2 = -s6 c7``), ``t = 4R7[2,1] = s6 s7``.
ENTRY_LAYOUT = (
    ("0R3", 0, 1, -1.0), ("0R3", 1, 1, -1.0), ("0R3", 2, 1, -1.0),
    ("0R3", 0, 0, 1.0), ("0R3", 1, 0, 1.0), ("0R3", 2, 0, 1.0), ("0R3", 2, 2, 1.0),
    ("4R7", 0, 2, 1.0), ("4R7", 1, 2, 1.0), ("4R7", 2, 2, 1.0),
    ("4R7", 0, 0, 1.0), ("4R7", 1, 0, 1.0), ("4R7", 2, 0, 1.0), ("4R7", 2, 1, 1.0),
)


def _selection_matrix() -> np.ndarray:
    """``(18, 14)``: flattened ``[0R3, 4R7]`` times it gives the signed entries of :data:`ENTRY_LAYOUT`."""
    selection = np.zeros((18, len(ENTRY_LAYOUT)))
    for column, (matrix, row, col, factor) in enumerate(ENTRY_LAYOUT):
        selection[(0 if matrix == "0R3" else 9) + 3 * row + col, column] = factor
    return selection


_SELECT = _selection_matrix()
# [u x] flattened is u @ _SKEW (a constant (3, 9) tensor)
_SKEW = np.zeros((3, 9))
_SKEW[2, 1], _SKEW[1, 2], _SKEW[2, 3], _SKEW[0, 5], _SKEW[1, 6], _SKEW[0, 7] = -1, 1, 1, -1, -1, 1
_EYE = np.eye(3)


def _frame_factors() -> np.ndarray:
    """``(3, 3, 9)``: ``(cos a, sin a, 1) @ F[k]`` is, flattened, ``Rz(a)`` (k = 0),
    ``Rx(-pi/2) Rz(a)`` (k = 1) and ``Rz(a) Rx(pi/2)`` (k = 2)."""
    rz = np.array([[[1.0, 0, 0], [0, 1, 0], [0, 0, 0]], [[0.0, -1, 0], [1, 0, 0], [0, 0, 0]], [[0.0, 0, 0], [0, 0, 0], [0, 0, 1]]])
    rx_minus = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])  # Rx(-pi/2)
    rx_plus = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # Rx(pi/2)
    return np.stack([rz, rx_minus @ rz, rz @ rx_plus]).reshape(3, 3, 9)


# 0R3o = Rz(theta_1o) [Rx(-pi/2) Rz(theta_2o)] and 3R4 = Rz(theta_4) Rx(pi/2), each linear in (cos, sin, 1)
_FRAME_FACTORS = _frame_factors()


@dataclass(frozen=True)
class ArmAngleFrame:
    """The psi-independent quantities of a batch of poses and elbow signs (eqs. 4-11).

    Attributes
    ----------
    theta4 : numpy.ndarray, shape (...)
        Elbow angle (eq. 11), independent of psi.
    u_sw : numpy.ndarray, shape (..., 3)
        Unit shoulder-to-wrist vector (batch axes broadcastable to those of ``theta4``).
    reference : numpy.ndarray, shape (..., 3, 3)
        ``0R3`` on the reference plane (``psi = 0``).
    elbow : numpy.ndarray, shape (..., 3, 3)
        ``3R4`` (depends on theta_4 only).
    rotation : numpy.ndarray, shape (..., 3, 3)
        Target ``0R7`` (batch axes broadcastable).
    """

    theta4: np.ndarray
    u_sw: np.ndarray
    reference: np.ndarray
    elbow: np.ndarray
    rotation: np.ndarray


@dataclass(frozen=True)
class ArmAngleCoefficients(ArmAngleFrame):
    """Eq. 12 and eq. 16 coefficients for a batch of poses and elbow signs.

    Attributes (besides those of :class:`ArmAngleFrame`)
    ----------------------------------------------------
    shoulder : numpy.ndarray, shape (..., 3, 3, 3)
        ``(A_s, B_s, C_s)`` of eq. 12.
    wrist : numpy.ndarray, shape (..., 3, 3, 3)
        ``(A_w, B_w, C_w)`` of eq. 16.
    entries : numpy.ndarray, shape (..., 3, 14)
        The rows ``(a, b, c)`` of the entries of :data:`ENTRY_LAYOUT`:
        ``entry(psi) = a sin psi + b cos psi + c``.
    """

    shoulder: np.ndarray
    wrist: np.ndarray
    entries: np.ndarray


def shoulder_to_wrist(geometry, position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """``x_sw = x_7 - l_bs - R_7 l_wt`` (eq. 4), batched."""
    x_sw = position - rotation[..., :, 2] * geometry.d_wt
    x_sw[..., 2] -= geometry.d_bs
    return x_sw


def elbow_cosine(geometry, x_sw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``|x_sw|^2`` and ``cos(theta_4 - phi) = (|x_sw|^2 - C) / R`` (eq. 11; with an offset elbow,
    :class:`redkin.srs.geometry.ElbowEquation`), batched.

    Without offsets ``C = d_se^2 + d_ew^2``, ``R = 2 d_se d_ew`` and ``phi = 0``: paper 000's eq. 11.
    """
    equation = geometry.elbow_equation
    squared = (x_sw[..., None, :] @ x_sw[..., :, None])[..., 0, 0]
    return squared, (squared - equation.mean) / equation.amplitude


def unreachable(cosine: np.ndarray) -> np.ndarray:
    """Which wrists are out of reach: ``|cos(theta_4 - phi)| > 1`` beyond :data:`REACH_TOLERANCE` (eq. 11)."""
    return np.abs(cosine) > 1.0 + REACH_TOLERANCE


def unreachable_message(geometry, x_sw: np.ndarray, cosine: np.ndarray) -> str | None:
    """A one-line message for the first pose whose wrist is out of reach, or ``None``."""
    bad = unreachable(cosine)
    if not bad.any():
        return None
    index = np.unravel_index(int(np.argmax(bad)), bad.shape)
    distance = float(np.linalg.norm(x_sw[index]))
    where = f" (pose {tuple(int(i) for i in index)}; {int(bad.sum())} unreachable)" if bad.ndim else ""
    mean, amplitude, _ = geometry.elbow_equation
    return (
        f"unreachable position: shoulder-wrist distance {distance:.6g} m must lie in "
        f"[{np.sqrt(max(mean - amplitude, 0.0)):.6g}, {np.sqrt(mean + amplitude):.6g}] m{where}"
    )


def arm_angle_frame(
    geometry, position: np.ndarray, rotation: np.ndarray, elbow_sign: np.ndarray | int
) -> ArmAngleFrame:
    """The psi-independent part of eqs. 4-11 for validated targets of frame 7 in frame 0.

    ``theta_4 = phi + sigma acos((|x_sw|^2 - C) / R)`` from eq. 11 (``phi =
    0`` without elbow offsets, :class:`redkin.srs.geometry.ElbowEquation`),
    wrapped to ``[-pi, pi]``; the reference plane ``theta_3 = 0`` (eq. 7,
    section 3.3): ``0R3o = Rz(theta_1o) Rx(-pi/2) Rz(theta_2o)`` with
    ``theta_1o = atan2(y_sw, x_sw)`` (0 on the joint-1 axis) and
    ``theta_2o = atan2(-z_sw, w) - atan2(v_y, v_x)``, ``(v_x, v_y, 0)`` the
    shoulder-to-wrist vector in frame 3; ``3R4 = Rz(theta_4) Rx(pi/2)`` (eq. 3
    with Table 1).  The three factors are built in one pass
    (:data:`_FRAME_FACTORS`).

    Parameters
    ----------
    geometry : SRSGeometry
    position : numpy.ndarray, shape (..., 3)
    rotation : numpy.ndarray, shape (..., 3, 3)
    elbow_sign : int or numpy.ndarray broadcastable to the batch shape
        Sign ``sigma`` of ``theta_4 - phi`` (+1 or -1).

    Raises
    ------
    ValueError
        If a wrist position is out of reach (eq. 11 has no solution).
    """
    x_sw = shoulder_to_wrist(geometry, position, rotation)
    squared, cosine = elbow_cosine(geometry, x_sw)  # eq. 11
    message = unreachable_message(geometry, x_sw, cosine)
    if message:
        raise ValueError(message)
    cosine = np.minimum(np.maximum(cosine, -1.0), 1.0)
    theta4 = np.arccos(cosine) * elbow_sign  # eq. 11, theta_4 - phi
    phase = geometry.elbow_equation.phase
    if phase:
        theta4 = np.mod(theta4 + (phase + np.pi), 2.0 * np.pi) - np.pi
    angles = np.empty(theta4.shape + (3,))  # theta_1o, theta_2o, theta_4
    angles[..., 2] = theta4
    cos4, sin4 = np.cos(theta4), np.sin(theta4)
    w = np.hypot(x_sw[..., 0], x_sw[..., 1])
    off_axis = w > AXIS_TOLERANCE * np.sqrt(geometry.elbow_equation.mean)
    angles[..., 0] = np.arctan2(x_sw[..., 1], x_sw[..., 0]) * off_axis
    # (v_x, v_y) = (a_3 + a_4 c4 + d_ew s4, -d_se + a_4 s4 - d_ew c4): the wrist in frame 3 (frame 2 at theta_2 = 0)
    d_se, d_ew, a3, a4 = geometry.d_se, geometry.d_ew, geometry.a3, geometry.a4
    angles[..., 1] = np.arctan2(-x_sw[..., 2], w * off_axis) - np.arctan2(
        a4 * sin4 - (d_se + d_ew * cos4), a3 + a4 * cos4 + d_ew * sin4)
    trig = np.empty(angles.shape + (1, 3))
    np.cos(angles, out=trig[..., 0, 0])
    np.sin(angles, out=trig[..., 0, 1])
    trig[..., 0, 2] = 1.0
    factors = (trig @ _FRAME_FACTORS).reshape(theta4.shape + (3, 3, 3))
    return ArmAngleFrame(
        theta4=theta4,
        u_sw=x_sw / np.sqrt(squared)[..., None],
        reference=factors[..., 0, :, :] @ factors[..., 1, :, :],
        elbow=factors[..., 2, :, :],
        rotation=rotation,
    )


def rodrigues_terms(u: np.ndarray) -> np.ndarray:
    """``([u x], I - u u^T, u u^T)`` of eq. 6, shape ``(..., 3, 3, 3)``."""
    terms = np.empty(u.shape[:-1] + (3, 3, 3))
    terms[..., 0, :, :] = (u @ _SKEW).reshape(u.shape[:-1] + (3, 3))
    np.multiply(u[..., :, None], u[..., None, :], out=terms[..., 2, :, :])
    np.subtract(_EYE, terms[..., 2, :, :], out=terms[..., 1, :, :])
    return terms


def rotation_terms(frame: ArmAngleFrame, weights: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``0R3`` (eq. 12) and ``4R7`` (eq. 16) for weights of the three Rodrigues terms.

    Parameters
    ----------
    frame : ArmAngleFrame
    weights : numpy.ndarray, shape (..., K, 3), optional
        Rows ``(w_sin, w_cos, w_1)`` giving ``R = w_sin [u x] + w_cos (I - u u^T)
        + w_1 u u^T``; ``(sin psi, cos psi, 1)`` is ``R_psi`` of eq. 6.  Default:
        the identity, i.e. the coefficient matrices ``(A, B, C)``.

    Returns
    -------
    shoulder, wrist : numpy.ndarray, shape (..., K, 3, 3)
        ``R R3o`` and ``3R4^T (R R3o)^T 0R7``.
    """
    terms = rodrigues_terms(frame.u_sw)
    if weights is not None:
        flat = weights @ terms.reshape(terms.shape[:-3] + (3, 9))
        terms = flat.reshape(flat.shape[:-1] + (3, 3))
    shoulder = terms @ frame.reference[..., None, :, :]  # eq. 12
    wrist = frame.elbow.swapaxes(-1, -2)[..., None, :, :] @ shoulder.swapaxes(-1, -2)
    wrist = wrist @ frame.rotation[..., None, :, :]  # eq. 16
    return shoulder, wrist


def entries_of(shoulder: np.ndarray, wrist: np.ndarray) -> np.ndarray:
    """The signed entries of :data:`ENTRY_LAYOUT` from ``0R3`` and ``4R7`` stacks ``(..., 3, 3)`` -> ``(..., 14)``."""
    flat_shoulder = shoulder.reshape(shoulder.shape[:-2] + (9,))
    flat_wrist = wrist.reshape(wrist.shape[:-2] + (9,))
    return flat_shoulder @ _SELECT[:9] + flat_wrist @ _SELECT[9:]


def entries_at(frame: ArmAngleFrame, psi: np.ndarray) -> np.ndarray:
    """The entries of :data:`ENTRY_LAYOUT` at arm angles ``psi`` (broadcast against the batch), ``(..., 14)``."""
    psi = np.asarray(psi, dtype=float)
    weights = np.stack([np.sin(psi), np.cos(psi), np.ones_like(psi)], axis=-1)[..., None, :]
    shoulder, wrist = rotation_terms(frame, weights)
    return entries_of(shoulder, wrist)[..., 0, :]


def arm_angle_coefficients(
    geometry, position: np.ndarray, rotation: np.ndarray, elbow_sign: np.ndarray | int
) -> ArmAngleCoefficients:
    """Coefficients of eqs. 12 and 16 for validated targets of frame 7 in frame 0.

    See :func:`arm_angle_frame` for the parameters.

    Raises
    ------
    ValueError
        If a wrist position is out of reach (eq. 11 has no solution).
    """
    frame = arm_angle_frame(geometry, position, rotation, elbow_sign)
    shoulder, wrist = rotation_terms(frame)
    return ArmAngleCoefficients(
        **vars(frame), shoulder=shoulder, wrist=wrist, entries=entries_of(shoulder, wrist)
    )
