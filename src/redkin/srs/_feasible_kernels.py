"""The compiled core of the feasible arm angles: paper 000 section 4, [000 eqs. 20-30].

The one implementation of the feasible sets in redkin.  For one pose and
one elbow sign (the entry coefficients ``(3, 14)`` of [000 eqs. 12, 16] and
theta_4 of [000 eq. 11]) :func:`pose_pieces` cuts the circle of arm angles where
any joint reaches a limit and reads, in the middle of each piece, the signs
of the joints' limit equations; :func:`classify` turns those signs into the
per-joint sets [000 eq. 29] and their intersection [000 eq. 30] on one branch.
:func:`pose_branch` does both for one pose-branch and
:func:`pose_all_branches` for the eight branches of a pose (the cuts made
once per elbow sign); :func:`pose_feasible` starts from the pose itself,
computing [000 eqs. 4-19] with :func:`redkin.srs._ik_kernels.coefficients_one`,
for any rows of branches (one, or all eight, sharing each elbow sign's
cuts).  :func:`poses_feasible` loops over a chunk of a batch of poses
(:func:`redkin._compiled.run_batch`), :func:`branches` and
:func:`all_branches` over coefficients computed beforehand.
:mod:`redkin.srs.feasible` validates at its public edge and calls them;
the kernels trust their inputs: C-contiguous arrays of the documented
shapes and types.

The per-arm tables (:func:`redkin.srs.feasible.limit_tables`, built once per
geometry from :attr:`~redkin.srs.geometry.SRSGeometry.psi_joint_limits`) are

``equations`` : (2, 17, 12) float64
    ``[0]`` the usual, ``[1]`` the stretched limit-equation table of
    :func:`redkin.srs.joints.limit_equation_table`: rows 0-13 the weights,
    rows 14-16 the offset, so that ``(p, q, r)`` of equation ``e`` is
    ``entries @ table[:14, e] + table[14:, e]``.
``membership`` : (2, 2, 6, 4) bool
    ``[n2, n6, k, 2 a + b]``: whether column ``k`` of
    :data:`redkin.srs.joints.PSI_JOINTS` is within its limits on a branch with
    ``sigma_2 < 0`` (``n2 = 1``) or not and likewise ``sigma_6``, where its
    lower-limit equation is positive (``a = 1``) or not and its upper-limit
    one likewise (``b``) (:func:`redkin.srs.joints.limit_sign_membership`).
``elbow`` : (3,) float64
    ``start, span, free`` of joint 4 for :func:`within`.

A pose's pieces are ``PIECES`` slots: piece ``j`` runs from ``start[j]`` to
``end[j]`` (``end`` may exceed ``pi``: the last piece wraps to the first
cut plus ``2 pi``); unused slots have a NaN start.  ``keep`` ``(R, 24)``
receives, per piece, row 0: feasible [000 eq. 30], and, when ``R = 7``, rows
``1 + k``: column ``k`` of ``PSI_JOINTS`` within its limits [000 eq. 29].
"""

from __future__ import annotations

from math import acos, atan2, cos, nan, pi, sin, sqrt

import numpy as np

from redkin._compiled import kernel
from redkin.circle import TWO_PI
from redkin.srs import _ik_kernels, joints
from redkin.srs.joints import STRETCHED_TOLERANCE

#: Limit equations per pose: lower and upper limit of the six psi-dependent joints.
EQUATIONS = 12
#: Piece slots per pose: at most two roots per limit equation.
PIECES = 2 * EQUATIONS
#: Pieces shorter than this (radians) are dropped: they are repeated roots split by
#: rounding, or a singular arm angle itself, where theta_1/3 or theta_5/7 are undefined.
PIECE_TOLERANCE = 1e-12
_GROUP = _ik_kernels.GROUP  # entries per group (shoulder, wrist): x, y, z, r0, r1, r2, t


# ---------------------------------------------------------------- scalars
@kernel
def turn_once(angle):
    """``angle mod 2 pi`` for ``angle`` in ``[-2 pi, 4 pi)``, with one addition or subtraction of ``2 pi``.

    Equal to the floored modulo there: ``fmod`` would subtract ``2 pi``
    exactly, and so does the subtraction (Sterbenz: ``2 pi <= angle < 4 pi``).
    """
    if angle < 0.0:
        return angle + TWO_PI
    if angle >= TWO_PI:
        return angle - TWO_PI
    return angle


