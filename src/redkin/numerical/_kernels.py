"""The compiled core of the numerical pose IK: damped Gauss-Newton steps with joint limits, restarts, certificates.

One start runs damped least-squares (Levenberg-Marquardt) steps [N2]-[N3] on
the pose error [N1] from a joint vector, each step clipped to the joint
limits with the joints pinned at a limit taken out of the step [N4]; with a
seed, every step also moves the joints towards the seed inside the
self-motion [N5].  A start ends when the error is within the tolerance (a
certified solution, read off our own FK, :func:`~redkin._chain_kernels.frames_one`),
or when it stops shrinking.  The starts are the seed and then random joint
vectors within the limits, drawn from a per-pose stream (:func:`uniform`),
until ``count`` distinct solutions are certified or the budget of starts is
spent.  Equations: docs/numerical-ik.md.

Inputs are trusted (C-contiguous float64 arrays of the documented shapes);
:mod:`redkin.numerical.solve` validates at the public edge.
"""

from __future__ import annotations

from math import atan2, isfinite, pi, sqrt

import numpy as np

from redkin import _array_copy, _chain_kernels
from redkin._compiled import kernel
from redkin._pose_kernels import OK, pose_defect

#: Entries of the ``settings`` array of :func:`solve`.
POSITION_TOLERANCE, ROTATION_TOLERANCE, SEPARATION, SETTINGS = 0, 1, 2, 3
#: Largest joint step of one iteration [rad]: a damped step near a singular configuration can be huge.
MAX_STEP = 0.5
#: Largest pull towards the seed in one iteration [rad] ([N5]).
MAX_PULL = 0.2
#: The damping of [N3] is ``DAMPING e.e + DAMPING_FLOOR`` (measured on five arms: 0.05 needs 15-25 % less time per
#: solve than Chan and Lawrence's 0.5, with the same success).
DAMPING = 0.05
#: Damping floor of [N3]: keeps the 6 x 6 system positive definite where ``J`` loses rank at a solution.
DAMPING_FLOOR = 1e-12
#: Iterations one start may take.
ITERATIONS = 60
#: A start is given up when its error has not halved over this many iterations.
STALL = 8
#: After a start is certified: steps that pull it towards the seed, with one ([N5]); then plain steps that take its
#: error from the tolerance to rounding.
SETTLE, POLISH = 8, 2
#: An error (position plus rotation) at which the polish stops: rounding.
ROUNDING = 1e-14
#: The phases of :func:`descend`.
DESCENT, PULL, FINAL = 0, 1, 2
#: The pull towards the seed has settled when its last step moved no joint by more than this [rad].
SETTLED = 1e-10
#: Where ``pi - theta`` falls below this, the rotation error's axis is read from the symmetric part of ``E``.
NEAR_HALF_TURN = 1e-3


