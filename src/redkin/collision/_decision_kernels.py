"""Compiled decision of one interval of the certified subdivision (:func:`redkin.collision.arm_angle_free.certify`,
whose module docstring states the argument): from the checked pairs' clearances at the interval's middle and the
bounds of how fast each changes over it, whether the interval is free, blocked, narrow enough to leave undecided, or
still open, and, where it is open, the stretch around its middle that its own clearances decide.
"""

from __future__ import annotations

from math import inf

import numpy as np

from redkin import _array_copy
from redkin._compiled import kernel

#: The kinds of a decided interval, and of one still open.
FREE, BLOCKED, UNDECIDED, OPEN = 0, 1, 2, 3
#: The radius of a carved stretch is this much less than its clearance over its speed bound (rounding of the
#: division).
CARVE_SHRINK = 1.0 - 1e-9


@kernel
def linear_extent(clearance, speed):
    """``clearance / speed`` as numpy divides (``+-inf`` where the speed is 0), with what numpy makes NaN (``0 / 0``,
    ``inf / inf``, a NaN) read as 0, without dividing there: run as Python, numpy would warn of it."""
    if speed == 0.0:
        return inf if clearance > 0.0 else (-inf if clearance < 0.0 else 0.0)
    if clearance != clearance or speed != speed or (abs(clearance) == inf and abs(speed) == inf):
        return 0.0
    return clearance / speed


@kernel
def decided_one(half, clearance, speed, below, above, active, finest, carve):
    """One interval of half width ``half``: ``clearance[k]`` (distance minus margin) of each checked pair ``k`` at its
    middle and ``speed[k]``, a bound of how fast it changes over the interval, for the pairs ``active[k]`` not yet
    proved clear on a wider interval; ``below[k]`` and ``above[k]``, how far from the middle, towards the interval's
    lower and upper end, the clearance is proved to keep its sign (each at least ``clearance / speed``:
    :func:`linear_extent`; negative where it is negative).  A pair whose clearance stays positive over the interval,
    ``c - v h > 0``, is proved clear: ``active[k]`` is set false.  Returns ``(kind, pair, down, up, carved,
    cause)``:

    * ``kind``: :data:`FREE` (no pair left open), :data:`BLOCKED` (a pair's ``c + v h < 0``: it collides on the whole
      interval), :data:`UNDECIDED` (neither, and no wider than ``finest``) or :data:`OPEN`;
    * ``pair``: the pair of the least ``c + v h`` (the first of equals; a NaN first), the cause where blocked;
    * with ``carve`` (the speeds bound each clearance's derivative: ``|c(psi) - c(m)| <= v |psi - m|``) and an open
      interval, the stretch ``[m - down, m + up]`` that the clearances at its middle decide (both 0 where none):
      free (``carved`` :data:`FREE`) out to the open pairs' least extent on each side where all are positive, else
      blocked (``carved`` :data:`BLOCKED`) by the negative pair ``cause`` whose two extents reach farthest in all;
      each shrunk by :data:`CARVE_SHRINK` and at most ``half`` (then the stretch reaches the interval's end).
      Without ``carve``, or on a decided interval, both 0.
    """
    pair, least = 0, inf
    still_open, blocked = False, False
    for k in range(clearance.shape[0]):
        high = inf
        if active[k]:
            low = clearance[k] - speed[k] * half
            high = clearance[k] + speed[k] * half
            if low > 0.0:
                active[k] = False
            else:
                still_open = True
            if high < 0.0:
                blocked = True
        if least == least and (high != high or high < least):  # numpy's argmin: the first NaN, else the first least
            pair, least = k, high
    if not still_open:
        return FREE, pair, 0.0, 0.0, FREE, 0
    if blocked:
        return BLOCKED, pair, 0.0, 0.0, FREE, 0
    if 2.0 * half <= finest:
        return UNDECIDED, pair, 0.0, 0.0, FREE, 0
    if not carve:
        return OPEN, pair, 0.0, 0.0, FREE, 0
    lowest, highest, nearest, farthest, cause, reaching = inf, inf, inf, 0.0, 0, 0
    for k in range(clearance.shape[0]):
        if active[k]:
            down = below[k] if below[k] == below[k] else 0.0  # a NaN proves nothing
            up = above[k] if above[k] == above[k] else 0.0
            lowest, highest = min(lowest, down), min(highest, up)
            if min(down, up) < nearest:
                nearest, cause = min(down, up), k
            if down <= 0.0 and up <= 0.0 and down + up < farthest:
                farthest, reaching = down + up, k
    if lowest > 0.0 or highest > 0.0:  # every open pair clear at the middle (an extent > 0 needs c > 0)
        return (OPEN, pair, min(max(lowest, 0.0) * CARVE_SHRINK, half), min(max(highest, 0.0) * CARVE_SHRINK, half),
                FREE, cause)
    if farthest < 0.0:
        down = below[reaching] if below[reaching] == below[reaching] else 0.0
        up = above[reaching] if above[reaching] == above[reaching] else 0.0
        return OPEN, pair, min(-down * CARVE_SHRINK, half), min(-up * CARVE_SHRINK, half), BLOCKED, reaching
    return OPEN, pair, 0.0, 0.0, BLOCKED, cause


