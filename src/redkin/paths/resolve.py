"""Path resolution: the arm angle chosen over a whole path of poses, inside the exact feasible sets.

:func:`resolve_path` (one path) and :func:`resolve_paths` (many, searched in
one sweep) build the graph of :mod:`redkin.paths.graph` over every waypoint,
search it (:mod:`redkin.paths.search`), refine around the path found, and
either return it -- checked: every pose reached within :data:`FK_TOLERANCE`,
every joint within its limits, no joint moving more than its bound -- or
the first waypoint where no path exists (:mod:`redkin.paths.failure`).
Method, objective and guarantees: docs/paths.md.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose, check_vectors
from redkin.chain import SerialChain
from redkin.circle import TWO_PI, wrap_angle
from redkin.errors import RedkinError, SizeLimitError
from redkin.franka.geometry import FrankaGeometry
from redkin.paths import graph as graphs
from redkin.paths import search
from redkin.paths.arm_family import path_family
from redkin.paths.bounds import step_bound
from redkin.paths.clear_steps import with_clear_steps
from redkin.paths.failure import step_blocker
from redkin.paths.family import Family
from redkin.paths.graph import Arm, Graph
from redkin.paths.polish import raised
from redkin.paths.result import PathFailure, PathResult
from redkin.paths.stops import timed, with_stops
from redkin.paths.timing import DEFAULT_RATE, check_timing
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.feasible import FeasiblePieces
from redkin.srs.geometry import SRSGeometry
from redkin.srs.nearly import NearlySRS

if TYPE_CHECKING:
    from redkin.collision.body import Body
    from redkin.collision.scene import Scene
    from redkin.collision.steps import StepClearance

#: Every waypoint of a returned path reaches its pose within this (largest entry of the 4x4 difference).
FK_TOLERANCE = 1e-9
#: The initial grid of arm angles in every feasible piece (radians): 16 points on the circle.
DEFAULT_SPACING = 2.0 * np.pi / 16
#: Neighbouring samples of a piece are made this close (a fraction of each joint's bound) before the search.
DEFAULT_CONNECT = 0.25
#: Rounds of refinement around the path found (:func:`redkin.paths.graph.window`; the window halves each round).
DEFAULT_REFINEMENTS = 30
#: Rounds of refinement where the first search's clearance is already proved optimal (for the motion alone: the
#: rounds after these changed the motion of 1000 iiwa14 waypoints by 1e-5 of itself).
_PROVED_REFINEMENTS = 10
#: The first refinement window (radians of arm angle on each side of the path found).
_FIRST_WINDOW = 0.05
#: Refinement stops once the window is narrower than this (radians of arm angle).
_REFINED = 1e-9
#: The most waypoints of one call, in all: the search holds about 55 kB a waypoint at its peak on the iiwa14 (100 000
#: waypoints: 5.5 GB, mostly the graph's first nodes, which :data:`redkin.paths.graph._MOST_NODES` bounds too).
_MAX_WAYPOINTS = 200_000
#: Two feasible pieces whose ends are this close touch (radians of the parameter; :func:`_arcs_around`).
_TOUCH = 1e-12
#: A joint the poses fix is proved unable to make a step where its least move exceeds its bound by more than this
#: fraction of it (:func:`_fixed_step`): the rounding of the two values, not a move the graph would allow.
_FIXED_SLACK = 1e-9
#: The first search sweeps the nodes of clearance at least these fractions of the clearance no path can exceed, in
#: turn, until it finds a path (:func:`_floored`).
_FLOOR_FRACTIONS = (1.0, 0.5)
#: Searches of a path not proved optimal inside limits moved inwards (:func:`_leveled`), at most.
_LEVEL_ROUNDS = 6
#: The levels of :func:`_leveled` and :func:`_ceiling` stop this close (radians).
_LEVEL_GAP = 1e-7
#: Bisections of :func:`_ceiling` at most.
_CEILING_STEPS = 6
#: What :func:`resolve_path` can make best: the clearance (then the motion), the motion (then the clearance), the
#: duration of the timed trajectory (the faster of the other two's), or in a cell the least distance of the body to
#: the obstacles and itself (then the motion).
OBJECTIVES = ("clearance", "motion", "time", "obstacle-clearance")
#: The objective that needs a cell.
_OBSTACLES = "obstacle-clearance"
#: In a cell, a timed path whose spline is not proved clear is timed again through this many points per straight
#: step between waypoints (the waypoints alone first; :func:`_timed`).
_DENSITIES = (1, 2, 4, 8)
#: In a cell, a timed path whose spline no density of :data:`_DENSITIES` proves clear (its steps graze the margin) is
#: searched again with the scene's margin this much larger (metres), which leaves the spline room beside the steps;
#: only where that fails too does the trajectory rest at every waypoint (:func:`_timed`).
_SPLINE_ROOM = 1e-3
#: A path's clearance is proved optimal when no path can keep this much more (radians; :func:`_bottleneck`).
OPTIMALITY_MARGIN = 1e-7


def resolve_path(
    arm: SerialChain | SRSGeometry | FrankaGeometry | NearlySRS,
    poses: ArrayLike,
    max_step: ArrayLike | None = None,
    *,
    speed: ArrayLike | None = None,
    dt: float | None = None,
    q0: ArrayLike | None = None,
    q_end: ArrayLike | None = None,
    end_branch: str | Branch | None = None,
    spacing: float = DEFAULT_SPACING,
    connect: float = DEFAULT_CONNECT,
    refinements: int = DEFAULT_REFINEMENTS,
    thorough: bool = False,
    objective: str = "clearance",
    srs_tolerance: float | None = None,
    timing: float | None = None,
    allow_stops: bool = False,
    body: Body | None = None,
    scene: Scene | None = None,
) -> PathResult:
    """Joint values along a path of poses, as far from the joint limits as the path allows, or where none exist.

    Maximises the smallest distance of any joint to its limits over the whole path, then (among equals) minimises
    the total joint motion, over arm angles inside the exact feasible sets [000 eq. 30] of every branch, with no
    joint moving more than its bound between waypoints.  The branch may change wherever the joint values stay
    within the bound (through a singular configuration).

    Parameters
    ----------
    arm : Arm, SerialChain, SRSGeometry, FrankaGeometry or NearlySRS
        A :func:`redkin.arm` (classified once), or an S-R-S or offset-elbow arm (the redundancy is the arm angle
        psi), a Franka-class arm (joint 7's value q7, :mod:`redkin.franka`) or a nearly S-R-S arm (the real arm's
        arm angle, :mod:`redkin.srs.nearly`; its feasible sets are certified, not exact: no clearance is proved
        optimal), with its joint limits.
    poses : array_like, shape (N, 4, 4)
        The waypoints.
    max_step : float or array_like of shape (7,), optional
        The largest move of each joint between consecutive waypoints (radians).
    speed : float or array_like of shape (7,), optional
        Joint speeds (rad/s), with ``dt``, instead of ``max_step`` (:func:`redkin.paths.step_bound`).
    dt : float, optional
        Seconds between waypoints.
    q0 : array_like, shape (7,), optional
        The configuration before the path: the first waypoint is within one step of it.  Its own arm angle and
        branch are sampled at the first waypoint, so ``q0`` itself is chosen where it reaches the first pose.
    q_end : array_like, shape (7,), optional
        The last waypoint is within one step of it.
    end_branch : str or Branch, optional
        The branch of the last waypoint.
    spacing : float
        The initial grid of arm angles in each feasible piece.
    connect : float
        Neighbouring samples of a piece are refined until no joint moves more than this fraction of its bound
        between them (0 < connect <= 1).
    refinements : int
        Rounds of refinement around the path found.
    thorough : bool
        Search the subdivided graph (the second stage, docs/paths.md "Method") for every path, not only where the
        samples alone neither found a path whose clearance is proved optimal nor proved that none exists: the
        least motion among the paths of that clearance is then sought on the finer graph too (a few percent
        less motion on short random paths, about ten times the time on long ones).
    objective : str
        What "best" means (:data:`OBJECTIVES`): ``"clearance"``, the largest smallest distance of a joint to its
        limits, then the least total motion (the default); ``"motion"``, the least total joint motion, then the
        largest clearance (both stages are searched, as with ``thorough``; no clearance is proved optimal);
        ``"time"``, the shortest timed trajectory (:func:`redkin.paths.time_path`) of the two paths the other
        objectives choose, so never slower than either (it needs the chain's velocity and acceleration limits;
        where one of the two cannot be timed, the other);
        ``"obstacle-clearance"`` (in a cell, ``body`` and ``scene``), the largest least distance over the waypoints
        between the parts of the body that the redundancy moves and the obstacles or the body's other links, then
        the least motion: every node of the graph is valued by that distance instead of its clearance from the
        limits (both stages are searched; the graph's best, not proved optimal).  A part the pose fixes (the tool's
        link, a ball at the wrist centre) is as close on every branch and arm angle, so it is left out of the
        comparison; it still keeps the margin, and :attr:`PathResult.cell_clearance` counts it.
    srs_tolerance : float, optional
        The nearly S-R-S tolerance of :func:`redkin.arms.classify.arm_angle_class` [m] for a chain of neither exact
        class.
    timing : float, optional
        Time the path found: the time-optimal trajectory through its joint values within the chain's velocity and
        acceleration limits (:func:`redkin.paths.time_path`, the ``timing`` extra), sampled at this rate (Hz), in
        :attr:`PathResult.trajectory`.  ``objective="time"`` times at :data:`redkin.paths.timing.DEFAULT_RATE`
        without it.
    allow_stops : bool
        Where no continuous path exists, split it into the fewest continuous segments joined by reconfiguration
        stops (:mod:`redkin.paths.stops`, :attr:`PathResult.stops`); a waypoint with no feasible configuration
        still fails the path.
    body, scene : Body and Scene, optional
        A cell (issue 40; S-R-S and offset-elbow arms): every waypoint's configuration keeps every capsule of
        ``body`` the scene's margin away from each obstacle and from the body's other links, inside the certified
        collision-free arm angles (:mod:`redkin.paths.collision_family`; the steps between waypoints are not
        searched: :func:`redkin.collision.step_clearance` checks them).  A waypoint the obstacles block on every
        branch fails with reason ``"collision"`` and the pair.

    Returns
    -------
    PathResult
        ``status`` ``"ok"`` with the path, or ``"no-path"`` with the first failing waypoint (:class:`PathFailure`).

    Raises
    ------
    RedkinError
        For malformed poses, bounds or configurations.
    """
    poses = check_pose(poses, "poses")
    if poses.ndim != 3:
        raise RedkinError(f"poses must have shape (N, 4, 4), got shape {poses.shape}; for many paths use "
                          "resolve_paths")
    options: dict[str, Any] = {"speed": speed, "dt": dt, "spacing": spacing, "connect": connect,
                               "refinements": refinements, "thorough": thorough, "objective": objective,
                               "srs_tolerance": srs_tolerance, "body": body, "scene": scene}
    if not allow_stops:
        return resolve_paths(arm, poses[None], max_step, q0=q0, q_end=q_end, end_branch=end_branch, timing=timing,
                             **options)[0]
    family = path_family(arm, srs_tolerance, body, scene)
    if objective == "time" and timing is None:
        timing = DEFAULT_RATE
    if timing is not None:
        check_timing(family.chain, timing)

    step = step_bound(family.chain, max_step, speed, dt)

    def in_cell(cell: Scene | None) -> PathResult:
        def segment(first: int, last: int, with_start: bool, with_end: bool) -> PathResult:
            return resolve_paths(arm, poses[None, first : last + 1], max_step, q0=q0 if with_start else None,
                                 q_end=q_end if with_end else None, end_branch=end_branch if with_end else None,
                                 **{**options, "scene": cell})[0]

        return with_stops(family if cell is scene else path_family(arm, srs_tolerance, body, cell), poses, step,
                          segment)

    result = in_cell(scene)
    if timing is None:
        return result
    return _timed(family, result, float(timing), None if scene is None else lambda: in_cell(_roomier(scene)))


def resolve_paths(
    arm: SerialChain | SRSGeometry | FrankaGeometry | NearlySRS,
    paths: ArrayLike,
    max_step: ArrayLike | None = None,
    *,
    speed: ArrayLike | None = None,
    dt: float | None = None,
    q0: ArrayLike | None = None,
    q_end: ArrayLike | None = None,
    end_branch: str | Branch | None = None,
    spacing: float = DEFAULT_SPACING,
    connect: float = DEFAULT_CONNECT,
    refinements: int = DEFAULT_REFINEMENTS,
    thorough: bool = False,
    objective: str = "clearance",
    srs_tolerance: float | None = None,
    timing: float | None = None,
    body: Body | None = None,
    scene: Scene | None = None,
) -> list[PathResult]:
    """:func:`resolve_path` for ``P`` paths of ``N`` poses each, ``paths`` of shape ``(P, N, 4, 4)``: one
    batch of feasible sets and IK, one sweep.  ``q0`` and ``q_end`` are ``(7,)`` (the same for every path) or
    ``(P, 7)``."""
    family = path_family(arm, srs_tolerance, body, scene)
    chain = family.chain
    poses = check_pose(paths, "paths")
    if poses.ndim != 4 or poses.shape[1] == 0:
        raise RedkinError(f"paths must have shape (P, N, 4, 4) with N >= 1, got shape {poses.shape}")
    count, length = poses.shape[:2]
    if count * length > _MAX_WAYPOINTS:
        raise SizeLimitError(f"at most {_MAX_WAYPOINTS:,} waypoints in all (a size too large to compute), got "
                             f"{count * length:,}", "waypoints", count * length, _MAX_WAYPOINTS)
    step = step_bound(chain, max_step, speed, dt)
    starts = _configurations(q0, count, "q0")
    ends = _configurations(q_end, count, "q_end")
    last_branch = None if end_branch is None else BRANCHES.index(parse_branch(end_branch))
    if not (np.isfinite(spacing) and 0.0 < spacing <= np.pi):
        raise RedkinError(f"spacing must be in (0, pi] radians, got {spacing!r}")
    if not (np.isfinite(connect) and 0.0 < connect <= 1.0):
        raise RedkinError(f"connect must be in (0, 1], got {connect!r}")
    if int(refinements) != refinements or refinements < 0:
        raise RedkinError(f"refinements must be an integer >= 0, got {refinements!r}")
    if objective not in OBJECTIVES:
        raise RedkinError(f"objective must be one of {', '.join(OBJECTIVES)}, got {objective!r}")
    if objective == _OBSTACLES and scene is None:
        raise RedkinError("the objective obstacle-clearance needs a cell: the arm's body and the scene")
    if objective == "time" and timing is None:
        timing = DEFAULT_RATE
    if timing is not None:  # refused before the search, not after it
        check_timing(chain, timing)

    def search(by: str, path: int | None = None, cell: Family = family) -> list[PathResult]:
        which = slice(None) if path is None else slice(path, path + 1)
        return search_paths(cell, poses[which], step, None if starts is None else starts[which],
                            None if ends is None else ends[which], last_branch,
                            lambda pieces: graphs.piece_samples(pieces, spacing, cell.sample_groups()), connect,
                            int(refinements), thorough, objective=by, levels=True)

    if timing is None:
        return search(objective)
    rate = float(timing)

    def again(by: str, path: int) -> Callable[[], PathResult] | None:
        if scene is None:
            return None
        return lambda: search(by, path, path_family(arm, srs_tolerance, body, _roomier(scene)))[0]

    if objective != "time":
        return [_timed(family, result, rate, again(objective, p)) for p, result in enumerate(search(objective))]
    def fastest(p: int, pair: tuple[PathResult, PathResult]) -> PathResult:
        """The shorter timed trajectory of path ``p``'s two, or the one that can be timed."""
        timed_paths, failures = [], []
        for by, result in zip(("clearance", "motion"), pair, strict=True):
            try:
                timed_paths.append(_timed(family, result, rate, again(by, p)))
            except RedkinError as exc:  # the time parametrisation's refusal of this joint path
                failures.append(exc)
        if not timed_paths:
            raise failures[0]
        return min(timed_paths, key=_duration)

    return [fastest(p, pair) for p, pair in enumerate(zip(search("clearance"), search("motion"), strict=True))]


