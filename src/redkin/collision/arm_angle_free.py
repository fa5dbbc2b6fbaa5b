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

The joint rates are bounded over the interval from [000 eqs. 13-14, 18-19]: each entry ``e(psi) = a sin psi + b cos
psi + c`` of ``0R3`` and ``4R7`` [000 eqs. 12, 16] and its derivative move by at most ``hypot(a, b) h`` from their
values at ``m``, and ``theta_1 = atan2(y, x)``, ``theta_2 = acos z`` (with ``x^2 + y^2 = 1 - z^2``) give
``|theta_1'| <= (|x| |y'| + |y| |x'|) / (x^2 + y^2)`` and ``|theta_2'| <= |z'| / sqrt(1 - z^2)``, each factor replaced
by its bound over the interval (the denominator by the larger of its two lower bounds, from ``|z|`` and from ``|x|,
|y|``); the same for ``theta_6, theta_7`` (``theta_7 = atan2(t, -r_2)``, ``t^2 + r_2^2 = 1 - z^2``).  These
bounds grow without limit near a singular arm angle [000 eqs. 31-34], where the branch's shoulder or wrist turns half
a turn.

An interval is **free** where every pair's ``c(m) - v h > 0``, **blocked** by a pair where ``c(m) + v h < 0`` (that
pair is its cause), and otherwise cut around its middle: since ``v`` bounds the speeds over the whole interval,
``c(psi) >= c(m) - v |psi - m|`` on it, so ``[m - r, m + r]`` is free with ``r`` the least ``c(m) / v`` of the pairs
still open where all are positive, and blocked by the pair of the largest ``-c(m) / v`` where one is negative (each
radius a hair smaller, for rounding); the pieces on either side (the halves, where ``r`` is 0) are decided in turn.
Near an end of a free arc this takes about half the evaluations of halving alone.  An interval no wider than half
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
from redkin.arms.feasible_sets import Arcs, merged_intervals
from redkin.arms.front_door import Arm
from redkin.arms.srs_kind import SRSKind
from redkin.chain import SerialChain
from redkin.circle import TWO_PI, ArcSet
from redkin.collision import _arm_angle_kernels
from redkin.collision.body import Body, capsule_ends, posed
from redkin.collision.clearance import checked_pairs, clearance_inputs
from redkin.collision.scene import Scene
from redkin.errors import RedkinError
from redkin.srs.coefficients import coefficient_arrays
from redkin.srs.geometry import SRSGeometry
from redkin.srs.ik import solve_with_status

