"""Singular arm angles of a nearly S-R-S arm: where the real arm's joint 1/3 or 5/7 pair aligns along the self-motion.

On an exact S-R-S arm the shoulder is singular where ``theta_2 = 0`` or ``pi`` ([000 eqs. 31-32], and their
counterpart for ``pi``, :mod:`redkin.srs.singular`): axes 1 and 3 lie on one line, parallel or antiparallel, and only
``theta_1 + theta_3`` (``theta_1 - theta_3``) is fixed; likewise the wrist where ``theta_6 = 0`` or ``pi``
[000 eqs. 33-34].  Which of the two a maker's zero pose is depends on the description: the Kinova Gen3's
``q_2 = 0`` and ``q_6 = 0`` are ``theta = pi`` of the Table 1 form, the Jaco2's and the iiwa's ``theta = 0``.  The
configurations with ``theta_2 = 0`` reach a set of poses of one dimension less, so most poses have no singular arm
angle.

On the real arm the pair's axes need not meet (the Gen3's axes 1 and 3 are 11.75 mm apart), so "on one line"
becomes **aligned**: axes 1 and 3 (5 and 7) parallel or antiparallel, measured by the signed angle ``sigma`` of
:func:`alignment_angles`.  With the axes apart, joints 1 and 3 no longer undo each other there, the aligned
configurations reach an open set of poses, and a self-motion near one of the neighbour's singular poses typically
passes through alignment at two arm angles, where its ``theta_2`` changes sign: the branch ``(+, s4, s6)`` ends
there and ``(-, s4, s6)`` goes on.  Near such an arm angle the neighbour's closed form is ill-conditioned, the
real arm can have two solutions on one branch, and :func:`redkin.srs.nearly.ik` may miss the solution or land on
another sheet (docs/srs.md).  So the search runs along the self-motion itself, not over ``nearly.ik``'s rows.

:func:`singular_arm_angles_nearly` computes, for one pose and branch, on the real arm:

1. the branch's solutions on a grid of arm angles, with the neighbour's nearest approaches to ``theta = 0`` and
   ``pi`` (the largest and smallest ``cos theta_2`` [000 eq. 14] and ``cos theta_6`` [000 eq. 18]) merged in;
2. the curves of the self-motion (:func:`redkin.srs.nearly.self_motion.curves_through`) through those where
   ``|sigma|`` of either pair has a local minimum on the grid, unless it is below :data:`_SINGULAR_START`;
3. along each curve, every local minimum of ``|sigma|`` over its points with the branch's other two signs, and over
   its points on the branch, located between the neighbouring points by sampling the curve (the solutions with the
   tangent's largest joint at given values, :func:`redkin.srs.nearly.search.polished`) and shrinking the bracket
   to :data:`_ZOOM_END` rad of arc length;
4. the **singular arm angles**: from each located minimum of the first kind, and each of the grid's minima, below
   :data:`_START`, Newton's method on the seven equations ``FK(q) = T``, ``sigma(q) = 0``; each result is certified
   (the pose within 1e-9 m and 1e-9 rad, ``|sigma|`` within 1e-9 rad, the branch's other two signs), its arm angle
   that of the configuration (:func:`redkin.srs.nearly.arm_angle`);
5. the **nearest approach** of each pair to alignment along the branch's certified solutions: the smallest
   ``|sigma|`` of the located minima of the second kind, of the grid's minima and of the aligned configurations
   (where the branch ends at alignment), and its arm angle.

What is not claimed: a curve of the self-motion through none of the grid's minima; a second alignment between two
neighbouring points of a curve; an alignment on a curve that is not followed (its grid sample within
:data:`_SINGULAR_START` of alignment) and that Newton's method does not reach from the grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.circle import wrap_angle
from redkin.errors import RedkinError
from redkin.srs.branches import Branch, branch_of_theta, parse_branch
from redkin.srs.nearly.arm import NearlySRS, arm_angle
from redkin.srs.nearly.search import merged, polished, solutions_at
from redkin.srs.nearly.self_motion import SelfMotion, curves_through
from redkin.srs.singular import SingularArmAngles, singular_arm_angles

#: The joints (0-based) of the shoulder's and the wrist's pair, the joint between them, and the branch signs that
#: stay fixed through the pair's alignment (Table 1 signs of theta_2, theta_4, theta_6).
_PAIRS = {"shoulder": (0, 2, 1, (1, 2)), "wrist": (4, 6, 5, (0, 1))}
#: Arm angles of the grid.
_SAMPLES = 720
#: A grid sample whose ``|sigma|`` is at most this [rad] is not followed along the self-motion (on a pair whose axes
#: meet, the Gen3's none, it is next to a singular configuration, where the certified steps shrink without end); it
#: starts a Newton search for alignment as it is.
_SINGULAR_START = 1e-6
#: A located minimum of ``|sigma|`` larger than this [rad] starts no Newton search for alignment.
_START = 0.2
#: Points per sampling of a bracket along a curve, and the spacing [rad of arc length] at which it stops.
_ZOOM, _ZOOM_END = 17, 1e-9
#: Sizes of ``|sigma|`` along a curve below this [rad] are one: a stretch of aligned points (an exact pair's
#: configurations at a singular pose, where only ``theta_5 + theta_7`` is fixed) has its rounding's local minima.
_FLOOR = 1e-10
#: Neighbouring sizes of ``|sigma|`` along a curve equal to this relative difference are one run
#: (:func:`_local_minima`).
_EQUAL = 1e-9
#: Singular arm angles closer than this [rad] are one.
_SAME = 1e-9


class Alignment(NamedTuple):
    """Where a pair of axes comes nearest to alignment along a branch: the arm angle [rad] and the angle between
    the axes' lines there [rad] (0 where they are parallel or antiparallel, at most pi/2)."""

    psi: float
    angle: float


