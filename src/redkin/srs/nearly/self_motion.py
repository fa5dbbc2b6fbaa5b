"""The certified self-motion of a nearly S-R-S arm at one pose, and what is read off it.

A pose's solutions on the real arm form closed curves in joint space (6 pose
equations in 7 joints).  :func:`self_motion` follows one with certified
steps (:mod:`redkin.srs.nearly._self_motion_kernels`; docs/srs.md, "The certified
self-motion"): between two consecutive points lies an arc of true solutions
in a tube about the chord, on a known branch and inside or outside the
limits, or not decided for a stretch of arm angle at most
:data:`redkin.srs.nearly._self_motion_kernels.RESOLUTION` wide where a sign or a
limit changes.  :func:`self_motions` finds every curve through
:func:`redkin.srs.nearly.ik`'s solutions at :data:`SEEDS` arm angles.

Along a curve the arm angle ``psi(q)`` (:func:`redkin.srs.nearly.arm_angle`)
need not increase: on an exact arm it does, one solution per branch and arm
angle, but on the real arm it can turn back (a fold, ``d psi / ds = 0``) near
a stretched elbow or a straight wrist or shoulder, where the branch then has
two solutions at the arm angles before the fold and none after it.

* :func:`feasible_along` -- the arm angles of a branch's certified arcs
  within the limits: each run of such steps covers the arm angles between
  the smallest and the largest at its points (the arc is continuous), so
  every reported arm angle has a solution on the branch within the limits.
* :func:`branch_solutions` -- every solution of a branch at an arm angle:
  where a step of the branch crosses it, located on the arc.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import run_batch, running_as_python, thread_count
from redkin._validation import check_pose
from redkin.circle import TWO_PI, ArcSet, wrap_angle
from redkin.errors import RedkinError
from redkin.srs._targets import check_psi
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.nearly import _self_motion_kernels
from redkin.srs.nearly.arm import NearlySolutions, NearlySRS, arm_angle, branch_of, ik

#: Longest step [rad of arc length in joint space] of the continuation (the certificate sets shorter ones).
_LONGEST = 0.2
#: Points of one curve, one way, at most.  Near a stretched elbow, or a straight wrist or shoulder, two sheets of the
#: self-motion come close, the curve turns sharply, and the certified steps shrink with the distance between them
#: (1e-4 to 1e-3 rad within a few mrad of it on the Gen3: up to 260 000 points on one curve of the poses tried); a
#: curve beyond this is left unfinished.
_MOST_POINTS = 150_000
#: Points of all the curves of one pose at most (about 15 s): no further seed is followed beyond it.
_BUDGET = 1_000_000
#: The arm angles at which :func:`redkin.srs.nearly.ik`'s solutions of every branch seed :func:`self_motions`.
SEEDS = np.linspace(-np.pi, np.pi, 8, endpoint=False)
#: Where a branch has no solution at one of :data:`SEEDS` (its self-motion may span a short stretch of arm angle: a
#: fold, near the stretched elbow), the seeds are these instead (0.1 rad apart).
_FINE_SEEDS = np.linspace(-np.pi, np.pi, 64, endpoint=False)
#: Starts of the numerical solver (:func:`redkin.numerical.ik`) for seeds where no arm angle of :data:`_FINE_SEEDS`
#: gives one.
_NUMERICAL_STARTS = 64
#: Joint values closer than this [rad] to a curve's point at the same arm angle and branch lie on that curve (a
#: seed already followed): two curves of one branch so close at one arm angle meet only at a singular pose.
_SAME_CURVE = 2e-3
#: How nearly the first joint values must reach the pose [m, and each entry of the rotation].
_REACHED = 1e-6
#: Width [rad of arm angle] to which :func:`branch_solutions` locates a crossing.
_RESOLUTION = 1e-11
#: Solutions closer than this [rad] in every joint are one: a certified row of ``nearly.ik`` lies up to about 2e-5
#: rad from the curve next to a fold, where the seven equations are nearly singular, and the branch's two solutions
#: there are this close only within about 1e-8 rad of arm angle of the fold (they part as its square root).
_SAME_SOLUTION = 1e-4


class SelfMotion(NamedTuple):
    """One curve of a pose's self-motion on the real arm, certified step by step.

    Attributes
    ----------
    q : numpy.ndarray, shape (M, 7)
        Its points, in order along the curve (joint values continuous, not wrapped); each reaches the pose to
        about 1e-15.  Where the curve is closed, the last point is the first (modulo whole turns).
    tangents : numpy.ndarray, shape (M, 7)
        The unit tangent at each point, in the sense of travel.
    psi : numpy.ndarray, shape (M,)
        The arm angle at each point (:func:`redkin.srs.nearly.arm_angle`).
    rates : numpy.ndarray, shape (M,)
        ``d psi / ds`` at each point, ``s`` the arc length in joint space.
    branches : numpy.ndarray of int, shape (M - 1,)
        The branch (index into :data:`redkin.srs.BRANCHES`) of the arc from point ``k`` to ``k + 1``, -1 where
        the arc may cross a branch's boundary.
    inside : numpy.ndarray of int, shape (M - 1,)
        Whether that arc lies within the limits: 1 everywhere, 0 outside them somewhere, -1 not decided.
    spread : numpy.ndarray, shape (M - 1,)
        A bound of the arm angle's change along that arc [rad].
    tubes : numpy.ndarray, shape (M - 1, 2)
        The certificate of that arc [C2]: the length ``H`` [rad] of its chord and the radius ``r*`` [rad] of the
        tube about it that holds the arc; the chord starts at point ``anchors[k]`` along its tangent (either way).
    anchors : numpy.ndarray of int, shape (M - 1,)
        The point each arc's tube is about: ``k`` where the arc was followed from point ``k``, ``k + 1`` where it
        was followed backwards from point ``k + 1``.  So every point of the arc lies within ``H |t_j| + r*`` of the
        anchor's ``q_j`` in each joint ``j`` (``t`` the anchor's tangent).
    closed : bool
        Whether the curve came back to its first point; where not, it stopped where a step could not be
        certified (a singular configuration, the wrist on joint 1's axis) or after :data:`_MOST_POINTS` points.
    """

    q: np.ndarray
    tangents: np.ndarray
    psi: np.ndarray
    rates: np.ndarray
    branches: np.ndarray
    inside: np.ndarray
    spread: np.ndarray
    tubes: np.ndarray
    anchors: np.ndarray
    closed: bool


def self_motion(arm: NearlySRS, pose: ArrayLike, q: ArrayLike, step: float = _LONGEST) -> SelfMotion:
    """The curve of the self-motion of ``pose`` through the solution ``q`` (7,), followed with certified steps of at
    most ``step`` [rad]; where it does not close, followed both ways from ``q`` (module docstring).

    Raises
    ------
    ValueError
        For a malformed pose or joint values, a step outside (0, 0.5], or joint values that do not reach the pose
        to :data:`_REACHED` (they are corrected onto the curve first).
    """
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    start = np.array(arm.chain.check_q(q), dtype=float)
    if start.shape != (7,):
        raise RedkinError(f"q must be one joint vector (7,), got shape {start.shape}")
    if not 0.0 < step <= 0.5:
        raise RedkinError(f"step must be in (0, 0.5] rad, got {step!r}")
    if np.abs(arm.chain.fk(start) - target).max() > _REACHED:
        raise RedkinError(f"q does not reach the pose (to {_REACHED:g} m and in each entry of the rotation): a "
                          "self-motion starts from a solution")
    return _followed(arm, target, start, step, _Room(_MOST_POINTS))


def self_motions(arm: NearlySRS, pose: ArrayLike) -> tuple[SelfMotion, ...]:
    """Every curve of the self-motion of ``pose`` through the seeds of :func:`whole_self_motion`
    (:func:`curves_through`): :func:`redkin.srs.nearly.ik`'s solutions of every branch at a grid of arm angles.  A
    curve through none of them is not found.

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose).
    """
    return whole_self_motion(arm, pose)[0]


def whole_self_motion(arm: NearlySRS, pose: ArrayLike) -> tuple[tuple[SelfMotion, ...], bool]:
    """:func:`self_motions`, and whether it is whole: every curve closed, and every seed followed or on a curve
    (not where :data:`_BUDGET` ran out first), and a curve found unless the pose is proven out of reach.

    The seeds are :func:`redkin.srs.nearly.ik`'s solutions of every branch at :data:`SEEDS`, at :data:`_FINE_SEEDS`
    where a branch has no solution at one of those, and where none of those has one, certified solutions of the
    numerical solver (:func:`redkin.numerical.ik`).

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose).
    """
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    grid, solved = seed_solutions(arm, target)
    found = np.nonzero(solved.exists)
    seeds, angles, rows = solved.q[found], grid[found[0]], found[1]
    if len(seeds) == 0:
        from redkin.numerical import ik as numerical_ik

        numerical = numerical_ik(arm.chain, target, count=8, restarts=_NUMERICAL_STARTS, rng=0)
        if numerical.reach is not None and bool(np.all(numerical.reach.out)):
            return (), True  # proven out of reach: no solution, nothing missed
        seeds = numerical.q[numerical.found]
        angles, rows = arm_angle(arm, seeds), branch_of(arm, seeds)
    curves, followed = _through(arm, target, seeds, angles, rows, len(seeds))
    return curves, followed and bool(curves) and all(curve.closed for curve in curves)


def seed_solutions(arm: NearlySRS, target: np.ndarray) -> tuple[np.ndarray, NearlySolutions]:
    """The seeds of :func:`whole_self_motion` at one pose (4, 4) (validated): the arm angles and
    :func:`redkin.srs.nearly.ik`'s solutions of every branch there, at :data:`SEEDS`, or at :data:`_FINE_SEEDS`
    where a branch has no solution at one of those.  (The call whose kernels ``redkin path`` on a nearly S-R-S arm
    compiles while a second process compiles the self-motion's.)"""
    grid = SEEDS
    solved = ik(arm, np.broadcast_to(target, grid.shape + (4, 4)), grid)
    if not solved.exists.all():
        grid = _FINE_SEEDS
        solved = ik(arm, np.broadcast_to(target, grid.shape + (4, 4)), grid)
    return grid, solved


def curves_through(arm: NearlySRS, pose: ArrayLike, solutions: ArrayLike, most: int = 16) -> tuple[SelfMotion, ...]:
    """The curves of the self-motion of ``pose`` through the ``solutions`` (M, 7), each once: one from each solution
    that lies on no curve found before (that curve's point at its arm angle and branch within
    :data:`_SAME_CURVE`), ``most`` curves at most.

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose) or joint values.
    """
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    q = np.asarray(arm.chain.check_q(solutions), dtype=float).reshape(-1, 7)
    return _through(arm, target, q, arm_angle(arm, q), branch_of(arm, q), most)[0]


def _through(arm: NearlySRS, target: np.ndarray, seeds: np.ndarray, angles: np.ndarray, rows: np.ndarray,
             most: int) -> tuple[tuple[SelfMotion, ...], bool]:
    """The curves through the solutions ``seeds`` (M, 7) at arm angles ``angles`` on branches ``rows``: each seed
    followed unless a curve followed from an earlier seed passes through it (:func:`_passes`, asked of the later
    seeds once a curve is followed), ``most`` curves and :data:`_BUDGET` points at most; and whether every seed was
    followed or lies on a curve.

    The seeds not yet on a curve at one arm angle (a pose's branches there: distinct points, on distinct curves
    unless a curve changes branch) are followed ahead together, one way, on the threads of
    :func:`redkin._compiled.run_batch` where it has more than one and the kernels run compiled
    (:func:`_traced_ahead`); a seed's curve is then taken from there only where the seed is still to be followed, so
    the curves are the same, point for point, as one after another."""
    curves: list[SelfMotion] = []
    covered = np.zeros(len(seeds), dtype=bool)  # on a curve followed from an earlier seed
    room = _Room(_MOST_POINTS)
    ahead: dict[int, SelfMotion] = {}  # seeds followed ahead, one way, by index
    tried = np.zeros(len(seeds), dtype=bool)  # followed ahead (a piece that filled its room is not in ``ahead``)
    for n, seed in enumerate(seeds):
        if covered[n]:
            continue
        if len(curves) == most or sum(len(curve.psi) for curve in curves) >= _BUDGET:
            return tuple(curves), False
        if not tried[n]:
            together = n + np.flatnonzero(~covered[n:] & (angles[n:] == angles[n]))[: most - len(curves)]
            tried[together] = True
            ahead = (_traced_ahead(arm, target, seeds[together], _LONGEST, together)
                     if len(together) > 1 and thread_count() > 1 and not running_as_python() else {})
        curves.append(_followed(arm, target, np.array(seed, dtype=float), _LONGEST, room, ahead.pop(n, None)))
        later = n + 1 + np.flatnonzero(~covered[n + 1:])
        covered[later] = _passes(curves[-1], angles[later], rows[later], seeds[later])
    return tuple(curves), True


def feasible_along(curves: tuple[SelfMotion, ...] | list[SelfMotion], branch: str | Branch) -> ArcSet:
    """The arm angles of the certified arcs of ``curves`` that lie on ``branch`` and within the limits (module
    docstring) [C6]: each run of such steps gives the arc from the smallest to the largest arm angle at its points
    (from the arm angle unwrapped along the run, each step's change less than pi by its certificate; the whole circle
    where it turns a whole turn)."""
    return feasible_along_all(curves)[BRANCHES.index(parse_branch(branch))]


def feasible_along_all(curves: tuple[SelfMotion, ...] | list[SelfMotion]) -> tuple[ArcSet, ...]:
    """:func:`feasible_along` of every branch, in the order of :data:`redkin.srs.BRANCHES`, in one pass over each
    curve."""
    arcs: list[list[tuple[float, float]]] = [[] for _ in BRANCHES]
    for curve in curves:
        for row, low, high in _branch_runs(curve):
            arcs[row].append((low, high))
    return tuple(ArcSet(found) for found in arcs)


def _branch_runs(curve: SelfMotion) -> list[tuple[int, float, float]]:
    """Each maximal run of steps of ``curve`` on one branch and within the limits (read cyclically where the curve
    is closed), as its branch row and the smallest and largest arm angle at its points, the arm angle unwrapped
    along the run from its first point."""
    label = np.where(curve.inside == _self_motion_kernels.INSIDE, curve.branches, -1)
    count = len(label)
    if count == 0:
        return []
    steps = np.diff(curve.psi)
    steps = steps - TWO_PI * np.round(steps / TWO_PI)  # each step turns less than pi (the certificate)
    order = np.arange(count)
    if curve.closed:
        changes = np.flatnonzero(label != np.roll(label, 1))
        if len(changes) == 0:  # one run all the way round
            psi = curve.psi[0] + np.concatenate([[0.0], np.cumsum(steps)])
            return [(int(label[0]), float(psi.min()), float(psi.max()))] if label[0] >= 0 else []
        order = np.roll(order, -int(changes[0]))
    labels = label[order]
    starts = np.flatnonzero(np.concatenate([[True], labels[1:] != labels[:-1]]))
    ends = np.append(starts[1:], count)  # a run's last point: the step after its last step starts there
    turned = np.concatenate([[0.0], np.cumsum(steps[order])])  # from point order[0], along order
    lows = np.minimum(np.minimum.reduceat(turned[:-1], starts), turned[ends]) - turned[starts]
    highs = np.maximum(np.maximum.reduceat(turned[:-1], starts), turned[ends]) - turned[starts]
    first = curve.psi[order[starts]]
    keep = labels[starts] >= 0
    return list(zip(labels[starts][keep].tolist(), (first + lows)[keep].tolist(), (first + highs)[keep].tolist(),
                    strict=True))


def branch_solutions(arm: NearlySRS, pose: ArrayLike, psi: float, branch: str | Branch,
                     curves: tuple[SelfMotion, ...] | list[SelfMotion] | None = None) -> np.ndarray:
    """Every solution of ``branch`` at the arm angle ``psi`` (K, 7), each once.

    :func:`redkin.srs.nearly.ik`'s row first where it exists (as a curve's point locates it where one passes through
    it: to rounding, where the row is certified to 1e-9; next to a limit the two may lie either side of it), then
    where a step of the branch on the self-motion's curves crosses ``psi``, the arc's point there, located by
    bisection along the step to :data:`_RESOLUTION` rad of arm angle and certified as ``nearly.ik`` certifies (the
    pose to 1e-9 m and rad, the arm angle to 1e-9 rad).  Where the branch has two solutions at ``psi`` (module
    docstring), both.  ``curves`` default to :func:`self_motions`; a curve through none of its seeds is not found.

    Raises
    ------
    ValueError
        For a malformed pose, arm angle or branch.
    """
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    angle = float(np.asarray(check_psi(psi)))
    label = parse_branch(branch)
    row = BRANCHES.index(label)
    if curves is None:
        curves = self_motions(arm, target)
    own = ik(arm, target, angle, label)
    found: list[np.ndarray] = [own.q[0]] if own.exists[0] else []
    for curve in curves:
        for k in _crossings(curve, angle, row):
            q = _located(arm, target, curve, int(k), angle)
            if q is None:
                continue
            same = [n for n, known in enumerate(found) if np.max(np.abs(wrap_angle(q - known))) <= _SAME_SOLUTION]
            if not same:
                found.append(q)
            elif same[0] == 0 and own.exists[0]:  # nearly.ik's row as the curve locates it: exact, not to 1e-9
                found[0] = own.q[0] + np.asarray(wrap_angle(q - own.q[0]))
    return np.array(found).reshape(-1, 7)


def _followed(arm: NearlySRS, target: np.ndarray, start: np.ndarray, step: float, room: _Room,
              forward: SelfMotion | None = None) -> SelfMotion:
    """The curve through ``start``: one way with the arm angle increasing (``forward``, where followed already), and
    where it does not close, the other way too, joined at ``start``."""
    if forward is None:
        forward = _traced(arm, target, start, step, 1.0, room)
    if forward.closed or len(forward.psi) == 0:
        return forward
    backward = _traced(arm, target, start, step, -1.0, room)
    if len(backward.psi) == 0:
        return forward
    joined = len(backward.psi) - 1  # backward's point k is the joined curve's point joined - k
    return SelfMotion(np.concatenate([backward.q[:0:-1], forward.q]),
                      np.concatenate([-backward.tangents[:0:-1], forward.tangents]),
                      np.concatenate([backward.psi[:0:-1], forward.psi]),
                      np.concatenate([-backward.rates[:0:-1], forward.rates]),
                      np.concatenate([backward.branches[::-1], forward.branches]),
                      np.concatenate([backward.inside[::-1], forward.inside]),
                      np.concatenate([backward.spread[::-1], forward.spread]),
                      np.concatenate([backward.tubes[::-1], forward.tubes]),
                      np.concatenate([joined - backward.anchors[::-1], joined + forward.anchors]), False)


class _Room:
    """The output arrays of :func:`redkin.srs.nearly._self_motion_kernels.traced` for ``count`` pieces (the first
    axis) of ``most`` points at most, each written by one piece after another (:func:`_motion` copies what it keeps):
    arrays this large are mapped fresh by the system on each allocation, and the first write to each page costs
    more than tracing a short curve."""

    def __init__(self, most: int, count: int = 1) -> None:
        self.most = most
        self.points, self.tangents = np.empty((count, most, 7)), np.empty((count, most, 7))
        self.angles, self.rates, self.spread = np.empty((count, most)), np.empty((count, most)), np.empty((count, most))
        self.signs, self.inside = np.empty((count, most, 3), dtype=np.int64), np.empty((count, most), dtype=np.int64)
        self.tubes = np.empty((count, most, 2))
        self.counts, self.statuses = np.zeros(count, dtype=np.int64), np.zeros(count, dtype=np.int64)


#: Points of one curve at most when seeds are followed ahead together (:func:`_traced_ahead`): a curve that is longer
#: (next to a singular configuration) is followed again alone, in a room of :data:`_MOST_POINTS`.
_AHEAD_POINTS = 8192


def _traced(arm: NearlySRS, target: np.ndarray, start: np.ndarray, step: float, sense: float,
            room: _Room) -> SelfMotion:
    """:func:`redkin.srs.nearly._self_motion_kernels.traced` one way from ``start``, ``room.most`` points at
    most."""
    _trace_each(0, 1, np.ascontiguousarray(start, dtype=float)[None], target, _kernel_arm(arm), float(step),
                float(sense), room)
    return _motion(arm, room, 0)


def _traced_ahead(arm: NearlySRS, target: np.ndarray, starts: np.ndarray, step: float,
                  indices: np.ndarray) -> dict[int, SelfMotion]:
    """:func:`_traced` with the arm angle increasing from each of ``starts`` (S, 7), on the threads of
    :func:`redkin._compiled.run_batch`, :data:`_AHEAD_POINTS` points at most: by ``indices`` (S,), each piece that
    ended before that (closed, or stuck)."""
    room = _Room(_AHEAD_POINTS, len(starts))
    run_batch(_trace_each, len(starts), np.ascontiguousarray(starts, dtype=float), target, _kernel_arm(arm),
              float(step), 1.0, room)
    return {int(index): _motion(arm, room, k) for k, index in enumerate(indices.tolist())
            if room.statuses[k] != _self_motion_kernels.FULL}


def _kernel_arm(arm: NearlySRS) -> tuple:
    """The arm's arguments of :func:`redkin.srs.nearly._self_motion_kernels.traced`, read once (before any thread
    of :func:`_traced_ahead` reads them)."""
    return arm.kernel_real, arm.kernel_model, arm.kernel_bounds, arm.real_phase, arm.kernel_limits


def _trace_each(start: int, stop: int, starts: np.ndarray, target: np.ndarray, kernel_arm: tuple, step: float,
                sense: float, room: _Room) -> None:
    """The batch of :func:`_traced_ahead`: :func:`redkin.srs.nearly._self_motion_kernels.traced` from ``starts[k]``
    into the room's piece ``k``, for ``k`` in ``[start, stop)``, on the arm's arguments ``kernel_arm``
    (:func:`_kernel_arm`; the kernel runs without the interpreter's lock)."""
    for k in range(start, stop):
        room.counts[k], room.statuses[k] = _self_motion_kernels.traced(
            starts[k], target, *kernel_arm, step, sense, room.most, room.points[k], room.tangents[k], room.angles[k],
            room.rates[k], room.signs[k], room.inside[k], room.spread[k], room.tubes[k])


#: The digits' weights of three signs read as a number in base 3 (each sign plus one).
_BASE_THREE = np.array([9, 3, 1], dtype=np.int64)


def _motion(arm: NearlySRS, room: _Room, k: int) -> SelfMotion:
    """The piece ``k`` of ``room`` as a :class:`SelfMotion` (copied): each step's branch the row of
    :data:`redkin.srs.BRANCHES` whose Table 1 signs its signs are, -1 where one is 0 (undecided)."""
    count, status = int(room.counts[k]), int(room.statuses[k])
    steps = max(count - 1, 0)
    row_of = np.full(27, -1, dtype=np.int64)  # each step's three signs (-1, 0 or 1) as a base-3 number -> its row
    row_of[(arm.geometry.kernel_branches.astype(np.int64) + 1) @ _BASE_THREE] = np.arange(len(BRANCHES))
    branches = row_of[(room.signs[k, :steps] + 1) @ _BASE_THREE]
    return SelfMotion(room.points[k, :count].copy(), room.tangents[k, :count].copy(), room.angles[k, :count].copy(),
                      room.rates[k, :count].copy(), branches, room.inside[k, :steps].copy(),
                      room.spread[k, :steps].copy(), room.tubes[k, :steps].copy(), np.arange(steps),
                      status == _self_motion_kernels.CLOSED)


def finer_steps(arm: NearlySRS, pose: np.ndarray, curve: SelfMotion, k: int, longest: float,
                most: int = 64) -> SelfMotion | None:
    """The arc of ``curve``'s step ``k`` followed again with certified steps of at most ``longest`` [rad], from the
    step's anchor (:attr:`SelfMotion.anchors`) the way the step runs from it, until past the step's other end: a
    piece of the same curve (the step's tube holds one arc of solutions, so no other), whose steps together cover
    the step's arc, with its points ordered from the anchor.  ``None`` where it could not be followed that far in
    ``most`` points (a step that cannot be certified)."""
    anchor = int(curve.anchors[k])
    other = k + 1 if anchor == k else k
    forward = 1.0 if anchor == k else -1.0
    direction = forward * curve.tangents[anchor]
    length = float((curve.q[other] - curve.q[anchor]) @ direction)
    rate = forward * curve.rates[anchor]
    room = _Room(most)
    for sense in ((1.0, -1.0) if rate >= 0.0 else (-1.0, 1.0)):  # the arm angle's sense along the step
        piece = _traced(arm, pose, curve.q[anchor], longest, sense, room)
        if len(piece.psi) < 2 or float(piece.tangents[0] @ direction) <= 0.0:
            continue
        along = (piece.q[:-1] - curve.q[anchor]) @ direction  # each step's start on the step's chord
        past = np.flatnonzero((piece.q[1:] - curve.q[anchor]) @ direction >= length)
        if not len(past):
            return None
        keep = int(past[0]) + 1  # the steps up to the first that ends past the other end
        if np.any(along[:keep] > length):
            return None
        return SelfMotion(piece.q[: keep + 1], piece.tangents[: keep + 1], piece.psi[: keep + 1],
                          piece.rates[: keep + 1], piece.branches[:keep], piece.inside[:keep], piece.spread[:keep],
                          piece.tubes[:keep], piece.anchors[:keep], False)
    return None


def _crossings(curve: SelfMotion, angle: float, row: int) -> np.ndarray:
    """The steps of ``curve`` on branch ``row`` whose ends lie on either side of the arm angle ``angle`` (or at
    it)."""
    return _crossing_steps(curve, np.array([angle]), np.array([row]))[1]


def _crossing_steps(curve: SelfMotion, angles: np.ndarray, rows: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_crossings` of each arm angle ``angles`` (S,) on its branch ``rows`` (S,) at once: the pairs (index
    into ``angles``, step) in row-major order, and at each the step's start less its angle and the step's change of
    arm angle (both wrapped)."""
    width = np.asarray(wrap_angle(curve.psi[1:] - curve.psi[:-1]))
    on_curve = np.zeros(len(BRANCHES) + 1, dtype=bool)  # the branches of the curve's steps (-1, none, last)
    on_curve[curve.branches] = True
    asked = np.flatnonzero(on_curve[rows])  # only these can cross it
    before = np.asarray(wrap_angle(curve.psi[:-1] - angles[asked, None]))
    after = before + width
    which, k = np.nonzero((curve.branches == rows[asked, None]) & (before * after <= 0.0)
                          & ((before != 0.0) | (after != 0.0)))
    return asked[which], k, before[which, k], width[k]


def _located(arm: NearlySRS, target: np.ndarray, curve: SelfMotion, k: int, angle: float) -> np.ndarray | None:
    """The point of the arc of step ``k`` at the arm angle ``angle``: bisection on the arc's hyperplanes (the
    corrector of :mod:`redkin.srs.nearly._self_motion_kernels`) until the bracket's arm angles are :data:`_RESOLUTION`
    apart, then certified as :func:`redkin.srs.nearly.ik` certifies; ``None`` where the certificate fails."""
    start, direction = curve.q[k], curve.tangents[k]
    low, high = 0.0, float((curve.q[k + 1] - start) @ direction)
    low_value = float(wrap_angle(curve.psi[k] - angle))
    point = curve.q[k].copy()
    value = low_value
    for _ in range(200):
        if abs(value) <= _RESOLUTION or high - low <= 1e-15:
            break
        middle = 0.5 * (low + high)
        point, value = _point(arm, target, start, direction, middle, angle)
        if np.sign(value) == np.sign(low_value):
            low, low_value = middle, value
        else:
            high = middle
    if abs(value) > _RESOLUTION:
        point = curve.q[k + 1] if abs(float(wrap_angle(curve.psi[k + 1] - angle))) <= _RESOLUTION else point
    error = np.abs(arm.chain.fk(point) - target)
    off = abs(float(wrap_angle(float(arm_angle(arm, point)) - angle)))
    if error[:3, 3].max() > 1e-9 or error[:3, :3].max() > 1e-9 or off > 1e-9:
        return None
    return point


def _point(arm: NearlySRS, target: np.ndarray, start: np.ndarray, direction: np.ndarray, distance: float,
           angle: float) -> tuple[np.ndarray, float]:
    """The curve's point on the hyperplane ``direction . (q - start) = distance`` and its arm angle less ``angle``
    (wrapped)."""
    point = start + distance * direction
    work = _self_motion_kernels.scratch()
    settled = _self_motion_kernels.corrected(point, start, direction, distance, target, arm.kernel_real,
                                             arm.kernel_bounds, work)[0]
    if not settled:
        raise RedkinError("the self-motion could not be followed between two of its points; please report this")
    return point, float(wrap_angle(arm_angle(arm, point) - angle))


def _passes(curve: SelfMotion, angles: np.ndarray, rows: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Whether ``curve`` passes through each solution ``q`` (S, 7) of branch ``rows`` (S,) at the arm angle
    ``angles`` (S,): a step of the branch crossing the angle whose chord there (by the arm angle's share) lies within
    :data:`_SAME_CURVE` of the solution, modulo whole turns."""
    which, k, before, width = _crossing_steps(curve, angles, rows)
    share = np.divide(-before, width, out=np.zeros_like(before), where=width != 0.0)
    chord = curve.q[k] + share[:, None] * (curve.q[k + 1] - curve.q[k])
    near = np.max(np.abs(np.asarray(wrap_angle(chord - q[which]))), axis=1, initial=0.0) <= _SAME_CURVE
    passes = np.zeros(len(angles), dtype=bool)
    passes[which[near]] = True
    return passes
