"""The compiled core of :class:`~redkin.chain.SerialChain`: DH link transforms, frames, FK and Jacobian.

The one implementation of a chain's kinematics in redkin: :func:`frames`
(all frames, or the end pose alone) and :func:`jacobian`.  Each kernel takes
a batch of joint vectors ``q`` of shape ``(N, n)`` and writes into an output
array; :class:`~redkin.chain.SerialChain` validates at its public edge and
calls them through :func:`~redkin._compiled.run_batch`, which hands out a
batch in chunks (each kernel computes items ``start .. stop - 1``).  They
trust their inputs: C-contiguous float64 arrays of the documented shapes.

A chain is passed as

``links`` : (n, 6) float64
    One row per joint: ``offset, sign, a, d, cos(alpha), sin(alpha)``, so that
    ``theta_i = offset_i + sign_i * q_i`` (:data:`LINK_COLUMNS`).
``ends`` : (2, 4, 4) float64
    The base and the tool transform.
``standard`` : bool
    ``True`` for standard DH, ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``;
    ``False`` for modified DH (Craig), ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``.

A running frame is its three axes and its origin ``x, y, z, p`` (3-tuples of
world coordinates, kept in registers); each elementary motion of a DH row
right-multiplies it in closed form: ``Rz`` and ``Rx`` turn two axes
(:func:`turn`), ``Tz`` and ``Tx`` move the origin along one (:func:`move`).
"""

from __future__ import annotations

from math import cos, sin

import numpy as np

from redkin._compiled import kernel

#: Columns of a chain's link table.
LINK_COLUMNS = ("offset", "sign", "a", "d", "cos_alpha", "sin_alpha")
OFFSET, SIGN, A, D, COS_ALPHA, SIN_ALPHA = range(6)


# ------------------------------------------------------------- one DH row
@kernel
def angles(q, links, trig):
    """``cos theta_i, sin theta_i`` of ``theta_i = offset_i + sign_i q_i`` into ``trig`` (n, 2).

    Taken ahead of the frame products, which then make no calls (a call to
    ``cos`` or ``sin`` would spill the running frame from the registers).
    """
    for i in range(links.shape[0]):
        theta = links[i, OFFSET] + links[i, SIGN] * q[i]
        trig[i, 0], trig[i, 1] = cos(theta), sin(theta)


@kernel
def turn(u, v, c, s):
    """Turn the frame's axes ``u, v`` (3-tuples) by the angle with ``c, s = cos, sin``: ``c u + s v, c v - s u``.

    ``m Rz(theta)`` turns ``x, y``; ``m Rx(alpha)`` turns ``y, z``.
    """
    return ((c * u[0] + s * v[0], c * u[1] + s * v[1], c * u[2] + s * v[2]),
            (c * v[0] - s * u[0], c * v[1] - s * u[1], c * v[2] - s * u[2]))


@kernel
def move(p, length, u):
    """``p + length * u``: the origin moved along the frame's axis ``u`` (``m Tx(a)``, ``m Tz(d)``)."""
    return (p[0] + length * u[0], p[1] + length * u[1], p[2] + length * u[2])


@kernel
def standard_link(x, y, z, p, links, trig, i):
    """The frame ``(x, y, z, p)`` (axes and origin, 3-tuples in world coordinates) times
    ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``, whose rotation is [000 eq. 3]."""
    x, y = turn(x, y, trig[i, 0], trig[i, 1])
    p = move(move(p, links[i, D], z), links[i, A], x)
    y, z = turn(y, z, links[i, COS_ALPHA], links[i, SIN_ALPHA])
    return x, y, z, p


@kernel
def modified_link(x, y, z, p, links, trig, i):
    """The frame ``(x, y, z, p)`` times ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)`` [001 eq. 2.1]."""
    y, z = turn(y, z, links[i, COS_ALPHA], links[i, SIN_ALPHA])
    p = move(p, links[i, A], x)
    x, y = turn(x, y, trig[i, 0], trig[i, 1])
    p = move(p, links[i, D], z)
    return x, y, z, p


@kernel
def columns(t):
    """The axes and the origin ``x, y, z, p`` (3-tuples) of a pose ``t`` (4, 4)."""
    return ((t[0, 0], t[1, 0], t[2, 0]), (t[0, 1], t[1, 1], t[2, 1]),
            (t[0, 2], t[1, 2], t[2, 2]), (t[0, 3], t[1, 3], t[2, 3]))


