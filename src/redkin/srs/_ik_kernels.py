"""The compiled core of arm-angle IK: [000 eqs. 4-19] for one pose, and batches of them.

The one implementation in redkin of

* the target in Table 1 form and the pose check (:func:`pose_defect`, :func:`table1_target`);
* the psi-independent frame of [000 eqs. 4-11] (:func:`wrist_point`, :func:`elbow_frame`): the elbow
  angle, the unit shoulder-to-wrist vector ``u``, ``0R3`` on the reference
  plane and ``3R4``;
* the coefficient matrices of [000 eqs. 12, 16] (:func:`coefficient_matrices`)
  and the 14 entries the joints are read from (:func:`select_entries`);
* the joint angles at an arm angle on a branch, [000 eqs. 13-15, 17-19]
  (:func:`branch_angles`), and the chain's joint values (:func:`chain_values`).

:mod:`redkin.srs.coefficients`, :mod:`redkin.srs.joints` and
:mod:`redkin.srs.ik` validate at the public edge and call the batch kernels
here: :func:`solve_poses`, :func:`coefficients` and :func:`angles_at`
through :func:`redkin._compiled.run_batch` (which hands each call a chunk
``start .. stop - 1`` of the batch), :func:`joint_values` directly.  Kernels
trust their inputs: C-contiguous float64 arrays of the documented shapes.

An arm is passed as

``arm`` : (11,) float64
    ``d_bs, d_se, d_ew, d_wt, a_3, a_4``, ``C, R, phi`` of
    :class:`redkin.srs.geometry.ElbowEquation`, and ``cos phi, sin phi`` (:data:`ARM_COLUMNS`).
``ends`` : (2, 4, 4) float64
    ``base^-1`` and ``tool^-1`` of the chain: frame 7 in frame 0 is ``base^-1 pose tool^-1``.
``joints`` : (5, 7) float64
    Per joint ``offset, sign``, whether its value is wrapped into its limits,
    and its lower and upper limit (``-inf``, ``inf`` for an unlimited joint)
    (:data:`JOINT_ROWS`; see :meth:`redkin.srs.geometry.SRSGeometry.to_chain_q`).
"""

from __future__ import annotations

from math import acos, atan2, cos, isfinite, pi, sin, sqrt

import numpy as np

from redkin._chain_kernels import range_middle, representative
from redkin._compiled import kernel
from redkin._pose_kernels import BAD_POSE, OK, pose_defect
from redkin.circle import TWO_PI

ARM_COLUMNS = ("d_bs", "d_se", "d_ew", "d_wt", "a3", "a4", "mean", "amplitude", "phase", "cos_phase", "sin_phase")
D_BS, D_SE, D_EW, D_WT, A3, A4, MEAN, AMPLITUDE, PHASE, COS_PHASE, SIN_PHASE = range(11)
JOINT_ROWS = ("offset", "sign", "wrap", "lower", "upper")
OFFSET, SIGN, WRAP, LOWER, UPPER = range(5)

#: Relative distance of the wrist from the joint-1 axis below which the wrist counts as on it.
AXIS_TOLERANCE = 1e-12
#: Slack on ``|cos(theta_4 - phi)| <= 1`` [000 eq. 11] absorbed as rounding before a pose counts as unreachable.
REACH_TOLERANCE = 1e-9
#: ``hypot(x, y)`` (``|sin theta_2|`` or ``|sin theta_6|``) at or below which the first joint of a
#: group is undefined and set to 0.  Rounding leaves ``x, y`` of about 1e-17 on an exactly singular
#: pose, where ``atan2`` alone would return an arbitrary angle.
UNDEFINED_TOLERANCE = 1e-12
#: Slack (radians) when a joint value is compared with its limits (:func:`in_limits`).
MEMBERSHIP_TOLERANCE = 1e-12
#: Status of a pose in the batch kernels (:data:`OK` and :data:`BAD_POSE` are :func:`pose_defect`'s).
BAD_PSI, UNREACHABLE = BAD_POSE + 1, BAD_POSE + 2