def _roomier(scene: Scene) -> Scene:
    """``scene`` with its margin :data:`_SPLINE_ROOM` larger."""
    return replace(scene, margin=scene.margin + _SPLINE_ROOM)


def _timed(family: Family, result: PathResult, rate: float,
           again: Callable[[], PathResult] | None = None) -> PathResult:
    """``result`` timed at ``rate`` (:func:`redkin.paths.stops.timed`), and in a cell with what is proved of the
    steps between its trajectory's samples (:attr:`PathResult.trajectory_steps`): the spline through the waypoints
    is not the linear interpolation whose steps the search proved clear, so where its steps are not proved clear it
    is timed again through more points of those linear steps (:data:`_DENSITIES`), until they are.  Where none
    suffices (a path whose steps graze the margin, which no curve beside them keeps), the path ``again()`` gives
    (the same search with :data:`_SPLINE_ROOM` more margin) is timed the same way and taken where its trajectory is
    proved clear; otherwise ``result`` is timed at rest at every waypoint, so that the trajectory runs along the
    proved steps themselves."""
    timed_result, steps = _spline(family, result, rate)
    if steps is None or steps.certified.all():
        return timed_result
    if again is not None:
        roomier = again()
        if roomier.ok:
            smooth, smooth_steps = _spline(family, roomier, rate)
            if smooth_steps is not None and smooth_steps.certified.all():
                return smooth
    timed_result = timed(family.chain, result, rate, at_rest=True)
    assert timed_result.trajectory is not None  # timed through the same waypoints above
    samples = timed_result.trajectory.q
    return replace(timed_result, trajectory_steps=family.steps(samples[:-1], samples[1:]))