@kernel
def combine(x, y, z, a, b, c):
    """``a x + b y + c z`` for 3-tuples ``x, y, z``."""
    return (a * x[0] + b * y[0] + c * z[0], a * x[1] + b * y[1] + c * z[1], a * x[2] + b * y[2] + c * z[2])


@kernel
def times(x, y, z, p, t):
    """The frame ``(x, y, z, p)`` times a fixed transform ``t`` (4, 4) whose last row is ``0 0 0 1``."""
    return (combine(x, y, z, t[0, 0], t[1, 0], t[2, 0]), combine(x, y, z, t[0, 1], t[1, 1], t[2, 1]),
            combine(x, y, z, t[0, 2], t[1, 2], t[2, 2]), move(combine(x, y, z, t[0, 3], t[1, 3], t[2, 3]), 1.0, p))


@kernel
def store(x, y, z, p, out):
    """Write the frame ``(x, y, z, p)`` into the pose ``out`` (4, 4)."""
    for r in range(3):
        out[r, 0], out[r, 1], out[r, 2], out[r, 3] = x[r], y[r], z[r], p[r]
    out[3, 0], out[3, 1], out[3, 2], out[3, 3] = 0.0, 0.0, 0.0, 1.0


# ---------------------------------------------------------- one configuration
# ``trig`` is an (n, 2) scratch array for :func:`angles`.
@kernel
def frames_one(q, links, ends, standard, trig, out):
    """The frames of one joint vector ``q`` (n,): all, or the end pose alone (forward kinematics:
    [000 eqs. 1-2] of a Table 1 arm, [001 eq. 2.2] of Table 2.1).

    ``out`` (n + 2, 4, 4) receives the base, frame ``k`` after joint ``k``
    (``base A_1 ... A_k``) and the tool frame ``base A_1 ... A_n tool``;
    ``out`` (1, 4, 4) receives the tool frame only.
    """
    n = links.shape[0]
    every = out.shape[0] > 1
    angles(q, links, trig)
    x, y, z, p = columns(ends[0])
    if every:
        store(x, y, z, p, out[0])
    for i in range(n):
        if standard:
            x, y, z, p = standard_link(x, y, z, p, links, trig, i)
        else:
            x, y, z, p = modified_link(x, y, z, p, links, trig, i)
        if every:
            store(x, y, z, p, out[i + 1])
    store(*times(x, y, z, p, ends[1]), out[out.shape[0] - 1])


@kernel
def jacobian_one(q, links, ends, standard, active, tool, offset, trig, out):
    """Geometric Jacobian ``[v; omega] = J q_dot`` [003 eq. 1] (6, n) of a point fixed in one frame, world coordinates.

    Joint ``i`` (of the first ``active``) turns with ``sign_i`` about the
    z axis of frame ``i - 1`` (standard DH) or ``i`` (modified DH), through
    that frame's origin ``o_i``: column ``i`` is ``sign_i [z_i x (point - o_i);
    z_i]``; columns from ``active`` on are zero.  The point's frame is frame
    ``active``, followed by the tool transform if ``tool``; the point is
    ``offset`` (3,) in that frame's coordinates.  ``trig`` (n, 2) is scratch.
    """
    angles(q, links, trig)
    jacobian_from_trig(links, ends, standard, active, tool, offset, trig, out)


@kernel
def jacobian_from_trig(links, ends, standard, active, tool, offset, trig, out):
    """:func:`jacobian_one` from the joints' ``cos theta_i, sin theta_i`` in ``trig`` (n, 2) (:func:`angles`), for a
    caller that has them already: :func:`frames_one` leaves those of its ``q`` in its ``trig``, so the pose and the
    Jacobian of one ``q`` take one set of sines and cosines."""
    n = links.shape[0]
    x, y, z, p = columns(ends[0])
    for i in range(active):
        if standard:  # the axis before the link
            axis, origin = z, p
            x, y, z, p = standard_link(x, y, z, p, links, trig, i)
        else:  # the axis after it
            x, y, z, p = modified_link(x, y, z, p, links, trig, i)
            axis, origin = z, p
        for r in range(3):  # z_i (angular rows) and, until the point is known, o_i (linear rows)
            out[3 + r, i] = links[i, SIGN] * axis[r]
            out[r, i] = origin[r]
    if tool:
        x, y, z, p = times(x, y, z, p, ends[1])
    point = move(combine(x, y, z, offset[0], offset[1], offset[2]), 1.0, p)
    for i in range(active):
        lx, ly, lz = point[0] - out[0, i], point[1] - out[1, i], point[2] - out[2, i]
        ux, uy, uz = out[3, i], out[4, i], out[5, i]
        out[0, i] = uy * lz - uz * ly
        out[1, i] = uz * lx - ux * lz
        out[2, i] = ux * ly - uy * lx
    for i in range(active, n):
        for r in range(6):
            out[r, i] = 0.0


