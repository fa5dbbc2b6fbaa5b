"""The self-motion of a nearly S-R-S arm at one pose, and the feasible arm angles read off it.

A pose's solutions on the real arm form closed curves in joint space (6 pose
equations in 7 joints), which :func:`self_motion` follows by continuation
(:mod:`redkin.srs._self_motion_kernels`).  Along a curve the arm angle
``psi(q)`` (:func:`redkin.srs.nearly.arm_angle`) turns, and the branch
(:func:`redkin.srs.nearly.branch_of`) changes where ``theta_2``, ``theta_4``
(from the real stretched elbow) or ``theta_6`` crosses its boundary.

On an exact arm ``psi`` increases monotonically along each branch's curve, so
a branch has one solution per arm angle.  On the real arm it need not: where
the elbow is near its stretch, so that its distance from the shoulder-wrist
line is of the order of the offsets (the Kinova Gen3's, with the wrist near
axis 1), ``psi`` turns back along the curve (a fold, ``d psi / ds = 0``), and
the branch has two solutions at the arm angles before the fold and none after
it.  :func:`redkin.srs.nearly.ik` returns one of them.

:func:`feasible_along` reads the feasible set off the curves instead: the arm
angles of the curves' points that lie on the branch and within the limits.
Each run of such points is an arc from the smallest to the largest arm angle
on it; those lie at the run's ends (where the branch or a limit flag changes,
located by bisection along the curve) or at a fold within it (where ``d psi /
ds`` changes sign, located the same way), to :data:`_RESOLUTION` rad.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.circle import ArcSet, wrap_angle
from redkin.errors import RedkinError
from redkin.srs import _nearly_kernels, _self_motion_kernels
from redkin.srs._targets import check_psi
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.nearly import NearlySRS, branch_of, ik

#: A point of a curve as :func:`_point` gives it: joint values, unit tangent, arm angle and ``d psi / ds``.
_Point = tuple[np.ndarray, np.ndarray, float, float]
#: Largest step [rad of arc length in joint space] of the continuation.
_STEP = 0.05
#: Points of one curve at most.
_MOST_POINTS = 20_000
#: Width [rad of arm angle] to which the ends of a run and its folds are located.
_RESOLUTION = 1e-10
#: Narrowest step [rad of arc length] of the bisections.
_FINEST = 1e-15
#: How nearly the first joint values must reach the pose [m, and each entry of the rotation].
_REACHED = 1e-6
#: Joint values closer than this [rad] are one solution (:func:`_lies_on`): a certified solution (1e-9) lies up to
#: about 1e-6 rad from the curve next to the stretched elbow, where the Jacobian is nearly singular.
_SAME = 1e-5
#: Width [rad of arc length] to which a joint's extremum is located.
_EXTREMUM = 1e-9
#: Slack [rad] of the limit test, as :func:`redkin.srs._nearly_kernels.within_limits`'s.
_LIMIT_SLACK = _nearly_kernels.LIMIT_SLACK


class SelfMotion(NamedTuple):
    """One curve of a pose's self-motion on the real arm.

    Attributes
    ----------
    q : numpy.ndarray, shape (M, 7)
        Its points, in order along the curve (joint values continuous, not wrapped); each reaches the pose to 1e-12.
    tangents : numpy.ndarray, shape (M, 7)
        The unit tangent at each point, in the sense of travel.
    psi : numpy.ndarray, shape (M,)
        The arm angle at each point (:func:`redkin.srs.nearly.arm_angle`).
    rates : numpy.ndarray, shape (M,)
        ``d psi / ds`` at each point, ``s`` the arc length in joint space.
    closed : bool
        Whether the curve came back to its first point; where not, it stopped at a singular configuration (a
        Jacobian of rank 5) or after :data:`_MOST_POINTS` points, and is a piece of a curve.
    """

    q: np.ndarray
    tangents: np.ndarray
    psi: np.ndarray
    rates: np.ndarray
    closed: bool


def self_motion(arm: NearlySRS, pose: ArrayLike, q: ArrayLike, step: float = _STEP) -> SelfMotion:
    """The curve of the self-motion of ``pose`` through the solution ``q`` (7,), followed with steps of at most
    ``step`` [rad]; where it does not close, followed both ways from ``q`` (module docstring).

    Raises
    ------
    ValueError
        For a malformed pose or joint values, a step outside (0, 0.5], or joint values that do not reach the pose
        to :data:`_REACHED` (they are corrected onto the curve first).
    """
    target = check_pose(pose)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    start = np.array(arm.chain.check_q(q), dtype=float)
    if start.shape != (7,):
        raise RedkinError(f"q must be one joint vector (7,), got shape {start.shape}")
    if not 0.0 < step <= 0.5:
        raise RedkinError(f"step must be in (0, 0.5] rad, got {step!r}")
    reached = arm.chain.fk(start)
    if np.abs(reached - target).max() > _REACHED:
        raise RedkinError(f"q does not reach the pose (to {_REACHED:g} m and in each entry of the rotation): a "
                          "self-motion starts from a solution")
    forward = _traced(arm, target, start, step, 1.0)
    if forward.closed or len(forward.psi) == 0:
        return forward
    backward = _traced(arm, target, start, step, -1.0)
    return SelfMotion(np.concatenate([backward.q[:0:-1], forward.q]),
                      np.concatenate([-backward.tangents[:0:-1], forward.tangents]),
                      np.concatenate([backward.psi[:0:-1], forward.psi]),
                      np.concatenate([-backward.rates[:0:-1], forward.rates]), False)


def curves_through(arm: NearlySRS, pose: ArrayLike, solutions: ArrayLike, most: int = 16) -> list[SelfMotion]:
    """The curves of the self-motion of ``pose`` through the ``solutions`` (M, 7): one from the first solution on no
    curve found before (:func:`_lies_on`), until each lies on one or ``most`` are found."""
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    found: list[SelfMotion] = []
    for q in np.asarray(solutions, dtype=float).reshape(-1, 7):
        if len(found) == most:
            break
        if not any(_lies_on(arm, target, curve, q) for curve in found):
            found.append(self_motion(arm, target, q))
    return found


def branch_solutions(arm: NearlySRS, pose: ArrayLike, psi: float, branch: str | Branch,
                     curves: list[SelfMotion] | None = None) -> np.ndarray:
    """Every solution of ``branch`` at the arm angle ``psi`` on the self-motion's curves (K, 7), each once (to
    :data:`_SAME` rad): :func:`redkin.srs.nearly.ik`'s row at ``psi`` first where it exists, then where a curve's
    points on the branch (:func:`_resolved`) cross ``psi``, located by bisection along it to :data:`_RESOLUTION` rad.
    Where the branch has two solutions at ``psi`` (module docstring), both; ``nearly.ik`` returns one.  ``curves``
    default to those through ``nearly.ik``'s solutions of the branch at 72 arm angles (:func:`curves_through`); a
    curve through none of them is not found.

    Raises
    ------
    ValueError
        For a malformed pose, arm angle or branch.
    """
    target = np.ascontiguousarray(check_pose(pose), dtype=float)
    if target.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {target.shape}")
    angle = float(np.asarray(check_psi(psi)))
    label = parse_branch(branch)
    row = BRANCHES.index(label)
    if curves is None:
        grid = np.linspace(-np.pi, np.pi, 72, endpoint=False)
        solved = ik(arm, np.broadcast_to(target, grid.shape + (4, 4)), grid, label)
        curves = curves_through(arm, target, solved.q[solved.exists[:, 0], 0])
    own = ik(arm, target, angle, label)
    found = [own.q[0]] if own.exists[0] else []
    for traced in curves:
        curve = _resolved(arm, target, traced)
        count = len(curve.psi)
        following = (np.arange(count) + 1) % count
        on = branch_of(arm, curve.q) == row
        off = np.asarray(wrap_angle(curve.psi - angle))
        crossing = on & on[following] & (off * off[following] <= 0.0) & (np.abs(off - off[following]) < np.pi)
        if not curve.closed:
            crossing[-1] = False
        for k in np.flatnonzero(crossing):
            low, high = _bisected(arm, target, curve, int(k), partial(_arm_angle_from, angle), 0.0)
            q, _, value, _ = _point(arm, target, curve, int(k), low)
            if abs(float(wrap_angle(value - angle))) > _RESOLUTION:
                q = _point(arm, target, curve, int(k), high)[0]
            if all(np.max(np.abs(wrap_angle(q - known))) > _SAME for known in found):  # a curve traced twice
                found.append(q)
    return np.array(found).reshape(-1, 7)


def _lies_on(arm: NearlySRS, pose: np.ndarray, curve: SelfMotion, q: np.ndarray) -> bool:
    """Whether the solution ``q`` (7,) of ``pose`` lies on ``curve``: the curve's point on the hyperplane through
    ``q`` normal to the tangent at its nearest point (:func:`_point`) is ``q`` to :data:`_SAME` rad (modulo whole
    turns)."""
    gaps = np.asarray(wrap_angle(q - curve.q))
    k = int(np.argmin(np.einsum("mj,mj->m", gaps, gaps)))
    if np.linalg.norm(gaps[k]) > _STEP:
        return False
    try:
        point = _point(arm, np.ascontiguousarray(pose, dtype=float), curve, k, float(gaps[k] @ curve.tangents[k]))[0]
    except RedkinError:
        return False
    return bool(np.max(np.abs(wrap_angle(point - q))) <= _SAME)


def _traced(arm: NearlySRS, target: np.ndarray, start: np.ndarray, step: float, sense: float) -> SelfMotion:
    """:func:`redkin.srs._self_motion_kernels.traced` one way from ``start``."""
    points, tangents = np.empty((_MOST_POINTS, 7)), np.empty((_MOST_POINTS, 7))
    angles, rates = np.empty(_MOST_POINTS), np.empty(_MOST_POINTS)
    count, closed = _self_motion_kernels.traced(start, np.ascontiguousarray(target), arm.kernel_real,
                                                arm.kernel_model, step, sense, _MOST_POINTS, points, tangents,
                                                angles, rates, _nearly_kernels.scratch()[0])
    return SelfMotion(points[:count], tangents[:count], angles[:count], rates[:count], bool(closed))


def feasible_along(arm: NearlySRS, pose: np.ndarray, branch: str | Branch, curves: list[SelfMotion]) -> ArcSet:
    """The arm angles of the points of ``curves`` (of ``pose``) that lie on ``branch`` and within the real arm's
    limits (module docstring), to :data:`_RESOLUTION` rad."""
    label = parse_branch(branch)
    row = BRANCHES.index(label)
    target = np.ascontiguousarray(pose, dtype=float)
    feasible = ArcSet.empty()
    for traced in curves:
        curve = _resolved(arm, target, traced)
        good = _good(arm, curve.q, row)
        for run in _runs(good, curve.closed):
            psi = np.unwrap(curve.psi[run])
            if len(run) == len(good) and curve.closed:  # the whole closed curve: it covers the circle if it winds
                psi = np.append(psi, psi[-1] + wrap_angle(psi[0] - psi[-1]))
            feasible = feasible.union(ArcSet([(float(np.min(psi)), float(np.max(psi)))]))
    return feasible


def _resolved(arm: NearlySRS, target: np.ndarray, curve: SelfMotion) -> SelfMotion:
    """``curve`` with points added where anything :func:`feasible_along` reads can change between two of its points
    (module docstring): first each extremum of a joint that comes within two steps of one of its
    :func:`_thresholds` (where its rate changes sign), then the two sides of each crossing of a threshold and of
    each fold of the arm angle (where ``d psi / ds`` changes sign), bracketed by bisection along the curve to
    :data:`_RESOLUTION` rad of arm angle."""
    thresholds = _thresholds(arm)

    def extrema(k: int, following: int) -> list[float]:
        found = []
        for j in range(7):
            if (thresholds[j].size and curve.tangents[k, j] * curve.tangents[following, j] < 0.0
                    and np.min(np.abs(wrap_angle(curve.q[k, j] - thresholds[j]))) <= 2.0 * _STEP):
                found.append(_bisected(arm, target, curve, k, partial(_joint_rate, j), _EXTREMUM)[0])
        return found

    curve = _inserted(arm, target, curve, extrema)

    def crossings(k: int, following: int) -> list[float]:
        found = []
        for j in range(7):
            for value in thresholds[j]:
                before, after = wrap_angle(curve.q[k, j] - value), wrap_angle(curve.q[following, j] - value)
                if before * after <= 0.0 and abs(before - after) < np.pi and before != after:
                    found += _bisected(arm, target, curve, k, partial(_joint_from, j, value), 0.0)
        if curve.rates[k] * curve.rates[following] < 0.0:
            found += _bisected(arm, target, curve, k, _arm_angle_rate, 0.0)
        return found

    return _inserted(arm, target, curve, crossings)


def _inserted(arm: NearlySRS, target: np.ndarray, curve: SelfMotion,
              events: Callable[[int, int], list[float]]) -> SelfMotion:
    """``curve`` with the points at the distances ``events(k, k + 1)`` along from each point ``k`` added after it."""
    count = len(curve.psi)
    last = count if curve.closed else count - 1
    rows: list[_Point] = []
    for k in range(count):
        rows.append((curve.q[k], curve.tangents[k], float(curve.psi[k]), float(curve.rates[k])))
        if k < last:
            rows += [_point(arm, target, curve, k, distance) for distance in sorted(set(events(k, (k + 1) % count)))]
    if len(rows) == count:
        return curve
    q, tangents, psi, rates = zip(*rows)
    return SelfMotion(np.array(q), np.array(tangents), np.array(psi), np.array(rates), curve.closed)


def _bisected(arm: NearlySRS, target: np.ndarray, curve: SelfMotion, k: int, measure: Callable[[_Point], float],
              width: float) -> list[float]:
    """Between point ``k`` and the next, where the sign of ``measure(point)`` changes from its sign at point ``k``,
    by bisection along the curve (:func:`_point`) until the bracket is ``width`` wide [rad of arc length] or, for
    ``width`` 0, its ends' arm angles are within :data:`_RESOLUTION` (or :data:`_FINEST` apart): the two ends'
    distances from point ``k``."""
    low, high = 0.0, _chord(curve, k)
    psi_low, psi_high = float(curve.psi[k]), float(curve.psi[(k + 1) % len(curve.psi)])
    sign = np.sign(measure((curve.q[k], curve.tangents[k], psi_low, float(curve.rates[k]))))
    while high - low > max(width, _FINEST) and (width > 0.0
                                                or abs(float(wrap_angle(psi_high - psi_low))) > _RESOLUTION):
        middle = 0.5 * (low + high)
        point = _point(arm, target, curve, k, middle)
        if np.sign(measure(point)) == sign:
            low, psi_low = middle, point[2]
        else:
            high, psi_high = middle, point[2]
    return [low, high]


def _joint_rate(j: int, point: _Point) -> float:
    """Joint ``j``'s rate along the curve at ``point``."""
    return float(point[1][j])