def _spline(family: Family, result: PathResult, rate: float) -> tuple[PathResult, StepClearance | None]:
    """``result`` timed at ``rate`` through the fewest points per step of :data:`_DENSITIES` whose trajectory's
    steps are proved clear (the most where none is), with what is proved of them (``None`` without a cell or a
    trajectory) in the result's :attr:`PathResult.trajectory_steps` too."""
    for density in _DENSITIES:
        timed_result = timed(family.chain, result, rate, density)
        if timed_result.trajectory is None:
            return timed_result, None
        samples = timed_result.trajectory.q
        steps = family.steps(samples[:-1], samples[1:])
        if steps is None:
            return timed_result, None
        timed_result = replace(timed_result, trajectory_steps=steps)
        if steps.certified.all():
            break
    return timed_result, steps


def _duration(result: PathResult) -> float:
    """A timed result's duration; ``inf`` for no path."""
    return result.trajectory.duration if result.trajectory is not None else np.inf


def search_paths(family: Family, poses: np.ndarray, step: np.ndarray, starts: np.ndarray | None,
                 ends: np.ndarray | None, last_branch: int | None, sampler: Callable, connect: float | None,
                 refinements: int, thorough: bool = False, polish: bool = True,
                 objective: str = "clearance", levels: bool = False) -> list[PathResult]:
    """:func:`resolve_paths` on validated input: ``poses`` (P, N, 4, 4), ``starts``/``ends`` (P, 7) or
    ``None``, ``last_branch`` an index into :data:`BRANCHES` or ``None``; ``sampler(pieces)`` gives the
    initial samples (waypoint, branch, piece, psi, sorted as a graph's nodes, the node whose sample each shares,
    and each piece's ends) from the feasible pieces (:func:`graph.piece_samples`); ``connect`` as in
    :func:`resolve_path`, ``None`` for the samples alone;
    ``polish``: raise the clearance of a path not proved optimal between the samples (:func:`_polished`);
    ``objective`` as in :func:`resolve_path`; ``levels``: search a path whose clearance is still not proved
    optimal again inside limits moved inwards (:func:`_leveled`).

    Two stages (docs/paths.md, "Method"): the samples alone first, refined around the path found; a path whose
    clearance is then proved optimal (:func:`_bottleneck`), or a failure proved by the exact sets, is final.
    The others (all but the proved failures with ``thorough``) are searched again on the samples subdivided until
    neighbours differ by ``connect`` of the bound, and the better of the two answers is kept."""
    count, length = poses.shape[:2]
    flat = np.ascontiguousarray(poses.reshape(-1, 4, 4))
    reach, arm_along = family.arm(flat, step)
    empty = np.zeros((0, len(BRANCHES), 1))
    found = family.pieces(flat[reach]) if reach.any() else FeasiblePieces(empty, empty, empty.astype(bool))
    shape = (len(flat), len(BRANCHES), found.start.shape[-1])
    start, end, feasible = np.full(shape, np.nan), np.full(shape, np.nan), np.zeros(shape, dtype=bool)
    start[reach], end[reach], feasible[reach] = found.start, found.end, found.feasible
    along = _Along(reach.reshape(count, length), arm_along, FeasiblePieces(start, end, feasible))
    motion = objective == "motion"
    value = family.moving_distances if objective == _OBSTACLES else None
    polish = polish and value is None  # the polish raises the clearance from the limits
    results = _search(family, poses, along, starts, ends, last_branch, sampler, None, refinements, polish, motion,
                      value)
    if connect is None:
        return results
    again = [p for p, result in enumerate(results) if (result.ok and (thorough or motion or not result.optimal))
             or (result.failure is not None and not result.failure.exact)]
    if again:
        rows = np.array(again)
        finer = _search(family, poses[rows], along.paths(rows), None if starts is None else starts[rows],
                        None if ends is None else ends[rows], last_branch, sampler, connect, refinements, polish,
                        motion, value)
        for p, result in zip(again, finer):
            results[p] = _better(results[p], result, objective, family)
    if levels and not motion and family.exact:
        for p, result in enumerate(results):
            if result.ok and not result.optimal:
                results[p] = _leveled(family, poses[p], step, None if starts is None else starts[p : p + 1],
                                      None if ends is None else ends[p : p + 1], last_branch, sampler, refinements,
                                      result)
    return results


