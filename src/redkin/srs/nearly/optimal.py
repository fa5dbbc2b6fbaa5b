"""The limit-avoiding arm angle of a nearly S-R-S arm, read off the pose's certified self-motion ([000 eqs. 36-40]
on the real arm's solutions; docs/srs.md, "The optimal arm angle").

Paper 000's objective [000 eq. 40] is ``r_s f_s + r_w f_w`` with ``f_s = trace(0R3 0R3d^T)`` [000 eq. 36] and
``f_w = trace(4R7 4R7d^T)`` [000 eq. 38]: how near the shoulder's and the wrist's rotations are to those of target
joint values.  On an exact arm they are sinusoids of the arm angle, maximised in closed form [000 eqs. 37, 39, 40]
and clamped to the nearest feasible arm angle.  On a nearly S-R-S arm they are functions of the real arm's
solutions, read through the neighbour's shoulder and wrist frames at the same joint values, and a branch can have two
solutions at one arm angle (the self-motion folds).  So :func:`optimal_arm_angles_nearly` maximises them over the
pose's certified self-motion (:func:`redkin.srs.nearly.self_motion.whole_self_motion`), whose consecutive points
are joined by proven arcs of true solutions, each on a known branch and within the limits or not [C2]-[C4]:

* each objective ``f`` and its derivative along the curve ``df/ds = grad f . t`` (``t`` the unit tangent, ``s``
  the arc length in joint space; :func:`_objectives`) at the ends of every step on the branch;
* where ``df/ds`` falls through zero between a step's ends, the maximum on the step's arc, located by bisection
  on the step's hyperplanes (the corrector of :mod:`redkin.srs.nearly._self_motion_kernels` [C2], as
  :func:`redkin.srs.nearly.self_motion.branch_solutions` locates an arm angle) to :data:`_RESOLUTION` rad of arc;
* the **unclamped** optimum: the best of these points over the branch's steps;
* the **clamped** optimum: the best over the steps on the branch and within the limits [C4] whose arm angles lie in
  the feasible set (by default the set read off the same curves, [C6]), the runs' ends included, and where a
  given set is narrower, the arc's points at its ends (located likewise).

Every optimum is a point of a certified arc: its configuration (:attr:`NearlyOptimal.unclamped_q`,
:attr:`NearlyOptimal.feasible_q`) reaches the pose, lies on the branch, and for the clamped one within the limits,
so the clamped optimum lies in the certified feasible set.  Where the branch has two solutions at the optimum's
arm angle, the configuration says which; :func:`redkin.srs.nearly.ik` there may return the other,
:func:`redkin.srs.nearly.self_motion.branch_solutions` lists both.

What is not claimed: a maximum on a curve of the self-motion that was not found (an island through none of the
seeds, or past where a curve could not be followed: :attr:`NearlyOptimal.complete` false), and a second maximum
within one step where ``df/ds`` has the same sign at both ends (steps are at most 0.2 rad of arc, and shorter where
the curve turns sharply).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose, check_vectors
from redkin.circle import ArcSet, wrap_angle
from redkin.errors import RedkinError
from redkin.srs._rotations import group_rotations
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.nearly import _self_motion_kernels
from redkin.srs.nearly.arm import NearlySRS, arm_angle
from redkin.srs.nearly.self_motion import SelfMotion, feasible_along, whole_self_motion
from redkin.srs.optimal import OptimalAngle, OptimalArmAngles, check_weights, optimal_arm_angles, weighted_objective

#: The objectives, in the order :func:`_objectives` returns them.
_PARTS = ("shoulder", "wrist", "overall")
#: Width [rad of arc length] to which a maximum, or an end of a given feasible set, is bracketed on a step.
_RESOLUTION = 1e-10
#: Arm angles this close [rad] to an end of the feasible set count as in it (the arm angles of the curves' points
#: and the set's ends read off them differ by rounding).
_AT_AN_END = 1e-12
#: Points of the curves evaluated at once (the frames of a pose's million points would not fit in memory).
_CHUNK = 1 << 15
#: How nearly a given curve's first point must reach the pose [m, and each entry of the rotation].
_REACHED = 1e-6


@dataclass(frozen=True)
class NearlyOptimal:
    """The limit-avoiding arm angles of one pose and branch of a nearly S-R-S arm (module docstring).

    Attributes
    ----------
    shoulder, wrist, overall : OptimalAngle
        The maxima of [000 eqs. 36, 38, 40] over the branch's certified solutions on the pose's self-motion:
        ``unclamped`` over all of them (``nan`` where the branch has no solution on the curves), ``feasible`` over
        those within the limits at arm angles of ``feasible`` (``None`` where there is none).
    branch : Branch
    weights : tuple of float
        ``(r_s, r_w)``.
    target : numpy.ndarray, shape (7,)
        The target joint values ``theta^d``.
    feasible : ArcSet
        The feasible set the optima were clamped to.
    neighbour : OptimalArmAngles or None
        The exact neighbour's optima [000 eqs. 37, 39, 40], clamped to the neighbour's own feasible set; ``None``
        where the neighbour cannot reach the pose.
    complete : bool
        Whether the self-motion was followed whole (:func:`redkin.srs.nearly.self_motion.whole_self_motion`; for
        curves given by the caller, whether each of them closed); where not, the optima are those of the curves
        followed and a better solution may lie on a curve that was not.
    unclamped_q, feasible_q : dict of str to numpy.ndarray or None
        For ``"shoulder"``, ``"wrist"`` and ``"overall"``: the certified solution (7,) at the optimum, each joint
        shifted by whole turns into its range (:meth:`redkin.chain.SerialChain.nearest_in_range`), ``None`` where
        there is no optimum; where the branch has two solutions at that arm angle, the one that attains it.
    """

    shoulder: OptimalAngle
    wrist: OptimalAngle
    overall: OptimalAngle
    branch: Branch
    weights: tuple[float, float]
    target: np.ndarray
    feasible: ArcSet
    neighbour: OptimalArmAngles | None
    complete: bool
    unclamped_q: dict[str, np.ndarray | None] = field(compare=False)
    feasible_q: dict[str, np.ndarray | None] = field(compare=False)


class _Steps:
    """The steps of the curves on one branch: their points (P, 7) with unit tangents and arm angles, whether each
    point ends a step within the limits [C4], and for each step (N,) its first and last point, whether it lies within
    the limits and the distance of its last point's hyperplane ``t . (q - start) = s`` from its first [C2]."""

    def __init__(self, curves: Sequence[SelfMotion], row: int) -> None:
        q, tangents, psi = [np.empty((0, 7))], [np.empty((0, 7))], [np.empty(0)]
        held, first, last, inside = [np.empty(0, bool)], [np.empty(0, int)], [np.empty(0, int)], [np.empty(0, bool)]
        count = 0
        for curve in curves:
            k = np.flatnonzero(curve.branches == row)
            used = np.union1d(k, k + 1)
            good = curve.inside[k] == _self_motion_kernels.INSIDE
            q.append(curve.q[used])
            tangents.append(curve.tangents[used])
            psi.append(curve.psi[used])
            held.append(np.isin(used, np.concatenate([k[good], k[good] + 1])))
            first.append(count + np.searchsorted(used, k))
            last.append(count + np.searchsorted(used, k + 1))
            inside.append(good)
            count += len(used)
        self.q, self.tangents, self.psi = np.concatenate(q), np.concatenate(tangents), np.concatenate(psi)
        self.held, self.inside = np.concatenate(held), np.concatenate(inside)
        self.first, self.last = np.concatenate(first), np.concatenate(last)
        self.length = np.einsum("nj,nj->n", self.q[self.last] - self.q[self.first], self.tangents[self.first])