# ------------------------------------------------------------------- batches
# Items start..stop - 1 of a batch, one scratch array per call (redkin._compiled.run_batch hands out the chunks).
@kernel
def frames(start, stop, q, links, ends, standard, out):
    """:func:`frames_one` for rows ``start .. stop - 1`` of ``q`` (N, n); ``out`` (N, n + 2, 4, 4), or (N, 1, 4, 4)
    for the end poses."""
    trig = np.empty((q.shape[1], 2))
    for b in range(start, stop):
        frames_one(q[b], links, ends, standard, trig, out[b])


@kernel
def jacobian(start, stop, q, links, ends, standard, active, tool, offsets, out):
    """:func:`jacobian_one` for rows ``start .. stop - 1`` of ``q`` (N, n); ``offsets`` (N, 3) or (1, 3) for all;
    ``out`` (N, 6, n)."""
    trig = np.empty((q.shape[1], 2))
    step = 1 if offsets.shape[0] > 1 else 0
    for b in range(start, stop):
        jacobian_one(q[b], links, ends, standard, active, tool, offsets[b * step], trig, out[b])


# ----------------------------------------------------------- joint ranges
# A joint's range is [lower, upper]; only a continuous joint (both infinite) is unlimited.  A range may be wider
# than 2 pi (a Sawyer's +-270 deg wrist): then an angle has several representatives q + 2 pi k inside it, and a
# value is chosen among them by a target (a seed, or the middle of the range).
@kernel
def range_middle(lower, upper):
    """The default target of :func:`representative`: the middle of ``[lower, upper]``; half a turn inside the finite
    end of a half-open range; 0 for an unlimited joint."""
    if lower > -np.inf and upper < np.inf:
        return 0.5 * (lower + upper)
    if lower > -np.inf:
        return lower + np.pi
    if upper < np.inf:
        return upper - np.pi
    return 0.0


@kernel
def representative(value, lower, upper, target):
    """The angle ``value + 2 pi k`` inside ``[lower, upper]`` nearest ``target``; NaN where no ``k`` puts it inside.

    ``k = 0`` where ``value`` itself is the answer, so a value already in place comes back bit for bit; a turned
    value that rounding puts an ulp past a limit is put on the limit.  An
    unlimited joint (both limits infinite) gets the representative nearest ``target``.
    """
    if lower <= value <= upper and upper - lower < 2.0 * np.pi:
        return value  # the one representative inside a range narrower than a turn (k = 0 below, without divisions)
    k = np.floor((target - value) / (2.0 * np.pi) + 0.5)
    low, high = -np.inf, np.inf
    if lower > -np.inf:
        low = np.ceil((lower - value) / (2.0 * np.pi))
    if upper < np.inf:
        high = np.floor((upper - value) / (2.0 * np.pi))
    if low > high:
        return np.nan
    k = min(max(k, low), high)
    moved = value + 2.0 * np.pi * k if k != 0.0 else value
    return min(max(moved, lower), upper)  # the turn's rounding may land an ulp past a limit


@kernel
def representatives(q, lower, upper, targets, seeded, out):
    """:func:`representative` for each entry of ``q`` (N, n) with ranges ``lower``, ``upper`` (n,) into ``out``.

    ``targets`` (N, n) are the seeds where ``seeded``; otherwise the middles of the ranges (:func:`range_middle`)
    are the targets.
    """
    for i in range(q.shape[0]):
        for j in range(q.shape[1]):
            target = targets[i, j] if seeded else range_middle(lower[j], upper[j])
            out[i, j] = representative(q[i, j], lower[j], upper[j], target)