#: The entries the joint angles are read from: ``(matrix, row, column, factor)``, matrix 0 being
#: ``0R3`` and 1 ``4R7``, for the slots ``x, y, z, r0, r1, r2, t`` of each group.  Shoulder:
#: ``x = -0R3[0,1] = c1 s2``, ``y = -0R3[1,1] = s1 s2``, ``z = -0R3[2,1] = c2``,
#: ``r = 0R3[:,0]`` (``r2 = -s2 c3``), ``t = 0R3[2,2] = s2 s3`` (section 3.3);
#: wrist: ``x = 4R7[0,2] = c5 s6``, ``y = 4R7[1,2] = s5 s6``, ``z = 4R7[2,2] = c6``,
#: ``r = 4R7[:,0]`` (``r2 = -s6 c7``), ``t = 4R7[2,1] = s6 s7``.
ENTRY_LAYOUT = np.array([
    (0, 0, 1, -1.0), (0, 1, 1, -1.0), (0, 2, 1, -1.0), (0, 0, 0, 1.0), (0, 1, 0, 1.0), (0, 2, 0, 1.0), (0, 2, 2, 1.0),
    (1, 0, 2, 1.0), (1, 1, 2, 1.0), (1, 2, 2, 1.0), (1, 0, 0, 1.0), (1, 1, 0, 1.0), (1, 2, 0, 1.0), (1, 2, 1, 1.0),
])
ENTRY_LAYOUT.setflags(write=False)
GROUP = 7  # entries per group (shoulder, wrist)


# ------------------------------------------------------------- the target
@kernel
def table1_target(pose, ends, target):
    """Frame 7 in frame 0, ``base^-1 pose tool^-1``, into ``target`` (3, 4): rotation and position."""
    base, tool = ends[0], ends[1]
    for r in range(3):
        row = (base[r, 0] * pose[0, 0] + base[r, 1] * pose[1, 0] + base[r, 2] * pose[2, 0],
               base[r, 0] * pose[0, 1] + base[r, 1] * pose[1, 1] + base[r, 2] * pose[2, 1],
               base[r, 0] * pose[0, 2] + base[r, 1] * pose[1, 2] + base[r, 2] * pose[2, 2],
               base[r, 0] * pose[0, 3] + base[r, 1] * pose[1, 3] + base[r, 2] * pose[2, 3] + base[r, 3])
        for c in range(4):
            target[r, c] = row[0] * tool[0, c] + row[1] * tool[1, c] + row[2] * tool[2, c]
        target[r, 3] += row[3]


# -------------------------------------------------------- [000 eqs. 4-11]
@kernel
def wrist_point(target, arm, u):
    """What both elbow signs share in [000 eqs. 4-11] for a target (3, 4) of frame 7 in frame 0.

    ``x_sw = x_7 - l_bs - R_7 l_wt`` [000 eq. 4] and ``cos(theta_4 - phi) =
    (|x_sw|^2 - C) / R`` [000 eq. 11]; writes ``u = x_sw / |x_sw|`` (3,).
    Returns ``(w, c1, s1, z, cosine, sine, angle)`` -- ``w = hypot(x_sw,
    y_sw)`` (0 on the joint-1 axis), ``c1, s1`` the cosine and sine of
    ``theta_1o = atan2(y_sw, x_sw)`` (``1, 0`` on the axis), ``z = z_sw``, and
    ``cosine``, ``sine`` and ``angle = acos(cosine)`` of ``|theta_4 - phi|`` --
    then ``|x_sw|`` and whether the wrist is within reach (``|cos| <= 1`` with
    :data:`REACH_TOLERANCE`).
    """
    x = target[0, 3] - target[0, 2] * arm[D_WT]
    y = target[1, 3] - target[1, 2] * arm[D_WT]
    z = target[2, 3] - target[2, 2] * arm[D_WT] - arm[D_BS]
    squared = x * x + y * y + z * z
    distance = sqrt(squared)
    cosine = (squared - arm[MEAN]) / arm[AMPLITUDE]  # [000 eq. 11]
    reach = abs(cosine) <= 1.0 + REACH_TOLERANCE
    cosine = min(max(cosine, -1.0), 1.0)
    w = sqrt(x * x + y * y)
    c1, s1 = 1.0, 0.0
    if w > AXIS_TOLERANCE * sqrt(arm[MEAN]):
        c1, s1 = x / w, y / w
    else:
        w = 0.0
    scale = 1.0 / distance if distance > 0.0 else 0.0
    u[0], u[1], u[2] = x * scale, y * scale, z * scale
    return (w, c1, s1, z, cosine, sqrt(1.0 - cosine * cosine), acos(cosine)), distance, reach


