"""The limit-avoiding arm angle of a nearly S-R-S arm, on the real arm ([000 eqs. 36-40] evaluated on its polished
joint values).

Paper 000's objective [000 eq. 40] is ``r_s f_s + r_w f_w`` with ``f_s = trace(0R3 0R3d^T)`` [000 eq. 36] and
``f_w = trace(4R7 4R7d^T)`` [000 eq. 38]: how near the shoulder's and the wrist's rotations are to those of target
joint values.  On an exact arm they are sinusoids of the arm angle, maximised in closed form [000 eqs. 37, 39, 40]
and clamped to the nearest feasible arm angle.  On a nearly S-R-S arm the rotations are those of the real arm's
certified solution ``q(psi)`` (:func:`redkin.srs.nearly.ik`), read through the neighbour's shoulder and wrist
frames at the same joint values, and the objective is a sinusoid only to within the model error, so
:func:`optimal_arm_angles_nearly`

* evaluates each objective (shoulder, wrist, weighted) at the solutions on a grid of :data:`_SAMPLES` arm angles
  with the neighbour's own optima [000 eqs. 37, 39, 40] merged in, and takes the best;
* locates the maximum between the best sample's neighbours by bisection on the objective's derivative along the
  self-motion (:func:`redkin.srs.nearly_search.located_extremum`) to 1e-10 rad: the **unclamped** optimum;
* does the same over the real feasible set (:func:`redkin.srs.nearly_feasible.feasible_arm_angles_nearly`), each
  arc sampled at least as densely with its ends: the optimum **clamped** to the feasible set, an arc's end where the
  objective still rises there.

What is not claimed: a maximum narrower than the grid that the neighbour's optima do not announce.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose, check_vectors
from redkin.circle import TWO_PI, ArcSet
from redkin.errors import RedkinError
from redkin.srs._rotations import group_rotations
from redkin.srs.branches import Branch, parse_branch
from redkin.srs.nearly import NearlySRS
from redkin.srs.nearly_feasible import feasible_arm_angles_nearly
from redkin.srs.nearly_search import located_extremum, merged, solutions_at
from redkin.srs.optimal import OptimalAngle, OptimalArmAngles, check_weights, optimal_arm_angles, weighted_objective

#: Arm angles of the uniform grid over the circle; each feasible arc is sampled at least as densely.
_SAMPLES = 720
#: The objectives, in the order :func:`_objective_values` returns them.
_PARTS = ("shoulder", "wrist", "overall")


@dataclass(frozen=True)
class NearlyOptimal:
    """The limit-avoiding arm angles of one pose and branch of a nearly S-R-S arm (module docstring).

    Attributes
    ----------
    shoulder, wrist, overall : OptimalAngle
        The maxima of [000 eqs. 36, 38, 40] on the real arm: ``unclamped`` over the arm angles where the branch has
        a certified solution (``nan`` where it has none), ``feasible`` over the feasible set (``None`` where that is
        empty).
    branch : Branch
    weights : tuple of float
        ``(r_s, r_w)``.
    target : numpy.ndarray, shape (7,)
        The target joint values ``theta^d``.
    feasible : ArcSet
        The real arm's feasible set the optima were clamped to.
    neighbour : OptimalArmAngles or None
        The exact neighbour's optima [000 eqs. 37, 39, 40], clamped to the neighbour's own feasible set; ``None``
        where the neighbour cannot reach the pose.
    """

    shoulder: OptimalAngle
    wrist: OptimalAngle
    overall: OptimalAngle
    branch: Branch
    weights: tuple[float, float]
    target: np.ndarray
    feasible: ArcSet
    neighbour: OptimalArmAngles | None


def _objective_values(arm: NearlySRS, q: np.ndarray, target: np.ndarray,
                     weights: tuple[float, float]) -> np.ndarray:
    """``f_s`` [000 eq. 36], ``f_w`` [000 eq. 38] and their weighted sum [000 eq. 40] at joint values ``q``
    (..., 7), stacked on a leading axis of 3: the shoulder's and wrist's rotations through the neighbour's frames at
    the same joint values, against those at ``target`` (7,)."""
    shoulder, wrist = group_rotations(arm.geometry, q)
    shoulder_target, wrist_target = group_rotations(arm.geometry, target)
    f_s = np.einsum("...ij,ij->...", shoulder, shoulder_target)  # [000 eq. 36]
    f_w = np.einsum("...ij,ij->...", wrist, wrist_target)  # [000 eq. 38]
    return np.stack([f_s, f_w, weighted_objective(f_s, f_w, weights)])  # [000 eq. 40]


def optimal_arm_angles_nearly(
    arm: NearlySRS,
    pose: ArrayLike,
    branch: str | Branch = "+++",
    target: ArrayLike | None = None,
    weights: ArrayLike = (0.5, 0.5),
    feasible: ArcSet | None = None,
) -> NearlyOptimal:
    """The arm angles of one pose and branch that maximise [000 eqs. 36, 38, 40] on the real arm, unclamped and
    within the real feasible set (module docstring).

    Parameters
    ----------
    arm : NearlySRS
        From :func:`redkin.srs.nearly_srs`.
    pose : array_like, shape (4, 4)
    branch : str or Branch
    target : array_like, shape (7,), optional
        Target joint values ``theta^d`` in the chain's ``q`` (joint 4 is not used); default the middles of the
        joint ranges.
    weights : (r_s, r_w)
        Weights of [000 eq. 40].
    feasible : ArcSet, optional
        The real arm's feasible set of the branch (:func:`redkin.srs.feasible_arm_angles_nearly`); computed when
        not given.

    Raises
    ------
    ValueError
        For a malformed pose, branch, target or weights.
    """
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
    label = parse_branch(branch)
    q_target = arm.chain.middle if target is None else check_vectors(target, 7, "target")
    if q_target.shape != (7,):
        raise RedkinError(f"target must have shape (7,), got {q_target.shape}")
    chosen = check_weights(weights)
    if feasible is None:
        feasible = feasible_arm_angles_nearly(arm, pose, label).feasible
    neighbour = _neighbour_optimal(arm, pose, label, q_target, chosen)
    hints = [] if neighbour is None else [getattr(neighbour, part).unclamped for part in _PARTS]
    circle = np.linspace(-np.pi, np.pi, _SAMPLES, endpoint=False)
    grid = merged(circle, np.array(hints, dtype=float))

    def objective(k: int):
        return lambda values: _objective_values(arm, values, q_target, chosen)[k]

    q, exists = solutions_at(arm, pose, grid, label)
    values = np.where(exists, _objective_values(arm, q, q_target, chosen), -np.inf)
    unclamped = [_maximum(arm, pose, label, objective(k), grid, q, values[k], circular=True) for k in range(3)]
    clamped = [u if u is not None and feasible.contains(u[0]) else None for u in unclamped]
    pending = [k for k in range(3) if clamped[k] is None]  # the optima outside the feasible set
    for start, end in feasible.arcs if pending else []:
        length = (end - start) % TWO_PI
        psi = start + np.linspace(0.0, length, max(8, int(np.ceil(length / TWO_PI * _SAMPLES)) + 1))
        q, exists = solutions_at(arm, pose, psi, label)
        arc_values = np.where(exists, _objective_values(arm, q, q_target, chosen), -np.inf)
        for k in pending:
            found, kept = _maximum(arm, pose, label, objective(k), psi, q, arc_values[k], circular=False), clamped[k]
            if found is not None and (kept is None or found[1] > kept[1]):
                clamped[k] = found
    angles = [OptimalAngle(float(np.nan) if u is None else u[0], None if c is None else c[0])
              for u, c in zip(unclamped, clamped)]
    return NearlyOptimal(angles[0], angles[1], angles[2], label, chosen, q_target, feasible, neighbour)


def _neighbour_optimal(arm: NearlySRS, pose: np.ndarray, label: Branch, target: np.ndarray,
                       weights: tuple[float, float]) -> OptimalArmAngles | None:
    """The neighbour's optima [000 eqs. 37, 39, 40], or ``None`` where the neighbour does not reach the pose."""
    from redkin.srs.ik import reachable

    if not reachable(arm.geometry, pose):
        return None
    return optimal_arm_angles(arm.geometry, pose, label, target=target, weights=weights)


