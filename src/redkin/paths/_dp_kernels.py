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

Edges may also be *forbidden* (``forbidden``: the sorted keys ``i * K + j`` of
the edges from node ``i`` to node ``j`` of ``K`` nodes): path resolution in a
cell forbids the steps that run into an obstacle (:mod:`redkin.paths.clear_steps`).
"""

from __future__ import annotations

from math import inf, pi

import numpy as np

from redkin import _array_copy
from redkin._compiled import kernel
from redkin.circle import TWO_PI
from redkin.franka._kernels import WORK, solve_q7
from redkin.srs._ik_kernels import apply_sign, chain_values, groups_angles


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
        solve_q7(frames[waypoint[k]], q7[k], arm, table[b : b + 1], joints, q[k : k + 1], exists,
                 scratch, work)
        clearance[k] = _clipped(q[k], lower, upper, circle) if exists[0] else -inf


@kernel
def sample_angles(start, stop, nodes, waypoint, branch, entries, psi, table, angles):
    """The shoulder's and wrist's angles on the branch signs +1 (:func:`redkin.srs._ik_kernels.groups_angles`
    [000 eqs. 13-15, 17-19]) of samples ``start .. stop - 1`` into ``angles`` (S, 7): sample ``t`` is arm angle
    ``psi[k]`` at waypoint ``waypoint[k]`` with the elbow sign of branch ``branch[k]`` (a row of ``table`` (8, 3),
    its Table 1 signs), ``k = nodes[t]``; ``entries`` (W, 2, 3, 14) holds each waypoint's entry coefficients for
    the elbow signs ``+1, -1``, read in place."""
    for t in range(start, stop):
        k = nodes[t]
        elbow = 1 if table[branch[k], 1] < 0.0 else 0
        groups_angles(entries[waypoint[k], elbow], psi[k], angles[t])


@kernel
def node_rows(start, stop, sample, angles, waypoint, branch, theta4, table, joints, lower, upper, circle, q,
              clearance):
    """The joint values of nodes ``start .. stop - 1`` into ``q`` (K, n) and their clearance into ``clearance``
    (K,): node ``k`` on branch ``branch[k]`` (a row of ``table`` (8, 3), its Table 1 signs) at waypoint
    ``waypoint[k]`` takes the angles of its arm angle's sample, ``angles[sample[k]]`` (:func:`sample_angles`),
    theta_4 of its elbow sign from ``theta4`` (W, 2) [000 eq. 11], its branch's signs
    (:func:`redkin.srs._ik_kernels.apply_sign`), then :func:`redkin.srs._ik_kernels.chain_values` (``joints``
    (5, 7)); each joint that is not ``circle`` is clipped into ``lower .. upper`` and the clearance is the one
    before the clip (:func:`_clipped`)."""
    theta = np.empty(7)
    for k in range(start, stop):
        b = branch[k]
        _array_copy.copy_into(theta, angles[sample[k]])
        theta[3] = theta4[waypoint[k], 1 if table[b, 1] < 0.0 else 0]
        apply_sign(theta, np.int64(0), table[b, 0])
        apply_sign(theta, np.int64(4), table[b, 2])
        chain_values(theta, joints, q[k])
        clearance[k] = _clipped(q[k], lower, upper, circle)


@kernel
def piece_nodes(start, stop, lo, hi, first, grid, spacing, offsets, leader, waypoint, branch, node_waypoint,
                node_branch, piece, psi, shared):
    """The initial nodes of pieces ``start .. stop - 1`` (:func:`redkin.paths.graph.piece_samples`) from
    ``offsets[k]`` on, in increasing arm angle: piece ``k`` (``lo[k] .. hi[k]``, on branch ``branch[k]`` at
    waypoint ``waypoint[k]``) gives its start, the ``grid[k]`` grid points ``-pi + (first[k] + j) spacing``
    (clipped into the piece against rounding) with its middle in their midst, and its end.  Writes each node's
    waypoint, branch, piece and arm angle, and in ``shared`` the node at the same place of piece ``leader[k]`` (a
    piece with the same ends)."""
    for k in range(start, stop):
        t = offsets[k]
        u = offsets[k + 1]
        psi[t] = lo[k]
        t += 1
        middle = 0.5 * (lo[k] + hi[k])
        placed = False
        for j in range(grid[k]):
            sample = min(max(-pi + spacing * (first[k] + j), lo[k]), hi[k])
            if not placed and middle <= sample:
                psi[t] = middle
                t += 1
                placed = True
            psi[t] = sample
            t += 1
        if not placed:
            psi[t] = middle
            t += 1
        psi[t] = hi[k]
        moved = offsets[leader[k]] - offsets[k]
        for t in range(offsets[k], u):
            node_waypoint[t], node_branch[t], piece[t], shared[t] = waypoint[k], branch[k], k, t + moved


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
def _forbids(forbidden, edge):
    """Whether the sorted keys ``forbidden`` hold ``edge``."""
    at = _first_at_least(forbidden, np.int64(0), forbidden.shape[0], edge)
    return at < forbidden.shape[0] and forbidden[at] == edge


@kernel
def _scan(first, last, order, node, q, step, circle, value, motion, clear, best, motion_first, forbidden):
    """Relax ``node`` from the candidates ``order[first .. last - 1]`` but the edges ``forbidden`` (module
    docstring); ``best`` (3,) holds (value, motion,
    parent) and is updated in place; ``motion_first``: the least motion first, then the largest value.  Exact ties
    go to the lower node index, so that the result does not depend on the order of the candidates (the window's
    key joint, :func:`redkin.paths.search.key_joint`)."""
    for t in range(first, last):
        i = order[t]
        reached = value[i]
        if reached == -inf or (not motion_first and min(reached, clear) < best[0]):
            continue  # not reached, or (clearance first) it cannot beat the best so far whatever its motion
        total = 0.0
        fits = True
        for a in range(q.shape[1]):
            d = gap(q[i, a], q[node, a], circle[a])
            if d > step[a]:
                fits = False
                break
            total += d
        if not fits or (forbidden.shape[0] > 0 and _forbids(forbidden, i * q.shape[0] + node)):
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
def _relax_waypoint(before, after, kept_offsets, q, clearance, sorted_key, order, key_joint, step, circle, value,
                    motion, parent, best, motion_first, forbidden):
    """Relax every kept node of waypoint ``after`` from the kept nodes of waypoint ``before`` (:func:`sweep`);
    returns whether any node was reached.  The nodes are taken in the order of their key joint's value, so the
    window's ends only move forward (one pass over the waypoint before, no bisection but for a circle's wrapped
    part)."""
    a0, a1 = kept_offsets[before], kept_offsets[before + 1]
    s = step[key_joint]
    wrap = circle[key_joint]
    alive = False
    lo, hi = a0, a0
    for t in range(kept_offsets[after], kept_offsets[after + 1]):
        node = order[t]
        best[0], best[1], best[2] = -inf, inf, -1.0
        key = q[node, key_joint]
        if wrap and s >= pi:
            _scan(a0, a1, order, node, q, step, circle, value, motion, clearance[node], best, motion_first,
                  forbidden)
        else:
            while lo < a1 and sorted_key[lo] < key - s:
                lo += 1
            hi = max(hi, lo)
            while hi < a1 and sorted_key[hi] <= key + s:
                hi += 1
            _scan(lo, hi, order, node, q, step, circle, value, motion, clearance[node], best, motion_first,
                  forbidden)
            if wrap and key - s < -pi:  # the window's part beyond -pi, seen from +pi
                first = _first_at_least(sorted_key, a0, a1, key - s + TWO_PI)
                _scan(first, a1, order, node, q, step, circle, value, motion, clearance[node], best, motion_first,
                      forbidden)
            if wrap and key + s > pi:
                last = _first_above(sorted_key, a0, a1, key + s - TWO_PI)
                _scan(a0, last, order, node, q, step, circle, value, motion, clearance[node], best, motion_first,
                      forbidden)
        value[node], motion[node], parent[node] = best[0], best[1], int(best[2])
        alive = alive or best[2] >= 0.0
    return alive


#: Runs of at most this many nodes are sorted in place by insertion (no allocation); longer ones by numpy's argsort.
_SHORT_RUN = 16


@kernel
def sort_by_key(start, stop, offsets, kept, kept_offsets, key, order, sorted_key):
    """Per waypoint ``w`` in ``start .. stop - 1`` (nodes ``offsets[w] .. offsets[w + 1] - 1``): its nodes that are
    ``kept`` (K,), sorted by ``key`` (K,), into ``order`` (the nodes) and ``sorted_key`` (their keys) at
    ``kept_offsets[w] .. kept_offsets[w + 1] - 1`` (the running count of kept nodes)."""
    for w in range(start, stop):
        first, t = kept_offsets[w], kept_offsets[w]
        for node in range(offsets[w], offsets[w + 1]):
            if kept[node]:
                order[t], sorted_key[t] = node, key[node]
                t += 1
        if t - first <= _SHORT_RUN:
            for u in range(first + 1, t):
                node, value = order[u], sorted_key[u]
                v = u
                while v > first and sorted_key[v - 1] > value:
                    order[v], sorted_key[v] = order[v - 1], sorted_key[v - 1]
                    v -= 1
                order[v], sorted_key[v] = node, value
            continue
        ranked = np.argsort(sorted_key[first:t])
        nodes = order[first:t][ranked]
        for u in range(t - first):
            order[first + u] = nodes[u]
            sorted_key[first + u] = key[nodes[u]]


@kernel
def sweep(path_starts, offsets, kept_offsets, q, clearance, sorted_key, order, key_joint, step, circle, value, motion,
          parent, dead, motion_first, forbidden):
    """Dynamic programming over every path: ``value``, ``motion`` and ``parent`` of each node (K,).

    ``path_starts`` (P + 1,): the waypoints of path ``p`` are ``path_starts[p] .. path_starts[p + 1] - 1``;
    ``offsets`` (W + 1,): the nodes of waypoint ``w`` are ``offsets[w] .. offsets[w + 1] - 1``; ``q`` (K, n)
    and ``clearance`` (K,) per node.  Only the *kept* nodes take part (the others stay unreached): those of
    waypoint ``w`` are ``order[kept_offsets[w] .. kept_offsets[w + 1] - 1]``, sorted by their key joint's values
    ``sorted_key`` (:func:`sort_by_key`).  The caller sets ``value`` and ``motion`` of each path's first waypoint
    (``-inf`` where a node is not allowed to start, or not kept) and ``value`` of the others to ``-inf``.
    ``motion_first``: the objective's order is (least motion, largest value) instead of the other way;
    ``forbidden``: edges left out (module docstring).  Writes
    ``dead[p]``: the first waypoint of path ``p`` (counted from its start) that no node reaches, ``-1`` if
    its last one is reached.
    """
    best = np.empty(3)  # value, motion, parent of the node being relaxed
    for p in range(path_starts.shape[0] - 1):
        dead[p] = -1
        first = path_starts[p]
        if first == path_starts[p + 1]:  # no waypoint
            dead[p] = 0
            continue
        alive = False
        for node in range(offsets[first], offsets[first + 1]):
            parent[node] = -1
            alive = alive or value[node] > -inf
        if not alive:
            dead[p] = 0
            continue
        for w in range(first + 1, path_starts[p + 1]):
            if not _relax_waypoint(w - 1, w, kept_offsets, q, clearance, sorted_key, order, key_joint, step, circle,
                                   value, motion, parent, best, motion_first, forbidden):
                dead[p] = w - first
                break
