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

from redkin.validation import check_positive
from redkin.velocity._inputs import jacobian_and_twist, nonnegative

#: Relative cut-off below which a singular value counts as zero in :func:`pseudoinverse`.
PINV_RCOND = 1e-12


def pseudoinverse(jacobian: ArrayLike, twist: ArrayLike) -> np.ndarray:
    """Minimum-norm joint velocity ``J^+ v`` (paper 003 section 1).

    Bound: ``||q_dot|| <= ||v|| / sigma_min`` -- unbounded as the smallest
    singular value goes to zero.  Singular values below ``PINV_RCOND *
    sigma_max`` are treated as zero (the component of ``v`` along them is
    dropped), so an exactly singular ``J`` gives a finite answer.
    """
    jac, vel = jacobian_and_twist(jacobian, twist)
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    return _filtered(u, vt, vel, np.where(s > PINV_RCOND * s[..., :1], 1.0 / np.where(s > 0, s, 1.0), 0.0))


def damped_least_squares(jacobian: ArrayLike, twist: ArrayLike, damping: float) -> np.ndarray:
    """``J^T (J J^T + lambda^2 I)^-1 v`` with constant damping ``lambda`` (Nakamura-Hanafusa, Wampler).

    Bound: ``||q_dot|| <= ||v|| / (2 lambda)`` everywhere, because each singular
    direction is scaled by ``sigma / (sigma^2 + lambda^2) <= 1 / (2 lambda)``.
    The price is a twist error ``lambda^2 / (sigma^2 + lambda^2)`` in every
    direction, also far from singularities.
    """
    lam = check_positive(damping, "damping")
    jac, vel = jacobian_and_twist(jacobian, twist)
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    return _filtered(u, vt, vel, s / (s * s + lam * lam))


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
    eps = check_positive(threshold, "threshold")
    lam_max = nonnegative(max_damping, "max_damping")
    if measure not in ("sigma", "manipulability"):
        raise ValueError(f"measure must be 'sigma' or 'manipulability', got {measure!r}")
    jac = np.asarray(jacobian, dtype=float)
    s = np.linalg.svd(jac, compute_uv=False)
    value = s[..., -1] if measure == "sigma" else np.prod(s, axis=-1)
    ratio = np.minimum(value / eps, 1.0)
    return lam_max * np.sqrt(1.0 - ratio * ratio)


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
    jac, vel = jacobian_and_twist(jacobian, twist)
    lam = adaptive_damping(jac, threshold, max_damping, measure)
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    lam2 = (lam * lam)[..., None]
    gain = np.where(lam2 > 0, s / (s * s + lam2), np.where(s > PINV_RCOND * s[..., :1], 1.0 / np.where(s > 0, s, 1.0), 0.0))
    return _filtered(u, vt, vel, gain)


def _filtered(u: np.ndarray, vt: np.ndarray, vel: np.ndarray, gain: np.ndarray) -> np.ndarray:
    """``V diag(gain) U^T v`` for a batch of SVDs."""
    coeff = gain * np.einsum("...ji,...j->...i", u, vel)
    return np.einsum("...ij,...i->...j", vt, coeff)
