"""Certified collision-free arm angles of nearly S-R-S arms (issue 40, item 4; docs/collisions.md, "Nearly S-R-S
arms").

For one pose and each branch, the arm angles at which the real arm has a solution of the branch within its limits
*and* clear of every checked pair (each capsule of the body against each obstacle, and the body's self-collision
pairs) by the scene's margin.  No closed form gives a nearly S-R-S arm's joints as functions of the arm angle, so the
sets are read off the pose's certified self-motion (:func:`redkin.srs.nearly.self_motion.whole_self_motion`), as
its feasible sets are (:mod:`redkin.srs.nearly.feasible`).

What is proved.  Each step of a curve is an arc of true solutions of the pose, on a known branch and within the
limits or not [C2]-[C4], every point of which lies within ``H |t_j| + r*`` of the step's anchor in joint ``j``
(:attr:`redkin.srs.nearly.self_motion.SelfMotion.tubes`: the anchor is a solution, ``t`` its tangent, ``H`` the
certified length and ``r*`` the tube's radius).  With those joint bounds, :mod:`redkin.collision.joint_motion`
bounds how far each pair's signed distance moves from its value at the anchor over the whole arc.  A step on the
branch and within the limits is

* **free** where every pair's clearance (distance minus margin) at the anchor exceeds that bound: every arm angle
  between its ends' (the arc is continuous, and its arm angles cover the short arc between them [C6]) then has a
  solution of the branch within the limits and clear by the margin;
* **blocked** by a pair whose clearance at the anchor is below minus the bound: that pair meets on the whole arc;
* otherwise followed again with steps a quarter as long (:func:`redkin.srs.nearly.self_motion.finer_steps`, the same
  certificate) and each of those decided, until a step's arm-angle bound is at most the resolution: then it is
  undecided and left out of the free set.

A free arc and a blocked one never share a point (the clearance would be both above and below zero there), so an
end of a free set lies within the resolution of a true end.  The free set is the union of the free steps' arm
angles, within the branch's feasible set read off the same curves; a branch's removed stretches are named by the
pair of the blocked steps that cover them, by the joints out of range, or undecided.

What is not claimed: the self-motion's curves through none of its seeds, or not followed whole, are not searched
(``complete`` false where :func:`redkin.srs.nearly.self_motion.whole_self_motion` says so, or the budget of
evaluations ran out).  Where a branch has two solutions at one arm angle (a fold next to a stretched elbow or a
straight shoulder), the arm angle is free where either is.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.feasible_sets import merged_intervals
from redkin.arms.front_door import Arm
from redkin.arms.nearly_kind import NearlyKind
from redkin.circle import ArcSet, arc_length, wrap_angle
from redkin.collision.arm_angle_free import (
    COLLISION,
    UNDECIDED,
    FreeArmAngles,
    Stretch,
    arcs_of,
    checked_inputs,
    circle_limit_stretches,
)
from redkin.collision.body import Body
from redkin.collision.clearance import checked_pairs, clearance_inputs, pair_clearances
from redkin.collision.joint_motion import pair_displacements, pair_levers, tightened
from redkin.collision.scene import Scene
from redkin.errors import RedkinError
from redkin.srs.nearly import _self_motion_kernels
from redkin.srs.nearly.self_motion import SelfMotion, feasible_along_all, finer_steps, whole_self_motion

#: Removed stretches no wider than this [rad] are where the free set's and the limits' ends meet, not stretches.
_ROUNDING = 1e-12
#: Consecutive steps of a curve first proved clear of a pair together (the pairs far from all of them).
_BLOCK = 32
#: How much shorter [times] the steps of an undecided step are when it is followed again.
_FINER = 4.0


def free_nearly_of(arm: Arm, poses: ArrayLike, body: Body, scene: Scene,
                   branches: str | tuple[str, ...] | list[str] | None = None, *, resolution: float = 1e-6,
                   budget: int = 100_000, causes: bool = True) -> list[FreeArmAngles]:
    """The certified collision-free arm angles (module docstring) of each pose of ``poses`` ``(P, 4, 4)`` on each
    branch (or ``branches``) of a nearly S-R-S arm; the arguments are those of
    :func:`redkin.collision.collision_free_arm_angles` (``budget`` evaluations per pose); without ``causes`` the
    removed stretches are neither named nor solved for (``blocked`` empty).

    Raises
    ------
    RedkinError
        For an arm of another class (named), a body on another number of joints, malformed poses or a resolution
        that is not > 0.
    """
    if not isinstance(arm.implementation, NearlyKind):
        raise RedkinError(f"these certified collision-free arm angles are computed on nearly S-R-S arms; "
                          f"{arm.chain.name} is {arm.kind}")
    poses = checked_inputs(arm, poses, body, resolution, budget)
    labels = arm.labels(branches)
    measure = _StepMeasure(arm, body, scene)
    return [_one_pose(arm, measure, pose, labels, float(resolution), budget, causes) for pose in poses]


class _StepMeasure:
    """The checked pairs' clearances at solutions, and the bounds of how far they move over a step's arc."""

    def __init__(self, arm: Arm, body: Body, scene: Scene) -> None:
        self.chain, self.body, self.scene = arm.chain, body, scene
        self.pairs = checked_pairs(body, scene)
        self.inputs = clearance_inputs(body, scene, self.pairs)
        self.levers = pair_levers(arm.chain, body, self.pairs)

    def bounds(self, q: np.ndarray, delta: np.ndarray, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds ``(N, P)`` of each pair's clearance over arcs within ``delta`` ``(N, 7)`` of the
        solutions ``q`` ``(N, 7)`` in each joint, for the pairs ``active`` ``(N, P)`` (``inf`` for the others: proved
        clear already); rows without an active pair are not posed.  Where the lower bound is positive (the pair is
        clear over the arc) the upper bound is ``inf``: a cheap lower bound of the distance that proves it is used
        in place of the distance (:func:`redkin.collision.clearance.pair_clearances`' ``floor``).  Where the
        displacement bound leaves a pair undecided, the bound along its normal is read instead
        (:func:`redkin.collision.joint_motion.tightened`: towards the margin, so the lower bound of a pair within
        it, and the upper of one clear of it, only say which side of zero it stays on)."""
        moved = pair_displacements(delta, self.levers)
        floor = np.nan_to_num(moved, nan=np.inf)  # a pair a bound proves clear by more than it moves: not measured
        clearance = pair_clearances(self.chain, self.inputs, q, active, self.scene.margin, floor)
        moved = tightened(self.chain, self.inputs, self.levers, q, delta, moved, clearance, active, self.scene.margin)
        with np.errstate(invalid="ignore"):  # inf - inf: a pair not measured, at an unbounded displacement
            low = np.where(active, clearance - moved, np.inf)
            return low, np.where(active & ~(low > 0.0), clearance + moved, np.inf)


