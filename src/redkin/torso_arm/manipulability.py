"""Manipulability of the wrist position w.r.t. joints 1-5 (chapter 5, thesis 001).

``w = sqrt(det(J J^T))`` ([001 eq. 5.3], Yoshikawa) with ``J`` the 3 x 5 Jacobian
of the wrist position (origin of frame 6) w.r.t. theta_1..theta_5 [001 eq. 5.2].
:func:`_wrist_manipulability` evaluates it on the chain (the reference);
:func:`_wrist_jacobian_from_joints` builds the same Jacobian in closed form
from the joint axes, for fast maps.  Because ``w`` is a Gram determinant it
does not depend on the signs of the columns, so all four position branches
(which share the points ``S``, ``E``, ``W`` and the axis lines) have the same
``w``; and because theta_1 turns the whole arm rigidly about the torso axis,
``w`` does not depend on theta_1.

Dual-arm manipulability is not defined in the thesis.  Our definition
(:func:`stacked_dual_manipulability`): both wrists' positions stacked, w.r.t.
the shared theta_1 and both arms' joints 2-5, a 6 x 9 Jacobian, and
``w = sqrt(det(J J^T))``, in closed form from the two arms' 3 x 3 Gram
matrices (:func:`dual_one`).  Any function of the two 3 x 5 Jacobians can be
passed to the maps instead.
"""

from __future__ import annotations

from math import cos, sin, sqrt

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel, run_batch
from redkin.errors import RedkinError
from redkin.torso_arm._kernel_tools import add, cross, flat, scale, shoulder_point, sub, turn_y
from redkin.torso_arm.geometry import WRIST_FRAME, TorsoArm


def _wrist_manipulability(arm: TorsoArm, q: ArrayLike) -> np.ndarray:
    """[001 eq. 5.3] on the chain: ``sqrt(det(J J^T))`` of the wrist Jacobian [001 eq. 5.2] (joints 1-5), ``(...)``."""
    return arm.chain.manipulability(q, rows=[0, 1, 2], columns=range(5), frame=WRIST_FRAME)


@kernel
def wrist_jacobian_one(q5, L0, L1, lew, delta, out):
    """Closed-form 3 x 5 wrist-position Jacobian [001 eq. 5.2] of the right arm at joints 1-5 ``q5`` into ``out``.

    Columns ``z_i x (W - p_i)`` (see :func:`_wrist_jacobian_from_joints`).
    """
    t1, t2, t3, t4, t5 = q5[0], q5[1], q5[2], q5[3], q5[4]
    c2, s2, c3, s3, c4, s4 = cos(t2), sin(t2), cos(t3), sin(t3), cos(t4), sin(t4)
    x3 = turn_y(t1, (c3, -s3 * c2, -s2 * s3))
    u = turn_y(t1, (s3, c2 * c3, s2 * c3))  # upper arm, joint-4 axis
    z3 = turn_y(t1, (0.0, -s2, c2))  # joint-3 axis
    shoulder = shoulder_point(L0, t1)  # joint-2 axis z2 = S / L0
    elbow = add(shoulder, scale(u, L1))
    x4 = add(scale(x3, s4), scale(z3, c4))
    y4 = sub(scale(x3, c4), scale(z3, s4))  # joint-5 axis
    theta5 = t5 + delta
    wrist = add(elbow, scale(add(scale(x4, cos(theta5)), scale(u, sin(theta5))), lew))
    columns = (cross((0.0, 1.0, 0.0), wrist), cross(scale(shoulder, 1.0 / L0), wrist),
               cross(z3, sub(wrist, shoulder)), cross(u, sub(wrist, shoulder)), cross(y4, sub(wrist, elbow)))
    for j in range(5):
        out[0, j], out[1, j], out[2, j] = columns[j][0], columns[j][1], columns[j][2]


@kernel
def _gram3(jacobian, first):
    """Entries ``g00, g01, g02, g11, g12, g22`` of ``J J^T`` over the columns ``first..k-1`` of ``J`` (3, k)."""
    g00 = g01 = g02 = g11 = g12 = g22 = 0.0
    for j in range(first, jacobian.shape[1]):
        x, y, z = jacobian[0, j], jacobian[1, j], jacobian[2, j]
        g00 += x * x
        g01 += x * y
        g02 += x * z
        g11 += y * y
        g12 += y * z
        g22 += z * z
    return g00, g01, g02, g11, g12, g22


@kernel
def _det3(g):
    """Determinant of the symmetric 3 x 3 matrix with entries ``g00, g01, g02, g11, g12, g22``."""
    g00, g01, g02, g11, g12, g22 = g
    return g00 * (g11 * g22 - g12 * g12) - g01 * (g01 * g22 - g12 * g02) + g02 * (g01 * g12 - g11 * g02)


@kernel
def gram_one(jacobian):
    """``sqrt(max(det(J J^T), 0))`` of one Jacobian ``(3, k)`` [001 eq. 5.3], by the explicit 3 x 3 determinant."""
    return sqrt(max(_det3(_gram3(jacobian, np.int64(0))), 0.0))


