"""Joint angles as functions of the arm angle: [000 eqs. 13-15, 17-19].

Every joint but the elbow is of one of two types [000 eqs. 21, 22]:

* tangent type (joints 1, 3, 5, 7): ``theta = atan2(sigma N(psi), sigma D(psi))``
  with ``N, D = (a sin psi + b cos psi + c)``;
* cosine type (joints 2, 6): ``cos theta = a sin psi + b cos psi + c``,
  ``theta = sigma acos(...)``;

where ``sigma`` is the branch sign of theta_2 (shoulder joints) or theta_6
(wrist joints).  ``sigma = -1`` turns a tangent-type angle by ``pi`` and
negates a cosine-type one.

The shoulder (joints 1-3, read from ``0R3``) and the wrist (joints 5-7,
read from ``4R7``) have the same structure: each group has the seven
signed entries ``x, y, z, r0, r1, r2, t`` of
:data:`redkin.srs._ik_kernels.ENTRY_LAYOUT` (shoulder: ``x = c1 s2``,
``y = s1 s2``, ``z = c2``, ``r`` the first column of ``0R3`` with ``r2 =
-s2 c3``, ``t = s2 s3``; wrist likewise with joints 5-7).  The angles
themselves are computed by :func:`redkin.srs._ik_kernels.group_angles`; this
module holds what the feasible sets need: the limit equations of each
joint and which of their signs mean "within the limits".
"""

from __future__ import annotations

import numpy as np

from redkin.srs import _ik_kernels

#: Joint numbers (1-based) whose angle depends on psi, in column order of the arrays below.
PSI_JOINTS = (1, 2, 3, 5, 6, 7)
#: Which of the columns of :data:`PSI_JOINTS` are of cosine type [000 eqs. 14, 18].
_IS_COSINE = np.array([False, True, False, False, True, False])
# slots of the seven entries of a group (see the module docstring)
_X, _Y, _Z, _R0, _R1, _R2, _T = range(7)
#: A group whose ``x, y`` coefficients [000 eqs. 12, 16] are all at or below this is singular at every
#: arm angle (the arm stretched along the joint-1 axis, or the mirror case at the wrist); below
#: :data:`redkin.srs._ik_kernels.UNDEFINED_TOLERANCE` / 3, so that the IK then sets its first joint to 0 at every psi.
STRETCHED_TOLERANCE = 1e-13
_GROUP = _ik_kernels.GROUP  # entries per group (shoulder, wrist): x, y, z, r0, r1, r2, t


def limit_equation_table(
    lower: np.ndarray, upper: np.ndarray, limited: np.ndarray, stretched: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The linear map from entry coefficients to the limit equations of the six psi-dependent joints.

    The arm angles where ``theta(psi)`` equals a limit ``L`` solve ``p sin psi
    + q cos psi + r = 0`` with

    * tangent type ([000 eq. 21] with ``theta = L``): ``N cos L - D sin L = 0``
      (also true where ``theta = L + pi``, which only adds a harmless cut);
    * cosine type [000 eq. 22]: ``z - cos L = 0`` (also true where ``theta =
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
            else:  # third joint [000 eqs. 15, 19]: N = t, D = -r2
                weights[base + _T, e], weights[base + _R2, e] = np.cos(limit), np.sin(limit)
    for array in (weights, offset):
        array.setflags(write=False)
    return weights, offset


def within(theta: np.ndarray, start, span, free) -> np.ndarray:
    """``start <= theta <= start + span`` modulo 2 pi (limits crossing +-pi work); free (unlimited) joints pass.

    ``start`` and ``span`` are the limits widened by :data:`redkin.srs.geometry.MEMBERSHIP_TOLERANCE`
    on both sides (:attr:`redkin.srs.geometry.SRSGeometry.psi_joint_limits`).
    """
    return (np.mod(theta - start, 2.0 * np.pi) <= span) | free


#: Width (radians) below which a region between the zeros of a joint's limit equations is rounding.
_REGION_TOLERANCE = 1e-12


def limit_sign_membership(lower: np.ndarray, upper: np.ndarray, start, span, free) -> np.ndarray:
    """Joint-limit membership as a function of the signs of the two limit equations of each joint [000 eqs. 21, 22, 29].

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
        if _IS_COSINE[k]:
            folded = np.abs(np.mod(limits + np.pi, 2.0 * np.pi) - np.pi)
            zeros = np.sort(np.concatenate([[0.0, np.pi], folded]))
            starts, ends = zeros[:-1], zeros[1:]
        else:
            zeros = np.sort(np.mod(np.concatenate([limits, limits + np.pi]), 2.0 * np.pi))
            starts, ends = zeros, np.append(zeros[1:], zeros[0] + 2.0 * np.pi)
        # one inside each region; regions narrower than _REGION_TOLERANCE are rounding (two limits pi apart give
        # zeros that differ in the last bit), and their signs would read 0 and overwrite a real region's entry
        samples = 0.5 * (starts + ends)[ends - starts > _REGION_TOLERANCE]
        if _IS_COSINE[k]:
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

