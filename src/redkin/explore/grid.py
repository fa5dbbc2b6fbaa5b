"""One branch over a grid of its redundancy parameter, for every class of arm (:meth:`redkin.arms.Arm.analyse`).

The grid is dense over the parameter's domain with every special value merged in exactly: the ends of the feasible
set (and of the per-joint sets where the class has them), the singular and the optimal values.  On it: the branch's
solution at each value (:meth:`redkin.arms.Arm.ik`; none where the branch does not exist there), each joint turned
by whole turns nearest the middle of its range, the postures, the limit flags and membership of the feasible set.
At a singular value the two joints about the common axis are fixed only in their combination: the values shown are
the split the solver chooses, or the aligned configuration itself where the class locates it on the real arm.
"""

from __future__ import annotations

import numpy as np

from redkin.arms import Arm
from redkin.arms.analysis import SAME_VALUE, Analysis, BranchAnalysis, in_arcs
from redkin.circle import wrap_angle
from redkin.explore.curves import BranchCurves, Mark, postures


def branch_curves(arm: Arm, pose: np.ndarray, analysis: Analysis, branch: BranchAnalysis,
                  grid: np.ndarray) -> BranchCurves:
    """``branch`` of ``analysis`` (of ``arm`` at ``pose``) over ``grid`` (sorted values in the parameter's domain)
    with its special values merged in (module docstring)."""
    parameter, chain = analysis.parameter, arm.chain
    special = [(kind, label, _in_domain(analysis, value), note)
               for kind, label, value, note in _special(analysis, branch)]
    ends = [] if branch.per_joint is None else [end for arcs in branch.per_joint.values() for end in arcs.ravel()]
    values = np.unique(np.concatenate([grid, [_in_domain(analysis, end) for end in ends],
                                       [value for _, _, value, _ in special]]))
    solved = arm.ik(np.broadcast_to(pose, values.shape + (4, 4)), values, branches=branch.branch)
    exists = solved.exists[:, 0].copy()
    q = np.where(exists[:, None], solved.q[:, 0], np.nan)
    for part in (branch.singular or {}).values():
        for value, configuration in zip(part.values, () if part.configurations is None else part.configurations):
            index = int(np.argmin(np.abs(values - _in_domain(analysis, value))))
            q[index], exists[index] = configuration, True  # where the solver is ill-conditioned
    q[exists] = chain.nearest_in_range(q[exists])
    origins, within = postures(chain, q, exists)
    marks = tuple(Mark(kind, label, int(np.searchsorted(values, value)), note) for kind, label, value, note in special)
    start = int(np.argmin(np.abs(values - _in_domain(analysis, branch.start))))
    notes = [f"The {name} is singular at every {parameter.symbol} for this pose."
             for name, part in (branch.singular or {}).items() if part.everywhere]
    missing = int(np.count_nonzero(~exists))
    if missing == len(values):
        notes.append(f"This branch has no {analysis.solution} at any {parameter.symbol} of the grid for this pose.")
    elif missing:
        notes.append(f"No {analysis.solution} was found at {missing} of the {len(values)} {parameter.plural} of the "
                     "grid: the curves break there.")
    per_joint = None if branch.per_joint is None else tuple(branch.per_joint[j + 1] for j in range(chain.n))
    return BranchCurves(branch.branch, values, q, exists, origins, within, in_arcs(values, branch.arcs), branch.arcs,
                        branch.full, per_joint, marks, start, tuple(notes))


def _special(analysis: Analysis, branch: BranchAnalysis) -> list[tuple[str, str, float, str]]:
    """``(kind, label, value, note)`` of the marked values of one branch: the feasible set's ends, the singular
    values, the overall optimum and, where it differs, the optimum clamped to the feasible set."""
    symbol, sets = analysis.parameter.symbol, analysis.parameter.set_symbol
    special: list[tuple[str, str, float, str]] = []
    for k, (lo, hi) in enumerate([] if branch.full else branch.arcs):
        special += [("feasible", f"{sets} arc {k + 1} starts", lo, ""),
                    ("feasible", f"{sets} arc {k + 1} ends", hi, "")]
    for name, part in (branch.singular or {}).items():
        special += [("singular", f"{name} singular {symbol} ({part.marks})", value, part.note) for value in part.values]
    unclamped, feasible = branch.optimal["overall"]
    if np.isfinite(unclamped):
        special.append(("optimal", f"optimal {symbol} ({analysis.parameter.optimum})", unclamped, ""))
    apart = abs(feasible - unclamped) if not analysis.parameter.wraps else abs(float(wrap_angle(feasible - unclamped)))
    if np.isfinite(feasible) and not (np.isfinite(unclamped) and apart <= SAME_VALUE):
        special.append(("optimal", f"optimal {symbol} clamped to {sets}", feasible, ""))
    return special


def _in_domain(analysis: Analysis, value: float) -> float:
    """``value`` of a parameter that wraps in ``[-pi, pi]``, unchanged where it is there already (wrapping could move
    it by a rounding); any other parameter's value as it is."""
    value = float(value)
    return value if not analysis.parameter.wraps or -np.pi <= value <= np.pi else float(wrap_angle(value))
