"""The compiled core of nearly S-R-S arm-angle IK (:mod:`redkin.srs.nearly`): one call solves a pose on every branch.

For one pose, arm angle and branch, :func:`solve_one`

1. corrects the neighbour's target a few times (:func:`corrections`): move it
   just inside the neighbour's reach, solve the neighbour at the arm angle
   [000 eqs. 4-19] (:func:`redkin.srs._ik_kernels.solve_pose`), take the real
   arm's pose of that solution (:func:`redkin._chain_kernels.frames_one`) and
   correct the target ``T' <- T G^-1 T'``, keeping the solution of the
   smallest error (:func:`redkin.numerical._kernels.pose_error`);
2. takes damped Newton steps on the real arm for the 7 equations, pose and arm
   angle (:func:`newton`), with the arm angle's gradient in closed form
   (:func:`arm_angle_one`), each step kept on the branch
   (:func:`kept_on_side`); where they do not end on the branch, once more
   with the elbow opened from its stretch (:func:`opened`);
3. certifies the solution as returned and keeps it only on its own branch, by
   the real arm's signs (:func:`branch_signs`);
4. for a branch still missing, starts from the other branches' solutions
   (:func:`flipped`), from the neighbour at nearby arm angles, and near a
   singular shoulder or wrist from the neighbour's solution turned along the
   singular direction (:func:`turned`).

Inputs are trusted.
"""

from __future__ import annotations

from math import atan2, isfinite, pi, sqrt

import numpy as np

from redkin import _array_copy, _chain_kernels
from redkin._compiled import kernel
from redkin._pose_kernels import pose_defect
from redkin.circle import HALF_PI, TWO_PI
from redkin.numerical._kernels import DAMPING, DAMPING_FLOOR, MAX_STEP, nearest_pose, pose_error
from redkin.srs._ik_kernels import (
    A3,
    A4,
    D_EW,
    D_SE,
    D_WT,
    OK,
    PHASE,
    _scratch,
    chain_values,
    elbow_frame,
    solve_pose,
    table1_target,
    turns_removed,
    wrist_point,
)

#: Entries of the ``reach`` array: the neighbour's shortest and longest shoulder-wrist distance (moved inside by a
#: relative 1e-9), the wrist-to-flange length ``d_7``, and the shoulder point (3).
LOW, HIGH, WRIST_LENGTH, SHOULDER = 0, 1, 2, 3
#: The certificate of a solution: position error [m], rotation angle [rad] and arm-angle error [rad].
TOLERANCE = 1e-9
#: Corrections of the neighbour's target per branch at most (they stop when the error stops shrinking).
CORRECTIONS = 3
#: Newton's steps per start at most; a start is given up when its error has not halved over ``STALL`` steps, and
#: ends at ``FINE`` (position plus rotation plus arm angle: rounding).
NEWTON_ITERATIONS, STALL, FINE = 30, 6, 1e-12
#: How far apart in arm angle [rad] two items of one pose and branch may be for :func:`solve_continued` to start the
#: later one's Newton steps from the earlier one's solution.
CONTINUED = 0.25
#: Slack [rad] of :func:`within_limits`.
LIMIT_SLACK = 1e-9
#: How far from its stretch [rad] the second start's elbow is opened (:func:`opened`).
OPENED = 0.05
#: The last starts of a branch not found otherwise: the neighbour's solutions at ``psi +- k SWEEP_STEP``, ``k = 1 ..
#: SWEEP``.  Near theta_2 = +-pi with the elbow stretched, or the wrist near axis 1, the arm angle turns fast with
#: the joints and the real arm's solution lies nearer the neighbour's at another arm angle (measured on 3000 Gen3
#: poses: of 99 branches missed without these starts, 67 found at 15 deg, 87 within 30 deg, 92 within 45 deg).
SWEEP, SWEEP_STEP = 3, TWO_PI / 24.0
#: The last starts of a missing branch whose neighbour's solution lies near a singular shoulder or wrist (``|sin
#: theta_2|`` or ``|sin theta_6|`` below ``TURNED_SINE``): there the real arm's outer joints of the group turn fast
#: with the arm angle (half a turn within a few mrad on the Gen3), and Newton's steps converge only from within a
#: few tenths of a radian along the singular direction (measured on the Gen3 and the ROS-I iiwa).  The pose error
#: of a turned start does not point to it (the smallest lies near the unturned start, which failed), so the
#: neighbour's solution is turned (:func:`turned`) by ``+-k 2 pi / TURNED``, the smallest turns first.
TURNED, TURNED_SINE = 16, 0.1


