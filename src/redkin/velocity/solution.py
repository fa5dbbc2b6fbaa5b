"""The result type of the singularity-consistent solvers."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class VelocitySolution(NamedTuple):
    """Joint velocity and the twist it realises.

    Attributes
    ----------
    joint_velocity : numpy.ndarray, shape (..., n)
    target_twist : numpy.ndarray, shape (..., m)
        ``J q_dot`` by construction (up to rounding): the commanded twist
        outside the singular region, the modified twist of [003 eq. 22]
        inside it.
    """

    joint_velocity: np.ndarray
    target_twist: np.ndarray