@kernel
def _adjugate_form(g, a):
    """``a^T adj(G) a`` for the symmetric 3 x 3 ``G`` (entries as :func:`_gram3`) and a 3-vector ``a``."""
    g00, g01, g02, g11, g12, g22 = g
    a00, a11, a22 = g11 * g22 - g12 * g12, g00 * g22 - g02 * g02, g00 * g11 - g01 * g01
    a01, a02, a12 = g02 * g12 - g01 * g22, g01 * g12 - g02 * g11, g01 * g02 - g00 * g12
    x, y, z = a
    return a00 * x * x + a11 * y * y + a22 * z * z + 2.0 * (a01 * x * y + a02 * x * z + a12 * y * z)


@kernel
def dual_one(right, left):
    """The stacked dual-arm manipulability of two ``(3, 5)`` Jacobians w.r.t. (theta_1, q2..q5).

    ``J J^T = a a^T + diag(D_R, D_L)`` with ``a`` the stacked theta_1
    columns and ``D = B B^T`` of each arm's joint 2-5 columns, so by the
    matrix determinant lemma (adjugate form, exact for singular ``D``)
    ``det(J J^T) = d_R d_L + d_L a_R^T adj(D_R) a_R + d_R a_L^T adj(D_L) a_L``,
    ``d = det(D)``; returns its square root (0 where rounding makes it negative).
    """
    g_right, g_left = _gram3(right, np.int64(1)), _gram3(left, np.int64(1))
    d_right, d_left = _det3(g_right), _det3(g_left)
    a_right = (right[0, 0], right[1, 0], right[2, 0])
    a_left = (left[0, 0], left[1, 0], left[2, 0])
    det = d_right * d_left + d_left * _adjugate_form(g_right, a_right) + d_right * _adjugate_form(g_left, a_left)
    return sqrt(max(det, 0.0))


@kernel
def _wrist_jacobians(start, stop, q5, L0, L1, lew, delta, out):
    """:func:`wrist_jacobian_one` for each row of ``q5`` (N, 5) -> ``out`` (N, 3, 5)."""
    for i in range(start, stop):
        wrist_jacobian_one(q5[i], L0, L1, lew, delta, out[i])


@kernel
def _grams(start, stop, jacobian, out):
    """:func:`gram_one` for each of ``jacobian`` (N, 3, k) -> ``out`` (N,)."""
    for i in range(start, stop):
        out[i] = gram_one(jacobian[i])


@kernel
def _duals(start, stop, right, left, out):
    """:func:`dual_one` for each pair of ``right``, ``left`` (N, 3, 5) -> ``out`` (N,)."""
    for i in range(start, stop):
        out[i] = dual_one(right[i], left[i])


def _wrist_jacobian_from_joints(arm: TorsoArm, q5: np.ndarray) -> np.ndarray:
    """Closed-form 3 x 5 wrist-position Jacobian of the right arm ([001 eq. 5.2]; columns up to sign).

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
    shape, (q,) = flat((q5, 1))
    out = np.empty((q.shape[0], 3, 5))
    run_batch(_wrist_jacobians, q.shape[0], q, arm.L0, arm.L1, arm.forearm, arm.delta, out)
    return out.reshape(shape + (3, 5))


def gram_manipulability(jacobian: np.ndarray) -> np.ndarray:
    """``sqrt(max(det(J J^T), 0))`` [001 eq. 5.3] of Jacobians ``(..., 3, k)`` by the explicit 3 x 3 determinant."""
    shape, (j,) = flat((jacobian, 2))
    if j.shape[1] != 3:
        raise RedkinError(f"jacobian must have shape (..., 3, k), got {np.shape(jacobian)}")
    out = np.empty(j.shape[0])
    run_batch(_grams, j.shape[0], j, out)
    return out.reshape(shape)


def stacked_dual_manipulability(jacobian_right: np.ndarray, jacobian_left: np.ndarray) -> np.ndarray:
    """Dual-arm manipulability (our definition; the thesis gives none).

    ``J = [[a_R, B_R, 0], [a_L, 0, B_L]]`` (6 x 9) where ``a`` is the theta_1
    column (same world sense for both arms) and ``B`` the joint 2-5 columns;
    returns ``sqrt(det(J J^T))``, evaluated in closed form (:func:`dual_one`).

    Parameters
    ----------
    jacobian_right, jacobian_left : numpy.ndarray, shape (..., 3, 5)
        World wrist-position Jacobians w.r.t. (theta_1, q2..q5) of each arm.
    """
    shape, (right, left) = flat((jacobian_right, 2), (jacobian_left, 2))
    if right.shape[1:] != (3, 5) or left.shape[1:] != (3, 5):
        raise RedkinError(f"jacobians must have shape (..., 3, 5), got {np.shape(jacobian_right)} and "
                          f"{np.shape(jacobian_left)}")
    out = np.empty(right.shape[0])
    run_batch(_duals, right.shape[0], right, left, out)
    return out.reshape(shape)
