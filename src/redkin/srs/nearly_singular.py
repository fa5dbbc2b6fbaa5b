"""Singular arm angles of a nearly S-R-S arm: where the real arm's joint 1/3 or 5/7 pair aligns along the self-motion.

On an exact S-R-S arm the shoulder is singular where ``theta_2 = 0`` [000 eqs. 31-32]: axes 1 and 3 coincide, and
only ``theta_1 + theta_3`` is fixed; likewise the wrist where ``theta_6 = 0`` [000 eqs. 33-34].  The configurations
with ``theta_2 = 0`` reach a set of poses of one dimension less, so most poses have no singular arm angle.

On the real arm the pair's axes need not meet (the Gen3's axes 1 and 3 are 11.75 mm apart), so "coincide" becomes
**aligned**: axes 1 and 3 (5 and 7) parallel, as the neighbour's are at ``theta_2 = 0`` (``theta_6 = 0``).  With
the axes apart, joints 1 and 3 no longer undo each other there, the aligned configurations reach an open set of
poses, and a self-motion near one of the neighbour's singular poses typically passes through alignment at two arm
angles, where its ``theta_2`` changes sign: the branch ``(+, s4, s6)`` ends there and ``(-, s4, s6)`` goes on.
Near such an arm angle the neighbour's closed form is ill-conditioned and :func:`redkin.srs.nearly.ik` may miss
the solution or land on another sheet (docs/srs.md).

:func:`singular_arm_angles_nearly` computes, for one pose and branch, on the real arm:

* the **singular arm angles** of the shoulder (wrist): the arm angles of configurations that reach the pose with
  the pair aligned, ``sigma(q) = 0`` (:func:`alignment_angles`), and the branch's other two signs.  Each is found
  by Newton's method on the seven equations ``FK(q) = T``, ``sigma(q) = 0`` (:func:`redkin.srs.nearly_search.polished`)
  from the branch's solution where ``|sigma|`` has a local minimum on a grid of arm angles (with the neighbour's own
  nearest approach, the largest ``cos theta_2`` [000 eq. 14] or ``cos theta_6`` [000 eq. 18], merged in), and is
  certified: the pose within 1e-9 m and 1e-9 rad, ``|sigma|`` within 1e-9 rad, the arm angle that of the
  configuration (:func:`redkin.srs.nearly.arm_angle`);
* the **nearest approach** of each pair to alignment along the branch's certified solutions: the arm angle where
  ``|sigma|`` is smallest, located by bisection on its derivative along the self-motion
  (:func:`redkin.srs.nearly_search.located_extremum`) to 1e-10 rad, and ``|sigma|`` there.

What is not claimed: a dip of ``|sigma|`` narrower than the grid that the neighbour's nearest approach does not
announce, and an aligned configuration whose Newton start is not in its basin.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.errors import RedkinError
from redkin.srs.branches import Branch, branch_of_theta, parse_branch
from redkin.srs.nearly import NearlySRS, arm_angle
from redkin.srs.nearly_search import located_extremum, merged, polished, solutions_at
from redkin.srs.singular import SingularArmAngles, singular_arm_angles

#: Arm angles of the uniform grid.
_SAMPLES = 720
#: The joints (0-based) of the shoulder's and the wrist's pair, the joint between them, and the branch signs that
#: stay fixed through the pair's alignment (Table 1 signs of theta_2, theta_4, theta_6).
_PAIRS = {"shoulder": (0, 2, 1, (1, 2)), "wrist": (4, 6, 5, (0, 1))}
#: A local minimum of ``|sigma|`` on the grid larger than this [rad] starts no Newton search.
_START = 0.2
#: The turns ``d`` of :func:`_split` [rad].
_SPLITS = np.linspace(-np.pi, np.pi, 12, endpoint=False)
#: Arm-angle offsets [rad] at which the self-motion through an aligned configuration is followed.
_TRACE = 1e-5 * 2.0 ** np.arange(12)
#: Singular arm angles closer than this [rad] are one.
_SAME = 1e-9


class Alignment(NamedTuple):
    """Where a pair of axes comes nearest to alignment along a branch: the arm angle [rad] and the angle between
    the axes there [rad]."""

    psi: float
    angle: float


@dataclass(frozen=True)
class NearlySingular:
    """Singular arm angles of one pose and branch of a nearly S-R-S arm (module docstring).

    Attributes
    ----------
    shoulder, wrist : tuple of float
        Arm angles [rad] at which a configuration reaching the pose has axes 1 and 3 (5 and 7) aligned, sorted;
        empty if none was found.
    shoulder_q, wrist_q : numpy.ndarray, shape (K, 7)
        Those configurations, certified (module docstring), in the order of the arm angles.
    shoulder_nearest, wrist_nearest : Alignment or None
        The pair's nearest approach to alignment along the branch's certified solutions; ``None`` where the branch
        has none at any sampled arm angle.
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
    """The signed angles ``sigma`` [rad] of the real arm's axes 1 and 3, and 5 and 7, from their alignment at joint
    values ``q`` (..., 7).

    Zero where the pair is parallel as the neighbour's is at ``theta_2 = 0`` (``theta_6 = 0``); the sign is that of
    the turn from axis 1 to axis 3 about axis 2 (5 to 7 about 6), so that ``sigma`` is smooth through alignment;
    ``sigma = +-theta_2`` (``+-theta_6``) on an arm whose twists are right angles.
    """
    directions, _ = arm.chain.joint_axes(q)
    reference, _ = arm.chain.joint_axes(arm.geometry.q_of_theta(np.zeros(7)))
    angles = []
    for first, second, middle, _ in _PAIRS.values():
        sense = np.sign(reference[first] @ reference[second])
        a, b = directions[..., first, :], sense * directions[..., second, :]
        cross = np.cross(a, b)
        turn = np.sign(np.einsum("...i,...i->...", cross, directions[..., middle, :]))
        angles.append(np.where(turn < 0.0, -1.0, 1.0) * np.arctan2(np.linalg.norm(cross, axis=-1),
                                                                   np.einsum("...i,...i->...", a, b)))
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
    signs = np.array(arm.geometry.kernel_branch(label)[0])
    found: dict[str, tuple[list[float], np.ndarray, Alignment | None]] = {}
    for k, (part, sigma) in enumerate(zip(_PAIRS, alignment_angles(arm, q))):
        size = np.where(exists, np.abs(sigma), np.inf)

        def pair_size(values: np.ndarray, k: int = k) -> np.ndarray:
            return np.abs(alignment_angles(arm, values)[k])

        def pair_sigma(values: np.ndarray, k: int = k) -> np.ndarray:
            return alignment_angles(arm, values)[k]

        minima = _local_minima(size)
        approaches = [_refined(arm, pose, label, psi, q, size, m, pair_size) for m in minima]
        starts = [m for m in minima if size[m] <= _START]
        angles, configurations = _aligned(arm, pose, _split(arm, q[starts], _PAIRS[part][0]), pair_sigma, signs,
                                          _PAIRS[part][3])
        found[part] = (angles, configurations, min(approaches, key=lambda a: a.angle) if approaches else None)
    return NearlySingular(tuple(found["shoulder"][0]), tuple(found["wrist"][0]), found["shoulder"][1],
                          found["wrist"][1], found["shoulder"][2], found["wrist"][2], label, neighbour)


