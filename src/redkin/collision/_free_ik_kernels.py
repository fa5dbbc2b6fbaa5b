"""The compiled core of the collision-free numerical IK (:mod:`redkin.collision.free_ik`): the numerical solver's
search of a pose ([N1]-[N5], :mod:`redkin.numerical._kernels`) that measures each new certified solution's clearance
as it is found (:func:`redkin.collision._clearance_kernels.least_one`), walks a colliding one along its self-motion
away from its closest pair before the next random start (:func:`escape`), and stops once enough keep the margin.

The starts, descents, certificates and distinctness are the solver's own kernels
(:func:`~redkin.numerical._kernels.begin`, :func:`~redkin.numerical._kernels.candidate`,
:func:`~redkin.numerical._kernels.settle`, :func:`~redkin.numerical._kernels.finish`): without the walk a pose's
candidates are the solver's, in its order, and the search only stops early.
"""

from __future__ import annotations

import numpy as np

from redkin import _array_copy
from redkin._chain_kernels import jacobian_one
from redkin._compiled import kernel
from redkin._pose_kernels import OK
from redkin.collision import _clearance_kernels
from redkin.numerical._kernels import (
    DAMPING_FLOOR,
    SEPARATION,
    begin,
    candidate,
    damped_step,
    finish,
    reach_budget,
    scratch,
    settle,
)

#: A step along the self-motion aims at this much clearance beyond the margin [m] (to first order).
LIFT = 0.05
#: Largest joint motion of one step along the self-motion [rad]; the smallest is twice the solver's separation.
WALK_STEP = 1.0


@kernel
def solve_one(target, seed, seeded, stream, links, ends, standard, bounds, settings, starts, frame, a, b, radius,
              obstacles, capsule, obstacle, other, margin, want, walk, q_out, found_out, closest, error, clearance_out,
              pair_out, work, local, spare):
    """:func:`redkin.numerical._kernels.solve_one`'s search of ``target``, each distinct certified solution's least
    distance and closest pair (the body ``frame``, ``a``, ``b``, ``radius`` against ``obstacles`` and itself over the
    checked pairs ``capsule``, ``obstacle``, ``other``) into ``clearance_out`` and ``pair_out`` (count,), stopping
    once ``want`` of them are at least ``margin`` clear; returns the starts used (-1 as the solver).

    After a candidate that does not keep the margin, up to ``walk`` starts are steps along its self-motion away from
    its closest pair (:func:`escape`), each from the last candidate, before the solver's next start; every step
    counts as a start (``walk`` 0: the solver's candidates alone, in its order).  ``spare`` is
    :func:`redkin.collision._clearance_kernels.scratch`'s."""
    if begin(target, seed, seeded, stream, q_out, found_out, local) != OK:
        return -1
    q = local[2][0]
    found = np.int64(0)
    used = np.int64(0)
    clear = np.int64(0)
    left = 0
    lower, upper = bounds[0], bounds[1]
    unpulled = bool(False)  # noqa: UP018 - not a literal: settle compiled once, for a bool
    while clear < want and found < q_out.shape[0] and used < starts:
        if left > 0:
            ok = escape(q, links, ends, standard, lower, upper, frame, a, b, radius, obstacles, capsule, obstacle,
                        other, pair_out[found - 1], margin - clearance_out[found - 1], settings[SEPARATION], work,
                        spare) and settle(seed, seeded, unpulled, links, ends, standard, lower, upper, settings,
                                          q_out, found, work, local)
        else:
            ok = candidate(used, seed, seeded, links, ends, standard, lower, upper, settings, q_out, found, work,
                           local)
        used += 1
        if not ok:
            left = 0
            continue
        _array_copy.copy_into(q_out[found], q)
        found_out[found] = True
        clearance_out[found], pair_out[found] = _clearance_kernels.least_one(
            q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, spare)
        if clearance_out[found] >= margin:
            clear += 1
            left = 0
        else:
            left = walk if left == 0 else left - 1
        found += 1
    finish(seed, seeded, links, ends, standard, q_out, found, closest, error, work, local)
    if seeded:  # the solutions were sorted by their distance to the seed: their clearances in that order
        for k in range(found):
            clearance_out[k], pair_out[k] = _clearance_kernels.least_one(
                q_out[k], links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, spare)
    return used


