"""Manipulability of the wrist position w.r.t. joints 1-5 (chapter 5, thesis 001).

``w = sqrt(det(J J^T))`` (eq. 5.3, Yoshikawa) with ``J`` the 3 x 5 Jacobian
of the wrist position (origin of frame 6) w.r.t. theta_1..theta_5 (eq. 5.2).
:func:`wrist_manipulability` evaluates it on the chain (the reference);
:func:`wrist_jacobian_from_joints` builds the same Jacobian in closed form
from the joint axes, for fast maps.  Because ``w`` is a Gram determinant it
does not depend on the signs of the columns, so all four position branches
(which share the points ``S``, ``E``, ``W`` and the axis lines) have the same
``w``; and because theta_1 turns the whole arm rigidly about the torso axis,
``w`` does not depend on theta_1.

Dual-arm manipulability is not defined in the thesis.  Our definition
(:func:`stacked_dual_manipulability`): both wrists' positions stacked, w.r.t.
the shared theta_1 and both arms' joints 2-5, a 6 x 9 Jacobian, and
``w = sqrt(det(J J^T))``.  Any function of the two 3 x 5 Jacobians can be
passed instead.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.torso_arm.geometry import WRIST_FRAME, TorsoArm


def wrist_manipulability(arm: TorsoArm, q: ArrayLike) -> np.ndarray:
    """Eq. 5.3 on the chain: ``sqrt(det(J J^T))`` of the wrist position w.r.t. joints 1-5, shape ``(...)``."""
    return arm.chain.manipulability(q, rows=[0, 1, 2], columns=range(5), frame=WRIST_FRAME)


def _rotate_y(theta1: np.ndarray, v: np.ndarray) -> np.ndarray:
    c, s = np.cos(theta1), np.sin(theta1)
    return np.stack([c * v[..., 0] + s * v[..., 2], v[..., 1], -s * v[..., 0] + c * v[..., 2]], axis=-1)


def wrist_jacobian_from_joints(arm: TorsoArm, q5: np.ndarray) -> np.ndarray:
    """Closed-form 3 x 5 wrist-position Jacobian of the right arm (columns up to sign).

    Columns ``z_i x (W - p_i)``: torso axis ``y`` and joint-2 axis
    ``z2 = S / L0`` through the origin, joint-3 axis ``Ry(theta_1) (0, -s2, c2)``
    and joint-4 axis ``u`` (upper arm) through ``S``, joint-5 axis
    ``y4 = c4 x3 - s4 z3`` through ``E``, with ``x3 = Ry(theta_1)(c3, -s3 c2, -s2 s3)``
    (frame 3 of Table 2.1).  Column signs may differ from the chain's; ``w`` does not.

    Parameters
    ----------
    q5 : numpy.ndarray, shape (..., 5)
        Joints 1-5 of the right arm (trusted).

    Returns
    -------
    numpy.ndarray, shape (..., 3, 5)
    """
    t1, t2, t3, t4, t5 = np.moveaxis(q5, -1, 0)
    c2, s2, c3, s3, c4, s4 = np.cos(t2), np.sin(t2), np.cos(t3), np.sin(t3), np.cos(t4), np.sin(t4)
    zero = np.zeros_like(t2)
    x3 = _rotate_y(t1, np.stack([c3, -s3 * c2, -s2 * s3], axis=-1))
    u = _rotate_y(t1, np.stack([s3, c2 * c3, s2 * c3], axis=-1))
    z3 = _rotate_y(t1, np.stack([zero, -s2, c2], axis=-1))
    shoulder = arm.shoulder(t1)
    elbow = shoulder + arm.L1 * u
    x4 = s4[..., None] * x3 + c4[..., None] * z3
    y4 = c4[..., None] * x3 - s4[..., None] * z3
    theta5 = t5 + arm.delta
    wrist = elbow + arm.forearm * (np.cos(theta5)[..., None] * x4 + np.sin(theta5)[..., None] * u)
    y = np.zeros_like(wrist)
    y[..., 1] = 1.0
    columns = [
        np.cross(y, wrist),
        np.cross(shoulder / arm.L0, wrist),
        np.cross(z3, wrist - shoulder),
        np.cross(u, wrist - shoulder),
        np.cross(y4, wrist - elbow),
    ]
    return np.stack(columns, axis=-1)


def gram_manipulability(jacobian: np.ndarray) -> np.ndarray:
    """``sqrt(max(det(J J^T), 0))`` of Jacobians ``(..., 3, k)`` by the explicit 3 x 3 determinant."""
    g = jacobian @ np.swapaxes(jacobian, -1, -2)
    det = (
        g[..., 0, 0] * (g[..., 1, 1] * g[..., 2, 2] - g[..., 1, 2] * g[..., 2, 1])
        - g[..., 0, 1] * (g[..., 1, 0] * g[..., 2, 2] - g[..., 1, 2] * g[..., 2, 0])
        + g[..., 0, 2] * (g[..., 1, 0] * g[..., 2, 1] - g[..., 1, 1] * g[..., 2, 0])
    )
    return np.sqrt(np.maximum(det, 0.0))


def stacked_dual_manipulability(jacobian_right: np.ndarray, jacobian_left: np.ndarray) -> np.ndarray:
    """Dual-arm manipulability (our definition; the thesis gives none).

    ``J = [[a_R, B_R, 0], [a_L, 0, B_L]]`` (6 x 9) where ``a`` is the theta_1
    column (same world sense for both arms) and ``B`` the joint 2-5 columns;
    returns ``sqrt(det(J J^T))``.

    Parameters
    ----------
    jacobian_right, jacobian_left : numpy.ndarray, shape (..., 3, 5)
        World wrist-position Jacobians w.r.t. (theta_1, q2..q5) of each arm.
    """
    shape = np.broadcast_shapes(jacobian_right.shape[:-2], jacobian_left.shape[:-2])
    stacked = np.zeros(shape + (6, 9))
    stacked[..., :3, 0] = jacobian_right[..., 0]
    stacked[..., 3:, 0] = jacobian_left[..., 0]
    stacked[..., :3, 1:5] = jacobian_right[..., 1:]
    stacked[..., 3:, 5:9] = jacobian_left[..., 1:]
    g = stacked @ np.swapaxes(stacked, -1, -2)
    return np.sqrt(np.maximum(np.linalg.det(g), 0.0))
