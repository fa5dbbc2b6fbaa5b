"""Compiled levels of the certified collision-free arm angles (:mod:`redkin.collision.arm_angle_free`): per
interval, the checked pairs' clearances at its middle, the bound of how fast each can change over it, and the
interval decided from both.

An interval ``n`` belongs to pose ``pose[n]`` and branch ``branch[n]``; the pose's entry coefficients ``entries``
(P, 2, 3, 14) and ``theta4`` (P, 2) are those of both elbow signs (:func:`redkin.srs.coefficients.coefficient_arrays`
with signs +1, -1), of which the branch's is row ``elbow[branch]``; ``signs`` (B, 3) are the branches' Table 1
signs.
"""

from __future__ import annotations

from math import ceil, cos, hypot, inf, pi, sin, sqrt

import numpy as np

from redkin._compiled import kernel
from redkin.collision._clearance_kernels import clearances_one, scratch
from redkin.collision._decision_kernels import decided_one, linear_extent
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
#: :func:`turning_bounds` bounds it: below it the pair's normal is not a direction of its own.
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
    """The dot product of two 3-tuples (or arrays of 3)."""
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


@kernel
def _quadratic_root(a, b, k):
    """The least ``t > 0`` at which ``a t^2 + b t`` reaches ``k`` (``a, k >= 0``, ``b`` of either sign; ``inf``
    where it never does, 0 for ``k = 0``: a clearance of exactly 0 keeps no sign, and 0 where ``a`` or ``b`` is not
    finite: such a bound proves nothing), in the forms that do not cancel: ``2 k / (b + sqrt(b^2 + 4 a k))`` for
    ``b >= 0``, ``(sqrt(b^2 + 4 a k) - b) / (2 a)`` for ``b < 0``."""
    if not k > 0.0 or not a < inf or not abs(b) < inf:
        return 0.0
    root = sqrt(b * b + 4.0 * a * k)
    if b < 0.0:
        return (root - b) / (2.0 * a) if a > 0.0 else inf
    denominator = b + root
    return 2.0 * k / denominator if denominator > 0.0 else inf


@kernel
def _one_side(slope, half):
    """A coefficient ``s`` with ``slope sin t <= s t`` for ``0 <= t <= half``: the slope where it is not negative;
    where it is, the slope times ``sin(half) / half`` (``sin t / t`` falls on ``[0, pi]``), or ``|slope|`` for a
    half width of pi or more."""
    if slope >= 0.0:
        return slope
    if half < pi:
        return slope * sin(half) / half
    return -slope