@kernel
def elbow_frame(shared, arm, elbow_sign, reference, elbow):
    """The rest of [000 eqs. 4-11] for one elbow sign ``sigma``, from :func:`wrist_point`'s ``shared``.

    ``theta_4 = phi + sigma acos((|x_sw|^2 - C) / R)`` [000 eq. 11] (``phi =
    0`` without elbow offsets), wrapped to ``[-pi, pi)``; the reference plane
    ``theta_3 = 0`` ([000 eq. 7], section 3.3): ``0R3o = Rz(theta_1o)
    Rx(-pi/2) Rz(theta_2o)`` with ``theta_2o = atan2(-z_sw, w) - atan2(v_y,
    v_x)``, ``(v_x, v_y) = (a_3 + a_4 c4 + d_ew s4, -d_se + a_4 s4 - d_ew c4)``
    the wrist in frame 3; ``3R4 = Rz(theta_4) Rx(pi/2)`` ([000 eq. 3], Table 1).
    The cosines and sines of theta_4 and theta_2o come from the angle-sum
    formulas, without evaluating the angles' trigonometric functions.

    Writes ``reference`` = ``0R3o`` and ``elbow`` = ``3R4`` (3, 3); returns ``theta_4``.
    """
    w, c1, s1, z, cosine, sine, angle = shared
    theta4 = elbow_sign * angle
    c4, s4 = cosine, elbow_sign * sine
    if arm[PHASE] != 0.0:
        theta4 = turns_removed(theta4 + arm[PHASE] + pi) - pi
        c4, s4 = arm[COS_PHASE] * c4 - arm[SIN_PHASE] * s4, arm[SIN_PHASE] * c4 + arm[COS_PHASE] * s4
    v_x = arm[A3] + arm[A4] * c4 + arm[D_EW] * s4
    v_y = arm[A4] * s4 - (arm[D_SE] + arm[D_EW] * c4)
    rho, length = sqrt(w * w + z * z), sqrt(v_x * v_x + v_y * v_y)
    ca, sa = (w / rho, -z / rho) if rho > 0.0 else (1.0, 0.0)  # atan2(-z, w)
    cb, sb = (v_x / length, v_y / length) if length > 0.0 else (1.0, 0.0)  # atan2(v_y, v_x)
    c2, s2 = ca * cb + sa * sb, sa * cb - ca * sb  # theta_2o = a - b
    # Rz(t1) Rx(-pi/2) Rz(t2): columns (c1 c2, s1 c2, -s2), (-c1 s2, -s1 s2, -c2), (-s1, c1, 0)
    reference[0, 0], reference[0, 1], reference[0, 2] = c1 * c2, -c1 * s2, -s1
    reference[1, 0], reference[1, 1], reference[1, 2] = s1 * c2, -s1 * s2, c1
    reference[2, 0], reference[2, 1], reference[2, 2] = -s2, -c2, 0.0
    # Rz(t4) Rx(pi/2)
    elbow[0, 0], elbow[0, 1], elbow[0, 2] = c4, 0.0, s4
    elbow[1, 0], elbow[1, 1], elbow[1, 2] = s4, 0.0, -c4
    elbow[2, 0], elbow[2, 1], elbow[2, 2] = 0.0, 1.0, 0.0
    return theta4


