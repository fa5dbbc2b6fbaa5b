"""The compiled step of :mod:`redkin.collision.mesh_cover`: the shortest capsule along one axis containing points.

The fit tries hundreds of axes per mesh (cuts, candidates, Nelder-Mead), each needing the smallest circle around the
points projected on the axis' normal plane; in Python that circle alone took about half a millisecond.

Inputs are trusted (the module that calls validates them): ``points`` a finite ``(N, 3)`` C-contiguous float array,
``N >= 1``; ``axis`` a unit vector; ``order`` a permutation of ``range(N)`` (Welzl's algorithm is expected linear in
a random order, cubic in a bad one, such as points listed round a circle).
"""

from __future__ import annotations

from math import hypot, pi, sqrt

import numpy as np

from redkin._compiled import kernel


@kernel
def _outside(x, y, cx, cy, radius):
    """Whether the point ``(x, y)`` lies outside the circle, beyond rounding."""
    return hypot(x - cx, y - cy) > radius * (1.0 + 1e-12) + 1e-15


@kernel
def _circle_through(px, py, qx, qy, sx, sy):
    """The circle through three points (centre and radius); for three on a line, the one whose diameter is the
    farthest two."""
    bx, by, cx, cy = qx - px, qy - py, sx - px, sy - py
    cross = bx * cy - by * cx
    bb, cc = bx * bx + by * by, cx * cx + cy * cy
    if abs(cross) <= 1e-14 * (bb + cc):
        pq, ps, qs = hypot(bx, by), hypot(cx, cy), hypot(sx - qx, sy - qy)
        if pq >= ps and pq >= qs:
            return (px + qx) / 2.0, (py + qy) / 2.0, pq / 2.0
        if ps >= qs:
            return (px + sx) / 2.0, (py + sy) / 2.0, ps / 2.0
        return (qx + sx) / 2.0, (qy + sy) / 2.0, qs / 2.0
    ox, oy = (cy * bb - by * cc) / (2.0 * cross), (bx * cc - cx * bb) / (2.0 * cross)
    return px + ox, py + oy, hypot(ox, oy)


@kernel
def enclosing_circle(flat, order):
    """The smallest circle containing the planar points ``flat`` (``(N, 2)``), visited in ``order``: Welzl's
    algorithm, iterative (a point outside the circle so far lies on the new one).  Returns ``(cx, cy, radius)``."""
    n = flat.shape[0]
    x = np.empty(n)
    y = np.empty(n)
    for k in range(n):
        x[k], y[k] = flat[order[k], 0], flat[order[k], 1]
    cx, cy, radius = x[0], y[0], 0.0
    for i in range(1, n):
        if _outside(x[i], y[i], cx, cy, radius):
            cx, cy, radius = x[i], y[i], 0.0
            for j in range(i):
                if _outside(x[j], y[j], cx, cy, radius):
                    cx, cy = (x[i] + x[j]) / 2.0, (y[i] + y[j]) / 2.0
                    radius = hypot(x[i] - x[j], y[i] - y[j]) / 2.0
                    for k in range(j):
                        if _outside(x[k], y[k], cx, cy, radius):
                            cx, cy, radius = _circle_through(x[i], y[i], x[j], y[j], x[k], y[k])
    return cx, cy, radius


@kernel
def capsule_along(points, axis, order):
    """The shortest capsule along the unit ``axis`` containing ``points`` (:mod:`redkin.collision.mesh_cover`'s
    fit): the radius of the smallest circle around the points projected on the normal plane, the segment through its
    centre from the lowest to the highest height any point needs.  Returns ``(ends, radius, volume)``, ``ends`` a
    ``(2, 3)`` array."""
    helper = 0
    for k in range(1, 3):
        if abs(axis[k]) < abs(axis[helper]):
            helper = k
    first = np.zeros(3)
    first[(helper + 1) % 3], first[(helper + 2) % 3] = -axis[(helper + 2) % 3], axis[(helper + 1) % 3]
    first /= sqrt(first[0] ** 2 + first[1] ** 2 + first[2] ** 2)  # normal to the axis and to e_helper
    second = np.cross(axis, first)
    n = points.shape[0]
    flat = np.empty((n, 2))
    heights = np.empty(n)
    for k in range(n):
        flat[k, 0] = points[k, 0] * first[0] + points[k, 1] * first[1] + points[k, 2] * first[2]
        flat[k, 1] = points[k, 0] * second[0] + points[k, 1] * second[1] + points[k, 2] * second[2]
        heights[k] = points[k, 0] * axis[0] + points[k, 1] * axis[1] + points[k, 2] * axis[2]
    cx, cy, radius = enclosing_circle(flat, order)
    low, high = np.inf, -np.inf
    for k in range(n):
        reach = sqrt(max(radius * radius - (flat[k, 0] - cx) ** 2 - (flat[k, 1] - cy) ** 2, 0.0))
        low = min(low, heights[k] + reach)
        high = max(high, heights[k] - reach)
    if low > high:  # a sphere holds them all: any height between the two does
        low = high = (low + high) / 2.0
    ends = np.empty((2, 3))
    for k in range(3):
        middle = cx * first[k] + cy * second[k]
        ends[0, k] = middle + low * axis[k]
        ends[1, k] = middle + high * axis[k]
    return ends, radius, pi * radius * radius * (high - low) + 4.0 / 3.0 * pi * radius ** 3
