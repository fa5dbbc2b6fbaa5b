"""Compiled levels of the certified collision-free arm angles (:mod:`redkin.collision.arm_angle_free`): per
interval, the checked pairs' clearances at its middle, the bound of how fast each can change over it, and the
interval decided from both.

An interval ``n`` belongs to pose ``pose[n]`` and branch ``branch[n]``; the pose's entry coefficients ``entries``
(P, 2, 3, 14) and ``theta4`` (P, 2) are those of both elbow signs (:func:`redkin.srs.coefficients.coefficient_arrays`
with signs +1, -1), of which the branch's is row ``elbow[branch]``; ``signs`` (B, 3) are the branches' Table 1
signs.
"""

from __future__ import annotations

from math import ceil, cos, hypot, inf, sin, sqrt

import numpy as np

from redkin._compiled import kernel
from redkin.collision._clearance_kernels import clearances_one, scratch
from redkin.collision._decision_kernels import decided_one
from redkin.srs._ik_kernels import GROUP, branch_angles, chain_values

#: The least lower bound of ``sin^2`` of a group's middle angle that a rate bound is computed from: below it the
#: group may be at a singular arm angle, where the kernels set the first angle to 0 (``|sin| <= 1e-12``,
#: :data:`redkin.srs._ik_kernels.UNDEFINED_TOLERANCE`) and the bounds do not hold; far above rounding.
LEAST_ROOM = 1e-12
#: The widest stretch of arm angle [rad] a joint-rate bound is taken over: a wider interval's bound is the largest of
#: its pieces' (:func:`interval_rates`, at most :data:`RATE_PIECES` of them), since the entries' swing grows with the
#: width (over 1.4 rad the bound is about twice the largest rate, over pieces of 0.2 rad within about 15 % of it;
#: narrower pieces cost more to bound than they save in evaluations).
RATE_PIECE = 0.2
RATE_PIECES = 8
#: The least distance [m] between the two cores of a pair (its distance plus both radii) from which
#: :func:`turning_speed` bounds it: below it the pair's normal is not a direction of its own.
LEAST_CORE_GAP = 1e-9
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
def interval_rates(entries, middle, half, rates, piece):
    """:func:`joint_rates` over ``[middle - half, middle + half]`` as the largest of its bounds over equal pieces
    no wider than :data:`RATE_PIECE` (at most :data:`RATE_PIECES`): each holds on its piece, so their largest holds
    on the whole.  ``piece`` (4,) is scratch."""
    pieces = min(max(int(ceil(2.0 * half / RATE_PIECE)), 1), RATE_PIECES)
    if pieces == 1:
        joint_rates(entries, middle, half, rates)
        return
    step = half / pieces
    for i in range(4):
        rates[i] = 0.0
    for k in range(pieces):
        joint_rates(entries, middle - half + (2 * k + 1) * step, step, piece)
        for i in range(4):
            rates[i] = max(rates[i], piece[i])


@kernel
def speeds_one(entries, middle, half, frame, reach, capsule, other, rates, turning, moving, out):
    """Over ``[middle - half, middle + half]`` of one branch (its entry coefficients ``entries`` (3, 14)), per
    checked pair ``k`` a bound of how fast its distance changes per radian of psi into ``out[k]``, the sum of its two
    shapes' speeds (an obstacle's is 0).  A capsule on frame ``f`` at distance ``reach[m]`` from what its frame turns
    about moves at that distance times the frame's turning rate: 0 for frames 0 and 7 and beyond, ``|theta_1'|`` for
    frame 1, ``|theta_1'| + |theta_2'|`` for 2, 1 for frames 3 and 4 (about the shoulder-wrist line),
    ``|theta_6'| + |theta_7'|`` for 5 and ``|theta_7'|`` for 6 (:func:`joint_rates`; the module docstring of
    :mod:`redkin.collision.arm_angle_free`; over pieces of the interval, :func:`interval_rates`).  ``rates`` (8,),
    ``turning`` (8,, zeros) and ``moving`` (M,) are scratch."""
    interval_rates(entries, middle, half, rates[:4], rates[4:])
    turning[1], turning[2], turning[3], turning[4] = rates[0], rates[0] + rates[1], 1.0, 1.0
    turning[5], turning[6] = rates[2] + rates[3], rates[3]
    for m in range(frame.shape[0]):
        distance = reach[m]
        moving[m] = distance * turning[min(frame[m], 7)] if distance > 0.0 else 0.0  # 0 * inf: on its axis
    for k in range(capsule.shape[0]):
        if other[k] >= 0 and _turns_about_line(frame[capsule[k]]) and _turns_about_line(frame[other[k]]):
            out[k] = 0.0  # both on links 3-4: they turn together, and their distance stays
        else:
            out[k] = moving[capsule[k]] + (moving[other[k]] if other[k] >= 0 else 0.0)