def _leveled(family: Family, poses: np.ndarray, step: np.ndarray, start: np.ndarray | None, end: np.ndarray | None,
             last_branch: int | None, sampler: Callable, refinements: int, found: PathResult) -> PathResult:
    """A path ``found`` whose clearance ``c`` is not proved optimal, searched again inside the limits moved
    inwards by a *level* between ``c`` and the least level at which some waypoint has no configuration left
    (:func:`_ceiling`; no path keeps more), halving the gap each round (:data:`_LEVEL_ROUNDS` at most): a path
    found there keeps at least the level, and its own search, free of the configurations below it, is not drawn
    to a path of clearance ``c`` again (a clearance that peaks near one end of an arc, where the samples and the
    refinement around the path found do not look).  A level where no path is found becomes the new top.  A path
    proved optimal inside moved limits is optimal inside the arm's own: the proof's level moves with them.  Each
    search is the first stage's (the samples, refined, polished; no subdivided second stage)."""
    best = found
    top = _ceiling(family, poses, best.clearance)
    for _ in range(_LEVEL_ROUNDS):
        if best.optimal or top - best.clearance <= _LEVEL_GAP:
            break
        level = 0.5 * (best.clearance + top)
        inner = family.inner(level)
        result = None if inner is None else search_paths(inner, poses[None], step, start, end, last_branch, sampler,
                                                         None, refinements)[0]
        if result is None or not result.ok:
            top = level
            continue
        chain, q = family.chain, result.q
        limited = ~chain.covers_circle
        clearance = float(np.minimum(q - chain.lower, chain.upper - q)[:, limited].min())
        best = replace(result, clearance=clearance, step=found.step, nodes=found.nodes + result.nodes)
    return best if best.clearance > found.clearance else replace(found, nodes=best.nodes)