# ------------------------------------------------------------------ random starts
@kernel
def uniform(state):
    """The next number in ``[0, 1)`` of the stream ``state`` (1,) uint64 (SplitMix64, Steele et al. 2014).

    Each pose has its own stream, seeded from one integer the caller draws per pose, so a pose's starts do not
    depend on the other poses of its batch or on which thread solves it.
    """
    state[0] += np.uint64(0x9E3779B97F4A7C15)
    z = state[0]
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return float(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@kernel
def random_start(lower, upper, state, q):
    """A joint vector drawn uniformly within the limits into ``q`` (n,); a turn wide where a limit is infinite."""
    for j in range(q.shape[0]):
        u = uniform(state)
        if lower[j] > -np.inf and upper[j] < np.inf:
            q[j] = lower[j] + u * (upper[j] - lower[j])
        elif lower[j] > -np.inf:
            q[j] = lower[j] + 2.0 * pi * u
        elif upper[j] < np.inf:
            q[j] = upper[j] - 2.0 * pi * u
        else:
            q[j] = -pi + 2.0 * pi * u


# ------------------------------------------------------------------ pose error
@kernel
def pose_error(target, pose, e):
    """The pose error [N1] ``e = [p_t - p; log(R_t R^T)]`` (6,) of ``pose`` against ``target``; returns its
    position error [m] and rotation angle [rad].

    The rotation vector is world-referred, so that ``e(q + dq) = e(q) - J dq`` to first order with the geometric
    Jacobian ``J``.  Its angle is ``atan2(|s| / 2, (tr E - 1) / 2)`` with ``s`` the skew part of ``E = R_t R^T``,
    accurate near 0 and near pi alike; near a half turn the axis comes from the symmetric part.
    """
    for r in range(3):
        e[r] = target[r, 3] - pose[r, 3]
    m = np.empty((3, 3))
    for r in range(3):
        for c in range(3):
            m[r, c] = target[r, 0] * pose[c, 0] + target[r, 1] * pose[c, 1] + target[r, 2] * pose[c, 2]
    s0, s1, s2 = m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]
    size = sqrt(s0 * s0 + s1 * s1 + s2 * s2)
    cosine = 0.5 * (m[0, 0] + m[1, 1] + m[2, 2] - 1.0)
    angle = atan2(0.5 * size, cosine)
    if pi - angle > NEAR_HALF_TURN:
        scale = angle / size if size > 0.0 else 0.0
        e[3], e[4], e[5] = scale * s0, scale * s1, scale * s2
    else:  # (E + E^T) / 2 = cos I + (1 - cos) a a^T: the largest diagonal entry gives a well-conditioned a_k
        k = 0
        for i in range(1, 3):
            if m[i, i] > m[k, k]:
                k = i
        axis = np.empty(3)
        axis[k] = sqrt(max((m[k, k] - cosine) / (1.0 - cosine), 0.0))
        for i in range(3):
            if i != k:
                axis[i] = 0.5 * (m[i, k] + m[k, i]) / ((1.0 - cosine) * axis[k])
        if axis[0] * s0 + axis[1] * s1 + axis[2] * s2 < 0.0:
            angle = -angle  # the sign that makes the axis agree with the skew part, 2 sin(theta) a
        for i in range(3):
            e[3 + i] = angle * axis[i]
        angle = abs(angle)
    position = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return position, angle


# ------------------------------------------------------------------ one step
@kernel
def damped_step(jac, e, free, pull, damping, a, y, dq):
    """The step [N2]-[N5] into ``dq`` (n,): ``dq = r + W J^T y`` with ``(J W J^T + lambda I) y = e - J r``.

    ``W`` is diagonal with ``free`` (n,) (1 for a joint that may move, 0 for one pinned at a limit), ``r`` the
    pull towards the seed (``pull`` (n,), zeros without a seed) on the free joints, ``lambda`` the ``damping``.
    The 6 x 6 system is solved by Cholesky factorisation in ``a`` (6, 6); ``y`` (6,) is scratch.
    """
    n = jac.shape[1]
    for r in range(6):
        total = e[r]
        for j in range(n):
            total -= jac[r, j] * free[j] * pull[j]
        y[r] = total
        for c in range(r + 1):
            value = 0.0
            for j in range(n):
                value += jac[r, j] * free[j] * jac[c, j]
            a[r, c] = value
        a[r, r] += damping
    for r in range(6):  # Cholesky: a = L L^T, L in the lower triangle
        for c in range(r + 1):
            value = a[r, c]
            for k in range(c):
                value -= a[r, k] * a[c, k]
            if r == c:
                a[r, r] = sqrt(max(value, DAMPING_FLOOR))
            else:
                a[r, c] = value / a[c, c]
    for r in range(6):  # L z = b
        value = y[r]
        for k in range(r):
            value -= a[r, k] * y[k]
        y[r] = value / a[r, r]
    for r in range(5, -1, -1):  # L^T y = z
        value = y[r]
        for k in range(r + 1, 6):
            value -= a[k, r] * y[k]
        y[r] = value / a[r, r]
    for j in range(n):
        value = 0.0
        for r in range(6):
            value += jac[r, j] * y[r]
        dq[j] = free[j] * (pull[j] + value)


@kernel
def limited_step(q, jac, e, seed, seeded, lower, upper, free, pull, a, y, dq):
    """One damped step [N3] from ``q`` with the limits [N4]: joints at a limit that the step would push out are
    pinned (``free = 0``) and the step taken again, until no pinned joint pushes out; then the step is scaled to
    at most :data:`MAX_STEP` and ``q + dq`` clipped to the limits, in place."""
    n = q.shape[0]
    damping = DAMPING_FLOOR
    for r in range(6):
        damping += DAMPING * e[r] * e[r]
    pull_size = 0.0
    for j in range(n):
        free[j] = 1.0
        pull[j] = seed[j] - q[j] if seeded else 0.0
        pull_size = max(pull_size, abs(pull[j]))
    if pull_size > MAX_PULL:
        for j in range(n):
            pull[j] *= MAX_PULL / pull_size
    for _ in range(n + 1):
        damped_step(jac, e, free, pull, damping, a, y, dq)
        pinned = False
        for j in range(n):
            if free[j] == 1.0 and ((q[j] <= lower[j] and dq[j] < 0.0) or (q[j] >= upper[j] and dq[j] > 0.0)):
                free[j] = 0.0
                pinned = True
        if not pinned:
            break
    largest = 0.0
    for j in range(n):
        largest = max(largest, abs(dq[j]))
    scale = MAX_STEP / largest if largest > MAX_STEP else 1.0
    for j in range(n):
        q[j] = min(max(q[j] + scale * dq[j], lower[j]), upper[j])
    return largest * scale


