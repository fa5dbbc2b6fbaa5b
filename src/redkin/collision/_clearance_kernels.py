"""Compiled clearances of an arm's body at joint values (:mod:`redkin.collision.clearance`): the frames, the body's
capsules there and the signed distance of each checked pair, in one pass per configuration; and a pair's distance's
gradient over the joints (:func:`pair_gradient`)."""

from __future__ import annotations

from math import inf, nan

import numpy as np

from redkin._chain_kernels import frames_one, jacobian_from_trig
from redkin._compiled import kernel
from redkin.collision._body_kernels import posed_one
from redkin.collision._distance_kernels import OUT, pair_distance, round_box_gap, round_round_gap
from redkin.collision.primitives import BOX, PLANE, WIDTH

#: A lower bound within this of the least distance so far [m] may still tie with it (:func:`least_one`).
TIE = 1e-12


@kernel
def scratch(links, frame, capsule, obstacles):
    """The work arrays of :func:`clearances_one` and :func:`least_one` for a chain of ``links`` (n, ...), a body of
    ``frame`` (M,), the checked pairs ``capsule`` (K,) and the ``obstacles`` (O, WIDTH): the joints' sines and
    cosines, the frames, the posed capsules and each pair's distance output (K, OUT) (at least one row), each pair's
    lower bound (K,), and the axis-aligned boxes of the posed capsules (M, 6) and of the obstacles (O, 6)."""
    return (np.empty((links.shape[0], 2)), np.empty((links.shape[0] + 2, 4, 4)), np.empty((frame.shape[0], WIDTH)),
            np.empty((max(capsule.shape[0], 1), OUT)), np.empty(capsule.shape[0]), np.empty((frame.shape[0], 6)),
            np.empty((obstacles.shape[0], 6)))


@kernel
def clearances_one(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin, active,
                   floor, out, work):
    """At joint values ``q`` (n,) of the chain (``links``, ``ends``, ``standard``: :mod:`redkin._chain_kernels`'),
    the signed distance minus ``margin`` of each checked pair ``k`` that is ``active[k]`` into ``out[k]`` (``inf``
    for the others): capsule ``capsule[k]`` of the body (``frame``, ``a``, ``b``, ``radius``:
    :class:`redkin.collision.Body`'s) against obstacle ``obstacle[k]`` of ``obstacles`` (O, WIDTH), or against
    capsule ``other[k]`` where that is -1.  Where the pair's :func:`lower_bound` minus the margin exceeds
    ``floor[k]`` (>= 0), that bound is written instead of the distance (``floor`` ``inf``: every distance exact).  A
    configuration with no active pair is not posed.  ``work`` is :func:`scratch`'s; its last array holds each
    measured pair's distance, witness points and normal (:func:`redkin.collision._distance_kernels.pair_distance`),
    and NaN for the others."""
    trig, held, rows, found = work[:4]
    posed = False
    for k in range(capsule.shape[0]):
        found[k, 0] = nan
        if not active[k]:
            out[k] = inf
            continue
        if not posed:
            frames_one(q, links, ends, standard, trig, held)
            posed_one(held, frame, a, b, radius, rows)
            posed = True
        shape = obstacles[obstacle[k]] if obstacle[k] >= 0 else rows[other[k]]
        if floor[k] < inf:
            bound = lower_bound(rows[capsule[k]], shape) - margin
            if bound > floor[k]:
                out[k] = bound
                continue
        pair_distance(rows[capsule[k]], shape, found[k])
        out[k] = found[k, 0] - margin


@kernel
def lower_bound(round_row, shape):
    """A lower bound, cheap beside the distance, of the signed distance of a body capsule ``round_row`` and
    ``shape`` (a row of :mod:`redkin.collision.primitives`) wherever it is positive
    (:func:`redkin.collision._distance_kernels.round_box_gap` against a box,
    :func:`~redkin.collision._distance_kernels.round_round_gap` against a sphere or capsule); ``-inf`` against a
    plane, whose distance is as cheap."""
    if shape[0] == PLANE:
        return -inf
    return round_box_gap(round_row, shape) if shape[0] == BOX else round_round_gap(round_row, shape)


@kernel
def least_one(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, work):
    """At joint values ``q`` (n,) (the arguments of :func:`clearances_one`), the least signed distance over the
    checked pairs and the first pair that has it (``inf`` and -1 with no pair).

    A first pass bounds every pair from below by the gap between the two shapes' axis-aligned boxes
    (:func:`_aligned_box`; against a plane its distance itself, as cheap), and the pair with the lowest is measured
    first.  Then a pair whose positive bound (that gap, then :func:`lower_bound`) exceeds the least distance so far
    by more than :data:`TIE` cannot be less, and is not measured (one within it may tie, computed otherwise: it is
    measured, so that the first pair with the least distance is the one named)."""
    trig, held, rows, found, bounds, boxes, obstacle_boxes = work
    pairs = capsule.shape[0]
    if not pairs:
        return inf, -1
    frames_one(q, links, ends, standard, trig, held)
    posed_one(held, frame, a, b, radius, rows)
    for m in range(rows.shape[0]):
        _aligned_box(rows[m], boxes[m])
    for o in range(obstacles.shape[0]):
        _aligned_box(obstacles[o], obstacle_boxes[o])
    first = 0
    for k in range(pairs):
        if obstacle[k] >= 0 and obstacles[obstacle[k], 0] == PLANE:
            pair_distance(rows[capsule[k]], obstacles[obstacle[k]], found[0])
            bounds[k] = found[0, 0]
        else:
            bounds[k] = _box_gap(boxes[capsule[k]], obstacle_boxes[obstacle[k]] if obstacle[k] >= 0
                                 else boxes[other[k]])
        if bounds[k] < bounds[first]:
            first = k
    best, closest = inf, -1
    for step in range(pairs + 1):
        k = first if step == 0 else step - 1
        if step and (k == first or (bounds[k] > 0.0 and bounds[k] > best + TIE)):
            continue
        shape = obstacles[obstacle[k]] if obstacle[k] >= 0 else rows[other[k]]
        if shape[0] == PLANE:
            distance = bounds[k]
        else:
            finer = lower_bound(rows[capsule[k]], shape)
            if step and finer > 0.0 and finer > best + TIE:
                continue
            pair_distance(rows[capsule[k]], shape, found[0])
            distance = found[0, 0]
        if distance < best or closest < 0 or (distance == best and k < closest):
            best, closest = distance, k
    return best, closest


