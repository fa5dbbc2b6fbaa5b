"""The compiled core of nearly S-R-S arm-angle IK: the corrections of the neighbour's target (:mod:`redkin.srs.nearly`).

For one pose, arm angle and branch, :func:`settle_one` repeats: move the
neighbour's target just inside its reach, solve the neighbour at the arm
angle [000 eqs. 4-19] (:func:`redkin.srs._ik_kernels.solve_pose`), take the
real arm's pose of that solution (:func:`redkin._chain_kernels.frames_one`),
and correct the target ``T' <- T G^-1 T'``; it keeps the solution of the
smallest error (:func:`redkin.numerical._kernels.pose_error`) and stops when
the error reaches rounding or stops shrinking.  Inputs are trusted.
"""

from __future__ import annotations

from math import sqrt

import numpy as np

from redkin import _chain_kernels
from redkin._compiled import kernel
from redkin.numerical._kernels import nearest_pose, pose_error
from redkin.srs._ik_kernels import OK, _scratch, solve_pose

#: Entries of the ``reach`` array: the neighbour's shortest and longest shoulder-wrist distance (moved inside by a
#: relative 1e-9), the wrist-to-flange length ``d_7``, and the shoulder point (3).
LOW, HIGH, WRIST_LENGTH, SHOULDER = 0, 1, 2, 3
#: Corrections per pose and branch; they go on while the error shrinks below ``SHRINK`` of the best so far, down
#: to ``FINE`` (position plus rotation).
ITERATIONS, SHRINK, FINE = 60, 0.9, 1e-14


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


@kernel
def settle_one(target, psi, signs, arm, ends, joints, links, chain_ends, standard, tool_inverse, reach, q, error,
               work):
    """The corrections (module docstring) for one pose ``target`` (4, 4), arm angle and branch ``signs`` (1, 3):
    the solution of the smallest error into ``q`` (7,) and its position and rotation error into ``error`` (2,)
    (``inf`` where the neighbour never reached a moved target)."""
    scratch, moved, trial, trig, reached, e, product = work
    moved[:] = target
    error[0], error[1] = np.inf, np.inf
    for _ in range(ITERATIONS):
        within_reach(moved, tool_inverse, reach)
        if solve_pose(moved, psi, signs, arm, ends, joints, trial, scratch) != OK:
            return
        _chain_kernels.frames_one(trial[0], links, chain_ends, standard, trig, reached)
        position, angle = pose_error(target, reached[0], e)
        best = error[0] + error[1]
        if position + angle < best:
            q[:] = trial[0]
            error[0], error[1] = position, angle
        if position + angle <= FINE or position + angle > SHRINK * best:
            return
        corrected(target, reached[0], moved, product)


@kernel
def settle(start, stop, targets, psi, signs, arm, ends, joints, links, chain_ends, standard, tool_inverse, reach,
           q, error):
    """:func:`settle_one` for poses ``start .. stop - 1`` of ``targets`` (N, 4, 4) at ``psi`` (N,) on every branch of
    ``signs`` (B, 3), into ``q`` (N, B, 7) and ``error`` (N, B, 2)."""
    work = (_scratch(), np.empty((4, 4)), np.empty((1, 7)), np.empty((7, 2)), np.empty((1, 4, 4)), np.empty(6),
            np.empty((2, 4, 4)))
    for n in range(start, stop):
        for b in range(signs.shape[0]):
            settle_one(targets[n], psi[n], signs[b:b + 1], arm, ends, joints, links, chain_ends, standard,
                       tool_inverse, reach, q[n, b], error[n, b], work)
