"""The proposed singularity-consistent method: a weighted sum of fixed-joint vectors (paper 003 section 3).

``n_sum = sum_i b_i n_i`` (eq. 15) realises ``J n_sum = D_sum t`` with
``D_sum = sum_i b_i det J_i`` (eq. 16).  Two choices of weights:

* ``b_i = det J_i`` (eq. 17): ``n_sum = J^T adj(J J^T) t`` -- the
  minimum-norm direction, orthogonal to the self-motion (Appendix A);
* ``b_i = det J_i / det(J J^T)`` (eq. 18): ``n_sum = J^+ t``.

Where the singularity factors through one index, ``det J_i = D_e D_i``
(eq. 19), eq. 18 becomes ``b_i = D_i / (D_e D_s)``, ``D_s = sum D_i^2``
(eq. 20).  Replacing ``1 / D_e`` by the blend weight ``w(D_e)`` of
:mod:`redkin.velocity.blend` (eq. 21, corrected) keeps ``b_i`` finite and
non-zero at ``D_e = 0``, so the joints keep moving through the singularity,
and gives the realised twist ``b_ep g(D_e) t'`` (eq. 22) where ``t'`` is the
command with its rotational part pre-multiplied by ``b_ep clip(D_e/eps)``.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from redkin.validation import check_positive
from redkin.velocity._inputs import jacobian_and_twist
from redkin.velocity.blend import blend_weight, rotation_factor, twist_scale
from redkin.velocity.cofactors import column_minors, fixed_joint_vectors, self_motion_vector, weighted_sum
from redkin.velocity.solution import VelocitySolution


def minimum_norm_weights(jacobian: ArrayLike) -> np.ndarray:
    """``b_i = det J_i`` (paper 003 eq. 17): ``n_sum = J^T adj(J J^T) t``."""
    return column_minors(jacobian)


def pseudoinverse_weights(jacobian: ArrayLike) -> np.ndarray:
    """``b_i = det J_i / det(J J^T)`` (paper 003 eq. 18): ``n_sum = J^+ t``; infinite at a singularity."""
    minors = column_minors(jacobian)
    return minors / np.sum(minors * minors, axis=-1, keepdims=True)  # Cauchy-Binet denominator


def weighted_sum_direction(jacobian: ArrayLike, twist: ArrayLike, weights: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``n_sum`` and ``D_sum`` of paper 003 eqs. 15-16 for weights ``b`` of shape ``(..., n)``."""
    vectors, minors = fixed_joint_vectors(jacobian, twist)
    b = np.asarray(weights, dtype=float)
    if b.shape[-1:] != minors.shape[-1:]:
        raise ValueError(f"weights must have shape (..., {minors.shape[-1]}), got shape {b.shape}")
    return weighted_sum(b, vectors), np.sum(b * minors, axis=-1)


def modified_twist(twist: np.ndarray, index: ArrayLike, eps: float, direction: float) -> np.ndarray:
    """``t'``: the rotational command pre-multiplied by ``b_ep clip(D_e / eps, -1, 1)`` (paper 003 eq. 22 text)."""
    if twist.shape[-1] != 6:
        raise ValueError(f"modify_rotation needs a 6-row (linear, angular) jacobian, got {twist.shape[-1]} rows")
    scale = direction * rotation_factor(index, eps)[..., None]
    return np.concatenate([twist[..., :3], scale * twist[..., 3:]], axis=-1)


def singularity_consistent(
    jacobian: ArrayLike,
    twist: ArrayLike,
    index: ArrayLike,
    factors: ArrayLike,
    eps: float,
    direction: float = 1.0,
    self_motion: float = 0.0,
    modify_rotation: bool = True,
) -> VelocitySolution:
    """Joint velocity of the proposed method (paper 003 eqs. 9, 15, 19-22).

    Parameters
    ----------
    jacobian : array_like, shape (..., 6, 7)
        Geometric Jacobian, linear rows first (any ``(m, m + 1)`` works when
        ``modify_rotation`` is false).
    twist : array_like, shape (..., 6)
        Commanded twist ``v^des`` (linear, angular).
    index : array_like, shape (...)
        Singularity index ``D_e`` with ``det J_i = D_e D_i``.
    factors : array_like, shape (..., 7)
        ``D_i`` (e.g. :class:`~redkin.velocity.factorisation.WamFactorisation`).
    eps : float
        Singular-region threshold ``D_eps`` on ``|D_e|``.
    direction : {+1, -1}
        ``b_ep`` of eq. 22: the sign of ``D_e`` on whose side the command is
        realised as given; on the other side the translation is reversed.
    self_motion : float
        ``b_sm`` of eq. 9 (self-motion added along ``n_sm``).
    modify_rotation : bool
        Pre-multiply the rotational command by ``b_ep clip(D_e / eps, -1, 1)``
        (eq. 22 text) so that rotation keeps its axis and sign through
        ``D_e = 0``.

    Returns
    -------
    VelocitySolution
        ``target_twist = b_ep g(D_e) t'``: the command outside the region
        ``|D_e| <= eps`` (translation reversed on the far side), eq. 22 inside.
    """
    jac, vel = jacobian_and_twist(jacobian, twist, one_redundant=True)
    check_positive(eps, "eps")
    if direction not in (1, -1):
        raise ValueError(f"direction must be +1 or -1, got {direction!r}")
    d_e = np.asarray(index, dtype=float)
    d_i = np.asarray(factors, dtype=float)
    if d_i.shape[-1:] != (jac.shape[-1],):
        raise ValueError(f"factors must have shape (..., {jac.shape[-1]}), got shape {d_i.shape}")
    if not (np.all(np.isfinite(d_e)) and np.all(np.isfinite(d_i))):
        raise ValueError("index and factors must be finite, got NaN or infinity")
    return blended_step(jac, vel, d_e, d_i, eps, direction, self_motion, modify_rotation, cramer_factor_sum)