#: The widest interval a limit-feasible arc is cut into before the first evaluation [rad].
_FIRST_WIDTH = 0.25
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
    margin).  A stretch through ``+-pi`` has ``start > end``.
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
        Per branch, every stretch removed from the circle, with its cause, in order of ``start``.
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
        For an arm of another class (named), a body on another number of joints, a malformed pose or a resolution
        that is not > 0; :class:`redkin.errors.UnreachablePoseError` for a pose out of reach.
    """
    return free_arm_angles_of(arm, one_pose(pose), body, scene, branches, resolution=resolution, budget=budget)[0]


def free_arm_angles_of(arm: Arm, poses: ArrayLike, body: Body, scene: Scene,
                       branches: str | tuple[str, ...] | list[str] | None = None, *, resolution: float = 1e-6,
                       budget: int = 100_000) -> list[FreeArmAngles]:
    """:func:`collision_free_arm_angles` of each pose of ``poses`` ``(P, 4, 4)``, decided together: the intervals
    of every pose and branch are halved in one batch, so the work per level is shared (``budget`` per pose)."""
    if not isinstance(arm.implementation, SRSKind):
        elsewhere = ("its q7 sets are redkin.collision.collision_free_q7's" if arm.parameter is not None
                     and arm.parameter.name == "q7" else "redkin.collision.free_sets_of takes every class")
        raise RedkinError(f"certified collision-free arm angles are computed on S-R-S and offset-elbow arms; "
                          f"{arm.chain.name} is {arm.kind} ({elsewhere})")
    poses = checked_inputs(arm, poses, body, resolution)
    limits = arm.feasible(poses, branches)
    geometry = arm.implementation.geometry
    labels = limits.branches
    count = len(labels)
    rows = np.array([arm.branches.index(label) for label in labels])
    limit_arcs = [tuple(limits.arcs(label, p) for label in labels) for p in range(len(poses))]
    measure = _Measure(arm, poses, body, scene, geometry.kernel_branches[rows], geometry)
    parts, complete = certify(first_intervals([arcs for pose_arcs in limit_arcs for arcs in pose_arcs]), count,
                              len(poses), resolution, measure, measure.speeds, budget, carve=True)
    results = []
    owned = by_owner(parts, len(poses) * count)
    for p, pose in enumerate(poses):
        free_sets, blocked = [], []
        at_limits = circle_limit_stretches(arm, pose, labels, limit_arcs[p])
        for b in range(count):
            lo, hi, kind, which = owned(p * count + b)
            clear = kind == 0
            free_sets.append(arcs_of(ArcSet(merged_intervals(lo[clear], hi[clear]).bounds.tolist())))
            stretches = collision_stretches(lo, hi, kind, which, measure.names, _wrapped)
            stretches += at_limits[b]
            blocked.append(tuple(sorted(stretches, key=lambda stretch: stretch.start)))
        results.append(FreeArmAngles(labels, tuple(free_sets), limit_arcs[p], tuple(blocked), float(resolution),
                                     int(measure.evaluations[p]), bool(complete[p])))
    return results


class _PairMeasure(Protocol):
    """What :func:`certify` measures with: the checked pairs' clearances at values of the parameter."""

    evaluations: np.ndarray  # configurations posed so far, per pose
    count: int  # checked pairs

    def __call__(self, middle: np.ndarray, owner: np.ndarray, active: np.ndarray) -> np.ndarray: ...


def one_pose(pose: ArrayLike) -> np.ndarray:
    """One pose ``(4, 4)``, checked, as a batch of one ``(1, 4, 4)`` (the one-pose forms of the free sets).

    Raises
    ------
    RedkinError
        For a malformed pose or another shape.
    """
    checked = check_pose(pose)
    if checked.shape != (4, 4):
        raise RedkinError(f"pose must be one 4x4 transform, got shape {checked.shape}")
    return checked[None]


def checked_inputs(arm: Arm, poses: ArrayLike, body: Body, resolution: float) -> np.ndarray:
    """The poses ``(P, 4, 4)`` of a batch of free sets, checked with the body and the resolution.

    Raises
    ------
    RedkinError
        For a body on another number of joints, a resolution that is not > 0 or malformed poses.
    """
    if len(body) and int(body.frame.max()) > arm.chain.n:
        raise RedkinError(f"the body uses frame {int(body.frame.max())}, but {arm.chain.name} has {arm.chain.n} joints")
    if not (np.isfinite(resolution) and resolution > 0.0):
        raise RedkinError(f"resolution must be a number > 0 (radians), got {resolution!r}")
    checked = check_pose(poses)
    if checked.ndim != 3:
        raise RedkinError(f"poses must have shape (P, 4, 4), got shape {checked.shape}")
    return checked