# ------------------------------------------------------ [000 eqs. 12, 16]
@kernel
def coefficient_matrices(u, reference, elbow, target, shoulder, wrist):
    """``(A_s, B_s, C_s)`` [000 eq. 12] and ``(A_w, B_w, C_w)`` [000 eq. 16] into ``shoulder``, ``wrist`` (3, 3, 3).

    ``0R3(psi) = R_psi 0R3o`` [000 eq. 8] with Rodrigues' ``R_psi = sin psi [u x] + cos psi
    (I - u u^T) + u u^T`` [000 eq. 6], so ``A_s = [u x] R3o``, ``B_s = (I - u u^T)
    R3o`` and ``C_s = u u^T R3o`` (the transcription prints ``C_s`` garbled;
    ``I + [u x]^2 = u u^T`` for a unit ``u``); ``4R7 = 3R4^T 0R3^T 0R7``, so
    ``A_w = 3R4^T A_s^T 0R7`` and likewise ``B_w``, ``C_w``.
    """
    ux, uy, uz = u[0], u[1], u[2]
    for c in range(3):
        r0, r1, r2 = reference[0, c], reference[1, c], reference[2, c]
        along = ux * r0 + uy * r1 + uz * r2
        shoulder[0, 0, c], shoulder[0, 1, c], shoulder[0, 2, c] = (
            uy * r2 - uz * r1, uz * r0 - ux * r2, ux * r1 - uy * r0
        )
        shoulder[2, 0, c], shoulder[2, 1, c], shoulder[2, 2, c] = ux * along, uy * along, uz * along
        shoulder[1, 0, c], shoulder[1, 1, c], shoulder[1, 2, c] = r0 - ux * along, r1 - uy * along, r2 - uz * along
    c4, s4 = elbow[0, 0], elbow[1, 0]  # 3R4 = Rz(theta_4) Rx(pi/2) = [[c4, 0, s4], [s4, 0, -c4], [0, 1, 0]]
    for k in range(3):
        # column r of 3R4^T S^T is row r of 3R4^T times S^T: (c4 S[m,0] + s4 S[m,1], S[m,2], s4 S[m,0] - c4 S[m,1])
        p0 = c4 * shoulder[k, 0, 0] + s4 * shoulder[k, 0, 1]
        p1 = c4 * shoulder[k, 1, 0] + s4 * shoulder[k, 1, 1]
        p2 = c4 * shoulder[k, 2, 0] + s4 * shoulder[k, 2, 1]
        q0, q1, q2 = shoulder[k, 0, 2], shoulder[k, 1, 2], shoulder[k, 2, 2]
        t0 = s4 * shoulder[k, 0, 0] - c4 * shoulder[k, 0, 1]
        t1 = s4 * shoulder[k, 1, 0] - c4 * shoulder[k, 1, 1]
        t2 = s4 * shoulder[k, 2, 0] - c4 * shoulder[k, 2, 1]
        for c in range(3):  # A_w = (3R4^T A_s^T) 0R7, likewise B_w, C_w
            wrist[k, 0, c] = p0 * target[0, c] + p1 * target[1, c] + p2 * target[2, c]
            wrist[k, 1, c] = q0 * target[0, c] + q1 * target[1, c] + q2 * target[2, c]
            wrist[k, 2, c] = t0 * target[0, c] + t1 * target[1, c] + t2 * target[2, c]


@kernel
def select_entries(shoulder, wrist, entries):
    """The signed entries of :data:`ENTRY_LAYOUT` of the coefficient matrices into ``entries`` (3, 14):
    row ``k`` holds those of ``A`` (``k = 0``), ``B`` and ``C``, so ``entry(psi) = a sin psi + b cos psi + c``."""
    for e in range(ENTRY_LAYOUT.shape[0]):
        row, col, factor = int(ENTRY_LAYOUT[e, 1]), int(ENTRY_LAYOUT[e, 2]), ENTRY_LAYOUT[e, 3]
        for k in range(3):
            source = shoulder if ENTRY_LAYOUT[e, 0] == 0.0 else wrist
            entries[k, e] = factor * source[k, row, col]


