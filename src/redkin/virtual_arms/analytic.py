"""The analytic forward model of virtual arms: eq. 1 of paper 004 computed from the chain.

Paper 004 section 4 builds the nonlinear functions ``f^i`` of eq. 1 directly
into each subsystem instead of learning them; this is that model.  One call
evaluates every virtual end point and its Jacobian from a single pass of the
chain, batched over leading axes of ``theta``.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.virtual_arms.points import VirtualPoint


def task_axes(chain: SerialChain) -> tuple[int, ...]:
    """World coordinates the task space uses: ``(0, 1)`` for a planar chain in the x-y plane, else ``(0, 1, 2)``.

    A chain is planar here when every joint axis is parallel to the world z axis
    and every frame origin has the base height, checked at two generic postures.
    """
    rng = np.random.default_rng(0)
    for q in rng.uniform(-2.0, 2.0, size=(2, chain.n)):
        directions, _ = chain.joint_axes(q)
        origins = chain.frames(q)[:, 2, 3]
        if not (np.allclose(np.abs(directions[:, 2]), 1.0, atol=1e-12) and np.allclose(origins, origins[0], atol=1e-12)):
            return (0, 1, 2)
    return (0, 1)


class AnalyticModel:
    """Positions and Jacobians of virtual end points computed from the chain.

    Parameters
    ----------
    chain : SerialChain
    points : sequence of VirtualPoint
    axes : tuple of int, optional
        World coordinates of the task space; default :func:`task_axes`.
    """

    def __init__(self, chain: SerialChain, points: Sequence[VirtualPoint], axes: tuple[int, ...] | None = None):
        if len(points) == 0:
            raise ValueError("points must name at least one virtual end point, got none")
        self.chain = chain
        self.points = list(points)
        self.axes = task_axes(chain) if axes is None else tuple(axes)
        anchors = [p.anchor(chain) for p in self.points]
        self._frames = np.array([a[0] for a in anchors])
        self._local = np.array([a[1] for a in anchors])
        # joints that move each point: those before its frame (the tool frame moves with all n)
        self._moved_by = np.arange(chain.n)[None, :] < np.minimum(self._frames, chain.n)[:, None]

    @property
    def dims(self) -> int:
        """Task-space dimension ``l``."""
        return len(self.axes)

    @property
    def count(self) -> int:
        """Number of virtual end points."""
        return len(self.points)

    @property
    def joints(self) -> int:
        """Number of joints ``m``."""
        return self.chain.n

    def evaluate(self, theta: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Positions ``X^i = f^i(theta)`` (eq. 1) and Jacobians ``d f^i / d theta``.

        Parameters
        ----------
        theta : array_like, shape (..., m)

        Returns
        -------
        positions : numpy.ndarray, shape (..., p, l)
        jacobians : numpy.ndarray, shape (..., p, l, m)
        """
        frames = self.chain.frames(theta)  # (..., n + 2, 4, 4); validates theta
        chosen = frames[..., self._frames, :, :]
        world = chosen[..., :3, 3] + (chosen[..., :3, :3] @ self._local[..., None])[..., 0]
        directions, origins = self.chain.joint_axes_in(frames)  # (..., m, 3)
        directions = directions * self.chain.sign[:, None]
        lever = world[..., :, None, :] - origins[..., None, :, :]  # (..., p, m, 3)
        turning = directions[..., None, :, :]
        # rows of the task space only: (directions x lever)[c] for c in self.axes
        linear = np.stack([turning[..., (c + 1) % 3] * lever[..., (c + 2) % 3]
                           - turning[..., (c + 2) % 3] * lever[..., (c + 1) % 3] for c in self.axes], axis=-2)
        return world[..., list(self.axes)], linear * self._moved_by[:, None, :]

    def split(self) -> list["AnalyticModel"]:
        """One single-point model per virtual end point (the subsystems' own models)."""
        return [AnalyticModel(self.chain, [p], self.axes) for p in self.points]
