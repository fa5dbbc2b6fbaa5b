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

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

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
    try:
        d_e = np.broadcast_to(d_e, jac.shape[:-2])
    except ValueError:
        raise ValueError(f"index must have shape {jac.shape[:-2]} (one D_e per jacobian), got shape {d_e.shape}") from None
    exact = np.abs(d_e) < limit
    if not exact.any():
        return _scaled_pseudoinverse(jac, vel, d_e, eps, direction, self_motion, modify_rotation)
    if exact.all():
        return singularity_consistent(jac, vel, d_e, factors(), eps, direction, self_motion, modify_rotation)
    # Mixed batch: each configuration takes its own path (the exact one only where it is needed).
    d_i = np.broadcast_to(np.asarray(factors(), dtype=float), jac.shape[:-2] + (jac.shape[-1],))
    qdot = np.empty(jac.shape[:-2] + (jac.shape[-1],))
    target = np.empty(vel.shape)
    lean = ~exact
    qdot[lean], target[lean] = _scaled_pseudoinverse(
        jac[lean], vel[lean], d_e[lean], eps, direction, self_motion, modify_rotation
    )
    qdot[exact], target[exact] = singularity_consistent(
        jac[exact], vel[exact], d_e[exact], d_i[exact], eps, direction, self_motion, modify_rotation
    )
    return VelocitySolution(qdot, target)


def _scaled_pseudoinverse(
    jac: np.ndarray,
    vel: np.ndarray,
    d_e: np.ndarray,
    eps: float,
    direction: float,
    self_motion: float,
    modify_rotation: bool,
) -> VelocitySolution:
    """``b_ep g(D_e) J^+ t'`` for ``D_e != 0`` (eqs. 18, 21, 22), one SVD per configuration."""
    target = modified_twist(vel, d_e, eps, direction) if modify_rotation else vel
    target = (direction * twist_scale(d_e, eps))[..., None] * target  # eq. 22
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    coefficients = np.einsum("...ij,...i->...j", u, target) / s
    qdot = np.einsum("...ij,...i->...j", vt, coefficients)  # J^+ (b_ep g t'), eqs. 18, 21
    if self_motion:
        qdot = qdot + self_motion * self_motion_vector(jac)
    return VelocitySolution(qdot, target)