def _ceiling(family: Family, poses: np.ndarray, least: float) -> float:
    """A level (radians, at least ``least``) above which some pose of ``poses`` has no configuration on any branch
    keeping that far from every limit, so that no path of these poses keeps more clearance: the exact feasible sets
    inside moved limits, bisected :data:`_CEILING_STEPS` times from half the narrowest range (the levels of
    :func:`_leveled` halve the gap below it further)."""
    chain = family.chain
    limited = ~chain.covers_circle
    if not limited.any():
        return np.inf
    low, high = least, 0.5 * float((chain.upper - chain.lower)[limited].min())
    for _ in range(_CEILING_STEPS):
        if high - low <= _LEVEL_GAP:
            break
        level = 0.5 * (low + high)
        inner = family.inner(level)
        if inner is not None and inner.pieces(poses).feasible.any(axis=(-2, -1)).all():
            low = level
        else:
            high = level
    return high


def _better(coarse: PathResult, fine: PathResult, objective: str, family: Family) -> PathResult:
    """Of two answers for one path, the found one, or the larger clearance then the lesser motion (``"motion"``:
    the other way round; ``"obstacle-clearance"``: the larger least distance of the parts the redundancy moves,
    :meth:`Family.moving_distances`, then the lesser motion); ``nodes`` counts both searches."""
    def key(result: PathResult) -> tuple[float, float]:
        if objective == "motion":
            return -result.motion, result.clearance
        if objective == _OBSTACLES:
            distances = family.moving_distances(result.q)
            assert distances is not None  # the objective needs a cell
            return float(distances.min(initial=np.inf)), -result.motion
        return result.clearance, -result.motion

    best = fine
    if coarse.ok and (not fine.ok or key(coarse) > key(fine)):
        best = coarse
    return replace(best, nodes=coarse.nodes + fine.nodes)


@dataclass(frozen=True)
class _Along:
    """What :func:`search_paths` computes once for both stages: per path and waypoint whether the pose is within
    reach (P, N), the arm along every waypoint, and the exact feasible pieces of every waypoint (none where out of
    reach)."""

    reach: np.ndarray
    arm: Arm
    pieces: FeasiblePieces

    def paths(self, rows: np.ndarray) -> _Along:
        """The same for the paths ``rows`` only."""
        length = self.reach.shape[1]
        flat = (rows[:, None] * length + np.arange(length)).reshape(-1)
        pieces = self.pieces
        return _Along(self.reach[rows], self.arm.take(flat),
                      FeasiblePieces(pieces.start[flat], pieces.end[flat], pieces.feasible[flat]))


