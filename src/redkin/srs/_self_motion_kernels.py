"""The compiled core of :mod:`redkin.srs.nearly_self_motion`: the real arm's self-motion followed by continuation.

For one pose ``T`` the real arm's solutions form curves in joint space (its
self-motion): ``FK(q) = T`` is 6 equations in 7 unknowns.  :func:`traced`
follows one from a solution by predictor-corrector continuation: the unit
tangent ``t`` is the null vector of the 6 x 7 Jacobian ``J`` [N1], from
``[J; t_prev^T] t = [0; 1]`` (the previous tangent fixes its sense); the
predictor is ``q + h t``; the corrector takes Newton's steps on the pose
equations and the hyperplane ``t . (q - q_pred) = 0`` (7 equations,
``[J; t^T] dq = [e; -t . (q - q_pred)]``), so that ``h`` is the arc length of
the step to first order.  A step is retried at half its length unless the
corrector settles, moves the point by at most :data:`CLOSE` times the step,
and the tangent and the arm angle turn little (:data:`COS_TURN`,
:data:`ARM_ANGLE_STEP`).

Inputs are trusted.
"""

from __future__ import annotations

from math import pi, sqrt

import numpy as np

from redkin import _chain_kernels
from redkin._compiled import kernel
from redkin.numerical._kernels import pose_error
from redkin.srs._ik_kernels import turns_removed
from redkin.srs._nearly_kernels import arm_angle_one

#: Newton's steps of the corrector at most, and the pose error (position plus rotation) at which it has settled.
CORRECTOR_STEPS, SETTLED = 8, 1e-12
#: The smallest step [rad of arc length in joint space] before the continuation gives up.
SMALLEST_STEP = 1e-9
#: A step is kept where the corrector moves the point by at most ``CLOSE`` times the step, the tangent turns by at most
#: ``acos(COS_TURN)`` (0.2 rad) and the arm angle by at most ``ARM_ANGLE_STEP`` [rad]; otherwise it is halved.  So a
#: joint's rate changes sign at most once between neighbouring points wherever the curve bends less than its steps
#: resolve, and neighbouring arm angles unwrap unambiguously.
CLOSE, COS_TURN, ARM_ANGLE_STEP = 0.1, 0.9800665778412416, 0.1


@kernel
def pose_jacobian(q, target, real, work, e):
    """The pose error [N1] of ``q`` (7,) on the real chain ``real`` against ``target`` into ``e[:6]`` and the
    geometric Jacobian into ``work``'s ``jac[:6]``; returns the position plus rotation error."""
    links, ends, standard = real
    trig, pose, jac, origin = work[0], work[1], work[5], work[9]
    _chain_kernels.frames_one(q, links, ends, standard, trig, pose)
    position, angle = pose_error(target, pose[0], e)
    _chain_kernels.jacobian_one(q, links, ends, standard, 7, True, origin, trig, jac)
    return position + angle


@kernel
def tangent(jac, previous, out):
    """The unit null vector of ``jac[:6]`` (7, 7) with ``previous . out > 0`` into ``out`` (7,): ``[J; previous^T]
    out = [0; 1]``, normalised; returns ``False`` where that system is singular (a singular configuration)."""
    system = jac.copy()
    system[6, :] = previous
    right = np.zeros(7)
    right[6] = 1.0
    if abs(np.linalg.det(system)) < 1e-300:
        return False
    out[:] = np.linalg.solve(system, right)
    size = sqrt(np.sum(out * out))
    if not np.isfinite(size) or size == 0.0:
        return False
    out /= size
    return True


@kernel
def corrected(q, direction, target, real, work, e):
    """Newton's steps from ``q`` (7,) in place onto the self-motion of ``target`` within the hyperplane through ``q``
    normal to ``direction`` (7,) (module docstring); returns whether the pose error settled (:data:`SETTLED`), and
    where it did, leaves the Jacobian at the settled ``q`` in ``work`` (:func:`pose_jacobian`)."""
    jac = work[5]
    anchor = q.copy()
    for _ in range(CORRECTOR_STEPS):
        size = pose_jacobian(q, target, real, work, e)
        if size <= SETTLED:
            return True
        if not np.isfinite(size):
            return False
        system = jac.copy()
        system[6, :] = direction
        right = np.empty(7)
        right[:6] = e[:6]
        right[6] = -np.sum(direction * (q - anchor))
        if abs(np.linalg.det(system)) < 1e-300:
            return False
        q += np.linalg.solve(system, right)
    return pose_jacobian(q, target, real, work, e) <= SETTLED


