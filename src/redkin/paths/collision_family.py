"""Path resolution in a cell (issue 40): an arm's class whose pieces are the certified collision-free sets of its
redundancy parameter (:func:`redkin.collision.free_sets_of`: the arm angles of S-R-S, offset-elbow and nearly S-R-S
arms, q7 on the Franka class) inside its exact feasible pieces, so that every waypoint of a resolved path keeps every
link of the body the scene's margin away from every obstacle and from the body's other links.

Each exact piece (an interval of the parameter on which the branch exists, keeps every limit and is continuous) is
cut to the free intervals within it, so the path search, its polish and its clearance levels (the limits moved in)
all stay inside the free sets.  Between waypoints nothing is searched here: the joint values interpolate between
two collision-free configurations, and a link may sweep through a thin obstacle on a long step;
:func:`redkin.collision.step_clearance` checks the steps of the path found (docs/paths.md).  The sets are certified,
not exact (undecided slivers of at most the resolution are left out): a clearance is proved optimal among them (on
an exact class, where the sets at the bottleneck are complete), not against a path through such a sliver.  Every
class with a redundancy parameter, as the free sets.  On a nearly S-R-S arm a waypoint's arm angle is free where
some solution of its branch is; next to a fold (a stretched elbow, a straight shoulder), where a branch has two
solutions at one arm angle, the solver's may be the other, so the waypoints' clearances are measured again.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from redkin.chain import SerialChain
from redkin.circle import TWO_PI, arc_length
from redkin.errors import RedkinError
from redkin.franka.ik import PARAMETER as Q7
from redkin.paths.family import PSI, ArmAngleFamily, Family, NearlyFamily, Q7Family
from redkin.paths.graph import Arm
from redkin.srs.branches import BRANCHES
from redkin.srs.feasible import FeasiblePieces

if TYPE_CHECKING:  # redkin.collision's free sets use the arms, whose classes use these families: read when called
    from redkin.arms.front_door import Arm as ClassifiedArm
    from redkin.collision.arm_angle_free import FreeArmAngles
    from redkin.collision.body import Body
    from redkin.collision.free_sets import FreeArcs
    from redkin.collision.scene import Scene
    from redkin.collision.steps import StepClearance


@dataclass(frozen=True)
class _CollisionFreeFamily(Family):
    """An S-R-S or offset-elbow arm's family (:class:`redkin.paths.family.ArmAngleFamily`), a nearly S-R-S arm's
    (:class:`redkin.paths.family.NearlyFamily`) or a Franka-class arm's (:class:`redkin.paths.family.Q7Family`),
    whose pieces are cut to the collision-free sets of ``body`` in ``scene``
    (module docstring)."""

    base: ArmAngleFamily | NearlyFamily | Q7Family
    body: Body
    scene: Scene
    parameter: str = PSI
    wraps: bool = True
    exact: bool = False
    baselines: bool = False

    @property
    def chain(self) -> SerialChain:
        return self.base.chain

    def arm(self, poses: np.ndarray, step: np.ndarray) -> tuple[np.ndarray, Arm]:
        return self.base.arm(poses, step)

    def _free_sets(self, poses: np.ndarray) -> tuple[FeasiblePieces, np.ndarray, FreeArcs]:
        """The base family's exact pieces of ``poses``, the waypoints they leave values at, and those waypoints'
        certified collision-free sets (without their causes: :func:`redkin.collision.free_sets.free_arcs_of`)."""
        from redkin.collision.free_sets import free_arcs_of

        exact, some = self._limited(poses)
        return exact, some, free_arcs_of(self._arm(), poses[some], self.body, self.scene)

    def _limited(self, poses: np.ndarray) -> tuple[FeasiblePieces, np.ndarray]:
        """The base family's exact pieces of ``poses``, and the waypoints they leave values at."""
        exact = self.base.pieces(poses)
        return exact, np.flatnonzero(exact.feasible.any(axis=(-2, -1)))

    def _arm(self) -> ClassifiedArm:
        """The :class:`redkin.arms.Arm` of the chain, classified as the base family was: with a nearly S-R-S
        family's tolerance (an arm nearly S-R-S only within a tolerance above the default)."""
        from redkin.arms.front_door import arm

        return arm(self.chain, srs_tolerance=self.base.tolerance if isinstance(self.base, NearlyFamily) else None)

    def pieces(self, poses: np.ndarray) -> FeasiblePieces:
        """The base family's pieces ``(W, 8, K)`` cut to each waypoint's free intervals."""
        return self._cut_to(poses, *self._free_sets(poses))

    def pieces_with_causes(self, poses: np.ndarray) -> tuple[FeasiblePieces, np.ndarray, list[FreeArmAngles]]:
        """:meth:`pieces`, the waypoints the limits leave values at, and those waypoints' certified sets with the
        stretches the cell removes named (:func:`redkin.collision.free_sets_of`): the sets computed once for both
        (what the picture of a path in a cell draws)."""
        from redkin.collision.free_sets import free_arcs_from, free_sets_of

        exact, some = self._limited(poses)
        found = free_sets_of(self._arm(), poses[some], self.body, self.scene) if len(some) else []
        return self._cut_to(poses, exact, some, free_arcs_from(found)), some, found

    def _cut_to(self, poses: np.ndarray, exact: FeasiblePieces, some: np.ndarray, free: FreeArcs) -> FeasiblePieces:
        """The base family's pieces ``exact`` of ``poses`` cut to the free arcs ``free`` of the waypoints ``some``."""
        owners = len(poses) * len(BRANCHES)  # an owner is waypoint * 8 + branch
        bounds, wraps, owner = free.arcs
        arc_owner = some[owner // len(BRANCHES)] * len(BRANCHES) + owner % len(BRANCHES)
        piece_owner = np.flatnonzero(exact.feasible.reshape(-1)) // exact.feasible.shape[-1]  # in C order, sorted
        cut = _cut(piece_owner, exact.start[exact.feasible], exact.end[exact.feasible], arc_owner, bounds[:, 0],
                   np.where(wraps, bounds[:, 1] + TWO_PI, bounds[:, 1]), owners, self.wraps)
        return FeasiblePieces(*(part.reshape(len(poses), len(BRANCHES), -1) for part in cut))

    def parameter_of(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.base.parameter_of(q)

    @property
    def proves_optimal(self) -> bool:
        """On an exact class (S-R-S, offset elbow, Franka): a clearance optimal among the certified sets."""
        return self.base.exact

    def proved_empty(self, poses: np.ndarray) -> np.ndarray:
        """Per pose, whether the limits leave nothing, or the certified collision-free sets are empty on every
        branch and complete (every value decided, but for undecided slivers no wider than the resolution)."""
        _, some, free = self._free_sets(poses)
        empty = np.ones(len(poses), dtype=bool)
        empty[some] = free.complete & (np.bincount(free.arcs.owner // len(BRANCHES), minlength=len(some)) == 0)
        return empty

    def inner(self, level: float) -> Family | None:
        inner = self.base.inner(level)
        if inner is None:
            return None
        assert isinstance(inner, ArmAngleFamily | NearlyFamily | Q7Family)
        return _CollisionFreeFamily(inner, self.body, self.scene, self.parameter, self.wraps)

    def model(self) -> str:
        return (f"in a cell: {len(self.scene)} obstacles at margin {self.scene.margin:g} m, {len(self.body)} body "
                f"capsules; the waypoints' sets are the certified collision-free {_NAMES[self.parameter]}, so "
                + ("a clearance is proved optimal among them, to their resolution" if self.proves_optimal else
                   "no clearance is proved optimal"))

    def blocker(self, pose: np.ndarray) -> tuple[int | None, dict[str, int | None], bool]:
        """The base family's answer where the limits alone leave nothing; else no joint: the obstacles do
        (:meth:`emptied` names them)."""
        if not self.base.pieces(pose[None]).feasible.any():
            return self.base.blocker(pose)
        return None, {}, False

    def emptied(self, pose: np.ndarray) -> tuple[str, tuple[str, str] | None]:
        """``("collision", (link, obstacle))`` where the limits leave arm angles and the obstacles take them all, the
        pair that blocks the most of them over the branches; else the base family's ``("empty", None)``."""
        from redkin.collision.arm_angle_free import COLLISION
        from redkin.collision.free_sets import collision_free_set

        if not self.base.pieces(pose[None]).feasible.any():
            return self.base.emptied(pose)
        free = collision_free_set(self._arm(), pose, self.body, self.scene)
        blocked: dict[tuple[str, str], float] = {}
        for stretches in free.blocked:
            for stretch in stretches:
                if stretch.cause == COLLISION:
                    pair = (stretch.link, stretch.against)
                    width = arc_length(stretch.start, stretch.end) if self.wraps else stretch.end - stretch.start
                    blocked[pair] = blocked.get(pair, 0.0) + width
        return "collision", (max(blocked, key=lambda pair: blocked[pair]) if blocked else None)

    def distances(self, q: np.ndarray) -> np.ndarray:
        """The least signed distance of each configuration of ``q`` in the cell (:func:`redkin.collision.clearance`)."""
        from redkin.collision.clearance import clearance

        return clearance(self.chain, self.body, self.scene, q).distance

    def moving_distances(self, q: np.ndarray) -> np.ndarray:
        """The least signed distance of each configuration of ``q`` over the pairs whose distance the redundancy can
        change at its pose (:func:`redkin.collision.free_sets.redundancy_moves`): a pair the pose fixes (the tool's
        link and a shelf; on S-R-S arms the elbow and a ball at the wrist centre) is as close on every value of the
        parameter, so it is left out of what the objective ``"obstacle-clearance"`` compares."""
        from redkin.collision.clearance import pair_table
        from redkin.collision.free_sets import redundancy_moves

        table, _ = pair_table(self.chain, self.body, self.scene, q)
        moves = redundancy_moves(self._arm(), self.body, self.scene, q)
        return np.where(moves, table, np.inf).min(axis=1, initial=np.inf)

    def steps(self, start: np.ndarray, end: np.ndarray) -> StepClearance:
        """What :func:`redkin.collision.steps_between` proves of the steps from ``start`` to ``end``."""
        from redkin.collision.steps import steps_between

        return steps_between(self.chain, self.body, self.scene, start, end)


def collision_free_family(family: Family, body: Body, scene: Scene) -> _CollisionFreeFamily:
    """``family`` in the cell ``scene`` with the arm's ``body`` (every class with a redundancy parameter)."""
    if not isinstance(family, ArmAngleFamily | NearlyFamily | Q7Family):
        raise RedkinError(f"paths in a cell are resolved over a redundancy parameter; {family.chain.name} has none "
                          "(a chain solved numerically)")
    return _CollisionFreeFamily(family, body, scene, family.parameter, family.wraps)


#: The parameter's values in words, by its name in results.
_NAMES = {PSI: "arm angles", Q7: "values of q7"}


def _cut(piece_owner: np.ndarray, start: np.ndarray, end: np.ndarray, arc_owner: np.ndarray, lo: np.ndarray,
         hi: np.ndarray, owners: int, circle: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each owner's pieces ``[start_k, end_k]`` (owners ``piece_owner``, sorted) cut to its free intervals ``[lo_j,
    hi_j]`` (owners ``arc_owner``, sorted; ``hi`` past pi through the seam): ``(start, end, feasible)`` of shape
    ``(owners, K)``, each owner's intersections sorted in its first slots.  On the ``circle`` (the arm angle) a
    piece's ``end`` may pass pi and the free arcs are met a turn either way."""
    first = np.searchsorted(arc_owner, piece_owner)  # each piece's owner's arcs: first .. first + count - 1
    count = np.searchsorted(arc_owner, piece_owner, side="right") - first
    piece = np.repeat(np.arange(len(piece_owner)), count)
    arc = np.repeat(first, count) + np.arange(len(piece)) - np.repeat(np.cumsum(count) - count, count)
    turns = np.array([-TWO_PI, 0.0, TWO_PI] if circle else [0.0])
    a = np.maximum(start[piece][:, None], lo[arc][:, None] + turns).ravel()
    b = np.minimum(end[piece][:, None], hi[arc][:, None] + turns).ravel()
    owner = np.repeat(piece_owner[piece], len(turns))
    keep = b > a
    owner, a, b = owner[keep], a[keep], b[keep]
    order = np.lexsort((b, a, owner))
    owner, a, b = owner[order], a[order], b[order]
    slot = np.arange(len(owner)) - np.searchsorted(owner, owner)  # its place among its owner's
    width = max(1, int(slot.max(initial=-1)) + 1)
    out_start, out_end = np.full((owners, width), np.nan), np.full((owners, width), np.nan)
    feasible = np.zeros((owners, width), dtype=bool)
    out_start[owner, slot], out_end[owner, slot], feasible[owner, slot] = a, b, True
    return out_start, out_end, feasible