@kernel
def within_reach(moved, tool_inverse, reach):
    """Move the target ``moved`` (4, 4) in place along the shoulder-wrist line to within the neighbour's reach
    ([000 eq. 11]), where it lies outside."""
    span = np.empty(3)
    length = 0.0
    for r in range(3):
        origin = moved[r, 0] * tool_inverse[0, 3] + moved[r, 1] * tool_inverse[1, 3] + moved[r, 2] * tool_inverse[2, 3]
        axis = moved[r, 0] * tool_inverse[0, 2] + moved[r, 1] * tool_inverse[1, 2] + moved[r, 2] * tool_inverse[2, 2]
        span[r] = moved[r, 3] + origin - reach[WRIST_LENGTH] * axis - reach[SHOULDER + r]
        length += span[r] * span[r]
    length = sqrt(length)
    wanted = min(max(length, reach[LOW]), reach[HIGH])
    if wanted != length and length > 0.0:
        for r in range(3):
            moved[r, 3] += (wanted - length) / length * span[r]


@kernel
def corrected(target, reached, moved, product):
    """``T' <- T G^-1 T'`` in place on ``moved`` (4, 4), with ``G = reached``, its rotation then the nearest
    rotation (:func:`redkin.numerical._kernels.nearest_pose`); ``product`` (2, 4, 4) is scratch."""
    inverse = product[0]
    for r in range(3):  # G^-1 of a rigid motion: R^T, -R^T p
        for c in range(3):
            inverse[r, c] = reached[c, r]
        inverse[r, 3] = -(reached[0, r] * reached[0, 3] + reached[1, r] * reached[1, 3] + reached[2, r] * reached[2, 3])
    inverse[3, 0], inverse[3, 1], inverse[3, 2], inverse[3, 3] = 0.0, 0.0, 0.0, 1.0
    step = product[1]
    for r in range(4):
        for c in range(4):
            step[r, c] = target[r, 0] * inverse[0, c] + target[r, 1] * inverse[1, c] + target[r, 2] * inverse[2, c] \
                + target[r, 3] * inverse[3, c]
    for r in range(4):
        for c in range(4):
            inverse[r, c] = step[r, 0] * moved[0, c] + step[r, 1] * moved[1, c] + step[r, 2] * moved[2, c] \
                + step[r, 3] * moved[3, c]
    nearest_pose(inverse, moved)