@kernel
def on_curve(q, direction, distance, target, real, work, e, out):
    """The point of the self-motion near ``q + distance direction`` (``q`` on it, ``direction`` its unit tangent
    there): that predictor corrected (:func:`corrected`) into ``out`` (7,); returns whether it settled."""
    out[:] = q + distance * direction
    return corrected(out, direction, target, real, work, e)


@kernel
def traced(start, target, real, model, step, sense, most, points, tangents, angles, rates, work):
    """Follow the self-motion of ``target`` (4, 4) on the real chain from the solution ``start`` (7,) with steps of
    at most ``step`` [rad of arc length], the arm angle first increasing (``sense`` +1) or decreasing (-1).

    ``start`` need reach the pose only nearly: it is first corrected onto the curve (:func:`corrected`, normal to
    its tangent there).  Writes up to ``most`` points into ``points`` (most, 7), their unit tangents into
    ``tangents`` (most, 7), arm angles (:func:`redkin.srs._nearly_kernels.arm_angle_one`) into ``angles`` (most,)
    and ``d psi / ds`` (``grad psi . t``) into ``rates`` (most,).  Stops where the curve closes (it comes back
    within a step of ``start`` heading the same way), at ``most`` points, or where a step fails (a singular
    configuration, or the corrector does not settle at :data:`SMALLEST_STEP`).  Returns the number of points and
    whether the curve closed.
    """
    e, gradient, jac = work[3], work[4], work[5]
    model_work = work[2]
    q = start.copy()
    pose_jacobian(q, target, real, work, e)
    guess = np.zeros(7)
    for k in range(7):  # a first sense for the tangent: any row of the identity not nearly in J's row space
        trial = np.zeros(7)
        trial[k] = 1.0
        if tangent(jac, trial, guess):
            break
    direction = np.empty(7)
    if not tangent(jac, guess, direction) or not corrected(q, direction, target, real, work, e) \
            or not tangent(jac, direction, direction):
        return 0, False
    start = q.copy()
    psi = arm_angle_one(q, model[0], model[1], model[2], model[3], model_work, gradient, True)
    rate = np.sum(gradient * direction)
    if rate * sense < 0.0:
        direction = -direction
        rate = -rate
    count = 0
    h = step
    moved, following = np.empty(7), np.empty(7)
    while count < most:
        points[count] = q
        tangents[count] = direction
        angles[count] = psi
        rates[count] = rate
        count += 1
        if count == most:
            break
        while True:  # a step is kept where it settles, stays near its predictor and turns little
            if on_curve(q, direction, h, target, real, work, e, moved):  # the Jacobian is at moved
                change = moved - q - h * direction
                if sqrt(np.sum(change * change)) <= CLOSE * h and tangent(jac, direction, following) \
                        and np.sum(following * direction) >= COS_TURN:
                    psi = arm_angle_one(moved, model[0], model[1], model[2], model[3], model_work, gradient, True)
                    if abs(turns_removed(psi - angles[count - 1] + pi) - pi) <= ARM_ANGLE_STEP:
                        break
            h *= 0.5
            if h < SMALLEST_STEP:
                return count, False
        from_start = 0.0
        ahead = 0.0
        for j in range(7):
            gap = turns_removed(moved[j] - start[j] + pi) - pi
            from_start += gap * gap
            ahead += gap * tangents[0, j]
        if count > 2 and sqrt(from_start) < h and ahead >= 0.0 and np.sum(following * tangents[0]) > 0.0:
            return count, True
        q[:] = moved
        direction[:] = following
        rate = np.sum(gradient * direction)
        h = min(step, 1.5 * h)
    return count, False


@kernel
def point_at(q, direction, distance, target, real, model, work, out, following):
    """The self-motion's point on the hyperplane through ``q + distance direction`` normal to ``direction``
    (:func:`on_curve`, ``q`` a point of the curve and ``direction`` its tangent there) into ``out`` (7,); returns
    whether it settled, its arm angle and ``d psi / ds`` along its unit tangent, which goes into ``following`` (7,)
    in the sense of ``direction``."""
    e, gradient, jac = work[3], work[4], work[5]
    if not on_curve(q, direction, distance, target, real, work, e, out):  # the Jacobian is at out
        return False, 0.0, 0.0
    if not tangent(jac, direction, following):
        return False, 0.0, 0.0
    psi = arm_angle_one(out, model[0], model[1], model[2], model[3], work[2], gradient, True)
    return True, psi, np.sum(gradient * following)
