"""Dynamic programming over a :class:`~redkin.paths.graph.Graph`: the best path to every node, and the path back.

The objective is lexicographic (:mod:`redkin.paths._dp_kernels`): the
largest smallest clearance along the path first, then the least total joint
motion.  The sweep itself is the one compiled loop; this module prepares its
arrays and reads its answer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin._compiled import run_batch
from redkin.paths import _dp_kernels
from redkin.paths.graph import Arm, Graph

_NO_EDGES = np.empty(0, dtype=np.int64)
#: Waypoint pairs, and nodes of each waypoint at most, on which :func:`key_joint` counts candidates.
_KEY_PAIRS, _KEY_NODES = 4, 2048


@dataclass(frozen=True)
class Sweep:
    """The best path to each node of a graph.

    Attributes
    ----------
    value, motion : numpy.ndarray, shape (K,)
        The smallest clearance (``-inf``: not reached) and the total motion of the best path to each node.
    parent : numpy.ndarray of int, shape (K,)
        The node before it (``-1`` on the first waypoint or where not reached).
    dead : numpy.ndarray of int, shape (P,)
        Per path, the first waypoint (from its start) no node reaches, ``-1`` if none.
    """

    value: np.ndarray
    motion: np.ndarray
    parent: np.ndarray
    dead: np.ndarray


def run(arm: Arm, graph: Graph, path_starts: np.ndarray, first_value: np.ndarray, first_motion: np.ndarray,
        motion_first: bool = False, key: int | None = None, floor: np.ndarray | None = None,
        forbidden: np.ndarray | None = None) -> Sweep:
    """Sweep every path; ``first_value``, ``first_motion`` (K,) are read on each path's first waypoint only;
    ``motion_first``: the least motion first, then the largest clearance; ``key``: the joint that keys the window
    of candidates (:func:`key_joint` of ``graph`` where ``None``, or where it is a joint compared on the circle
    whose values leave ``[-pi, pi]`` in ``graph``); ``floor`` (P,): each path uses only the nodes whose clearance
    is at least this (``None``: every node); ``forbidden``: the edges left out, sorted keys ``i * K + j`` of the
    edges from node ``i`` to node ``j`` of ``graph``'s ``K`` (:mod:`redkin.paths._dp_kernels`)."""
    waypoint = graph.waypoint
    if key is None or not _keys_circle(graph, arm.circle, key):
        key = key_joint(graph, arm.step, arm.circle)
    offsets = np.ascontiguousarray(graph.offsets, dtype=np.int64)
    starts = np.zeros(len(waypoint), dtype=bool)
    starts[np.isin(waypoint, path_starts[:-1])] = True
    value = np.where(starts, first_value, -np.inf)
    kept = np.ones(len(waypoint), dtype=bool)
    if floor is not None:
        kept = graph.clearance >= np.repeat(np.repeat(floor, np.diff(path_starts)), np.diff(offsets))
        value[~kept] = -np.inf
    kept_offsets = np.concatenate([[0], np.cumsum(kept)])[offsets]
    order, sorted_key = np.empty(kept_offsets[-1], dtype=np.int64), np.empty(kept_offsets[-1])
    run_batch(_dp_kernels.sort_by_key, len(offsets) - 1, offsets, kept, kept_offsets,
              np.ascontiguousarray(graph.q[:, key]), order, sorted_key)
    motion = np.where(starts, first_motion, 0.0)
    parent = np.full(len(waypoint), -1, dtype=np.int64)
    dead = np.empty(len(path_starts) - 1, dtype=np.int64)
    _dp_kernels.sweep(np.ascontiguousarray(path_starts, dtype=np.int64), offsets, kept_offsets,
                      np.ascontiguousarray(graph.q), np.ascontiguousarray(graph.clearance), sorted_key, order, key,
                      np.ascontiguousarray(arm.step), np.ascontiguousarray(arm.circle), value, motion, parent, dead,
                      motion_first, _NO_EDGES if forbidden is None else np.ascontiguousarray(forbidden, dtype=np.int64))
    return Sweep(value, motion, parent, dead)


def key_joint(graph: Graph, step: np.ndarray, circle: np.ndarray) -> int:
    """The joint whose sorted values give the sweep's window of candidates for each node (the nodes of the waypoint
    before within one step of it in that joint alone): the one whose windows hold the fewest nodes, counted on
    :data:`_KEY_PAIRS` pairs of neighbouring waypoints spread over the graph (at most :data:`_KEY_NODES` nodes of
    each; joints compared on the circle counted as plain values).  A joint compared on the circle (``circle``)
    qualifies only where its values lie in ``[-pi, pi]``, as the sweep's window reads them (q7 of a Franka-class arm
    is reported as the joint has it).  Joint 1 where there is no pair.

    A tight bound on one joint makes its window narrow: with bounds of 0.066 rad on joint 1 and 0.002 rad on joint
    3, a window on joint 3 holds a few per cent of the nodes that one on joint 1 holds."""
    offsets = graph.offsets
    if len(offsets) < 3:  # one waypoint: no pair
        return 0
    pairs = np.unique(np.linspace(0, len(offsets) - 3, _KEY_PAIRS).astype(np.int64))
    counts = np.zeros(graph.q.shape[1])
    for joint in np.flatnonzero(circle).tolist():
        if not _keys_circle(graph, circle, joint):
            counts[joint] = np.inf
    for w in pairs:
        before = graph.q[offsets[w]:offsets[w + 1]]
        after = graph.q[offsets[w + 1]:offsets[w + 2]]
        before = before[::max(1, len(before) // _KEY_NODES)]
        after = after[::max(1, len(after) // _KEY_NODES)]
        ordered = np.sort(before, axis=0)
        for j in range(graph.q.shape[1]):
            counts[j] += np.sum(np.searchsorted(ordered[:, j], after[:, j] + step[j], side="right")
                                - np.searchsorted(ordered[:, j], after[:, j] - step[j], side="left"))
    return int(np.argmin(counts))


def _keys_circle(graph: Graph, circle: np.ndarray, joint: int) -> bool:
    """Whether ``joint`` can key the sweep's window in ``graph``: it is not compared on the circle, or its values lie
    in ``[-pi, pi]``, as the window reads them."""
    values = graph.q[:, joint]
    return not circle[joint] or values.size == 0 or bool(np.abs(values).max() <= np.pi)


def best_end(sweep: Sweep, nodes: np.ndarray, motion_first: bool = False) -> int:
    """The best of ``nodes`` (largest value, then least motion; ``motion_first``: the other way round), or -1
    where none is reached."""
    nodes = nodes[sweep.value[nodes] > -np.inf]
    if nodes.size == 0:
        return -1
    keys = (-sweep.value[nodes], sweep.motion[nodes]) if motion_first else (sweep.motion[nodes], -sweep.value[nodes])
    order = np.lexsort(keys)
    return int(nodes[order[0]])


def trace(sweep: Sweep, last: int, count: int) -> np.ndarray:
    """The nodes of the path ending at node ``last``, ``count`` waypoints long, first to last."""
    nodes = np.empty(count, dtype=np.int64)
    node = last
    for k in range(count - 1, -1, -1):
        nodes[k] = node
        node = sweep.parent[node]
    return nodes