def _aligned(arm: NearlySRS, pose: np.ndarray, starts: np.ndarray, sigma, signs: np.ndarray,
             kept: tuple[int, int]) -> tuple[list[float], np.ndarray]:
    """The certified aligned configurations Newton reaches from ``starts`` (M, 7) whose branch signs ``kept`` are
    those of ``signs``: their arm angles, sorted and each once, and the configurations (K, 7)."""
    if len(starts) == 0:
        return [], np.empty((0, 7))
    q, certified = polished(arm, starts, pose, sigma)
    q = q[certified]
    q = np.concatenate([q, _traced_crossings(arm, pose, q, sigma)])
    theta = arm.geometry.theta_of_q(q)
    same = np.all(branch_of_theta(theta, arm.real_phase)[:, kept] == signs[list(kept)], axis=-1)
    q = q[same]
    psi = arm_angle(arm, q)
    order = np.argsort(psi)
    angles: list[float] = []
    rows: list[np.ndarray] = []
    for index in order:
        if not angles or abs(np.angle(np.exp(1j * (psi[index] - angles[-1])))) > _SAME:
            angles.append(float(psi[index]))
            rows.append(q[index])
    if len(angles) > 1 and abs(np.angle(np.exp(1j * (angles[-1] - angles[0])))) <= _SAME:
        angles.pop()
        rows.pop()
    return angles, np.array(rows).reshape(-1, 7)