@kernel
def decided(start, stop, half, clearance, speed, active, finest, carve, kind, pair, down, up, carved, cause):
    """:func:`decided_one` of intervals ``start .. stop - 1`` (``half`` (N,), ``clearance``, ``speed`` and
    ``active`` (N, K)), into ``kind``, ``pair``, ``down``, ``up``, ``carved`` and ``cause`` (N,); each clearance's
    extent is ``clearance / speed`` on both sides (:func:`linear_extent`)."""
    extent = np.empty(clearance.shape[1])
    for n in range(start, stop):
        for k in range(clearance.shape[1]):
            extent[k] = linear_extent(clearance[n, k], speed[n, k])
        kind[n], pair[n], down[n], up[n], carved[n], cause[n] = decided_one(half[n], clearance[n], speed[n], extent,
                                                                            extent, active[n], finest, carve)


@kernel
def next_level(lo, hi, owner, active, kind, pair, down, up, carved, cause, bounds, labels, open_bounds, open_owner,
               open_active):
    """Split one level of intervals ``[lo, hi]`` of owners ``owner`` (N,), each decided as :func:`decided_one` gives
    (``kind``, ``pair``, ``down``, ``up``, ``carved``, ``cause``, (N,); ``active`` (N, K), the pairs still open on
    each), into what is decided and what stays open (:func:`redkin.collision.arm_angle_free.certify`'s subdivision).

    Decided, into the columns of ``bounds`` (2, 2N) ``(lo, hi)`` and ``labels`` (3, 2N) ``(owner, kind, pair)``:
    each interval not :data:`OPEN`, and of an open one the stretch ``[m - down, m + up]`` around its middle ``m``
    that its own clearances decide, where it is not empty (of kind ``carved``, by pair ``cause``).  Open, into the
    columns of ``open_bounds`` (2, 2N), ``open_owner`` (2N,) and the rows of ``open_active`` (2N, K): the pieces of
    each open interval beside that stretch (its halves where both are 0), each with its interval's active pairs.
    Returns how many of each were written.
    """
    done = 0
    left = 0
    for n in range(lo.shape[0]):
        if kind[n] != OPEN:
            bounds[0, done], bounds[1, done] = lo[n], hi[n]
            labels[0, done], labels[1, done], labels[2, done] = owner[n], kind[n], pair[n]
            done += 1
            continue
        middle, half = (lo[n] + hi[n]) / 2.0, (hi[n] - lo[n]) / 2.0
        start = lo[n] if down[n] >= half else middle - down[n]  # a side decided whole: to its end, not a hair short
        end = hi[n] if up[n] >= half else middle + up[n]
        if down[n] > 0.0 or up[n] > 0.0:
            bounds[0, done], bounds[1, done] = start, end
            labels[0, done], labels[1, done], labels[2, done] = owner[n], carved[n], cause[n]
            done += 1
        if start > lo[n]:
            open_bounds[0, left], open_bounds[1, left], open_owner[left] = lo[n], start, owner[n]
            _array_copy.copy_into(open_active[left], active[n])
            left += 1
        if end < hi[n]:
            open_bounds[0, left], open_bounds[1, left], open_owner[left] = end, hi[n], owner[n]
            _array_copy.copy_into(open_active[left], active[n])
            left += 1
    return done, left