# ------------------------------------------------------------------ the arm angle of the real arm and its gradient
@kernel
def arm_angle_one(q, neighbour, neighbour_ends, arm, ends, work, gradient, with_gradient):
    """The real arm's arm angle at ``q`` (7,): the neighbour's at the same joint values [000 eqs. 5-8]; with
    ``with_gradient``, its gradient ``d psi / d q`` into ``gradient`` (7,) (derived below, in closed form).

    ``neighbour`` and ``neighbour_ends`` are the neighbour's link table and ends (standard DH, Table 1 form), ``arm``
    and ``ends`` its kernel arm and ends (:mod:`redkin.srs._ik_kernels`).  ``0R3 = R_psi 0R3o`` [000 eq. 8]: ``psi``
    is the angle of ``R_psi = 0R3 0R3o^T`` about the shoulder-wrist direction ``u``, the reference ``0R3o`` that of
    the elbow sign of ``theta_4`` (:func:`redkin.srs._ik_kernels.elbow_frame`).

    Gradient: ``R_psi = A B^T`` with ``A = 0R3`` and ``B = 0R3o``, so its angular velocity is ``w_A - R_psi w_B``
    and, ``R_psi`` being a turn about ``u`` (``R_psi^T u = u``), ``d psi = u . (w_A - w_B)`` whatever ``u``
    does.  ``w_A`` of joint ``j <= 3`` is its axis; ``B = Rz(theta_1o) Rx(-pi/2) Rz(theta_2o)`` turns with
    ``d theta_1o z + d theta_2o (-s_1, c_1, 0)``, where ``theta_1o = atan2(y, x)`` and ``theta_2o = atan2(-z, w) -
    atan2(v_y, v_x)`` move with the wrist ``x_sw`` (its velocity ``axis_j x (x_w - o_j)`` for joints 1-4) and
    ``v`` with ``theta_4``.  Joints 5-7 do not move it.
    """
    frames, trig, target, u, reference, elbow = work
    _chain_kernels.frames_one(q, neighbour, neighbour_ends, np.bool_(True), trig, frames)
    table1_target(frames[8], ends, target)
    shared, _, _ = wrist_point(target, arm, u)
    theta4 = neighbour[3, _chain_kernels.OFFSET] + neighbour[3, _chain_kernels.SIGN] * q[3]
    sign = 1.0 if turns_removed(theta4 - arm[PHASE] + pi) - pi >= 0.0 else -1.0  # Table 1's elbow sign
    elbow_frame(shared, arm, sign, reference, elbow)
    m = np.empty((3, 3))  # R_psi = 0R3 0R3o^T, 0R3 = R_base^T R_3
    for r in range(3):
        for c in range(3):
            m[r, c] = 0.0
            for k in range(3):
                shoulder = (frames[0, 0, r] * frames[3, 0, k] + frames[0, 1, r] * frames[3, 1, k]
                            + frames[0, 2, r] * frames[3, 2, k])
                m[r, c] += shoulder * reference[c, k]
    sine = 0.5 * (u[0] * (m[2, 1] - m[1, 2]) + u[1] * (m[0, 2] - m[2, 0]) + u[2] * (m[1, 0] - m[0, 1]))
    psi = atan2(sine, 0.5 * (m[0, 0] + m[1, 1] + m[2, 2] - 1.0))
    if not with_gradient:
        return psi
    w, c1, s1, z = shared[0], shared[1], shared[2], shared[3]
    x, y = w * c1, w * s1
    w = max(w, 1e-12)
    c4, s4 = elbow[0, 0], elbow[1, 0]
    v_x = arm[A3] + arm[A4] * c4 + arm[D_EW] * s4
    v_y = arm[A4] * s4 - (arm[D_SE] + arm[D_EW] * c4)
    beta = (v_x * (arm[A4] * c4 + arm[D_EW] * s4) - v_y * (arm[D_EW] * c4 - arm[A4] * s4)) / (v_x * v_x + v_y * v_y)
    wrist0 = target[0, 3] - target[0, 2] * arm[D_WT]  # x_w in frame 0
    wrist1 = target[1, 3] - target[1, 2] * arm[D_WT]
    wrist2 = target[2, 3] - target[2, 2] * arm[D_WT]
    for j in range(4, 7):
        gradient[j] = 0.0
    for j in range(4):
        axis, base = frames[j, :3, 2], frames[0]  # joint j's axis: frame j - 1's z (standard DH), in the world
        sense = neighbour[j, _chain_kernels.SIGN]
        a0 = sense * (base[0, 0] * axis[0] + base[1, 0] * axis[1] + base[2, 0] * axis[2])  # in frame 0
        a1 = sense * (base[0, 1] * axis[0] + base[1, 1] * axis[1] + base[2, 1] * axis[2])
        a2 = sense * (base[0, 2] * axis[0] + base[1, 2] * axis[1] + base[2, 2] * axis[2])
        p0, p1, p2 = frames[j, 0, 3] - base[0, 3], frames[j, 1, 3] - base[1, 3], frames[j, 2, 3] - base[2, 3]
        d0 = wrist0 - (base[0, 0] * p0 + base[1, 0] * p1 + base[2, 0] * p2)  # x_w - o_j in frame 0
        d1 = wrist1 - (base[0, 1] * p0 + base[1, 1] * p1 + base[2, 1] * p2)
        d2 = wrist2 - (base[0, 2] * p0 + base[1, 2] * p1 + base[2, 2] * p2)
        moved_x, moved_y, moved_z = a1 * d2 - a2 * d1, a2 * d0 - a0 * d2, a0 * d1 - a1 * d0
        turn1 = (x * moved_y - y * moved_x) / (w * w)
        moved_w = (x * moved_x + y * moved_y) / w
        turn2 = (z * moved_w - w * moved_z) / (w * w + z * z)
        if j == 3:  # theta_4 turns v as well
            turn2 -= neighbour[3, _chain_kernels.SIGN] * beta
        own = u[0] * a0 + u[1] * a1 + u[2] * a2 if j < 3 else 0.0
        gradient[j] = own - (u[2] * turn1 + (c1 * u[1] - s1 * u[0]) * turn2)
    return psi


# ------------------------------------------------------------------ Newton's steps on the 7 equations
@kernel
def measured(q, target, psi, real, model, work, gradient, with_gradient, e):
    """Our FK of ``q`` on the real arm and its pose error [N1] against ``target`` into ``e[:6]``, the arm-angle
    error ``psi - psi(q)`` (wrapped) into ``e[6]``; returns the position error [m], rotation angle [rad] and
    ``|e[6]|``.  ``real`` is the real chain's ``(links, ends, standard)``, ``model`` the neighbour's ``(links,
    ends, kernel arm, kernel ends)`` (:func:`arm_angle_one`), ``work`` the scratch of :func:`scratch`."""
    links, ends, standard = real
    trig, pose = work[0], work[1]
    _chain_kernels.frames_one(q, links, ends, standard, trig, pose)
    position, angle = pose_error(target, pose[0], e)
    value = arm_angle_one(q, model[0], model[1], model[2], model[3], work[2], gradient, with_gradient)
    e[6] = turns_removed(psi - value + pi) - pi
    return position, angle, abs(e[6])


