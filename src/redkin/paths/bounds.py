"""The bound on joint motion between consecutive waypoints: a maximum step, or joint speeds and a time step.

Chains do not carry velocity limits yet (the URDF importer does not read ``<limit velocity=...>``), so the bound
is always given: ``max_step`` in radians per waypoint, or ``speed`` in radians per second with the time ``dt``
between waypoints (``step = speed * dt``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import as_float_array
from redkin.chain import SerialChain
from redkin.errors import RedkinError


def _positive_per_joint(value: ArrayLike, n: int, name: str) -> np.ndarray:
    """``value`` as ``n`` finite positive numbers (a scalar is the same for every joint)."""
    array = as_float_array(value, name)
    if array.ndim > 1 or array.size not in (1, n):
        raise RedkinError(f"{name} must be one number or {n} numbers (one per joint), got shape {array.shape}")
    if not np.all(np.isfinite(array)) or np.any(array <= 0.0):
        raise RedkinError(f"{name} must be finite and > 0, got {array.tolist()}")
    return np.broadcast_to(array.reshape(-1), (n,)).astype(float)


def step_bound(
    chain: SerialChain,
    max_step: ArrayLike | None = None,
    speed: ArrayLike | None = None,
    dt: float | None = None,
) -> np.ndarray:
    """The largest move of each joint between consecutive waypoints, ``(n,)`` radians.

    Parameters
    ----------
    chain : SerialChain
    max_step : float or array_like of shape (n,), optional
        The bound itself.
    speed : float or array_like of shape (n,), optional
        Joint speeds in rad/s, with ``dt``: the bound is ``speed * dt``.
    dt : float, optional
        Seconds between waypoints.

    Raises
    ------
    RedkinError
        Unless exactly one of ``max_step`` and ``speed`` (with ``dt``) is given, finite and positive.
    """
    if (max_step is None) == (speed is None):
        raise RedkinError("give the bound on joint motion as max_step, or as speed with dt (one of them)")
    if max_step is not None:
        if dt is not None:
            raise RedkinError("dt goes with speed; max_step is already a step per waypoint")
        return _positive_per_joint(max_step, chain.n, "max_step")
    if dt is None:
        raise RedkinError("speed needs dt, the time between waypoints in seconds")
    seconds = _positive_per_joint(dt, 1, "dt")[0]
    assert speed is not None  # one of the two, and not max_step
    return _positive_per_joint(speed, chain.n, "speed") * seconds
