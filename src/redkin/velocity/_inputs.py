"""Input checks shared by the velocity solvers (public-edge validation)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.validation import as_float_array, check_finite


def jacobian_and_twist(jacobian: ArrayLike, twist: ArrayLike, one_redundant: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Validate Jacobians ``(..., m, n)`` and twists ``(..., m)``; broadcast their leading axes.

    Parameters
    ----------
    one_redundant : bool
        Require ``n = m + 1`` (the cofactor methods of paper 003 assume one
        degree of redundancy, e.g. a 6 x 7 Jacobian).
    """
    jac = as_float_array(jacobian, "jacobian")
    if jac.ndim < 2:
        raise ValueError(f"jacobian must have shape (..., m, n), got shape {jac.shape}")
    check_finite(jac, "jacobian")
    m, n = jac.shape[-2:]
    if one_redundant and n != m + 1:
        raise ValueError(f"jacobian must have one more column than rows (e.g. 6 x 7), got {m} x {n}")
    vel = as_float_array(twist, "twist")
    if vel.ndim == 0 or vel.shape[-1] != m:
        raise ValueError(f"twist must have shape (..., {m}) to match the jacobian, got shape {vel.shape}")
    check_finite(vel, "twist")
    try:
        lead = np.broadcast_shapes(jac.shape[:-2], vel.shape[:-1])
    except ValueError as exc:
        raise ValueError(
            f"leading axes of jacobian {jac.shape[:-2]} and twist {vel.shape[:-1]} do not broadcast"
        ) from exc
    return np.broadcast_to(jac, lead + (m, n)), np.broadcast_to(vel, lead + (m,))


def nonnegative(value: float, name: str) -> float:
    """``value`` as a float, ``ValueError`` unless finite and >= 0."""
    number = float(value)
    if not np.isfinite(number) or number < 0.0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return number
