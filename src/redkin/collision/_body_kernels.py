"""Compiled posing of an arm's body (:mod:`redkin.collision.body`): its capsules, fixed in the chain's frames, as
primitive rows in the base frame (:mod:`redkin.collision.primitives`)."""

from __future__ import annotations

from redkin._compiled import kernel
from redkin.collision.primitives import CAPSULE


@kernel
def posed_one(frames, frame, a, b, radius, rows):
    """The body's capsules at one configuration's frames ``frames`` (n + 2, 4, 4) into ``rows`` (M, WIDTH): capsule
    ``m`` has ends ``a[m]``, ``b[m]`` (3,) in frame ``frame[m]`` and radius ``radius[m]``; each end is the frame's
    columns weighted by its coordinates plus the frame's origin, and the row's orientation the identity."""
    for m in range(frame.shape[0]):
        held = frames[frame[m]]
        rows[m, 0] = CAPSULE
        rows[m, 1] = radius[m]
        for k in range(3):
            rows[m, 2 + k] = held[k, 0] * a[m, 0] + held[k, 1] * a[m, 1] + held[k, 2] * a[m, 2] + held[k, 3]
            rows[m, 5 + k] = held[k, 0] * b[m, 0] + held[k, 1] * b[m, 1] + held[k, 2] * b[m, 2] + held[k, 3]
        for k in range(9):
            rows[m, 8 + k] = 1.0 if k % 4 == 0 else 0.0


@kernel
def posed_rows(start, stop, frames, frame, a, b, radius, rows):
    """:func:`posed_one` for configurations ``start .. stop - 1`` of ``frames`` (N, n + 2, 4, 4) into ``rows``
    (N, M, WIDTH)."""
    for n in range(start, stop):
        posed_one(frames[n], frame, a, b, radius, rows[n])