def optimal_arm_angles_nearly(
    arm: NearlySRS,
    pose: ArrayLike,
    branch: str | Branch = "+++",
    target: ArrayLike | None = None,
    weights: ArrayLike = (0.5, 0.5),
    feasible: ArcSet | None = None,
    curves: Sequence[SelfMotion] | None = None,
) -> NearlyOptimal:
    """The arm angles of one pose and branch that maximise [000 eqs. 36, 38, 40] on the real arm's certified
    solutions, unclamped and within the limits (module docstring).

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
        The arm angles the clamped optimum may take; default the branch's certified feasible set read off the
        curves (:func:`redkin.srs.nearly.self_motion.feasible_along`, as
        :func:`redkin.srs.feasible_arm_angles_nearly` gives it).  Either way the clamped optimum is a solution
        within the limits.
    curves : sequence of SelfMotion, optional
        The pose's self-motion (:func:`redkin.srs.nearly.self_motion.self_motions`, or
        :attr:`redkin.srs.nearly.feasible.NearlyFeasible.curves`); followed here when not given.

    Returns
    -------
    NearlyOptimal
        With :attr:`NearlyOptimal.complete` false where the self-motion was not followed whole.

    Raises
    ------
    ValueError
        For a malformed pose, branch, target, weights or feasible set, or curves that are not the pose's.
    """
    pose = np.ascontiguousarray(check_pose(pose), dtype=float)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
    label = parse_branch(branch)
    q_target = arm.chain.middle if target is None else check_vectors(target, 7, "target")
    if q_target.shape != (7,):
        raise RedkinError(f"target must have shape (7,), got {q_target.shape}")
    chosen = check_weights(weights)
    if feasible is not None and not isinstance(feasible, ArcSet):
        raise RedkinError(f"feasible must be an ArcSet (redkin.circle), got {type(feasible).__name__}")
    if curves is None:
        found, complete = whole_self_motion(arm, pose)
    else:
        found = _checked_curves(arm, pose, curves)
        complete = all(curve.closed for curve in found)
    allowed = feasible_along(found, label) if feasible is None else feasible
    steps = _Steps(found, BRANCHES.index(label))
    candidates = _candidates(arm, pose, steps, allowed, q_target, chosen)
    angles, unclamped_q, feasible_q = zip(*(_chosen(arm, candidates, k, allowed) for k in range(len(_PARTS))))
    neighbour = _neighbour_optimal(arm, pose, label, q_target, chosen)
    return NearlyOptimal(angles[0], angles[1], angles[2], label, chosen, q_target, allowed, neighbour, complete,
                         dict(zip(_PARTS, unclamped_q)), dict(zip(_PARTS, feasible_q)))