@kernel
def sinusoid_roots(p, q, r, tolerance=1e-12):
    """Roots in ``[-pi, pi)`` of ``p sin psi + q cos psi + r = 0``, a pair, ``(nan, nan)`` where none.

    With ``rho = hypot(p, q)`` and ``phi = atan2(p, q)``, ``p s + q c = rho
    cos(psi - phi)``, so ``psi = phi +- acos(-r / rho)`` (the stationary points of [000 eq. 25] and the
    limit crossings of [000 eqs. 21, 22], without [000 eq. 25]'s division by ``b_t - c_t``).  Near tangency
    (``|r| <= rho (1 + tolerance)``) the double root is returned.  ``rho`` is
    taken as ``sqrt(p^2 + q^2)``: the coefficients are of order 1 (entries of
    rotations, or a normalised vector), far from overflow, and ``hypot`` cost a
    quarter of the roots' time.
    """
    rho = sqrt(p * p + q * q)
    # a root needs |r| <= rho (with the tolerance) and rho not negligible: rho > tolerance
    # suffices, because |r| <= rho (1 + tolerance) already bounds r by rho
    if not (abs(r) <= rho * (1.0 + tolerance) and rho > tolerance):
        return nan, nan
    half = acos(min(max(r / rho, -1.0), 1.0))  # acos(r / rho) = pi - acos(-r / rho)
    phi = atan2(p, q)
    # phi -+ acos(-r / rho) shifted by pi, taken back into [-pi, pi)
    return turn_once(phi + half) - pi, turn_once(phi - half) - pi


#: :func:`redkin.srs.joints.within` compiled (the same source): is a joint value within its limits.
within = kernel(joints.within)


# -------------------------------------------------- one pose, [000 eqs. 20-28]
@kernel
def limit_equations(entries, table, out):
    """Rows ``(p, q, r)`` of the twelve limit equations ``p sin psi + q cos psi + r = 0`` into ``out`` (3, 12).

    Column ``2 k + j`` is column ``k`` of ``PSI_JOINTS`` at its lower
    (``j = 0``) or upper limit (``j = 1``): [000 eqs. 21, 22] set equal to the
    limit, through the table of the module docstring.  A group (shoulder,
    wrist) whose ``x, y`` coefficients all vanish (:data:`~redkin.srs.joints.STRETCHED_TOLERANCE`) is
    singular at every arm angle -- e.g. the home pose of an arm stretched
    along the joint-1 axis -- and takes the stretched table: [000 eqs. 15, 19] are
    0/0 there for every psi, while the third joint the IK returns still
    turns with psi.  Each equation weighs the seven entries of its own group.
    """
    for group in range(2):
        largest = 0.0
        for row in range(3):
            for slot in range(2):
                largest = max(largest, abs(entries[row, _GROUP * group + slot]))
        which = 1 if largest <= STRETCHED_TOLERANCE else 0
        for e in range(6 * group, 6 * group + 6):
            for row in range(3):
                value = 0.0
                for slot in range(_GROUP * group, _GROUP * group + _GROUP):
                    value += entries[row, slot] * table[which, slot, e]
                out[row, e] = value + table[which, 14 + row, e]


@kernel
def cut_points(equations, cuts):
    """Every arm angle where a joint reaches a limit into ``cuts`` (24,) (NaN: none).

    Slots ``4 k .. 4 k + 3`` hold the roots of the two :func:`limit_equations`
    of column ``k`` of ``PSI_JOINTS`` ([000 eqs. 21, 22] at its lower and upper
    limit); an unlimited joint's equations read ``0 = 1`` and have none.
    """
    for e in range(EQUATIONS):
        cuts[2 * e], cuts[2 * e + 1] = sinusoid_roots(equations[0, e], equations[1, e], equations[2, e])


@kernel
def pieces(start, end):
    """Cuts in ``start`` (24,) (NaN: none) -> the pieces between consecutive cuts, sorted, in ``start`` and ``end``.

    The last piece wraps to the first cut plus ``2 pi``; without cuts one
    piece covers the circle, ``[-pi, pi]``.  Unused slots get a NaN start
    and the wrapped end.
    """
    count = 0
    for j in range(PIECES):  # the cuts first, in order (insertion sort: at most 24)
        value = start[j]
        if value != value:
            continue
        i = count
        while i > 0 and start[i - 1] > value:
            start[i] = start[i - 1]
            i -= 1
        start[i] = value
        count += 1
    if count == 0:
        start[0] = -pi
        count = 1
    wrap = start[0] + TWO_PI
    for j in range(count, PIECES):
        start[j] = nan
    for j in range(PIECES):
        end[j] = start[j + 1] if j + 1 < count else wrap


