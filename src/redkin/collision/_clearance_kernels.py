"""Compiled clearances of an arm's body at joint values (:mod:`redkin.collision.clearance`): the frames, the body's
capsules there and the signed distance of each checked pair, in one pass per configuration."""

from __future__ import annotations

from math import inf

import numpy as np

from redkin._chain_kernels import frames_one
from redkin._compiled import kernel
from redkin.collision._body_kernels import posed_one
from redkin.collision._distance_kernels import OUT, pair_distance, round_box_gap, round_round_gap
from redkin.collision.primitives import BOX, PLANE, WIDTH


@kernel
def scratch(links, frame):
    """The work arrays of :func:`clearances_one` for a chain of ``links`` (n, ...) and a body of ``frame`` (M,):
    the joints' sines and cosines, the frames, the posed capsules and a distance's output."""
    return (np.empty((links.shape[0], 2)), np.empty((links.shape[0] + 2, 4, 4)), np.empty((frame.shape[0], WIDTH)),
            np.empty(OUT))


@kernel
def clearances_one(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin, active,
                   floor, out, work):
    """At joint values ``q`` (n,) of the chain (``links``, ``ends``, ``standard``: :mod:`redkin._chain_kernels`'),
    the signed distance minus ``margin`` of each checked pair ``k`` that is ``active[k]`` into ``out[k]`` (``inf``
    for the others): capsule ``capsule[k]`` of the body (``frame``, ``a``, ``b``, ``radius``:
    :class:`redkin.collision.Body`'s) against obstacle ``obstacle[k]`` of ``obstacles`` (O, WIDTH), or against
    capsule ``other[k]`` where that is -1.  Where a cheap lower bound of the pair's distance minus the margin
    exceeds ``floor[k]`` (:func:`redkin.collision._distance_kernels.round_box_gap` against a box,
    :func:`~redkin.collision._distance_kernels.round_round_gap` against a sphere or capsule; none against a
    plane), that bound is written instead of the distance (``floor`` ``inf``: every distance exact).  A
    configuration with no active pair is not posed.  ``work`` is :func:`scratch`'s."""
    trig, held, rows, found = work
    posed = False
    for k in range(capsule.shape[0]):
        if not active[k]:
            out[k] = inf
            continue
        if not posed:
            frames_one(q, links, ends, standard, trig, held)
            posed_one(held, frame, a, b, radius, rows)
            posed = True
        shape = obstacles[obstacle[k]] if obstacle[k] >= 0 else rows[other[k]]
        if floor[k] < inf and shape[0] != PLANE:  # a plane's distance is as cheap as a bound
            bound = (round_box_gap(rows[capsule[k]], shape) if shape[0] == BOX
                     else round_round_gap(rows[capsule[k]], shape)) - margin
            if bound > floor[k]:
                out[k] = bound
                continue
        pair_distance(rows[capsule[k]], shape, found)
        out[k] = found[0] - margin


@kernel
def clearances(start, stop, q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
               active, out):
    """:func:`clearances_one` for configurations ``start .. stop - 1`` of ``q`` (N, n), ``active`` (N, K) and
    ``out`` (N, K), every distance exact."""
    work = scratch(links, frame)
    exact = np.full(capsule.shape[0], inf)
    for n in range(start, stop):
        clearances_one(q[n], links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
                       active[n], exact, out[n], work)