def _checked_curves(arm: NearlySRS, pose: np.ndarray, curves: Sequence[SelfMotion]) -> tuple[SelfMotion, ...]:
    """The given curves, each a :class:`SelfMotion` whose first point reaches ``pose`` to :data:`_REACHED`."""
    given = tuple(curves)
    for curve in given:
        if not isinstance(curve, SelfMotion):
            raise RedkinError(f"curves must be SelfMotion curves of the pose (redkin.srs.self_motions), got "
                              f"{type(curve).__name__}")
        if len(curve.q) and np.abs(arm.chain.fk(curve.q[0]) - pose).max() > _REACHED:
            raise RedkinError("curves must be the pose's self-motion: a curve's first point does not reach the pose "
                              f"(to {_REACHED:g} m and in each entry of the rotation)")
    return given


def _candidates(arm: NearlySRS, pose: np.ndarray, steps: _Steps, allowed: ArcSet, target: np.ndarray,
                weights: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The candidates of every optimum (module docstring): the steps' points, the maxima located within steps where
    ``df/ds`` falls through zero, and the points of steps within the limits at the ends of ``allowed``; as joint
    values (C, 7), arm angles (C,), objectives (3, C), within the limits (C,) and candidate of which objective
    (3, C)."""
    goals = group_rotations(arm.geometry, target)
    chunks = [_objectives(arm, steps.q[k:k + _CHUNK], steps.tangents[k:k + _CHUNK], goals, weights)
              for k in range(0, max(len(steps.q), 1), _CHUNK)]
    values, slopes = (np.concatenate(pieces, axis=1) for pieces in zip(*chunks))
    part, rows = np.nonzero((slopes[:, steps.first] > 0.0) & (slopes[:, steps.last] < 0.0))  # a maximum within

    def rising(chosen: np.ndarray, points: np.ndarray) -> np.ndarray:
        tangents = _tangents(arm, points, steps.tangents[steps.first[rows[chosen]]])
        return _objectives(arm, points, tangents, goals, weights)[1][part[chosen], np.arange(len(chosen))] > 0.0

    maxima = np.concatenate(_bisected(arm, pose, steps, rows, rising))
    edges = np.array([] if allowed.is_full else [end for arc in allowed.arcs for end in arc])
    start_psi, end_psi = steps.psi[steps.first], steps.psi[steps.last]
    before = np.asarray(wrap_angle(start_psi[None, :] - edges[:, None])).reshape(len(edges), len(start_psi))
    after = before + np.asarray(wrap_angle(end_psi - start_psi))[None, :]
    crossing = (before * after < 0.0) & (np.abs(before) > _AT_AN_END) & (np.abs(after) > _AT_AN_END)
    edge, crossed = np.nonzero(crossing & steps.inside[None, :])  # an end of a given set within a step

    def on_start_side(chosen: np.ndarray, points: np.ndarray) -> np.ndarray:
        off = np.asarray(wrap_angle(arm_angle(arm, points) - edges[edge[chosen]]))
        return np.sign(off) == np.sign(before[edge[chosen], crossed[chosen]])

    low, high = _bisected(arm, pose, steps, crossed, on_start_side)
    start_held = np.asarray(allowed.contains(start_psi[crossed], _AT_AN_END), dtype=bool).reshape(-1, 1)
    ends = np.where(start_held, low, high)  # the side within the set
    located = np.concatenate([maxima, ends])
    q, psi = np.concatenate([steps.q, located]), np.concatenate([steps.psi, arm_angle(arm, located)])
    inside = np.concatenate([steps.held, np.tile(steps.inside[rows], 2), np.ones(len(crossed), dtype=bool)])
    parts = np.concatenate([np.ones((3, len(steps.q)), dtype=bool), np.tile(np.arange(3)[:, None] == part, 2),
                            np.ones((3, len(crossed)), dtype=bool)], axis=1)
    values = np.concatenate([values, _objectives(arm, located, np.zeros_like(located), goals, weights)[0]], axis=1)
    return q, psi, values, inside, parts


def _chosen(arm: NearlySRS, candidates: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray], k: int,
            allowed: ArcSet) -> tuple[OptimalAngle, np.ndarray | None, np.ndarray | None]:
    """Objective ``k``'s optimum unclamped (the best candidate) and clamped (the best within the limits and in
    ``allowed``), and the configurations there (each joint in its range)."""
    q, psi, values, inside, parts = candidates
    mine = parts[k]
    held = mine & inside & np.asarray(allowed.contains(psi, _AT_AN_END), dtype=bool).reshape(-1)
    unclamped, clamped = [None if not pick.any() else int(np.flatnonzero(pick)[np.argmax(values[k][pick])])
                          for pick in (mine, held)]
    return (OptimalAngle(float(np.nan) if unclamped is None else float(wrap_angle(psi[unclamped])),
                         None if clamped is None else float(wrap_angle(psi[clamped]))),
            None if unclamped is None else arm.chain.nearest_in_range(q[unclamped]),
            None if clamped is None else arm.chain.nearest_in_range(q[clamped]))


def _bisected(arm: NearlySRS, pose: np.ndarray, steps: _Steps, rows: np.ndarray,
              on_start_side: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The points of the arcs of steps ``rows`` (K,) either side of where ``on_start_side(chosen, points)`` (whether
    the arc's points (J, 7) of entries ``chosen`` (J,) of ``rows`` lie on the step's first point's side of it) turns
    false: bisection on the step's hyperplanes ``t . (q - start) = s`` [C2], each point the corrector's from
    ``start + s t``, until the bracket is :data:`_RESOLUTION` wide (or the corrector fails, which leaves it
    wider); the bracket's ends on the start's side and the other (K, 7) each."""
    start, direction = steps.q[steps.first[rows]], steps.tangents[steps.first[rows]]
    low, high = np.zeros(len(rows)), steps.length[rows].copy()
    low_q, high_q = start.copy(), steps.q[steps.last[rows]]
    live = high - low > _RESOLUTION
    work = _self_motion_kernels.scratch()
    while live.any():
        chosen = np.flatnonzero(live)
        middle = 0.5 * (low[chosen] + high[chosen])
        points = start[chosen] + middle[:, None] * direction[chosen]
        settled = np.array([_self_motion_kernels.corrected(points[j], start[n], direction[n], middle[j], pose,
                                                           arm.kernel_real, arm.kernel_bounds, work)[0]
                            for j, n in enumerate(chosen)], dtype=bool)
        live[chosen[~settled]] = False
        chosen, middle, points = chosen[settled], middle[settled], points[settled]
        near = on_start_side(chosen, points)
        low[chosen[near]], low_q[chosen[near]] = middle[near], points[near]
        high[chosen[~near]], high_q[chosen[~near]] = middle[~near], points[~near]
        live &= high - low > _RESOLUTION
    return low_q, high_q


