"""Obstacles and the clearance of an arm to them (paper 004 section 4, Fig. 8).

An obstacle is a circle in a planar task space or a sphere in a spatial one.
The arm is monitored as its *skeleton*: the polyline through the base, every
joint origin and the tool origin (the chain's frame origins), so every virtual
end point at a joint or anywhere along a link is covered, and a link cannot cut
through an obstacle between two monitored points.  Clearance is the distance
to the obstacle's surface, negative inside.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import MAX_LENGTH, check_magnitude
from redkin.chain import SerialChain
from redkin.errors import RedkinError


@dataclass(frozen=True)
class Obstacle:
    """A circle (2-D task space) or a sphere (3-D) with ``centre`` and ``radius`` in metres.

    Raises
    ------
    ValueError
        If the centre is not a finite 2- or 3-vector or the radius is not a finite positive number.
    """

    centre: np.ndarray
    radius: float

    def __post_init__(self) -> None:
        centre = np.asarray(self.centre, dtype=float)
        if centre.shape not in ((2,), (3,)) or not np.all(np.isfinite(centre)):
            raise RedkinError(f"obstacle centre must be 2 or 3 finite coordinates, got {self.centre!r}")
        radius = float(self.radius)
        if not np.isfinite(radius) or radius <= 0.0:
            raise RedkinError(f"obstacle radius must be a finite positive number of metres, got {self.radius!r}")
        object.__setattr__(self, "centre", centre)
        object.__setattr__(self, "radius", radius)

    @property
    def dims(self) -> int:
        return len(self.centre)

    def clearance(self, points: ArrayLike) -> np.ndarray:
        """Distance from ``points`` (..., l) to the surface (negative inside)."""
        return np.linalg.norm(np.asarray(points, dtype=float) - self.centre, axis=-1) - self.radius


def as_obstacles(obstacles: Sequence[Obstacle | ArrayLike], dims: int) -> list[Obstacle]:
    """Obstacles from :class:`Obstacle` objects or rows ``(x, y, r)`` / ``(x, y, z, r)``, checked against ``dims``.

    Raises
    ------
    ValueError
        For a row of the wrong length, a bad radius, or an obstacle of another dimension than the task space.
    """
    checked = []
    for k, item in enumerate(obstacles):
        if not isinstance(item, Obstacle):
            row = np.asarray(item, dtype=float).ravel()
            if row.shape != (dims + 1,):
                raise RedkinError(f"obstacle {k} must be {dims} centre coordinates and a radius, got {list(row)}")
            item = Obstacle(row[:-1], row[-1])
        if item.dims != dims:
            raise RedkinError(f"obstacle {k} is {item.dims}-D but the task space is {dims}-D")
        check_magnitude(np.append(item.centre, item.radius), f"obstacle {k}", MAX_LENGTH, "m")
        checked.append(item)
    return checked


def skeleton(chain: SerialChain, theta: ArrayLike, axes: Sequence[int]) -> np.ndarray:
    """Frame origins (base, joints, tool) of ``chain`` at ``theta`` (..., m) in task coordinates: (..., n + 2, l)."""
    return chain.frames(theta)[..., :3, 3][..., list(axes)]


def _segment_clearance(starts: np.ndarray, ends: np.ndarray, obstacle: Obstacle) -> np.ndarray:
    """Clearance of the segments ``starts -> ends`` (..., l) to ``obstacle``: nearest point of each segment."""
    along = ends - starts
    length2 = np.sum(along * along, axis=-1)
    t = np.sum((obstacle.centre - starts) * along, axis=-1) / np.where(length2 > 0.0, length2, 1.0)
    nearest = starts + np.clip(t, 0.0, 1.0)[..., None] * along
    return obstacle.clearance(nearest)


def arm_clearance(
    chain: SerialChain, theta: ArrayLike, obstacles: Sequence[Obstacle], axes: Sequence[int]
) -> np.ndarray:
    """Smallest clearance of the arm's skeleton (every link segment) to any obstacle, per joint vector (...).

    ``inf`` when there are no obstacles.
    """
    points = skeleton(chain, theta, axes)
    result = np.full(points.shape[:-2], np.inf)
    for obstacle in obstacles:
        per_link = _segment_clearance(points[..., :-1, :], points[..., 1:, :], obstacle)
        result = np.minimum(result, per_link.min(axis=-1))
    return result


def densify(theta: np.ndarray, max_joint_step: float) -> tuple[np.ndarray, np.ndarray]:
    """Joint vectors linearly interpolated between consecutive records so no joint moves more than ``max_joint_step``.

    Returns
    -------
    dense : numpy.ndarray, shape (D, m)
        The records and the points between them, in order.
    record : numpy.ndarray of int, shape (D,)
        For every dense vector, the index of the record that ends its interval (0 for the first record).
    """
    theta = np.asarray(theta, dtype=float)
    jumps = np.max(np.abs(np.diff(theta, axis=0)), axis=1, initial=0.0) if len(theta) > 1 else np.zeros(0)
    pieces = np.maximum(1, np.ceil(jumps / max_joint_step).astype(int))
    dense, record = [theta[:1]], [np.zeros(1, dtype=int)]
    for k, count in enumerate(pieces):
        fractions = np.arange(1, count + 1)[:, None] / count
        dense.append(theta[k] + fractions * (theta[k + 1] - theta[k]))
        record.append(np.full(count, k + 1))
    return np.concatenate(dense), np.concatenate(record)