def _maximum(arm: NearlySRS, pose: np.ndarray, label: Branch, objective, psi: np.ndarray, q: np.ndarray,
             values: np.ndarray, circular: bool) -> tuple[float, float] | None:
    """The maximum of the objective over sorted arm angles ``psi`` with solutions ``q`` and sampled ``values``
    (``-inf`` where no solution), located between the best sample's neighbours along the self-motion through it
    (:func:`redkin.srs.nearly_search.located_extremum`), and its value; ``None`` where no sample has a solution.
    On a circular grid the first and last samples are neighbours; otherwise the ends bound the search (an arc's
    ends)."""
    if not np.isfinite(values).any():
        return None
    best = int(np.argmax(values))
    count = len(psi)
    if circular:
        low = psi[best - 1] - (TWO_PI if best == 0 else 0.0)
        high = psi[(best + 1) % count] + (TWO_PI if best == count - 1 else 0.0)
    else:
        low, high = psi[max(best - 1, 0)], psi[min(best + 1, count - 1)]
    located, q_located = located_extremum(arm, pose, label, objective, (float(psi[best]), q[best]), float(low),
                                          float(high), maximum=True)
    value = float(objective(q_located[None])[0])
    if value < values[best]:
        return float(np.angle(np.exp(1j * psi[best]))), float(values[best])
    return located, value