# --------------------------------------------------- [000 eqs. 13-15, 17-19]
@kernel
def group_angles(x, y, z, r0, r1, r2, theta, first):
    """The three angles of a group (joints 1-3 from ``0R3``, or 5-7 from ``4R7``) on the branch sign +1.

    * first joint [000 eqs. 13, 17]: ``atan2(y, x)``; where ``hypot(x, y) = |sin
      theta_2|`` is at most :data:`UNDEFINED_TOLERANCE` only ``theta_1 +
      theta_3`` is defined and ``theta_1 = 0``, the convention of the end of
      section 3.3;
    * second joint [000 eqs. 14, 18]: ``acos z``, evaluated as ``atan2(hypot(x,
      y), z)`` (no loss of digits near 0 and pi);
    * third joint [000 eqs. 15, 19]: from the rotation left after the first two,
      ``0R3 = Rz(theta_1) Ry(theta_2) Rz(theta_3) Rx(-pi/2)``, so ``theta_3 =
      atan2(p_2 . r, p_1 . r)`` with ``p_k`` the columns of ``Rz(theta_1)
      Ry(theta_2)``.  This equals [000 eq. 15] (``atan2(t, -r2)``) wherever [000 eq. 15] is
      defined and stays exact at the singular arm angle (theta_2 = 0), where
      [000 eq. 15] is 0/0.

    Writes ``theta[first:first + 3]``; :func:`apply_sign` gives the branch sign -1.
    """
    sine = sqrt(x * x + y * y)  # entries of a rotation: no overflow to guard against
    c1, s1, angle1 = 1.0, 0.0, 0.0
    if sine > UNDEFINED_TOLERANCE:
        c1, s1, angle1 = x / sine, y / sine, atan2(y, x)
    c2, s2 = z, sine  # (x, y, z) = (c1 s2, s1 s2, c2) is a column of a rotation: a unit vector
    theta[first] = angle1
    theta[first + 1] = atan2(sine, z)
    theta[first + 2] = atan2(c1 * r1 - s1 * r0, c2 * (c1 * r0 + s1 * r1) - s2 * r2)


@kernel
def apply_sign(theta, first, sigma):
    """A group's angles on the branch sign ``sigma``: for -1 the tangent-type angles (first, third) turn
    by pi and the cosine type (second) is negated (``atan2(-N, -D)``, ``-acos``; [000 eqs. 13-15, 17-19])."""
    if sigma < 0:
        for k in (first, first + 2):
            theta[k] += -pi if theta[k] > 0.0 else pi
        theta[first + 1] = -theta[first + 1]


@kernel
def entry_at(entries, e, s, c):
    """Entry ``e`` at the arm angle with ``s, c = sin psi, cos psi``: ``a s + b c + c`` [000 eqs. 12, 16]."""
    return entries[0, e] * s + entries[1, e] * c + entries[2, e]


@kernel
def groups_angles(entries, psi, theta):
    """The shoulder's and the wrist's angles [000 eqs. 13-15, 17-19] at arm angle ``psi`` on the branch signs +1,
    from the entry coefficients (3, 14) of one elbow sign, into ``theta[0:3]`` and ``theta[4:7]``."""
    s, c = sin(psi), cos(psi)
    for g in range(2):
        k = GROUP * g
        group_angles(entry_at(entries, k, s, c), entry_at(entries, k + 1, s, c), entry_at(entries, k + 2, s, c),
                     entry_at(entries, k + 3, s, c), entry_at(entries, k + 4, s, c), entry_at(entries, k + 5, s, c),
                     theta, 4 * g)


@kernel
def branch_angles(entries, theta4, psi, sigma2, sigma6, theta):
    """The 7 DH angles [000 eqs. 11, 13-15, 17-19] at arm angle ``psi`` on the branch ``(sigma_2, sigma_6)``
    from the entry coefficients (3, 14) of the elbow sign of ``theta4``, into ``theta`` (7,):
    :func:`groups_angles`, then the branch's signs (:func:`apply_sign`)."""
    groups_angles(entries, psi, theta)
    theta[3] = theta4
    apply_sign(theta, np.int64(0), sigma2)
    apply_sign(theta, np.int64(4), sigma6)


