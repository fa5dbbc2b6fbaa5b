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
(:func:`apply_branch_signs`).

The shoulder (joints 1-3, read from ``0R3``) and the wrist (joints 5-7,
read from ``4R7``) have the same structure, so both are computed by the
same array operations on a group axis of length 2.  Each group has the
seven signed entries ``x, y, z, r0, r1, r2, t`` of
:data:`redkin.srs.coefficients.ENTRY_LAYOUT` (shoulder: ``x = c1 s2``,
``y = s1 s2``, ``z = c2``, ``r`` the first column of ``0R3`` with ``r2 =
-s2 c3``, ``t = s2 s3``; wrist likewise with joints 5-7):

* first joint (eqs. 13, 17): ``atan2(y, x)``; where ``hypot(x, y) = |sin
  theta_2|`` is below :data:`UNDEFINED_TOLERANCE` only ``theta_1 + theta_3``
  is defined, and ``theta_1 = 0`` (turned by pi for ``sigma = -1``), the
  convention of the end of section 3.3, so that the third joint takes the
  whole rotation;
* second joint (eqs. 14, 18): ``acos z`` evaluated as
  ``atan2(hypot(x, y), z)``, the same function without the loss of digits
  of ``acos`` near 0 and pi;
* third joint (eqs. 15, 19): read from the rotation left after the first two
  joints: ``0R3 = Rz(theta_1) Ry(theta_2) Rz(theta_3) Rx(-pi/2)``, so
  ``theta_3 = atan2(p_2 . r, p_1 . r)`` with ``p_k`` the columns of
  ``Rz(theta_1) Ry(theta_2)``.  This equals eq. 15 (``atan2(t, -r2)``)
  wherever eq. 15 is defined and stays exact at the singular arm angle
  (theta_2 = 0), where eq. 15 is 0/0 and only theta_1 + theta_3 is
  determined.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

#: Joint numbers (1-based) whose angle depends on psi, in column order of the arrays below.
PSI_JOINTS = (1, 2, 3, 5, 6, 7)
#: Which of the columns of :data:`PSI_JOINTS` are of cosine type (eqs. 14, 18).
IS_COSINE = np.array([False, True, False, False, True, False])
# slots of the seven entries of a group (see the module docstring)
_X, _Y, _Z, _R0, _R1, _R2, _T = range(7)
#: ``hypot(x, y)`` (``|sin theta_2|`` or ``|sin theta_6|``) at or below which the first joint of a
#: group is undefined and set to 0.  Rounding leaves ``x, y`` of about 1e-17 on an exactly singular
#: pose, where ``atan2`` alone would return an arbitrary angle.
UNDEFINED_TOLERANCE = 1e-12
#: A group whose ``x, y`` coefficients (eqs. 12, 16) are all at or below this is singular at every
#: arm angle (the arm stretched along the joint-1 axis, or the mirror case at the wrist); below
#: :data:`UNDEFINED_TOLERANCE` / 3, so that the IK then sets its first joint to 0 at every psi.
STRETCHED_TOLERANCE = 1e-13
_GROUP = 7