@kernel
def sign_patterns(equations, start, end, patterns):
    """The signs of each joint's limit equations in the middle of each used piece into ``patterns`` (24, 6).

    ``patterns[j, k] = 2 a + b``, ``a`` (``b``) whether the lower (upper)
    limit equation of column ``k`` of ``PSI_JOINTS`` is positive in the
    middle of piece ``j``.  Between consecutive cuts a joint stays on one side
    of each limit, so these signs decide its membership there (:func:`classify`).
    """
    for j in range(PIECES):
        if start[j] != start[j]:
            break
        middle = 0.5 * (start[j] + end[j])
        s, c = sin(middle), cos(middle)
        for k in range(6):
            lower = equations[0, 2 * k] * s + equations[1, 2 * k] * c + equations[2, 2 * k]
            upper = equations[0, 2 * k + 1] * s + equations[1, 2 * k + 1] * c + equations[2, 2 * k + 1]
            patterns[j, k] = 2 * (lower > 0.0) + (upper > 0.0)


@kernel
def pose_pieces(entries, equations_table, equations, start, end, patterns):
    """Pieces of one pose and elbow sign and their sign patterns [000 eqs. 20-28]: :func:`limit_equations`
    (into the scratch ``equations`` (3, 12)), :func:`cut_points`, :func:`pieces`, :func:`sign_patterns`.

    The cuts and the patterns do not depend on ``sigma_2, sigma_6``: they serve
    the four branches of the elbow sign.
    """
    limit_equations(entries, equations_table, equations)
    cut_points(equations, start)
    pieces(start, end)
    sign_patterns(equations, start, end, patterns)


# ------------------------------------------ one pose-branch, [000 eqs. 29-30]
@kernel
def classify(patterns, start, membership, elbow_inside, keep):
    """[000 eq. 29] per joint and [000 eq. 30] per piece from the sign patterns, for one branch.

    ``membership`` (6, 4) is the branch's table (``membership[n2, n6]`` of the
    module docstring); ``elbow_inside`` whether theta_4 (independent of psi,
    [000 eq. 11]) is within its limits.  Row 0 of ``keep`` (R, 24): the piece
    satisfies every limit [000 eq. 30]; rows ``1 + k`` (when ``R = 7``): column
    ``k`` of ``PSI_JOINTS`` is within its limits there [000 eq. 29].  Unused
    slots keep nothing.
    """
    every = keep.shape[0] > 1
    for j in range(PIECES):
        used = start[j] == start[j]
        feasible = used and elbow_inside
        for k in range(6):
            inside = used and membership[k, patterns[j, k]]
            feasible = feasible and inside
            if every:
                keep[1 + k, j] = inside
        keep[0, j] = feasible


@kernel
def pose_branch(entries, theta4, n2, n6, equations_table, membership, elbow, equations, patterns, start, end, keep):
    """The feasible set of one pose-branch [000 eqs. 20-30] as pieces: ``start``, ``end`` (24,) and ``keep`` (R, 24).

    ``entries`` (3, 14) and ``theta4`` are the pose's coefficients for the
    branch's elbow sign; ``n2``, ``n6`` are 1 where ``sigma_2``, ``sigma_6``
    are negative, else 0; ``equations`` (3, 12) and ``patterns`` (24, 6,
    int64) are scratch.  Returns whether theta_4 is within its limits.
    """
    pose_pieces(entries, equations_table, equations, start, end, patterns)
    elbow_inside = within(theta4, elbow[0], elbow[1], elbow[2] != 0.0)
    classify(patterns, start, membership[n2, n6], elbow_inside, keep)
    return elbow_inside


