"""Every number the arm-angle explorer shows, computed with redkin's public S-R-S functions.

For each of the eight branches: a dense grid of arm angles with every
special arm angle merged in exactly (the ends of each per-joint set Psi_i and
of the feasible set Psi, the singular and the optimal arm angles), the joint
values on it, the frame origins of the posture at each grid point, which
joint values are within their limits, and which grid points lie in Psi.
At a singular arm angle the two joints about the common axis are fixed only
in their combination: the joint values there are the split :func:`ik`
chooses, and may be outside the limits although psi lies in the closed set Psi.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.circle import ArcSet, wrap_angle
from redkin.srs import (
    BRANCHES,
    OptimalArmAngles,
    SingularArmAngles,
    feasible_arm_angles,
    ik,
    optimal_arm_angles,
    parse_branch,
    singular_arm_angles,
)

#: Arm angles of the dense grid over [-pi, pi] (0.5 deg apart), before the special ones are merged in.
GRID_SAMPLES = 721
#: Arm angles closer than this [rad] are one: an optimum that needed no clamping is one mark, and Psi holds the
#: arm angles this close to its ends (its ends and the per-joint ends it came from differ by roundings).
_SAME_ANGLE = 1e-12
#: A joint value this far [rad] beyond a limit counts as within it (the value at a set's end, rounded).
_LIMIT_TOLERANCE = 1e-9
#: What a singular arm angle means for the joint values shown there.
_SINGULAR_NOTE = {
    "shoulder": ("joints 1 and 3 turn about one axis here: only their combination is fixed, the values shown are "
                 "one split"),
    "wrist": "joints 5 and 7 turn about one axis here: only their combination is fixed, the values shown are one split",
}
#: Stated limits of ``samples``.
MIN_SAMPLES, MAX_SAMPLES = 16, 20_000


@dataclass(frozen=True)
class Mark:
    """A special arm angle on a branch's grid: its kind (``feasible``, ``optimal``, ``singular``), label, index
    and note."""

    kind: str
    label: str
    index: int
    note: str = ""


@dataclass(frozen=True)
class BranchCurves:
    """One branch over the arm angle.

    Attributes
    ----------
    branch : str
        Signs of theta_2, theta_4, theta_6, e.g. ``"+-+"``.
    psi : numpy.ndarray, shape (G,)
        Sorted arm angles in ``[-pi, pi]`` [rad]: the dense grid and the special arm angles.
    q : numpy.ndarray, shape (G, n)
        Joint values of the chain at each arm angle [rad].
    origins : numpy.ndarray, shape (G, n + 2, 3)
        Base, joint-frame and tool origins of the posture [m] (``SerialChain.frames``).
    within : numpy.ndarray of bool, shape (G, n)
        Whether each joint value is within its limits (to :data:`_LIMIT_TOLERANCE`).
    feasible_at : numpy.ndarray of bool, shape (G,)
        Whether each arm angle lies in ``Psi`` (within :data:`_SAME_ANGLE` of it).
    per_joint : dict of int to ArcSet
        ``Psi_i`` (joints numbered from 1).
    feasible : ArcSet
        ``Psi``.
    singular : SingularArmAngles
    optimal : OptimalArmAngles
    marks : tuple of Mark
        The feasible-set ends, singular and optimal arm angles, with their indices into ``psi``.
    start : int
        Index shown first: the optimal arm angle clamped to ``Psi``, else the grid point nearest psi = 0.
    """

    branch: str
    psi: np.ndarray
    q: np.ndarray
    origins: np.ndarray
    within: np.ndarray
    feasible_at: np.ndarray
    per_joint: dict[int, ArcSet]
    feasible: ArcSet
    singular: SingularArmAngles
    optimal: OptimalArmAngles
    marks: tuple[Mark, ...]
    start: int


@dataclass(frozen=True)
class ExplorerData:
    """The explorer's numbers for one arm and one pose: every branch, the limits and the branch shown first."""

    robot: str
    joint_names: tuple[str, ...]
    pose: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    branches: tuple[BranchCurves, ...]
    initial: int