def _search(family: Family, poses: np.ndarray, along: _Along, starts: np.ndarray | None,
            ends: np.ndarray | None, last_branch: int | None, sampler: Callable, connect: float | None,
            refinements: int, polish: bool, motion_first: bool,
            value: Callable[[np.ndarray], np.ndarray | None] | None = None) -> list[PathResult]:
    """One search of :func:`search_paths`: the graph of the samples (subdivided by ``connect`` unless ``None``),
    swept, refined around the paths found, each path checked and its optimality tried; ``value(q)``: each node's
    value for the sweep instead of its clearance from the limits (the objective ``"obstacle-clearance"``)."""

    def valued(graph: Graph) -> Graph:
        values = None if value is None else value(graph.q)
        return graph if values is None else replace(graph, clearance=values)

    count, length = poses.shape[:2]
    flat = np.ascontiguousarray(poses.reshape(-1, 4, 4))
    reach = along.reach
    prefix = np.where(reach.all(axis=1), length, np.argmin(reach, axis=1))  # waypoints before the first unreachable
    rows = np.concatenate([p * length + np.arange(n) for p, n in enumerate(prefix.tolist())]).astype(np.int64)
    path_starts = np.concatenate([[0], np.cumsum(prefix)]).astype(np.int64)
    arm_data = along.arm.take(rows)
    step = arm_data.step
    pieces = along.pieces
    waypoint, branch, piece, psi, shared, bounds = sampler(FeasiblePieces(pieces.start[rows], pieces.end[rows],
                                                                          pieces.feasible[rows]))
    extra = _own_nodes(family, starts, path_starts[:-1], prefix > 0) + _own_nodes(
        family, ends, path_starts[1:] - 1, prefix == length)
    for w, b, p in extra:
        waypoint, branch, shared = np.append(waypoint, w), np.append(branch, b), np.append(shared, len(shared))
        piece, psi = np.append(piece, -1), np.append(psi, p)
    graph = graphs.build(arm_data, waypoint, branch, piece, psi, len(rows), ordered=not extra, shared=shared)
    if connect is not None:
        graph = graphs.connect(arm_data, graph, connect)
    graph = samples = valued(graph)

    key = search.key_joint(graph, arm_data.step, arm_data.circle)  # the refinements' graphs lie in the same pieces

    def searched(graph: Graph, floor: np.ndarray | None = None,
                 forbidden: np.ndarray | None = None) -> tuple[search.Sweep, dict[int, np.ndarray]]:
        """The sweep of ``graph`` (each path on its nodes of clearance at least ``floor``, without the edges
        ``forbidden``) and the best path of each path that has one."""
        first_value, first_motion = _first_values(arm_data, graph, path_starts, starts)
        sweep = search.run(arm_data, graph, path_starts, first_value, first_motion, motion_first, key, floor,
                           forbidden)
        chosen = {}
        for p in np.flatnonzero((prefix > 0) & (sweep.dead < 0)).tolist():
            last = search.best_end(sweep, _end_nodes(arm_data, graph, path_starts[p + 1] - 1, ends, p, last_branch),
                                   motion_first)
            if last >= 0:
                chosen[p] = search.trace(sweep, last, int(prefix[p]))
        return sweep, chosen

    def checked(graph: Graph, path: np.ndarray, p: int, size: int) -> PathResult:
        """Path ``p``'s ``path`` of ``graph`` checked (:func:`_checked_path`; ``size`` nodes searched)."""
        return _checked_path(family, arm_data, graph, path, poses[p], starts, p, size, not motion_first)

    def polished(graph: Graph, path: np.ndarray, p: int, result: PathResult) -> PathResult | None:
        """``result`` (path ``p``'s ``path`` of ``graph``) polished where that gains clearance, else ``None``."""
        if not (polish and not motion_first and result.ok and not result.optimal):
            return None
        better = _polished(family, arm_data, graph, path, pieces, poses[p], path_starts[p], starts, ends, p, result)
        return None if better is result else better

    sweep, chosen = _floored(graph, path_starts, searched, motion_first)
    failures = {p: _failure(family, arm_data, graph, sweep, flat[rows], path_starts, p, starts, ends, last_branch,
                            int(prefix[p])) for p in range(count) if p not in chosen}
    nodes = len(graph.psi)
    width = _FIRST_WINDOW
    rounds = {p: refinements if motion_first or not _proved(family, arm_data, graph, chosen[p], poses[p])
              else min(refinements, _PROVED_REFINEMENTS) for p in chosen}  # proved: rounds for the motion alone
    for done in range(refinements):  # finer around the paths found, in a window that halves each round
        if not chosen or width < _REFINED or all(rounds[p] <= done for p in chosen):
            break
        path_nodes = np.concatenate([chosen[p] for p in sorted(chosen)])
        frozen = np.concatenate([np.full(len(chosen[p]), rounds[p] <= done) for p in sorted(chosen)])
        graph = valued(graphs.window(arm_data, graph, path_nodes, width, bounds, len(rows), frozen))
        nodes += len(graph.psi)
        _, chosen = searched(graph)
        width *= 0.5

    results = []
    for p in range(count):
        failure = failures.get(p)
        if failure is None and prefix[p] < length:
            failure = PathFailure(int(prefix[p]), "out-of-reach", None, True)
        if failure is not None:
            results.append(PathResult("no-path", np.empty((0, 7)), [], np.empty(0), float("nan"), float("nan"),
                                      step, replace(failure, parameter=family.parameter), nodes,
                                      parameter=family.parameter))
            continue
        result = checked(graph, chosen[p], p, nodes)
        better = polished(graph, chosen[p], p, result) if result.ok else None
        results.append(result if better is None else better)
    return with_clear_steps(family, arm_data, results, samples, path_starts,
                            lambda graph, edges: searched(graph, None, edges),
                            lambda graph, path, p: checked(graph, path, p, len(graph.psi)), polished)


def _polished(family: Family, arm: Arm, graph: Graph, nodes: np.ndarray, pieces: FeasiblePieces, poses: np.ndarray,
              first: int, starts: np.ndarray | None, ends: np.ndarray | None, p: int, found: PathResult) -> PathResult:
    """Path ``p`` (``nodes`` of ``graph``, from waypoint ``first``; ``pieces`` of every waypoint) with its clearance
    raised between the samples (:func:`redkin.paths.polish.raised`) inside the feasible arcs its parameters lie in
    (:func:`_arcs_around`), checked and its optimality tried again; ``found`` where nothing is gained."""
    rows = first + np.arange(len(nodes))
    branch = graph.branch[nodes]
    parameter = graph.psi[nodes]
    arcs = _arcs_around(pieces, rows, branch, parameter)
    arcs[graph.piece[nodes] < 0] = parameter[graph.piece[nodes] < 0, None]  # q0's own node stays
    along = arm.take(rows)
    moved = raised(along, branch, parameter, arcs, None if starts is None else starts[p],
                   None if ends is None else ends[p])
    if np.array_equal(moved, parameter):
        return found
    q, clearance = along.rows(np.arange(len(nodes)), branch, moved)
    path = Graph(np.arange(len(nodes) + 1), graph.piece[nodes], branch, moved, q, np.maximum(clearance, 0.0))
    better = _checked_path(family, arm, path, np.arange(len(nodes)), poses, starts, p, found.nodes, True)
    return better if better.ok and better.clearance > found.clearance else found


def _arcs_around(pieces: FeasiblePieces, rows: np.ndarray, branch: np.ndarray, parameter: np.ndarray) -> np.ndarray:
    """The feasible arc ``(N, 2)`` each parameter lies in: its piece joined with the feasible pieces of the same
    waypoint and branch that touch it (pieces are also cut where no joint meets a limit); ``(parameter,
    parameter)`` where none holds it."""
    arcs = np.repeat(parameter[:, None], 2, axis=1)
    for i, (row, b, value) in enumerate(zip(rows.tolist(), branch.tolist(), parameter.tolist())):
        keep = pieces.feasible[row, b]
        start, end = pieces.start[row, b][keep], pieces.end[row, b][keep]
        order = np.argsort(start)
        start, end = start[order], end[order]
        inside = np.flatnonzero((start <= value) & (value <= end))
        if inside.size == 0:
            continue
        low = high = int(inside[0])
        while low > 0 and end[low - 1] >= start[low] - _TOUCH:
            low -= 1
        while high + 1 < len(start) and start[high + 1] <= end[high] + _TOUCH:
            high += 1
        arcs[i] = start[low], end[high]
    return arcs