@kernel
def escape(q, links, ends, standard, lower, upper, frame, a, b, radius, obstacles, capsule, obstacle, other, pair,
           short, separation, work, spare):
    """Move the solution ``q`` (n,) in place along its self-motion so that checked pair ``pair``'s distance rises,
    to first order, by ``short`` (what it lacks of the margin) plus :data:`LIFT`; returns ``False`` where the
    self-motion does not move that distance (``q`` unchanged).

    The step is the distance's gradient ``g`` (:func:`redkin.collision._clearance_kernels.pair_gradient`) projected
    on the null space of the tool's Jacobian ``J``, ``v = (I - J^T (J J^T)^-1 J) g`` (the pull of
    :func:`redkin.numerical._kernels.damped_step` with no pose error), along which the distance rises at ``g . v =
    |v|^2``; its largest joint motion is held between twice ``separation`` and :data:`WALK_STEP`, and within the
    limits (``False`` where they leave less than twice ``separation``: the self-motion is blocked this way).  It
    leaves the pose by a second-order amount, which the next descent removes.
    ``work`` is :func:`redkin.numerical._kernels.scratch`'s, ``spare`` the clearance scratch."""
    n = q.shape[0]
    trig, _, e, jac, free, gradient, a6, y, v, _ = work
    _clearance_kernels.pair_gradient(q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle,
                                     other, pair, spare, jac, gradient)
    tool = bool(True)  # noqa: UP018 - not a literal: the chain's compiled jacobian_one (a bool) serves
    jacobian_one(q, links, ends, standard, n, tool, np.zeros(3), trig, jac)
    e[:] = 0.0
    free[:] = 1.0
    damped_step(jac, e, free, gradient, DAMPING_FLOOR, a6, y, v)
    rate = 0.0
    largest = 0.0
    for j in range(n):
        rate += gradient[j] * v[j]
        largest = max(largest, abs(v[j]))
    if not rate > 1e-12 or largest == 0.0:
        return False
    room = WALK_STEP / largest  # the longest step within the limits, and at most WALK_STEP in a joint
    for j in range(n):
        if v[j] > 0.0:
            room = min(room, (upper[j] - q[j]) / v[j])
        elif v[j] < 0.0:
            room = min(room, (lower[j] - q[j]) / v[j])
    step = min(max((short + LIFT) / rate, 2.0 * separation / largest), room)
    if step * largest < 2.0 * separation:  # a limit blocks the self-motion this way
        return False
    for j in range(n):
        q[j] += step * v[j]
    return True


@kernel
def solve(start, stop, targets, seeds, seeded, streams, links, ends, standard, bounds, settings, starts, reach, frame,
          a, b, radius, obstacles, capsule, obstacle, other, margin, want, walk, q_out, found_out, closest, error, used,
          distance, clearance_out, pair_out):
    """:func:`solve_one` for poses ``start .. stop - 1`` of ``targets``, with the arguments and outputs of
    :func:`redkin.numerical._kernels.solve` and ``clearance_out``, ``pair_out`` (N, count); returns how many targets
    are not poses."""
    bad = 0
    work, local = scratch(bounds.shape[1])
    spare = _clearance_kernels.scratch(links, frame, capsule, obstacles)
    for n in range(start, stop):
        budget = reach_budget(targets[n], reach, starts, distance[n:n + 1])
        used[n] = solve_one(targets[n], seeds[n], seeded, streams[n], links, ends, standard, bounds, settings, budget,
                            frame, a, b, radius, obstacles, capsule, obstacle, other, margin, want, walk, q_out[n],
                            found_out[n], closest[n], error[n], clearance_out[n], pair_out[n], work, local, spare)
        bad += used[n] < 0
    return bad