class _Steps:
    """Steps of self-motion curves still to decide: per step its curve, index and branch (a row of
    :data:`redkin.srs.BRANCHES`)."""

    def __init__(self) -> None:
        self.curves: list[SelfMotion] = []
        self.index: list[np.ndarray] = []
        self.rows: list[np.ndarray] = []

    def add(self, curve: SelfMotion, rows: np.ndarray) -> None:
        """Add the steps of ``curve`` on a branch of ``rows`` and within the limits."""
        good = np.isin(curve.branches, rows) & (curve.inside == _self_motion_kernels.INSIDE)
        self.curves.append(curve)
        self.index.append(np.flatnonzero(good))
        self.rows.append(curve.branches[good])

    def __len__(self) -> int:
        return sum(len(index) for index in self.index)

    def arrays(self) -> tuple[np.ndarray, ...]:
        """Per step: the anchor ``(N, 7)``, the joint bounds of its arc ``(N, 7)``, its arm angles' arc ``(N, 2)``
        (unrolled, ``lo <= hi``), its arm-angle bound, its branch row, its curve and its index on the curve."""
        anchors, deltas, arcs, spreads = [], [], [], []
        for curve, index in zip(self.curves, self.index, strict=True):
            at = curve.anchors[index]
            anchors.append(curve.q[at])
            deltas.append(curve.tubes[index, :1] * np.abs(curve.tangents[at]) + curve.tubes[index, 1:])
            arcs.append(_step_arcs(curve, index))
            spreads.append(curve.spread[index])
        owner = np.concatenate([np.full(len(index), c) for c, index in enumerate(self.index)])
        return (np.concatenate(anchors), np.concatenate(deltas), np.concatenate(arcs), np.concatenate(spreads),
                np.concatenate(self.rows), owner, np.concatenate(self.index))

    def blocks(self) -> np.ndarray:
        """Per step (in the order of :meth:`arrays`), its block: steps of one curve whose indices share a multiple of
        :data:`_BLOCK`, numbered in order."""
        return np.cumsum(np.concatenate([np.diff(index // _BLOCK, prepend=-1) != 0 for index in self.index])) - 1


def _step_arcs(curve: SelfMotion, index: np.ndarray) -> np.ndarray:
    """The arm angles of steps ``index`` of ``curve`` ``(N, 2)``: the short arc between their ends', unrolled."""
    start = curve.psi[index]
    end = start + np.asarray(wrap_angle(curve.psi[index + 1] - start))
    return np.stack([np.minimum(start, end), np.maximum(start, end)], axis=-1)


def _one_pose(arm: Arm, measure: _StepMeasure, pose: np.ndarray, labels: tuple[str, ...], resolution: float,
              budget: int, causes: bool) -> FreeArmAngles:
    """The free sets of one pose (module docstring): the steps decided down to the resolution, then each run of
    undecided steps wider than the resolution followed again more finely, as
    :func:`redkin.collision.arm_angle_free.certify` halves such runs."""
    assert isinstance(arm.implementation, NearlyKind)
    curves, whole = whole_self_motion(arm.implementation.nearly, pose)
    rows = [arm.branches.index(label) for label in labels]  # the class's labels are BRANCHES' order
    decision = _Decision(arm, measure, pose, rows, budget)
    steps = _Steps()
    for curve in curves:
        steps.add(curve, np.array(rows))
    every = feasible_along_all(curves)
    limits = {row: every[row] for row in rows}
    finest = resolution
    while True:
        decision.run(steps, finest)
        wide = {row: ArcSet([arc for arc in decision.sets(row, limits[row])[2].arcs
                             if arc_length(*arc) > resolution]) for row in rows}
        if not any(not part.is_empty for part in wide.values()) or not decision.complete:
            break
        finest /= _FINER
        if finest < resolution * 1e-6:  # a clearance that grazes the margin over a stretch: left undecided
            decision.complete = False
            break
        steps = decision.again(wide, finest)
    free_sets, stretches = [], []
    for row in rows:
        clear, named, _ = decision.sets(row, limits[row])
        free_sets.append(arcs_of(clear))
        stretches.append(named)
    limit_arcs = tuple(arcs_of(limits[row]) for row in rows)
    blocked: tuple[tuple[Stretch, ...], ...] = tuple(() for _ in labels)
    if causes:
        at_limits = circle_limit_stretches(arm, pose, labels, limit_arcs)
        blocked = tuple(tuple(sorted(mine + theirs, key=lambda stretch: stretch.start))
                        for mine, theirs in zip(stretches, at_limits, strict=True))
    return FreeArmAngles(labels, tuple(free_sets), limit_arcs, blocked, resolution, decision.evaluations,
                         whole and decision.complete)


class _Decision:
    """The steps decided so far for one pose: the free steps' and the blocked steps' arm angles per branch (and pair),
    and the undecided steps."""

    def __init__(self, arm: Arm, measure: _StepMeasure, pose: np.ndarray, rows: list[int], budget: int) -> None:
        assert isinstance(arm.implementation, NearlyKind)
        self.nearly, self.measure, self.pose, self.budget = arm.implementation.nearly, measure, pose, budget
        self.free: dict[int, list[np.ndarray]] = {row: [] for row in rows}  # per branch row, arm angles (K, 2) each
        self.blocked: dict[tuple[int, int], list[np.ndarray]] = {}  # per branch row and pair
        self.undecided: list[tuple[SelfMotion, int, int, np.ndarray]] = []  # curve, step, branch row, arm angles
        self.evaluations = 0
        self.complete = True

    def run(self, steps: _Steps, finest: float) -> None:
        """Decide ``steps`` and the finer steps of those undecided, down to steps whose arm-angle bound is at most
        ``finest``."""
        while len(steps):
            anchor, delta, arcs, spread, row, owner, index = steps.arrays()
            if self.evaluations + len(anchor) > self.budget:  # the steps left are undecided
                self.complete = False
                return
            block = steps.blocks()
            starts = np.flatnonzero(np.diff(block, prepend=-1))
            reference = anchor[starts]  # a solution: every arc of its block lies within the block's bounds of it
            around = np.maximum.reduceat(np.abs(anchor - reference[block]) + delta, starts, axis=0)
            everything = np.ones((len(starts), len(self.measure.pairs.names)), dtype=bool)
            active = ~(self.measure.bounds(reference, around, everything)[0] > 0.0)[block]
            self.evaluations += len(starts) + int(active.any(axis=1).sum())
            low, high = self.measure.bounds(anchor, delta, active)
            is_free = np.all(low > 0.0, axis=1)
            is_blocked = ~is_free & np.any(high < 0.0, axis=1)
            which = np.argmin(high, axis=1) if high.shape[1] else np.zeros(len(anchor), dtype=np.int64)
            for r in np.unique(row[is_free]).tolist():
                self.free[r].append(arcs[is_free & (row == r)])
            for r, pair in set(zip(row[is_blocked].tolist(), which[is_blocked].tolist(), strict=True)):
                self.blocked.setdefault((r, pair), []).append(arcs[is_blocked & (row == r) & (which == pair)])
            finer = _Steps()
            for n in np.flatnonzero(~is_free & ~is_blocked).tolist():  # few: next to the sets' ends
                r, curve, k = int(row[n]), steps.curves[owner[n]], int(index[n])
                if spread[n] <= finest or not self._followed(finer, curve, k, r):
                    self.undecided.append((curve, k, r, arcs[n]))
            steps = finer

    def _followed(self, steps: _Steps, curve: SelfMotion, k: int, row: int) -> bool:
        """Add the finer steps of step ``k`` of ``curve`` to ``steps``; whether it could be followed again (its finer
        steps off the branch or the limits are left out: undecided)."""
        piece = finer_steps(self.nearly, self.pose, curve, k, curve.tubes[k, 0] / _FINER)
        if piece is not None:
            steps.add(piece, np.array([row]))
        return piece is not None

    def again(self, wide: dict[int, ArcSet], finest: float) -> _Steps:
        """The finer steps of the undecided steps whose arm angles meet ``wide`` (per branch row), taken out of the
        undecided ones."""
        steps, kept = _Steps(), []
        for curve, k, row, arc in self.undecided:
            if wide[row].intersection(ArcSet([tuple(arc)])).is_empty or curve.spread[k] <= finest \
                    or not self._followed(steps, curve, k, row):
                kept.append((curve, k, row, arc))
        self.undecided = kept
        return steps

    def sets(self, row: int, within: ArcSet) -> tuple[ArcSet, list[Stretch], ArcSet]:
        """The free set of branch ``row`` within its feasible set ``within``, the stretches the obstacles remove
        from it (named by pair, or undecided), and the undecided set."""
        clear = _arc_set(self.free[row]).intersection(within)
        removed = _wider(within.intersection(clear.complement()))  # not the points where two sets' ends meet
        named: list[Stretch] = []
        covered = ArcSet.empty()
        for (r, pair), found in sorted(self.blocked.items()):
            if r != row:
                continue
            cut = _arc_set(found).intersection(removed)
            covered = covered.union(cut)
            link, against = self.measure.pairs.names[pair]
            named += [Stretch(start, end, COLLISION, link, against) for start, end in cut.arcs]
        undecided = _wider(removed.intersection(covered.complement()))  # not the ends of the named stretches
        named += [Stretch(start, end, UNDECIDED, "", "") for start, end in undecided.arcs]
        return clear, named, undecided


def _wider(arcs: ArcSet) -> ArcSet:
    """The arcs of ``arcs`` wider than :data:`_ROUNDING` (the whole circle among them)."""
    return ArcSet([arc for arc in arcs.arcs if arc_length(*arc) > _ROUNDING])


def _arc_set(parts: list[np.ndarray]) -> ArcSet:
    """The union of the arm angles' arcs ``(K, 2)`` of each part (unrolled, ``lo <= hi``), merged as line intervals
    first (thousands of steps' arcs become a few)."""
    arcs = np.concatenate([np.empty((0, 2)), *parts])
    return ArcSet(merged_intervals(arcs[:, 0], arcs[:, 1]).bounds.tolist())