@kernel
def turns_removed(angle):
    """``angle mod 2 pi`` in ``[0, 2 pi)`` (the floor form, without the branches of Python's float ``%``)."""
    return angle - TWO_PI * np.floor(angle / TWO_PI)


@kernel
def chain_values(theta, joints, q):
    """The chain's joint values ``q = sign (theta - offset)`` of DH angles ``theta`` (7,), into ``q`` (7,).

    A wrapped joint is shifted by a multiple of ``2 pi`` into its limit range
    when one such shift lands there (limits crossing ``+-pi``); of several
    such shifts (a range wider than ``2 pi``) the one nearest the middle of
    the range (:func:`redkin._chain_kernels.representative`).  A value no
    shift brings inside, and a value of an unlimited joint, is wrapped to
    ``[-pi, pi)``.
    """
    for k in range(theta.shape[0]):
        value = joints[SIGN, k] * (theta[k] - joints[OFFSET, k])
        if joints[WRAP, k] != 0.0:
            lower, upper = joints[LOWER, k], joints[UPPER, k]
            inside = np.nan
            if lower > -np.inf or upper < np.inf:
                inside = representative(value, lower, upper, range_middle(lower, upper))
            value = inside if inside == inside else turns_removed(value + pi) - pi
        q[k] = value


# ----------------------------------------------------------------- batches
# A batch kernel computes items start..stop - 1 (redkin._compiled.run_batch hands out the chunks).
@kernel
def solve_pose(pose, psi, branches, arm, ends, joints, out, scratch):
    """All requested branches of one pose at one arm angle: the status and ``out`` (B, 7).

    ``branches`` (B, 3) holds the Table 1 signs ``(sigma_2, sigma_4,
    sigma_6)`` of each output row; each elbow sign's frame is computed once.
    Returns :data:`OK`, :data:`BAD_POSE`, :data:`BAD_PSI` or :data:`UNREACHABLE`.
    """
    if pose_defect(pose) != OK:
        return BAD_POSE
    if not isfinite(psi):
        return BAD_PSI
    target, u, reference, elbow, shoulder, wrist, entries, values, theta = scratch
    table1_target(pose, ends, target)
    shared, _, reach = wrist_point(target, arm, u)
    if not reach:
        return UNREACHABLE
    for e in range(2):
        sign = 1.0 if e == 0 else -1.0
        needed = False
        for b in range(branches.shape[0]):
            needed = needed or branches[b, 1] == sign
        if not needed:
            continue
        theta4 = elbow_frame(shared, arm, sign, reference, elbow)
        coefficient_matrices(u, reference, elbow, target, shoulder, wrist)
        select_entries(shoulder, wrist, entries)
        # the branches of this elbow sign differ by the group signs: the chain's values of both, per joint
        branch_angles(entries, theta4, psi, 1.0, 1.0, theta)
        chain_values(theta, joints, values[e, 0])
        apply_sign(theta, np.int64(0), -1.0)
        apply_sign(theta, np.int64(4), -1.0)
        chain_values(theta, joints, values[e, 1])
    for b in range(branches.shape[0]):
        e = 0 if branches[b, 1] > 0 else 1
        shoulder_turned, wrist_turned = int(branches[b, 0] < 0), int(branches[b, 2] < 0)
        for k in range(3):
            out[b, k] = values[e, shoulder_turned, k]
            out[b, k + 4] = values[e, wrist_turned, k + 4]
        out[b, 3] = values[e, 0, 3]
    return OK


@kernel
def _scratch():
    """The work arrays of :func:`solve_pose`, views into one allocation (one per thread)."""
    work = np.empty(164)
    return (work[0:12].reshape((3, 4)), work[12:15], work[15:24].reshape((3, 3)), work[24:33].reshape((3, 3)),
            work[33:60].reshape((3, 3, 3)), work[60:87].reshape((3, 3, 3)), work[87:129].reshape((3, 2 * GROUP)),
            work[129:157].reshape((2, 2, 7)), work[157:164])


