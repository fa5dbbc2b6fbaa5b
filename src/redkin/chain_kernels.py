"""The compiled core of :class:`~redkin.chain.SerialChain`: DH link transforms, frames, FK and Jacobian.

The one implementation of a chain's kinematics in redkin.  Each kernel takes
a batch of joint vectors ``q`` of shape ``(N, n)`` and writes into an output
array; :class:`~redkin.chain.SerialChain` validates at its public edge and
calls them (:func:`~redkin.compiled.run_batch` picks the serial or the
parallel loop).  They trust their inputs: C-contiguous float64 arrays of the
documented shapes.

A chain is passed as

``links`` : (n, 6) float64
    One row per joint: ``offset, sign, a, d, cos(alpha), sin(alpha)``, so that
    ``theta_i = offset_i + sign_i * q_i`` (:data:`LINK_COLUMNS`).
``ends`` : (2, 4, 4) float64
    The base and the tool transform.
``standard`` : bool
    ``True`` for standard DH, ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``;
    ``False`` for modified DH (Craig), ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``.

A running frame is the top three rows of a pose, columns ``x, y, z, p``; each
elementary motion of a DH row right-multiplies it in closed form.
"""

from __future__ import annotations

from math import cos, sin

import numpy as np
from numba import prange

from redkin.compiled import kernel

#: Columns of a chain's link table.
LINK_COLUMNS = ("offset", "sign", "a", "d", "cos_alpha", "sin_alpha")
OFFSET, SIGN, A, D, COS_ALPHA, SIN_ALPHA = range(6)


# ------------------------------------------------------------- one DH row
@kernel
def turn_z(m, c, s):
    """``m <- m Rz(theta)`` with ``c, s = cos, sin theta``: ``x, y <- c x + s y, c y - s x``."""
    for r in range(3):
        x, y = m[r, 0], m[r, 1]
        m[r, 0] = c * x + s * y
        m[r, 1] = c * y - s * x


@kernel
def turn_x(m, c, s):
    """``m <- m Rx(alpha)`` with ``c, s = cos, sin alpha``: ``y, z <- c y + s z, c z - s y``."""
    for r in range(3):
        y, z = m[r, 1], m[r, 2]
        m[r, 1] = c * y + s * z
        m[r, 2] = c * z - s * y


@kernel
def shift(m, column, length):
    """``m <- m T``, ``T`` a translation by ``length`` along the frame's own axis ``column`` (0 = x, 2 = z)."""
    for r in range(3):
        m[r, 3] += length * m[r, column]


@kernel
def link(m, links, i, q, standard):
    """``m <- m A_i(q)``: the DH transform of row ``i`` at joint value ``q``."""
    theta = links[i, OFFSET] + links[i, SIGN] * q
    c, s = cos(theta), sin(theta)
    if standard:  # Rz(theta) Tz(d) Tx(a) Rx(alpha)
        turn_z(m, c, s)
        shift(m, 2, links[i, D])
        shift(m, 0, links[i, A])
        turn_x(m, links[i, COS_ALPHA], links[i, SIN_ALPHA])
    else:  # Rx(alpha) Tx(a) Rz(theta) Tz(d)
        turn_x(m, links[i, COS_ALPHA], links[i, SIN_ALPHA])
        shift(m, 0, links[i, A])
        turn_z(m, c, s)
        shift(m, 2, links[i, D])


@kernel
def times(m, t):
    """``m <- m t`` for a fixed transform ``t`` (4, 4) whose last row is ``0 0 0 1``."""
    for r in range(3):
        x, y, z, p = m[r, 0], m[r, 1], m[r, 2], m[r, 3]
        for k in range(4):
            m[r, k] = x * t[0, k] + y * t[1, k] + z * t[2, k]
        m[r, 3] += p


@kernel
def copy_pose(m, pose):
    """``m <- pose`` (all four rows)."""
    for r in range(4):
        for k in range(4):
            m[r, k] = pose[r, k]


# ---------------------------------------------------------- one configuration
@kernel
def fk_one(q, links, ends, standard, out):
    """``out <- base A_1 ... A_n tool`` for one joint vector ``q`` (n,); ``out`` (4, 4)."""
    copy_pose(out, ends[0])
    for i in range(links.shape[0]):
        link(out, links, i, q[i], standard)
    times(out, ends[1])