def certify(intervals: tuple[np.ndarray, np.ndarray, np.ndarray], count: int, poses: int, resolution: float,
            measure: _PairMeasure, rates: Callable, budget: int, *, carve: bool = False
            ) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Decide the intervals ``(lo, hi, owner)`` (an owner is ``pose * count + branch``) as free, blocked or undecided to
    ``resolution`` (module docstring), then decide further each run of undecided intervals wider than it, and each
    sliver between two intervals of one kind (:func:`_undecided_runs`); ``measure(middle, owner, active)`` gives the
    pairs' clearances, ``rates(owner, middle, half)`` bounds how fast each pair's clearance changes over the interval
    (with ``carve``, a bound of its derivative there: then each evaluation also decides the stretch around the middle
    its own clearances prove, :func:`_decide`). Returns the decided intervals ``(lo, hi, owner, kind, pair)`` and per
    pose whether it was decided completely (the budget, ``budget`` evaluations per pose, sufficed and no undecided
    run is wider than the resolution)."""
    parts, undone = _decide(*intervals, resolution / 2.0, measure, rates, budget * poses, carve)
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
        again, undone = _decide(parts[0][wide], parts[1][wide], parts[2][wide], finest, measure, rates,
                                budget * poses, carve)
        complete[undone // count] = False
        open_owners = np.isin(parts[2], parts[2][wide])  # the others' intervals do not change any more
        settled.append(tuple(part[~open_owners] for part in parts))
        parts = tuple(np.concatenate([part[open_owners & ~wide], more]) for part, more in zip(parts, again,
                                                                                              strict=True))
        finest /= 2.0
    return tuple(np.concatenate(column) for column in zip(*settled, parts, strict=True)), complete


def _decide(lo: np.ndarray, hi: np.ndarray, owner: np.ndarray, finest: float, measure: _PairMeasure, rates: Callable,
            budget: int, carve: bool) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Halve the intervals ``[lo, hi]`` of the branches ``owner`` until each is free, blocked, or undecided and no
    wider than ``finest`` (module docstring); ``rates(owner, middle, half)`` bounds each pair's speed.

    With ``carve`` (the rates bound each clearance's derivative over the interval: ``|c(psi) - c(m)| <= v |psi -
    m|``), an interval left open is not halved but cut around its middle ``m``: where every open pair's clearance
    is positive, ``[m - r, m + r]`` with ``r`` the least ``c / v`` of them is free; where one is negative, the
    largest ``-c / v`` gives a stretch it blocks; the two pieces beside it stay open (halves where ``r`` is 0).

    Returns ``(lo, hi, owner, kind, pair)`` of the decided intervals (kind 0 free, 1 blocked by ``pair``, 2
    undecided), and the owners of the intervals still open when the budget ran out (left undecided).
    """
    decided: list[tuple[np.ndarray, ...]] = [(lo[:0], hi[:0], owner[:0], owner[:0], owner[:0])]
    active = np.ones((len(lo), measure.count), dtype=bool)  # the pairs not yet proved clear on each interval
    while len(lo):
        if measure.evaluations.sum() + len(lo) > budget:
            decided.append((lo, hi, owner, np.full(len(lo), 2), np.zeros(len(lo), dtype=np.int64)))
            break
        middle, half = (lo + hi) / 2.0, (hi - lo) / 2.0
        clearance = measure(middle, owner, active)
        speed = rates(owner, middle, half)
        with np.errstate(invalid="ignore"):  # inf - inf: a pair already clear, at an unbounded speed
            low = np.where(active, clearance - speed * half[:, None], np.inf)
            high = np.where(active, clearance + speed * half[:, None], np.inf)
        active &= ~(low > 0.0)
        free = ~active.any(axis=1)
        blocked = ~free & np.any(high < 0.0, axis=1)
        small = ~free & ~blocked & (2.0 * half <= finest)
        kind = np.where(free, 0, np.where(blocked, 1, 2))
        which = np.argmin(high, axis=1) if high.shape[1] else np.zeros(len(lo), np.int64)
        done = free | blocked | small
        decided.append((lo[done], hi[done], owner[done], kind[done], which[done]))
        split = ~done
        lo, hi, owner, middle, active = lo[split], hi[split], owner[split], middle[split], active[split]
        cut = np.zeros(len(lo))
        if carve and len(lo):
            cut, cause, kind = _carved(clearance[split], speed[split], active, half[split])
            kept = cut > 0.0
            decided.append((middle[kept] - cut[kept], middle[kept] + cut[kept], owner[kept], kind[kept], cause[kept]))
        left, right = middle - cut > lo, middle + cut < hi  # the open pieces beside the middle (or its stretch)
        lo, hi, owner = (np.concatenate([lo[left], (middle + cut)[right]]),
                         np.concatenate([(middle - cut)[left], hi[right]]),
                         np.concatenate([owner[left], owner[right]]))
        active = np.concatenate([active[left], active[right]])
    parts = tuple(np.concatenate(column) for column in zip(*decided, strict=True))
    return parts, owner


