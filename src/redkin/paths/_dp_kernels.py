"""The compiled sweep of path resolution: dynamic programming over the arm-angle samples of consecutive waypoints.

:func:`sweep` walks each path waypoint by waypoint.  A node is one sample
(waypoint, branch, arm angle) with its joint values and clearance; its value
is the pair (smallest clearance along the best path reaching it, total
joint motion of that path), compared lexicographically: larger clearance
first, then less motion.  An edge joins two nodes of consecutive waypoints
where no joint moves more than its bound (on the circle for a joint whose
range holds every angle, as a plain difference otherwise).

The candidates of a node are found by a window on one key joint: the nodes
of each waypoint are sorted by that joint's value (``sorted_key``,
``order``), so those within its bound form one run (two on the circle),
found by bisection; only they are checked joint by joint.  The window is a
necessary condition of an edge, so nothing is lost by it.
"""

from __future__ import annotations

from math import inf, pi

import numpy as np

from redkin._compiled import kernel
from redkin.circle import TWO_PI


@kernel
def gap(a, b, circle):
    """``|a - b|``, taken on the circle (the shorter way round) when ``circle``."""
    d = abs(a - b)
    if circle:
        d = d % TWO_PI
        if d > pi:
            d = TWO_PI - d
    return d


@kernel
def _first_at_least(keys, first, last, x):
    """The first index in ``first .. last - 1`` whose key is ``>= x`` (``last`` if none); keys sorted."""
    while first < last:
        middle = (first + last) // 2
        if keys[middle] < x:
            first = middle + 1
        else:
            last = middle
    return first


@kernel
def _first_above(keys, first, last, x):
    """The first index in ``first .. last - 1`` whose key is ``> x`` (``last`` if none); keys sorted."""
    while first < last:
        middle = (first + last) // 2
        if keys[middle] <= x:
            first = middle + 1
        else:
            last = middle
    return first


@kernel
def _scan(first, last, order, node, q, step, circle, value, motion, clear, best):
    """Relax ``node`` from the candidates ``order[first .. last - 1]``; ``best`` (3,) holds (value, motion,
    parent) and is updated in place."""
    for t in range(first, last):
        i = order[t]
        reached = value[i]
        if reached == -inf:
            continue
        total = 0.0
        fits = True
        for a in range(q.shape[1]):
            d = gap(q[i, a], q[node, a], circle[a])
            if d > step[a]:
                fits = False
                break
            total += d
        if not fits:
            continue
        v = min(reached, clear)
        m = motion[i] + total
        if v > best[0] or (v == best[0] and m < best[1]):
            best[0], best[1], best[2] = v, m, i


@kernel
def _relax_waypoint(before, after, offsets, q, clearance, sorted_key, order, key_joint, step, circle, value, motion,
                    parent, best):
    """Relax every node of waypoint ``after`` from waypoint ``before``; returns whether any node was reached."""
    a0, a1 = offsets[before], offsets[before + 1]
    s = step[key_joint]
    wrap = circle[key_joint]
    alive = False
    for node in range(offsets[after], offsets[after + 1]):
        best[0], best[1], best[2] = -inf, inf, -1.0
        key = q[node, key_joint]
        if wrap and s >= pi:
            _scan(a0, a1, order, node, q, step, circle, value, motion, clearance[node], best)
        else:
            lo = _first_at_least(sorted_key, a0, a1, key - s)
            hi = _first_above(sorted_key, a0, a1, key + s)
            _scan(lo, hi, order, node, q, step, circle, value, motion, clearance[node], best)
            if wrap and key - s < -pi:  # the window's part beyond -pi, seen from +pi
                lo = _first_at_least(sorted_key, a0, a1, key - s + TWO_PI)
                _scan(lo, a1, order, node, q, step, circle, value, motion, clearance[node], best)
            if wrap and key + s > pi:
                hi = _first_above(sorted_key, a0, a1, key + s - TWO_PI)
                _scan(a0, hi, order, node, q, step, circle, value, motion, clearance[node], best)
        value[node], motion[node], parent[node] = best[0], best[1], int(best[2])
        alive = alive or best[2] >= 0.0
    return alive


@kernel
def sweep(path_starts, offsets, q, clearance, sorted_key, order, key_joint, step, circle, value, motion, parent,
          dead):
    """Dynamic programming over every path: ``value``, ``motion`` and ``parent`` of each node (K,).

    ``path_starts`` (P + 1,): the waypoints of path ``p`` are ``path_starts[p] .. path_starts[p + 1] - 1``;
    ``offsets`` (W + 1,): the nodes of waypoint ``w`` are ``offsets[w] .. offsets[w + 1] - 1``; ``q`` (K, n)
    and ``clearance`` (K,) per node; ``sorted_key``, ``order`` (K,): per waypoint, the key joint's values
    sorted and the node each came from.  The caller sets ``value`` and ``motion`` of each path's first
    waypoint (``-inf`` where a node is not allowed to start) and ``value`` of the others to ``-inf``.  Writes
    ``dead[p]``: the first waypoint of path ``p`` (counted from its start) that no node reaches, ``-1`` if
    its last one is reached.
    """
    best = np.empty(3)  # value, motion, parent of the node being relaxed
    for p in range(path_starts.shape[0] - 1):
        dead[p] = -1
        first = path_starts[p]
        alive = False
        for node in range(offsets[first], offsets[first + 1]):
            parent[node] = -1
            alive = alive or value[node] > -inf
        if not alive:
            dead[p] = 0
            continue
        for w in range(first + 1, path_starts[p + 1]):
            if not _relax_waypoint(w - 1, w, offsets, q, clearance, sorted_key, order, key_joint, step, circle,
                                   value, motion, parent, best):
                dead[p] = w - first
                break


@kernel
def closest_pair(before, after, step, circle):
    """The pair of rows of ``before`` (R, n) and ``after`` (M, n) whose largest move relative to ``step`` is
    least: returns their indices and that ratio (a pair is dropped as soon as one joint exceeds the best so far)."""
    best, first, second = inf, -1, -1
    for i in range(before.shape[0]):
        for j in range(after.shape[0]):
            worst = 0.0
            for a in range(before.shape[1]):
                worst = max(worst, gap(before[i, a], after[j, a], circle[a]) / step[a])
                if worst >= best:
                    break
            if worst < best:
                best, first, second = worst, i, j
    return first, second, best