def cramer_factor_sum(jacobian: np.ndarray, twist: np.ndarray, factors: np.ndarray) -> np.ndarray:
    """``sum_i D_i n_i`` (eq. 15 with ``b_i = D_i``) from the fixed-joint vectors of eqs. 6-8 (Cramer's rule)."""
    vectors, _ = fixed_joint_vectors(jacobian, twist)
    return weighted_sum(factors, vectors)


def adjugate_factor_sum(jacobian: np.ndarray, twist: np.ndarray, factors: np.ndarray) -> np.ndarray:
    """``sum_i D_i n_i`` as ``adj(M) [t; 0]`` with ``M = [J; c^T]``, ``c_i = (-1)^i D_i``: one SVD of ``M``.

    Both sides are polynomials in ``J``, ``t`` and ``D``.  For ``D_e != 0``:
    expanding ``det M`` along its last row gives ``sum_i D_i det J_i =
    D_e D_s`` (eqs. 19-20), and both ``x = adj(M) [t; 0]`` and ``sum_i D_i n_i``
    solve ``M x = D_e D_s [t; 0]`` (``J n_i = det(J_i) t``, and ``c`` is
    parallel to the self-motion vector of eqs. 4-5, to which the
    minimum-norm ``sum_i D_i n_i = D_e D_s J^+ t`` is orthogonal); ``M`` is
    regular there, so they are equal, and by continuity also on ``D_e = 0``.
    The adjugate comes from the SVD ``M = U S V^T`` as
    ``det(U) det(V) V diag(prod_{j != i} s_j) U^T``, which stays accurate for
    a singular ``M`` (no division by a singular value).  Batched over leading
    axes; about a quarter of the cost of :func:`cramer_factor_sum`.
    """
    k = factors.shape[-1]
    signs = (-1.0) ** np.arange(k)
    square = np.concatenate([jacobian, (signs * factors)[..., None, :]], axis=-2)
    u, s, vt = np.linalg.svd(square)
    ones = np.ones(s.shape[:-1] + (1,))
    before = np.cumprod(np.concatenate([ones, s[..., :-1]], axis=-1), axis=-1)
    after = np.cumprod(np.concatenate([ones, s[..., :0:-1]], axis=-1), axis=-1)[..., ::-1]
    orientation = np.linalg.det(u) * np.linalg.det(vt)
    rhs = np.concatenate([twist, np.zeros(twist.shape[:-1] + (1,))], axis=-1)
    coefficients = before * after * np.einsum("...ji,...j->...i", u, rhs)  # diag(prod_{j != i} s_j) U^T [t; 0]
    return orientation[..., None] * np.einsum("...ij,...i->...j", vt, coefficients)


def blended_step(
    jac: np.ndarray,
    vel: np.ndarray,
    d_e: np.ndarray,
    d_i: np.ndarray,
    eps: float,
    direction: float,
    self_motion: float,
    modify_rotation: bool,
    factor_sum: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray],
) -> VelocitySolution:
    """Eqs. 9, 15, 20-22 on trusted arrays, with ``sum_i D_i n_i`` from ``factor_sum`` (Cramer or adjugate)."""
    d_s = np.sum(d_i * d_i, axis=-1)  # eq. 20
    if np.any(d_s <= 0.0):
        raise ValueError("D_s = sum D_i^2 is zero: every factor D_i vanishes, the method is undefined here")
    if modify_rotation:
        vel = modified_twist(vel, d_e, eps, direction)
    # eq. 21 (derived form): b_i = b_ep w(D_e) D_i / D_s, so sum_i b_i n_i = (b_ep w / D_s) sum_i D_i n_i (eq. 15)
    qdot = (direction * blend_weight(d_e, eps) / d_s)[..., None] * factor_sum(jac, vel, d_i)
    if self_motion:
        qdot = qdot + self_motion * self_motion_vector(jac)
    return VelocitySolution(qdot, (direction * twist_scale(d_e, eps))[..., None] * vel)  # eq. 22
