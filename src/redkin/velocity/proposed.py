"""The proposed singularity-consistent method: a weighted sum of fixed-joint vectors (paper 003 section 3).

``n_sum = sum_i b_i n_i`` [003 eq. 15] realises ``J n_sum = D_sum t`` with
``D_sum = sum_i b_i det J_i`` [003 eq. 16].  Two choices of weights:

* ``b_i = det J_i`` [003 eq. 17]: ``n_sum = J^T adj(J J^T) t`` -- the
  minimum-norm direction, orthogonal to the self-motion (Appendix A);
* ``b_i = det J_i / det(J J^T)`` [003 eq. 18]: ``n_sum = J^+ t``.

Where the singularity factors through one index, ``det J_i = D_e D_i``
[003 eq. 19], [003 eq. 18] becomes ``b_i = D_i / (D_e D_s)``, ``D_s = sum D_i^2``
[003 eq. 20].  Replacing ``1 / D_e`` by the blend weight ``w(D_e)`` of
:mod:`redkin.velocity.blend` ([003 eq. 21], corrected) keeps ``b_i`` finite and
non-zero at ``D_e = 0``, so the joints keep moving through the singularity,
and gives the realised twist ``b_ep g(D_e) t'`` [003 eq. 22] where ``t'`` is the
command with its rotational part pre-multiplied by ``b_ep clip(D_e/eps)``.

Both steps here are the kernel :func:`~redkin.velocity._step_kernels.sc_one`.
It sums the fixed-joint vectors in closed form: ``sum_i D_i n_i`` is
``adj(M) [t'; 0]`` with ``M = [J; c^T]``, ``c_i = (-1)^i D_i``.  Both sides
are polynomials in ``J``, ``t'`` and ``D``; for ``D_e != 0``, expanding
``det M`` along its last row gives ``sum_i D_i det J_i = D_e D_s`` (eqs.
19-20), and both solve ``M x = D_e D_s [t'; 0]`` (``J n_i = det(J_i) t'``,
and ``c`` is parallel to the self-motion vector of [003 eqs. 4-5], to which the
minimum-norm ``sum_i D_i n_i`` is orthogonal); ``M`` is regular there, so
they are equal, and by continuity also on ``D_e = 0``.  Away from ``D_e =
0`` the sum collapses further.  With ``det J_i = D_e D_i`` [003 eq. 19],
``sum_i det J_i n_i = J^T adj(J J^T) t'`` [003 eq. 17] and, by Cauchy-Binet,
``det(J J^T) = D_e^2 D_s`` [003 eqs. 18, 20]:

    sum_i D_i n_i = D_e D_s J^+ t',    so    q_dot = b_ep g(D_e) J^+ t'   (D_e != 0)

-- one pseudoinverse, and ``D_i`` is not needed at all.  At ``D_e = 0`` both
``g`` and ``1 / sigma_min`` are singular and the product is 0/0, its
rounding error growing like ``sigma_max / sigma_min``; so
:func:`lean_singularity_consistent` takes the pseudoinverse only where
``|D_e| >= near_zero`` and the adjugate below, while
:func:`singularity_consistent` always takes the adjugate.  The definitional
form, the weighted sum of [003 eq. 15] over the Cramer vectors of
:func:`~redkin.velocity.cofactors.fixed_joint_vectors`, is the tests'
reference for both.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import check_jacobian_and_twist, check_nonnegative, check_positive
from redkin.errors import RedkinError
from redkin.velocity import _step_kernels
from redkin.velocity.cofactors import column_minors, fixed_joint_vectors, weighted_sum
from redkin.velocity.solution import VelocitySolution

NEAR_ZERO_FRACTION = 1e-2
"""Default fallback threshold ``near_zero = NEAR_ZERO_FRACTION * eps`` on ``|D_e|`` of the lean step."""


def minimum_norm_weights(jacobian: ArrayLike) -> np.ndarray:
    """``b_i = det J_i`` [003 eq. 17]: ``n_sum = J^T adj(J J^T) t``."""
    return column_minors(jacobian)


def pseudoinverse_weights(jacobian: ArrayLike) -> np.ndarray:
    """``b_i = det J_i / det(J J^T)`` [003 eq. 18]: ``n_sum = J^+ t``; infinite at a singularity."""
    minors = column_minors(jacobian)
    return minors / np.sum(minors * minors, axis=-1, keepdims=True)  # Cauchy-Binet denominator


def weighted_sum_direction(jacobian: ArrayLike, twist: ArrayLike, weights: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``n_sum`` and ``D_sum`` of [003 eqs. 15-16] for weights ``b`` of shape ``(..., n)``."""
    vectors, minors = fixed_joint_vectors(jacobian, twist)
    b = np.asarray(weights, dtype=float)
    if b.shape[-1:] != minors.shape[-1:]:
        raise RedkinError(f"weights must have shape (..., {minors.shape[-1]}), got shape {b.shape}")
    return weighted_sum(b, vectors), np.sum(b * minors, axis=-1)


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
    """Joint velocity of the proposed method [003 eqs. 9, 15, 19-22].

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
        ``b_ep`` of [003 eq. 22]: the sign of ``D_e`` on whose side the command is
        realised as given; on the other side the translation is reversed.
    self_motion : float
        ``b_sm`` of [003 eq. 9] (self-motion added along ``n_sm``).
    modify_rotation : bool
        Pre-multiply the rotational command by ``b_ep clip(D_e / eps, -1, 1)``
        ([003 eq. 22] text) so that rotation keeps its axis and sign through
        ``D_e = 0``.

    Returns
    -------
    VelocitySolution
        ``target_twist = b_ep g(D_e) t'``: the command outside the region
        ``|D_e| <= eps`` (translation reversed on the far side), [003 eq. 22] inside.
    """
    jac, vel, e = _checked(jacobian, twist, eps, direction, self_motion, modify_rotation)
    d_e = _index(index, jac)
    d_i = _factors(factors, jac)
    return _sc_steps(jac, vel, d_e, d_i, e, direction, self_motion, modify_rotation, np.inf)


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
    """The SC joint velocity ``b_ep g(D_e) J^+ t'`` ([003 eqs. 17-22] combined), equal to the exact path.

    Parameters
    ----------
    jacobian, twist, index, eps, direction, self_motion, modify_rotation
        As in :func:`singularity_consistent`.
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
    jac, vel, e = _checked(jacobian, twist, eps, direction, self_motion, modify_rotation)
    limit = NEAR_ZERO_FRACTION * e if near_zero is None else check_nonnegative(near_zero, "near_zero")
    d_e = _index(index, jac)
    exact = np.abs(d_e) < limit
    d_i = _factors(factors(), jac) if exact.any() else np.zeros(jac.shape[:-2] + jac.shape[-1:])
    return _sc_steps(jac, vel, d_e, d_i, e, direction, self_motion, modify_rotation, limit)


def _checked(jacobian: ArrayLike, twist: ArrayLike, eps: float, direction: float, self_motion: float,
             modify_rotation: bool) -> tuple[np.ndarray, np.ndarray, float]:
    """The checks both SC functions share: Jacobians ``(..., m, m + 1)``, twists, ``eps``, ``b_ep``, ``b_sm``."""
    jac, vel = check_jacobian_and_twist(jacobian, twist, one_redundant=True)
    e = check_positive(eps, "eps")
    if direction not in (1, -1):
        raise RedkinError(f"direction must be +1 or -1, got {direction!r}")
    if not np.isfinite(self_motion):
        raise RedkinError(f"self_motion must be finite, got {self_motion!r}")
    if modify_rotation and vel.shape[-1] != 6:
        raise RedkinError(f"modify_rotation needs a 6-row (linear, angular) jacobian, got {vel.shape[-1]} rows")
    return jac, vel, e


def _index(index: ArrayLike, jac: np.ndarray) -> np.ndarray:
    d_e = np.asarray(index, dtype=float)
    if not np.all(np.isfinite(d_e)):
        raise RedkinError("index must be finite, got NaN or infinity")
    try:
        return np.broadcast_to(d_e, jac.shape[:-2])
    except ValueError:
        raise RedkinError(f"index must have shape {jac.shape[:-2]} (one D_e per jacobian), "
                          f"got shape {d_e.shape}") from None


def _factors(factors: ArrayLike, jac: np.ndarray) -> np.ndarray:
    d_i = np.asarray(factors, dtype=float)
    if d_i.shape[-1:] != (jac.shape[-1],):
        raise RedkinError(f"factors must have shape (..., {jac.shape[-1]}), got shape {d_i.shape}")
    if not np.all(np.isfinite(d_i)):
        raise RedkinError("factors D_i must be finite, got NaN or infinity")
    try:
        return np.broadcast_to(d_i, jac.shape[:-2] + d_i.shape[-1:])
    except ValueError:
        raise RedkinError(f"factors must have shape {jac.shape[:-2] + d_i.shape[-1:]}, got shape {d_i.shape}") from None


def _sc_steps(jac: np.ndarray, vel: np.ndarray, d_e: np.ndarray, d_i: np.ndarray, eps: float, direction: float,
             self_motion: float, modify_rotation: bool, near_zero: float) -> VelocitySolution:
    """:func:`~redkin.velocity._step_kernels.sc_one` over trusted arrays with common leading axes.

    Raises
    ------
    ValueError
        Where the exact path meets ``D_s = sum_i D_i^2 = 0`` (the method is undefined there).
    """
    lead, (m, n) = jac.shape[:-2], jac.shape[-2:]
    count = int(np.prod(lead))
    qdot, target, ok = np.empty((count, n)), np.empty((count, m)), np.empty(count, dtype=np.bool_)
    run_batch(_step_kernels.sc, count,
              kernel_array(jac.reshape(count, m, n)), kernel_array(vel.reshape(count, m)),
              kernel_array(d_e.reshape(count)), kernel_array(d_i.reshape(count, n)),
              eps, float(direction), float(self_motion), bool(modify_rotation), float(near_zero), qdot, target, ok)
    if not ok.all():
        raise RedkinError("D_s = sum D_i^2 is zero: every factor D_i vanishes, the method is undefined here")
    return VelocitySolution(qdot.reshape(lead + (n,)), target.reshape(lead + (m,)))
