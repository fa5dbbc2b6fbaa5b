"""The explorer's numbers for nearly S-R-S arms (the Kinova Gen3 and Jaco2, the ROS-Industrial iiwa), on the real arm.

The page is the arm-angle page (:mod:`redkin.explore.arm_angle`), filled from the real arm's functions
(docs/srs.md, "Nearly S-R-S arms"): for each of the eight branches a dense grid of arm angles with the ends of the
real feasible set (:func:`redkin.srs.feasible_arm_angles_nearly`), the singular arm angles
(:func:`redkin.srs.singular_arm_angles_nearly`) and the optima clamped and not
(:func:`redkin.srs.optimal_arm_angles_nearly`) merged in; the joint values are the real arm's certified solutions
(:func:`redkin.srs.nearly.ik`), each joint turned by whole turns nearest the middle of its range, NaN where none
was found, and at a singular arm angle the aligned configuration itself.  What the page cannot draw it says in a
line: the per-joint sets (not computed on such arms) and the arm angles where no certified solution was found.
The neighbour and the model error are stated on the page.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from redkin.chain import SerialChain
from redkin.circle import wrap_angle
from redkin.errors import UnreachablePoseError
from redkin.explore.arm_angle import ARM_ANGLE, on_circle
from redkin.explore.curves import BranchCurves, Mark, Parameter, as_arcs, postures
from redkin.srs import (
    BRANCHES,
    NearlySRS,
    feasible_arm_angles_nearly_all,
    nearly_srs,
    optimal_arm_angles_nearly,
    singular_arm_angles_nearly,
)
from redkin.srs.nearly import ik
from redkin.srs.nearly.feasible import NearlyFeasible

#: Arm angles closer than this [rad] are one mark (an optimum that needed no clamping).
_SAME_ANGLE = 1e-12
#: What a singular arm angle of the real arm means for the values shown there.
_SINGULAR_NOTE = ("axes {0} of the real arm are parallel or antiparallel here: the branch's sign of {1} changes, "
                  "and the values shown are the aligned configuration")


def remarks_of(arm: NearlySRS) -> tuple[str, ...]:
    """The lines a nearly S-R-S arm's page states: the neighbour and the model error, and what it cannot draw."""
    return (f"{arm.chain.name} is nearly S-R-S: {arm.describe()}.",
            "The per-joint sets Ψi are not computed on nearly S-R-S arms: the dashed limits show which joint closes "
            "an arc of Ψ.")


def nearly_curves(chain: SerialChain, pose: np.ndarray, samples: int, target, weights,
                  tolerance: float, also: tuple[float, ...] = ()) -> tuple[Parameter, tuple[BranchCurves, ...]]:
    """The arm angle and every branch of the nearly S-R-S ``chain`` (within ``tolerance`` of its neighbour) at
    ``pose`` over a grid of ``samples`` arm angles in ``[-pi, pi]`` and the arm angles ``also`` (module
    docstring).

    Raises
    ------
    UnreachablePoseError
        Where no branch has a certified solution at any arm angle of the grid.
    """
    arm = nearly_srs(chain, tolerance)
    grid = np.union1d(np.linspace(-np.pi, np.pi, samples), [on_circle(value) for value in also])
    weights = (0.5, 0.5) if weights is None else weights
    parameter = replace(ARM_ANGLE, optimum="[000 eq. 40] on the real arm",
                        method="the exact S-R-S neighbour's closed form polished on the real nearly S-R-S arm, "
                               "its feasible sets, singular and optimal arm angles located on the real arm")
    sets = feasible_arm_angles_nearly_all(arm, pose)
    branches = tuple(_branch_curves(arm, pose, b, grid, target, weights, sets[k]) for k, b in enumerate(BRANCHES))
    if not any(b.exists.any() for b in branches):
        raise UnreachablePoseError(f"{chain.name} cannot reach this pose: no branch has a certified solution at any "
                                   f"of {samples} arm angles")
    return parameter, branches


def _branch_curves(arm: NearlySRS, pose: np.ndarray, branch, grid: np.ndarray, target, weights,
                   result: NearlyFeasible) -> BranchCurves:
    feasible = result.feasible
    singular = singular_arm_angles_nearly(arm, pose, branch)
    optimal = optimal_arm_angles_nearly(arm, pose, branch, target=target, weights=weights, feasible=feasible,
                                        curves=result.curves)
    special: list[tuple[str, str, float, str]] = []
    for k, (lo, hi) in enumerate([] if feasible.is_full else feasible.arcs):
        special += [("feasible", f"Ψ arc {k + 1} starts", lo, ""), ("feasible", f"Ψ arc {k + 1} ends", hi, "")]
    aligned = [(value, q) for part in ("shoulder", "wrist")
               for value, q in zip(getattr(singular, part), getattr(singular, f"{part}_q"))]
    special += [("singular", "shoulder singular ψ (axes 1, 3 on one line)", a, _SINGULAR_NOTE.format("1 and 3", "θ2"))
                for a in singular.shoulder]
    special += [("singular", "wrist singular ψ (axes 5, 7 on one line)", a, _SINGULAR_NOTE.format("5 and 7", "θ6"))
                for a in singular.wrist]
    overall = optimal.overall
    if np.isfinite(overall.unclamped):
        special.append(("optimal", "optimal ψ ([000 eq. 40], real arm)", overall.unclamped, ""))
    if overall.feasible is not None and not (np.isfinite(overall.unclamped) and abs(
            float(wrap_angle(overall.feasible - overall.unclamped))) <= _SAME_ANGLE):
        special.append(("optimal", "optimal ψ clamped to Ψ", overall.feasible, ""))
    special = [(kind, label, on_circle(value), note) for kind, label, value, note in special]
    psi = np.unique(np.concatenate([grid, [value for _, _, value, _ in special]]))
    solutions = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    exists = solutions.exists[:, 0].copy()
    q = np.where(exists[:, None], solutions.q[:, 0], np.nan)
    for value, configuration in aligned:  # the aligned configuration itself, where nearly.ik is ill-conditioned
        index = int(np.argmin(np.abs(psi - on_circle(value))))
        q[index], exists[index] = configuration, True
    middle = np.broadcast_to(arm.chain.middle, q[exists].shape)
    q[exists] = arm.chain.nearest_in_range(q[exists], middle)  # each turn as drawn against the limits
    origins, within = postures(arm.chain, q, exists)
    marks = tuple(Mark(kind, label, int(np.searchsorted(psi, value)), note) for kind, label, value, note in special)
    first = overall.feasible if overall.feasible is not None else (
        overall.unclamped if np.isfinite(overall.unclamped) else 0.0)
    start = int(np.argmin(np.abs(psi - on_circle(first))))
    notes = []
    missing = int(np.count_nonzero(~exists))
    if missing == len(psi):
        notes.append("This branch has no certified solution at any ψ of the grid for this pose.")
    elif missing:
        notes.append(f"No certified solution was found at {missing} of {len(psi)} ψ of the grid (near singular "
                     "configurations of the real arm): the curves break there.")
    return BranchCurves(str(singular.branch), psi, q, exists, origins, within,
                        np.asarray(feasible.contains(psi, _SAME_ANGLE)), as_arcs(feasible.arcs), feasible.is_full,
                        None, marks, start, tuple(notes))

