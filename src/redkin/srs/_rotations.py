"""Rotations of the spherical shoulder and wrist of a Table 1 arm ([000 eq. 3]).

``0R3`` (joints 1-3) and ``4R7`` (joints 5-7) at given joint values are
read from the frames of the arm's Table 1 chain
(:meth:`redkin.chain.SerialChain.frames`, the compiled DH products of
[000 eq. 3]) rather than multiplied out again here.  (The IK kernels write
the single factor ``3R4 = Rz(theta_4) Rx(pi/2)`` in closed form,
:func:`redkin.srs._ik_kernels.elbow_frame`.)
"""

from __future__ import annotations

import numpy as np


def group_rotations(geometry, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``0R3`` and ``4R7`` of ``0R7 = 0R3 3R4 4R7`` [000 eq. 2] (each ``(..., 3, 3)``) of validated joint
    values ``q`` ``(..., 7)`` of ``geometry.chain``.

    Frame ``k`` of the chain is ``base A_1 ... A_k``, so ``0R3 = R_base^T
    R_3`` and ``4R7 = R_4^T R_7``.
    """
    frames = geometry.chain.frames(q)[..., :3, :3]
    shoulder = np.swapaxes(frames[..., 0, :, :], -1, -2) @ frames[..., 3, :, :]
    wrist = np.swapaxes(frames[..., 4, :, :], -1, -2) @ frames[..., 7, :, :]
    return shoulder, wrist
