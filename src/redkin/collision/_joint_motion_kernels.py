"""Compiled bounds of how far a checked pair's clearance moves between two configurations of one pose whose joints
differ by at most given amounts, read along the pair's normal (:mod:`redkin.collision.joint_motion`, "Along the
normal"): per pair the witness points and normal at the first configuration (:func:`redkin.collision.
_distance_kernels.pair_distance`), the joints' axes there, and the levers of :func:`redkin.collision.joint_motion.
_joint_levers` for the second-order remainder."""

from __future__ import annotations

from math import inf, sqrt

import numpy as np

from redkin._chain_kernels import frames_one
from redkin._compiled import kernel
from redkin.collision._body_kernels import posed_one
from redkin.collision._distance_kernels import OUT, pair_distance
from redkin.collision.primitives import BOX, PLANE, WIDTH

#: Added to every bound [m]: the rounding of the support values and projections (of shapes a few metres across).
ROUNDING = 1e-12
#: A core distance below this [m] gives no normal to read the rise along (the pair keeps its lever bound).
_TOUCHING = 1e-9
#: The first joint from the base, and the two ways along the chain: int64 values, not literals, so that the callees
#: compile once (a literal argument is a type of its own to numba).
_FIRST, _UP, _DOWN = np.int64(0), np.int64(1), np.int64(-1)


@kernel
def reaches(start, stop, q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
            base, tip, delta, lever, want, out):
    """:func:`reach_one` for configurations ``start .. stop - 1`` of ``q`` (N, n), with ``delta`` (N, n), ``lever``,
    ``want`` and ``out`` (N, K)."""
    n = links.shape[0]
    trig, held = np.empty((n, 2)), np.empty((n + 2, 4, 4))
    rows, found = np.empty((frame.shape[0], WIDTH)), np.empty(OUT)
    axes, points, vectors = np.empty((n, 3)), np.empty((n, 3)), np.empty((3, 3))
    for c in range(start, stop):
        reach_one(q[c], links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin, base,
                  tip, delta[c], lever[c], want[c], out[c], trig, held, rows, found, axes, points, vectors)


@kernel
def reach_one(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin, base, tip,
              delta, lever, want, out, trig, held, rows, found, axes, points, vectors):
    """For each checked pair ``k`` that is ``want[k]`` (the arguments of
    :func:`redkin.collision._clearance_kernels.clearances_one`), a bound ``out[k]`` of how far its clearance may
    move from its value at ``q`` (n,) towards the margin, over configurations of the same pose whose joints differ
    from ``q`` by at most ``delta`` (n,): down (:func:`_fall`) where the pair is farther apart than ``margin`` at
    ``q``, up (:func:`_rise`) where it is not; ``inf`` where no such bound is given and for the other pairs.
    ``lever[k]`` bounds how far the pair's shapes move relative to each other (the lever bound); ``base`` and ``tip``
    (M, n) are the levers of :func:`redkin.collision.joint_motion._joint_levers`.  The rest is scratch."""
    posed = False
    for k in range(capsule.shape[0]):
        out[k] = inf
        if not want[k]:
            continue
        if not posed:
            frames_one(q, links, ends, standard, trig, held)
            posed_one(held, frame, a, b, radius, rows)
            shift = 0 if standard else 1  # joint j's axis: frame j - 1's z axis (standard DH), else frame j's
            for j in range(links.shape[0]):
                for r in range(3):
                    axes[j, r], points[j, r] = held[j + shift, r, 2], held[j + shift, r, 3]
            posed = True
        shape = obstacles[obstacle[k]] if obstacle[k] >= 0 else rows[other[k]]
        pair_distance(rows[capsule[k]], shape, found)
        if found[0] > margin:
            out[k] = _fall(k, rows, shape, frame, capsule, obstacle, other, base, tip, delta, axes, points, found,
                           vectors[0])
        else:
            out[k] = _rise(k, rows, shape, frame, capsule, obstacle, other, base, tip, delta, lever[k], axes, points,
                           found, vectors)