def entry_values(entries: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """The entries at arm angles ``psi``: ``a sin psi + b cos psi + c`` (eqs. 12, 16).

    ``entries`` has shape ``(..., 3, 14)`` (rows ``a, b, c``); ``psi``
    broadcasts against ``(...)``.  Returns ``(..., 14)``.
    """
    psi = np.asarray(psi, dtype=float)
    trig = np.empty(psi.shape + (1, 3))
    np.sin(psi, out=trig[..., 0, 0])
    np.cos(psi, out=trig[..., 0, 1])
    trig[..., 0, 2] = 1.0
    return (trig @ entries)[..., 0, :]


def positive_branch_angles(values: np.ndarray) -> np.ndarray:
    """Joints 1, 2, 3, 5, 6, 7 for ``sigma_2 = sigma_6 = +1`` from the entry values ``(..., 14)``.

    The work runs on a slot-major copy ``(7, 2, batch)`` so that every
    operation sees contiguous arrays (strided views cost twice the time).
    """
    batch = values.shape[:-1]
    slots = values.reshape(-1, 2, _GROUP).transpose(2, 1, 0).copy()  # (7, 2, B)
    x, y, z = slots[_X], slots[_Y], slots[_Z]
    r0, r1, r2 = slots[_R0], slots[_R1], slots[_R2]
    angles = np.empty((3,) + x.shape)
    sine = np.hypot(x, y)
    np.arctan2(y, x, out=angles[0])  # eqs. 13, 17
    np.copyto(angles[0], 0.0, where=sine <= UNDEFINED_TOLERANCE)  # only theta_1 + theta_3 defined
    np.arctan2(sine, z, out=angles[1])  # eqs. 14, 18
    cosines, sines = np.cos(angles[:2]), np.sin(angles[:2])
    c1, c2, s1, s2 = cosines[0], cosines[1], sines[0], sines[1]
    along_p1 = c2 * (c1 * r0 + s1 * r1) - s2 * r2
    along_p2 = c1 * r1 - s1 * r0
    np.arctan2(along_p2, along_p1, out=angles[2])  # eqs. 15, 19
    return angles.transpose(2, 1, 0).reshape(batch + (6,))


@lru_cache(maxsize=None)
def branch_signs(shoulder: int, wrist: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`branch_sign_arrays` of one branch ``(sigma_2, sigma_6)``, cached."""
    return branch_sign_arrays(np.array([shoulder, wrist]))


def branch_sign_arrays(signs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(factor, turn)``, each ``(..., 2, 3)``, for branch signs ``(..., 2)`` = ``(sigma_2, sigma_6)``.

    ``factor`` is -1 for the cosine-type joint of a group with ``sigma = -1``;
    ``turn`` marks its tangent-type joints (turned by pi).
    """
    negative = (np.asarray(signs) < 0)[..., None]
    factor = np.where(negative & IS_COSINE[:3], -1.0, 1.0)
    turn = (negative & ~IS_COSINE[:3]).astype(float)
    return factor, turn


def apply_branch_signs(angles: np.ndarray, signs: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Angles of the branch ``(sigma_2, sigma_6)`` from those of ``(+1, +1)`` (eqs. 13-19).

    A tangent-type angle with ``sigma = -1`` is ``atan2(-N, -D)``, i.e. turned
    by ``pi``; a cosine-type one is negated.  ``signs`` is the ``(factor,
    turn)`` pair of :func:`branch_sign_arrays` or :func:`branch_signs`; it
    broadcasts against the batch axes of ``angles`` ``(..., 6)``.
    """
    factor, turn = signs
    grouped = angles.reshape(angles.shape[:-1] + (2, 3))
    signed = grouped * factor + turn * np.where(grouped > 0.0, -np.pi, np.pi)
    return signed.reshape(signed.shape[:-2] + (6,))


def psi_joint_angles(values: np.ndarray, signs: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Joints 1, 2, 3, 5, 6, 7, shape ``(..., 6)``, from entry values and branch signs (:func:`branch_signs`)."""
    return apply_branch_signs(positive_branch_angles(values), signs)


def assemble_theta(theta4: np.ndarray, psi_joints: np.ndarray) -> np.ndarray:
    """The 7 DH angles from theta_4 ``(...)`` and the six psi-dependent joints ``(..., 6)``."""
    theta4 = np.broadcast_to(theta4, psi_joints.shape[:-1])
    return np.concatenate([psi_joints[..., :3], theta4[..., None], psi_joints[..., 3:]], axis=-1)


def limit_equation_table(
    lower: np.ndarray, upper: np.ndarray, limited: np.ndarray, stretched: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The linear map from entry coefficients to the limit equations of the six psi-dependent joints.

    The arm angles where ``theta(psi)`` equals a limit ``L`` solve ``p sin psi
    + q cos psi + r = 0`` with

    * tangent type (eq. 21 with ``theta = L``): ``N cos L - D sin L = 0``
      (also true where ``theta = L + pi``, which only adds a harmless cut);
    * cosine type (eq. 22): ``z - cos L = 0`` (also true where ``theta =
      -L``, likewise harmless).

    ``(p, q, r)`` of all twelve equations (lower and upper limit of each
    column of :data:`PSI_JOINTS`) are ``entries @ weights + offset`` for
    entry coefficients ``(..., 3, 14)``.  An unlimited joint gets ``0 = 1``
    (no root).

    With ``stretched`` the table is that of a group singular at every arm
    angle (``x = y = 0``, :data:`STRETCHED_TOLERANCE`): there the IK sets the
    first joint to 0 (``N = 0, D = 1``: the constant ``-sin L = 0``) and
    reads the third from the rest of the rotation, ``theta_3 = atan2(r1,
    r0)`` (``N = r1, D = r0``); the second joint is unchanged.

    Parameters
    ----------
    lower, upper : numpy.ndarray, shape (6,)
        DH limits of the columns of :data:`PSI_JOINTS`.
    limited : numpy.ndarray of bool, shape (6,)
    stretched : bool
        The table of a group singular at every arm angle.

    Returns
    -------
    weights : numpy.ndarray, shape (14, 12)
    offset : numpy.ndarray, shape (3, 12)
        Equation ``2 k + j`` is column ``k`` at its lower (``j = 0``) or upper limit.
    """
    weights = np.zeros((2 * _GROUP, 12))
    offset = np.zeros((3, 12))
    for k in range(6):
        base = _GROUP * (k // 3)
        for j, limit in enumerate((lower[k], upper[k])):
            e = 2 * k + j
            if not limited[k]:
                offset[2, e] = 1.0
            elif k % 3 == 0 and stretched:  # first joint set to 0: N = 0, D = 1
                offset[2, e] = -np.sin(limit)
            elif k % 3 == 0:  # first joint: N = y, D = x
                weights[base + _Y, e], weights[base + _X, e] = np.cos(limit), -np.sin(limit)
            elif k % 3 == 1:  # second joint: cos theta = z
                weights[base + _Z, e], offset[2, e] = 1.0, -np.cos(limit)
            elif stretched:  # third joint after a first joint of 0: N = r1, D = r0
                weights[base + _R1, e], weights[base + _R0, e] = np.cos(limit), -np.sin(limit)
            else:  # third joint (eq. 15 / 19): N = t, D = -r2
                weights[base + _T, e], weights[base + _R2, e] = np.cos(limit), np.sin(limit)
    for array in (weights, offset):
        array.setflags(write=False)
    return weights, offset


def first_joint_coefficients(entries: np.ndarray) -> np.ndarray:
    """``|a|, |b|, |c|`` of ``x`` and ``y`` of both groups, shape ``(..., 3, 2, 2)`` (rows, group, entry).

    ``x = c1 s2`` and ``y = s1 s2`` (or ``c5 s6``, ``s5 s6``) vanish for
    every psi exactly when all their coefficients do: the group is then
    singular at every arm angle (:data:`STRETCHED_TOLERANCE`).
    """
    return np.abs(entries.reshape(entries.shape[:-1] + (2, _GROUP))[..., :2])


def within(theta: np.ndarray, start, span, free) -> np.ndarray:
    """``start <= theta <= start + span`` modulo 2 pi (limits crossing +-pi work); free (unlimited) joints pass.

    ``start`` and ``span`` are the limits widened by :data:`redkin.srs.geometry.MEMBERSHIP_TOLERANCE`
    on both sides (:attr:`redkin.srs.geometry.SRSGeometry.psi_joint_limits`).
    """
    return (np.mod(theta - start, 2.0 * np.pi) <= span) | free


#: Width (radians) below which a region between the zeros of a joint's limit equations is rounding.
REGION_TOLERANCE = 1e-12


def limit_sign_membership(lower: np.ndarray, upper: np.ndarray, start, span, free) -> np.ndarray:
    """Joint-limit membership as a function of the signs of the two limit equations of each joint (eqs. 21, 22, 29).

    Between consecutive zeros of its two limit equations (:func:`limit_equation_table`)
    a joint stays on one side of each limit, so whether it is within its
    limits depends only on which of the two equations are positive: for
    the tangent type ``N cos L - D sin L = rho sin(theta_+ - L)`` with
    ``theta_+ = atan2(N, D)`` the angle of the ``sigma = +1`` branch, for the
    cosine type ``z - cos L = cos theta_+ - cos L`` with ``theta_+ = acos z``.
    The table is filled from one ``theta_+`` inside each region between the
    zeros (``L``, ``U``, ``L + pi``, ``U + pi`` on the circle, or ``|L|``,
    ``|U|`` on ``[0, pi]``), whose branch angle (``theta_+`` turned by ``pi``
    or negated for ``sigma = -1``) is tested with :func:`within`.

    Parameters
    ----------
    lower, upper : numpy.ndarray, shape (6,)
        DH limits of the columns of :data:`PSI_JOINTS` (as given to :func:`limit_equation_table`).
    start, span, free : numpy.ndarray, shape (6,)
        The membership test of :func:`within` (limits with slack; unlimited joints).

    Returns
    -------
    numpy.ndarray of bool, shape (2, 6, 4)
        ``[n, k, 2 a + b]``: column ``k`` on a branch with ``sigma < 0`` (``n = 1``)
        or ``sigma > 0`` (``n = 0``) is within its limits where its lower-limit
        equation is positive (``a = 1``) or not (``a = 0``) and its upper-limit
        equation likewise (``b``).  Patterns that never occur are False.
    """
    table = np.zeros((2, 6, 4), dtype=bool)
    table[:, free, :] = True  # an unlimited joint's equations read 0 = 1
    for k in np.flatnonzero(~free):
        limits = np.array([lower[k], upper[k]])
        if IS_COSINE[k]:
            folded = np.abs(np.mod(limits + np.pi, 2.0 * np.pi) - np.pi)
            zeros = np.sort(np.concatenate([[0.0, np.pi], folded]))
            starts, ends = zeros[:-1], zeros[1:]
        else:
            zeros = np.sort(np.mod(np.concatenate([limits, limits + np.pi]), 2.0 * np.pi))
            starts, ends = zeros, np.append(zeros[1:], zeros[0] + 2.0 * np.pi)
        # one inside each region; regions narrower than REGION_TOLERANCE are rounding (two limits pi apart give
        # zeros that differ in the last bit), and their signs would read 0 and overwrite a real region's entry
        samples = 0.5 * (starts + ends)[ends - starts > REGION_TOLERANCE]
        if IS_COSINE[k]:
            signs = np.cos(samples)[:, None] - np.cos(limits) > 0.0
            branch_angles = (samples, -samples)
        else:
            signs = np.sin(samples[:, None] - limits) > 0.0
            branch_angles = (samples, samples + np.pi)
        patterns = 2 * signs[:, 0] + signs[:, 1]
        for n, theta in enumerate(branch_angles):
            table[n, k, patterns] = within(theta, start[k], span[k], free[k])
    table.setflags(write=False)
    return table