@kernel
def _aligned_box(row, out):
    """The box along the frame's axes around the shape ``row`` into ``out`` (6,): its lowest and highest corners
    (everywhere for a plane)."""
    for i in range(3):
        if row[0] == PLANE:
            out[i], out[3 + i] = -inf, inf
        elif row[0] == BOX:  # the centre plus or minus |R| times the half sizes
            extent = abs(row[8 + 3 * i]) * row[5] + abs(row[9 + 3 * i]) * row[6] + abs(row[10 + 3 * i]) * row[7]
            out[i], out[3 + i] = row[2 + i] - extent, row[2 + i] + extent
        else:  # a segment's ends, widened by the radius
            out[i] = min(row[2 + i], row[5 + i]) - row[1]
            out[3 + i] = max(row[2 + i], row[5 + i]) + row[1]


@kernel
def _box_gap(first, second):
    """The widest gap between two axis-aligned boxes ``first`` and ``second`` (6,) along one axis: a lower bound of
    the distance of any two shapes inside them where it is positive (every point of one is that far from every point
    of the other along that axis)."""
    gap = -inf
    for i in range(3):
        gap = max(gap, second[i] - first[3 + i], first[i] - second[3 + i])
    return gap


@kernel
def pair_gradient(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, k, work, jac,
                  gradient):
    """The gradient over the joints of checked pair ``k``'s signed distance at ``q`` (n,) (the arguments of
    :func:`clearances_one`) into ``gradient`` (n,); returns the distance.

    With the pair's witness points ``pa`` (on capsule ``capsule[k]``) and ``pb`` and the unit normal ``u`` from a to
    b (:func:`redkin.collision._distance_kernels.pair_distance`, ``pb - pa = d u``), moving the two solids changes
    the distance by ``u . (dpb - dpa)`` to first order, so the gradient is ``u^T (J_b(pb) - J_a(pa))`` with ``J``
    the linear rows of the Jacobian of a point fixed in the capsule's frame (``J_b = 0`` for an obstacle).  It is
    the distance's derivative wherever the witness points are unique (not where two features of a pair are equally
    near, nor for a capsule's core inside a box, where the depth may have a kink).  ``jac`` (6, n) is scratch;
    ``work`` is :func:`scratch`'s."""
    trig, held, rows, found = work[:4]
    frames_one(q, links, ends, standard, trig, held)
    posed_one(held, frame, a, b, radius, rows)
    shape = obstacles[obstacle[k]] if obstacle[k] >= 0 else rows[other[k]]
    out = found[0]
    pair_distance(rows[capsule[k]], shape, out)
    gradient[:] = 0.0
    _point_motion(links, ends, standard, held, frame[capsule[k]], out[1:4], out[7:10], -1.0, trig, jac, gradient)
    if obstacle[k] < 0:
        _point_motion(links, ends, standard, held, frame[other[k]], out[4:7], out[7:10], 1.0, trig, jac,
                      gradient)
    return out[0]


@kernel
def _point_motion(links, ends, standard, held, which, point, direction, sign, trig, jac, gradient):
    """Add ``sign direction^T J(point)`` to ``gradient`` (n,), ``J`` the linear rows of the Jacobian of ``point``
    (world) held fixed in frame ``which`` of ``held`` (:func:`redkin._chain_kernels.frames_one`'s: the base, the
    frames after each joint, the tool), ``trig`` the sines and cosines that call left."""
    n = links.shape[0]
    frame = held[which]
    offset = np.empty(3)
    for c in range(3):
        offset[c] = (frame[0, c] * (point[0] - frame[0, 3]) + frame[1, c] * (point[1] - frame[1, 3])
                     + frame[2, c] * (point[2] - frame[2, 3]))
    jacobian_from_trig(links, ends, standard, min(which, n), which > n, offset, trig, jac)
    for j in range(n):
        gradient[j] += sign * (direction[0] * jac[0, j] + direction[1] * jac[1, j] + direction[2] * jac[2, j])


@kernel
def least(start, stop, q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, distance,
          pair):
    """:func:`least_one` for configurations ``start .. stop - 1`` of ``q`` (N, n), into ``distance`` and ``pair``
    (N,)."""
    work = scratch(links, frame, capsule, obstacles)
    for n in range(start, stop):
        distance[n], pair[n] = least_one(q[n], links, ends, standard, frame, a, b, radius, obstacles, capsule,
                                         obstacle, other, work)


@kernel
def clearances(start, stop, q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
               active, floor, out):
    """:func:`clearances_one` for configurations ``start .. stop - 1`` of ``q`` (N, n), ``active``, ``floor`` and
    ``out`` (N, K)."""
    work = scratch(links, frame, capsule, obstacles)
    for n in range(start, stop):
        clearances_one(q[n], links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, margin,
                       active[n], floor[n], out[n], work)
