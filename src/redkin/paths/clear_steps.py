"""Paths in a cell whose steps are proved clear (issue 40): search again without the steps that run into an obstacle.

Every waypoint of a path in a cell lies in the certified collision-free sets
(:mod:`redkin.paths.collision_family`), but the joint values interpolate
between two waypoints, and on the way a link may cut the corner of an obstacle
that both ends keep clear of, or sweep through a thin one.  The family's
:meth:`~redkin.paths.family.Family.steps` proves each step clear or finds it
blocked (:func:`redkin.collision.step_clearance`).

The search here is *lazy*, as in lazy roadmaps: a path whose steps are not all
proved clear is searched again on its graph of samples with the edges of those
steps left out, and with them every other edge between the same two waypoints
whose step is not proved clear (each pair of waypoints is checked whole once,
the first time a path's step between them is not proved).  The new path's
steps are checked in turn, until every step of the best path is proved clear
or no path is left; each round settles at least one pair of waypoints, so
there are at most as many rounds as steps.  The dynamic programme is exact on
the graph that remains, so the path returned is the best of the sampled graph
among the paths whose every step is proved clear.  Where no path is left, the
failure is a statement about the sampled graph, not a proof (``exact`` is
False): it names the first waypoint no path reaches and the link and obstacle
that block the most of the steps left out into it.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from redkin.circle import wrap_angle
from redkin.paths.family import Family
from redkin.paths.graph import Arm, Graph
from redkin.paths.result import PathFailure, PathResult


def with_clear_steps(family: Family, arm: Arm, results: list[PathResult], graph: Graph, path_starts: np.ndarray,
                     searched: Callable, checked: Callable, polished: Callable) -> list[PathResult]:
    """``results`` (one per path) with every path's steps proved clear by ``family.steps``.

    A path whose steps are all proved clear keeps its result, with :attr:`PathResult.steps` set.  The others are
    searched again on ``graph`` (the samples the search began with, of the arm ``arm`` along its waypoints;
    ``path_starts`` (P + 1,): the first waypoint of each path in it) without the edges of steps not proved clear
    (module docstring).  ``searched(graph, forbidden)`` returns ``{path: nodes}`` for the paths that have one in
    ``graph`` without the edges ``forbidden`` (sorted keys ``i * K + j``), and their sweep; ``checked(graph, nodes,
    path)`` the checked :class:`PathResult` of those nodes; ``polished(graph, nodes, path, result)`` the same
    polished (``None`` where polishing gains nothing), asked only of a path whose steps are proved clear, and taken
    where its own steps are proved clear too."""
    out = list(results)
    open_paths = []
    for p, result in enumerate(results):
        if not result.ok:
            continue
        steps = family.steps(result.q[:-1], result.q[1:])
        if steps is None:  # not in a cell
            return out
        if steps.certified.all():
            out[p] = replace(result, steps=steps)
        else:
            open_paths.append(p)
    forbidden: dict[int, tuple[str, str] | None] = {}  # edge key -> the pair found blocking it (None: unproved)
    settled: set[int] = set()  # waypoints whose steps to the next are all checked
    while open_paths:
        sweep, chosen = searched(graph, np.array(sorted(forbidden), dtype=np.int64))
        still = []
        for p in open_paths:
            if p not in chosen:  # the first waypoint the sweep does not reach (the last: no end node reached)
                dead = int(sweep.dead[p])
                waypoint = dead if dead >= 0 else int(path_starts[p + 1] - path_starts[p] - 1)
                out[p] = _failure(graph, path_starts, p, waypoint, forbidden, results[p])
                continue
            nodes = chosen[p]
            plain = checked(graph, nodes, p)
            steps = family.steps(plain.q[:-1], plain.q[1:]) if plain.ok else None
            if steps is None or steps.certified.all():
                better = polished(graph, nodes, p, plain) if plain.ok else None
                out[p] = _best_clear(family, plain, steps, better, results[p].nodes)
                continue
            for k in np.flatnonzero(~steps.certified).tolist():
                pair = (str(steps.link[k]), str(steps.against[k])) if steps.blocked[k] else None
                forbidden[int(nodes[k]) * len(graph.psi) + int(nodes[k + 1])] = pair
                w = int(path_starts[p]) + k
                if w not in settled:
                    settled.add(w)
                    forbidden.update(_unclear_edges(family, arm, graph, w))
            still.append(p)
        open_paths = still
    return out


def _unclear_edges(family: Family, arm: Arm, graph: Graph, w: int) -> dict[int, tuple[str, str] | None]:
    """Every edge of ``graph`` from waypoint ``w`` to the next (no joint moving more than its bound) whose step is
    not proved clear, with the pair found blocking it (``None`` where unproved)."""
    before = np.arange(graph.offsets[w], graph.offsets[w + 1])
    after = np.arange(graph.offsets[w + 1], graph.offsets[w + 2])
    fits = np.all(arm.moves(graph.q[before][:, None], graph.q[after][None]) <= arm.step, axis=-1)
    i, j = before[np.nonzero(fits)[0]], after[np.nonzero(fits)[1]]
    start = graph.q[i]
    turn = graph.q[j] - start
    end = start + np.where(arm.circle, wrap_angle(turn), turn)  # the shorter way round
    steps = family.steps(start, end)
    assert steps is not None
    unclear = np.flatnonzero(~steps.certified)
    return {int(i[k]) * len(graph.psi) + int(j[k]): (str(steps.link[k]), str(steps.against[k]))
            if steps.blocked[k] else None for k in unclear.tolist()}


def _best_clear(family: Family, plain: PathResult, steps, polished: PathResult | None, before: int) -> PathResult:
    """``plain`` with its ``steps`` (proved clear), or ``polished`` where its own steps are proved clear too; the
    graphs' sizes counted with the ``before`` nodes of the first search.  A ``plain`` that failed its check (a joint
    that would wind past its range) is returned as it is."""
    if not plain.ok:
        return plain
    if polished is not None:
        again = family.steps(polished.q[:-1], polished.q[1:])
        if again is not None and again.certified.all():
            return replace(polished, steps=again, nodes=before + polished.nodes)
    return replace(plain, steps=steps, nodes=before + plain.nodes)


def _failure(graph: Graph, path_starts: np.ndarray, p: int, waypoint: int,
             forbidden: dict[int, tuple[str, str] | None], found: PathResult) -> PathResult:
    """The failure of path ``p`` at ``waypoint`` (counted from its first): no step into it that the graph allows is
    proved clear; the pair named blocks the most of the steps left out into it."""
    size = len(graph.psi)
    into = graph.waypoint[np.array([key % size for key in forbidden], dtype=np.int64)] - int(path_starts[p])
    pairs = Counter(pair for pair, w in zip(forbidden.values(), into.tolist(), strict=True)
                    if w == waypoint and pair is not None)
    pair = pairs.most_common(1)[0][0] if pairs else None
    return PathResult("no-path", np.empty((0, 7)), [], np.empty(0), float("nan"), float("nan"), found.step,
                      PathFailure(int(waypoint), "steps", None, False, pair=pair, parameter=found.parameter),
                      found.nodes,
                      parameter=found.parameter)
