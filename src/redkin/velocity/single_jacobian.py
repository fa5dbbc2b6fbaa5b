"""Geometric Jacobian of one configuration in scalar arithmetic (the control-loop case).

``SerialChain.jacobian`` is built for batches: for a single ``q`` most of its
time is numpy call overhead on 3-vectors.  :class:`SingleJacobian` propagates
the frame columns ``x, y, z, p`` of one configuration on plain Python floats
(about 40 multiply-adds per joint) and builds the ``6 x n`` array once at the
end.  It is the same kinematics as ``SerialChain._propagate`` (standard DH
``Rz(theta) Tz(d) Tx(a) Rx(alpha)``; modified DH ``Rx(alpha) Tx(a) Rz(theta)
Tz(d)``); ``tests/test_velocity_fast_step.py`` checks it against
``chain.jacobian`` on random configurations, bases and tools, both conventions.
"""

from __future__ import annotations

import math
from math import cos, sin
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain

_EXACT = 1e-15


def _quarter_turn_exact(alpha: float) -> tuple[float, float]:
    """``cos, sin`` of a DH twist, snapped to exact 0 / +-1 for quarter turns (as ``SerialChain`` does)."""
    c, s = math.cos(alpha), math.sin(alpha)
    if abs(s) < _EXACT:
        return math.copysign(1.0, c), 0.0
    if abs(c) < _EXACT:
        return 0.0, math.copysign(1.0, s)
    return c, s


class SingleJacobian:
    """Geometric Jacobian (world frame, linear rows first) of one configuration of a chain.

    Same result as ``chain.jacobian(q)`` for a single ``q`` of shape ``(n,)``
    (to rounding, ~1e-16), about five times faster.  The chain is bound once.

    Examples
    --------
    >>> from redkin.models import barrett_wam
    >>> jacobian = SingleJacobian(barrett_wam())
    >>> jacobian([0.1, 0.2, 0.3, 1.0, 0.5, 0.6, 0.7]).shape
    (6, 7)
    """

    def __init__(self, chain: SerialChain) -> None:
        self.n = chain.n
        self._standard = chain.convention == "dh"
        self._rows = tuple(
            (float(off), float(sg), float(a), float(d), *_quarter_turn_exact(float(al)))
            for off, sg, a, d, al in zip(chain.offset, chain.sign, chain.a, chain.d, chain.alpha)
        )
        base = chain.base
        self._base = tuple(float(v) for k in range(4) for v in base[:3, k])
        self._tool = tuple(float(v) for v in chain.tool[:3, 3])

    def __call__(self, q: ArrayLike) -> np.ndarray:
        """Jacobian ``(6, n)`` at ``q`` (shape ``(n,)``, finite; ``ValueError`` otherwise)."""
        values = np.asarray(q, dtype=float)
        if values.shape != (self.n,) or not np.all(np.isfinite(values)):
            raise ValueError(f"q must be a finite vector of shape ({self.n},), got shape {values.shape}")
        return self.unchecked(values.tolist())

    def unchecked(self, values: Sequence[float]) -> np.ndarray:
        """Jacobian ``(6, n)`` for ``n`` trusted finite floats (no input check; the controller's inner call)."""
        joints, (xx, xy, xz, yx, yy, yz, zx, zy, zz, px, py, pz) = (
            self._standard_frames(values) if self._standard else self._modified_frames(values)
        )
        tx, ty, tz = self._tool
        ex = px + tx * xx + ty * yx + tz * zx
        ey = py + tx * xy + ty * yy + tz * zy
        ez = pz + tx * xz + ty * yz + tz * zz
        flat: list[float] = []
        for sg, ux, uy, uz, ax, ay, az in joints:
            lx, ly, lz = ex - ax, ey - ay, ez - az
            ux, uy, uz = sg * ux, sg * uy, sg * uz
            flat += (uy * lz - uz * ly, uz * lx - ux * lz, ux * ly - uy * lx, ux, uy, uz)
        return np.array(flat).reshape(self.n, 6).T

    def _standard_frames(self, values: Sequence[float]):
        """Joint axes (sign, direction, point) and the last frame; rows ``Rz(theta) Tz(d) Tx(a) Rx(alpha)``."""
        xx, xy, xz, yx, yy, yz, zx, zy, zz, px, py, pz = self._base
        joints = []
        for angle, (off, sg, a, d, ca, sa) in zip(values, self._rows):
            joints.append((sg, zx, zy, zz, px, py, pz))  # joint i turns about z_{i-1}
            theta = off + sg * angle
            c, s = cos(theta), sin(theta)
            xx, xy, xz, yx, yy, yz = (c * xx + s * yx, c * xy + s * yy, c * xz + s * yz,
                                      c * yx - s * xx, c * yy - s * xy, c * yz - s * xz)
            px, py, pz = px + d * zx + a * xx, py + d * zy + a * xy, pz + d * zz + a * xz
            yx, yy, yz, zx, zy, zz = (ca * yx + sa * zx, ca * yy + sa * zy, ca * yz + sa * zz,
                                      ca * zx - sa * yx, ca * zy - sa * yy, ca * zz - sa * yz)
        return joints, (xx, xy, xz, yx, yy, yz, zx, zy, zz, px, py, pz)

    def _modified_frames(self, values: Sequence[float]):
        """Joint axes (sign, direction, point) and the last frame; rows ``Rx(alpha) Tx(a) Rz(theta) Tz(d)``."""
        xx, xy, xz, yx, yy, yz, zx, zy, zz, px, py, pz = self._base
        joints = []
        for angle, (off, sg, a, d, ca, sa) in zip(values, self._rows):
            yx, yy, yz, zx, zy, zz = (ca * yx + sa * zx, ca * yy + sa * zy, ca * yz + sa * zz,
                                      ca * zx - sa * yx, ca * zy - sa * yy, ca * zz - sa * yz)
            px, py, pz = px + a * xx, py + a * xy, pz + a * xz
            joints.append((sg, zx, zy, zz, px, py, pz))  # joint i turns about z_i
            theta = off + sg * angle
            c, s = cos(theta), sin(theta)
            xx, xy, xz, yx, yy, yz = (c * xx + s * yx, c * xy + s * yy, c * xz + s * yz,
                                      c * yx - s * xx, c * yy - s * xy, c * yz - s * xz)
            px, py, pz = px + d * zx, py + d * zy, pz + d * zz
        return joints, (xx, xy, xz, yx, yy, yz, zx, zy, zz, px, py, pz)
