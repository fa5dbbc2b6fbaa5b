"""Rotations of the spherical shoulder and wrist of a Table 1 arm (eq. 3 of paper 000)."""

from __future__ import annotations

import numpy as np

HALF_PI = np.pi / 2.0


def dh_rotation(theta: np.ndarray, alpha: tuple[float, ...]) -> np.ndarray:
    """``prod_k Rz(theta_k) Rx(alpha_k)`` (eq. 3) for DH angles ``theta`` of shape ``(..., K)``."""
    theta = np.asarray(theta, dtype=float)
    result = np.broadcast_to(np.eye(3), theta.shape[:-1] + (3, 3)).copy()
    for k, twist in enumerate(alpha):
        c, s = np.cos(theta[..., k]), np.sin(theta[..., k])
        ca, sa = np.cos(twist), np.sin(twist)
        step = np.zeros(theta.shape[:-1] + (3, 3))
        step[..., 0, 0], step[..., 0, 1], step[..., 0, 2] = c, -s * ca, s * sa
        step[..., 1, 0], step[..., 1, 1], step[..., 1, 2] = s, c * ca, -c * sa
        step[..., 2, 1], step[..., 2, 2] = sa, ca
        result = result @ step
    return result


def shoulder_rotation(theta: np.ndarray) -> np.ndarray:
    """``0R3`` from DH angles ``(..., 7)`` (joints 1-3)."""
    return dh_rotation(np.asarray(theta)[..., 0:3], (-HALF_PI, HALF_PI, -HALF_PI))


def wrist_rotation(theta: np.ndarray) -> np.ndarray:
    """``4R7`` from DH angles ``(..., 7)`` (joints 5-7)."""
    return dh_rotation(np.asarray(theta)[..., 4:7], (-HALF_PI, HALF_PI, 0.0))