# ------------------------------------------------------------------ one start
@kernel
def measure(q, target, links, ends, standard, trig, pose, e):
    """Our FK of ``q`` (:func:`~redkin._chain_kernels.frames_one`) into ``pose`` (1, 4, 4) and its error [N1]
    into ``e``; returns the position error [m] and the rotation angle [rad]."""
    _chain_kernels.frames_one(q, links, ends, standard, trig, pose)
    return pose_error(target, pose[0], e)


@kernel
def descend(q, target, seed, seeded, links, ends, standard, lower, upper, tolerance, work, best, best_error):
    """Damped steps from ``q`` (n,) until it is certified (returns ``True``, ``q`` the solution) or stalls.

    Three phases: plain damped steps [N3]-[N4] until the error is within the tolerance; with a seed, up to
    :data:`SETTLE` steps that also pull towards it [N5] while the error stays within the tolerance (the pull only
    once certified, so that it never slows the descent); then up to :data:`POLISH` plain steps, which take the error
    from the tolerance to rounding (:data:`ROUNDING`).  The last certified ``q`` is the answer.  ``best`` (n,) and
    ``best_error`` (2,) keep the joint vector of the smallest error met across calls (position plus rotation).
    """
    n = q.shape[0]
    trig, pose, e, jac, free, pull, a, y, dq, certified = work
    tool = bool(True)  # noqa: UP018 - the chain's compiled jacobian_one (a bool) serves
    origin = np.zeros(3)
    checkpoint = np.inf
    phase, left = DESCENT, 0
    for iteration in range(ITERATIONS + SETTLE + POLISH):
        position, angle = measure(q, target, links, ends, standard, trig, pose, e)
        if position + angle < best_error[0] + best_error[1]:
            best_error[0], best_error[1] = position, angle
            _array_copy.copy_into(best, q)
        within = position <= tolerance[0] and angle <= tolerance[1]
        if phase == DESCENT:
            if within:
                phase, left = (PULL, SETTLE) if seeded else (FINAL, POLISH)
            elif iteration >= ITERATIONS:
                return False
            elif iteration % STALL == 0:
                if position + angle > 0.5 * checkpoint:
                    return False
                checkpoint = position + angle
        if phase != DESCENT:
            if not within:  # a pull step left the tolerance: polish from the last certified q
                _array_copy.copy_into(q, certified)
                if phase == FINAL:
                    return True
                phase, left = FINAL, POLISH
                continue
            _array_copy.copy_into(certified, q)
            if left == 0 or (phase == FINAL and position + angle <= ROUNDING):
                if phase == FINAL:
                    return True
                phase, left = FINAL, POLISH
            left -= 1
        # q as measured: its sines and cosines are in trig
        _chain_kernels.jacobian_from_trig(links, ends, standard, n, tool, origin, trig, jac)
        moved = limited_step(q, jac, e, seed, phase == PULL, lower, upper, free, pull, a, y, dq)
        if phase == PULL and moved <= SETTLED:
            phase, left = FINAL, POLISH
    _array_copy.copy_into(q, certified)
    return phase != DESCENT


# ------------------------------------------------------------------ one pose, a batch
@kernel
def nearest_pose(target, out):
    """``target`` (4, 4) with its rotation block replaced by the nearest rotation (its polar factor), into ``out``.

    The public edge accepts rotations orthonormal to within ``1e-6`` (:func:`redkin._validation.check_pose`); a
    solution can match only a rotation, so the target is the nearest one.  Newton-Schulz iterations
    ``X <- X (3 I - X^T X) / 2`` converge quadratically from there (three reach rounding from ``1e-6``).
    """
    _array_copy.copy_rows_into(out, target)
    gram = np.empty((3, 3))
    for _ in range(4):
        for r in range(3):
            for c in range(3):
                gram[r, c] = 1.5 * (r == c) - 0.5 * (out[0, r] * out[0, c] + out[1, r] * out[1, c]
                                                      + out[2, r] * out[2, c])
        for r in range(3):
            x0, x1, x2 = out[r, 0], out[r, 1], out[r, 2]
            for c in range(3):
                out[r, c] = x0 * gram[0, c] + x1 * gram[1, c] + x2 * gram[2, c]


