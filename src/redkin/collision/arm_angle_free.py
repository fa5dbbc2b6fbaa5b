"""Certified collision-free arm angles of S-R-S and offset-elbow arms (issue 40, item 4).

For one pose and each branch, the arm angles psi [000 eq. 6] at which the branch's solution [000 eqs. 11-19] lies
within the joint limits [000 eq. 30] *and* every checked pair of shapes -- each capsule of the arm's body against
each obstacle, and the body's self-collision pairs (:mod:`redkin.collision.body`) -- is at least the scene's
margin apart.

What is proved.  The clearance of a pair, ``c(psi) = signed distance - margin``, is evaluated at the middle ``m`` of
an interval ``[m - h, m + h]`` and bounded over the whole interval by ``|c(psi) - c(m)| <= v h``, ``v`` an upper
bound of the two shapes' speeds over the interval (the signed distances of :func:`redkin.collision.signed_distance`
move no faster than the points of either shape).  The speeds come from the structure of an S-R-S arm at a fixed
pose, with ``S`` the shoulder centre (on axes 1-3), ``W`` the wrist centre (on axes 5-7) and ``u`` the unit vector
from ``S`` to ``W``:

* the base (frame 0) and the last link (frame 7, the tool's) do not move;
* links 3 and 4 turn rigidly about the line ``S``-``W`` at unit rate: ``0R3(psi) = R_u(psi) 0R3o`` [000 eq. 12],
  so a point at distance ``rho`` from that line moves at ``rho`` per radian, exactly;
* link 1 turns about axis 1 at ``|dtheta_1/dpsi|``, link 2 about ``S`` at no more than ``|dtheta_1/dpsi| +
  |dtheta_2/dpsi|``; from the tip, link 6 turns about axis 7 at ``|dtheta_7/dpsi|`` and link 5 about ``W`` at no
  more than ``|dtheta_6/dpsi| + |dtheta_7/dpsi|``.

A pair of a capsule on links 3-4 and a still shape (an obstacle, the base, the tool's link) is bounded more tightly
from the pair's normal and closest points at ``m``
(:func:`redkin.collision._arm_angle_kernels.turning_bounds`): the distance lies between the gap of the two cores'
projections on the normal and the distance of the two closest points, both exact at ``m``, and under the rigid
turn each is a sinusoid in ``psi - m`` whose rise over the interval is bounded in closed form; so ``v`` is the speed
of the distance itself to first order.  For the stretch cut around a middle (below) the two bounds are read one-sided
and as quadratics in ``|psi - m|`` (a rise at distance ``t`` of at most ``s t + b t^2``, not the interval's rate
times ``t``): a clear pair stays clear while the projections' bound falls by less than its clearance, a colliding one
colliding while the closest points' bound rises by less than its depth, so the cut reaches to within second order of
a free arc's end however wide the interval (where ``c(m) / v`` reached a fraction of the way: the benchmark cell's
ends took about one evaluation in four of all).  Each side is bounded apart: the first-order term of a sinusoid keeps
its sign along a side (psi grows as the links turn positively about the line from the shoulder to the wrist,
``0R3(psi) = R_u(psi) 0R3o`` [000 eq. 12]), and where it takes the distance away from the margin the cut reaches past
the end's side of the interval in the same evaluation (it left a sliver there that cost an evaluation of its own).
Two shapes both on links 3-4 turn together: their distance does not change.

The joint rates are bounded over the interval from [000 eqs. 13-14, 18-19]: each entry ``e(psi) = a sin psi + b cos
psi + c`` of ``0R3`` and ``4R7`` [000 eqs. 12, 16] and its derivative move by at most ``hypot(a, b) h`` from their
values at ``m``, and ``theta_1 = atan2(y, x)``, ``theta_2 = acos z`` (with ``x^2 + y^2 = 1 - z^2``) give
``|theta_1'| <= (|x| |y'| + |y| |x'|) / (x^2 + y^2)`` and ``|theta_2'| <= |z'| / sqrt(1 - z^2)``, each factor replaced
by its bound over the interval (the denominator by the larger of its two lower bounds, from ``|z|`` and from ``|x|,
|y|``); the same for ``theta_6, theta_7`` (``theta_7 = atan2(t, -r_2)``, ``t^2 + r_2^2 = 1 - z^2``).  Over an
interval wider than 0.2 rad they are the largest of the bounds over its pieces (each holds on its piece).  These
bounds grow without limit near a singular arm angle [000 eqs. 31-34], where the branch's shoulder or wrist turns half
a turn.

An interval is **free** where every pair's ``c(m) - v h > 0``, **blocked** by a pair where ``c(m) + v h < 0`` (that
pair is its cause), and otherwise cut around its middle: since ``v`` bounds the speeds over the whole interval,
``c(psi) >= c(m) - v |psi - m|`` on it, so ``[m - r, m + r]`` is free with ``r`` the least ``c(m) / v`` of the pairs
still open where all are positive (or, on each side, the quadratic bound's root where it is larger, above: then
``[m - r_down, m + r_up]``), and blocked by the pair of the largest ``-c(m) / v`` (or roots) where one is negative
(each radius a hair smaller, for rounding); the pieces on either side (the halves, where ``r`` is 0) are decided in
turn.  Near an end of a free arc this takes about half
the evaluations of halving alone.  An interval no wider than half
the resolution that is still undecided is reported as such and left out of the free set; a run of undecided
intervals wider than the resolution is cut further until it is not, and so is a run between two intervals of one kind
(a sliver inside a free arc or a blocked stretch, where no end need lie), down to a thousandth of the resolution.
So every point of a free arc is collision-free; two certified intervals of opposite kinds cannot touch, so every end
of a free arc is located to within the resolution; and a free stretch is missed only where some pair's clearance is
within ``v h`` of the margin on all of it (a stretch that only grazes the margin, or one narrower than the
resolution).  The stretches the joint limits remove are named by the
joints that leave their range there ([000 eq. 29]).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple, Protocol

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import check_pose
from redkin.arms.analysis import check_in_reach
from redkin.arms.feasible_sets import ArcArrays, Arcs, owner_arcs
from redkin.arms.front_door import Arm
from redkin.arms.srs_kind import SRSKind
from redkin.chain import SerialChain
from redkin.circle import TWO_PI, ArcSet, arc_length
from redkin.collision import _arm_angle_kernels, _decision_kernels
from redkin.collision.body import Body, capsule_ends, posed
from redkin.collision.clearance import checked_pairs, clearance_inputs
from redkin.collision.scene import Scene
from redkin.errors import RedkinError
from redkin.srs.coefficients import coefficient_arrays
from redkin.srs.geometry import SRSGeometry
from redkin.srs.ik import solve_with_status

#: The widest interval a limit-feasible arc is cut into before the first evaluation [rad]: a quarter turn.  Each
#: evaluation carves the stretch its clearances prove around its middle, so wide first intervals cost no more
#: evaluations than a fine grid and leave fewer pieces to merge (the benchmark cell's 1000-waypoint path: 0.88-0.99 s
#: of sets at 0.25 rad, 0.56-0.58 s at 1.5-2 rad).
_FIRST_WIDTH = np.pi / 2
#: The causes of a removed stretch.
COLLISION, LIMIT, UNDECIDED = "collision", "limit", "undecided"
#: A capsule this close to what its frame turns about, or to the shoulder-wrist line, is on it [m]
#: (:func:`moved_pairs`).
_STILL = 1e-9


class Stretch(NamedTuple):
    """A stretch ``[start, end]`` of arm angles removed from a branch's free set, and why.

    ``cause`` is :data:`COLLISION` (``link`` meets ``against``: an obstacle's name, or another link of the body),
    :data:`LIMIT` (``against`` names the joints out of range, ``"joint 2, joint 6"``, or says ``"no solution"``) or
    :data:`UNDECIDED` (no wider than the resolution, next to a singular arm angle or where a clearance grazes the
    margin).  A stretch through ``+-pi`` has ``start > end``; the whole circle is ``(-pi, pi)``
    (:func:`redkin.circle.arc_length`).
    """

    start: float
    end: float
    cause: str
    link: str
    against: str


@dataclass(frozen=True, eq=False)
class FreeArmAngles:
    """The certified collision-free values of the redundancy parameter of one pose: arm angles (module docstring),
    or q7 on the Franka class (:func:`redkin.collision.collision_free_q7`).

    Attributes
    ----------
    branches : tuple of str
    free : tuple of Arcs
        Per branch, the values within the limits and clear of every checked pair by the margin.
    limits : tuple of Arcs
        Per branch, the values within the limits ([000 eq. 30]; [F8]-[F9] for q7).
    blocked : tuple of tuple of Stretch
        Per branch, every stretch removed from the circle, with its cause, in order of ``start`` (empty where the
        sets were computed without their causes: ``free_sets_of(..., causes=False)``, what path resolution reads).
    resolution : float
        The width [rad] below which an undecided interval is no longer halved.
    evaluations : int
        How many configurations were posed and measured.
    complete : bool
        False where the budget of evaluations ran out first, or a run of undecided intervals stayed wider than the
        resolution: those are then undecided stretches wider than it (a degenerate pose, such as a stretched elbow
        with the wrist on axis 1, where every arm angle is singular; or a clearance that equals the margin over a
        stretch).
    parameter : str
        ``"psi"``, or ``"q7"`` on the Franka class.
    """

    branches: tuple[str, ...]
    free: tuple[Arcs, ...]
    limits: tuple[Arcs, ...]
    blocked: tuple[tuple[Stretch, ...], ...]
    resolution: float
    evaluations: int
    complete: bool
    parameter: str = "psi"

    def arcs(self, branch: str) -> Arcs:
        """The free arcs of ``branch``."""
        if branch not in self.branches:
            raise RedkinError(f"no branch {branch!r} here (branches: {', '.join(self.branches)})")
        return self.free[self.branches.index(branch)]


def collision_free_arm_angles(arm: Arm, pose: ArrayLike, body: Body, scene: Scene,
                              branches: str | tuple[str, ...] | list[str] | None = None, *,
                              resolution: float = 1e-6, budget: int = 100_000) -> FreeArmAngles:
    """The certified collision-free arm angles of one pose on each branch (module docstring).

    Parameters
    ----------
    arm : Arm
        An S-R-S or offset-elbow arm (:func:`redkin.arm`).
    pose : array_like, shape (4, 4)
        The tool's target pose in the base frame.
    body : Body
        The arm's capsules, on ``arm.chain``'s frames.
    scene : Scene
        The obstacles and the margin (also kept between the body's self-collision pairs).
    branches : str or sequence of str, optional
        Default all eight.
    resolution : float
        Ends are located to this width [rad], > 0.
    budget : int
        The most configurations to evaluate; beyond it the open intervals are left undecided (``complete`` false).

    Raises
    ------
    RedkinError
        For an arm of another class (named), a body on another number of joints, a malformed pose, a resolution
        that is not > 0 or a budget that is not an integer >= 1; :class:`redkin.errors.UnreachablePoseError` for a
        pose out of reach.
    """
    return free_arm_angles_of(arm, one_pose(arm, pose), body, scene, branches, resolution=resolution, budget=budget)[0]


def free_arm_angles_of(arm: Arm, poses: ArrayLike, body: Body, scene: Scene,
                       branches: str | tuple[str, ...] | list[str] | None = None, *, resolution: float = 1e-6,
                       budget: int = 100_000, causes: bool = True) -> list[FreeArmAngles]:
    """:func:`collision_free_arm_angles` of each pose of ``poses`` ``(P, 4, 4)``, decided together: the intervals
    of every pose and branch are halved in one batch, so the work per level is shared (``budget`` per pose).
    Without ``causes`` the removed stretches are neither named nor solved for (``blocked`` empty)."""
    poses, certified = certified_arm_angles(arm, poses, body, scene, branches, resolution=resolution, budget=budget)
    limits, labels = certified.limits_per_pose(), certified.labels
    blocked = merged_stretches(certified.decided.stretches(certified.owners, certified.names, _wrapped),
                               _circle_limit_stretches_of(arm, poses, labels, limits), len(labels)) \
        if causes else certified.no_causes()
    return certified.results(limits, blocked, resolution, "psi")


def certified_arm_angles(arm: Arm, poses: ArrayLike, body: Body, scene: Scene,
                         branches: str | tuple[str, ...] | list[str] | None = None, *, resolution: float = 1e-6,
                         budget: int = 100_000) -> tuple[np.ndarray, Certified]:
    """:func:`free_arm_angles_of`'s decision, before it is read per pose: the poses checked ``(P, 4, 4)`` and what
    :func:`certify` decided (:class:`Certified`)."""
    if not isinstance(arm.implementation, SRSKind):
        elsewhere = ("its q7 sets are redkin.collision.collision_free_q7's" if arm.parameter is not None
                     and arm.parameter.name == "q7" else "redkin.collision.free_sets_of takes every class")
        raise RedkinError(f"certified collision-free arm angles are computed on S-R-S and offset-elbow arms; "
                          f"{arm.chain.name} is {arm.kind} ({elsewhere})")
    poses = checked_inputs(arm, poses, body, resolution, budget)
    limits = arm.feasible(poses, branches)
    geometry = arm.implementation.geometry
    rows = np.array([arm.branches.index(label) for label in limits.branches])
    limit_arcs = limits.arc_arrays()
    measure = _Measure(arm, poses, body, scene, geometry.kernel_branches[rows], geometry)
    parts, complete = certify(first_intervals(limit_arcs, _FIRST_WIDTH), len(limits.branches), len(poses), resolution,
                              measure, budget, carve=True)
    return poses, Certified(limits.branches, limit_arcs, Decided.of(parts), complete, measure.evaluations,
                            measure.names, True)


class Certified(NamedTuple):
    """What :func:`certify` decided for a batch of poses, each interval's owner ``pose * B + branch``: the branches'
    labels ``(B,)``, their limit-feasible arcs, the decided intervals, per pose whether it was decided completely and
    how many configurations were posed, the checked pairs' names, and whether the parameter wraps (an arm angle)."""

    labels: tuple[str, ...]
    limits: ArcArrays
    decided: Decided
    complete: np.ndarray
    evaluations: np.ndarray
    names: list[tuple[str, str]]
    wraps: bool

    @property
    def owners(self) -> int:
        return len(self.complete) * len(self.labels)

    def free(self) -> ArcArrays:
        """The free arcs of every owner: the free intervals merged."""
        return owner_arcs(*self.decided.free_runs(), self.wraps)

    def limits_per_pose(self) -> list[tuple[Arcs, ...]]:
        """Per pose, the limit-feasible arcs of each branch."""
        return self._per_pose(self.limits)

    def no_causes(self) -> list[tuple[tuple[Stretch, ...], ...]]:
        """Per pose, no removed stretch named on any branch (sets computed without their causes)."""
        return [tuple(() for _ in self.labels)] * len(self.complete)

    def results(self, limits: list[tuple[Arcs, ...]], blocked: list[tuple[tuple[Stretch, ...], ...]],
                resolution: float, parameter: str) -> list[FreeArmAngles]:
        """Per pose, its :class:`FreeArmAngles` with the limit arcs ``limits`` and the removed stretches ``blocked``
        (per pose and branch)."""
        free = self._per_pose(self.free())
        return [FreeArmAngles(self.labels, free[p], limits[p], blocked[p], float(resolution),
                              int(self.evaluations[p]), bool(self.complete[p]), parameter)
                for p in range(len(self.complete))]

    def _per_pose(self, arcs: ArcArrays) -> list[tuple[Arcs, ...]]:
        count = len(self.labels)
        every = arcs.split(self.owners)
        return [tuple(every[p * count:(p + 1) * count]) for p in range(len(self.complete))]


def merged_stretches(removed: list[list[Stretch]], at_limits: list[list[list[Stretch]]],
                     count: int) -> list[tuple[tuple[Stretch, ...], ...]]:
    """Per pose and branch (``count`` a pose), the stretches the decision removed (``removed``, per owner ``pose *
    count + branch``) and those the limits remove (``at_limits``, per pose and branch), in order of ``start``."""
    return [tuple(tuple(sorted(removed[p * count + b] + theirs, key=lambda stretch: stretch.start))
                  for b, theirs in enumerate(pose_limits)) for p, pose_limits in enumerate(at_limits)]


class _Settle(Protocol):
    """What :func:`certify` decides intervals with: the checked pairs' clearances at the intervals' middles and the
    bounds of how fast each changes over them, decided (:func:`redkin.collision._decision_kernels.decided_one`)."""

    evaluations: np.ndarray  # configurations posed so far, per pose
    count: int  # checked pairs

    def __call__(self, middle: np.ndarray, half: np.ndarray, owner: np.ndarray, active: np.ndarray, finest: float,
                 carve: bool) -> tuple[np.ndarray, ...]: ...


def one_pose(arm: Arm, pose: ArrayLike) -> np.ndarray:
    """One pose ``(4, 4)``, checked, as a batch of one ``(1, 4, 4)`` (the one-pose forms of the free sets), refused
    where ``arm``'s class proves it out of reach (as :meth:`redkin.arms.front_door.Arm.analyse` refuses it; a batch
    of poses answers such a pose with no free set instead, each branch's circle removed as "no solution").

    Raises
    ------
    RedkinError
        For a malformed pose or another shape; :class:`redkin.errors.UnreachablePoseError` for a pose out of reach,
        with the distance and the range.
    """
    checked = check_pose(pose)
    if checked.shape != (4, 4):
        raise RedkinError(f"pose must be one 4x4 transform, got shape {checked.shape}")
    if arm.parameter is not None:  # a class with closed forms (the others are refused by the sets themselves)
        check_in_reach(arm.ik(checked, 0.0).reach)
    return checked[None]


def checked_inputs(arm: Arm, poses: ArrayLike, body: Body, resolution: float, budget: int) -> np.ndarray:
    """The poses ``(P, 4, 4)`` of a batch of free sets, checked with the body, the resolution and the budget.

    Raises
    ------
    RedkinError
        For a body on another number of joints, a resolution that is not > 0, a budget that is not an integer >= 1
        or malformed poses.
    """
    if len(body) and int(body.frame.max()) > arm.chain.n:
        raise RedkinError(f"the body uses frame {int(body.frame.max())}, but {arm.chain.name} has {arm.chain.n} joints")
    if not (np.isfinite(resolution) and resolution > 0.0):
        raise RedkinError(f"resolution must be a number > 0 (radians), got {resolution!r}")
    if isinstance(budget, bool) or not isinstance(budget, int | np.integer) or budget < 1:
        raise RedkinError(f"budget must be an integer >= 1 (configurations per pose), got {budget!r}")
    checked = check_pose(poses)
    if checked.ndim != 3:
        raise RedkinError(f"poses must have shape (P, 4, 4), got shape {checked.shape}")
    return checked


def certify(intervals: tuple[np.ndarray, np.ndarray, np.ndarray], count: int, poses: int, resolution: float,
            settle: _Settle, budget: int, *, carve: bool = False) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Decide the intervals ``(lo, hi, owner)`` (an owner is ``pose * count + branch``) as free, blocked or undecided to
    ``resolution`` (module docstring), then decide further each run of undecided intervals wider than it, and each
    sliver between two intervals of one kind (:func:`_undecided_runs`); ``settle(middle, half, owner, active, finest,
    carve)`` decides intervals from the pairs' clearances at their middles and the bounds of how fast they change
    over them (:func:`redkin.collision._decision_kernels.decided_one`; with ``carve``, bounds of the derivative: then
    each evaluation also decides the stretch around the middle its own clearances prove, :func:`_decide`). Returns
    the decided intervals ``(lo, hi, owner, kind, pair)`` and per pose whether it was decided completely (the budget,
    ``budget`` evaluations per pose, sufficed and no undecided run is wider than the resolution)."""
    parts, undone = _decide(*intervals, resolution / 2.0, settle, budget * poses, carve)
    complete = np.ones(poses, dtype=bool)
    complete[undone // count] = False
    finest = resolution / 4.0
    settled: list[tuple[np.ndarray, ...]] = []  # the intervals of owners with nothing left to cut
    while True:  # runs of undecided intervals wider than the resolution (and slivers between one kind), cut further
        wide, inner = _undecided_runs(parts, resolution)
        wide &= complete[parts[2] // count]
        if finest < resolution * 1e-6:  # a clearance that grazes the margin over a stretch: left undecided
            complete[parts[2][wide] // count] = False
            break
        wide |= inner & complete[parts[2] // count] & (finest >= resolution * _INNER_FLOOR)
        if not wide.any():
            break
        again, undone = _decide(parts[0][wide], parts[1][wide], parts[2][wide], finest, settle, budget * poses, carve)
        complete[undone // count] = False
        open_owners = np.isin(parts[2], parts[2][wide])  # the others' intervals do not change any more
        settled.append(tuple(part[~open_owners] for part in parts))
        parts = tuple(np.concatenate([part[open_owners & ~wide], more]) for part, more in zip(parts, again,
                                                                                              strict=True))
        finest /= 2.0
    return tuple(np.concatenate(column) for column in zip(*settled, parts, strict=True)), complete


def _decide(lo: np.ndarray, hi: np.ndarray, owner: np.ndarray, finest: float, settle: _Settle, budget: int,
            carve: bool) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Halve the intervals ``[lo, hi]`` of the branches ``owner`` until each is free, blocked, or undecided and no
    wider than ``finest`` (module docstring), each level decided by ``settle``.

    With ``carve`` (the speeds bound each clearance's derivative over the interval: ``|c(psi) - c(m)| <= v |psi -
    m|``), an interval left open is not halved but cut around its middle ``m``: where every open pair's clearance
    is positive, ``[m - r, m + r]`` with ``r`` the least ``c / v`` of them is free (each side as far as the measure
    proves it, ``[m - down, m + up]``); where one is negative, the largest ``-c / v`` gives a stretch it blocks; the
    two pieces beside it stay open (halves where both are 0).

    Returns ``(lo, hi, owner, kind, pair)`` of the decided intervals (kind 0 free, 1 blocked by ``pair``, 2
    undecided), and the owners of the intervals still open when the budget ran out (left undecided).
    """
    decided: list[tuple[np.ndarray, np.ndarray]] = [(np.empty((2, 0)), np.empty((3, 0), dtype=np.int64))]
    active = np.ones((len(lo), settle.count), dtype=bool)  # the pairs not yet proved clear on each interval
    while len(lo):
        if settle.evaluations.sum() + len(lo) > budget:
            undecided = np.full(len(lo), _decision_kernels.UNDECIDED)
            decided.append((np.stack([lo, hi]), np.stack([owner, undecided, np.zeros(len(lo), dtype=np.int64)])))
            break
        kind, which, down, up, carved, cause = settle((lo + hi) / 2.0, (hi - lo) / 2.0, owner, active, finest, carve)
        room = 2 * len(lo)  # an interval leaves at most two decided pieces, and at most two open ones
        bounds, labels = np.empty((2, room)), np.empty((3, room), dtype=np.int64)
        open_bounds, open_owner = np.empty((2, room)), np.empty(room, dtype=np.int64)
        open_active = np.empty((room, settle.count), dtype=bool)
        done, left = _decision_kernels.next_level(lo, hi, owner, active, kind, which, down, up, carved, cause, bounds,
                                                  labels, open_bounds, open_owner, open_active)
        decided.append((bounds[:, :done], labels[:, :done]))
        lo, hi, owner, active = open_bounds[0, :left], open_bounds[1, :left], open_owner[:left], open_active[:left]
    bounds, labels = (np.concatenate(column, axis=1) for column in zip(*decided, strict=True))
    return (bounds[0], bounds[1], labels[0], labels[1], labels[2]), owner


def settled(half: np.ndarray, clearance: np.ndarray, speed: np.ndarray, active: np.ndarray, finest: float,
            carve: bool) -> tuple[np.ndarray, ...]:
    """Intervals of half widths ``half`` (N,) decided from their pairs' clearances at the middles and speed bounds
    ``(N, P)`` (:func:`redkin.collision._decision_kernels.decided_one`, in one compiled pass; ``active`` ``(N, P)``
    updated in place): ``(kind, pair, down, up, carved, cause)``, each (N,), the carved stretch reaching ``down``
    below the middle and ``up`` above it (equal: a speed bound is the same on both sides).  For a measure whose
    clearances and bounds are computed apart (the Franka class's q7)."""
    count = len(half)
    kind, pair, carved, cause = (np.empty(count, dtype=np.int64) for _ in range(4))
    down, up = np.empty(count), np.empty(count)
    run_batch(_decision_kernels.decided, count, kernel_array(half), kernel_array(clearance), kernel_array(speed),
              active, float(finest), bool(carve), kind, pair, down, up, carved, cause)
    return kind, pair, down, up, carved, cause


#: Slivers left undecided between two intervals of one kind (:func:`_undecided_runs`) are cut down to this fraction
#: of the resolution, then left undecided (no end of the free set need lie there).
_INNER_FLOOR = 1e-3


def _undecided_runs(parts: tuple[np.ndarray, ...], resolution: float) -> tuple[np.ndarray, np.ndarray]:
    """Which decided intervals are undecided ones in a run of touching undecided intervals of one branch (a) wider
    than ``resolution``, (b) touched on both sides by intervals of one kind, both free or both blocked (a sliver that
    cuts around a middle leave inside a free arc or a blocked stretch: no end of the free set need lie there)."""
    order = np.lexsort((parts[0], parts[2]))
    lo, hi, owner, kind = (part[order] for part in parts[:4])
    undecided = kind == 2
    touching = np.zeros(len(lo), dtype=bool)  # each interval touches the one before it, of the same branch
    touching[1:] = (owner[1:] == owner[:-1]) & (lo[1:] <= hi[:-1])
    joined = np.zeros(len(lo), dtype=bool)
    joined[1:] = undecided[1:] & undecided[:-1] & touching[1:]
    run = np.cumsum(~joined) - 1
    starts = np.flatnonzero(~joined)
    ends = np.append(starts[1:] - 1, len(lo) - 1) if len(lo) else starts
    wide, inner = np.zeros(len(lo), dtype=bool), np.zeros(len(lo), dtype=bool)
    if len(lo):
        before_index, after_index = np.maximum(starts - 1, 0), np.minimum(ends + 1, len(lo) - 1)
        before = np.where((starts > 0) & touching[starts], kind[before_index], -1)  # the kind touching it, or -1
        after = np.where((ends + 1 < len(lo)) & touching[after_index], kind[after_index], -1)
        wide[order] = undecided & (hi[ends][run] - lo[starts][run] > resolution)
        inner[order] = undecided & ((before >= 0) & (before == after))[run]
    return wide, inner


def first_intervals(arcs: ArcArrays, widest: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each owner's limit-feasible arcs (a pose's branch) cut into intervals no wider than ``widest``,
    unrolled so that ``lo < hi`` (an arc through the seam ends beyond pi): ``(lo, hi, owner)``, the cuts of each
    arc evenly spaced as :func:`numpy.linspace` spaces them."""
    bounds, wraps, owner = arcs
    if not len(bounds):
        return np.empty(0), np.empty(0), np.empty(0, dtype=np.int64)
    start, end = bounds[:, 0], np.where(wraps, bounds[:, 1] + TWO_PI, bounds[:, 1])
    pieces = np.maximum(1, np.ceil((end - start) / widest)).astype(np.int64)
    arc = np.repeat(np.arange(len(start)), pieces)
    k = np.arange(len(arc)) - np.repeat(np.cumsum(pieces) - pieces, pieces)  # each piece's index in its arc
    step = ((end - start) / pieces)[arc]
    lo = k * step + start[arc]
    hi = np.where(k + 1 == pieces[arc], end[arc], (k + 1) * step + start[arc])  # the last cut is the arc's end
    return lo, hi, owner[arc]


class _Measure:
    """The intervals of arm angles of the poses decided from every checked pair's clearance at their middles and the
    speed bounds of the body's capsules (module docstring), one level in one compiled pass
    (:mod:`redkin.collision._arm_angle_kernels`); an interval's owner is ``pose * B + branch`` over the ``B``
    branches of ``signs``."""

    def __init__(self, arm: Arm, poses: np.ndarray, body: Body, scene: Scene, signs: np.ndarray,
                 geometry: SRSGeometry) -> None:
        self.arm, self.poses, self.body, self.scene = arm, poses, body, scene
        self.signs, self.geometry = np.array(signs, dtype=float), geometry
        self.signs.flags.writeable = False  # read-only as the IK's branch tables: one compile of its kernels
        self.elbow = np.where(signs[:, 1] > 0.0, 0, 1)  # the Table 1 elbow sign of each branch, as coefficients' row
        coefficients, _, _ = coefficient_arrays(geometry, poses[:, None], np.array([1.0, -1.0]))
        self.entries, self.theta4 = kernel_array(coefficients.entries), kernel_array(coefficients.theta4)  # (P, 2, ...)
        self.evaluations = np.zeros(len(poses), dtype=np.int64)  # per pose
        self.pairs = checked_pairs(body, scene)
        self.names, self.count = self.pairs.names, len(self.pairs.names)
        self.reach = np.full((len(poses), len(body)), np.nan)  # per pose and capsule: its distance from what it turns
        # about, read from the pose's first configuration measured (it is the same at every arm angle)
        self.line = np.full((len(poses), 6), np.nan)  # per pose: the shoulder centre and the unit direction to the
        # wrist centre, read with the reach
        self.inputs = clearance_inputs(body, scene, self.pairs)

    def __call__(self, middle: np.ndarray, half: np.ndarray, owner: np.ndarray, active: np.ndarray, finest: float,
                 carve: bool) -> tuple[np.ndarray, ...]:
        """The intervals of half widths ``half`` around arm angles ``middle`` of the owners ``owner`` decided from
        their active pairs' clearances ``active`` ``(N, P)`` (updated in place) and speed bounds, in one compiled
        pass (:func:`redkin.collision._arm_angle_kernels.level`): ``(kind, pair, down, up, carved, cause)``, each
        (N,)."""
        pose, branch = np.divmod(owner, len(self.signs))
        if len(self.body) and np.isnan(self.reach[pose, 0]).any():
            new, first = np.unique(pose, return_index=True)
            fresh = np.isnan(self.reach[new, 0])
            self._measure_reach(new[fresh], middle[first[fresh]], branch[first[fresh]])
        self.evaluations += np.bincount(pose, minlength=len(self.evaluations))
        count = len(middle)
        kind, pair, carved, cause = (np.empty(count, dtype=np.int64) for _ in range(4))
        down, up = np.empty(count), np.empty(count)
        chain = self.arm.chain
        run_batch(_arm_angle_kernels.level, count, kernel_array(middle), kernel_array(half), kernel_array(pose),
                  kernel_array(branch), self.entries, self.theta4, self.elbow, self.signs,
                  self.geometry.kernel_joints, chain._links, chain._ends, chain._standard, *self.inputs.body,
                  self.inputs.obstacles, *self.inputs.pairs, float(self.scene.margin), kernel_array(self.reach),
                  kernel_array(self.line), float(finest), bool(carve), active, kind, pair, down, up, carved, cause)
        return kind, pair, down, up, carved, cause

    def _measure_reach(self, poses: np.ndarray, middle: np.ndarray, branch: np.ndarray) -> None:
        """Each capsule's distance from what it turns about (:func:`_turning_reach`) at poses ``poses``, from the
        configuration of branch ``branch`` at arm angle ``middle`` of each."""
        q, _, _, _ = solve_with_status(self.geometry, self.poses[poses], middle, self.signs)
        frames = self.arm.chain.frames(q[np.arange(len(poses)), branch])
        self.reach[poses] = _turning_reach(self.arm.chain, self.body, frames, posed(self.body, frames))
        _, _, shoulder, wrist = _centres(self.arm.chain, frames)
        self.line[poses] = np.concatenate([shoulder, _unit(wrist - shoulder)], axis=-1)


def _turning_reach(chain: SerialChain, body: Body, frames: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Per configuration and capsule ``(N, M)``, the largest distance of the capsule's segment from what its frame
    turns about as the arm angle changes at the configuration's pose (module docstring): axis 1 (frame 1), the
    shoulder centre (frame 2), the shoulder-wrist line (frames 3 and 4), the wrist centre (frame 5) or axis 7
    (frame 6); 0 on frames 0 and 7, which do not move.  ``frames`` ``(N, n + 2, 4, 4)`` of :meth:`SerialChain.frames`
    and ``shapes`` ``(N, M, WIDTH)`` of :func:`redkin.collision.body.posed` at those frames.  Every capsule at once:
    a centre is a line of direction 0."""
    directions, points, shoulder, wrist = _centres(chain, frames)
    origins = np.stack([points[:, 0], points[:, 6], shoulder, wrist], axis=1)  # (N, 4, 3)
    lines = np.stack([directions[:, 0], directions[:, 6], _unit(wrist - shoulder), np.zeros_like(shoulder)], axis=1)
    frame = np.asarray(body.frame, dtype=np.int64)
    origin_of, line_of = _TURNING_ORIGIN[frame], _TURNING_LINE[frame]
    reach = _line_distance(capsule_ends(shapes), origins[:, origin_of, None], lines[:, line_of, None]).max(axis=-1)
    return np.where((frame >= 1) & (frame <= 6), reach, 0.0)


#: Per frame 0-7, what :func:`_turning_reach` measures its capsules from: the origin (axis 1's point, axis 7's, the
#: shoulder centre, the wrist centre) and the line through it (axis 1, axis 7, the shoulder-wrist line, none).
_TURNING_ORIGIN = np.array([0, 0, 2, 2, 2, 3, 1, 0])
_TURNING_LINE = np.array([3, 0, 3, 2, 2, 3, 1, 3])


def moved_pairs(arm: Arm, body: Body, scene: Scene, q: ArrayLike) -> np.ndarray:
    """Per configuration ``q`` ``(N, 7)`` of an S-R-S or offset-elbow arm and checked pair of ``body`` and ``scene``
    (:func:`redkin.collision.clearance.checked_pairs`), whether the pair's distance can change with the arm angle at
    the configuration's pose ``(N, P)``.  It cannot where both shapes stay where the pose puts them (the base, the
    tool's link, a ball at the shoulder or wrist centre, a capsule along axis 1 or 7: :func:`_turning_reach` at most
    :data:`_STILL`), or where one is on links 3-4, which turn rigidly about the shoulder-wrist line [000 eq. 12], and
    the other is on those links too or lies on that line (a ball at the wrist centre: the elbow's distance to it is
    fixed by the pose)."""
    chain = arm.chain
    q = chain.check_q(q).reshape(-1, chain.n)
    frames = chain.frames(q)
    shapes = posed(body, frames)
    _, _, shoulder, wrist = _centres(chain, frames)
    still = _turning_reach(chain, body, frames, shapes) <= _STILL  # (N, M)
    on_line = _line_distance(capsule_ends(shapes), shoulder[:, None, None],
                             _unit(wrist - shoulder)[:, None, None]).max(axis=-1) <= _STILL
    about_line = np.isin(body.frame, (3, 4))[None]
    pairs = checked_pairs(body, scene)
    other = np.maximum(pairs.other, 0)
    has_other = pairs.other >= 0  # else an obstacle: still, off the line (a pair with one moves unless the capsule
    # stays still)
    mine_still, mine_line, mine_about = still[:, pairs.capsule], on_line[:, pairs.capsule], about_line[:, pairs.capsule]
    fixed = mine_still & (~has_other | still[:, other])
    rigid = has_other & ((mine_about & (about_line[:, other] | on_line[:, other]))
                         | (about_line[:, other] & mine_line))
    return ~(fixed | rigid)


def _centres(chain: SerialChain, frames: np.ndarray) -> tuple[np.ndarray, ...]:
    """The joint axes ``(N, n, 3)`` (directions, points) of configurations' frames, and their shoulder and wrist
    centres ``(N, 3)``."""
    directions, points = chain.joint_axes_in(frames)
    shoulder = _meeting_point(points[:, 0], directions[:, 0], points[:, 1], directions[:, 1])
    wrist = _meeting_point(points[:, 5], directions[:, 5], points[:, 6], directions[:, 6])
    return directions, points, shoulder, wrist


def _unit(vectors: np.ndarray) -> np.ndarray:
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


def _meeting_point(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """The midpoint of the closest points of two lines ``(N, 3)`` each (their intersection on an S-R-S arm's shoulder
    or wrist)."""
    w = p1 - p2
    b = np.sum(u1 * u2, axis=-1, keepdims=True)
    u2w, u1w = np.sum(u2 * w, axis=-1, keepdims=True), np.sum(u1 * w, axis=-1, keepdims=True)
    denominator = 1.0 - b * b
    s = (b * u2w - u1w) / denominator
    t = (u2w - b * u1w) / denominator
    return (p1 + s * u1 + p2 + t * u2) / 2.0


def _line_distance(points: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Distances of ``points`` ``(..., 3)`` from the lines through ``origin`` along the unit ``direction`` (each
    ``(..., 3)``, broadcast against them; a direction 0 gives the distance from ``origin``)."""
    offset = points - origin
    along = np.sum(offset * direction, axis=-1, keepdims=True)
    return np.linalg.norm(offset - along * direction, axis=-1)


def arcs_of(arcs: ArcSet) -> Arcs:
    """A set of arm angles as disjoint, merged arcs (``start > end`` through ``+-pi``)."""
    bounds = np.array(arcs.arcs, dtype=float).reshape(-1, 2)
    return Arcs(bounds, bounds[:, 0] > bounds[:, 1])


def _wrapped(angle: float) -> float:
    return float((angle + np.pi) % TWO_PI - np.pi)


class Decided(NamedTuple):
    """The intervals :func:`certify` decided (``kind`` 0 free, 1 blocked by ``pair``, 2 undecided), sorted by owner
    and start: disjoint within an owner, so each one's end is at most the next one's start."""

    lo: np.ndarray
    hi: np.ndarray
    owner: np.ndarray
    kind: np.ndarray
    pair: np.ndarray

    @classmethod
    def of(cls, parts: tuple[np.ndarray, ...]) -> Decided:
        """:func:`certify`'s ``(lo, hi, owner, kind, pair)``, sorted."""
        order = np.lexsort((parts[0], parts[2]))
        return cls(*(part[order] for part in parts))

    def _runs(self, which: np.ndarray, cause: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The first and last of each run of the intervals ``which`` that touch, of one owner and one ``cause``."""
        owner, lo, hi = self.owner[which], self.lo[which], self.hi[which]
        first = np.ones(len(lo), dtype=bool)
        first[1:] = (owner[1:] != owner[:-1]) | (cause[1:] != cause[:-1]) | (lo[1:] > hi[:-1])
        starts = np.flatnonzero(first)
        return starts, (np.append(starts[1:] - 1, len(lo) - 1) if len(lo) else starts)

    def free_runs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The free intervals merged where they touch, as ``(start, end, owner)`` sorted by owner and start."""
        clear = np.flatnonzero(self.kind == 0)
        starts, ends = self._runs(clear, np.zeros(len(clear), dtype=np.int64))
        return self.lo[clear][starts], self.hi[clear][ends], self.owner[clear][starts]

    def stretches(self, owners: int, names: list[tuple[str, str]],
                  wrapped: Callable[[float], float]) -> list[list[Stretch]]:
        """Per owner, its blocked and undecided intervals merged into stretches of one cause (touching intervals
        blocked by pairs of the same names, such as two capsules of one link against one obstacle, or undecided),
        each end written by ``wrapped`` (into ``[-pi, pi)`` for an arm angle; a run around the whole circle as
        ``(-pi, pi)``, which wrapping would write as a point)."""
        removed = np.flatnonzero(self.kind != 0)
        kind, which = self.kind[removed], self.pair[removed]
        named = {pair: k for k, pair in enumerate(dict.fromkeys(names))}  # pairs of shapes named alike are one cause
        same_name = np.array([named[pair] for pair in names], dtype=np.int64)
        cause = np.where(kind == 1, same_name[which] if len(names) else -1, -1)  # the names that block, or -1
        starts, ends = self._runs(removed, cause)
        stretches: list[list[Stretch]] = [[] for _ in range(owners)]
        for owner, start, end, blocked, pair in zip(
                self.owner[removed][starts].tolist(), self.lo[removed][starts].tolist(),
                self.hi[removed][ends].tolist(), (kind[starts] == 1).tolist(), which[starts].tolist(), strict=True):
            reason, (link, against) = (COLLISION, names[pair]) if blocked else (UNDECIDED, ("", ""))
            whole = end - start >= TWO_PI  # written (-pi, pi): wrapped, its ends would be one point
            stretches[owner].append(Stretch(-np.pi if whole else wrapped(start), np.pi if whole else wrapped(end),
                                            reason, link, against))
        return stretches


def circle_limit_stretches(arm: Arm, pose: np.ndarray, labels: tuple[str, ...],
                           limits: tuple[Arcs, ...]) -> list[list[Stretch]]:
    """Per branch, the stretches of the circle between its limit-feasible arcs of arm angles, named by their
    causes."""
    return _circle_limit_stretches_of(arm, pose[None], labels, [limits])[0]


def _circle_limit_stretches_of(arm: Arm, poses: np.ndarray, labels: tuple[str, ...],
                              limits: list[tuple[Arcs, ...]]) -> list[list[list[Stretch]]]:
    """:func:`circle_limit_stretches` of each pose of ``poses`` (P, 4, 4), its arcs ``limits[p]``."""
    gaps = [[ArcSet(arcs.bounds.tolist()).complement().arcs for arcs in pose_limits] for pose_limits in limits]
    middles = [[_wrapped(start + arc_length(start, end) / 2.0) for arcs in pose_gaps for start, end in arcs]
               for pose_gaps in gaps]
    return limit_stretches_of(arm, poses, labels, gaps, middles)


def limit_stretches_of(arm: Arm, poses: np.ndarray, labels: tuple[str, ...], gaps: list[list],
                       middles: list[list[float]]) -> list[list[list[Stretch]]]:
    """Per pose of ``poses`` (P, 4, 4) and branch, the stretches ``gaps[p]`` (per branch, ``(start, end)`` each)
    removed by the joint limits, each named by the joints out of range at its middle (``middles[p]``, in the order
    of the pose's stretches; "no solution" where the branch has none there), all solved in one batch."""
    stretches: list[list[list[Stretch]]] = [[[] for _ in labels] for _ in poses]
    where = [(p, b) for p, pose_gaps in enumerate(gaps) for b, spans in enumerate(pose_gaps) for _ in spans]
    if not where:
        return stretches
    pose, owner = np.array(where, dtype=np.int64).T
    solutions = arm.ik(poses[pose], np.array([m for pose_middles in middles for m in pose_middles]), branches=labels)
    rows = np.arange(len(owner))
    q, exists = solutions.q[rows, owner], solutions.exists[rows, owner]
    inside = arm.chain.joints_within_limits(q, wrap=True)
    spans = [span for pose_gaps in gaps for branch_spans in pose_gaps for span in branch_spans]
    for (start, end), (p, b), there, within in zip(spans, where, exists.tolist(), inside, strict=True):
        out = ", ".join(f"joint {joint + 1}" for joint in np.flatnonzero(~within)) if there else "no solution"
        stretches[p][b].append(Stretch(start, end, LIMIT, "", out))
    return stretches