@kernel
def _turns_about_line(frame):
    """Whether a shape on ``frame`` turns rigidly about the shoulder-wrist line (links 3 and 4)."""
    return frame == 3 or frame == 4


@kernel
def _still(frame):
    """Whether a shape on ``frame`` stays where the pose puts it (the base, and the tool's link and beyond)."""
    return frame == 0 or frame >= 7


@kernel
def _turned(line, point):
    """For ``point`` (3,) turned by ``delta`` about the shoulder-wrist line ``line`` (its point, then its unit
    direction ``e``), the coefficients of ``n . turned(delta) = alpha + beta cos delta + gamma sin delta`` for a
    vector ``n`` given later: returned as the two vectors ``w_perp`` and ``e x w`` (``w = point - line point``,
    ``w_perp`` its part across the line), so ``beta = n . w_perp`` and ``gamma = n . (e x w)``."""
    wx, wy, wz = point[0] - line[0], point[1] - line[1], point[2] - line[2]
    ex, ey, ez = line[3], line[4], line[5]
    along = wx * ex + wy * ey + wz * ez
    return ((wx - along * ex, wy - along * ey, wz - along * ez),
            (ey * wz - ez * wy, ez * wx - ex * wz, ex * wy - ey * wx))


@kernel
def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


@kernel
def turning_speed(row, witness, flip, other_radius, line, half):
    """A bound of how fast the distance of a pair changes per radian of psi over ``[m - half, m + half]`` where one
    shape, ``row`` (a capsule on links 3-4), turns rigidly about the shoulder-wrist line ``line`` (its point, its
    unit direction) and the other (radius ``other_radius``) stays still; ``inf`` where the pair was not measured
    or its cores touch.  ``witness`` is the pair's :func:`redkin.collision._distance_kernels.pair_distance` output
    at ``m`` with ``row`` first, or second where ``flip``.  With ``u`` the unit normal from the turning core to
    the still one, ``c_a, c_b`` their closest points and ``g = |c_b - c_a|`` (the module docstring of
    :mod:`redkin.collision.arm_angle_free` states the argument):

    * the distance is at least ``u . c_b - max_e u . e(psi)`` minus both radii (the gap of the projections on
      ``u``; ``e`` the segment's two ends), and each ``u . e`` is ``alpha + beta cos delta + gamma sin delta``
      in ``delta = psi - m``, which rises by at most ``(|gamma| + max(0, -beta) half / 2) |delta|``;
    * it is at most ``|c_a(psi) - c_b|`` minus both radii, whose square is ``A + B cos delta + C sin delta``, so
      it rises by at most ``(|C| + max(0, -B) half / 2) |delta| / (2 g)``.

    Both equal the distance at ``m``, so the larger of the two rates bounds ``|c(psi) - c(m)| / |delta|``."""
    distance = witness[0]
    gap = distance + row[1] + other_radius
    if distance != distance or not gap > LEAST_CORE_GAP or not half > 0.0:
        return inf
    sign, a, b = (-1.0, 4, 1) if flip else (1.0, 1, 4)  # the turning shape's witness point first
    u = (sign * witness[7], sign * witness[8], sign * witness[9])
    core_a = (witness[a] - row[1] * u[0], witness[a + 1] - row[1] * u[1], witness[a + 2] - row[1] * u[2])
    core_b = (witness[b] + other_radius * u[0], witness[b + 1] + other_radius * u[1],
              witness[b + 2] + other_radius * u[2])
    top = max(_dot(u, row[2:5]), _dot(u, row[5:8]))
    rate = 0.0
    for end in range(2):
        across, swept = _turned(line, row[2 + 3 * end:5 + 3 * end])
        lag = min(_dot(u, row[2 + 3 * end:5 + 3 * end]) - top, 0.0)  # this end's projection below the top
        rate = max(rate, abs(_dot(u, swept)) + max(0.0, -_dot(u, across)) * half / 2.0 + lag / half)
    across, swept = _turned(line, core_a)
    z = (line[0] - core_b[0], line[1] - core_b[1], line[2] - core_b[2])
    rise = 2.0 * abs(_dot(z, swept)) + max(0.0, -2.0 * _dot(z, across)) * half / 2.0
    return max(rate, rise / (2.0 * gap))