@kernel
def pose_all_branches(entries, theta4, equations_table, membership, elbow, order, equations, patterns, start, end,
                      keep):
    """The feasible sets of the eight branches of one pose: the pieces once per elbow sign, classified four ways.

    ``entries`` (2, 3, 14) and ``theta4`` (2,) for the elbow signs ``+1, -1``
    of paper 000 Table 1; the Table 1 branch with index ``i`` in
    :data:`redkin.srs.branches.BRANCHES` (``4 n2 + 2 n4 + n6``) goes to slot
    ``order[i]`` of ``start``, ``end`` (8, 24) and ``keep`` (8, R, 24).
    """
    for n4 in range(2):
        first = order[2 * n4]
        pose_pieces(entries[n4], equations_table, equations, start[first], end[first], patterns)
        elbow_inside = within(theta4[n4], elbow[0], elbow[1], elbow[2] != 0.0)
        for n2 in range(2):
            for n6 in range(2):
                slot = order[4 * n2 + 2 * n4 + n6]
                if slot != first:
                    for j in range(PIECES):  # element by element: a slice assignment compiles numba's shape checks
                        start[slot, j], end[slot, j] = start[first, j], end[first, j]
                classify(patterns, start[slot], membership[n2, n6], elbow_inside, keep[slot])


# ------------------------------------- from the pose: [000 eqs. 4-19] fused
@kernel
def pose_scratch():
    """The work arrays of :func:`pose_feasible` (one set per thread): the
    frame and coefficient arrays of :func:`redkin.srs._ik_kernels.coefficients_one`, the entries and theta_4
    of both elbow signs, the limit equations and the sign patterns."""
    return (np.empty((3, 4)), np.empty(3), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3, 3)),
            np.empty((3, 3, 3)), np.empty((2, 3, 2 * _GROUP)), np.empty(2), np.empty((3, EQUATIONS)),
            np.empty((PIECES, 6), np.int64))


@kernel
def pose_coefficients(pose, arm, ends, scratch, signs):
    """[000 eqs. 4-19] of one pose (4, 4) of the chain for the elbow signs ``+1`` (``signs`` 0 or 2) and/or ``-1``
    (1 or 2) into the scratch entries and theta_4 (:func:`redkin.srs._ik_kernels.coefficients_one`).

    Returns the status (:data:`redkin.srs._ik_kernels.OK`, ``BAD_POSE`` or ``UNREACHABLE``) and ``|x_sw|``.
    """
    target, u, reference, elbow, shoulder, wrist, entries, theta4, _, _ = scratch
    status, distance = _ik_kernels.OK, np.nan
    for e in range(2):
        if signs == 1 - e:
            continue
        status, theta4[e], distance = _ik_kernels.coefficients_one(
            pose, 1.0 - 2.0 * e, arm, ends, target, u, reference, elbow, shoulder, wrist, entries[e])
        if status != _ik_kernels.OK:
            break
    return status, distance


@kernel
def pose_feasible(pose, branches, arm, ends, equations_table, membership, elbow, scratch, start, end, keep, theta4,
                  elbow_inside):
    """The feasible sets of one pose (4, 4) of the chain on some branches, from the pose: [000 eqs. 4-30] in one
    call.

    ``branches`` (B, 3) holds the Table 1 signs ``sigma_2, sigma_4,
    sigma_6`` of each output row (:meth:`redkin.srs.geometry.SRSGeometry.kernel_branch`,
    :attr:`~redkin.srs.geometry.SRSGeometry.kernel_branches`).  Each elbow
    sign's coefficients, cuts and sign patterns are computed once and
    classified for its rows.  Writes ``start``, ``end`` (B, 24), ``keep``
    (B, R, 24) as :func:`pose_branch`, theta_4 and whether it is within its
    limits (B,); returns the status and ``|x_sw|`` of :func:`pose_coefficients`.
    """
    status, distance = _ik_kernels.OK, np.nan
    entries, angles, equations, patterns = scratch[6], scratch[7], scratch[8], scratch[9]
    for n4 in range(2):
        first = -1
        inside = False
        for b in range(branches.shape[0]):
            if (branches[b, 1] < 0.0) != (n4 == 1):
                continue
            if first < 0:
                status, distance = pose_coefficients(pose, arm, ends, scratch, n4)
                if status != _ik_kernels.OK:
                    return status, distance
                pose_pieces(entries[n4], equations_table, equations, start[b], end[b], patterns)
                inside = within(angles[n4], elbow[0], elbow[1], elbow[2] != 0.0)
                first = b
            else:
                for j in range(PIECES):  # as in pose_all_branches
                    start[b, j], end[b, j] = start[first, j], end[first, j]
            classify(patterns, start[b], membership[int(branches[b, 0] < 0.0), int(branches[b, 2] < 0.0)], inside,
                     keep[b])
            theta4[b], elbow_inside[b] = angles[n4], inside
    return status, distance