def _split(arm: NearlySRS, q: np.ndarray, first: int) -> np.ndarray:
    """Newton starts (M * S, 7) from joint values ``q`` (M, 7): the pair's turns ``theta_1 + d``, ``theta_3 - d``
    (``theta_5``, ``theta_7``) for :data:`_SPLITS` values of ``d``.  Near alignment the neighbour's pose depends on
    their sum alone; the real arm's aligned configuration has one split, which the closed form does not know."""
    theta = np.repeat(arm.geometry.theta_of_q(q), len(_SPLITS), axis=0)
    turns = np.tile(_SPLITS, len(q))
    theta[:, first] += turns
    theta[:, first + 2] -= turns
    return arm.geometry.q_of_theta(theta)


def _traced_crossings(arm: NearlySRS, pose: np.ndarray, q: np.ndarray, sigma) -> np.ndarray:
    """Further aligned configurations (K, 7) next to aligned ones ``q`` (M, 7): the self-motion through each is
    followed (Newton's method at fixed arm angles, :func:`redkin.srs.nearly_search.polished`) over arm angles
    :data:`_TRACE` rad either side, and where ``sigma`` changes sign between two of its points Newton solves
    ``sigma = 0`` from the later one.  Near one of the neighbour's singular poses the self-motion passes through
    alignment twice, often closer together than the grid's spacing."""
    if len(q) == 0:
        return np.empty((0, 7))
    psi0 = np.repeat(arm_angle(arm, q), 2)
    side = np.tile([1.0, -1.0], len(q))
    current = np.repeat(q, 2, axis=0)
    before = np.zeros(len(current))
    alive = np.ones(len(current), dtype=bool)
    found = []
    for step in _TRACE:
        target = psi0 + side * step
        moved, certified = polished(arm, current[alive], pose, lambda values: arm_angle(arm, values),
                                    target[alive])
        rows = np.flatnonzero(alive)
        alive[rows[~certified]] = False
        rows = rows[certified]
        current[rows] = moved[certified]
        now = sigma(current[rows])
        crossed = rows[(before[rows] != 0.0) & (np.sign(now) != np.sign(before[rows]))]
        if crossed.size:
            aligned, good = polished(arm, current[crossed], pose, sigma)
            found.append(aligned[good])
        before[rows] = now
    return np.concatenate(found) if found else np.empty((0, 7))


def _neighbour_singular(arm: NearlySRS, pose: np.ndarray, label: Branch) -> SingularArmAngles | None:
    """The neighbour's singular arm angles of the pose, or ``None`` where the neighbour does not reach it."""
    from redkin.srs.ik import reachable

    if not reachable(arm.geometry, pose):
        return None
    return singular_arm_angles(arm.geometry, pose, label)


def _neighbour_nearest(neighbour: SingularArmAngles) -> np.ndarray:
    """The neighbour's nearest approaches: the arm angles of largest ``cos theta_2 = -(a s + b c + c)``
    [000 eq. 14] and ``cos theta_6 = a s + b c + c`` [000 eq. 18]."""
    a_s, b_s, _ = neighbour.shoulder_coefficients
    a_w, b_w, _ = neighbour.wrist_coefficients
    return np.array([np.arctan2(-a_s, -b_s), np.arctan2(a_w, b_w)])


def _local_minima(size: np.ndarray) -> list[int]:
    """Indices of the cyclic local minima of the sampled sizes (finite, no larger than either neighbour and
    smaller than one; next to a missing solution, ``inf``, too)."""
    before, after = np.roll(size, 1), np.roll(size, -1)
    minimum = np.isfinite(size) & (size <= before) & (size <= after) & ((size < before) | (size < after))
    return np.flatnonzero(minimum).tolist()


def _refined(arm: NearlySRS, pose: np.ndarray, label: Branch, psi: np.ndarray, q: np.ndarray, size: np.ndarray,
             m: int, pair_size) -> Alignment:
    """The local minimum of the grid at index ``m`` located between its neighbours along the self-motion through
    the grid's solution there (:func:`redkin.srs.nearly_search.located_extremum`)."""
    count = len(psi)
    low = psi[m - 1] - (2.0 * np.pi if m == 0 else 0.0)
    high = psi[(m + 1) % count] + (2.0 * np.pi if m == count - 1 else 0.0)
    located, q_located = located_extremum(arm, pose, label, pair_size, (float(psi[m]), q[m]), float(low),
                                          float(high), maximum=False)
    value = float(pair_size(q_located[None])[0])
    return Alignment(located, value) if value <= size[m] else Alignment(float(psi[m]), float(size[m]))