@dataclass(frozen=True)
class NearlySingular:
    """Singular arm angles of one pose and branch of a nearly S-R-S arm (module docstring).

    Attributes
    ----------
    shoulder, wrist : tuple of float
        Arm angles [rad] at which a configuration reaching the pose has axes 1 and 3 (5 and 7) aligned (parallel or
        antiparallel) and the branch's other two signs, sorted; empty if none was found.
    shoulder_q, wrist_q : numpy.ndarray, shape (K, 7)
        Those configurations, certified (module docstring), in the order of the arm angles.
    shoulder_nearest, wrist_nearest : Alignment or None
        The pair's nearest approach to alignment along the branch's certified solutions (module docstring, step
        5); ``None`` where the branch has none at any sampled arm angle.
    branch : Branch
    neighbour : SingularArmAngles or None
        The exact neighbour's singular arm angles [000 eqs. 31-34]; ``None`` where it cannot reach the pose.
    """

    shoulder: tuple[float, ...]
    wrist: tuple[float, ...]
    shoulder_q: np.ndarray
    wrist_q: np.ndarray
    shoulder_nearest: Alignment | None
    wrist_nearest: Alignment | None
    branch: Branch
    neighbour: SingularArmAngles | None


def alignment_angles(arm: NearlySRS, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The signed angles ``sigma`` [rad] of the real arm's axes 1 and 3, and 5 and 7, from alignment at joint values
    ``q`` (..., 7), each in ``[-pi/2, pi/2]``.

    Aligned means parallel or antiparallel: on the neighbour, ``theta_2 = 0`` or ``pi`` (``theta_6 = 0`` or ``pi``)
    of the Table 1 form [000 eqs. 31-34], whichever of the two the user's ``q_2 = 0`` is (``pi`` on the Kinova
    Gen3).  ``|sigma|`` is the angle between the axes' lines, ``arctan2(|a x b|, |a . b|)`` for unit directions
    ``a``, ``b``; its sign is that of ``(a x b) . m`` (``m`` axis 2, or 6) times that of ``a . b``, so that ``sigma``
    is smooth through both alignments; ``sigma = +-theta_2`` (``+-theta_6``) from the nearer of 0 and pi on an arm
    whose twists are right angles.
    """
    directions, _ = arm.chain.joint_axes(q)
    angles = []
    for first, second, middle, _ in _PAIRS.values():
        a, b = directions[..., first, :], directions[..., second, :]
        cross = np.cross(a, b)
        dot = np.einsum("...i,...i->...", a, b)
        turn = np.einsum("...i,...i->...", cross, directions[..., middle, :])
        sign = np.where(turn < 0.0, -1.0, 1.0) * np.where(dot < 0.0, -1.0, 1.0)
        angles.append(sign * np.arctan2(np.linalg.norm(cross, axis=-1), np.abs(dot)))
    return angles[0], angles[1]


def singular_arm_angles_nearly(arm: NearlySRS, pose: ArrayLike, branch: str | Branch = "+++",
                               samples: int = _SAMPLES) -> NearlySingular:
    """The arm angles of one pose and branch at which the real arm's shoulder or wrist pair aligns, and the pairs'
    nearest approach to alignment along the branch (module docstring).

    Parameters
    ----------
    arm : NearlySRS
        From :func:`redkin.srs.nearly_srs`.
    pose : array_like, shape (4, 4)
    branch : str or Branch
    samples : int
        Arm angles of the grid, at least 8.

    Raises
    ------
    ValueError
        For a malformed pose or branch, or fewer than 8 samples.
    """
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 8:
        raise RedkinError(f"samples must be an integer of at least 8, got {samples!r}")
    label = parse_branch(branch)
    neighbour = _neighbour_singular(arm, pose, label)
    psi = np.linspace(-np.pi, np.pi, int(samples), endpoint=False)
    if neighbour is not None:
        psi = merged(psi, _neighbour_nearest(neighbour))
    q, exists = solutions_at(arm, pose, psi, label)
    sizes = np.where(exists, np.abs(np.array(alignment_angles(arm, q))), np.inf)
    minima = np.unique(np.concatenate([_local_minima(size, closed=True) for size in sizes]))
    followed = minima[sizes[:, minima].min(axis=0) > _SINGULAR_START]
    curves = curves_through(arm, pose, q[followed]) if followed.size else ()
    signs = np.array(arm.geometry.kernel_branch(label)[0])
    tracks = [_track(arm, curve) for curve in curves]
    found: dict[str, tuple[list[float], np.ndarray, Alignment | None]] = {}
    for k, part in enumerate(_PAIRS):

        def pair_sigma(values: np.ndarray, k: int = k) -> np.ndarray:
            return alignment_angles(arm, values)[k]

        kept = list(_PAIRS[part][3])
        located, on_branch = _located_minima(arm, pose, tracks, k, pair_sigma, signs, kept)
        starts = np.concatenate([located[~on_branch], q[minima]])
        angles, configurations = _aligned(arm, pose, starts[np.abs(pair_sigma(starts)) <= _START], pair_sigma, signs,
                                          kept)
        ends = located[on_branch]
        approaches = ([Alignment(float(a), float(v)) for a, v in zip(psi[minima], sizes[k, minima]) if np.isfinite(v)]
                      + [Alignment(float(a), float(v)) for a, v in zip(arm_angle(arm, ends), np.abs(pair_sigma(ends)))]
                      + [Alignment(a, float(v)) for a, v in zip(angles, np.abs(pair_sigma(configurations)))])
        found[part] = (angles, configurations, min(approaches, key=lambda a: a.angle) if approaches else None)
    return NearlySingular(tuple(found["shoulder"][0]), tuple(found["wrist"][0]), found["shoulder"][1],
                          found["wrist"][1], found["shoulder"][2], found["wrist"][2], label, neighbour)


def _neighbour_nearest(neighbour: SingularArmAngles) -> np.ndarray:
    """The neighbour's nearest approaches to alignment: the arm angles of the largest and the smallest
    ``cos theta_2 = -(a s + b c + c)`` [000 eq. 14] and ``cos theta_6 = a s + b c + c`` [000 eq. 18], nearest
    ``theta = 0`` and ``theta = pi``."""
    a_s, b_s, _ = neighbour.shoulder_coefficients
    a_w, b_w, _ = neighbour.wrist_coefficients
    return np.arctan2([-a_s, a_s, a_w, -a_w], [-b_s, b_s, b_w, -b_w])


class _Track(NamedTuple):
    """A curve's points (a closed curve's last, its first again, left out), tangents, branch signs (M, 3), ``sigma`` of
    both pairs (2, M), and whether it is closed."""

    q: np.ndarray
    tangents: np.ndarray
    signs: np.ndarray
    sigma: np.ndarray
    closed: bool


def _track(arm: NearlySRS, curve: SelfMotion) -> _Track:
    count = len(curve.q) - 1 if curve.closed else len(curve.q)
    q = curve.q[:count]
    return _Track(q, curve.tangents[:count], branch_of_theta(arm.geometry.theta_of_q(q), arm.real_phase),
                  np.array(alignment_angles(arm, q)), curve.closed)


def _located_minima(arm: NearlySRS, pose: np.ndarray, tracks: list[_Track], k: int, sigma, signs: np.ndarray,
                    kept: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """The local minima of ``|sigma|`` of pair ``k`` along the curves, over their points with the branch's ``kept``
    signs and over their points on the branch (``signs``), each located between its neighbouring points (module
    docstring, step 3): the certified configurations (K, 7) and whether each is a minimum of the second kind."""
    pair = [j for j in range(3) if j not in kept]
    starts, tangents, lows, highs, kinds = [], [], [], [], []
    for track in tracks:
        points, count = track.q, len(track.q)
        with_kept = np.all(track.signs[:, kept] == signs[kept], axis=-1)
        size = np.maximum(np.abs(track.sigma[k]), _FLOOR)
        for kind, mask in enumerate((with_kept, with_kept & (track.signs[:, pair[0]] == signs[pair[0]]))):
            for m in _local_minima(np.where(mask, size, np.inf), track.closed):
                before = points[m - 1] if m > 0 or track.closed else points[m]
                after = points[(m + 1) % count] if m < count - 1 or track.closed else points[m]
                gaps = np.asarray(wrap_angle(np.array([before, after]) - points[m])) @ track.tangents[m]
                starts.append(points[m])
                tangents.append(track.tangents[m])
                lows.append(min(gaps[0], 0.0))
                highs.append(max(gaps[1], 0.0))
                kinds.append(kind)
    if not starts:
        return np.empty((0, 7)), np.empty(0, dtype=bool)
    on_branch = np.array(kinds) == 1
    checked = np.zeros((len(starts), 3), dtype=bool)
    checked[:, kept] = True
    checked[:, pair[0]] = on_branch
    located = _along(arm, pose, np.array(starts), np.array(tangents), np.array(lows), np.array(highs), sigma, signs,
                     checked)
    return located, on_branch


def _along(arm: NearlySRS, pose: np.ndarray, start: np.ndarray, tangent: np.ndarray, low: np.ndarray,
           high: np.ndarray, sigma, signs: np.ndarray, checked: np.ndarray) -> np.ndarray:
    """The points (K, 7) of smallest ``|sigma|`` whose branch signs are ``signs`` where ``checked`` (K, 3), on the
    curves through ``start`` (K, 7) between the distances ``low`` and ``high`` along their ``tangent`` (K, 7): the
    curve sampled at :data:`_ZOOM` points, the bracket shrunk to one spacing either side of the best point so far
    until the spacing is below :data:`_ZOOM_END`.  The point at distance ``d`` is the solution with the tangent's
    largest joint ``j`` at ``start_j + d t_j``, polished (:func:`redkin.srs.nearly.search.polished`) from
    ``start + d t``."""
    best, best_size = start.copy(), np.abs(sigma(start))
    rows = np.arange(len(start))
    joint = np.argmax(np.abs(tangent), axis=1)
    centre = np.zeros(len(start))
    while True:
        distance = low[:, None] + (high - low)[:, None] * np.linspace(0.0, 1.0, _ZOOM)[None, :]
        moved = start[:, None, :] + distance[..., None] * tangent[:, None, :]
        size = np.full(distance.shape, np.inf)
        for j in np.unique(joint):
            group = joint == j
            points, certified = polished(arm, moved[group].reshape(-1, 7), pose, partial(_joint_value, int(j)),
                                         moved[group][..., j].reshape(-1))
            own = branch_of_theta(arm.geometry.theta_of_q(points), arm.real_phase).reshape(-1, _ZOOM, 3)
            fits = np.all((own == signs) | ~checked[group][:, None, :], axis=-1)
            moved[group] = points.reshape(-1, _ZOOM, 7)
            size[group] = np.where(certified.reshape(-1, _ZOOM) & fits,
                                   np.abs(sigma(points)).reshape(-1, _ZOOM), np.inf)
        k = np.argmin(size, axis=1)
        better = size[rows, k] < best_size
        best[better], best_size[better] = moved[rows[better], k[better]], size[rows[better], k[better]]
        centre[better] = distance[rows[better], k[better]]
        spacing = (high - low) / (_ZOOM - 1)
        if spacing.max() < _ZOOM_END:
            return best
        low, high = np.maximum(low, centre - spacing), np.minimum(high, centre + spacing)


def _joint_value(j: int, values: np.ndarray) -> np.ndarray:
    """Joint ``j``'s values of joint values ``values`` (..., 7)."""
    return values[..., j]