@kernel
def normalise(q, seed, seeded, lower, upper):
    """Each joint moved by whole turns to the representative within its limits nearest the seed (with a seed), or
    an unlimited joint into ``[-pi, pi]`` (without); a value already in place stays bit for bit
    (:func:`redkin._chain_kernels.representative`, which keeps the turned value within the limits)."""
    for j in range(q.shape[0]):
        if seeded:
            q[j] = _chain_kernels.representative(q[j], lower[j], upper[j], seed[j])
        elif lower[j] == -np.inf and upper[j] == np.inf:
            q[j] = _chain_kernels.representative(q[j], lower[j], upper[j], 0.0)


@kernel
def distinct(q, solutions, found, separation):
    """Whether ``q`` differs from every found row of ``solutions`` by more than ``separation`` in some joint."""
    for k in range(found):
        largest = 0.0
        for j in range(q.shape[0]):
            largest = max(largest, abs(q[j] - solutions[k, j]))
        if largest <= separation:
            return False
    return True


@kernel
def scratch(n):
    """The scratch arrays of :func:`solve_one` for a chain of ``n`` joints, made once per batch: those of
    :func:`descend` (``work``) and the target, the random stream's state, two joint vectors and an error pair."""
    work = (np.empty((n, 2)), np.empty((1, 4, 4)), np.empty(6), np.empty((6, n)), np.empty(n), np.empty(n),
            np.empty((6, 6)), np.empty(6), np.empty(n), np.empty(n))
    local = (np.empty((4, 4)), np.empty(1, dtype=np.uint64), np.empty((2, n)), np.empty(2))
    return work, local


@kernel
def begin(target, seed, seeded, stream, q_out, found_out, local):
    """Ready the search of one pose (:func:`solve_one`): the target's nearest pose into ``local``'s goal, the random
    stream ``stream``, no error met yet, no solution yet; returns ``OK``, or -1 for a target that is not a pose
    (:func:`~redkin._pose_kernels.pose_defect`) or a seed that is not finite.  ``local`` is :func:`scratch`'s."""
    if pose_defect(target) != OK:
        return -1
    for j in range(seed.shape[0]):
        if seeded and not isfinite(seed[j]):
            return -1
    goal, state, _, best_error = local
    nearest_pose(target, goal)
    state[0] = stream
    best_error[0], best_error[1] = np.inf, np.inf
    q_out[:] = 0.0
    found_out[:] = False
    return OK


@kernel
def candidate(start, seed, seeded, links, ends, standard, lower, upper, settings, q_out, found, work, local):
    """Start number ``start`` (from 0) of a search :func:`begin` readied: the seed first (with one, clipped to the
    limits), then random joint vectors; returns whether it ends in a certified solution, distinct from the
    ``found`` rows of ``q_out`` by ``settings``' separation, left in ``local``'s first joint vector."""
    q = local[2][0]
    if start == 0 and seeded:
        for j in range(q.shape[0]):
            q[j] = min(max(seed[j], lower[j]), upper[j])
    else:
        random_start(lower, upper, local[1], q)
    return settle(seed, seeded, seeded, links, ends, standard, lower, upper, settings, q_out, found, work, local)


@kernel
def settle(seed, seeded, pulled, links, ends, standard, lower, upper, settings, q_out, found, work, local):
    """Descend from the start in ``local``'s first joint vector (:func:`descend`, pulled towards the seed once
    certified where ``pulled``); returns whether it ends in a certified solution there, distinct from the ``found``
    rows of ``q_out`` by ``settings``' separation (each joint's turn nearest the seed, with one)."""
    goal, _, vectors, best_error = local
    q, best = vectors[0], vectors[1]
    tolerance = settings[POSITION_TOLERANCE:ROTATION_TOLERANCE + 1]
    if not descend(q, goal, seed, seeded and pulled, links, ends, standard, lower, upper, tolerance, work, best,
                   best_error):
        return False
    normalise(q, seed, seeded, lower, upper)
    position, angle = measure(q, goal, links, ends, standard, work[0], work[1], work[2])
    if position > tolerance[0] or angle > tolerance[1]:  # the certificate is of the q returned
        return False
    return distinct(q, q_out, found, settings[SEPARATION])