def _configurations(value: ArrayLike | None, count: int, name: str) -> np.ndarray | None:
    """``q0`` or ``q_end`` as ``(P, 7)``, or ``None``."""
    if value is None:
        return None
    array = check_vectors(value, 7, name)
    if array.shape not in ((7,), (1, 7), (count, 7)):
        raise RedkinError(f"{name} must have shape (7,) or ({count}, 7), got {array.shape}")
    return np.broadcast_to(array.reshape(-1, 7), (count, 7))


def _own_nodes(family: Family, configurations: np.ndarray | None, waypoints: np.ndarray,
               used: np.ndarray) -> list[tuple[int, int, float]]:
    """The parameter and branch of ``q0`` (``q_end``) as a sample of the first (last) waypoint of each path."""
    if configurations is None or not used.any():
        return []
    paths = np.flatnonzero(used)
    branch, value = family.parameter_of(np.ascontiguousarray(configurations[paths]))
    return [(int(waypoints[p]), int(b), float(v)) for p, b, v in zip(paths.tolist(), branch, value)]


def _floored(graph: Graph, path_starts: np.ndarray, searched: Callable, motion_first: bool):
    """``searched(graph, floor)`` on the nodes of clearance at least a floor, raised as far as it can be: the best
    path of a graph keeps its clearance on the nodes at or above it, so the best path found above a floor is the
    best of the whole graph, and the nodes below are never swept.  Each path's floor is :data:`_FLOOR_FRACTIONS`
    of its *ceiling* in turn (the least, over its waypoints, of the largest clearance of a node there: no path of
    the graph keeps more), then none, until the path is found; a path not found without a floor has none (its
    sweep is the whole graph's, which its failure reads).  The objective ``"motion"`` sweeps without a floor."""
    paths = len(path_starts) - 1
    floor = np.full(paths, -np.inf)
    levels = iter(() if motion_first or not len(graph.psi) else _FLOOR_FRACTIONS)
    ceiling = floor.copy()
    first = next(levels, None)
    if first is not None:
        nodes = np.diff(graph.offsets)
        most = np.full(len(nodes), -np.inf)
        most[nodes > 0] = np.maximum.reduceat(graph.clearance, graph.offsets[:-1][nodes > 0])
        lengths = np.diff(path_starts)
        ceiling[lengths > 0] = np.minimum.reduceat(most, path_starts[:-1][lengths > 0])
        floor = np.where(ceiling > 0.0, first * ceiling, -np.inf)
    while True:
        sweep, chosen = searched(graph, floor)
        again = np.array([p not in chosen for p in range(paths)], dtype=bool) & (floor > 0.0)  # clearance is >= 0
        if not again.any():
            break
        fraction = next(levels, None)
        floor[again] = -np.inf if fraction is None else fraction * ceiling[again]
    return sweep, chosen


def _first_values(arm: Arm, graph: Graph, path_starts: np.ndarray, starts: np.ndarray | None):
    """The value and motion of the first waypoint's nodes: their clearance, and without ``q0`` no motion;
    with it, only the nodes within one step of it, and their move from it."""
    value = graph.clearance.copy()
    motion = np.zeros(len(value))
    if starts is not None:
        path = np.searchsorted(path_starts, graph.waypoint, side="right") - 1
        origin = starts[np.minimum(path, len(starts) - 1)]
        moves = arm.moves(graph.q, origin)
        value[np.any(moves > arm.step, axis=-1)] = -np.inf
        motion = moves.sum(axis=-1)
    return value, motion


def _end_nodes(arm: Arm, graph: Graph, waypoint: int, ends: np.ndarray | None, path: int,
               last_branch: int | None) -> np.ndarray:
    """The nodes of the last waypoint that meet the end conditions."""
    nodes = np.arange(graph.offsets[waypoint], graph.offsets[waypoint + 1])
    if last_branch is not None:
        nodes = nodes[graph.branch[nodes] == last_branch]
    if ends is not None:
        nodes = nodes[np.all(arm.moves(graph.q[nodes], ends[path]) <= arm.step, axis=-1)]
    return nodes


def _failure(family: Family, arm: Arm, graph: Graph, sweep: search.Sweep, poses: np.ndarray,
             path_starts: np.ndarray, p: int, starts: np.ndarray | None, ends: np.ndarray | None,
             last_branch: int | None, prefix: int) -> PathFailure:
    """Why path ``p`` has no path: the first waypoint and its reason."""
    if prefix == 0:
        return PathFailure(0, "out-of-reach", None, True)
    first = int(path_starts[p])
    dead = int(sweep.dead[p])
    if dead < 0:  # every waypoint reached, but not the end conditions
        last = first + prefix - 1
        reached = np.arange(graph.offsets[last], graph.offsets[last + 1])
        reached = reached[sweep.value[reached] > -np.inf]
        joint, needed = None, None
        if ends is not None:
            if last_branch is not None:
                reached = reached[graph.branch[reached] == last_branch]
            if reached.size:
                joint, needed = step_blocker(arm, graph.q[reached], ends[p][None])
        return PathFailure(prefix - 1, "end", joint, False, needed)
    w = first + dead
    after = graph.q[graph.offsets[w]:graph.offsets[w + 1]]
    if after.shape[0] == 0:
        joint, per_branch, proved = family.blocker(poses[w])
        reason, pair = family.emptied(poses[w])
        return PathFailure(dead, reason, joint, proved, None, per_branch, pair)
    if dead == 0:  # nodes exist, none within a step of q0
        assert starts is not None
        impossible = _fixed_step(arm, starts[p][None], arm.pose_fixed(w))
        if impossible is not None:
            return PathFailure(0, "start", *impossible)
        joint, needed = step_blocker(arm, starts[p][None], after)
        return PathFailure(0, "start", joint, False, needed)
    impossible = _fixed_step(arm, arm.pose_fixed(w - 1), arm.pose_fixed(w))
    if impossible is not None:
        return PathFailure(dead, "step", *impossible)
    before = np.arange(graph.offsets[w - 1], graph.offsets[w])
    before = before[sweep.value[before] > -np.inf]
    joint, needed = step_blocker(arm, graph.q[before], after)
    return PathFailure(dead, "step", joint, False, needed)