def _aligned(arm: NearlySRS, pose: np.ndarray, starts: np.ndarray, sigma, signs: np.ndarray,
             kept: list[int]) -> tuple[list[float], np.ndarray]:
    """The certified aligned configurations Newton reaches from ``starts`` (M, 7) whose branch signs ``kept`` are
    those of ``signs``: their arm angles, sorted and each once, and the configurations (K, 7)."""
    if len(starts) == 0:
        return [], np.empty((0, 7))
    q, certified = polished(arm, starts, pose, sigma)
    q = q[certified]
    theta = arm.geometry.theta_of_q(q)
    q = q[np.all(branch_of_theta(theta, arm.real_phase)[:, kept] == signs[kept], axis=-1)]
    psi = arm_angle(arm, q)
    angles: list[float] = []
    rows: list[np.ndarray] = []
    for index in np.argsort(psi):
        if not angles or abs(np.angle(np.exp(1j * (psi[index] - angles[-1])))) > _SAME:
            angles.append(float(psi[index]))
            rows.append(q[index])
    if len(angles) > 1 and abs(np.angle(np.exp(1j * (angles[-1] - angles[0])))) <= _SAME:
        angles.pop()
        rows.pop()
    return angles, np.array(rows).reshape(-1, 7)


def _neighbour_singular(arm: NearlySRS, pose: np.ndarray, label: Branch) -> SingularArmAngles | None:
    """The neighbour's singular arm angles of the pose, or ``None`` where the neighbour does not reach it."""
    from redkin.srs.ik import reachable

    if not reachable(arm.geometry, pose):
        return None
    return singular_arm_angles(arm.geometry, pose, label)


