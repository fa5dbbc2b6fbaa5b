"""The arm-angle parametrisation of paper 000 section 3: [000 eqs. 4-19].

For a target pose (frame 7 in frame 0, Table 1 form) and the sign of the
elbow angle, :func:`arm_angle_coefficients` returns the constant coefficient
matrices of

* [000 eq. 12]: ``0R3(psi) = A_s sin psi + B_s cos psi + C_s``
* [000 eq. 16]: ``4R7(psi) = A_w sin psi + B_w cos psi + C_w``

with ``A_s = [u x] R3o``, ``B_s = -[u x]^2 R3o`` and ``C_s = u u^T R3o``
(the transcription prints ``C_s`` garbled; ``I + [u x]^2 = u u^T`` for a unit
``u``, so ``B_s = (I - u u^T) R3o``), and ``A_w = 3R4^T A_s^T 0R7`` etc.
(``4R7 = 3R4^T 0R3^T 0R7``), where ``u`` is the unit shoulder-to-wrist vector
and ``R3o = 0R3`` on the reference plane ``theta_3 = 0``.  ``psi`` is a
right-handed rotation of the arm plane about ``u`` (Rodrigues, [000 eq. 6]:
``R_psi = sin psi [u x] + cos psi (I - u u^T) + u u^T``).

[000 eqs. 12, 16] are linear in the three Rodrigues terms ``[u x]``,
``I - u u^T`` and ``u u^T``, so :func:`rotation_terms` computes them for
any weights of these terms: the identity gives the coefficient matrices,
``(sin psi, cos psi, 1)`` gives ``0R3`` and ``4R7`` at ``psi`` -- one
implementation for both.

Reference plane ([000 eq. 7] with ``theta_3 = 0``): at ``theta_3 = 0``,
``0R3 = Rz(theta_1) Rx(-pi/2) Rz(theta_2)`` and
``x_sw = [c1 w, s1 w, z]`` with ``(w, -z)`` = ``(v_x, v_y)`` turned by
``theta_2``, ``v = (d_ew s4, -(d_se + d_ew c4))`` (with an offset elbow
``v = (a_3 + a_4 c4 + d_ew s4, -d_se + a_4 s4 - d_ew c4)``).  We take
``theta_1o = atan2(y_sw, x_sw)`` (so ``w >= 0``) and, when the wrist lies
on the joint-1 axis, ``theta_1o = 0`` (end of section 3.3).

The joint angles are read from 14 entries of ``0R3`` and ``4R7``
(:data:`redkin.srs._ik_kernels.ENTRY_LAYOUT`, in the order used by
:mod:`redkin.srs.joints`).  The equations are computed by the compiled
kernels of :mod:`redkin.srs._ik_kernels`; this module gives their batched
results a named form.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin.chain import SerialChain
from redkin.srs import _ik_kernels
from redkin.srs._targets import as_geometry, as_poses, raise_for_status
from redkin.srs.geometry import SRSGeometry


@dataclass(frozen=True)
class ArmAngleCoefficients:
    """[000 eqs. 4-12, 16] for a batch of poses and elbow signs.

    Attributes
    ----------
    theta4 : numpy.ndarray, shape (...)
        Elbow angle [000 eq. 11], independent of psi.
    u_sw : numpy.ndarray, shape (..., 3)
        Unit shoulder-to-wrist vector.
    reference : numpy.ndarray, shape (..., 3, 3)
        ``0R3`` on the reference plane (``psi = 0``).
    elbow : numpy.ndarray, shape (..., 3, 3)
        ``3R4`` (depends on theta_4 only).
    shoulder : numpy.ndarray, shape (..., 3, 3, 3)
        ``(A_s, B_s, C_s)`` of [000 eq. 12].
    wrist : numpy.ndarray, shape (..., 3, 3, 3)
        ``(A_w, B_w, C_w)`` of [000 eq. 16].
    entries : numpy.ndarray, shape (..., 3, 14)
        The rows ``(a, b, c)`` of the entries of :data:`redkin.srs._ik_kernels.ENTRY_LAYOUT`:
        ``entry(psi) = a sin psi + b cos psi + c``.
    """

    theta4: np.ndarray
    u_sw: np.ndarray
    reference: np.ndarray
    elbow: np.ndarray
    shoulder: np.ndarray
    wrist: np.ndarray
    entries: np.ndarray


def coefficient_arrays(
    geometry, pose: np.ndarray, elbow_sign: np.ndarray | int
) -> tuple[ArmAngleCoefficients, np.ndarray, np.ndarray]:
    """[000 eqs. 4-12, 16] for poses of the chain's tool ``(..., 4, 4)`` (:func:`as_poses`), with the kernels'
    status per pose and ``|x_sw|``.

    ``elbow_sign`` (+1 or -1, the sign ``sigma`` of ``theta_4 - phi``)
    broadcasts against the batch shape.  A pose that fails its check or is
    out of reach is not an error here: its status says so (see
    :func:`raise_for_status`) and its coefficients are meaningless.
    """
    signs = np.asarray(elbow_sign, dtype=float)
    shape = np.broadcast_shapes(pose.shape[:-2], signs.shape)
    poses = kernel_array(pose, shape + (4, 4)).reshape(-1, 4, 4)
    count = poses.shape[0]
    signs = kernel_array(signs, shape).reshape(count)
    status, theta4, distance = np.empty(count, dtype=np.int64), np.empty(count), np.empty(count)
    u, reference, elbow = np.empty((count, 3)), np.empty((count, 3, 3)), np.empty((count, 3, 3))
    shoulder, wrist = np.empty((count, 3, 3, 3)), np.empty((count, 3, 3, 3))
    entries = np.empty((count, 3, 2 * _ik_kernels.GROUP))
    run_batch(_ik_kernels.coefficients, count, poses, signs, geometry.kernel_arm, geometry.kernel_ends, status, theta4,
              distance, u, reference, elbow, shoulder, wrist, entries)
    result = ArmAngleCoefficients(
        theta4=theta4.reshape(shape), u_sw=u.reshape(shape + (3,)), reference=reference.reshape(shape + (3, 3)),
        elbow=elbow.reshape(shape + (3, 3)), shoulder=shoulder.reshape(shape + (3, 3, 3)),
        wrist=wrist.reshape(shape + (3, 3, 3)), entries=entries.reshape(shape + entries.shape[1:]),
    )
    return result, status.reshape(shape), distance.reshape(shape)


def coefficients_for(
    arm: SerialChain | SRSGeometry, pose: ArrayLike, elbow_sign: int | np.ndarray
) -> ArmAngleCoefficients:
    """[000 eqs. 12, 16] coefficients of poses ``(..., 4, 4)`` of the chain's tool for an elbow sign (validated)."""
    return arm_angle_coefficients(as_geometry(arm), pose, elbow_sign)


def arm_angle_coefficients(geometry, pose: ArrayLike, elbow_sign: np.ndarray | int) -> ArmAngleCoefficients:
    """Coefficients of [000 eqs. 12, 16] for poses of the chain's tool ``(..., 4, 4)`` and elbow signs.

    See :func:`coefficient_arrays`.

    Raises
    ------
    RedkinError
        For a malformed pose.
    UnreachablePoseError
        For a wrist position out of reach ([000 eq. 11] has no solution).
    """
    pose = as_poses(pose)
    result, status, distance = coefficient_arrays(geometry, pose, elbow_sign)
    raise_for_status(geometry, pose, status, distance)
    return result
