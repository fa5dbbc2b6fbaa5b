"""A lean control step of the singularity-consistent method (paper 003 eqs. 17-22), same result as the exact path.

Away from ``D_e = 0`` the weighted sum of fixed-joint vectors collapses to a
scaled pseudoinverse.  With ``det J_i = D_e D_i`` (eq. 19) and
``sum_i det J_i n_i = J^T adj(J J^T) t`` (eq. 17),
``adj(J J^T) = det(J J^T) (J J^T)^-1`` and, by Cauchy-Binet,
``det(J J^T) = sum_i det(J_i)^2 = D_e^2 D_s`` (eqs. 18, 20):

    sum_i D_i n_i = (1 / D_e) J^T adj(J J^T) t' = D_e D_s J^+ t'.

With the weights of eq. 21, ``b_i = b_ep w(D_e) D_i / D_s`` and
``w(D_e) D_e = g(D_e)`` (:mod:`redkin.velocity.blend`), so

    q_dot = b_ep g(D_e) J^+ t'                                  (D_e != 0)

-- one SVD of the 6 x 7 Jacobian instead of 49 6 x 6 determinants, and ``D_i``
is not needed at all.  At ``D_e = 0`` both ``g`` and ``1 / sigma_min`` are
singular and the product is 0/0; its rounding error grows like
``sigma_max / sigma_min``.  Where ``|D_e| < near_zero`` the step therefore
falls back to the exact cofactor path
:func:`~redkin.velocity.proposed.singularity_consistent`, which is finite and
exact on ``D_e = 0``.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.validation import check_positive
from redkin.velocity._inputs import jacobian_and_twist, nonnegative
from redkin.velocity.blend import twist_scale
from redkin.velocity.cofactors import self_motion_vector
from redkin.velocity.proposed import modified_twist, singularity_consistent
from redkin.velocity.solution import VelocitySolution

NEAR_ZERO_FRACTION = 1e-2
"""Default fallback threshold ``near_zero = NEAR_ZERO_FRACTION * eps`` on ``|D_e|``."""


def lean_singularity_consistent(
    jacobian: ArrayLike,
    twist: ArrayLike,
    index: ArrayLike,
    factors: Callable[[], ArrayLike],
    eps: float,
    direction: float = 1.0,
    self_motion: float = 0.0,
    modify_rotation: bool = True,
    near_zero: float | None = None,
) -> VelocitySolution:
    """The SC joint velocity ``b_ep g(D_e) J^+ t'`` (paper 003 eqs. 17-22 combined), equal to the exact path.

    Parameters
    ----------
    jacobian, twist, index, eps, direction, self_motion, modify_rotation
        As in :func:`~redkin.velocity.proposed.singularity_consistent`.
    factors : callable
        ``factors()`` returns ``D_i`` ``(..., 7)``; called only where the exact
        path is needed (``|D_e| < near_zero``).
    near_zero : float, optional
        Fallback threshold on ``|D_e|``; default ``NEAR_ZERO_FRACTION * eps``.

    Returns
    -------
    VelocitySolution
        The same joint velocity and target twist as the exact path (to
        rounding, ~1e-12 relative for ``|D_e| >= near_zero`` on the WAM).
    """
    jac, vel = jacobian_and_twist(jacobian, twist, one_redundant=True)
    check_positive(eps, "eps")
    if direction not in (1, -1):
        raise ValueError(f"direction must be +1 or -1, got {direction!r}")
    limit = NEAR_ZERO_FRACTION * eps if near_zero is None else nonnegative(near_zero, "near_zero")
    d_e = np.asarray(index, dtype=float)
    if not np.all(np.isfinite(d_e)):
        raise ValueError("index must be finite, got NaN or infinity")
    exact = np.abs(d_e) < limit
    if np.all(exact):
        return singularity_consistent(jac, vel, d_e, factors(), eps, direction, self_motion, modify_rotation)
    target = modified_twist(vel, d_e, eps, direction) if modify_rotation else vel
    target = (direction * twist_scale(d_e, eps))[..., None] * target  # eq. 22
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    coefficients = np.einsum("...ij,...i->...j", u, target) / s
    qdot = np.einsum("...ij,...i->...j", vt, coefficients)  # J^+ (b_ep g t'), eqs. 18, 21
    if self_motion:
        qdot = qdot + self_motion * self_motion_vector(jac)
    if np.any(exact):
        slow = singularity_consistent(jac, vel, d_e, factors(), eps, direction, self_motion, modify_rotation)
        qdot = np.where(exact[..., None], slow.joint_velocity, qdot)
        target = np.where(exact[..., None], slow.target_twist, target)
    return VelocitySolution(qdot, target)


class SingleJacobian:
    """Geometric Jacobian of one configuration of a standard-DH chain in scalar arithmetic (the control-loop case).

    Same result as ``chain.jacobian(q)`` for a single ``q`` of shape ``(7,)``,
    without the batching overhead: the frames are propagated on plain floats
    (``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` per row).  The chain is bound once.
    """

    def __init__(self, chain: SerialChain) -> None:
        if chain.convention != "dh":
            raise ValueError(f"SingleJacobian needs a standard-DH chain, got convention {chain.convention!r}")
        self.n = chain.n
        self._rows = [
            (float(off), float(sg), float(a), float(d), math.cos(al), math.sin(al))
            for off, sg, a, d, al in zip(chain.offset, chain.sign, chain.a, chain.d, chain.alpha)
        ]
        self._base = [[float(v) for v in chain.base[:3, k]] for k in range(4)]
        self._tool = [float(v) for v in chain.tool[:3, 3]]

    def __call__(self, q: ArrayLike) -> np.ndarray:
        values = np.asarray(q, dtype=float)
        if values.shape != (self.n,) or not np.all(np.isfinite(values)):
            raise ValueError(f"q must be a finite vector of shape ({self.n},), got shape {values.shape}")
        x, y, z, p = self._base
        axes, points = [], []
        for angle, (off, sg, a, d, ca, sa) in zip(values.tolist(), self._rows):
            axes.append(z)
            points.append(p)
            theta = off + sg * angle
            c, s = math.cos(theta), math.sin(theta)
            x, y = [c * xi + s * yi for xi, yi in zip(x, y)], [c * yi - s * xi for xi, yi in zip(x, y)]
            p = [pi + d * zi + a * xi for pi, zi, xi in zip(p, z, x)]
            y, z = [ca * yi + sa * zi for yi, zi in zip(y, z)], [ca * zi - sa * yi for yi, zi in zip(y, z)]
        tx, ty, tz = self._tool
        end = [pi + tx * xi + ty * yi + tz * zi for pi, xi, yi, zi in zip(p, x, y, z)]
        columns = []
        for (ux, uy, uz), (px, py, pz), sg in zip(axes, points, (row[1] for row in self._rows)):
            lx, ly, lz = end[0] - px, end[1] - py, end[2] - pz
            columns.append([sg * (uy * lz - uz * ly), sg * (uz * lx - ux * lz), sg * (ux * ly - uy * lx),
                            sg * ux, sg * uy, sg * uz])
        return np.array(columns).T