@kernel
def turning_bounds(row, witness, flip, still, line, half, clearance):
    """Bounds of a pair's distance over ``[m - half, m + half]`` where one shape, ``row`` (a capsule on links 3-4),
    turns rigidly about the shoulder-wrist line ``line`` (its point, its unit direction) and the other, ``still`` (a
    row of :mod:`redkin.collision.primitives`), stays still: ``(rate, below, above)``, a bound of how fast the distance
    changes per radian of psi over the interval, and how far from ``m``, towards lower and towards higher psi, the
    pair's ``clearance`` there keeps its sign (positive: clear within each; negative: colliding within each's size);
    ``(inf, 0, 0)`` where the pair was not measured or its cores touch.  ``witness`` is the pair's
    :func:`redkin.collision._distance_kernels.pair_distance` output at ``m`` with ``row`` first, or second where
    ``flip``.  With ``u`` the unit normal from the turning core to the still one, ``c_a, c_b`` their closest points,
    ``g = |c_b - c_a|`` and ``R`` the turn by ``delta = psi - m`` (positive about the line's direction, from the
    shoulder to the wrist: ``0R3(psi) = R_u(psi) 0R3o`` [000 eq. 12]; the module docstring of
    :mod:`redkin.collision.arm_angle_free` states the argument), the distance is

    * at least ``u . c_b - max_e u . e(psi)`` minus both radii (the gap of the projections on ``u``; ``e`` the
      segment's two ends), and each ``u . e`` is ``alpha + beta cos delta + gamma sin delta``, which rises by at
      most ``|gamma| |delta| + max(0, -beta) delta^2 / 2``;
    * at least ``min_b (R u) . (b - P) - u . (c_a - P)`` minus both radii (the gap of the projections on the normal
      turned with the capsule, ``P`` a point of the line, ``b`` the corners of the still shape's core: a sphere's
      centre, a capsule's ends, a box's eight corners; none for a plane), each ``(R u) . (b - P)`` a sinusoid that
      falls by at most ``|gamma| |delta| + max(0, beta) delta^2 / 2``: its fall is the distance's own to first
      order where the closest point is inside the capsule's segment, whose ends the first bound follows;
    * at most ``|c_a(psi) - c_b|`` minus both radii, whose square is ``A + B cos delta + C sin delta``, so it
      rises by at most ``(|C| |delta| + max(0, -B) delta^2 / 2) / (2 g)``.

    All equal the distance at ``m``.  So the larger of the falls' lesser rate and the rise's (each at ``|delta| =
    half``) bounds ``|c(psi) - c(m)| / |delta|``; a positive clearance stays positive while either lower bound falls
    by less than it, a negative one negative while the upper bound rises by less than its size: each a quadratic in
    ``t = |delta|``, whose root is the extent (where the interval's own rate would give only ``clearance / rate``).
    On each side the first-order term keeps its sign, ``gamma sin delta = (+-gamma) sin t``: where it falls towards
    that side it is at most ``(+-gamma) sin(half) / half t`` for ``t <= half`` (:func:`_one_side`), so the extent
    reaches farther on the side the clearance grows towards (the stretch beyond it, near an end of a free arc, is
    decided by the same evaluation instead of another)."""
    distance, other_radius = witness[0], still[1]
    gap = distance + row[1] + other_radius
    if distance != distance or not gap > LEAST_CORE_GAP or not half > 0.0:
        return inf, 0.0, 0.0
    sign, a, b = (-1.0, 4, 1) if flip else (1.0, 1, 4)  # the turning shape's witness point first
    u = (sign * witness[7], sign * witness[8], sign * witness[9])
    core_a = (witness[a] - row[1] * u[0], witness[a + 1] - row[1] * u[1], witness[a + 2] - row[1] * u[2])
    core_b = (witness[b] + other_radius * u[0], witness[b + 1] + other_radius * u[1],
              witness[b + 2] + other_radius * u[2])
    top = max(_dot(u, row[2:5]), _dot(u, row[5:8]))
    fall, below, above = 0.0, inf, inf
    for end in range(2):
        across, swept = _turned(line, row[2 + 3 * end:5 + 3 * end])
        lag = min(_dot(u, row[2 + 3 * end:5 + 3 * end]) - top, 0.0)  # this end's projection below the top
        gamma, bend = _dot(u, swept), max(0.0, -_dot(u, across)) / 2.0
        fall = max(fall, abs(gamma) + bend * half + lag / half)
        if clearance > 0.0:  # this end's projection rises by less than the clearance (and its lag) within the root
            below = min(below, _quadratic_root(bend, _one_side(-gamma, half), clearance - lag))
            above = min(above, _quadratic_root(bend, _one_side(gamma, half), clearance - lag))
    turned_fall, turned_below, turned_above = _turned_normal_fall(still, u, core_b, line, half, clearance)
    fall = min(fall, turned_fall)
    across, swept = _turned(line, core_a)
    z = (line[0] - core_b[0], line[1] - core_b[1], line[2] - core_b[2])
    gamma, bend = 2.0 * _dot(z, swept), max(0.0, -2.0 * _dot(z, across)) / 2.0
    rate = max(fall, (abs(gamma) + bend * half) / (2.0 * gap))
    if not clearance > 0.0:
        depth = -2.0 * gap * clearance
        return (rate, -_quadratic_root(bend, _one_side(-gamma, half), depth),
                -_quadratic_root(bend, _one_side(gamma, half), depth))
    return rate, max(below, turned_below), max(above, turned_above)