@kernel
def newton(q, target, psi, real, model, work, best, side, real_phase):
    """Damped Newton steps on the 7 equations ``FK(q) = T``, ``psi(q) = psi`` from ``q`` (7,), the Jacobian
    our geometric one [N1] over the gradient of :func:`arm_angle_one`; the iterate of the smallest error (position
    plus rotation plus arm angle) into ``best`` (7,), returned with its three errors.

    The step is ``dq = J^T y`` with ``(J J^T + lambda I) y = e`` [N2]-[N3] (``lambda`` as the numerical IK's,
    :data:`redkin.numerical._kernels.DAMPING`), at most :data:`redkin.numerical._kernels.MAX_STEP` in any joint.
    Each step stays on the branch ``side`` (3,) (Table 1 signs, :func:`branch_signs`): a joint 2, 4 or 6 that it
    would take across its branch's boundary (``theta = 0`` or ``pi``, from the real stretched elbow ``real_phase``
    for joint 4) goes half way to it instead (:func:`kept_on_side`).  It stops at rounding (:data:`FINE`), after
    :data:`NEWTON_ITERATIONS`, or once the error has not halved over :data:`STALL` steps.
    """
    links, ends, standard = real
    trig = work[0]
    e, gradient, jac, a, y, dq, origin = work[3], work[4], work[5], work[6], work[7], work[8], work[9]
    smallest = (np.inf, np.inf, np.inf)
    checkpoint = np.inf
    for iteration in range(NEWTON_ITERATIONS):
        position, angle, turn = measured(q, target, psi, real, model, work, gradient, np.bool_(True), e)
        size = position + angle + turn
        if size < smallest[0] + smallest[1] + smallest[2]:
            smallest = (position, angle, turn)
            _array_copy.copy_into(best, q)
        if size <= FINE or not isfinite(size):
            break
        if iteration % STALL == 0:
            if size > 0.5 * checkpoint:
                break
            checkpoint = size
        # q as measured: its sines and cosines are in trig
        _chain_kernels.jacobian_from_trig(links, ends, standard, np.int64(7), np.bool_(True), origin, trig, jac)
        for c in range(7):
            jac[6, c] = gradient[c]
        damping = DAMPING_FLOOR + DAMPING * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] + e[4] * e[4]
                                             + e[5] * e[5] + e[6] * e[6])
        for r in range(7):
            y[r] = e[r]
            for c in range(r + 1):
                value = 0.0
                for k in range(7):
                    value += jac[r, k] * jac[c, k]
                a[r, c] = value
            a[r, r] += damping
        for r in range(7):  # Cholesky a = L L^T, then L z = e and L^T y = z
            for c in range(r + 1):
                value = a[r, c]
                for k in range(c):
                    value -= a[r, k] * a[c, k]
                a[r, c] = sqrt(max(value, DAMPING_FLOOR)) if r == c else value / a[c, c]
        for r in range(7):
            value = y[r]
            for k in range(r):
                value -= a[r, k] * y[k]
            y[r] = value / a[r, r]
        for r in range(6, -1, -1):
            value = y[r]
            for k in range(r + 1, 7):
                value -= a[k, r] * y[k]
            y[r] = value / a[r, r]
        largest = 0.0
        for k in range(7):
            step = 0.0
            for r in range(7):
                step += jac[r, k] * y[r]
            dq[k] = step
            largest = max(largest, abs(step))
        scale = MAX_STEP / largest if largest > MAX_STEP else 1.0
        for k in range(7):
            moved = q[k] + scale * dq[k]
            if k % 2 == 1:
                moved = kept_on_side(q[k], moved, model[0], k, side[k // 2], real_phase if k == 3 else 0.0)
            q[k] = moved
    return smallest


@kernel
def kept_on_side(old, new, neighbour, k, sense, centre):
    """Joint ``k``'s value ``new``, or where it leaves the side ``sense`` (+-1) of its branch (the neighbour's
    ``theta - centre`` in ``(0, pi)`` for +1, ``(-pi, 0)`` for -1, wrapped) that ``old`` lies on, the point half
    way from ``old`` to the boundary it crosses."""
    sign, offset = neighbour[k, _chain_kernels.SIGN], neighbour[k, _chain_kernels.OFFSET]
    after = turns_removed(offset + sign * new - centre + pi) - pi
    if (after >= 0.0) == (sense > 0.0):
        return new
    before = turns_removed(offset + sign * old - centre + pi) - pi
    if (before >= 0.0) != (sense > 0.0):
        return new  # not on the side to begin with: nothing to keep
    if abs(after) < HALF_PI:  # across 0
        kept = 0.5 * before
    else:  # across +-pi
        kept = before + 0.5 * ((pi if before >= 0.0 else -pi) - before)
    return new + sign * (kept - after)


# ------------------------------------------------------------------ one pose, all branches
@kernel
def branch_signs(q, neighbour, real_phase, signs):
    """The real arm's branch of ``q`` (7,) into ``signs`` (3,): the signs of the neighbour's ``theta_2``, ``theta_4
    - real_phase`` (the real arm's stretched elbow) and ``theta_6`` at the same joint values, wrapped to
    ``[-pi, pi)``, zero counting as +."""
    for k in range(3):
        j = 2 * k + 1
        theta = neighbour[j, _chain_kernels.OFFSET] + neighbour[j, _chain_kernels.SIGN] * q[j]
        if j == 3:
            theta -= real_phase
        signs[k] = 1.0 if turns_removed(theta + pi) - pi >= 0.0 else -1.0


@kernel
def opened(q, neighbour, phase, sense, start):
    """``q`` (7,) with the neighbour's ``theta_4`` at least :data:`OPENED` rad from ``phase`` on the side
    ``sense`` (+-1), into ``start`` (7,): near the stretch the arm angle's gradient vanishes, a start from which
    Newton's steps go nowhere."""
    _array_copy.copy_into(start, q)
    sign, offset = neighbour[3, _chain_kernels.SIGN], neighbour[3, _chain_kernels.OFFSET]
    theta = turns_removed(offset + sign * q[3] - phase + pi) - pi
    theta = phase + sense * max(abs(theta), OPENED)
    start[3] = sign * (theta - offset)


@kernel
def scratch():
    """The scratch arrays of :func:`solve_one`, made once per batch: those of :func:`newton` and of
    :func:`corrections`, five joint vectors, and each branch's primary solution and its branch
    (:func:`primary`)."""
    model_work = (np.empty((9, 4, 4)), np.empty((7, 2)), np.empty((3, 4)), np.empty(3), np.empty((3, 3)),
                  np.empty((3, 3)))
    work = (np.empty((7, 2)), np.empty((1, 4, 4)), model_work, np.empty(7), np.empty(7), np.empty((7, 7)),
            np.empty((7, 7)), np.empty(7), np.empty(7), np.zeros(3))
    correction = (_scratch(), np.empty((4, 4)), np.empty((1, 7)), np.empty((7, 2)), np.empty((1, 4, 4)), np.empty(6),
                  np.empty((2, 4, 4)))
    vectors = np.empty((5, 7))
    return work, correction, vectors, np.empty((8, 7)), np.empty(8, dtype=np.int64)


@kernel
def corrections(target, psi, signs, geometry, real, tool_inverse, reach, q, work):
    """A few corrections of the neighbour's target ``T' <- T G^-1 T'`` (module docstring) on the branch ``signs``
    (1, 3), the closed form's solution [000 eqs. 4-19] of the smallest pose error into ``q`` (7,); returns whether
    the neighbour reached a target."""
    arm, model_ends, joints = geometry
    links, chain_ends, standard = real
    closed, moved, trial, trig, reached, e, product = work
    _array_copy.copy_rows_into(moved, target)
    best = np.inf
    for _ in range(CORRECTIONS):
        within_reach(moved, tool_inverse, reach)
        if solve_pose(moved, psi, signs, arm, model_ends, joints, trial, closed) != OK:
            return best < np.inf
        _chain_kernels.frames_one(trial[0], links, chain_ends, standard, trig, reached)
        position, angle = pose_error(target, reached[0], e)
        if position + angle < best:
            _array_copy.copy_into(q, trial[0])
            best = position + angle
        else:
            break
        corrected(target, reached[0], moved, product)
    return True


@kernel
def certified_branch(q, target, psi, side, signs, geometry, real, model, real_phase, work):
    """Newton's steps (:func:`newton`, kept on the branch ``side`` (3,)) from ``q`` (7,), the result normalised to
    the chain's joint ranges
    (:func:`redkin.srs._ik_kernels.chain_values`) into ``q`` and certified as returned (FK within
    :data:`TOLERANCE` of the target, arm angle within :data:`TOLERANCE` of ``psi``); returns the row of ``signs``
    (8, 3) of its branch (:func:`branch_signs`), or -1 where it is not certified."""
    newton_work, _, vectors, _, _ = work
    joints, neighbour = geometry[2], model[0]
    best, theta, label = vectors[1], vectors[2], vectors[3]
    e, gradient = newton_work[3], newton_work[4]
    position, angle, turn = newton(q, target, psi, real, model, newton_work, best, side, real_phase)
    if position > TOLERANCE or angle > TOLERANCE or turn > TOLERANCE:
        return -1
    for k in range(7):
        theta[k] = neighbour[k, _chain_kernels.OFFSET] + neighbour[k, _chain_kernels.SIGN] * best[k]
    chain_values(theta, joints, q)
    moved = False
    for k in range(7):  # whole turns only: a value the map merely rounds stays bit for bit
        if abs(q[k] - best[k]) < 1.0:
            q[k] = best[k]
        else:
            moved = True
    if moved:  # the certificate is of the joint values returned
        position, angle, turn = measured(q, target, psi, real, model, newton_work, gradient, np.bool_(False), e)
        if position > TOLERANCE or angle > TOLERANCE or turn > TOLERANCE:
            return -1
    branch_signs(q, neighbour, real_phase, label)
    for row in range(signs.shape[0]):
        if label[0] == signs[row, 0] and label[1] == signs[row, 1] and label[2] == signs[row, 2]:
            return row
    return -1


@kernel
def primary(b, target, psi, signs, geometry, real, model, tool_inverse, reach, real_phase, work):
    """The first starts of branch ``b`` (a row of ``signs``, (8, 3)): corrections of the neighbour's target
    (:func:`corrections`), then :func:`certified_branch`; where that is not certified on ``b``, once more with the
    elbow opened (:func:`opened`).  Writes the solution into ``work``'s primaries (the one on ``b``, else the first
    certified one, on another branch) and returns its branch, or -1."""
    _, correction_work, vectors, found, labels = work
    start, seed = vectors[0], vectors[4]
    labels[b] = -1
    if not corrections(target, psi, signs[b:b + 1], geometry, real, tool_inverse, reach, seed, correction_work):
        return -1
    for attempt in range(2):
        if attempt == 0:
            _array_copy.copy_into(start, seed)
        else:
            opened(seed, model[0], geometry[0][PHASE], signs[b, 1], start)
        label = certified_branch(start, target, psi, signs[b], signs, geometry, real, model, real_phase, work)
        if label >= 0 and labels[b] < 0:
            labels[b] = label
            _array_copy.copy_into(found[b], start)
        if label == b:
            labels[b] = b
            _array_copy.copy_into(found[b], start)
            break
    return labels[b]


@kernel
def flipped(q, neighbour, phase, to, signs, start):
    """A start for the branch ``to`` (3,) from a solution ``q`` (7,) on the branch ``signs`` (3,), into ``start``:
    the shoulder's ``(theta_1 + pi, -theta_2, theta_3 + pi)`` and likewise the wrist's where their signs differ (the
    exact arm's other branch), the elbow mirrored across ``phase`` and opened (:func:`opened`) where its sign
    differs."""
    for k in range(7):
        start[k] = neighbour[k, _chain_kernels.OFFSET] + neighbour[k, _chain_kernels.SIGN] * q[k]
    for group in range(2):
        if to[2 * group] != signs[2 * group]:
            first = 4 * group
            start[first] += pi
            start[first + 1] = -start[first + 1]
            start[first + 2] += pi
    if to[1] != signs[1]:
        start[3] = 2.0 * phase - start[3]
    for k in range(7):
        start[k] = neighbour[k, _chain_kernels.SIGN] * (start[k] - neighbour[k, _chain_kernels.OFFSET])
    if to[1] != signs[1]:
        opened(start.copy(), neighbour, phase, to[1], start)


@kernel
def turned(q, neighbour, group, angle, start):
    """``q`` (7,) with the shoulder's (``group`` 0) or wrist's (1) outer joints turned by ``angle`` along their
    singular direction (:data:`TURNED`), into ``start`` (7,): for the shoulder ``theta_1 + angle`` and ``theta_3 -
    angle`` where ``cos theta_2 >= 0`` (their sum, which the pose fixes at ``theta_2 = 0``, stays), ``theta_3 +
    angle`` otherwise (their difference stays); for the wrist likewise ``theta_5``, ``theta_6``, ``theta_7``."""
    _array_copy.copy_into(start, q)
    first = 4 * group
    middle = neighbour[first + 1, _chain_kernels.OFFSET] + neighbour[first + 1, _chain_kernels.SIGN] * q[first + 1]
    start[first] += neighbour[first, _chain_kernels.SIGN] * angle
    start[first + 2] += neighbour[first + 2, _chain_kernels.SIGN] * (-angle if np.cos(middle) >= 0.0 else angle)


@kernel
def near_singular(q, neighbour, group):
    """Whether the neighbour's ``theta_2`` (``group`` 0) or ``theta_6`` (1) at ``q`` (7,) has ``|sin|`` below
    :data:`TURNED_SINE`."""
    j = 4 * group + 1
    return abs(np.sin(neighbour[j, _chain_kernels.OFFSET] + neighbour[j, _chain_kernels.SIGN] * q[j])) < TURNED_SINE


@kernel
def turned_solution(base, target, psi, b, signs, geometry, real, model, real_phase, work, q):
    """Newton's steps (:func:`certified_branch`) from ``base`` (7,) turned along each singular direction it lies near
    (:data:`TURNED`, :func:`turned`), the first certified on branch ``b`` into ``q`` (7,); returns whether one was
    found.  ``base`` is not written."""
    start = work[2][0]
    for group in range(2):
        if not near_singular(base, model[0], group):
            continue
        for k in range(1, TURNED):
            turned(base, model[0], group, ((k + 1) // 2) * (TWO_PI / TURNED) * (1.0 if k % 2 == 1 else -1.0), start)
            if certified_branch(start, target, psi, signs[b], signs, geometry, real, model, real_phase, work) == b:
                _array_copy.copy_into(q, start)
                return True
    return False


@kernel
def solve_one(target, psi, rows, signs, geometry, real, model, tool_inverse, reach, real_phase, q, exists, work):
    """The branches ``rows`` (R,) (rows of ``signs``, (8, 3), the Table 1 signs of every branch) of one pose
    ``target`` (4, 4) at arm angle ``psi``: the certified solution into ``q[r]`` (7,) and ``exists[r]``, or zeros and
    ``False``.

    A branch's first starts are :func:`primary`'s.  Where they end elsewhere, the branch takes, in this order, the
    first other branch's primary solution that landed on it, or Newton's steps (:func:`certified_branch`) from the
    primary solutions of the three branches that differ from it in one sign, :func:`flipped` to it, from the
    neighbour's solutions on the branch at nearby arm angles (:data:`SWEEP`), or, where the neighbour's solution on
    the branch lies near a singular shoulder or wrist, from it turned along the singular direction
    (:func:`turned_solution`).  A row is
    computed the same whichever other rows are asked for, holds one solution of its own branch (the real arm's
    signs, :func:`branch_signs`), and two rows never hold the same solution.
    """
    _, _, vectors, found, labels = work
    start, seed = vectors[0], vectors[4]
    done = np.zeros(signs.shape[0], dtype=np.bool_)
    for r in range(rows.shape[0]):
        b = rows[r]
        q[r, :] = 0.0
        exists[r] = False
        if not done[b]:
            primary(b, target, psi, signs, geometry, real, model, tool_inverse, reach, real_phase, work)
            done[b] = True
        if labels[b] == b:
            _array_copy.copy_into(q[r], found[b])
            exists[r] = True
    for r in range(rows.shape[0]):
        if exists[r]:
            continue
        b = rows[r]
        for o in range(signs.shape[0]):
            if not done[o]:
                primary(o, target, psi, signs, geometry, real, model, tool_inverse, reach, real_phase, work)
                done[o] = True
        for o in range(signs.shape[0]):
            if o != b and labels[o] == b:
                _array_copy.copy_into(q[r], found[o])
                exists[r] = True
                break
        for o in range(signs.shape[0]):  # the branches that differ from it in one sign
            if exists[r] or labels[o] != o:
                continue
            count = 0
            for k in range(3):
                count += signs[o, k] != signs[b, k]
            if count != 1:
                continue
            flipped(found[o], model[0], real_phase, signs[b], signs[o], start)
            if certified_branch(start, target, psi, signs[b], signs, geometry, real, model, real_phase, work) == b:
                _array_copy.copy_into(q[r], start)
                exists[r] = True
        for k in range(2 * SWEEP):
            if exists[r]:
                break
            moved = psi + (k // 2 + 1) * SWEEP_STEP * (1.0 if k % 2 == 0 else -1.0)
            if not corrections(target, moved, signs[b:b + 1], geometry, real, tool_inverse, reach, start, work[1]):
                break
            if certified_branch(start, target, psi, signs[b], signs, geometry, real, model, real_phase, work) == b:
                _array_copy.copy_into(q[r], start)
                exists[r] = True
        if exists[r] or not corrections(target, psi, signs[b:b + 1], geometry, real, tool_inverse, reach, seed,
                                        work[1]):
            continue
        exists[r] = turned_solution(seed, target, psi, b, signs, geometry, real, model, real_phase, work, q[r])


@kernel
def within_limits(q, limits):
    """Whether ``q`` (7,) is within the joint limits modulo whole turns, with 1e-9 rad of slack: ``limits`` (3, 7)
    holds the lower limits, the widths and whether a joint covers the circle (as
    :meth:`redkin.chain.SerialChain.within_limits` with ``wrap=True`` reads them)."""
    for k in range(7):
        if limits[2, k] == 0.0 and turns_removed(q[k] - limits[0, k] + LIMIT_SLACK) > limits[1, k] + 2.0 * LIMIT_SLACK:
            return False
    return True


@kernel
def solve(start, stop, targets, psi, rows, signs, geometry, real, model, tool_inverse, reach, real_phase, limits, q,
          exists, inside):
    """:func:`solve_one` for poses ``start .. stop - 1`` of ``targets`` (N, 4, 4) at ``psi`` (N,) on the branches
    ``rows`` (R,) of ``signs`` (8, 3), into ``q`` (N, R, 7), ``exists`` (N, R) and ``inside`` (N, R), whether a
    solution is within the limits (:func:`within_limits`); returns how many targets are not poses
    (:func:`redkin._pose_kernels.pose_defect`; their rows are missing)."""
    work = scratch()
    bad = 0
    for n in range(start, stop):
        if pose_defect(targets[n]) != OK:
            bad += 1
            q[n, :, :] = 0.0
            exists[n, :] = False
            inside[n, :] = False
            continue
        solve_one(targets[n], psi[n], rows, signs, geometry, real, model, tool_inverse, reach, real_phase, q[n],
                  exists[n], work)
        for r in range(rows.shape[0]):
            inside[n, r] = exists[n, r] and within_limits(q[n, r], limits)
    return bad


@kernel
def solve_continued(start, stop, firsts, order, targets, psi, branch, signs, geometry, real, model, tool_inverse,
                    reach, real_phase, q, exists):
    """One branch's certified solution of each item, groups ``start .. stop - 1`` of ``firsts`` (G + 1,): group ``g``
    is the items ``order[firsts[g]:firsts[g + 1]]``, one pose and branch, arm angles increasing.  Item ``n`` is pose
    ``targets[n]`` (N, 4, 4) (validated) at ``psi[n]`` on the row ``branch[n]`` of ``signs`` (8, 3); its solution
    goes into ``q[n]`` (N, 7) and ``exists[n]``.

    Where the item before it in its group has a solution within :data:`CONTINUED` of arm angle, Newton's steps
    start from that solution (:func:`certified_branch`: certified, normalised and on the branch as
    :func:`solve_one`'s rows are), a continuation along the self-motion that skips :func:`solve_one`'s corrections
    of the neighbour's target and starts nearer; where they are not certified on the branch, and for the first
    item, :func:`solve_one` solves it.  A group's answers do not depend on the other groups, so not on how
    a batch is split."""
    work = scratch()
    trial = np.empty(7)
    row = np.empty(1, dtype=np.int64)
    one_q = np.empty((1, 7))
    one_exists = np.empty(1, dtype=np.bool_)
    for g in range(start, stop):
        previous = np.int64(-1)
        for k in range(firsts[g], firsts[g + 1]):
            n = order[k]
            b = branch[n]
            found = False
            if previous >= 0 and exists[previous] and abs(psi[n] - psi[previous]) <= CONTINUED:
                _array_copy.copy_into(trial, q[previous])
                if certified_branch(trial, targets[n], psi[n], signs[b], signs, geometry, real, model, real_phase,
                                    work) == b:
                    _array_copy.copy_into(q[n], trial)
                    exists[n] = True
                    found = True
            if not found:
                row[0] = b
                solve_one(targets[n], psi[n], row, signs, geometry, real, model, tool_inverse, reach, real_phase,
                          one_q, one_exists, work)
                _array_copy.copy_into(q[n], one_q[0])
                exists[n] = one_exists[0]
            previous = n


@kernel
def equations(start, stop, q, targets, psi, real, model, e, jac):
    """The residual of the 7 equations ``FK(q) = T``, ``psi(q) = psi`` (:func:`measured`) of joint vectors ``start
    .. stop - 1`` of ``q`` (N, 7) against ``targets`` (N, 4, 4) and ``psi`` (N,) into ``e`` (N, 7), and their
    Jacobian, our geometric one [N1] over the arm angle's gradient (:func:`arm_angle_one`), into ``jac`` (N, 7, 7):
    the system of :func:`newton`'s steps, undamped."""
    links, ends, standard = real
    work = scratch()[0]
    gradient = work[4]
    for n in range(start, stop):
        measured(q[n], targets[n], psi[n], real, model, work, gradient, np.bool_(True), e[n])
        _chain_kernels.jacobian_from_trig(links, ends, standard, np.int64(7), np.bool_(True), work[9], work[0],
                                          jac[n])  # q[n]'s sines and cosines, as measured
        for c in range(7):
            jac[n, 6, c] = gradient[c]


@kernel
def arm_angles(start, stop, q, model, out, gradients, with_gradient):
    """:func:`arm_angle_one` of joint vectors ``start .. stop - 1`` of ``q`` (N, 7) into ``out`` (N,), with
    ``with_gradient`` their gradients into ``gradients`` (N, 7)."""
    work = scratch()[0][2]
    for n in range(start, stop):
        out[n] = arm_angle_one(q[n], model[0], model[1], model[2], model[3], work, gradients[n], with_gradient)