def _tangents(arm: NearlySRS, q: np.ndarray, sense: np.ndarray) -> np.ndarray:
    """Unit tangents (M, 7) of the self-motion at solutions ``q`` (M, 7): the null vectors of the real arm's
    geometric Jacobian, turned to have a positive component along ``sense`` (M, 7)."""
    null = np.linalg.svd(arm.chain.jacobian(q))[2][:, -1]
    return null * np.where(np.einsum("mj,mj->m", null, sense) < 0.0, -1.0, 1.0)[:, None]


def _objectives(arm: NearlySRS, q: np.ndarray, tangents: np.ndarray, goals: tuple[np.ndarray, np.ndarray],
                weights: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """``f_s`` [000 eq. 36], ``f_w`` [000 eq. 38] and their weighted sum [000 eq. 40] at joint values ``q`` (M, 7),
    and their derivatives along ``tangents`` (M, 7), each stacked on a leading axis of 3: the shoulder's and wrist's
    rotations through the neighbour's frames at the same joint values, against those of the target, ``goals``
    (``0R3d``, ``4R7d``: :func:`redkin.srs._rotations.group_rotations` of the target joint values).

    The derivative, ours: along ``t``, ``0R3 = R_0^T R_3`` turns as ``[a_s]x 0R3`` with ``a_s = R_0^T sum_{i <= 3}
    w_i t_i`` (``w_i`` joint ``i``'s signed unit axis, ``R_k`` frame ``k``'s rotation), and ``4R7 = R_4^T R_7`` as
    ``[a_w]x 4R7`` with ``a_w = R_4^T sum_{i >= 5} w_i t_i``; with ``trace([a]x X) = -a . vee(X - X^T)``,
    ``df_s = -a_s . vee(S - S^T)``, ``S = 0R3 0R3d^T``, and ``df_w`` likewise."""
    geometry = arm.geometry
    shoulder, wrist = group_rotations(geometry, q)
    frames = geometry.chain.frames(q)
    axes = geometry.chain.joint_axes_in(frames)[0] * geometry.chain.sign[:, None]
    turned = np.einsum("mj,mjk->mjk", tangents, axes)
    a_s = np.einsum("mki,mk->mi", frames[:, 0, :3, :3], turned[:, :3].sum(axis=1))
    a_w = np.einsum("mki,mk->mi", frames[:, 4, :3, :3], turned[:, 4:].sum(axis=1))
    values, slopes = [], []
    for rotation, goal, turn in ((shoulder, goals[0], a_s), (wrist, goals[1], a_w)):
        product = rotation @ goal.T
        values.append(np.einsum("mij,ij->m", rotation, goal))  # [000 eqs. 36, 38]
        slopes.append(-np.einsum("mi,mi->m", turn, _vee(product - np.swapaxes(product, -1, -2))))
    return (np.stack([*values, weighted_objective(values[0], values[1], weights)]),  # [000 eq. 40]
            np.stack([*slopes, weighted_objective(slopes[0], slopes[1], weights)]))


def _vee(skew: np.ndarray) -> np.ndarray:
    """The vectors (M, 3) of skew matrices (M, 3, 3): ``[x]x -> x``."""
    return np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]], axis=-1)


def _neighbour_optimal(arm: NearlySRS, pose: np.ndarray, label: Branch, target: np.ndarray,
                       weights: tuple[float, float]) -> OptimalArmAngles | None:
    """The neighbour's optima [000 eqs. 37, 39, 40], or ``None`` where the neighbour does not reach the pose."""
    from redkin.srs.ik import reachable

    if not reachable(arm.geometry, pose):
        return None
    return optimal_arm_angles(arm.geometry, pose, label, target=target, weights=weights)