@kernel
def frames_one(q, links, ends, standard, out):
    """``out[0]`` base, ``out[k]`` frame ``k`` after joint ``k``, ``out[n + 1]`` tool frame; ``out`` (n + 2, 4, 4)."""
    n = links.shape[0]
    copy_pose(out[0], ends[0])
    for i in range(n):
        copy_pose(out[i + 1], out[i])
        link(out[i + 1], links, i, q[i], standard)
    copy_pose(out[n + 1], out[n])
    times(out[n + 1], ends[1])


@kernel
def jacobian_one(q, links, ends, standard, active, tool, offset, frame, out):
    """Geometric Jacobian ``[v; omega] = J q_dot`` (6, n) of a point fixed in one frame, world coordinates.

    Joint ``i`` (of the first ``active``) turns with ``sign_i`` about the
    z axis of frame ``i - 1`` (standard DH) or ``i`` (modified DH), through
    that frame's origin ``o_i``: column ``i`` is ``sign_i [z_i x (point - o_i);
    z_i]``; columns from ``active`` on are zero.  The frame is frame
    ``active``, followed by the tool transform if ``tool``; the point is
    ``offset`` (3,) in that frame's coordinates.  ``frame`` is a (4, 4)
    scratch array for the running frame.
    """
    n = links.shape[0]
    copy_pose(frame, ends[0])
    for i in range(active):
        if not standard:
            link(frame, links, i, q[i], standard)
        for r in range(3):  # the axis z_i (angular rows) and, until the point is known, o_i (linear rows)
            out[3 + r, i] = links[i, SIGN] * frame[r, 2]
            out[r, i] = frame[r, 3]
        if standard:
            link(frame, links, i, q[i], standard)
    if tool:
        times(frame, ends[1])
    px = frame[0, 3] + frame[0, 0] * offset[0] + frame[0, 1] * offset[1] + frame[0, 2] * offset[2]
    py = frame[1, 3] + frame[1, 0] * offset[0] + frame[1, 1] * offset[1] + frame[1, 2] * offset[2]
    pz = frame[2, 3] + frame[2, 0] * offset[0] + frame[2, 1] * offset[1] + frame[2, 2] * offset[2]
    for i in range(active):
        lx, ly, lz = px - out[0, i], py - out[1, i], pz - out[2, i]
        zx, zy, zz = out[3, i], out[4, i], out[5, i]
        out[0, i] = zy * lz - zz * ly
        out[1, i] = zz * lx - zx * lz
        out[2, i] = zx * ly - zy * lx
    for i in range(active, n):
        for r in range(6):
            out[r, i] = 0.0


# ------------------------------------------------------------------- batches
# Each kernel comes as a serial loop and a parallel one (numba caches one
# dispatcher per Python function, so the two loops are two functions).
@kernel
def fk(q, links, ends, standard, out):
    """:func:`fk_one` for each row of ``q`` (N, n); ``out`` (N, 4, 4)."""
    for b in range(q.shape[0]):
        fk_one(q[b], links, ends, standard, out[b])


@kernel(parallel=True)
def fk_parallel(q, links, ends, standard, out):
    """:func:`fk` on all cores."""
    for b in prange(q.shape[0]):
        fk_one(q[b], links, ends, standard, out[b])


@kernel
def frames(q, links, ends, standard, out):
    """:func:`frames_one` for each row of ``q`` (N, n); ``out`` (N, n + 2, 4, 4)."""
    for b in range(q.shape[0]):
        frames_one(q[b], links, ends, standard, out[b])


@kernel(parallel=True)
def frames_parallel(q, links, ends, standard, out):
    """:func:`frames` on all cores."""
    for b in prange(q.shape[0]):
        frames_one(q[b], links, ends, standard, out[b])


@kernel
def jacobian(q, links, ends, standard, active, tool, offsets, out):
    """:func:`jacobian_one` for each row of ``q`` (N, n); ``offsets`` (N, 3) or (1, 3) for all; ``out`` (N, 6, n)."""
    frame = np.empty((4, 4))
    step = 1 if offsets.shape[0] > 1 else 0
    for b in range(q.shape[0]):
        jacobian_one(q[b], links, ends, standard, active, tool, offsets[b * step], frame, out[b])


@kernel(parallel=True)
def jacobian_parallel(q, links, ends, standard, active, tool, offsets, out):
    """:func:`jacobian` on all cores."""
    step = 1 if offsets.shape[0] > 1 else 0
    for b in prange(q.shape[0]):
        frame = np.empty((4, 4))
        jacobian_one(q[b], links, ends, standard, active, tool, offsets[b * step], frame, out[b])
