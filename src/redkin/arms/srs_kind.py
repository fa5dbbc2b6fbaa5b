"""S-R-S and offset-elbow arms as :class:`redkin.arms.Arm` asks them (paper 000): the arm angle psi, the closed form
[000 eqs. 11-19] on every branch, the exact feasible sets [000 eq. 30], the singular arm angles [000 eqs. 31-34] and
the limit-avoiding arm angle [000 eqs. 36-40]."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.analysis import Analysis, BranchAnalysis, SingularPart, as_arcs, check_in_reach, optimal_parts
from redkin.arms.feasible_sets import Arcs
from redkin.arms.parameter import Parameter
from redkin.arms.protocol import ArmKind
from redkin.arms.solutions import CLOSED_FORM, Solutions
from redkin.chain import Reach
from redkin.circle import ArcSet
from redkin.errors import UnreachablePoseError
from redkin.paths.family import ArmAngleFamily
from redkin.srs import _ik_kernels
from redkin.srs._feasible_kernels import PIECES
from redkin.srs.branches import BRANCHES
from redkin.srs.feasible import FeasibleArmAngles, feasible_arm_angles, feasible_pieces_all_branches
from redkin.srs.geometry import SRSGeometry
from redkin.srs.ik import reach, reachable, solve_with_status
from redkin.srs.optimal import optimal_arm_angles
from redkin.srs.singular import singular_arm_angles

#: The arm angle: an angle on the circle [000 eq. 6].
ARM_ANGLE = Parameter(
    name="psi", domain=(-float(np.pi), float(np.pi)), wraps=True, noun="arm angle", plural="arm angles", symbol="ψ",
    set_symbol="Ψ", set_ascii="Psi", prefix="arm-angle", joint_symbol="θ", branch_signs="signs of theta 2, 4, 6",
    equation="[000 eq. 30]", optimum="[000 eq. 40]")
#: The branch labels, in the order of :data:`redkin.srs.BRANCHES`.
LABELS = tuple(str(branch) for branch in BRANCHES)


class SRSKind(ArmKind):
    """An S-R-S or offset-elbow arm converted once to paper 000's Table 1 form."""

    parameter = ARM_ANGLE
    branches = LABELS
    exact = True
    method = "paper 000's closed-form arm-angle IK and exact feasible sets"

    def __init__(self, kind: str, geometry: SRSGeometry) -> None:
        self.kind, self.geometry, self.chain = kind, geometry, geometry.chain
        self.family = ArmAngleFamily(geometry)

    def solve(self, poses: ArrayLike, t: np.ndarray, rows: np.ndarray | None) -> Solutions:
        signs = self.geometry.kernel_branches
        if rows is not None:
            signs = signs[rows]
            signs.flags.writeable = False  # read-only as the whole table: one compile of the IK's kernels
        q, within, status, checked = solve_with_status(self.geometry, poses, t, signs)
        out = status == _ik_kernels.UNREACHABLE
        exists = np.broadcast_to(~out[..., None], within.shape)
        labels = LABELS if rows is None else tuple(LABELS[r] for r in rows)

        def measured() -> Reach:
            return reach(self.geometry, checked)

        return Solutions(q, exists, within, labels, CLOSED_FORM, t, lambda: out, measured)

    def pieces(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        inside = None if len(poses) == 1 else reachable(self.geometry, poses)
        if inside is None or inside.all():
            try:
                pieces = feasible_pieces_all_branches(self.geometry, poses)
                return pieces.start, pieces.end, pieces.feasible
            except UnreachablePoseError:
                inside = np.zeros(1, dtype=bool)
        start = np.full((len(poses), len(LABELS), PIECES), np.nan)
        end, feasible = start.copy(), np.zeros(start.shape, dtype=bool)
        if inside.any():  # a pose out of reach has no solution at any arm angle: empty sets
            pieces = feasible_pieces_all_branches(self.geometry, poses[inside])
            start[inside], end[inside], feasible[inside] = pieces.start, pieces.end, pieces.feasible
        return start, end, feasible

    def optimal(self, pose: np.ndarray, row: int, target: np.ndarray | None,
                weights: tuple[float, float] | None, within: Arcs | None = None) -> tuple[float, float]:
        """[000 eq. 40]'s optimum, clamped to the nearest arm angle of the feasible set (or of ``within``)."""
        overall = optimal_arm_angles(self.geometry, pose, BRANCHES[row], target=target,
                                     weights=(0.5, 0.5) if weights is None else weights,
                                     feasible=None if within is None else ArcSet(within.bounds.tolist())).overall
        return (np.nan if overall.feasible is None else overall.feasible), overall.unclamped

    def joint_sets(self, pose: np.ndarray, row: int) -> dict[int, list[tuple[float, float]]]:
        """[000 eq. 29]'s per-joint sets (joint 4 does not depend on psi: all or nothing)."""
        return {joint: arcs.arcs for joint, arcs in feasible_arm_angles(self.geometry, pose, BRANCHES[row])
                .per_joint.items()}

    def singular(self, pose: np.ndarray, row: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
        angles = singular_arm_angles(self.geometry, pose, BRANCHES[row])
        return angles.shoulder, angles.wrist

    def analyse(self, pose: np.ndarray, rows: np.ndarray, target: np.ndarray | None,
                weights: tuple[float, float] | None) -> Analysis:
        """[000 eqs. 20-40] at one pose; raises :class:`redkin.errors.UnreachablePoseError` out of reach ([000 eq.
        11], :func:`redkin.srs.ik.reach`)."""
        check_in_reach(reach(self.geometry, pose))
        every = [feasible_arm_angles(self.geometry, pose, branch) for branch in BRANCHES]
        sets = tuple(as_arcs(result.feasible.arcs) for result in every)
        return Analysis(self.parameter, self.method, sets,
                        tuple(self._branch(pose, int(row), every[row], sets[row], target, weights) for row in rows))

    def _branch(self, pose: np.ndarray, row: int, result: FeasibleArmAngles, arcs: np.ndarray,
                target: np.ndarray | None, weights: tuple[float, float] | None) -> BranchAnalysis:
        singular = singular_arm_angles(self.geometry, pose, BRANCHES[row])
        optimal = optimal_arm_angles(self.geometry, pose, BRANCHES[row], target=target,
                                     weights=(0.5, 0.5) if weights is None else weights, feasible=result.feasible)
        elbow = self.geometry.q_of_theta(np.r_[np.zeros(3), result.theta4, np.zeros(3)])[3]
        parts = {"shoulder": SingularPart(singular.shoulder, singular.shoulder_everywhere, "θ2 = 0 or π",
                                          _SPLIT.format(1, 3)),
                 "wrist": SingularPart(singular.wrist, singular.wrist_everywhere, "θ6 = 0 or π", _SPLIT.format(5, 7))}
        return BranchAnalysis(LABELS[row], arcs, result.feasible.is_full, optimal_parts(optimal),
                              {joint: as_arcs(arcs.arcs) for joint, arcs in result.per_joint.items()}, parts,
                              {4: float(elbow)})


#: What a singular arm angle means for the joint values shown there.
_SPLIT = ("joints {0} and {1} turn about one axis here: only their combination is fixed, the values shown are one "
          "split")