@kernel
def in_limits(q, joints):
    """Whether joint values ``q`` (7,) lie within the chain's limits (``joints`` rows :data:`LOWER`, :data:`UPPER`),
    with the slack :data:`MEMBERSHIP_TOLERANCE`."""
    for k in range(7):
        if q[k] < joints[LOWER, k] - MEMBERSHIP_TOLERANCE or q[k] > joints[UPPER, k] + MEMBERSHIP_TOLERANCE:
            return False
    return True


@kernel
def solve_rows(pose, psi, branches, arm, ends, joints, out, within, scratch):
    """:func:`solve_pose`, then whether each row lies within the limits into ``within`` (B,); the rows of a pose
    whose status is not :data:`OK` are zeros, not within the limits.  Returns the status."""
    status = solve_pose(pose, psi, branches, arm, ends, joints, out, scratch)
    for b in range(branches.shape[0]):
        if status != OK:
            out[b, :] = 0.0
        within[b] = status == OK and in_limits(out[b], joints)
    return status


@kernel
def solve_single(pose, psi, branches, arm, ends, joints, out, within):
    """:func:`solve_rows` for one pose (4, 4) and arm angle (a 0-d array) into ``out`` (B, 7) and ``within`` (B,);
    returns the status."""
    return solve_rows(pose, psi[()], branches, arm, ends, joints, out, within, _scratch())


@kernel
def solve_poses(start, stop, poses, psi, branches, arm, ends, joints, out, within, status):
    """:func:`solve_rows` for poses ``start .. stop - 1`` of ``poses`` (N, 4, 4) and arm angles (N,) into ``out``
    (N, B, 7), ``within`` (N, B) and ``status`` (N,).

    Returns the number of those poses whose status is not :data:`OK` (their rows of ``out`` are zeros).
    """
    scratch = _scratch()
    failed = 0
    for n in range(start, stop):
        status[n] = solve_rows(poses[n], psi[n], branches, arm, ends, joints, out[n], within[n], scratch)
        if status[n] != OK:
            failed += 1
    return failed


@kernel
def coefficients_one(pose, sign, arm, ends, target, u, reference, elbow, shoulder, wrist, entries):
    """Frame, coefficient matrices and entries of one pose (4, 4) of the chain and an elbow sign.

    Returns the status (:data:`OK`, :data:`BAD_POSE` or :data:`UNREACHABLE`),
    ``theta_4`` and ``|x_sw|``; ``target`` (3, 4) is scratch.
    """
    if pose_defect(pose) != OK:
        return BAD_POSE, np.nan, np.nan
    table1_target(pose, ends, target)
    shared, distance, reach = wrist_point(target, arm, u)
    theta4 = elbow_frame(shared, arm, sign, reference, elbow)
    coefficient_matrices(u, reference, elbow, target, shoulder, wrist)
    select_entries(shoulder, wrist, entries)
    return (OK if reach else UNREACHABLE), theta4, distance


@kernel
def coefficients(start, stop, poses, signs, arm, ends, status, theta4, distance, u, reference, elbow, shoulder, wrist,
                 entries):
    """:func:`coefficients_one` for poses ``start .. stop - 1`` of ``poses`` (N, 4, 4) and elbow signs (N,) into
    the (N, ...) outputs."""
    target = np.empty((3, 4))
    for n in range(start, stop):
        status[n], theta4[n], distance[n] = coefficients_one(
            poses[n], signs[n], arm, ends, target, u[n], reference[n], elbow[n], shoulder[n], wrist[n], entries[n])


@kernel
def angles_at(start, stop, entries, theta4, psi, signs, out):
    """:func:`branch_angles` for items ``start .. stop - 1`` of entries (N, 3, 14), ``theta4`` (N,), ``psi`` (N,)
    and branch signs ``(sigma_2, sigma_6)`` (N, 2) into ``out`` (N, 7)."""
    for n in range(start, stop):
        branch_angles(entries[n], theta4[n], psi[n], signs[n, 0], signs[n, 1], out[n])


@kernel
def joint_values(theta, joints, out):
    """:func:`chain_values` for each row of ``theta`` (N, 7) into ``out`` (N, 7)."""
    for n in range(theta.shape[0]):
        chain_values(theta[n], joints, out[n])