def _joint_from(j: int, value: float, point: _Point) -> float:
    """Joint ``j`` at ``point`` less ``value``, wrapped."""
    return float(wrap_angle(point[0][j] - value))


def _arm_angle_rate(point: _Point) -> float:
    """``d psi / ds`` at ``point``."""
    return point[3]


def _arm_angle_from(angle: float, point: _Point) -> float:
    """The arm angle at ``point`` less ``angle``, wrapped."""
    return float(wrap_angle(point[2] - angle))


def _thresholds(arm: NearlySRS) -> list[np.ndarray]:
    """For each joint, the values [rad] where its flag in :func:`_good` can change: a limited joint's limits, and for
    joints 2, 4 and 6 the boundaries of their branch signs (the neighbour's ``theta`` at 0 and pi, from the real
    stretched elbow for joint 4)."""
    chain, neighbour = arm.chain, arm.neighbour
    values: list[list[float]] = [[] for _ in range(7)]
    for limited in np.flatnonzero(~chain.covers_circle):
        values[limited] += [float(chain.lower[limited]), float(chain.upper[limited])]
    for j in (1, 3, 5):
        centre = arm.real_phase if j == 3 else 0.0
        values[j] += [float(neighbour.sign[j] * (centre + turn - neighbour.offset[j])) for turn in (0.0, np.pi)]
    return [np.array(v) for v in values]


