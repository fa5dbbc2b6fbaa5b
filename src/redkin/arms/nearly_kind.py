"""Nearly S-R-S arms as :class:`redkin.arms.Arm` asks them (docs/srs.md, "Nearly S-R-S arms"): the real arm's arm
angle, its exact neighbour's closed form polished and certified on the real arm, the feasible sets located on its
self-motion (certified, not proved complete), its singular and limit-avoiding arm angles, and a branch's every
solution at an arm angle (near a stretched elbow or a straight shoulder, a branch can have two)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.analysis import Analysis, BranchAnalysis, SingularPart, as_arcs, check_in_reach, optimal_parts
from redkin.arms.feasible_sets import Arcs
from redkin.arms.protocol import ArmKind
from redkin.arms.solutions import CLOSED_FORM, Solutions
from redkin.arms.srs_kind import ARM_ANGLE, LABELS
from redkin.chain import Reach
from redkin.circle import ArcSet
from redkin.paths.family import NearlyFamily
from redkin.srs.branches import BRANCHES
from redkin.srs.nearly import NearlySRS
from redkin.srs.nearly import ik as nearly_ik
from redkin.srs.nearly import reach as nearly_reach
from redkin.srs.nearly.feasible import NearlyFeasible, feasible_arm_angles_nearly_all
from redkin.srs.nearly.optimal import optimal_arm_angles_nearly
from redkin.srs.nearly.self_motion import branch_solutions, self_motions
from redkin.srs.nearly.singular import singular_arm_angles_nearly


class NearlyKind(ArmKind):
    """A nearly S-R-S arm and its exact neighbour, built once."""

    parameter = replace(ARM_ANGLE, optimum="[000 eq. 40] on the real arm")
    branches = LABELS
    exact = False
    one_per_branch = False
    method = ("the exact S-R-S neighbour's closed form polished on the real nearly S-R-S arm, its feasible sets, "
              "singular and optimal arm angles located on the real arm")

    def __init__(self, kind: str, nearly: NearlySRS, tolerance: float) -> None:
        self.kind, self.nearly, self.chain = kind, nearly, nearly.chain  # nearly: the protocol's exact neighbour
        self.family = NearlyFamily(nearly, tolerance)

    def solve(self, poses: ArrayLike, t: np.ndarray, rows: np.ndarray | None) -> Solutions:
        labels = LABELS if rows is None else tuple(LABELS[r] for r in rows)
        one = rows is not None and len(rows) == 1
        found = nearly_ik(self.nearly, poses, t, BRANCHES[rows[0]] if one else None)  # type: ignore[index]
        q, exists, within = found.q, found.exists, found.within_limits
        if rows is not None and not one:
            q, exists, within = q[..., rows, :], exists[..., rows], within[..., rows]

        def measured() -> Reach:
            bound = nearly_reach(self.nearly, poses)
            return bound._replace(distance=np.broadcast_to(bound.distance, exists.shape[:-1]),
                                  out=np.broadcast_to(bound.out, exists.shape[:-1]))

        return Solutions(q, exists, within, labels, CLOSED_FORM, t, lambda: measured().out, measured,
                         "no certified solution of the branch at this arm angle")

    def optimal(self, pose: np.ndarray, row: int, target: np.ndarray | None,
                weights: tuple[float, float] | None, within: Arcs | None = None) -> tuple[float, float]:
        """[000 eq. 40]'s optimum on the real arm ([000 eqs. 36-40] through the neighbour), clamped to the feasible
        set or to ``within`` (the collision-free arcs: the best point of the branch's certified steps in them)."""
        allowed = None if within is None else ArcSet(within.bounds.tolist())
        overall = optimal_arm_angles_nearly(self.nearly, pose, BRANCHES[row], target=target,
                                            weights=(0.5, 0.5) if weights is None else weights,
                                            feasible=allowed).overall
        return (np.nan if overall.feasible is None else overall.feasible), overall.unclamped

    def singular(self, pose: np.ndarray, row: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
        angles = singular_arm_angles_nearly(self.nearly, pose, BRANCHES[row])
        return angles.shoulder, angles.wrist

    def every_solutions(self, pose: np.ndarray, t: float, rows: np.ndarray) -> tuple[np.ndarray, ...]:
        """Along the pose's certified self-motion, traced once for every branch of ``rows``."""
        curves = self_motions(self.nearly, pose)
        return tuple(branch_solutions(self.nearly, pose, t, BRANCHES[row], curves) for row in rows)

    def analyse(self, pose: np.ndarray, rows: np.ndarray, target: np.ndarray | None,
                weights: tuple[float, float] | None) -> Analysis:
        """The real arm's feasible sets of every branch from one self-motion, and its singular and limit-avoiding
        arm angles; no per-joint sets (not computed on such arms); raises :class:`redkin.errors.UnreachablePoseError`
        where the links' reach proves the pose out of reach."""
        check_in_reach(nearly_reach(self.nearly, pose))
        every = feasible_arm_angles_nearly_all(self.nearly, pose)
        remarks = (f"{self.chain.name} is nearly S-R-S: {self.nearly.describe()}.",
                   "The per-joint sets are not computed on nearly S-R-S arms.")
        sets = tuple(as_arcs(result.feasible.arcs) for result in every)
        return Analysis(self.parameter, self.method, sets,
                        tuple(self._branch(pose, int(row), every[row], sets[row], target, weights) for row in rows),
                        all(result.complete for result in every), every[0].samples, remarks, "certified solution")

    def _branch(self, pose: np.ndarray, row: int, result: NearlyFeasible, arcs: np.ndarray,
                target: np.ndarray | None, weights: tuple[float, float] | None) -> BranchAnalysis:
        singular = singular_arm_angles_nearly(self.nearly, pose, BRANCHES[row])
        optimal = optimal_arm_angles_nearly(self.nearly, pose, BRANCHES[row], target=target,
                                            weights=(0.5, 0.5) if weights is None else weights,
                                            feasible=result.feasible, curves=result.curves)
        parts = {part: SingularPart(getattr(singular, part), False, f"axes {axes[0]}, {axes[1]} on one line",
                                    _ALIGNED.format(*axes), np.asarray(getattr(singular, f"{part}_q")),
                                    None if (near := getattr(singular, f"{part}_nearest")) is None
                                    else (float(near.psi), float(near.angle)))
                 for part, axes in (("shoulder", (1, 3, "θ2")), ("wrist", (5, 7, "θ6")))}
        return BranchAnalysis(LABELS[row], arcs, result.feasible.is_full, optimal_parts(optimal), None, parts)


#: What a singular arm angle of the real arm means for the values shown there.
_ALIGNED = ("axes {0} and {1} of the real arm are parallel or antiparallel here: the branch's sign of {2} changes, "
            "and the values shown are the aligned configuration")
