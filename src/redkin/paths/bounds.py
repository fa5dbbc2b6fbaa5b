"""The bound on joint motion between consecutive waypoints: a maximum step, or joint speeds and a time step.

The bound is ``max_step`` in radians per waypoint, or joint speeds in radians per second times the time ``dt``
between waypoints (``step = speed * dt``).  The speeds are ``speed`` where it is given, else the chain's own
velocity limits (:attr:`redkin.chain.SerialChain.velocity`: a model's maker's figures, a URDF's
``<limit velocity=...>``), so that ``dt`` alone bounds a path by what the robot can do.
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
        Joint speeds in rad/s, with ``dt``: the bound is ``speed * dt``.  Without it, ``dt`` takes the chain's
        velocity limits (:attr:`~redkin.chain.SerialChain.velocity`).
    dt : float, optional
        Seconds between waypoints.

    Raises
    ------
    RedkinError
        Unless exactly one of ``max_step`` and ``dt`` is given, finite and positive (``speed`` goes with ``dt``);
        and for ``dt`` without ``speed`` on a chain that lacks a velocity limit on some joint (the message names
        those joints).
    """
    if max_step is not None:
        if speed is not None or dt is not None:
            raise RedkinError("give the bound on joint motion as max_step, or as dt (with speed, or the chain's "
                              "velocity limits), one of them: max_step is already a step per waypoint")
        return _positive_per_joint(max_step, chain.n, "max_step")
    if dt is None:
        if speed is not None:
            raise RedkinError("speed needs dt, the time between waypoints in seconds")
        raise RedkinError("give the bound on joint motion as max_step, or as dt (with speed, or the chain's velocity "
                          "limits)")
    seconds = _positive_per_joint(dt, 1, "dt")[0]
    if speed is not None:
        return _positive_per_joint(speed, chain.n, "speed") * seconds
    missing = missing_speeds(chain)
    if missing:
        raise RedkinError(f"{chain.name} has no velocity limit on {missing}: give speed (rad/s) with dt, or max_step")
    return chain.velocity * seconds


def missing_speeds(chain: SerialChain) -> str:
    """The joints without a velocity limit, in words: ``""`` for none, ``"any joint"`` for all, else ``"joint 2"``
    or ``"joints 2, 5 (A5)"`` (1-based numbers, each with its name where the chain has one of its own)."""
    unknown = np.flatnonzero(~chain.velocity_known).tolist()
    if not unknown:
        return ""
    if len(unknown) == chain.n:
        return "any joint"
    return chain.joints_in_words(unknown)