@kernel
def finish(seed, seeded, links, ends, standard, q_out, found, closest, error, work, local):
    """End a search with ``found`` solutions in ``q_out``: with a seed, sorted by their largest joint distance to it
    (stably); ``closest`` and ``error`` as :func:`solve_one` gives them."""
    goal, _, vectors, best_error = local
    if seeded:  # insertion sort by the largest joint distance to the seed
        for k in range(1, found):
            row = q_out[k].copy()
            key = np.max(np.abs(row - seed))
            i = k
            while i > 0 and np.max(np.abs(q_out[i - 1] - seed)) > key:
                _array_copy.copy_into(q_out[i], q_out[i - 1])
                i -= 1
            _array_copy.copy_into(q_out[i], row)
    if found:
        _array_copy.copy_into(closest, q_out[0])
        position, angle = measure(closest, goal, links, ends, standard, work[0], work[1], work[2])
        error[0], error[1] = position, angle
    else:
        _array_copy.copy_into(closest, vectors[1])
        _array_copy.copy_into(error, best_error)


@kernel
def solve_one(target, seed, seeded, stream, links, ends, standard, bounds, settings, starts, q_out, found_out, closest,
              error, work, local):
    """Up to ``count = q_out.shape[0]`` distinct certified solutions of one pose ``target`` (4, 4) into ``q_out``
    (count, n) and ``found_out`` (count,), with at most ``starts`` starts; returns the starts used.

    ``closest`` (n,) receives the first solution, or without one the joint vector of the smallest error met, and
    ``error`` (2,) its position and rotation error.  ``bounds`` (2, n) holds the lower and the upper limits.  With
    a seed the solutions are sorted by their largest joint distance to it.  ``work`` and ``local`` are the scratch
    arrays of :func:`scratch`.  A target that is not a pose (:func:`~redkin._pose_kernels.pose_defect`), or a seed
    that is not finite, returns -1.
    """
    if begin(target, seed, seeded, stream, q_out, found_out, local) != OK:
        return -1
    found = np.int64(0)
    used = np.int64(0)
    while found < q_out.shape[0] and used < starts:
        if candidate(used, seed, seeded, links, ends, standard, bounds[0], bounds[1], settings, q_out, found, work,
                     local):
            _array_copy.copy_into(q_out[found], local[2][0])
            found_out[found] = True
            found += 1
        used += 1
    finish(seed, seeded, links, ends, standard, q_out, found, closest, error, work, local)
    return used


@kernel
def reach_budget(target, reach, starts, distance):
    """The starts a search of ``target`` may use: ``starts``, or one where the tool point lies farther than
    ``reach[3]`` from the centre ``reach[:3]`` of the chain's reach bound (no solution: only ``closest`` is wanted);
    that distance into ``distance[0]``."""
    x, y, z = target[0, 3] - reach[0], target[1, 3] - reach[1], target[2, 3] - reach[2]
    distance[0] = sqrt(x * x + y * y + z * z)
    return 1 if distance[0] > reach[3] else starts


@kernel
def solve(start, stop, targets, seeds, seeded, streams, links, ends, standard, bounds, settings, starts, reach, q_out,
          found_out, closest, error, used, distance):
    """:func:`solve_one` for poses ``start .. stop - 1`` of ``targets`` (N, 4, 4), with ``seeds`` (N, n) and
    ``streams`` (N,) uint64, into ``q_out`` (N, count, n), ``found_out`` (N, count), ``closest`` (N, n),
    ``error`` (N, 2) and ``used`` (N,); returns how many targets are not poses.

    ``reach`` (4,) is the centre of the chain's reach bound and the largest distance from it that may hold a
    solution (:meth:`redkin.chain.SerialChain.reach`); ``distance`` (N,) receives each target's.  A target farther
    out takes one start (for ``closest``) instead of ``starts``.
    """
    bad = 0
    work, local = scratch(bounds.shape[1])
    for b in range(start, stop):
        budget = reach_budget(targets[b], reach, starts, distance[b:b + 1])
        used[b] = solve_one(targets[b], seeds[b], seeded, streams[b], links, ends, standard, bounds, settings,
                            budget, q_out[b], found_out[b], closest[b], error[b], work, local)
        bad += used[b] < 0
    return bad