def explorer_data(
    chain: SerialChain,
    pose: ArrayLike,
    branch: str = "+++",
    target: ArrayLike | None = None,
    weights: ArrayLike = (0.5, 0.5),
    samples: int = GRID_SAMPLES,
) -> ExplorerData:
    """The numbers of an arm-angle explorer page for ``chain`` at ``pose``, all eight branches.

    Parameters
    ----------
    chain : SerialChain
        An arm with arm-angle IK (S-R-S, in any description :mod:`redkin.srs` accepts).
    pose : array_like, shape (4, 4)
        The tool pose in the base frame.
    branch : str
        The branch shown first (signs of theta_2, theta_4, theta_6).
    target, weights
        Target joint values and weights of the optimal arm angle [000 eq. 40], as
        :func:`redkin.srs.optimal_arm_angles` takes them.
    samples : int
        Points of the dense grid over ``[-pi, pi]``, from 16 to 20000.

    Returns
    -------
    ExplorerData

    Raises
    ------
    ValueError
        For an arm without arm-angle IK, a malformed or unreachable pose, a
        malformed branch, target or weights, or ``samples`` out of range.
    """
    if (isinstance(samples, bool) or not isinstance(samples, (int, np.integer))
            or not MIN_SAMPLES <= samples <= MAX_SAMPLES):
        raise ValueError(f"samples must be an integer from {MIN_SAMPLES} to {MAX_SAMPLES}, got {samples!r}")
    first = parse_branch(branch)
    pose = np.asarray(pose, dtype=float)
    grid = np.linspace(-np.pi, np.pi, int(samples))
    curves = tuple(_branch_curves(chain, pose, b, grid, target, weights) for b in BRANCHES)
    return ExplorerData(
        robot=chain.name,
        joint_names=tuple(chain.joint_names),
        pose=pose,
        lower=np.asarray(chain.lower, dtype=float),
        upper=np.asarray(chain.upper, dtype=float),
        branches=curves,
        initial=BRANCHES.index(first),
    )


def _branch_curves(chain: SerialChain, pose: np.ndarray, branch, grid: np.ndarray, target, weights) -> BranchCurves:
    result = feasible_arm_angles(chain, pose, branch)
    singular = singular_arm_angles(chain, pose, branch)
    optimal = optimal_arm_angles(chain, pose, branch, target=target, weights=weights, feasible=result.feasible)
    special = _special_angles(result.feasible, singular, optimal)
    sets = list(result.per_joint.values()) + [result.feasible]
    arc_ends = [end for arcs in sets for interval in arcs.intervals for end in interval]
    psi = np.unique(np.concatenate([grid, arc_ends, [value for _, _, value, _ in special]]))
    q = ik(chain, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    origins = chain.frames(q)[..., :3, 3]
    within = (q >= chain.lower - _LIMIT_TOLERANCE) & (q <= chain.upper + _LIMIT_TOLERANCE)
    marks = tuple(Mark(kind, label, int(np.searchsorted(psi, value)), note) for kind, label, value, note in special)
    clamped = optimal.overall.feasible
    start = int(np.argmin(np.abs(psi - (0.0 if clamped is None else _on_circle(float(clamped))))))
    in_set = np.asarray(result.feasible.contains(psi, _SAME_ANGLE))
    return BranchCurves(str(branch), psi, q, origins, within, in_set, dict(result.per_joint),
                        result.feasible, singular, optimal, marks, start)


def _special_angles(feasible: ArcSet, singular: SingularArmAngles,
                    optimal: OptimalArmAngles) -> list[tuple[str, str, float, str]]:
    """``(kind, label, psi, note)`` of the marked arm angles, psi in ``[-pi, pi]``."""
    special: list[tuple[str, str, float, str]] = []
    for k, (lo, hi) in enumerate([] if feasible.is_full else feasible.arcs):
        special += [("feasible", f"Ψ arc {k + 1} starts", lo, ""), ("feasible", f"Ψ arc {k + 1} ends", hi, "")]
    special += [("singular", "shoulder singular ψ (θ2 = 0)", a, _SINGULAR_NOTE["shoulder"]) for a in singular.shoulder]
    special += [("singular", "wrist singular ψ (θ6 = 0)", a, _SINGULAR_NOTE["wrist"]) for a in singular.wrist]
    special.append(("optimal", "optimal ψ ([000 eq. 40])", optimal.overall.unclamped, ""))
    clamped = optimal.overall.feasible
    if clamped is not None and abs(float(wrap_angle(float(clamped) - float(optimal.overall.unclamped)))) > _SAME_ANGLE:
        special.append(("optimal", "optimal ψ clamped to Ψ", clamped, ""))
    return [(kind, label, _on_circle(float(value)), note) for kind, label, value, note in special]


def _on_circle(angle: float) -> float:
    """``angle`` in ``[-pi, pi]``: unchanged when it is there already (wrapping could move it by a rounding)."""
    return angle if -np.pi <= angle <= np.pi else float(wrap_angle(angle))