@kernel
def _fall(k, rows, shape, frame, capsule, obstacle, other, base, tip, delta, axes, points, found, u):
    """How far pair ``k``'s distance ``d`` (``found[0]``, the pair apart) may fall: ``d - S`` plus the rise of the
    moving capsule's support along the normal ``u`` (into ``u`` (3,): the witness normal, minus the normal against
    a plane), where ``S``, the gap between the two shapes' supports along ``u``, bounds ``d`` from below at every
    configuration (module :mod:`redkin.collision.joint_motion`)."""
    mine = rows[capsule[k]]
    if shape[0] == PLANE:
        _unit_into(shape[5:8], -1.0, u)
        gap = _dot(shape[2:5], u) - _support_high(mine, u)  # the lowest end's height less the radius
    else:
        for r in range(3):
            u[r] = found[7 + r]
        gap = _support_low(shape, u) - _support_high(mine, u)
    own = frame[capsule[k]]
    if obstacle[k] >= 0:  # the capsule moves relative to the base (joints 1..k) and to the tool (k + 1..n)
        moved = min(_drop(mine, u, 1.0, _FIRST, own, _UP, base[capsule[k]], delta, axes, points),
                    _drop(mine, u, 1.0, base.shape[1] - 1, own - 1, _DOWN, tip[capsule[k]], delta, axes, points))
    else:
        moved = _relative_drop(k, rows, frame, capsule, other, base, tip, delta, axes, points, u)
    return max(found[0] - gap, 0.0) + moved + ROUNDING


@kernel
def _relative_drop(k, rows, frame, capsule, other, base, tip, delta, axes, points, u):
    """How far self pair ``k``'s support gap along ``u`` (from its capsule towards the other) may fall: the capsule
    on the lower link moving relative to the upper one (joints from the upper link down), or the upper relative to
    the lower (joints from the lower link up), whichever bounds it lower."""
    first, second = capsule[k], other[k]
    low, high, sign = (first, second, 1.0) if frame[first] <= frame[second] else (second, first, -1.0)
    bottom, top = frame[low], frame[high]
    return min(_drop(rows[low], u, sign, top - 1, bottom - 1, _DOWN, tip[low], delta, axes, points),
               _drop(rows[high], u, -sign, bottom, top, _UP, base[high], delta, axes, points))


@kernel
def _rise(k, rows, shape, frame, capsule, obstacle, other, base, tip, delta, lever, axes, points, found, vectors):
    """How far pair ``k``'s distance ``d`` (``found[0]``, within the margin) may rise: the distance is at most that of
    two points on the cores, ``x = c_b - c_a`` (the witness cores, ``|x| - r_a - r_b`` no less than ``d``), which
    rises by at most ``x/|x| . dx + |dx|^2 / (2 |x|)``, ``|dx|`` at most ``lever``; against a plane at most the height
    of the lowest end less its radius, which rises by that end's motion along the plane's normal.  ``inf`` where the
    cores touch, or a capsule's core lies in a box.  ``vectors`` (3, 3) is scratch."""
    mine = rows[capsule[k]]
    own = frame[capsule[k]]
    direction, core, there = vectors[0], vectors[1], vectors[2]
    if shape[0] == PLANE:
        _unit_into(shape[5:8], 1.0, direction)
        low = 0 if _dot(mine[2:5], direction) <= _dot(mine[5:8], direction) else 3
        for r in range(3):
            core[r] = mine[2 + low + r]
        above = _dot(core, direction) - _dot(shape[2:5], direction) - mine[1]
        moved = _still_side_rise(core, direction, own, base[capsule[k]], tip[capsule[k]], delta, axes, points)
        return max(above - found[0], 0.0) + moved + ROUNDING
    if shape[0] == BOX and not found[0] > -mine[1]:
        return inf  # the core may be inside the box: its distance is not bounded by a point's
    other_radius = 0.0 if shape[0] == BOX else shape[1]
    for r in range(3):
        core[r] = found[1 + r] - mine[1] * found[7 + r]
        there[r] = found[4 + r] + other_radius * found[7 + r]
        direction[r] = there[r] - core[r]
    length = sqrt(_dot(direction, direction))
    if not length > _TOUCHING:
        return inf
    for r in range(3):
        direction[r] /= length
    if obstacle[k] >= 0:
        moved = _still_side_rise(core, direction, own, base[capsule[k]], tip[capsule[k]], delta, axes, points)
    else:
        second = other[k]
        bottom, top = min(own, frame[second]), max(own, frame[second])
        low_point, low, high_point, high = (core, capsule[k], there, second) if own <= frame[second] else \
            (there, second, core, capsule[k])
        moved = min(_point_rise(low_point, direction, top - 1, bottom - 1, _DOWN, tip[low], delta, axes, points),
                    _point_rise(high_point, direction, bottom, top, _UP, base[high], delta, axes, points))
    return max(length - mine[1] - other_radius - found[0], 0.0) + moved + lever * lever / (2.0 * length) + ROUNDING


