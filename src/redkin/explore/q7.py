"""The explorer's numbers for Franka-class arms, whose redundancy parameter is q7 (docs/franka.md).

For each of the eight branches: a dense grid of q7 over joint 7's range (the
domain of :func:`redkin.franka.feasible_q7`) with the ends of the feasible
arcs and the optimal q7 (:func:`redkin.franka.optimal_q7`) merged in exactly,
the solution :func:`redkin.franka.ik` gives at each (none where the branch
does not exist there), the postures, the limit flags and membership of the
feasible arcs.  No singular values are marked: where q2 passes through 0
the branch's q1 and q3 may jump, and the curves show the jump.
"""

from __future__ import annotations

import numpy as np

from redkin.chain import SerialChain
from redkin.errors import RedkinError, UnreachablePoseError
from redkin.explore.curves import BranchCurves, Mark, Parameter, as_arcs, postures
from redkin.franka import FeasibleQ7, feasible_q7, ik, optimal_q7

#: Optima closer than this [rad] are one mark (an optimum that needed no clamping).
_SAME_VALUE = 1e-12


def q7_curves(chain: SerialChain, pose: np.ndarray, samples: int, target,
              weights, also: tuple[float, ...] = ()) -> tuple[Parameter, tuple[BranchCurves, ...]]:
    """q7 and every branch of the Franka-class ``chain`` at ``pose`` over ``samples`` values of q7 spanning joint
    7's range, and the values ``also`` within it.

    ``target`` is that of :func:`redkin.franka.optimal_q7` (default: the middle of each range).  ``weights``
    (the shoulder and wrist weights of the optimal arm angle) has no meaning for q7 and must be ``None``.

    Raises
    ------
    RedkinError
        For ``weights`` given, or a malformed pose or target.
    UnreachablePoseError
        Where no branch has a solution at any value of q7 on the grid.
    """
    if weights is not None:
        raise RedkinError(f"weights weigh the shoulder against the wrist in the optimal arm angle of S-R-S arms; "
                          f"{chain.name} is of the Franka class (parameter q7): leave them out")
    sets = feasible_q7(chain, pose)
    lo, hi = sets.domain
    grid = np.union1d(np.linspace(lo, hi, samples), [value for value in also if lo <= value <= hi])
    branches = tuple(_branch_curves(chain, pose, sets, k, grid, target) for k in range(len(sets.branches)))
    if not any(b.exists.any() for b in branches):
        raise UnreachablePoseError(f"{chain.name} cannot reach this pose: no branch has a solution at any of "
                                   f"{samples} values of q7 over joint 7's range [{lo:.6g}, {hi:.6g}] rad")
    parameter = Parameter(
        name="q7", symbol="q7", set_symbol="Q7", noun="q7", plural="values of q7", title="q7 explorer",
        joint_symbol="q", optimum="[F10]",
        branches="signs of the shoulder (q2), the elbow (either side of the longest reach) and the wrist (cos q5)",
        method="the Franka class's closed-form IK at a given q7 and its exact feasible q7 sets, docs/franka.md",
        domain=(lo, hi), circular=False, kinds=("feasible", "optimal"),
    )
    return parameter, branches


def _branch_curves(chain: SerialChain, pose: np.ndarray, sets: FeasibleQ7, index: int, grid: np.ndarray,
                   target) -> BranchCurves:
    branch = sets.branches[index]
    arcs = as_arcs(sets.arcs[index])
    optimal = optimal_q7(chain, pose, branch, target=target, feasible=sets)
    special = [(kind, f"Q7 arc {k + 1} {word}", value) for k, (start, end) in enumerate(arcs)
               for kind, word, value in (("feasible", "starts", start), ("feasible", "ends", end))]
    if optimal.unclamped is not None:
        special.append(("optimal", "optimal q7 ([F10])", optimal.unclamped))
    if optimal.feasible is not None and (optimal.unclamped is None
                                         or abs(optimal.feasible - optimal.unclamped) > _SAME_VALUE):
        special.append(("optimal", "optimal q7 clamped to Q7", optimal.feasible))
    values = np.unique(np.concatenate([grid, [value for _, _, value in special]]))
    solutions = ik(chain, pose, values, branch)
    exists = solutions.exists[:, 0]
    q = np.where(exists[:, None], solutions.q[:, 0], np.nan)
    origins, within = postures(chain, q, exists)
    feasible_at = np.any((arcs[:, :1] <= values) & (values <= arcs[:, 1:]), axis=0)
    marks = tuple(Mark(kind, label, int(np.searchsorted(values, value))) for kind, label, value in special)
    first = next((v for v in (optimal.feasible, optimal.unclamped) if v is not None), 0.0)
    start = int(np.argmin(np.abs(values - first)))
    notes = () if exists.any() else ("This branch has no solution at any q7 of the grid for this pose.",)
    full = len(arcs) == 1 and arcs[0, 0] <= sets.domain[0] and arcs[0, 1] >= sets.domain[1]
    return BranchCurves(str(branch), values, q, exists, origins, within, feasible_at, arcs, bool(full), None,
                        marks, start, notes)