def _local_minima(size: np.ndarray, closed: bool) -> np.ndarray:
    """Indices of the local minima of sizes sampled along a curve, the first and last samples neighbours where
    ``closed``: one per run of neighbouring sizes equal to :data:`_EQUAL` (relative), at its smallest, where the runs
    either side are larger (or ``inf``, a missing value, on one side and larger on the other).  A stretch that only
    rounding varies (a joint pair that the self-motion leaves still) is one run, not thousands of minima."""
    if len(size) == 0:
        return np.empty(0, dtype=int)

    def equal(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return np.isclose(a, b, rtol=_EQUAL, atol=0.0) | (np.isinf(a) & np.isinf(b))

    run = np.concatenate([[0], np.cumsum(~equal(size[1:], size[:-1]))])
    if closed and run[-1] > 0 and equal(size[:1], size[-1:])[0]:
        run[run == run[-1]] = 0  # the last run goes on round into the first
    order = np.lexsort((size, run))
    lowest = order[np.searchsorted(run[order], np.unique(run))]
    value = size[lowest]
    if len(value) == 1:
        return lowest[np.isfinite(value)]
    padded = np.concatenate([value[-1:], value, value[:1]]) if closed else np.concatenate([[np.inf], value, [np.inf]])
    before, after = padded[:-2], padded[2:]
    minimum = np.isfinite(value) & (value <= before) & (value <= after) & ((value < before) | (value < after))
    return lowest[minimum]
