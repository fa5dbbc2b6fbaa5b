"""The compiled core of the collision-free numerical IK (:mod:`redkin.collision.free_ik`): the numerical solver's
search of a pose ([N1]-[N5], :mod:`redkin.numerical._kernels`) that measures each new certified solution's clearance
as it is found (:func:`redkin.collision._clearance_kernels.least_one`) and stops once enough keep the margin.

The starts, descents, certificates and distinctness are the solver's own kernels
(:func:`~redkin.numerical._kernels.begin`, :func:`~redkin.numerical._kernels.candidate`,
:func:`~redkin.numerical._kernels.finish`), so a pose's candidates are the solver's, in its order: the search stops
early, it does not search otherwise.
"""

from __future__ import annotations

import numpy as np

from redkin._compiled import kernel
from redkin._pose_kernels import OK
from redkin.collision import _clearance_kernels
from redkin.numerical._kernels import begin, candidate, finish, reach_budget, scratch


@kernel
def solve_one(target, seed, seeded, stream, links, ends, standard, bounds, settings, starts, frame, a, b, radius,
              obstacles, capsule, obstacle, other, margin, want, q_out, found_out, closest, error, clearance_out,
              pair_out, work, local, spare):
    """:func:`redkin.numerical._kernels.solve_one`'s search of ``target``, each distinct certified solution's least
    distance and closest pair (the body ``frame``, ``a``, ``b``, ``radius`` against ``obstacles`` and itself over the
    checked pairs ``capsule``, ``obstacle``, ``other``) into ``clearance_out`` and ``pair_out`` (count,), stopping
    once ``want`` of them are at least ``margin`` clear; returns the starts used (-1 as the solver).  ``spare`` is
    :func:`redkin.collision._clearance_kernels.scratch`'s."""
    if begin(target, seed, seeded, stream, q_out, found_out, local) != OK:
        return -1
    q = local[2][0]
    found = np.int64(0)
    used = np.int64(0)
    clear = np.int64(0)
    while clear < want and found < q_out.shape[0] and used < starts:
        if candidate(used, seed, seeded, links, ends, standard, bounds[0], bounds[1], settings, q_out, found, work,
                     local):
            q_out[found] = q
            found_out[found] = True
            clearance_out[found], pair_out[found] = _clearance_kernels.least_one(
                q, links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, spare)
            clear += clearance_out[found] >= margin
            found += 1
        used += 1
    finish(seed, seeded, links, ends, standard, q_out, found, closest, error, work, local)
    if seeded:  # the solutions were sorted by their distance to the seed: their clearances in that order
        for k in range(found):
            clearance_out[k], pair_out[k] = _clearance_kernels.least_one(
                q_out[k], links, ends, standard, frame, a, b, radius, obstacles, capsule, obstacle, other, spare)
    return used


@kernel
def solve(start, stop, targets, seeds, seeded, streams, links, ends, standard, bounds, settings, starts, reach, frame,
          a, b, radius, obstacles, capsule, obstacle, other, margin, want, q_out, found_out, closest, error, used,
          distance, clearance_out, pair_out):
    """:func:`solve_one` for poses ``start .. stop - 1`` of ``targets``, with the arguments and outputs of
    :func:`redkin.numerical._kernels.solve` and ``clearance_out``, ``pair_out`` (N, count); returns how many targets
    are not poses."""
    bad = 0
    work, local = scratch(bounds.shape[1])
    spare = _clearance_kernels.scratch(links, frame, capsule)
    for n in range(start, stop):
        budget = reach_budget(targets[n], reach, starts, distance[n:n + 1])
        used[n] = solve_one(targets[n], seeds[n], seeded, streams[n], links, ends, standard, bounds, settings, budget,
                            frame, a, b, radius, obstacles, capsule, obstacle, other, margin, want, q_out[n],
                            found_out[n], closest[n], error[n], clearance_out[n], pair_out[n], work, local, spare)
        bad += used[n] < 0
    return bad