def _fixed_step(arm: Arm, before: np.ndarray, after: np.ndarray) -> tuple[int, bool, float] | None:
    """Where a joint that the poses fix (:meth:`Arm.pose_fixed`) must move more than its bound between any
    configuration of ``before`` and any of ``after`` (rows of fixed values, NaN: free), whatever the redundancy
    chooses: ``(joint, True, needed)`` of the joint furthest over its bound (1-based), the step proved impossible;
    else ``None``."""
    least = graphs.least_moves(arm, before, after)
    over = least / arm.step
    joint = int(np.argmax(over))
    return (joint + 1, True, float(least[joint])) if over[joint] > 1.0 + _FIXED_SLACK else None


def _unwound(arm: Arm, q: np.ndarray, origin: np.ndarray | None) -> np.ndarray:
    """``q`` with each joint of a range of ``2 pi`` or more (compared on the circle) made continuous along the
    path, from ``origin`` where given; a finite such range is then met by a whole number of turns if one fits."""
    circle = arm.circle
    if not circle.any():
        return q
    chain = arm.chain
    reference = q[0, circle] if origin is None else origin[circle]
    turned = np.diff(np.concatenate([reference[None], q[:, circle]]), axis=0)
    out = q.copy()  # whole turns added to each value, never a sum of steps: a value left where it is keeps every bit
    out[:, circle] -= np.cumsum(np.round(turned / TWO_PI), axis=0) * TWO_PI  # (the Franka class's q7 is the node's)
    if origin is None:
        middle = chain.middle[circle]
        centre = 0.5 * (out[:, circle].min(axis=0) + out[:, circle].max(axis=0))
        out[:, circle] += np.round((middle - centre) / TWO_PI) * TWO_PI
    return out


def _checked_path(family: Family, arm: Arm, graph: Graph, nodes: np.ndarray, poses: np.ndarray,
                  starts: np.ndarray | None, p: int, size: int, prove: bool) -> PathResult:
    """The :class:`PathResult` of the nodes found (:func:`_unwound`), checked against the poses, the limits and
    the bound, its clearance's optimality tried where ``prove`` (:func:`_bottleneck`); a ``"winding"`` failure
    where a joint of a range over ``2 pi`` would leave it."""
    chain = arm.chain
    origin = None if starts is None else starts[p]
    q = _unwound(arm, graph.q[nodes], origin)
    inside = chain.joints_within_limits(q)
    if not inside.all():
        waypoint, joint = (int(i) for i in np.argwhere(~inside)[0])
        return PathResult("no-path", np.empty((0, 7)), [], np.empty(0), float("nan"), float("nan"), arm.step,
                          PathFailure(waypoint, "winding", joint + 1, False, parameter=family.parameter), size,
                          parameter=family.parameter)
    error = float(np.abs(chain.fk(q) - poses).max())
    moves = arm.moves(q[1:], q[:-1])
    if error > FK_TOLERANCE or np.any(moves > arm.step):
        raise RuntimeError(f"path resolution produced a path that fails its check (FK error {error:.3g}, largest "
                           f"step/bound {float((moves / arm.step).max(initial=0.0)):.6g}); please report it")
    motion = float(moves.sum()) + (0.0 if origin is None else float(arm.moves(q[0], origin).sum()))
    parameter = np.asarray(wrap_angle(graph.psi[nodes])) if family.wraps else q[:, 6].copy()
    clearance = arm.clearance(q)
    bottleneck = _bottleneck(family, poses, clearance) if prove else None
    distances = family.distances(q)
    return PathResult("ok", q, [str(BRANCHES[b]) for b in graph.branch[nodes]], parameter, float(clearance.min()),
                      motion, arm.step, None, size, bottleneck is not None, bottleneck, family.parameter,
                      cell_clearance=None if distances is None else float(distances.min()))


def _proved(family: Family, arm: Arm, graph: Graph, nodes: np.ndarray, poses: np.ndarray) -> bool:
    """Whether the path ``nodes`` of ``graph`` already has a clearance proved optimal (:func:`_bottleneck`)."""
    return _bottleneck(family, poses, arm.clearance(graph.q[nodes])) is not None


def _bottleneck(family: Family, poses: np.ndarray, clearance: np.ndarray) -> int | None:
    """A waypoint that proves a path's clearance optimal, or ``None``.

    ``clearance`` (N,) is the path's own at each waypoint, ``c`` its smallest.  A waypoint where the path is at
    ``c`` and whose exact feasible sets ([000 eq. 30], or [F8]-[F9] of q7) are empty on every branch once each
    limit is moved :data:`OPTIMALITY_MARGIN` past ``c`` inwards, cannot be passed by any path more than ``c +``
    :data:`OPTIMALITY_MARGIN` from the limits: no other choice of branches and parameters does better.
    A chain with no joint of a range under ``2 pi`` has clearance ``inf`` everywhere: waypoint 0 proves it.  A
    family whose sets prove nothing (:attr:`redkin.paths.family.Family.proves_optimal`: a nearly S-R-S arm's) proves
    nothing; in a cell the sets are the certified collision-free ones, complete, so the proof is among them
    (:meth:`redkin.paths.family.Family.proved_empty`)."""
    if not family.proves_optimal:
        return None
    least = float(clearance.min())
    if least == np.inf:
        return 0
    level = least + OPTIMALITY_MARGIN
    tight = np.flatnonzero(clearance <= level)
    inner = family.inner(level)
    if inner is None:  # no configuration at all is that far
        return int(tight[0])
    empty = inner.proved_empty(poses[tight])
    return int(tight[np.argmax(empty)]) if empty.any() else None