@kernel
def _still_side_rise(point, direction, own, base, tip, delta, axes, points):
    """:func:`_point_rise` of a point on frame ``own`` against something the world holds still, the smaller of its
    motion relative to the base (joints 1..own, levers ``base``) and to the tool (own + 1..n, levers ``tip``)."""
    return min(_point_rise(point, direction, _FIRST, own, _UP, base, delta, axes, points),
               _point_rise(point, direction, base.shape[0] - 1, own - 1, _DOWN, tip, delta, axes, points))


@kernel
def _drop(row, u, sign, first, stop, step, levers, delta, axes, points):
    """How far the largest of ``sign u . e`` over the two ends ``e`` of capsule ``row`` may rise when the joints
    ``first, first + step, .. (before stop)`` turn it, each by at most ``delta[j]``, about axes held still by the
    joints before it in that order (the first's fixed): :func:`_point_rise` of each end, the largest."""
    start_value, end_value = sign * _dot(row[2:5], u), sign * _dot(row[5:8], u)
    best = max(start_value, end_value)
    risen = max(start_value + _point_rise(row[2:5], u, first, stop, step, levers, delta, axes, points),
                end_value + _point_rise(row[5:8], u, first, stop, step, levers, delta, axes, points))
    return risen - best


@kernel
def _point_rise(point, direction, first, stop, step, levers, delta, axes, points):
    """A bound of ``|direction . (p' - p)|`` for a point ``p`` moved by the joints ``first, first + step, ..``
    (before ``stop``), each by at most ``delta[j]`` (module :mod:`redkin.collision.joint_motion`, "Along the
    normal"): ``sum_j |direction . (w_j x (p - o_j))| delta_j`` at the axes ``w_j`` through ``o_j``, plus half the
    bound ``sum_j delta_j (2 A_j l_j + B_j)`` of the second derivative along the straight path in joint space, ``l_j``
    = ``levers[j]`` bounding ``|p - o_j|`` in every configuration, ``A_j`` the sum of the ``delta`` before ``j`` in
    the order, ``B_j`` the sum of ``delta_i l_i`` from ``j`` on."""
    first_order, remainder, before, after = 0.0, 0.0, 0.0, 0.0
    j = first
    while j != stop:  # B_j of the first joint: every delta_i l_i
        after += delta[j] * levers[j]
        j += step
    j = first
    while j != stop:
        ox, oy, oz = point[0] - points[j, 0], point[1] - points[j, 1], point[2] - points[j, 2]
        wx, wy, wz = axes[j, 0], axes[j, 1], axes[j, 2]
        speed = (direction[0] * (wy * oz - wz * oy) + direction[1] * (wz * ox - wx * oz)
                 + direction[2] * (wx * oy - wy * ox))
        first_order += abs(speed) * delta[j]
        remainder += delta[j] * (2.0 * before * levers[j] + after)
        before += delta[j]
        after -= delta[j] * levers[j]
        j += step
    return first_order + 0.5 * remainder


@kernel
def _support_high(row, u):
    """The largest ``u . x`` over a capsule or sphere ``row``."""
    return max(_dot(row[2:5], u), _dot(row[5:8], u)) + row[1]


@kernel
def _support_low(row, u):
    """The least ``u . x`` over the shape ``row``, a box, a capsule or a sphere."""
    if row[0] == BOX:
        low = _dot(row[2:5], u)
        for axis in range(3):
            along = u[0] * row[8 + axis] + u[1] * row[11 + axis] + u[2] * row[14 + axis]
            low -= row[5 + axis] * abs(along)
        return low
    return min(_dot(row[2:5], u), _dot(row[5:8], u)) - row[1]


@kernel
def _dot(x, y):
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]


@kernel
def _unit_into(vector, sign, out):
    """``sign vector / |vector|`` into ``out`` (3,)."""
    length = sqrt(_dot(vector, vector))
    for r in range(3):
        out[r] = sign * vector[r] / length
