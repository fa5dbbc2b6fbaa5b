"""The explorer's numbers for arms whose redundancy parameter is the arm angle psi (S-R-S and offset elbows).

For each of the eight branches: a dense grid of arm angles with every
special arm angle merged in exactly (the ends of each per-joint set Psi_i and
of the feasible set Psi, the singular and the optimal arm angles), the joint
values on it, the frame origins of the posture at each grid point, which
joint values are within their limits, and which grid points lie in Psi, all
from the public :mod:`redkin.srs` functions.  At a singular arm angle the two
joints about the common axis are fixed only in their combination: the joint
values there are the split :func:`redkin.srs.ik` chooses, and may be outside
the limits although psi lies in the closed set Psi.
"""

from __future__ import annotations

import numpy as np

from redkin.chain import SerialChain
from redkin.circle import ArcSet, wrap_angle
from redkin.explore.curves import BranchCurves, Mark, Parameter, as_arcs, postures
from redkin.srs import (
    BRANCHES,
    OptimalArmAngles,
    SingularArmAngles,
    feasible_arm_angles,
    ik,
    optimal_arm_angles,
    singular_arm_angles,
)

#: Arm angles closer than this [rad] are one: an optimum that needed no clamping is one mark, and Psi holds the
#: arm angles this close to its ends (its ends and the per-joint ends it came from differ by roundings).
_SAME_ANGLE = 1e-12
#: What a singular arm angle means for the joint values shown there.
_SINGULAR_NOTE = {
    "shoulder": ("joints 1 and 3 turn about one axis here: only their combination is fixed, the values shown are "
                 "one split"),
    "wrist": "joints 5 and 7 turn about one axis here: only their combination is fixed, the values shown are one split",
}
#: The arm angle as the page names it (a nearly S-R-S arm's page, :mod:`redkin.explore.nearly`, changes its method).
ARM_ANGLE = Parameter(
    name="psi", symbol="ψ", set_symbol="Ψ", noun="arm angle", plural="arm angles", title="Arm-angle explorer",
    joint_symbol="θ", branches="signs of theta 2, 4, 6", optimum="[000 eq. 40]",
    method="paper 000's closed-form arm-angle IK and exact feasible sets", domain=(-np.pi, np.pi), circular=True,
    kinds=("feasible", "singular", "optimal"),
)


def arm_angle_curves(chain: SerialChain, pose: np.ndarray, samples: int, target,
                     weights, also: tuple[float, ...] = ()) -> tuple[Parameter, tuple[BranchCurves, ...]]:
    """The arm angle and every branch of ``chain`` at ``pose`` over a grid of ``samples`` arm angles in
    ``[-pi, pi]``.

    ``target`` and ``weights`` are those of the optimal arm angle [000 eq. 40] (default: the limit midpoints,
    0.5 and 0.5); the arm angles ``also`` join the grid.  Raises the ValueError of :mod:`redkin.srs` for an arm it
    does not serve or an unreachable pose.
    """
    grid = np.union1d(np.linspace(-np.pi, np.pi, samples), [on_circle(value) for value in also])
    weights = (0.5, 0.5) if weights is None else weights
    return ARM_ANGLE, tuple(_branch_curves(chain, pose, b, grid, target, weights) for b in BRANCHES)


def _branch_curves(chain: SerialChain, pose: np.ndarray, branch, grid: np.ndarray, target, weights) -> BranchCurves:
    result = feasible_arm_angles(chain, pose, branch)
    singular = singular_arm_angles(chain, pose, branch)
    optimal = optimal_arm_angles(chain, pose, branch, target=target, weights=weights, feasible=result.feasible)
    special = _special_angles(result.feasible, singular, optimal)
    sets = list(result.per_joint.values()) + [result.feasible]
    arc_ends = [end for arcs in sets for interval in arcs.intervals for end in interval]
    psi = np.unique(np.concatenate([grid, arc_ends, [value for _, _, value, _ in special]]))
    q = ik(chain, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    exists = np.ones(len(psi), dtype=bool)
    origins, within = postures(chain, q, exists)
    marks = tuple(Mark(kind, label, int(np.searchsorted(psi, value)), note) for kind, label, value, note in special)
    clamped = optimal.overall.feasible
    start = int(np.argmin(np.abs(psi - (0.0 if clamped is None else on_circle(float(clamped))))))
    in_set = np.asarray(result.feasible.contains(psi, _SAME_ANGLE))
    notes = tuple(f"The {part} is singular at every ψ for this pose." for part, every in
                  (("shoulder", singular.shoulder_everywhere), ("wrist", singular.wrist_everywhere)) if every)
    per_joint = tuple(as_arcs(result.per_joint[j + 1].arcs) for j in range(chain.n))
    return BranchCurves(str(branch), psi, q, exists, origins, within, in_set, as_arcs(result.feasible.arcs),
                        result.feasible.is_full, per_joint, marks, start, notes)


def _special_angles(feasible: ArcSet, singular: SingularArmAngles,
                    optimal: OptimalArmAngles) -> list[tuple[str, str, float, str]]:
    """``(kind, label, psi, note)`` of the marked arm angles, psi in ``[-pi, pi]``."""
    special: list[tuple[str, str, float, str]] = []
    for k, (lo, hi) in enumerate([] if feasible.is_full else feasible.arcs):
        special += [("feasible", f"Ψ arc {k + 1} starts", lo, ""), ("feasible", f"Ψ arc {k + 1} ends", hi, "")]
    special += [("singular", "shoulder singular ψ (θ2 = 0 or π)", a, _SINGULAR_NOTE["shoulder"])
                for a in singular.shoulder]
    special += [("singular", "wrist singular ψ (θ6 = 0 or π)", a, _SINGULAR_NOTE["wrist"]) for a in singular.wrist]
    special.append(("optimal", "optimal ψ ([000 eq. 40])", optimal.overall.unclamped, ""))
    clamped = optimal.overall.feasible
    if clamped is not None and abs(float(wrap_angle(float(clamped) - float(optimal.overall.unclamped)))) > _SAME_ANGLE:
        special.append(("optimal", "optimal ψ clamped to Ψ", clamped, ""))
    return [(kind, label, on_circle(float(value)), note) for kind, label, value, note in special]


def on_circle(angle: float) -> float:
    """``angle`` in ``[-pi, pi]``: unchanged when it is there already (wrapping could move it by a rounding)."""
    return angle if -np.pi <= angle <= np.pi else float(wrap_angle(angle))
