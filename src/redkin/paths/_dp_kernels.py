"""The compiled sweep of path resolution: dynamic programming over the arm-angle samples of consecutive waypoints.

:func:`sweep` walks each path waypoint by waypoint.  A node is one sample
(waypoint, branch, arm angle) with its joint values and clearance; its value
is the pair (smallest clearance along the best path reaching it, total
joint motion of that path), compared lexicographically: larger clearance
first, then less motion (or, for the objective ``"motion"``, the other way
round).  An edge joins two nodes of consecutive waypoints
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
from redkin.franka._kernels import WORK, solve_q7
from redkin.srs._ik_kernels import branch_angles, chain_values


@kernel
def _node_row(entries, theta4, angle, first, third, joints, lower, upper, circle, theta, row):
    """One node's joint values into ``row`` (n,): :func:`redkin.srs._ik_kernels.branch_angles` [000 eqs. 11, 13-15,
    17-19] at arm angle ``angle`` from one waypoint's ``entries`` (3, 14) and ``theta4`` for one elbow sign, with
    the branch's shoulder and wrist signs ``first``, ``third``, then :func:`redkin.srs._ik_kernels.chain_values`
    (``joints`` (5, 7), ``theta`` (7,) scratch).  Each joint that is not ``circle`` is clipped into ``lower`` ..
    ``upper``; returns the node's clearance before the clip: the smallest distance of such a joint to a limit
    (negative outside, ``inf`` where every joint is ``circle``)."""
    branch_angles(entries, theta4, angle, first, third, theta)
    chain_values(theta, joints, row)
    return _clipped(row, lower, upper, circle)


@kernel
def _clipped(row, lower, upper, circle):
    """Clip each joint of ``row`` that is not ``circle`` into ``lower`` .. ``upper``; returns the clearance before
    the clip: the smallest distance of such a joint to a limit (negative outside, ``inf`` where every joint is
    ``circle``)."""
    least = inf
    for a in range(row.shape[0]):
        if not circle[a]:
            least = min(least, min(row[a] - lower[a], upper[a] - row[a]))
            row[a] = min(max(row[a], lower[a]), upper[a])
    return least


@kernel
def q7_node_rows(start, stop, waypoint, branch, frames, q7, arm, table, joints, lower, upper, circle, q, clearance):
    """The Franka class's nodes ``start .. stop - 1`` into ``q`` (K, 7) and ``clearance`` (K,): node ``k`` is
    joint 7 at ``q7[k]`` on branch ``branch[k]`` (a row of ``table`` (8, 3), the solver's signs) at waypoint
    ``waypoint[k]``, whose frame 7 in frame 0 is ``frames[waypoint[k]]``: one branch of
    :func:`redkin.franka._kernels.solve_q7` [F1]-[F7] (``arm``, ``joints`` as there), clipped as :func:`_clipped`.
    Where the branch does not exist the clearance is ``-inf`` (and the row zeros)."""
    scratch = np.empty((8, 3, 3))
    work = np.empty(WORK)
    exists = np.empty(1, dtype=np.bool_)
    for k in range(start, stop):
        b = branch[k]
        solve_q7(frames[waypoint[k]], q7[k] + joints[0, 6], arm, table[b : b + 1], joints, q[k : k + 1], exists,
                 scratch, work)
        clearance[k] = _clipped(q[k], lower, upper, circle) if exists[0] else -inf


@kernel
def node_rows(start, stop, waypoint, branch, entries, theta4, psi, table, joints, lower, upper, circle, q, clearance):
    """:func:`_node_row` of nodes ``start .. stop - 1`` into ``q`` (K, n) and ``clearance`` (K,): node ``k`` is
    arm angle ``psi[k]`` on branch ``branch[k]`` (a row of ``table`` (8, 3), its Table 1 signs) at waypoint
    ``waypoint[k]``, whose entry coefficients and theta_4 for the elbow signs ``+1, -1`` are ``entries`` (W, 2,
    3, 14) and ``theta4`` (W, 2), read in place (no per-node copy of a waypoint's coefficients)."""
    theta = np.empty(7)
    for k in range(start, stop):
        b = branch[k]
        elbow = 1 if table[b, 1] < 0.0 else 0
        clearance[k] = _node_row(entries[waypoint[k], elbow], theta4[waypoint[k], elbow], psi[k], table[b, 0],
                                 table[b, 2], joints, lower, upper, circle, theta, q[k])


@kernel
def split_counts(psi, piece, q, step, circle, fraction, min_spacing, parts):
    """Into how many parts :func:`redkin.paths.graph.connect` cuts the interval between nodes ``i`` and ``i + 1``
    (``parts`` (K - 1,), 1: not cut): nodes sorted by waypoint, piece and parameter ``psi`` (K,), ``piece`` (K,)
    (-1: a node alone), joint values ``q`` (K, n).  An interval inside a piece wider than ``2 min_spacing`` is cut into
    ``ceil(r / fraction)`` parts, ``r`` the largest move of a joint across it relative to ``step`` (on the circle
    where ``circle``), but none narrower than ``min_spacing``."""
    for i in range(psi.shape[0] - 1):
        parts[i] = 1
        if piece[i + 1] != piece[i] or piece[i + 1] < 0:
            continue
        width = psi[i + 1] - psi[i]
        if not width > 2.0 * min_spacing:
            continue
        ratio = 0.0
        for a in range(q.shape[1]):
            ratio = max(ratio, gap(q[i + 1, a], q[i, a], circle[a]) / step[a])
        count = min(np.ceil(ratio / fraction), np.floor(width / min_spacing))
        if count > 1.0:
            parts[i] = int(count)


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
def _scan(first, last, order, node, q, step, circle, value, motion, clear, best, motion_first):
    """Relax ``node`` from the candidates ``order[first .. last - 1]``; ``best`` (3,) holds (value, motion,
    parent) and is updated in place; ``motion_first``: the least motion first, then the largest value.  Exact ties
    go to the lower node index, so that the result does not depend on the order of the candidates (the window's
    key joint, :func:`redkin.paths.search.key_joint`)."""
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
        if motion_first:
            better = m < best[1] or (m == best[1] and (v > best[0] or (v == best[0] and i < best[2])))
        else:
            better = v > best[0] or (v == best[0] and (m < best[1] or (m == best[1] and i < best[2])))
        if better:
            best[0], best[1], best[2] = v, m, i


@kernel
def _relax_waypoint(before, after, offsets, q, clearance, sorted_key, order, key_joint, step, circle, value, motion,
                    parent, best, motion_first):
    """Relax every node of waypoint ``after`` from waypoint ``before``; returns whether any node was reached."""
    a0, a1 = offsets[before], offsets[before + 1]
    s = step[key_joint]
    wrap = circle[key_joint]
    alive = False
    for node in range(offsets[after], offsets[after + 1]):
        best[0], best[1], best[2] = -inf, inf, -1.0
        key = q[node, key_joint]
        if wrap and s >= pi:
            _scan(a0, a1, order, node, q, step, circle, value, motion, clearance[node], best, motion_first)
        else:
            lo = _first_at_least(sorted_key, a0, a1, key - s)
            hi = _first_above(sorted_key, a0, a1, key + s)
            _scan(lo, hi, order, node, q, step, circle, value, motion, clearance[node], best, motion_first)
            if wrap and key - s < -pi:  # the window's part beyond -pi, seen from +pi
                lo = _first_at_least(sorted_key, a0, a1, key - s + TWO_PI)
                _scan(lo, a1, order, node, q, step, circle, value, motion, clearance[node], best, motion_first)
            if wrap and key + s > pi:
                hi = _first_above(sorted_key, a0, a1, key + s - TWO_PI)
                _scan(a0, hi, order, node, q, step, circle, value, motion, clearance[node], best, motion_first)
        value[node], motion[node], parent[node] = best[0], best[1], int(best[2])
        alive = alive or best[2] >= 0.0
    return alive


@kernel
def sweep(path_starts, offsets, q, clearance, sorted_key, order, key_joint, step, circle, value, motion, parent,
          dead, motion_first):
    """Dynamic programming over every path: ``value``, ``motion`` and ``parent`` of each node (K,).

    ``path_starts`` (P + 1,): the waypoints of path ``p`` are ``path_starts[p] .. path_starts[p + 1] - 1``;
    ``offsets`` (W + 1,): the nodes of waypoint ``w`` are ``offsets[w] .. offsets[w + 1] - 1``; ``q`` (K, n)
    and ``clearance`` (K,) per node; ``sorted_key``, ``order`` (K,): per waypoint, the key joint's values
    sorted and the node each came from.  The caller sets ``value`` and ``motion`` of each path's first
    waypoint (``-inf`` where a node is not allowed to start) and ``value`` of the others to ``-inf``.
    ``motion_first``: the objective's order is (least motion, largest value) instead of the other way.  Writes
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
                                   value, motion, parent, best, motion_first):
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
