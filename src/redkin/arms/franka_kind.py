"""Franka-class arms as :class:`redkin.arms.Arm` asks them (docs/franka.md): the value q7 of joint 7, the closed form
at q7 [F1]-[F7] on every branch, the exact feasible q7 sets [F8]-[F9] and the limit-avoiding q7 [F10]."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.protocol import ArmKind, Parameter
from redkin.arms.solutions import CLOSED_FORM, Solutions
from redkin.arms.srs_kind import LABELS
from redkin.chain import Reach
from redkin.franka.feasible import q7_domain
from redkin.franka.geometry import FrankaGeometry
from redkin.franka.ik import ik, reach
from redkin.franka.optimal import optimal_q7
from redkin.paths.family import Q7Family
from redkin.srs.branches import BRANCHES


class FrankaKind(ArmKind):
    """A Franka-class arm converted once to the solver's form."""

    branches = LABELS
    exact = True

    def __init__(self, kind: str, geometry: FrankaGeometry) -> None:
        self.kind, self.geometry, self.chain = kind, geometry, geometry.chain
        self.family = Q7Family(geometry)
        low, high = q7_domain(geometry)  # joint 7's range, [-pi, pi] where it covers the circle
        self.parameter = Parameter("q7", (float(low), float(high)), False)

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
                weights: tuple[float, float] | None) -> tuple[float, float]:
        if weights is not None:
            from redkin.errors import RedkinError

            raise RedkinError(f"weights weigh the shoulder against the wrist in the optimal arm angle of S-R-S arms; "
                              f"{self.chain.name!r} is of the Franka class (parameter q7): leave them out")
        best = optimal_q7(self.geometry, pose, BRANCHES[row], target=target)
        return tuple(np.nan if value is None else value for value in (best.feasible, best.unclamped))  # type: ignore[return-value]
