"""The fewest reconfiguration stops where no continuous path exists (``resolve_path(..., allow_stops=True)``).

Where no configuration sequence moves every joint within its bound from one waypoint to the next, an industrial
user stops the tool at a waypoint, reconfigures the arm there (changes branch, or swings the elbow: a jump of the
arm angle or of q7) and goes on.  The path is then split into the fewest continuous segments, each joined to the
next at a stop.

Why greedy is optimal: a segment ``[a, b]`` of waypoints is *continuous* where a path with every step within the
bound exists through them; every part ``[a', b']`` of a continuous segment is continuous.  Covering ``0 .. N-1`` with
continuous segments that share their ends, the one from ``0`` reaching furthest leaves the least to cover, so
reaching furthest from each stop gives the fewest stops (the interval-covering exchange argument).  The furthest
reach is the waypoint before the first failing one of :func:`redkin.paths.resolve_path` on the rest of the path; a
``"step"`` failure is a statement about the searched graph (docs/paths.md), so the count is the fewest on that
graph.  A waypoint with no feasible configuration at all (``"empty"``, ``"out-of-reach"``) cannot be passed with any
number of stops, and the path fails there as without stops.

Between the arrival and departure configurations of a stop (one pose), the arm moves along its *self-motion* where
both lie on one branch in one feasible piece of that pose (the tool stays still; the joint path is the closed form
along the parameter between them); otherwise the move is named a *free-space* move (a straight joint-space motion,
during which the tool leaves the path).  In a cell the reconfiguration's steps are checked, not searched: a
self-motion stays inside one collision-free piece, but a free-space move may cross an obstacle, and
:attr:`redkin.paths.Stop.steps` (and its message) says whether it is proved clear.

:func:`timed` gives a result its trajectory (:func:`redkin.paths.time_path`), at rest at each stop and through its
reconfiguration.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from itertools import pairwise

import numpy as np

from redkin.chain import SerialChain
from redkin.paths.family import Family
from redkin.paths.result import PathResult, Stop
from redkin.paths.timing import time_path
from redkin.srs.branches import BRANCHES, parse_branch

#: Parameter samples of a self-motion at most this far apart (radians).
_SELF_MOTION_SPACING = 0.01
#: The self-motion's joint values meet the stop's two configurations to within this (radians).
_MEETS = 1e-6
#: ``segment(first, last, with_start, with_end)``: :func:`resolve_path` on waypoints ``first..last``, with the
#: caller's start configuration (``with_start``) and end conditions (``with_end``) or without them.
_Segment = Callable[[int, int, bool, bool], PathResult]


def with_stops(family: Family, poses: np.ndarray, step: np.ndarray, segment: _Segment) -> PathResult:
    """The path through ``poses`` in the fewest continuous segments (see the module's docstring), or the failure
    that no stop can pass."""
    last = len(poses) - 1
    first = 0
    pieces: list[PathResult] = []
    stops: list[Stop] = []
    while True:
        result = segment(first, last, first == 0, True)
        if result.ok:
            pieces.append(result)
            break
        failure = result.failure
        assert failure is not None
        reach = first + failure.waypoint - 1  # the furthest waypoint a continuous segment from ``first`` reaches
        if failure.reason != "step" or reach <= first:
            return replace(result, failure=replace(failure, waypoint=first + failure.waypoint),
                           nodes=result.nodes + sum(p.nodes for p in pieces))
        part = segment(first, reach, first == 0, False)
        assert part.ok, "a segment short of the first failing waypoint has a path"
        pieces.append(part)
        first = reach
    for before, after in pairwise(pieces):
        stops.append(_stop(family, poses, step, before, after, stops[-1].waypoint if stops else 0, len(before.q)))
    return _joined(pieces, stops)


def _stop(family: Family, poses: np.ndarray, step: np.ndarray, before: PathResult, after: PathResult,
          start: int, length: int) -> Stop:
    """The stop between two consecutive segments: at the last waypoint of ``before`` (which starts at ``start``
    and holds ``length`` waypoints), the first of ``after``."""
    waypoint = start + length - 1
    q_before, q_after = before.q[-1], after.q[0]
    branch_before, branch_after = before.branch[-1], after.branch[0]
    psi_before, psi_after = float(before.psi[-1]), float(after.psi[0])
    path = None if branch_before != branch_after else _self_motion(family, poses[waypoint], step, branch_before,
                                                                     psi_before, psi_after, q_before, q_after)
    moves = np.abs(q_after - q_before)
    rows = np.stack([q_before, q_after]) if path is None else path
    return Stop(waypoint=waypoint, reason="branch" if branch_before != branch_after else "jump",
                branch_before=branch_before, branch_after=branch_after, parameter_before=psi_before,
                parameter_after=psi_after, joint=int(np.argmax(moves)) + 1, move=float(moves.max()),
                motion="free-space" if path is None else "self-motion", path=rows,
                steps=family.steps(rows[:-1], rows[1:]))


def _self_motion(family: Family, pose: np.ndarray, step: np.ndarray, branch: str, start: float, end: float,
                 q_start: np.ndarray, q_end: np.ndarray) -> np.ndarray | None:
    """The joint path of the self-motion from ``start`` to ``end`` of the parameter on ``branch`` at ``pose``,
    where one feasible piece holds both and the closed form meets both configurations; else ``None``."""
    index = BRANCHES.index(parse_branch(branch))
    pieces = family.pieces(pose[None])
    for lo, hi, feasible in zip(pieces.start[0, index], pieces.end[0, index], pieces.feasible[0, index]):
        if not feasible:
            continue
        # the representatives inside the piece (a piece may run past pi: it wraps)
        inside = [[v for v in (value, value + 2.0 * np.pi) if lo - _MEETS <= v <= hi + _MEETS]
                  for value in (start, end)]
        if not (inside[0] and inside[1]):
            continue
        first, last = inside[0][0], inside[1][0]
        count = int(np.ceil(abs(last - first) / _SELF_MOTION_SPACING)) + 1
        values = np.linspace(first, last, max(count, 2))
        _, arm = family.arm(pose[None], step)
        q, _ = arm.rows(np.zeros(len(values), dtype=np.int64), np.full(len(values), index), values)
        joined = np.abs(q[0] - q_start).max() <= _MEETS and np.abs(q[-1] - q_end).max() <= _MEETS
        if joined and np.all(np.abs(np.diff(q, axis=0)) <= step):
            q[0], q[-1] = q_start, q_end
            return q
    return None


def _stopped_rows(result: PathResult) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """The whole joint path of a result with stops, for timing it: its rows (each waypoint's, with each stop's
    reconfiguration inserted after its arrival), the row of each waypoint, and the rows where the arm rests (each
    stop's arrival and departure)."""
    inserted = [len(stop.path) - 1 for stop in result.stops]  # rows of each reconfiguration after its arrival
    waypoints = np.array([stop.waypoint for stop in result.stops], dtype=np.int64)
    shift = np.zeros(len(result.q) + 1, dtype=np.int64)
    np.add.at(shift, waypoints + 1, inserted)  # the waypoints after a stop come that many rows later
    waypoint_rows = np.arange(len(result.q)) + np.cumsum(shift)[:-1]
    rows = np.insert(result.q, np.repeat(waypoints + 1, inserted),
                     np.concatenate([stop.path[1:] for stop in result.stops] or [np.empty((0, result.q.shape[1]))]),
                     axis=0)
    arrivals = waypoint_rows[waypoints]
    rests = np.stack([arrivals, arrivals + np.array(inserted, dtype=np.int64)], axis=-1).reshape(-1).tolist()
    return rows, waypoint_rows, rests


def _joined(pieces: list[PathResult], stops: list[Stop]) -> PathResult:
    """One result of consecutive segments: one row per waypoint (a stop's waypoint keeps its arrival
    configuration; the departure one is the stop's ``path[-1]``)."""
    rows = [pieces[0].q] + [p.q[1:] for p in pieces[1:]]
    branch = pieces[0].branch + [b for p in pieces[1:] for b in p.branch[1:]]
    psi = np.concatenate([pieces[0].psi] + [p.psi[1:] for p in pieces[1:]])
    motion = sum(p.motion for p in pieces) + sum(float(np.abs(np.diff(s.path, axis=0)).sum()) for s in stops)
    steps = pieces[0].steps
    if steps is not None:  # in a cell: each segment's steps, in order (a stop's waypoint ends one, begins the next)
        steps = type(steps)(*(np.concatenate([getattr(p.steps, name) for p in pieces]) for name in steps._fields))
    return replace(pieces[0], q=np.concatenate(rows), branch=branch, psi=psi,
                   clearance=min(p.clearance for p in pieces), motion=motion, nodes=sum(p.nodes for p in pieces),
                   optimal=False, bottleneck=None, stops=tuple(stops), steps=steps,
                   cell_clearance=min((p.cell_clearance for p in pieces if p.cell_clearance is not None), default=None))


def timed(chain: SerialChain, result: PathResult, rate: float, density: int = 1, *, at_rest: bool = False
          ) -> PathResult:
    """``result`` with its :attr:`~redkin.paths.PathResult.trajectory` (:func:`time_path` of its joint values at
    ``rate``, at rest at each stop and through its reconfiguration); a result without a path as it is.
    ``density``: the spline passes through ``density - 1`` more points evenly spaced on each straight joint-space
    step between consecutive rows, so that it stays nearer those steps (a path in a cell proves them clear).
    ``at_rest``: the arm rests at every row, so that the joint path between two rows is their straight step itself
    (a spline through two points is the line), at the cost of stopping at each."""
    if not result.ok:
        return result
    rows, waypoint_rows, rests = _stopped_rows(result)
    if density > 1:
        fractions = np.arange(density)[:, None, None] / density  # (density, 1, 1)
        between = (1.0 - fractions) * rows[None, :-1] + fractions * rows[None, 1:]  # (density, R - 1, n)
        rows = np.concatenate([between.transpose(1, 0, 2).reshape(-1, rows.shape[1]), rows[-1:]])
        waypoint_rows = waypoint_rows * density
        rests = [row * density for row in rests]
    resting = sorted(set(rests) | set(range(1, len(rows) - 1))) if at_rest else rests
    trajectory = time_path(chain, rows, rate=rate, rests=resting)
    times = trajectory.waypoint_times
    spans = np.stack([times[rests[0::2]], times[rests[1::2]]], axis=-1).reshape(-1, 2)
    return replace(result, trajectory=replace(trajectory, waypoint_times=times[waypoint_rows], stop_spans=spans))