@kernel
def level(start, stop, middle, half, pose, branch, entries, theta4, elbow, signs, joints, links, ends, standard,
          frame, a, b, radius, obstacles, capsule, obstacle, other, margin, reach, line, finest, carve, active, kind,
          pair, cut, carved, cause):
    """One level of the subdivision for intervals ``start .. stop - 1``: the branch's configuration at arm angle
    ``middle[n]`` [000 eqs. 11-19], there the active pairs' clearances (:func:`redkin.collision._clearance_kernels.
    clearances_one`, whose arguments ``links .. margin`` are), their speed bounds over the interval of half width
    ``half[n]`` (:func:`speeds_one`, from ``reach`` (P, M); a pair of a shape on links 3-4 and a still one by
    :func:`turning_speed` where that is less, from the shoulder-wrist ``line`` (P, 6)), and the interval decided
    (:func:`redkin.collision._decision_kernels.decided_one`: ``active[n]`` updated, the rest into ``kind``,
    ``pair``, ``cut``, ``carved`` and ``cause``)."""
    theta, q = np.empty(7), np.empty(7)
    work = scratch(links, frame, capsule)
    rows, found = work[2], work[3]
    clearance, speed, floor = np.empty(capsule.shape[0]), np.empty(capsule.shape[0]), np.empty(capsule.shape[0])
    rates, turning, moving = np.empty(8), np.zeros(8), np.empty(frame.shape[0])
    for n in range(start, stop):
        p, e = pose[n], elbow[branch[n]]
        branch_angles(entries[p, e], theta4[p, e], middle[n], signs[branch[n], 0], signs[branch[n], 2], theta)
        chain_values(theta, joints, q)
        speeds_one(entries[p, e], middle[n], half[n], frame, reach[p], capsule, other, rates, turning, moving, speed)
        for k in range(capsule.shape[0]):  # a pair whose clearance exceeds this is clear on the whole interval
            floor[k] = speed[k] * half[n]
        clearances_one(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
                       active[n], floor, clearance, work)
        for k in range(capsule.shape[0]):
            if not abs(clearance[k]) <= floor[k]:
                continue  # decided by the bound above (or not measured): no tighter one needed
            if other[k] < 0:
                mine, still, flip, radius_b = capsule[k], True, False, obstacles[obstacle[k], 1]
            elif _turns_about_line(frame[capsule[k]]):
                mine, still, flip, radius_b = capsule[k], _still(frame[other[k]]), False, rows[other[k], 1]
            else:
                mine, still, flip, radius_b = other[k], _still(frame[capsule[k]]), True, rows[capsule[k], 1]
            if still and _turns_about_line(frame[mine]):
                speed[k] = min(speed[k], turning_speed(rows[mine], found[k], flip, radius_b, line[p], half[n]))
        kind[n], pair[n], cut[n], carved[n], cause[n] = decided_one(half[n], clearance, speed, active[n], finest,
                                                                    carve)