@kernel
def _turned_normal_fall(still, u, core_b, line, half, clearance):
    """The second lower bound of :func:`turning_bounds`: ``min_b (R u) . (b - P)`` over the corners ``b`` of the still
    shape's core, its fall's rate over the interval of half width ``half`` and, for a positive ``clearance``, how
    far on each side it stays less than the clearance: ``(rate, below, above)`` (``(inf, 0, 0)`` for a plane, which
    has no corners).  Each
    corner's ``(R u) . (b - P)`` lies ``lag = u . (b - c_b) >= 0`` above the least at ``m``, and ``(R u) . w =
    (u . e)(e . w) + (u_perp . w) cos delta + ((e x u) . w) sin delta``."""
    kind = still[0]
    if kind == 3.0:  # a plane: min_b is unbounded once the normal turns
        return inf, 0.0, 0.0
    ex, ey, ez = line[3], line[4], line[5]
    along = u[0] * ex + u[1] * ey + u[2] * ez
    u_perp = (u[0] - along * ex, u[1] - along * ey, u[2] - along * ez)
    e_u = (ey * u[2] - ez * u[1], ez * u[0] - ex * u[2], ex * u[1] - ey * u[0])
    rate, below, above = 0.0, inf, inf
    corners = 8 if kind == 2.0 else 2
    for corner in range(corners):
        if kind == 2.0:  # a box: centre plus or minus each half size along its axes (the rotation's columns)
            bx, by, bz = still[2], still[3], still[4]
            for axis in range(3):
                size = still[5 + axis] if (corner >> axis) & 1 else -still[5 + axis]
                bx += size * still[8 + axis]
                by += size * still[11 + axis]
                bz += size * still[14 + axis]
        else:  # a sphere's centre (twice), a capsule's ends
            bx, by, bz = still[2 + 3 * corner], still[3 + 3 * corner], still[4 + 3 * corner]
        w = (bx - line[0], by - line[1], bz - line[2])
        lag = max(u[0] * (bx - core_b[0]) + u[1] * (by - core_b[1]) + u[2] * (bz - core_b[2]), 0.0)
        gamma, bend = _dot(e_u, w), max(0.0, _dot(u_perp, w)) / 2.0  # falls as -gamma sin delta, to first order
        rate = max(rate, abs(gamma) + bend * half - lag / half)
        if clearance > 0.0:
            below = min(below, _quadratic_root(bend, _one_side(gamma, half), clearance + lag))
            above = min(above, _quadratic_root(bend, _one_side(-gamma, half), clearance + lag))
    return (rate, below, above) if clearance > 0.0 else (rate, 0.0, 0.0)


@kernel
def level(start, stop, middle, half, pose, branch, entries, theta4, elbow, signs, joints, links, ends, standard,
          frame, a, b, radius, obstacles, capsule, obstacle, other, margin, reach, line, finest, carve, active, kind,
          pair, down, up, carved, cause):
    """One level of the subdivision for intervals ``start .. stop - 1``: the branch's configuration at arm angle
    ``middle[n]`` [000 eqs. 11-19], there the active pairs' clearances (:func:`redkin.collision._clearance_kernels.
    clearances_one`, whose arguments ``links .. margin`` are), their speed bounds over the interval of half width
    ``half[n]`` (:func:`speeds_one`, from ``reach`` (P, M); a pair of a shape on links 3-4 and a still one by
    :func:`turning_bounds` where that is less, from the shoulder-wrist ``line`` (P, 6)), and the interval decided
    (:func:`redkin.collision._decision_kernels.decided_one`: ``active[n]`` updated, the rest into ``kind``,
    ``pair``, ``down``, ``up``, ``carved`` and ``cause``)."""
    theta, q = np.empty(7), np.empty(7)
    work = scratch(links, frame, capsule, obstacles)
    rows, found = work[2], work[3]
    clearance, speed, floor = np.empty(capsule.shape[0]), np.empty(capsule.shape[0]), np.empty(capsule.shape[0])
    below, above = np.empty(capsule.shape[0]), np.empty(capsule.shape[0])
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
            below[k], above[k] = 0.0, 0.0
            if not abs(clearance[k]) <= floor[k]:
                continue  # decided by the bound above (or not measured): no tighter one needed
            if other[k] < 0:
                mine, still, flip, still_row = capsule[k], True, False, obstacles[obstacle[k]]
            elif _turns_about_line(frame[capsule[k]]):
                mine, still, flip, still_row = capsule[k], _still(frame[other[k]]), False, rows[other[k]]
            else:
                mine, still, flip, still_row = other[k], _still(frame[capsule[k]]), True, rows[capsule[k]]
            if still and _turns_about_line(frame[mine]):
                rate, below[k], above[k] = turning_bounds(rows[mine], found[k], flip, still_row, line[p], half[n],
                                                          clearance[k])
                speed[k] = min(speed[k], rate)
        for k in range(capsule.shape[0]):  # how far each clearance keeps its sign: the farther of the two proofs
            linear = linear_extent(clearance[k], speed[k])
            if clearance[k] > 0.0:
                below[k], above[k] = max(linear, below[k]), max(linear, above[k])
            else:
                below[k], above[k] = min(linear, below[k]), min(linear, above[k])
        kind[n], pair[n], down[n], up[n], carved[n], cause[n] = decided_one(half[n], clearance, speed, below, above,
                                                                            active[n], finest, carve)
