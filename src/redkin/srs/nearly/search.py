"""Solutions of a nearly S-R-S arm on a grid of arm angles, and the pose with one more equation on the real arm.

:func:`solutions_at` gives a branch's certified solutions (:func:`redkin.srs.nearly.ik`) on a grid of arm angles,
:func:`merged` adds arm angles to such a grid.  :func:`polished` solves the pose and one more equation ``F(q) = c``
on the real arm (Levenberg-Marquardt): an aligned configuration (``F`` the angle between two axes), or a point of
the self-motion at a given arm angle.  Used by :mod:`redkin.srs.nearly.singular`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from redkin.srs.branches import Branch
from redkin.srs.nearly.arm import TOLERANCE, NearlySRS, ik

#: Arm angles closer than this [rad] are one sample (:func:`merged`).
_DISTINCT = 1e-6
#: Step [rad] of the central differences in ``q``.
_STEP = 1e-6


def solutions_at(arm: NearlySRS, pose: np.ndarray, psi: np.ndarray, branch: Branch) -> tuple[np.ndarray, np.ndarray]:
    """The branch's certified solutions of ``pose`` at arm angles ``psi`` (M,): joint values (M, 7) and whether each
    exists."""
    result = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    return result.q[:, 0], result.exists[:, 0]


def merged(grid: np.ndarray, extra: np.ndarray) -> np.ndarray:
    """The sorted arm angles of ``grid`` and of ``extra`` (wrapped into ``(-pi, pi]``) that lie more than
    :data:`_DISTINCT` rad from every grid value: two samples closer than that are one (a minimum between them
    has no room)."""
    extra = np.angle(np.exp(1j * np.asarray(extra, dtype=float)))
    gap = np.abs(np.angle(np.exp(1j * (extra[:, None] - grid[None, :])))).min(axis=1) if grid.size else extra
    return np.sort(np.concatenate([grid, np.unique(extra[gap > _DISTINCT])]))


def polished(arm: NearlySRS, q: np.ndarray, pose: np.ndarray, function: Callable[[np.ndarray], np.ndarray],
             target: np.ndarray | float = 0.0, iterations: int = 60) -> tuple[np.ndarray, np.ndarray]:
    """Levenberg-Marquardt steps on the real arm for the seven equations ``FK(q) = pose`` and ``F(q) = target``
    (an angle: the difference is wrapped) from joint values ``q`` (M, 7), ``grad F`` by central differences; the
    joint values and whether each is certified: its pose within :data:`redkin.srs.nearly.TOLERANCE` (metres,
    radians) of ``pose`` and ``F`` within it of ``target`` too.

    A step is taken where it lowers the residual (the damping then shrinks), else the damping grows: near an
    alignment of the arm's axes the seven equations are ill-conditioned and plain Newton steps leap away.
    """
    q = q.copy()
    damping = np.full(len(q), 1e-6)
    goal = np.broadcast_to(target, (len(q),))

    def residual_of(values: np.ndarray, rows: np.ndarray) -> np.ndarray:
        off = _wrapped(goal[rows] - function(values))
        return np.concatenate([_pose_residual(arm.chain.fk(values), pose), off[:, None]], axis=-1)

    residual = residual_of(q, np.arange(len(q)))
    size = np.linalg.norm(residual, axis=-1)
    for _ in range(iterations):
        active = np.flatnonzero((size > 1e-14) & (damping < 1e6))  # on to rounding, unless stalled
        if active.size == 0:
            break
        matrix = np.empty((active.size, 7, 7))
        matrix[:, :6] = arm.chain.jacobian(q[active])
        matrix[:, 6] = _gradient(q[active], function)
        transposed = np.swapaxes(matrix, -1, -2)
        normal = transposed @ matrix + damping[active, None, None] * np.eye(7)
        step = np.linalg.solve(normal, transposed @ residual[active, :, None])[..., 0]
        trial = q[active] + step
        trial_residual = residual_of(trial, active)
        trial_size = np.linalg.norm(trial_residual, axis=-1)
        better = np.isfinite(trial_size) & (trial_size < size[active])
        taken = active[better]
        q[taken], residual[taken], size[taken] = trial[better], trial_residual[better], trial_size[better]
        damping[taken] = np.maximum(damping[taken] / 3.0, 1e-15)
        damping[active[~better]] *= 4.0
    position, rotation = _pose_error(arm.chain.fk(q), pose)
    certified = (position <= TOLERANCE) & (rotation <= TOLERANCE) & (np.abs(_wrapped(goal - function(q))) <= TOLERANCE)
    return q, certified


def _gradient(q: np.ndarray, function: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """``grad F`` (M, 7) at joint values ``q`` (M, 7) by central differences (of an angle: wrapped)."""
    moved = np.repeat(q[None], 14, axis=0)
    for j in range(7):
        moved[2 * j, :, j] += _STEP
        moved[2 * j + 1, :, j] -= _STEP
    values = function(moved).reshape(7, 2, len(q))
    return (_wrapped(values[:, 0] - values[:, 1]) / (2.0 * _STEP)).T


def _wrapped(angle: np.ndarray) -> np.ndarray:
    """Angles (or small differences) into ``(-pi, pi]``."""
    return np.angle(np.exp(1j * angle))


def _rotation_vector(relative: np.ndarray) -> np.ndarray:
    """The rotation vectors (M, 3) of rotation matrices (M, 3, 3)."""
    skew = np.stack([relative[:, 2, 1] - relative[:, 1, 2], relative[:, 0, 2] - relative[:, 2, 0],
                     relative[:, 1, 0] - relative[:, 0, 1]], axis=-1)
    size = np.linalg.norm(skew, axis=-1)
    angle = np.arctan2(0.5 * size, 0.5 * (np.trace(relative, axis1=-2, axis2=-1) - 1.0))
    return np.where(size > 0.0, angle / np.where(size > 0.0, size, 1.0), 0.5)[:, None] * skew


def _pose_residual(reached: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """``[p_t - p; rotation vector of R_t R^T]`` (M, 6): the world-referred error of poses (M, 4, 4) against one
    target, the right side of Newton's step with the geometric Jacobian."""
    relative = pose[:3, :3] @ np.swapaxes(reached[:, :3, :3], -1, -2)
    return np.concatenate([pose[:3, 3] - reached[:, :3, 3], _rotation_vector(relative)], axis=-1)


def _pose_error(reached: np.ndarray, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error [m] and rotation angle [rad] of poses (M, 4, 4) against one target."""
    relative = pose[:3, :3] @ np.swapaxes(reached[:, :3, :3], -1, -2)
    return (np.linalg.norm(pose[:3, 3] - reached[:, :3, 3], axis=-1),
            np.linalg.norm(_rotation_vector(relative), axis=-1))
