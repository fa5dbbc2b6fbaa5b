"""What the compiled kernels of :mod:`redkin.torso_arm` share: 3-vector tuples, and batching for their wrappers.

The kernels hold points and directions in registers as 3-tuples ``(x, y, z)``
(as :mod:`redkin._chain_kernels` holds a running frame); :func:`add` ...
:func:`turn_y` are the few operations they need, written out by components.
The public functions of the package validate their inputs, broadcast and
flatten them with :func:`flat` (the kernels take C-contiguous float64
batches ``(N, ...)``), and launch a batch kernel with
:func:`redkin._compiled.run_batch`.  A batch kernel's first two arguments
``start, stop`` are the chunk of the batch it computes: "each item" in its
docstring means items ``start .. stop - 1``.
"""

from __future__ import annotations

from math import cos, sin, sqrt

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel, kernel_array


def flat(*pairs: tuple[ArrayLike, int]) -> tuple[tuple[int, ...], list[np.ndarray]]:
    """Broadcast arrays over their leading axes and flatten them to ``(N, *trailing)``.

    Parameters
    ----------
    *pairs : (array_like, int)
        Each array with the number of its trailing (per-item) axes.

    Returns
    -------
    shape : tuple of int
        The broadcast leading shape (``N`` is its product).
    arrays : list of numpy.ndarray
        C-contiguous writeable float64 views or copies, shape ``(N, *trailing)``
        (:func:`redkin._compiled.kernel_array`: one compiled type per kernel).
    """
    arrays = [np.asarray(a, dtype=float) for a, _ in pairs]
    shape = np.broadcast_shapes(*(a.shape[:a.ndim - k] for a, (_, k) in zip(arrays, pairs)))
    count = int(np.prod(shape, dtype=np.int64))
    out = []
    for a, (_, k) in zip(arrays, pairs):
        trailing = a.shape[a.ndim - k:]
        out.append(kernel_array(a, shape + trailing).reshape((count,) + trailing))
    return shape, out


@kernel
def add(a, b):
    """``a + b``."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@kernel
def sub(a, b):
    """``a - b``."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@kernel
def scale(a, s):
    """``s a``."""
    return (s * a[0], s * a[1], s * a[2])


@kernel
def dot(a, b):
    """``a . b``."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@kernel
def cross(a, b):
    """``a x b``."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@kernel
def norm(a):
    """``|a|``."""
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@kernel
def turn_y(theta, a):
    """``Ry(theta) a``: ``a`` turned about the torso axis ``y``."""
    c, s = cos(theta), sin(theta)
    return (c * a[0] + s * a[2], a[1], -s * a[0] + c * a[2])


@kernel
def row(array, i):
    """Row ``i`` of an ``(N, 3)`` array as a 3-tuple."""
    return (array[i, 0], array[i, 1], array[i, 2])


@kernel
def put(array, i, a):
    """Write the 3-tuple ``a`` into row ``i`` of an ``(N, 3)`` array."""
    array[i, 0], array[i, 1], array[i, 2] = a[0], a[1], a[2]


@kernel
def shoulder_point(L0, theta1):
    """The right shoulder ``S(theta_1) = L0 (cos theta_1, 0, -sin theta_1)`` (frame 2; :meth:`TorsoArm.shoulder`)."""
    return (L0 * cos(theta1), 0.0, -L0 * sin(theta1))


@kernel
def shoulder_points(L0, theta1, out):
    """:func:`shoulder_point` over a flat batch ``theta1`` (N,), written into ``out`` (N, 3)."""
    for i in range(theta1.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = shoulder_point(L0, theta1[i])
