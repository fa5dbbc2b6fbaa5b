"""A deterministic, near-uniform set of orientations: super-Fibonacci spirals on SO(3).

Alexa, "Super-Fibonacci Spirals: Fast, Low-Discrepancy Sampling of SO(3)",
CVPR 2022 (Algorithm 1).  Sample ``i`` of ``n`` is the unit quaternion

    s = i + 1/2,  r = sqrt(s / n),  R = sqrt(1 - s / n),
    alpha = 2 pi s / sqrt(2),  beta = 2 pi s / psi_0,
    q = (r sin alpha, r cos alpha, R sin beta, R cos beta),

with ``psi_0`` the real root of ``psi^4 = psi + 4``.  The set depends on
``n`` alone (no seed), covers SO(3) with low discrepancy for every ``n``,
and a map stores it beside its values.
"""

from __future__ import annotations

import numpy as np

from redkin._constants import WORKSPACE_MAX_ORIENTATIONS as MAX_ORIENTATIONS  # most orientations of a map
from redkin._validation import check_count

#: The real root > 1 of psi^4 = psi + 4 (Alexa 2022, equation 11).
_SUPER_FIBONACCI_PSI = 1.533751168755204288118041


def _quaternion_to_matrix(quaternion: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` of unit quaternions ``(..., 4)`` ordered ``(w, x, y, z)``."""
    w, x, y, z = np.moveaxis(quaternion, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=-2,
    )


def super_fibonacci_rotations(count: int) -> np.ndarray:
    """``count`` rotations spread near-uniformly over SO(3), shape ``(count, 3, 3)``.

    Parameters
    ----------
    count : int
        Number of orientations, ``1..MAX_ORIENTATIONS``.

    Returns
    -------
    numpy.ndarray
        Proper rotation matrices; the same ``count`` always gives the same set.

    Raises
    ------
    ValueError
        For a count that is not an integer in the allowed range.
    """
    n = check_count(count, "count", 1, MAX_ORIENTATIONS)
    s = np.arange(n) + 0.5
    r, big_r = np.sqrt(s / n), np.sqrt(1.0 - s / n)
    alpha, beta = 2.0 * np.pi * s / np.sqrt(2.0), 2.0 * np.pi * s / _SUPER_FIBONACCI_PSI
    quaternion = np.stack([r * np.sin(alpha), r * np.cos(alpha), big_r * np.sin(beta), big_r * np.cos(beta)], axis=-1)
    return _quaternion_to_matrix(quaternion)