def _good(arm: NearlySRS, q: np.ndarray, row: int) -> np.ndarray:
    """Whether each of ``q`` (M, 7) lies on the branch ``row`` and within the limits (modulo whole turns)."""
    within = arm.chain.joints_within_limits(q, _LIMIT_SLACK, wrap=True).all(axis=-1)
    return (branch_of(arm, q) == row) & within


def _runs(good: np.ndarray, closed: bool) -> list[np.ndarray]:
    """The maximal runs of True in ``good`` as index arrays, read cyclically where ``closed``."""
    count = len(good)
    if closed and not good.all():
        shift = int(np.argmin(good))
        order = (np.arange(count) + shift) % count
    else:
        order = np.arange(count)
    edges = np.diff(np.concatenate([[0], good[order].astype(int), [0]]))
    return [order[low:high] for low, high in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1))]


def _chord(curve: SelfMotion, k: int) -> float:
    """The distance along the tangent at point ``k`` of the hyperplane (normal to it) that holds the next point
    (cyclic; the first point is the same modulo whole turns)."""
    following = (k + 1) % len(curve.psi)
    gap = curve.q[following] - curve.q[k]
    if following == 0:
        gap = np.asarray(wrap_angle(gap))
    return float(gap @ curve.tangents[k])


def _point(arm: NearlySRS, target: np.ndarray, curve: SelfMotion, k: int, distance: float) -> _Point:
    """The curve's point ``distance`` along from point ``k`` (:func:`redkin.srs._self_motion_kernels.point_at`): its
    joint values, unit tangent, arm angle and ``d psi / ds``."""
    out, following = np.empty(7), np.empty(7)
    settled, psi, rate = _self_motion_kernels.point_at(curve.q[k], curve.tangents[k], distance, target,
                                                       arm.kernel_real, arm.kernel_model,
                                                       _nearly_kernels.scratch()[0], out, following)
    if not settled:
        raise RedkinError("the self-motion could not be followed between two of its points; please report this")
    return out, following, float(psi), float(rate)
