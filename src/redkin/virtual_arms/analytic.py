"""The analytic forward model of virtual arms: [004 eq. 1] computed from the chain.

Paper 004 section 4 builds the nonlinear functions ``f^i`` of [004 eq. 1] directly
into each subsystem instead of learning them; this is that model.  One call
evaluates every virtual end point and its Jacobian from a single pass of the
chain, batched over leading axes of ``theta``: the compiled kernel
:func:`~redkin.virtual_arms._kernels.virtual_points` over the chain kernels
(its tables, the chain's own, are read from the chain).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import run_batch
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.virtual_arms import _kernels as kernels
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
        if not (np.allclose(np.abs(directions[:, 2]), 1.0, atol=1e-12)
                and np.allclose(origins, origins[0], atol=1e-12)):
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
            raise RedkinError("points must name at least one virtual end point, got none")
        self.chain = chain
        self.points = list(points)
        self.axes = task_axes(chain) if axes is None else tuple(axes)
        anchors = [p.anchor(chain) for p in self.points]
        self._frames = np.array([a[0] for a in anchors], dtype=np.int64)
        self._local = np.ascontiguousarray([a[1] for a in anchors], dtype=float)
        self._axes = np.array(self.axes, dtype=np.int64)

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
        """Positions ``X^k = f^k(theta)`` [004 eq. 1] of all end points ([004 eq. 2], as ``(..., n, l)``) and
        Jacobians ``d f^k / d theta``.

        The kernel :func:`~redkin.virtual_arms._kernels.virtual_points`: the
        chain's frames and, per end point, the Jacobian of that point
        (:func:`~redkin._chain_kernels.jacobian_one`), task-space rows only.

        Parameters
        ----------
        theta : array_like, shape (..., m)

        Returns
        -------
        positions : numpy.ndarray, shape (..., p, l)
        jacobians : numpy.ndarray, shape (..., p, l, m)
        """
        q = self.chain.check_q(theta, "theta")
        lead, n, p, dims = q.shape[:-1], self.chain.n, self.count, self.dims
        flat = np.ascontiguousarray(q.reshape(-1, n))
        positions, jacobians = np.empty((flat.shape[0], p, dims)), np.empty((flat.shape[0], p, dims, n))
        run_batch(kernels.virtual_points, flat.shape[0], flat, self.chain._links, self.chain._ends,
                  self.chain._standard, self._frames, self._local, self._axes, positions, jacobians)
        return positions.reshape(lead + (p, dims)), jacobians.reshape(lead + (p, dims, n))

    def split(self) -> list[AnalyticModel]:
        """One single-point model per virtual end point (the subsystems' own models)."""
        return [AnalyticModel(self.chain, [p], self.axes) for p in self.points]