#: Slivers left undecided between two intervals of one kind (:func:`_undecided_runs`) are cut down to this fraction
#: of the resolution, then left undecided (no end of the free set need lie there).
_INNER_FLOOR = 1e-3
#: The radius of a carved stretch is this much less than its clearance over its speed bound (rounding of the
#: division; :func:`_carved`).
_CARVE_SHRINK = 1.0 - 1e-9


def _carved(clearance: np.ndarray, speed: np.ndarray, active: np.ndarray, half: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per open interval (its clearances and speed bounds ``(N, P)`` at the middle, its open pairs, its half width),
    the radius of the stretch around the middle that the clearances decide (:func:`_decide`; 0 where none), the
    pair that blocks it, and its kind (0 free, 1 blocked)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        reach = np.nan_to_num(np.where(active, clearance / speed, np.inf), nan=0.0, posinf=np.inf, neginf=-np.inf)
    clear = np.minimum(np.maximum(reach.min(axis=1), 0.0), half)  # every open pair positive out to here
    cause = np.argmin(reach, axis=1)  # the most negative pair
    blocking = np.minimum(np.maximum(-reach[np.arange(len(reach)), cause], 0.0), half)
    kind = np.where(clear > 0.0, 0, 1)
    return np.where(clear > 0.0, clear, blocking) * _CARVE_SHRINK, cause, kind


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


def first_intervals(arcs: list[Arcs]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each owner's limit-feasible arcs (a pose's branch) cut into intervals no wider than :data:`_FIRST_WIDTH`,
    unrolled so that ``lo < hi`` (an arc through the seam ends beyond pi)."""
    lo: list[float] = []
    hi: list[float] = []
    owner: list[int] = []
    for b, arc in enumerate(arcs):
        for (start, end), wraps in zip(arc.bounds.tolist(), arc.wraps.tolist(), strict=True):
            end = end + TWO_PI if wraps else end
            cuts = np.linspace(start, end, max(1, int(np.ceil((end - start) / _FIRST_WIDTH))) + 1)
            lo.extend(cuts[:-1])
            hi.extend(cuts[1:])
            owner.extend([b] * (len(cuts) - 1))
    return np.array(lo, dtype=float), np.array(hi, dtype=float), np.array(owner, dtype=np.int64)


class _Measure:
    """The clearances of every checked pair at arm angles of the poses, and the speed bounds of the body's capsules
    (module docstring), each in one compiled pass (:mod:`redkin.collision._arm_angle_kernels`); an interval's owner
    is ``pose * B + branch`` over the ``B`` branches of ``signs``."""

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
        self.inputs = clearance_inputs(body, scene, self.pairs)

    def __call__(self, middle: np.ndarray, owner: np.ndarray, active: np.ndarray) -> np.ndarray:
        """Clearances ``(N, P)`` (distance minus margin) at arm angles ``middle`` of the owners ``owner``, of the
        pairs ``active`` ``(N, P)`` (``inf`` for the others: already proved clear on a wider interval)."""
        pose, branch = np.divmod(owner, len(self.signs))
        new, first = np.unique(pose, return_index=True)
        fresh = np.isnan(self.reach[new, 0]) if len(self.body) else np.zeros(len(new), dtype=bool)
        if fresh.any():
            self._measure_reach(new[fresh], middle[first[fresh]], branch[first[fresh]])
        np.add.at(self.evaluations, pose, 1)
        clearance = np.empty(active.shape)
        chain = self.arm.chain
        run_batch(_arm_angle_kernels.clearances, len(middle), kernel_array(middle), kernel_array(pose),
                  kernel_array(branch), self.entries, self.theta4, self.elbow, self.signs,
                  self.geometry.kernel_joints, chain._links, chain._ends, chain._standard, *self.inputs.body,
                  self.inputs.obstacles, *self.inputs.pairs, float(self.scene.margin), kernel_array(active),
                  clearance)
        return clearance

    def _measure_reach(self, poses: np.ndarray, middle: np.ndarray, branch: np.ndarray) -> None:
        """Each capsule's distance from what it turns about (:func:`_turning_reach`) at poses ``poses``, from the
        configuration of branch ``branch`` at arm angle ``middle`` of each."""
        q, _, _, _ = solve_with_status(self.geometry, self.poses[poses], middle, self.signs)
        frames = self.arm.chain.frames(q[np.arange(len(poses)), branch])
        self.reach[poses] = _turning_reach(self.arm.chain, self.body, frames, posed(self.body, frames))

    def speeds(self, owner: np.ndarray, middle: np.ndarray, half: np.ndarray) -> np.ndarray:
        """Per interval and pair ``(N, P)``, a bound of how fast the pair's distance changes per radian of psi over
        ``[middle - half, middle + half]`` (:func:`redkin.collision._arm_angle_kernels.speeds`)."""
        pose, branch = np.divmod(owner, len(self.signs))
        out = np.empty((len(middle), self.count))
        run_batch(_arm_angle_kernels.speeds, len(middle), kernel_array(middle), kernel_array(half),
                  kernel_array(pose), kernel_array(branch), self.entries, self.elbow, self.inputs.body[0],
                  kernel_array(self.reach), self.inputs.pairs[0], self.inputs.pairs[2], out)
        return out


def _turning_reach(chain: SerialChain, body: Body, frames: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """Per configuration and capsule ``(N, M)``, the largest distance of the capsule's segment from what its frame
    turns about as the arm angle changes at the configuration's pose (module docstring): axis 1 (frame 1), the
    shoulder centre (frame 2), the shoulder-wrist line (frames 3 and 4), the wrist centre (frame 5) or axis 7
    (frame 6); 0 on frames 0 and 7, which do not move.  ``frames`` ``(N, n + 2, 4, 4)`` of :meth:`SerialChain.frames`
    and ``shapes`` ``(N, M, WIDTH)`` of :func:`redkin.collision.body.posed` at those frames."""
    directions, points, shoulder, wrist = _centres(chain, frames)
    ends = capsule_ends(shapes)
    reach = np.zeros(shapes.shape[:2])
    for index, frame in enumerate(body.frame.tolist()):
        if frame in (1, 6):
            axis = 0 if frame == 1 else 6
            reach[:, index] = _line_distance(ends[:, index], points[:, axis], directions[:, axis]).max(axis=-1)
        elif frame in (3, 4):
            reach[:, index] = _line_distance(ends[:, index], shoulder, _unit(wrist - shoulder)).max(axis=-1)
        elif frame in (2, 5):
            centre = shoulder if frame == 2 else wrist
            reach[:, index] = np.linalg.norm(ends[:, index] - centre[:, None], axis=-1).max(axis=-1)
    return reach


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
    on_line = _line_distance(capsule_ends(shapes).reshape(len(q), -1, 3), shoulder, _unit(wrist - shoulder)).reshape(
        len(q), len(body), 2).max(axis=-1) <= _STILL
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
    """Distances of ``points`` ``(N, K, 3)`` from the lines through ``origin`` along ``direction`` ``(N, 3)``."""
    offset = points - origin[:, None]
    along = np.sum(offset * direction[:, None], axis=-1, keepdims=True)
    return np.linalg.norm(offset - along * direction[:, None], axis=-1)


def arcs_of(arcs: ArcSet) -> Arcs:
    """A set of arm angles as disjoint, merged arcs (``start > end`` through ``+-pi``)."""
    bounds = np.array(arcs.arcs, dtype=float).reshape(-1, 2)
    return Arcs(bounds, bounds[:, 0] > bounds[:, 1])


def _wrapped(angle: float) -> float:
    return float((angle + np.pi) % TWO_PI - np.pi)


def by_owner(parts: tuple[np.ndarray, ...], owners: int) -> Callable[[int], tuple[np.ndarray, ...]]:
    """The decided intervals ``(lo, hi, owner, kind, pair)`` of :func:`certify` sorted once by owner and start: a
    function giving one owner's ``(lo, hi, kind, pair)``, sorted by ``lo``."""
    order = np.lexsort((parts[0], parts[2]))
    lo, hi, owner, kind, pair = (part[order] for part in parts)
    edges = np.searchsorted(owner, np.arange(owners + 1))

    def of(which: int) -> tuple[np.ndarray, ...]:
        mine = slice(edges[which], edges[which + 1])
        return lo[mine], hi[mine], kind[mine], pair[mine]

    return of


def collision_stretches(lo: np.ndarray, hi: np.ndarray, kind: np.ndarray, which: np.ndarray,
                        names: list[tuple[str, str]], wrapped: Callable[[float], float]) -> list[Stretch]:
    """The blocked and undecided intervals of one branch (its decided intervals, disjoint) merged into stretches of
    one cause (touching intervals blocked by pairs of the same names, such as two capsules of one link against one
    obstacle, or undecided), each end written by ``wrapped`` (into ``[-pi, pi)`` for an arm angle)."""
    removed = kind != 0
    order = np.argsort(lo[removed], kind="stable")
    lo, hi, kind, which = lo[removed][order], hi[removed][order], kind[removed][order], which[removed][order]
    named = {pair: k for k, pair in enumerate(dict.fromkeys(names))}  # pairs of shapes named alike are one cause
    same_name = np.array([named[pair] for pair in names], dtype=np.int64)
    cause = np.where(kind == 1, same_name[which] if len(names) else -1, -1)  # the names that block, or -1: undecided
    first = np.ones(len(lo), dtype=bool)
    first[1:] = (cause[1:] != cause[:-1]) | (lo[1:] > hi[:-1])
    starts = np.flatnonzero(first)
    ends = np.append(starts[1:] - 1, len(lo) - 1) if len(lo) else starts  # each run's last interval
    stretches = []
    for start, end, first_of in zip(lo[starts].tolist(), hi[ends].tolist(), starts.tolist(), strict=True):
        reason, (link, against) = (COLLISION, names[which[first_of]]) if kind[first_of] == 1 else (UNDECIDED, ("", ""))
        stretches.append(Stretch(wrapped(start), wrapped(end), reason, link, against))
    return stretches


def circle_limit_stretches(arm: Arm, pose: np.ndarray, labels: tuple[str, ...],
                           limits: tuple[Arcs, ...]) -> list[list[Stretch]]:
    """Per branch, the stretches of the circle between its limit-feasible arcs of arm angles, named by their
    causes."""
    gaps = [ArcSet(arcs.bounds.tolist()).complement().arcs for arcs in limits]
    middles = [_wrapped(start + ((end - start) % TWO_PI) / 2.0) for arcs in gaps for start, end in arcs]
    return limit_stretches(arm, pose, labels, gaps, middles)


def limit_stretches(arm: Arm, pose: np.ndarray, labels: tuple[str, ...], gaps: list, middles: list[float]
                    ) -> list[list[Stretch]]:
    """Per branch, the stretches ``gaps`` (per branch, ``(start, end)`` each) removed by the joint limits, each named
    by the joints out of range at its middle (``middles``, in the order of the stretches; "no solution" where the
    branch has none there)."""
    owner = np.array([b for b, spans in enumerate(gaps) for _ in spans], dtype=np.int64)
    stretches: list[list[Stretch]] = [[] for _ in labels]
    if not len(middles):
        return stretches
    solutions = arm.ik(pose, np.array(middles), branches=labels)
    q, exists = solutions.q[np.arange(len(owner)), owner], solutions.exists[np.arange(len(owner)), owner]
    inside = arm.chain.joints_within_limits(q, wrap=True)
    spans = [span for branch_spans in gaps for span in branch_spans]
    for (start, end), b, there, within in zip(spans, owner.tolist(), exists.tolist(), inside, strict=True):
        out = ", ".join(f"joint {joint + 1}" for joint in np.flatnonzero(~within)) if there else "no solution"
        stretches[b].append(Stretch(start, end, LIMIT, "", out))
    return stretches
