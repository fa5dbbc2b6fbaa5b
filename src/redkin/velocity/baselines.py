"""Baseline velocity IK: pseudoinverse and damped least squares (constant and adaptive damping).

Every solver maps Jacobians ``J`` of shape ``(..., m, n)`` and twists ``v`` of
shape ``(..., m)`` (leading axes broadcast) to joint velocities ``(..., n)``.
They are the references paper 003 (section 1) argues against: the
pseudoinverse is exact but unbounded near a singularity; damped least squares
is bounded but does not realise the commanded twist (neither its size nor,
in general, its direction) and stalls at the workspace boundary.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_finite, check_jacobian_and_twist, check_nonnegative, check_positive
from redkin.errors import RedkinError
from redkin.velocity import _step_kernels

#: Relative cut-off below which a singular value counts as zero in :func:`pseudoinverse`.
PINV_RCOND = 1e-12
_MEASURES = {"sigma": _step_kernels.SIGMA, "manipulability": _step_kernels.MANIPULABILITY}


def pseudoinverse(jacobian: ArrayLike, twist: ArrayLike) -> np.ndarray:
    """Minimum-norm joint velocity ``J^+ v`` (paper 003 section 1).

    Bound: ``||q_dot|| <= ||v|| / sigma_min`` -- unbounded as the smallest
    singular value goes to zero.  Singular values below ``PINV_RCOND *
    sigma_max`` are treated as zero (the component of ``v`` along them is
    dropped), so an exactly singular ``J`` gives a finite answer.
    """
    jac, vel = check_jacobian_and_twist(jacobian, twist)
    return least_squares(jac, vel, 0.0, 1.0, _step_kernels.CONSTANT)[0]


def damped_least_squares(jacobian: ArrayLike, twist: ArrayLike, damping: float) -> np.ndarray:
    """``J^T (J J^T + lambda^2 I)^-1 v`` with constant damping ``lambda`` (Nakamura-Hanafusa, Wampler).

    Bound: ``||q_dot|| <= ||v|| / (2 lambda)`` everywhere, because each singular
    direction is scaled by ``sigma / (sigma^2 + lambda^2) <= 1 / (2 lambda)``.
    The price is a twist error ``lambda^2 / (sigma^2 + lambda^2)`` in every
    direction, also far from singularities.
    """
    lam = check_positive(damping, "damping")
    jac, vel = check_jacobian_and_twist(jacobian, twist)
    return least_squares(jac, vel, lam, 1.0, _step_kernels.CONSTANT)[0]


def adaptive_damping(
    jacobian: ArrayLike,
    threshold: float,
    max_damping: float,
    measure: str = "sigma",
) -> np.ndarray:
    """Damping ``lambda`` that grows from 0 as the arm nears a singularity.

    ``measure="sigma"`` (Maciejewski-Klein / Chiaverini): with ``s`` the
    smallest singular value, ``lambda^2 = max_damping^2 (1 - (s/threshold)^2)``
    for ``s < threshold``, else 0.  ``measure="manipulability"`` (Nakamura):
    the same with ``s`` replaced by Yoshikawa's ``w = prod(sigma)``.

    Returns
    -------
    numpy.ndarray, shape (...)
    """
    eps, lam_max, code = _adaptive(threshold, max_damping, measure)
    jac = as_float_array(jacobian, "jacobian")
    if jac.ndim < 2:
        raise RedkinError(f"jacobian must have shape (..., m, n), got shape {jac.shape}")
    check_finite(jac, "jacobian")
    return least_squares(jac, np.zeros(jac.shape[:-1]), lam_max, eps, code)[1]


def adaptive_damped_least_squares(
    jacobian: ArrayLike,
    twist: ArrayLike,
    threshold: float,
    max_damping: float,
    measure: str = "sigma",
) -> np.ndarray:
    """Damped least squares with the damping of :func:`adaptive_damping`.

    Exact (the pseudoinverse) while the measure is above ``threshold``.
    Bound: ``||q_dot|| <= ||v|| min(1 / sigma_min, 1 / (2 lambda))`` at each
    step; at an exact singularity (``lambda = max_damping``) this is
    ``||v|| / (2 max_damping)``.
    """
    eps, lam_max, code = _adaptive(threshold, max_damping, measure)
    jac, vel = check_jacobian_and_twist(jacobian, twist)
    return least_squares(jac, vel, lam_max, eps, code)[0]


def _adaptive(threshold: float, max_damping: float, measure: str) -> tuple[float, float, int]:
    eps = check_positive(threshold, "threshold")
    lam_max = check_nonnegative(max_damping, "max_damping")
    if measure not in _MEASURES:
        raise RedkinError(f"measure must be 'sigma' or 'manipulability', got {measure!r}")
    return eps, lam_max, _MEASURES[measure]


def least_squares(jac: np.ndarray, vel: np.ndarray, damping: float, threshold: float,
                  measure: int) -> tuple[np.ndarray, np.ndarray]:
    """Joint velocities ``(..., n)`` and dampings ``(...)`` of :func:`~redkin.velocity._step_kernels.least_squares_one`
    for trusted Jacobians ``(..., m, n)`` and twists ``(..., m)`` with the same leading axes."""
    lead, (m, n) = jac.shape[:-2], jac.shape[-2:]
    flat_j = kernel_array(jac.reshape(-1, m, n))
    flat_v = kernel_array(vel.reshape(-1, m))
    out = np.empty((flat_j.shape[0], n))
    lam = np.empty(flat_j.shape[0])
    run_batch(_step_kernels.least_squares, flat_j.shape[0], flat_j, flat_v, damping, threshold, measure, PINV_RCOND,
              out, lam)
    return out.reshape(lead + (n,)), lam.reshape(lead)
