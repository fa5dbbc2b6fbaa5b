"""Compiled levels of the certified collision-free arm angles (:mod:`redkin.collision.arm_angle_free`): per
interval, the checked pairs' clearances at its middle, the bound of how fast each can change over it, and the
interval decided from both.

An interval ``n`` belongs to pose ``pose[n]`` and branch ``branch[n]``; the pose's entry coefficients ``entries``
(P, 2, 3, 14) and ``theta4`` (P, 2) are those of both elbow signs (:func:`redkin.srs.coefficients.coefficient_arrays`
with signs +1, -1), of which the branch's is row ``elbow[branch]``; ``signs`` (B, 3) are the branches' Table 1
signs.
"""

from __future__ import annotations

from math import cos, hypot, inf, sin, sqrt

import numpy as np

from redkin._compiled import kernel
from redkin.collision._clearance_kernels import clearances_one, scratch
from redkin.collision._decision_kernels import decided_one
from redkin.srs._ik_kernels import GROUP, branch_angles, chain_values

#: The least lower bound of ``sin^2`` of a group's middle angle that a rate bound is computed from: below it the
#: group may be at a singular arm angle, where the kernels set the first angle to 0 (``|sin| <= 1e-12``,
#: :data:`redkin.srs._ik_kernels.UNDEFINED_TOLERANCE`) and the bounds do not hold; far above rounding.
LEAST_ROOM = 1e-12
#: Entry columns (:data:`redkin.srs._ik_kernels.ENTRY_LAYOUT`) of ``x, y, z`` and ``r_2, t`` of a group, from its
#: first entry.
_X, _Y, _Z, _R2, _T = 0, 1, 2, 5, 6


@kernel
def _entry_bounds(entries, e, s, c, half):
    """Over ``[m - half, m + half]`` (``s, c = sin m, cos m``), bounds of entry ``e`` ``a sin psi + b cos psi + c``
    [000 eqs. 12, 16]: the largest ``|e|``, the largest ``|e'|`` and the least ``e^2``.  The entry and its
    derivative move by at most ``hypot(a, b) half`` from their values at ``m``."""
    value = entries[0, e] * s + entries[1, e] * c + entries[2, e]
    slope = entries[0, e] * c - entries[1, e] * s
    swing = hypot(entries[0, e], entries[1, e]) * half
    least = max(abs(value) - swing, 0.0)
    return abs(value) + swing, abs(slope) + swing, least * least


@kernel
def joint_rates(entries, middle, half, rates):
    """Upper bounds of ``|theta_1'|, |theta_2'|, |theta_6'|, |theta_7'|`` over ``[middle - half, middle + half]``
    into ``rates`` (4,), from the entry coefficients (3, 14) of one elbow sign (the module docstring of
    :mod:`redkin.collision.arm_angle_free`; ``inf`` where the group may be singular, :data:`LEAST_ROOM`)."""
    s, c = sin(middle), cos(middle)
    for g in range(2):
        k = GROUP * g
        size_x, change_x, least_x = _entry_bounds(entries, k + _X, s, c, half)
        size_y, change_y, least_y = _entry_bounds(entries, k + _Y, s, c, half)
        size_z, change_z, _ = _entry_bounds(entries, k + _Z, s, c, half)
        size_r2, change_r2, least_r2 = _entry_bounds(entries, k + _R2, s, c, half)
        size_t, change_t, least_t = _entry_bounds(entries, k + _T, s, c, half)
        # sin^2 of the group's middle angle: 1 - z^2 = x^2 + y^2 = r_2^2 + t^2, bounded below three ways
        room = max(1.0 - min(size_z, 1.0) ** 2, max(least_x + least_y, least_r2 + least_t))
        fine = room > LEAST_ROOM
        second = change_z / sqrt(room) if fine else inf
        if g == 0:
            rates[0] = (size_x * change_y + size_y * change_x) / room if fine else inf
            rates[1] = second
        else:
            rates[2] = second
            rates[3] = (size_t * change_r2 + size_r2 * change_t) / room if fine else inf


@kernel
def speeds_one(entries, middle, half, frame, reach, capsule, other, rates, turning, moving, out):
    """Over ``[middle - half, middle + half]`` of one branch (its entry coefficients ``entries`` (3, 14)), per
    checked pair ``k`` a bound of how fast its distance changes per radian of psi into ``out[k]``, the sum of its two
    shapes' speeds (an obstacle's is 0).  A capsule on frame ``f`` at distance ``reach[m]`` from what its frame turns
    about moves at that distance times the frame's turning rate: 0 for frames 0 and 7 and beyond, ``|theta_1'|`` for
    frame 1, ``|theta_1'| + |theta_2'|`` for 2, 1 for frames 3 and 4 (about the shoulder-wrist line),
    ``|theta_6'| + |theta_7'|`` for 5 and ``|theta_7'|`` for 6 (:func:`joint_rates`; the module docstring of
    :mod:`redkin.collision.arm_angle_free`).  ``rates`` (4,), ``turning`` (8,, zeros) and ``moving`` (M,) are
    scratch."""
    joint_rates(entries, middle, half, rates)
    turning[1], turning[2], turning[3], turning[4] = rates[0], rates[0] + rates[1], 1.0, 1.0
    turning[5], turning[6] = rates[2] + rates[3], rates[3]
    for m in range(frame.shape[0]):
        distance = reach[m]
        moving[m] = distance * turning[min(frame[m], 7)] if distance > 0.0 else 0.0  # 0 * inf: on its axis
    for k in range(capsule.shape[0]):
        out[k] = moving[capsule[k]] + (moving[other[k]] if other[k] >= 0 else 0.0)


@kernel
def level(start, stop, middle, half, pose, branch, entries, theta4, elbow, signs, joints, links, ends, standard,
          frame, a, b, radius, obstacles, capsule, obstacle, other, margin, reach, finest, carve, active, kind, pair,
          cut, carved, cause):
    """One level of the subdivision for intervals ``start .. stop - 1``: the branch's configuration at arm angle
    ``middle[n]`` [000 eqs. 11-19], there the active pairs' clearances (:func:`redkin.collision._clearance_kernels.
    clearances_one`, whose arguments ``links .. margin`` are), their speed bounds over the interval of half width
    ``half[n]`` (:func:`speeds_one`, from ``reach`` (P, M)), and the interval decided
    (:func:`redkin.collision._decision_kernels.decided_one`: ``active[n]`` updated, the rest into ``kind``,
    ``pair``, ``cut``, ``carved`` and ``cause``)."""
    theta, q = np.empty(7), np.empty(7)
    work = scratch(links, frame)
    clearance, speed, floor = np.empty(capsule.shape[0]), np.empty(capsule.shape[0]), np.empty(capsule.shape[0])
    rates, turning, moving = np.empty(4), np.zeros(8), np.empty(frame.shape[0])
    for n in range(start, stop):
        p, e = pose[n], elbow[branch[n]]
        branch_angles(entries[p, e], theta4[p, e], middle[n], signs[branch[n], 0], signs[branch[n], 2], theta)
        chain_values(theta, joints, q)
        speeds_one(entries[p, e], middle[n], half[n], frame, reach[p], capsule, other, rates, turning, moving, speed)
        for k in range(capsule.shape[0]):  # a pair whose clearance exceeds this is clear on the whole interval
            floor[k] = speed[k] * half[n]
        clearances_one(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
                       active[n], floor, clearance, work)
        kind[n], pair[n], cut[n], carved[n], cause[n] = decided_one(half[n], clearance, speed, active[n], finest,
                                                                    carve)
