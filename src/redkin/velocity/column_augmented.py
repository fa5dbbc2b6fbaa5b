"""Conventional singularity-consistent method with one joint fixed (paper 003 section 2.1, [003 eqs. 9-11]).

``q_dot = b_sm n_sm + b_ep n_i`` with ``n_i`` the end-point vector of
:func:`~redkin.velocity.cofactors.fixed_joint_vectors` and the weight of
[003 eq. 11], ``b_ep = w(det J_i)`` (:func:`~redkin.velocity.blend.blend_weight`).
The realised twist is ``g(det J_i) v``: exactly ``+-v`` outside the region
``|det J_i| <= eps``, slowed and reversed through ``det J_i = 0``.

Documented weakness (the "internal obstacle", paper 003 section 2.1): the
motion stops and reverses wherever ``det J_i = 0``, which happens inside the
workspace where ``det(J J^T) > 0`` -- an *algorithmic* singularity that
depends on the fixed joint.  On the Barrett WAM ``det J_4`` is identically
zero (fixing the elbow leaves a spherical shoulder and wrist), so fixing
joint 4 never moves the end point at all.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_jacobian_and_twist, check_positive
from redkin.errors import RedkinError
from redkin.velocity.blend import blend_weight, twist_scale
from redkin.velocity.cofactors import column_minors, fixed_joint_vectors, self_motion_vector
from redkin.velocity.solution import VelocitySolution


def fixed_joint_sc(
    jacobian: ArrayLike,
    twist: ArrayLike,
    joint: int,
    eps: float,
    self_motion: float = 0.0,
) -> VelocitySolution:
    """Joint velocity of the column-augmented SC method with joint ``joint`` (0-based) fixed [003 eqs. 9-11]
    (``q_bar = b_sm n_sm + b_ep n_ep`` of [003 eq. 3]).

    Parameters
    ----------
    jacobian : array_like, shape (..., m, m + 1)
    twist : array_like, shape (..., m)
        Commanded twist ``v`` ([003 eq. 11] writes ``||V||`` times a unit direction; linear in ``v``).
    joint : int
        Fixed joint ``i`` (0-based).
    eps : float
        Singular-region threshold ``D_eps`` on ``|det J_i|``.
    self_motion : float
        ``b_sm`` of [003 eq. 9].
    """
    jac, vel = check_jacobian_and_twist(jacobian, twist, one_redundant=True)
    k = jac.shape[-1]
    if int(joint) != joint or not 0 <= joint < k:
        raise RedkinError(f"joint must be an integer in 0..{k - 1}, got {joint!r}")
    check_positive(eps, "eps")
    vectors, minors = fixed_joint_vectors(jac, vel)
    minor = minors[..., joint]
    qdot = blend_weight(minor, eps)[..., None] * vectors[..., joint, :]  # [003 eqs. 9, 11]
    if self_motion:
        qdot = qdot + self_motion * self_motion_vector(jac)
    return VelocitySolution(qdot, twist_scale(minor, eps)[..., None] * vel)


def algorithmic_singularity(jacobian: ArrayLike, joint: int, tolerance: float = 1e-9) -> np.ndarray:
    """Whether joint ``joint`` (0-based) fixed gives an algorithmic singularity: ``det J_i ~ 0`` but ``det(J J^T) > 0``.

    Both are compared relative to ``sqrt(det(J J^T))`` (Cauchy-Binet:
    ``det(J J^T) = sum det(J_i)^2``), so the answer is scale-free.
    """
    minors = column_minors(jacobian)
    if int(joint) != joint or not 0 <= joint < minors.shape[-1]:
        raise RedkinError(f"joint must be an integer in 0..{minors.shape[-1] - 1}, got {joint!r}")
    total = np.sqrt(np.sum(minors * minors, axis=-1))
    return (np.abs(minors[..., joint]) <= tolerance * total) & (total > tolerance)
