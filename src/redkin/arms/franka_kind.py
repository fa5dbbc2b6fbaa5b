"""Franka-class arms as :class:`redkin.arms.Arm` asks them (docs/franka.md): the value q7 of joint 7, the closed form
at q7 [F1]-[F7] on every branch, the exact feasible q7 sets [F8]-[F9] and the limit-avoiding q7 [F10]."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.analysis import Analysis, BranchAnalysis, as_arcs, check_in_reach, value
from redkin.arms.feasible_sets import Arcs
from redkin.arms.parameter import Parameter
from redkin.arms.protocol import ArmKind
from redkin.arms.solutions import CLOSED_FORM, Solutions
from redkin.arms.srs_kind import LABELS
from redkin.chain import Reach
from redkin.errors import RedkinError
from redkin.franka.feasible import FeasibleQ7, feasible_q7, q7_domain
from redkin.franka.geometry import FrankaGeometry
from redkin.franka.ik import ik, reach
from redkin.franka.optimal import optimal_q7
from redkin.paths.family import Q7Family
from redkin.srs.branches import BRANCHES


class FrankaKind(ArmKind):
    """A Franka-class arm converted once to the solver's form."""

    branches = LABELS
    exact = True
    method = "the Franka class's closed-form IK at a given q7 and its exact feasible q7 sets, docs/franka.md"

    def __init__(self, kind: str, geometry: FrankaGeometry) -> None:
        self.kind, self.geometry, self.chain = kind, geometry, geometry.chain
        self.family = Q7Family(geometry)
        low, high = q7_domain(geometry)  # joint 7's range, [-pi, pi] where it covers the circle
        self.parameter: Parameter = Parameter(
            name="q7", domain=(float(low), float(high)), wraps=False, noun="q7", plural="values of q7", symbol="q7",
            set_symbol="Q7", set_ascii="Q7", prefix="q7", joint_symbol="q",
            branch_signs="signs of the shoulder (q2), the elbow (either side of the longest reach) and the wrist "
                         "(cos q5)",
            equation="[F8]-[F9], docs/franka.md", optimum="[F10]")

    def solve(self, poses: ArrayLike, t: np.ndarray, rows: np.ndarray | None) -> Solutions:
        one = rows is not None and len(rows) == 1
        result = ik(self.geometry, poses, t, BRANCHES[rows[0]] if one else None)  # type: ignore[index]
        q, exists, within = result.q, result.exists, result.within_limits
        if rows is not None and not one:
            q, exists, within = q[..., rows, :], exists[..., rows], within[..., rows]
        labels = LABELS if rows is None else tuple(LABELS[r] for r in rows)

        def measured() -> Reach:
            return reach(self.geometry, poses)

        return Solutions(q, exists, within, labels, CLOSED_FORM, t, lambda: measured().out, measured,
                         "no solution of the branch at this q7")

    def optimal(self, pose: np.ndarray, row: int, target: np.ndarray | None,
                weights: tuple[float, float] | None, within: Arcs | None = None) -> tuple[float, float]:
        """[F10]'s minimiser over the feasible set (or over the intervals ``within`` it) and over every q7."""
        self._no_weights(weights)
        sets = None
        if within is not None:  # the branch's intervals in place of its feasible set; the others' are not read
            empty = np.empty((0, 2))
            low, high = q7_domain(self.geometry)
            sets = FeasibleQ7(tuple(within.bounds if b == row else empty for b in range(len(BRANCHES))),
                              (float(low), float(high)), BRANCHES)
        best = optimal_q7(self.geometry, pose, BRANCHES[row], target=target, feasible=sets)
        return value(best.feasible), value(best.unclamped)

    def analyse(self, pose: np.ndarray, rows: np.ndarray, target: np.ndarray | None,
                weights: tuple[float, float] | None) -> Analysis:
        """[F8]-[F10] at one pose: the feasible q7 of every branch and the limit-avoiding q7; no per-joint sets and no
        singular values (where q2 passes through 0 a branch's q1 and q3 may jump); raises
        :class:`redkin.errors.UnreachablePoseError` where no q7 reaches the pose (:func:`redkin.franka.ik.reach`)."""
        self._no_weights(weights)
        check_in_reach(reach(self.geometry, pose))
        sets = feasible_q7(self.geometry, pose)
        arcs = tuple(as_arcs(pieces) for pieces in sets.arcs)
        low, high = self.parameter.domain

        def branch(row: int) -> BranchAnalysis:
            best = optimal_q7(self.geometry, pose, BRANCHES[row], target=target, feasible=sets)
            full = len(arcs[row]) == 1 and arcs[row][0, 0] <= low and arcs[row][0, 1] >= high
            return BranchAnalysis(LABELS[row], arcs[row], bool(full),
                                  {"overall": (value(best.unclamped), value(best.feasible))})

        return Analysis(self.parameter, self.method, arcs, tuple(branch(int(row)) for row in rows))

    def _no_weights(self, weights: tuple[float, float] | None) -> None:
        if weights is not None:
            raise RedkinError(f"weights weigh the shoulder against the wrist in the optimal arm angle of S-R-S arms; "
                              f"{self.chain.name!r} is of the Franka class (parameter q7): leave them out")