@kernel
def arc_runs(start, end, keep, out):
    """The arcs of the runs of kept pieces, each piece starting where the previous one ends, into ``out`` (K, 2).

    ``keep`` (K,) is one row of :func:`classify` (K = 24: each piece ends where the next starts), or of sorted,
    disjoint pieces (a nearly S-R-S or Franka-class arm's sets, a cell's: a gap between two kept pieces ends a
    run).  Runs not longer than :data:`PIECE_TOLERANCE` are dropped; returns how many arcs were written.
    """
    count = 0
    previous = False
    for j in range(keep.shape[0]):
        joined = keep[j] and previous and start[j] <= out[count - 1, 1]
        if previous and not joined and out[count - 1, 1] - out[count - 1, 0] <= PIECE_TOLERANCE:
            count -= 1  # the run before ended, too short
        if joined:
            out[count - 1, 1] = end[j]
        elif keep[j]:
            out[count, 0], out[count, 1] = start[j], end[j]
            count += 1
        previous = keep[j]
    if previous and out[count - 1, 1] - out[count - 1, 0] <= PIECE_TOLERANCE:
        count -= 1
    return count


# ------------------------------------------------------------------- batches
# From poses (the public path), items start..stop - 1 of a batch with one set of scratch arrays per call, launched
# through redkin._compiled.run_batch (which hands out the chunks).  From coefficients computed beforehand (paths,
# optimal arm angles: a Python loop over the poses follows) a plain loop over the batch.


@kernel
def branches(entries, theta4, n2, n6, equations_table, membership, elbow, start, end, keep, elbow_inside):
    """:func:`pose_branch` for each pose of ``entries`` (N, 3, 14), ``theta4`` (N,), one branch.

    Writes ``start``, ``end`` (N, 24), ``keep`` (N, R, 24) and ``elbow_inside`` (N,).
    """
    equations, patterns = np.empty((3, EQUATIONS)), np.empty((PIECES, 6), np.int64)
    for b in range(entries.shape[0]):
        elbow_inside[b] = pose_branch(entries[b], theta4[b], n2, n6, equations_table, membership, elbow,
                                      equations, patterns, start[b], end[b], keep[b])


@kernel
def batch_arc_runs(start, end, keep, out, counts):
    """:func:`arc_runs` of every row of ``keep`` (N, R, K), packed: the arcs of pose ``b`` row after row from
    ``out[b, 0]`` (``out`` (N, K R, 2)), how many per row in ``counts`` (N, R).

    Serial only: it feeds a Python loop that builds one :class:`~redkin.circle.ArcSet` per row.
    """
    for b in range(keep.shape[0]):
        used = 0
        for row in range(keep.shape[1]):
            counts[b, row] = arc_runs(start[b], end[b], keep[b, row], out[b, used:])
            used += counts[b, row]


@kernel
def all_branches(entries, theta4, equations_table, membership, elbow, order, start, end, keep):
    """:func:`pose_all_branches` for each pose of ``entries`` (N, 2, 3, 14), ``theta4`` (N, 2).

    Writes ``start``, ``end`` (N, 8, 24) and ``keep`` (N, 8, R, 24).
    """
    equations, patterns = np.empty((3, EQUATIONS)), np.empty((PIECES, 6), np.int64)
    for b in range(entries.shape[0]):
        pose_all_branches(entries[b], theta4[b], equations_table, membership, elbow, order,
                          equations, patterns, start[b], end[b], keep[b])


@kernel
def poses_feasible(start, stop, poses, branches, arm, ends, equations_table, membership, elbow, status, distance,
                   theta4, elbow_inside, start_angles, end_angles, keep):
    """:func:`pose_feasible` for poses ``start .. stop - 1`` of ``poses`` (N, 4, 4) on the branches (B, 3), into
    ``status``, ``distance`` (N,), ``theta4``, ``elbow_inside`` (N, B), ``start_angles``, ``end_angles``
    (N, B, 24) and ``keep`` (N, B, R, 24).

    Returns how many of those poses failed (a status other than :data:`redkin.srs._ik_kernels.OK`).
    """
    scratch = pose_scratch()
    failed = 0
    for n in range(start, stop):
        status[n], distance[n] = pose_feasible(poses[n], branches, arm, ends, equations_table, membership, elbow,
                                               scratch, start_angles[n], end_angles[n], keep[n], theta4[n],
                                               elbow_inside[n])
        failed += status[n] != _ik_kernels.OK
    return failed
