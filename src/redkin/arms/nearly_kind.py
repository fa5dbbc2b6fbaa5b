"""Nearly S-R-S arms as :class:`redkin.arms.Arm` asks them (docs/srs.md, "Nearly S-R-S arms"): the real arm's arm
angle, its exact neighbour's closed form polished and certified on the real arm, the feasible sets located on its
self-motion (certified, not proved complete), its singular and limit-avoiding arm angles, and a branch's every
solution at an arm angle (near a stretched elbow or a straight shoulder, a branch can have two)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.protocol import ArmKind
from redkin.arms.solutions import CLOSED_FORM, Solutions
from redkin.arms.srs_kind import ARM_ANGLE, LABELS
from redkin.chain import Reach
from redkin.paths.family import NearlyFamily
from redkin.srs.branches import BRANCHES
from redkin.srs.nearly import TOLERANCE as NEARLY_TOLERANCE
from redkin.srs.nearly import NearlySRS
from redkin.srs.nearly import ik as nearly_ik
from redkin.srs.nearly.optimal import optimal_arm_angles_nearly
from redkin.srs.nearly.self_motion import branch_solutions
from redkin.srs.nearly.singular import singular_arm_angles_nearly


class NearlyKind(ArmKind):
    """A nearly S-R-S arm and its exact neighbour, built once."""

    parameter = ARM_ANGLE
    branches = LABELS
    exact = False

    def __init__(self, kind: str, nearly: NearlySRS, tolerance: float) -> None:
        self.kind, self.nearly, self.chain = kind, nearly, nearly.chain
        self.family = NearlyFamily(nearly, tolerance)

    def solve(self, poses: ArrayLike, t: np.ndarray, rows: np.ndarray | None) -> Solutions:
        labels = LABELS if rows is None else tuple(LABELS[r] for r in rows)
        one = rows is not None and len(rows) == 1
        found = nearly_ik(self.nearly, poses, t, BRANCHES[rows[0]] if one else None)  # type: ignore[index]
        q, exists, within = found.q, found.exists, found.within_limits
        if rows is not None and not one:
            q, exists, within = q[..., rows, :], exists[..., rows], within[..., rows]

        def measured() -> Reach:  # the links' bound, with the slack of the real arm's certificate
            bound = self.chain.reach(poses, tolerance=NEARLY_TOLERANCE)
            return bound._replace(distance=np.broadcast_to(bound.distance, exists.shape[:-1]),
                                  out=np.broadcast_to(bound.out, exists.shape[:-1]))

        return Solutions(q, exists, within, labels, CLOSED_FORM, t, lambda: measured().out, measured,
                         "no certified solution of the branch at this arm angle")

    def optimal(self, pose: np.ndarray, row: int, target: np.ndarray | None,
                weights: tuple[float, float] | None) -> tuple[float, float]:
        overall = optimal_arm_angles_nearly(self.nearly, pose, BRANCHES[row], target=target,
                                            weights=(0.5, 0.5) if weights is None else weights).overall
        return (np.nan if overall.feasible is None else overall.feasible), overall.unclamped

    def singular(self, pose: np.ndarray, row: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
        angles = singular_arm_angles_nearly(self.nearly, pose, BRANCHES[row])
        return angles.shoulder, angles.wrist

    def every_solution(self, pose: np.ndarray, t: float, row: int) -> np.ndarray:
        return branch_solutions(self.nearly, pose, t, BRANCHES[row])
