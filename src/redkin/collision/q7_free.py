"""Certified collision-free values of q7 of Franka-class arms (issue 40, item 4; docs/collisions.md, "The Franka
class").

For one pose and each branch, the values of q7 at which the branch's solution [F1]-[F7] lies within the joint limits
[F8]-[F9] *and* every checked pair of shapes (each capsule of the arm's body against each obstacle, and the body's
self-collision pairs) is at least the scene's margin apart: the Franka class's counterpart of
:func:`redkin.collision.collision_free_arm_angles`, decided by the same subdivision
(:func:`redkin.collision.arm_angle_free.certify`), with another bound of how far the shapes move.

What is proved.  On an interval ``I = [m - h, m + h]`` inside one of the branch's limit-feasible arcs (where the
branch exists and turns continuously), let ``delta_j`` bound ``|q_j(t) - q_j(m)|`` over ``I`` for each joint
(``delta_7 = h``).  Each pair's signed distance then changes over ``I`` by at most the bound of
:mod:`redkin.collision.joint_motion` (levers along the joints' axes, from the base or from the tool, which the pose
holds still), and where that leaves the pair undecided, by at most the same module's bound along the pair's normal
at ``m`` (towards the margin: down where the pair is clear of it, up where not), so ``c(t) - c(m)`` is bounded over
``I``, and the interval is free, blocked or halved as :mod:`redkin.collision.arm_angle_free` says.

The bounds ``delta_j`` are proposed from the joints' values at ``m`` and at the ends of ``I`` widened by the level
test's slack (at the ends of ``I`` themselves where the slack reaches past an end of the branch's existence, which
ends many limit-feasible arcs; one and a half times the larger change, a little more) and then proved: with the
levels ``q_j(m) -+ delta_j`` in place of the limits, no level polynomial of [F8] has a root in ``I``
(:func:`redkin.franka._kernels.levels_crossed`, the isolation the exact feasible sets use), so no joint of any of
the four conjugate solutions reaches its levels in ``I``, and each joint of the branch stays strictly between them.
Where a level is crossed, the branch does not exist at the middle or an end, or a bound reaches a quarter turn, the
interval's bound is infinite and it is halved. The proof is spent only where the proposed bounds would decide
something (settle the interval, or prove a pair clear on it): elsewhere the interval is halved with its pairs as
they were whether the bounds hold or not (on the benchmark's Panda pose in a cell, before the bounds along the
normals, 3087 of 5568 intervals).
Below the slack (1e-9 rad) the bounds no longer shrink with the interval (about ``1.5 |dq_j/dq7|`` times the
slack), so an end of a free interval is located to the resolution only where the clearance changes fast enough
against the shapes' speeds; where it grazes the margin the stretch stays undecided (twice the slack proposed, as
before, left 1.3e-6 rad undecided at an FR3 pose after the whole budget).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import run_batch
from redkin.arms.feasible_sets import Arcs
from redkin.arms.franka_kind import FrankaKind
from redkin.arms.front_door import Arm
from redkin.circle import TWO_PI
from redkin.collision.arm_angle_free import (
    Certified,
    Decided,
    FreeArmAngles,
    Stretch,
    certify,
    checked_inputs,
    first_intervals,
    limit_stretches_of,
    merged_stretches,
    one_pose,
    settled,
)
from redkin.collision.body import Body
from redkin.collision.clearance import checked_pairs, clearance_inputs, pair_clearances
from redkin.collision.joint_motion import pair_displacements, pair_levers, tightened
from redkin.collision.scene import Scene
from redkin.errors import RedkinError
from redkin.franka import _kernels
from redkin.franka.feasible import q7_domain
from redkin.franka.geometry import FrankaGeometry
from redkin.franka.ik import frames_seven

#: The widest interval a limit-feasible q7 arc is cut into before the first evaluation [rad]: the intervals are
#: halved (the joints' displacement bounds prove nothing wide), so the first ones are narrow.
_FIRST_WIDTH = 0.25
#: A joint's proposed bound is this many times its larger change from the middle to an end of the interval (widened
#: by the level test's slack).
_PROPOSAL = 1.5
#: Added to each proposed bound [rad], so that a joint that does not move at the interval's ends still has room.
_ROOM = 1e-12
#: The largest bound proved by levels: beyond a quarter turn a level and its opposite (``L + pi``, which the level
#: polynomials share) would both lie within reach.
_WIDEST = np.pi / 2.0


def collision_free_q7(arm: Arm, pose: ArrayLike, body: Body, scene: Scene,
                      branches: str | tuple[str, ...] | list[str] | None = None, *,
                      resolution: float = 1e-6, budget: int = 100_000) -> FreeArmAngles:
    """The certified collision-free values of q7 of one pose on each branch of a Franka-class arm (module docstring).

    ``arm`` is a Franka-class arm (:func:`redkin.arm`); ``pose``, ``body``, ``scene``, ``branches``, ``resolution``
    and ``budget`` are those of :func:`redkin.collision.collision_free_arm_angles`.  Returns its
    :class:`~redkin.collision.FreeArmAngles` with ``parameter`` ``"q7"``, whose intervals never wrap.

    Raises
    ------
    RedkinError
        For an arm of another class (named), a body on another number of joints, a malformed pose, a resolution
        that is not > 0 or a budget that is not an integer >= 1; :class:`redkin.errors.UnreachablePoseError` for a
        pose out of reach.
    """
    return free_q7_of(arm, one_pose(arm, pose), body, scene, branches, resolution=resolution, budget=budget)[0]


def free_q7_of(arm: Arm, poses: ArrayLike, body: Body, scene: Scene,
               branches: str | tuple[str, ...] | list[str] | None = None, *, resolution: float = 1e-6,
               budget: int = 100_000, causes: bool = True) -> list[FreeArmAngles]:
    """:func:`collision_free_q7` of each pose of ``poses`` ``(P, 4, 4)``, decided together (``budget`` per pose);
    without ``causes`` the removed stretches are neither named nor solved for (``blocked`` empty)."""
    poses, certified = certified_q7(arm, poses, body, scene, branches, resolution=resolution, budget=budget)
    assert isinstance(arm.implementation, FrankaKind)  # certified_q7 refuses any other class
    limits = certified.limits_per_pose()
    domain = q7_domain(arm.implementation.geometry)
    blocked = merged_stretches(certified.decided.stretches(certified.owners, certified.names, float),
                               _limit_stretches(arm, poses, certified.labels, limits, domain), len(certified.labels)) \
        if causes else certified.no_causes()
    return certified.results(limits, blocked, resolution, "q7")


def certified_q7(arm: Arm, poses: ArrayLike, body: Body, scene: Scene,
                 branches: str | tuple[str, ...] | list[str] | None = None, *, resolution: float = 1e-6,
                 budget: int = 100_000) -> tuple[np.ndarray, Certified]:
    """:func:`free_q7_of`'s decision, before it is read per pose: the poses checked ``(P, 4, 4)`` and what
    :func:`redkin.collision.arm_angle_free.certify` decided."""
    if not isinstance(arm.implementation, FrankaKind):
        raise RedkinError(f"certified collision-free q7 sets are computed on Franka-class arms; {arm.chain.name} is "
                          f"{arm.kind}")
    poses = checked_inputs(arm, poses, body, resolution, budget)
    limits = arm.feasible(poses, branches)
    limit_arcs = limits.arc_arrays()
    measure = _Q7Measure(arm, poses, body, scene, np.array([arm.branches.index(label) for label in limits.branches]))
    parts, complete = certify(first_intervals(limit_arcs, _FIRST_WIDTH), len(limits.branches), len(poses), resolution,
                              measure, budget)
    return poses, Certified(limits.branches, limit_arcs, Decided.of(parts), complete, measure.evaluations,
                            measure.names, False)


class _Q7Measure:
    """The clearances of every checked pair at values of q7 of the poses, and the bounds of how far the pairs' shapes
    move over an interval (module docstring); an interval's owner is ``pose * B + branch`` over the ``B`` branches
    of ``rows`` (indices into the class's eight)."""

    def __init__(self, arm: Arm, poses: np.ndarray, body: Body, scene: Scene, rows: np.ndarray) -> None:
        assert isinstance(arm.implementation, FrankaKind)
        self.geometry: FrankaGeometry = arm.implementation.geometry
        self.chain, self.poses, self.body, self.scene, self.rows = arm.chain, poses, body, scene, rows
        self.frames_seven = np.ascontiguousarray(frames_seven(self.geometry, poses))
        # per pose, the level polynomials' Fourier coefficients at any levels (the level test's)
        self.spectra = np.empty((len(poses), 6, 5, 9), dtype=np.complex128)
        run_batch(_kernels.limit_spectra_of, len(poses), self.frames_seven, self.geometry.kernel_arm, self.spectra,
                  np.empty((len(poses), 2, 17), dtype=np.complex128))
        self.evaluations = np.zeros(len(poses), dtype=np.int64)  # per pose
        self.pairs = checked_pairs(body, scene)
        self.names, self.count = self.pairs.names, len(self.pairs.names)
        self.inputs = clearance_inputs(body, scene, self.pairs)
        self.levers = pair_levers(arm.chain, body, self.pairs)
        self._last: tuple[np.ndarray, ...] | None = None  # joints' last arguments and answer

    def joints(self, q7: np.ndarray, owner: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The owners' branch solutions ``(N, 7)`` at ``q7`` ``(N,)``, and whether each exists: each branch solved
        for its own intervals only.  The last call's answer is kept, for the rates at the same middles."""
        if self._last is not None and self._last[0] is q7 and self._last[1] is owner:
            return self._last[2], self._last[3]
        q, exists = np.empty((len(q7), 7)), np.empty(len(q7), dtype=bool)
        geometry = self.geometry
        run_batch(_kernels.solve_branch_rows, len(q7), self.poses, owner // len(self.rows),
                  np.ascontiguousarray(q7, dtype=float), self.rows[owner % len(self.rows)], geometry.kernel_arm,
                  geometry.kernel_ends, geometry.kernel_branches, geometry.kernel_joints, q, exists)
        self._last = (q7, owner, q, exists)
        return q, exists

    def __call__(self, middle: np.ndarray, half: np.ndarray, owner: np.ndarray, active: np.ndarray, finest: float,
                 carve: bool) -> tuple[np.ndarray, ...]:
        """The intervals of half widths ``half`` around ``middle`` of the owners ``owner`` decided from their active
        pairs' clearances ``active`` ``(N, P)`` (updated in place) and the rates :meth:`proposals` proposes and
        :meth:`proved` proves (:func:`redkin.collision.arm_angle_free.settled`): ``(kind, pair, down, up,
        carved, cause)``, each (N,).  Only the intervals the proposed rates would settle, or on which they would prove a
        pair clear, are proved: on the others any rate leaves the interval open (or undecided) with its pairs as
        they were, so the level test would be spent for nothing."""
        q, _ = self.joints(middle, owner)
        self.evaluations += np.bincount(owner // len(self.rows), minlength=len(self.evaluations))
        proposed, at_middle, delta = self.proposals(owner, middle, half)
        floor = np.nan_to_num(proposed * half[:, None], nan=np.inf)  # a pair a bound proves clear: not measured
        clearance = pair_clearances(self.chain, self.inputs, q, active, self.scene.margin, floor)
        proposed = tightened(self.chain, self.inputs, self.levers, q, delta, proposed * half[:, None], clearance,
                             active, self.scene.margin) / half[:, None]
        reach = proposed * half[:, None]
        with np.errstate(invalid="ignore"):  # inf - inf where a rate is not proposed: NaN, which decides nothing
            deciding = (active & ((clearance - reach > 0.0) | (clearance + reach < 0.0))).any(axis=1)
        rate = self.proved(owner, middle, half, at_middle, delta, proposed, deciding)
        return settled(half, clearance, rate, active, finest, carve)

    def proposals(self, owner: np.ndarray, middle: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, ...]:
        """Per interval the joints' bounds proposed from their values at the middle and the ends (module docstring):
        ``(rate, at_middle, delta)``, ``rate`` ``(N, P)`` the bound of each pair's displacement over the interval
        divided by ``half`` (what :func:`redkin.collision.arm_angle_free.certify` multiplies by ``half``) if the
        bounds ``delta`` ``(N, 7)`` hold, infinite where they cannot be proved (the branch missing at the middle or an
        end, or a bound of a quarter turn); ``at_middle`` ``(N, 7)`` the branch's joints at the middle."""
        at_middle, here = self.joints(middle, owner)
        reach = half + _kernels.LEVEL_SLACK  # the roots the test counts lie within the slack of the interval
        at_ends, there = self.joints(np.concatenate([middle - reach, middle + reach]), np.concatenate([owner, owner]))
        count = len(middle)
        past = np.flatnonzero(here & ~(there[:count] & there[count:]))
        if len(past):  # the slack reaches past an end of the branch (a limit arc ends where the branch does): the
            # interval's own ends, where it exists, propose (the level test proves the bands over the interval)
            ends = np.concatenate([middle[past] - half[past], middle[past] + half[past]])
            inside, exists = self.joints(ends, np.concatenate([owner[past], owner[past]]))
            at_ends[past], at_ends[count + past] = inside[:len(past)], inside[len(past):]
            there[past], there[count + past] = exists[:len(past)], exists[len(past):]
        here = here & there[:count] & there[count:]
        moved = np.maximum(np.abs((at_ends[:count] - at_middle + np.pi) % TWO_PI - np.pi),
                           np.abs((at_ends[count:] - at_middle + np.pi) % TWO_PI - np.pi))
        delta = _PROPOSAL * moved + _ROOM
        delta[:, 6] = half
        rate = pair_displacements(delta, self.levers) / half[:, None]
        rate[~(here & (delta[:, :6].max(axis=1) < _WIDEST))] = np.inf
        return rate, at_middle, delta

    def proved(self, owner: np.ndarray, middle: np.ndarray, half: np.ndarray, at_middle: np.ndarray,
               delta: np.ndarray, rate: np.ndarray, needed: np.ndarray) -> np.ndarray:
        """:meth:`proposals`' ``rate`` on the intervals ``needed`` (N,) whose joints provably keep within their
        bands ``at_middle -+ delta`` (:meth:`leaves_band`), infinite on every other: the rates the decision may
        use."""
        which = np.flatnonzero(needed & np.isfinite(rate).all(axis=1))
        which = which[~self.leaves_band(owner[which], middle[which], half[which], at_middle[which], delta[which])]
        out = np.full_like(rate, np.inf)
        out[which] = rate[which]
        return out

    def leaves_band(self, owner: np.ndarray, middle: np.ndarray, half: np.ndarray, at_middle: np.ndarray,
                    delta: np.ndarray) -> np.ndarray:
        """Per interval ``[middle - half, middle + half]`` of the owners ``owner`` (N,), whether a joint 1-6 of the
        branch may leave its band ``at_middle -+ delta`` ``(N, 7)`` somewhere in it (each ``delta`` under a quarter
        turn; :func:`redkin.franka._kernels.levels_crossed`, module docstring): false proves it stays inside."""
        crossed = np.ones(len(owner), dtype=bool)
        if len(owner):
            joints = self.geometry.kernel_joints
            levels = np.zeros((len(owner), 3, 7))
            for row, sign in ((0, -1.0), (1, 1.0)):  # theta = offset + sign q (chain_values inverted)
                levels[:, row] = joints[0] + joints[1] * (at_middle + sign * delta)
            levels[:, 2, :6] = 1.0
            signs = self.geometry.kernel_branches[self.rows[owner % len(self.rows)]]
            for table in (levels, signs):  # read-only as the limits and branches of the feasible sets: one compile
                table.flags.writeable = False
            run_batch(_kernels.levels_crossed, len(owner), owner // len(self.rows), self.frames_seven, self.spectra,
                      self.geometry.kernel_arm, levels, middle - half, middle + half, signs, joints, crossed)
        return crossed


def _limit_stretches(arm: Arm, poses: np.ndarray, labels: tuple[str, ...], limits: list[tuple[Arcs, ...]],
                     domain: np.ndarray) -> list[list[list[Stretch]]]:
    """Per pose and branch, the stretches of joint 7's range between its limit-feasible intervals, named by their
    causes."""
    gaps: list[list[list[tuple[float, float]]]] = []
    for pose_limits in limits:
        gaps.append([])
        for arcs in pose_limits:
            edges = [float(domain[0]), *arcs.bounds.ravel().tolist(), float(domain[1])]
            gaps[-1].append([(a, b) for a, b in zip(edges[::2], edges[1::2], strict=True) if b > a])
    middles = [[(a + b) / 2.0 for spans in pose_gaps for a, b in spans] for pose_gaps in gaps]
    return limit_stretches_of(arm, poses, labels, gaps, middles)
