"""The compiled core of :mod:`redkin.srs.nearly.self_motion`: the real arm's self-motion, followed with a certificate.

For one pose ``T`` the real arm's solutions form curves in joint space (its
self-motion): 6 equations ``F(q) = 0`` in 7 unknowns.  :func:`traced`
follows one from a solution by predictor-corrector continuation and proves,
step by step, that the points it returns are joined by a curve of true
solutions, and where that curve lies (docs/srs.md, "The certified
self-motion", eqs. C1-C6).

The equations [C1] are ``F(q) = [c (p(q) - p_T); r(q)]``, ``r = vee(M - M^T)
/ 2`` with ``M = R(q) R_T^T`` (``r = sin(angle) axis``, zero at the target's
rotation), ``c`` a scale [1/m] (2 over the arm's longest lever arm).  Their
derivatives are exact (:func:`residual`, :func:`curvature`): with ``w_i``
joint ``i``'s signed unit axis, the position rows of ``F'`` are ``c`` times
the geometric Jacobian's, ``dr/dq_i = N(M) w_i`` with ``N(X) = (tr(X) I - X)
/ 2`` (from ``dM/dq_i = [w_i]x M`` and ``[w]x M + M^T [w]x = [2 N(M) w]x``),
and for ``j <= i`` the second derivatives are ``w_j x J_pos,i`` and ``N([w_j]x
M) w_i + N(M) (w_j x w_i)`` (the last term for ``j < i`` only).

A step from a point ``x`` with unit tangent ``t`` (``F'(x) t = 0``) covers
``s`` in ``[0, H]``: the curve's point on the hyperplane ``t . (q - x) = s``
solves ``G_s(q) = [F(q); t . (q - x) - s] = 0``, whose Jacobian is ``A(q) =
[F'(q); t^T]``.  The predictor is the curve's second-order expansion ``y_s =
x + s t + s^2 kappa / 2``, ``kappa = -A(x)^-1 [F''(x)[t, t]; 0]`` (on the
hyperplane: ``t . kappa = 0``).  The affine-covariant Newton-Kantorovich
theorem [C2] (Deuflhard, *Newton Methods for Nonlinear Problems*, thm. 2.1)
from ``y_s`` needs

* ``omega``, a Lipschitz constant of ``A(x)^-1 F'`` over a ball ``D`` about
  ``x`` holding every ``y_s`` and room about it (:data:`BALL_ROOM`) [C3]:
  ``omega = Omega + beta K |D|``, ``Omega`` bounding ``|A(x)^-1 F''(x)|``
  (the 28 second derivatives at ``x`` mapped by ``A(x)^-1``, their norms'
  spectral norm bounded by its Frobenius norm and its largest row sum),
  ``beta >= |A(x)^-1|`` (:func:`inverse_bound`) and ``K`` a bound of the third
  derivatives everywhere (the Frobenius norm of bounds of their 343 entries:
  along joints ``i <= j <= m`` the end point's is ``w_i x (w_j x (w_m x (p -
  o_m)))``, no longer than the links after joint ``m``, and ``M``'s is
  ``[w_i]x [w_j]x [w_m]x M``, so the rotation rows' is at most 1);
* relative to ``A(y_s)``, with ``d = |y_s - x| <= s + s^2 |kappa| / 2`` and
  ``c`` a bound of ``|A(x)^-1 (A(y_s) - A(x))|``, the smaller of ``omega d``
  and (Taylor's theorem along the step) ``s Omega_t + s^2 |kappa| Omega / 2 +
  beta T_2 / 2``, ``Omega_t`` bounding ``|A(x)^-1 F''(x)[t, .]|``:
  ``omega_s = omega / (1 - c)``, and by Taylor's theorem the first Newton
  step ``alpha_s <= (beta (eps + s delta + s^2 e / 2) + Omega (s^3 |kappa| /
  2 + s^4 |kappa|^2 / 8) + beta T_3 / 6) / (1 - c)`` (``eps = |F(x)|``,
  ``delta = |F'(x) t|``, ``e`` the residual of ``kappa``'s equations:
  rounding), ``T_3`` and ``T_2`` bounding ``|F'''(z)[y_s - x]^3|`` and
  ``|F'''(z)[y_s - x, y_s - x, .]|`` everywhere from the same entry bounds as
  ``K``, summed along the step's own direction (:func:`third_along`: several
  times less than ``K d^3`` and ``K d^2``).

Where ``h_K = omega_s alpha_s <= 0.45`` for ``s = H``, it gives one solution
``x*(s)`` within ``r* = (1 - sqrt(1 - 2 h_K)) / omega_s`` of ``y_s`` for every
``s``, the only one within the larger uniqueness radius, and so (by the
implicit function theorem at each ``x*(s)``) a continuous arc of true
solutions.  Consecutive steps share a point: each is certified a little past
its end (:data:`OVERLAP`) and the next step's start lies within its
uniqueness ball.  Every joint therefore stays, over the arc, within ``r*`` of
the predictor (and nearer the start within ``R(s)``, :func:`tube_range`), and
within ``r* + H^2 |kappa| / 2`` of the tangent ``x + s t``; a step is
classified by that tube [C4]: each branch sign (the neighbour's ``theta_2``,
``theta_4 - phi_real`` and ``theta_6`` away from 0 and pi) and each limited
joint (within its limits modulo whole turns, outside them, or not decided).
The arm angle stays over the arc within ``sum_j G_j e_j`` of its value at
the start [C5] (:func:`arm_angle_spread`): ``G_j`` bounds ``|d psi / d q_j|``
over the ball from the wrist's distances to joint 1's axis and to the
shoulder, ``e_j`` is how far joint ``j`` gets within the tube, for joints 2-4
(joint 1 turns the reference plane with the arm, joints 5-7 do not move the
wrist); a step is kept only where that is at most :data:`ARM_ANGLE_STEP`,
less than pi, so the arc's arm angles cover the short arc between its ends
[C6].  Where a step is not
decided (a sign or a limit crossed, or a fold: ``d psi / ds`` changes sign)
it is shortened (:func:`_shorter`) until its arm-angle bound is at most
:data:`RESOLUTION`.

Floating-point rounding of the bounds themselves is covered by the margin of
0.45 against Kantorovich's 1/2 and by :data:`OVERLAP`.  Inputs are trusted.
"""

from __future__ import annotations

from math import floor, pi, sqrt

import numpy as np

from redkin import _array_copy, _chain_kernels
from redkin._compiled import kernel
from redkin.circle import TWO_PI
from redkin.srs._ik_kernels import AXIS_TOLERANCE, turns_removed, wrist_point
from redkin.srs.nearly._kernels import arm_angle_one

#: Entries of an arm's ``bounds`` (:attr:`redkin.srs.nearly.NearlySRS.kernel_bounds`): the position rows' scale ``c``
#: [1/m]; ``K``, a bound of the third derivatives of ``F`` everywhere [C3] (module docstring); each of joints 1-4's
#: lever arm to the neighbour's wrist point [m] (4); the forearm's length [m]; and for each joint ``k`` the bound
#: ``c rho_k`` of the position rows' third derivatives whose last joint is ``k`` (7, :func:`third_along`).
SCALE, THIRD, LEVER = range(3)
FOREARM = LEVER + 4
REACHES = FOREARM + 1
#: Entries of a point's ``state`` (:func:`described`): ``|F|``, ``delta = |F' t|``, ``beta``, ``psi``, ``d psi /
#: ds``, the wrist's distance ``w`` from joint 1's axis, ``|x_sw|``, ``Omega``; from ``BEND`` the curve's second
#: derivative ``kappa`` (7), then ``|kappa|``, the rounding of its equations and ``Omega_t`` (a bound of ``|A^-1
#: F''[t, .]|``); and the state's length.
SIZE, DELTA, BETA, PSI, PSI_RATE, OFF_AXIS, APART, OMEGA, BEND = range(9)
BEND_SIZE, BEND_ROUNDING, TURNING, STATE = BEND + 7, BEND + 8, BEND + 9, BEND + 10
#: Kantorovich's ``h_K`` at most (1/2 in the theorem; the margin covers the rounding of the bounds).
KANTOROVICH = 0.45
#: How far past its end [rad of arc length] a step is certified at least, so that it meets the next (module
#: docstring); more where the next point's existence radius ``2 beta |F|`` (and, for the step that closes a curve,
#: the first point's and the distance between the two) is larger.
OVERLAP = 1e-12
#: The ball ``D`` about a step's start over which ``omega`` holds [C3] reaches this many times the step's length
#: beyond it (plus :data:`REGION`), the first that certifies: little room makes ``omega`` smaller, and is enough
#: where the tube is narrow (Kantorovich's uniqueness ball about ``y_s`` must lie inside ``D``).
BALL_ROOM = (0.25, 1.0)
#: Added to the radius [rad] of the ball about a step's start over which ``L`` holds, so that a short step's
#: uniqueness ball still reaches well past its tube.
REGION = 1e-6
#: A step's arm-angle change at most [rad], less than pi, so that the arm angle covers the short arc between its
#: ends [C6] (the bound of C5 is loose: the change itself is some 50 times smaller on a typical step).
ARM_ANGLE_STEP = 2.0
#: ``(1 - sqrt(1 - 2 h)) / h`` at ``h`` = :data:`KANTOROVICH` (1.5195) at least: Kantorovich's radius is at most this
#: many first Newton steps ``alpha`` wherever ``h_K`` is at most that [C4].
RADIUS_FACTOR = 1.52
#: The arm-angle bound [rad] down to which a step that is not decided is halved.
RESOLUTION = 1e-10
#: Newton's steps of the corrector at most; the residual ``|F|`` at which it stops, and at most which it has settled
#: where Newton's steps stop halving it (rounding).
CORRECTOR_STEPS, FINE, SETTLED = 12, 1e-15, 1e-13
#: The smallest step [rad] before the continuation gives up (a singular configuration).
SMALLEST_STEP = 1e-15
#: The shortest step [rad] the certificate alone may allow before the continuation gives up: the curve runs into a
#: singular configuration (two sheets of the self-motion crossing, as at a wrist exactly straight on an arm whose
#: wrist axes meet), towards which the certified steps shrink without end.
SINGULAR_STEP = 1e-9
#: States of a step's limited joints: all within their limits, one outside, not decided.
INSIDE, OUTSIDE, UNDECIDED = 1, 0, -1
#: What :func:`traced` returns: the curve came back to its first point; it stopped at ``most`` points; a step could
#: not be certified (a singular configuration, or the wrist on joint 1's axis).
CLOSED, FULL, STUCK = 0, 1, 2


# ------------------------------------------------------------------ small dense linear algebra
@kernel
def factored(a, pivots):
    """LU factorisation with partial pivoting of ``a`` (7, 7) in place (LAPACK's layout); returns ``False`` where a
    pivot is zero."""
    n = 7
    for k in range(n):
        row, big = k, abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                row, big = i, abs(a[i, k])
        if big == 0.0 or not np.isfinite(big):
            return False
        pivots[k] = row
        if row != k:
            for j in range(n):
                a[k, j], a[row, j] = a[row, j], a[k, j]
        inverse = 1.0 / a[k, k]
        for i in range(k + 1, n):
            a[i, k] *= inverse
            factor = a[i, k]
            for j in range(k + 1, n):
                a[i, j] -= factor * a[k, j]
    return True


@kernel
def solved(a, pivots, b):
    """``b`` (7,) in place by the factors of :func:`factored`."""
    n = 7
    for k in range(n):
        row = pivots[k]
        if row != k:
            b[k], b[row] = b[row], b[k]
    for k in range(n):
        for i in range(k + 1, n):
            b[i] -= a[i, k] * b[k]
    for k in range(n - 1, -1, -1):
        total = b[k]
        for j in range(k + 1, n):
            total -= a[k, j] * b[j]
        b[k] = total / a[k, k]


@kernel
def inverse_bound(a, pivots, inverse, power, squared):
    """``A^-1`` into ``inverse`` (7, 7) from the factors of :func:`factored` (all seven columns at once: the
    permuted identity through both triangles), and an upper bound of ``|A^-1|_2``: with ``B = A^-T A^-1``,
    ``|A^-1|_2^2 = lambda_max(B) <= |B^8|_F^(1/8)``, at most ``7^(1/16)`` times too large (the Frobenius norm of
    ``A^-1`` alone can be ``sqrt(7)`` times too large).  ``power`` and ``squared`` (7, 7) are scratch."""
    inverse[:] = 0.0
    for k in range(7):
        inverse[k, k] = 1.0
    for k in range(7):
        row = pivots[k]
        if row != k:
            for j in range(7):
                inverse[k, j], inverse[row, j] = inverse[row, j], inverse[k, j]
    for k in range(7):
        for i in range(k + 1, 7):
            factor = a[i, k]
            for j in range(7):
                inverse[i, j] -= factor * inverse[k, j]
    for k in range(6, -1, -1):
        for m in range(k + 1, 7):
            factor = a[k, m]
            for j in range(7):
                inverse[k, j] -= factor * inverse[m, j]
        for j in range(7):
            inverse[k, j] /= a[k, k]
    gram(inverse, power)
    for _ in range(3):  # B^2, B^4, B^8: B is symmetric, so B B = B^T B
        gram(power, squared)
        power, squared = squared, power
    total = 0.0
    for i in range(7):
        for j in range(7):
            total += power[i, j] * power[i, j]
    return sqrt(total) ** (1.0 / 16.0)


@kernel
def gram(a, out):
    """``a^T a`` (7, 7) into ``out`` (symmetric: each entry computed once)."""
    for i in range(7):
        for j in range(i + 1):
            total = 0.0
            for k in range(7):
                total += a[k, i] * a[k, j]
            out[i, j] = total
            out[j, i] = total


# ------------------------------------------------------------------ the equations [C1]
@kernel
def residual(q, target, real, scale, work):
    """``F(q)`` [C1] of the real chain ``real`` against ``target`` (4, 4) into ``work``'s ``f`` (6,), its Jacobian
    into ``system[:6]`` (7, 7), the signed axes ``w_i`` into ``axes`` (3, 7) and ``M`` into ``m`` (3, 3)
    (:func:`scratch`); returns ``|F|``."""
    trig, pose, origin, system, f, axes, m = work[0], work[1], work[2], work[3], work[4], work[11], work[12]
    links, ends, standard = real
    _chain_kernels.frames_one(q, links, ends, standard, trig, pose)
    _chain_kernels.jacobian_from_trig(links, ends, standard, np.int64(7), np.bool_(True), origin, trig, system)
    end = pose[0]
    for r in range(3):
        f[r] = scale * (end[r, 3] - target[r, 3])
        for c in range(3):
            m[r, c] = end[r, 0] * target[c, 0] + end[r, 1] * target[c, 1] + end[r, 2] * target[c, 2]
    f[3], f[4], f[5] = 0.5 * (m[2, 1] - m[1, 2]), 0.5 * (m[0, 2] - m[2, 0]), 0.5 * (m[1, 0] - m[0, 1])
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    for i in range(7):
        z0, z1, z2 = system[3, i], system[4, i], system[5, i]
        axes[0, i], axes[1, i], axes[2, i] = z0, z1, z2
        for r in range(3):
            system[r, i] *= scale
            system[3 + r, i] = 0.5 * (trace * axes[r, i] - m[r, 0] * z0 - m[r, 1] * z1 - m[r, 2] * z2)
    size = 0.0
    for r in range(6):
        size += f[r] * f[r]
    return sqrt(size)


@kernel
def curvature(work, inverse, tangent, turned):
    """``Omega`` [C3]: a bound of ``|A^-1 F''|`` (a bilinear map) at the point last passed to :func:`residual`
    (``F'`` copied to ``work``'s ``jacobian`` by :func:`described`), ``inverse`` (7, 7) being ``A^-1``: the spectral
    norm of the matrix of the norms ``|A^-1 [F''_ij; 0]|`` bounded by the smaller of its Frobenius norm and its
    largest row sum (module docstring's second derivatives).  Also ``F''[t, e_j]`` into column ``j`` of ``turned``
    (6, 7), ``t`` the ``tangent``."""
    jacobian, axes, m, norms, h, mw = work[10], work[11], work[12], work[15], work[18], work[19]
    turned[:] = 0.0
    for i in range(7):
        w0, w1, w2 = axes[0, i], axes[1, i], axes[2, i]
        mw[0] = m[0, 0] * w0 + m[0, 1] * w1 + m[0, 2] * w2
        mw[1] = m[1, 0] * w0 + m[1, 1] * w1 + m[1, 2] * w2
        mw[2] = m[2, 0] * w0 + m[2, 1] * w1 + m[2, 2] * w2
        for j in range(i + 1):
            v0, v1, v2 = axes[0, j], axes[1, j], axes[2, j]
            p0, p1, p2 = jacobian[0, i], jacobian[1, i], jacobian[2, i]  # c w_i x (p - o_i)
            h[0], h[1], h[2] = v1 * p2 - v2 * p1, v2 * p0 - v0 * p2, v0 * p1 - v1 * p0
            turn = v0 * (m[1, 2] - m[2, 1]) + v1 * (m[2, 0] - m[0, 2]) + v2 * (m[0, 1] - m[1, 0])  # tr([v]x M)
            h[3] = 0.5 * (turn * w0 - (v1 * mw[2] - v2 * mw[1]))
            h[4] = 0.5 * (turn * w1 - (v2 * mw[0] - v0 * mw[2]))
            h[5] = 0.5 * (turn * w2 - (v0 * mw[1] - v1 * mw[0]))
            if j < i:  # N(M) (w_j x w_i): N(M)'s rows are system[3:6]'s map of an axis
                c0, c1, c2 = v1 * w2 - v2 * w1, v2 * w0 - v0 * w2, v0 * w1 - v1 * w0
                trace = m[0, 0] + m[1, 1] + m[2, 2]
                h[3] += 0.5 * (trace * c0 - m[0, 0] * c0 - m[0, 1] * c1 - m[0, 2] * c2)
                h[4] += 0.5 * (trace * c1 - m[1, 0] * c0 - m[1, 1] * c1 - m[1, 2] * c2)
                h[5] += 0.5 * (trace * c2 - m[2, 0] * c0 - m[2, 1] * c1 - m[2, 2] * c2)
            for r in range(6):  # F''_ij = F''_ji
                turned[r, j] += tangent[i] * h[r]
                if j < i:
                    turned[r, i] += tangent[j] * h[r]
            total = 0.0
            for r in range(7):
                value = 0.0
                for k in range(6):
                    value += inverse[r, k] * h[k]
                total += value * value
            norms[i, j] = norms[j, i] = sqrt(total)
    squares, largest = 0.0, 0.0
    for i in range(7):
        row = 0.0
        for j in range(7):
            squares += norms[i, j] * norms[i, j]
            row += norms[i, j]
        largest = max(largest, row)
    return min(sqrt(squares), largest)


# ------------------------------------------------------------------ one point of the curve
@kernel
def scratch():
    """The scratch arrays of :func:`residual`, :func:`described` (with :func:`inverse_bound` and :func:`curvature`)
    and :func:`corrected`: ``F`` (6,), the system (7, 7) whose first six rows hold ``F'`` at the point last
    evaluated, the axes (3, 7) and ``M`` (3, 3) there, and the rest."""
    model_work = (np.empty((9, 4, 4)), np.empty((7, 2)), np.empty((3, 4)), np.empty(3), np.empty((3, 3)),
                  np.empty((3, 3)))
    return (np.empty((7, 2)), np.empty((1, 4, 4)), np.zeros(3), np.empty((7, 7)), np.empty(6), np.empty(7, np.int64),
            np.empty((7, 7)), np.empty(7), model_work, np.empty(3), np.empty((6, 7)), np.empty((3, 7)),
            np.empty((3, 3)), np.empty((7, 7)), np.empty((7, 7)), np.empty((7, 7)), np.empty((6, 7)), np.empty(6),
            np.empty(6), np.empty(3))


@kernel
def described(q, size, previous, model, work, tangent, gradient, state):
    """Everything a step from ``q`` (7,) needs, ``F`` and ``F'`` being in ``work`` (:func:`residual`, whose norm
    is ``size``): into ``tangent`` (7,) the unit null vector of ``F'`` with ``previous . tangent > 0``, into
    ``gradient`` (7,) ``d psi / dq``, and into ``state`` (:data:`STATE`,) ``|F|``,
    ``delta = |F' t|``, ``beta`` (bounds ``|A^-1|``, ``A = [F'; t^T]``), ``psi``, ``d psi / ds``, the wrist's distance
    ``w`` from joint 1's axis, ``|x_sw|``, ``Omega`` (:func:`curvature`) (module docstring), and from :data:`BEND` on
    the curve's second derivative ``kappa = -A^-1 [F''[t, t]; 0]`` [C2], ``|kappa|``, the residual ``|[F' kappa +
    F''[t, t]; t . kappa]|`` of its equations (rounding) and ``Omega_t`` [C3].  Returns ``False`` at a singular
    configuration."""
    system, pivots, inverse, model_work, u, jacobian = work[3], work[5], work[6], work[8], work[9], work[10]
    _array_copy.copy_rows_into(jacobian, system[:6])
    _array_copy.copy_into(system[6], previous)
    if not factored(system, pivots):
        return False
    tangent[:] = 0.0
    tangent[6] = 1.0
    solved(system, pivots, tangent)
    length = sqrt(np.sum(tangent * tangent))
    if not np.isfinite(length) or length == 0.0:
        return False
    tangent /= length
    delta = 0.0
    for r in range(6):
        value = 0.0
        for j in range(7):
            value += jacobian[r, j] * tangent[j]
        delta += value * value
    _array_copy.copy_rows_into(system[:6], jacobian)
    _array_copy.copy_into(system[6], tangent)
    if not factored(system, pivots):
        return False
    psi = arm_angle_one(q, model[0], model[1], model[2], model[3], model_work, gradient, np.bool_(True))
    shared = wrist_point(model_work[2], model[2], u)[0]
    state[SIZE], state[DELTA] = size, sqrt(delta)
    state[BETA] = inverse_bound(system, pivots, inverse, work[13], work[14])
    state[PSI], state[PSI_RATE] = psi, np.sum(gradient * tangent)
    state[OFF_AXIS], state[APART] = shared[0], sqrt(shared[0] * shared[0] + shared[3] * shared[3])
    turned, along = work[16], work[17]
    along[:] = 0.0
    state[OMEGA] = curvature(work, inverse, tangent, turned)
    squares = 0.0
    for r in range(7):  # Omega_t: the Frobenius norm of A^-1 [F''[t, .]; 0]
        for j in range(7):
            value = 0.0
            for k in range(6):
                value += inverse[r, k] * turned[k, j]
            squares += value * value
    state[TURNING] = sqrt(squares)
    for k in range(6):
        for j in range(7):
            along[k] += turned[k, j] * tangent[j]
    for r in range(7):
        value = 0.0
        for k in range(6):
            value -= inverse[r, k] * along[k]
        state[BEND + r] = value
    bend = state[BEND:BEND + 7]
    rounding = 0.0
    for k in range(6):
        value = along[k]
        for j in range(7):
            value += jacobian[k, j] * bend[j]
        rounding += value * value
    state[BEND_SIZE] = sqrt(np.sum(bend * bend))
    state[BEND_ROUNDING] = sqrt(rounding + np.sum(bend * tangent) ** 2)
    return bool(np.isfinite(state[BETA]) and np.isfinite(state[OMEGA]) and np.isfinite(state[BEND_SIZE])
                and np.isfinite(state[TURNING]))


@kernel
def corrected(q, anchor, direction, distance, target, real, bounds, work):
    """Newton's steps from ``q`` (7,) in place onto ``G_s(q) = 0`` (module docstring) for the hyperplane
    ``direction . (q - anchor) = distance``; returns whether ``|F|`` settled (:data:`FINE`, or :data:`SETTLED` where
    rounding stops Newton's steps halving it) and ``|F|`` there, ``F`` and ``F'`` at the settled ``q``
    being left in ``work``."""
    system, f, pivots, right = work[3], work[4], work[5], work[7]
    best = np.inf
    for _ in range(CORRECTOR_STEPS):
        size = residual(q, target, real, bounds[SCALE], work)
        if not np.isfinite(size):
            return False, size
        if size <= FINE or size >= 0.5 * best:
            return size <= SETTLED, size
        best = size
        _array_copy.copy_into(system[6], direction)
        if not factored(system, pivots):
            return False, size
        for r in range(6):
            right[r] = -f[r]
        along = 0.0
        for j in range(7):
            along += direction[j] * (q[j] - anchor[j])
        right[6] = distance - along
        solved(system, pivots, right)
        q += right
    size = residual(q, target, real, bounds[SCALE], work)
    return size <= SETTLED, size


# ------------------------------------------------------------------ the certificate of a step [C2]-[C5]
@kernel
def certified(state, tangent, bounds, reach, overlap):
    """The certificate of a step of length ``reach`` (``H``, the ``overlap`` past its end included) from a point
    with ``state`` (:func:`described`) along its ``tangent`` ``t`` [C2]-[C4], from the predictor ``y_s = x + s t + s^2
    kappa / 2``: the radius
    ``r*`` of the tube about ``y_s`` that holds the arc, or -1 where the theorem's conditions fail (the uniqueness
    radius must exceed ``r*`` by twice the overlap, so that the next step's start, within the overlap of this step's
    end, is this step's arc's point); the radius ``r* + H^2 |kappa| / 2`` of the tube about the tangent ``x + s t``
    that holds it; and the radii ``R(0)`` and ``R(H)`` of the narrower tube about ``y_s`` [C4] (:func:`tube_range`):
    the arc's point at ``s`` lies within ``R(s)`` of ``y_s``, ``R`` convex in ``s``."""
    size, delta, beta, local = state[SIZE], state[DELTA], state[BETA], state[OMEGA]
    bend, rounding = state[BEND_SIZE], state[BEND_ROUNDING]
    bow = 0.5 * bend * reach * reach  # |y_H - x - H t|
    span = reach + bow  # |y_s - x| at most
    along, across = third_along(bounds, tangent, state[BEND:BEND + 7], reach)
    for room in BALL_ROOM:  # the ball D about x: every y_s, and room about it for Kantorovich's balls
        ball = (1.0 + room) * span + REGION
        third = beta * bounds[THIRD]
        omega = local + third * ball
        # |A(x)^-1 (A(y_s) - A(x))| <= s Omega_t + s^2 |kappa| Omega / 2 + beta |F'''[d, d, .]| / 2 (Taylor,
        # d = y_s - x), and at most omega |y_s - x| (the Lipschitz bound): the step moves along the curve, where A
        # changes least
        shrink = 1.0 - min(omega * span, reach * state[TURNING] + local * bow + 0.5 * beta * across)
        if shrink <= 0.0:
            continue
        omega_s = omega / shrink
        alpha = (beta * (size + reach * (delta + 0.5 * reach * rounding))
                 + local * reach * bow * (1.0 + 0.25 * reach * bend) + beta * along / 6.0) / shrink
        h = omega_s * alpha
        if h > KANTOROVICH:
            continue
        root = sqrt(1.0 - 2.0 * h)
        radius = (1.0 - root) / omega_s
        if min((1.0 + root) / omega_s, room * span + REGION) <= radius + 2.0 * overlap:
            continue
        return radius, radius + bow, RADIUS_FACTOR * beta * size / shrink, RADIUS_FACTOR * alpha
    return -1.0, -1.0, -1.0, -1.0


@kernel
def third_along(bounds, tangent, bend, reach):
    """Bounds [C2] of ``|F'''(z)[d, d, d]|`` and of ``|F'''(z)[d, d, .]|`` (a linear map), at every ``z``, for the
    steps ``d = s t + s^2 kappa / 2`` of the predictor up to ``s = reach`` (``t`` the ``tangent``, ``kappa`` the
    ``bend``): from the bounds of the entries along joints ``i, j, m`` (``c rho_max(i, j, m)`` in the position rows,
    1 in the rotation rows: the module docstring) summed with ``a_i a_j a_m`` (and ``a_i a_j |v_m|``), ``a_i = reach
    |t_i| + reach^2 |kappa_i| / 2 >= |d_i|``.  With ``A_k = a_1 + ... + a_k``, the triples whose last joint is
    ``k`` weigh ``A_k^3 - A_(k-1)^3`` (so the position rows' sum is ``sum_k c rho_k (A_k^3 - A_(k-1)^3)``, the
    rotation rows' ``A_7^3``), and the map's column ``m`` is ``c rho_m A_m^2 + sum_(k > m) c rho_k (A_k^2 -
    A_(k-1)^2)`` in the position rows, ``A_7^2`` in the rotation rows.  Along one direction these are several times
    smaller than ``K |d|^3`` and ``K |d|^2``, ``K`` the Frobenius norm over all 343 entries."""
    curving = 0.5 * reach * reach
    total, cube = 0.0, 0.0
    for k in range(7):
        below = total
        total += reach * abs(tangent[k]) + curving * abs(bend[k])
        cube += bounds[REACHES + k] * (total * total * total - below * below * below)
    along = sqrt(cube * cube + total ** 6)
    squares, later, upto = 0.0, 0.0, total
    for m in range(6, -1, -1):
        column = bounds[REACHES + m] * upto * upto + later
        squares += column * column
        below = upto - (reach * abs(tangent[m]) + curving * abs(bend[m]))
        later += bounds[REACHES + m] * (upto * upto - below * below)
        upto = below
    return along, sqrt(squares + 7.0 * total ** 4)


@kernel
def tube_range(a, d, e, radius, near, far):
    """The interval [C4] holding a joint (or an affine function of one) over a step's arc, its predictor running
    from ``a`` through ``a + sigma d + sigma^2 e`` (``sigma = s / H`` in [0, 1]): within ``radius`` (``r*``) of the
    predictor's point, and within ``R(s)`` of it, ``R`` convex from ``near`` (``R(0)``) to ``far`` (``R(H)``), so at
    most the line between them."""
    low, high = _quadratic_range(a, d, e)
    above = _quadratic_range(a + near, d + far - near, e)[1]
    below = _quadratic_range(a - near, d - far + near, e)[0]
    return max(low - radius, below), min(high + radius, above)


@kernel
def _quadratic_range(a, b, c):
    """The least and the largest value of ``a + b x + c x^2`` for ``x`` in [0, 1]."""
    end = a + b + c
    low, high = min(a, end), max(a, end)
    if c != 0.0:
        vertex = -0.5 * b / c
        if 0.0 < vertex < 1.0:
            value = a + 0.5 * b * vertex
            low, high = min(low, value), max(high, value)
    return low, high


@kernel
def arm_angle_spread(state, bounds, direction, bend, reach, radius):
    """A bound [C5] of how far the arm angle gets from its value at a step's start over the step's arc: ``sum_j G_j
    e_j`` over joints 2-4, ``e_j`` how far joint ``j`` gets from the start within the tube (the range of the
    predictor ``s t_j + s^2 kappa_j / 2`` over the step of length ``reach``, ``t`` the ``direction`` and ``kappa``
    the ``bend``, widened by ``radius``), and ``G_j`` bounding ``|d psi / d q_j|`` there from the wrist's distances
    to joint 1's axis and to the shoulder, each less at most ``sum_j L_j e_j`` than at the start (``L_j`` joint
    ``j``'s lever arm to the wrist).  Joint 1 moves neither the arm angle (turning the whole arm about joint 1's
    axis turns the reference plane with it) nor those distances; joints 5-7 do not move the wrist.  Infinite where
    the wrist may come to the axis (where the arm angle is not continuous) or to the shoulder."""
    curving = 0.5 * reach * reach
    second = _extent(reach * direction[1], curving * bend[1]) + radius
    third = _extent(reach * direction[2], curving * bend[2]) + radius
    fourth = _extent(reach * direction[3], curving * bend[3]) + radius
    moved = bounds[LEVER + 1] * second + bounds[LEVER + 2] * third + bounds[LEVER + 3] * fourth
    off_axis, apart = state[OFF_AXIS] - moved, state[APART] - moved
    if off_axis <= AXIS_TOLERANCE * 10.0 or apart <= 0.0:
        return np.inf
    turning = 1.0 / off_axis + 1.0 / apart
    return ((1.0 + bounds[LEVER + 1] * turning) * second + (1.0 + bounds[LEVER + 2] * turning) * third
            + (1.0 + bounds[LEVER + 3] * turning + bounds[FOREARM] / apart) * fourth)


@kernel
def _extent(b, c):
    """The largest ``|b x + c x^2|`` for ``x`` in [0, 1]."""
    low, high = _quadratic_range(0.0, b, c)
    return max(-low, high)


@kernel
def classified(start, direction, bend, reach, radius, near, far, model, real_phase, limits, signs):
    """The branch signs [C4] (+1, -1, or 0 where the tube crosses a boundary) into ``signs`` (3,), and the state of
    the limited joints (:data:`INSIDE`, :data:`OUTSIDE` or :data:`UNDECIDED`; ``limits`` as
    :attr:`redkin.srs.nearly.NearlySRS.kernel_limits`, modulo whole turns), over the tube of the step from ``start``
    along ``direction``, bending by ``bend`` (``kappa``), for ``reach`` (:func:`tube_range` with ``radius``, ``near``
    and ``far``).  Also the arc
    length along the chord [rad] at which it first meets a boundary the tube crosses (0 where its start is within
    ``near`` of it, ``inf`` where none), and the rate [rad / rad] at which the chord approaches that boundary: what
    :func:`traced` needs to choose a step that ends short of it."""
    neighbour = model[0]
    meets, rate = np.inf, 0.0
    for k in range(3):
        j = 2 * k + 1
        sign, offset = neighbour[j, _chain_kernels.SIGN], neighbour[j, _chain_kernels.OFFSET]
        centre = real_phase if j == 3 else 0.0
        a = offset + sign * start[j] - centre
        d = sign * reach * direction[j]
        low, high = tube_range(a, d, 0.5 * sign * reach * reach * bend[j], radius, near, far)
        turn = floor(low / pi)
        if high >= (turn + 1.0) * pi:
            signs[k] = 0
            below = pi * floor(a / pi)
            length = _meeting(a, d, reach, below, below + pi, near)
            if length < meets:
                meets, rate = length, abs(d) / reach
        else:
            signs[k] = 1 if turn % 2.0 == 0.0 else -1
    state = INSIDE
    for j in range(7):
        if limits[2, j] > 0.5:  # covers the circle
            continue
        lower, width = limits[0, j], limits[1, j]
        a, d = start[j], reach * direction[j]
        low, high = tube_range(a, d, 0.5 * reach * reach * bend[j], radius, near, far)
        base = lower + TWO_PI * floor((low - lower) / TWO_PI)  # the turn of the range at or below low
        if low - base <= width:
            if high <= base + width:
                continue
        elif high < base + TWO_PI:
            return OUTSIDE, meets, rate
        state = UNDECIDED
        length = _limit_meeting(a, d, reach, lower, width, near)
        if length < meets:
            meets, rate = length, abs(d) / reach
    return state, meets, rate


@kernel
def _limit_meeting(a, d, reach, lower, width, near):
    """:func:`_meeting` for a joint at ``a`` and its range from ``lower`` over ``width``, modulo whole turns: between
    the range's ends about ``a`` (inside the range or outside it)."""
    base = lower + TWO_PI * floor((a - lower) / TWO_PI)
    if a - base <= width:
        return _meeting(a, d, reach, base, base + width, near)
    return _meeting(a, d, reach, base + width, base + TWO_PI, near)


@kernel
def _meeting(a, d, reach, low, high, near):
    """Where the chord from ``a`` (changing by ``d`` over ``reach``) first leaves ``(low, high)``, as arc length
    [rad]; 0 where its start is within ``near`` of either end (at the boundary already), ``inf`` where it stays."""
    if a - low <= near or high - a <= near:
        return 0.0
    if d > 0.0:
        return reach * (high - a) / d
    if d < 0.0:
        return reach * (a - low) / -d
    return np.inf


# ------------------------------------------------------------------ the curve
@kernel
def _shorter(h, reach, radius, spread, meets, rate):
    """The next, shorter step to try after a step of ``h`` (its ``reach``, tube ``radius`` and arm-angle bound
    ``spread``) was not decided, the chord meeting a boundary the tube crosses at arc length ``meets`` while
    approaching it at ``rate`` (:func:`classified`).  Only the length is chosen here; the step is certified and
    classified again.

    * at the boundary (within the resolution's arm angle of it), or at a fold (``meets`` infinite), the step must
      be narrow: one whose arm-angle bound is within :data:`RESOLUTION` where the boundary is that near, half
      otherwise (a fold's place is not predicted);
    * short of it, the step that ends there with its tube's radius (about ``radius (h / reach)^2``) to spare: the
      next start is then closer by the square of the distance (Newton-like), where halving gains a factor of 2.
    """
    per_length = spread / (reach + radius)  # the arm angle's bound per arc length
    if meets * per_length <= 0.5 * RESOLUTION:
        return min(0.5 * h, 0.45 * RESOLUTION / per_length)
    if not meets < np.inf or rate <= 0.0:
        return 0.5 * h
    curving = radius / (reach * reach)
    room = 0.9 * meets * rate
    predicted = 2.0 * room / (rate + sqrt(rate * rate + 4.0 * curving * room))
    return predicted if predicted < 0.95 * h else 0.5 * h


@kernel
def started(seed, target, real, model, bounds, work, q, tangent, gradient, state):
    """The curve's point nearest the solution ``seed`` (7,) into ``q`` (7,): Newton's steps on the hyperplane
    through ``seed`` normal to the tangent there; returns whether it settled, with the point's tangent and state
    (:func:`described`)."""
    _array_copy.copy_into(q, seed)
    trial = np.zeros(7)
    size = residual(q, target, real, bounds[SCALE], work)
    found = False
    for k in range(7):  # a first sense for the tangent: any unit vector not nearly in F''s row space
        trial[:] = 0.0
        trial[k] = 1.0
        if described(q, size, trial, model, work, tangent, gradient, state):
            found = True
            break
    if not found:
        return False
    settled, size = corrected(q, seed, tangent, 0.0, target, real, bounds, work)
    _array_copy.copy_into(trial, tangent)
    return settled and described(q, size, trial, model, work, tangent, gradient, state)


@kernel
def longest_step(state, tangent, bounds, longest, guess):
    """The longest step [rad] up to ``longest`` that :func:`certified` and :data:`ARM_ANGLE_STEP` admit from a point
    with ``state`` along ``tangent``, to 6 %: from the longer of ``guess`` (the last point's: the length changes
    slowly along the curve) and twice the length at which ``omega H`` is 0.48 (where a straight predictor's ``h_K``
    would be 0.45 for a negligible ``|F|``), shortened until both hold (both only tighten as ``H``
    grows), or lengthened while they still do (the curve's own bend and ``Omega_t`` may allow several times more),
    then bisected once between the last length that holds and the first that does not."""
    k = state[BETA] * bounds[THIRD]  # omega(h) = Omega + beta K (2 h + REGION) and omega h = 0.48
    linear = state[OMEGA] + k * REGION
    h = min(longest, max(guess, 4.0 * 0.48 / (linear + sqrt(linear * linear + 8.0 * k * 0.48))))
    first = h
    while not _admitted(state, tangent, bounds, h):
        h *= 0.8
        if h < SINGULAR_STEP:  # the caller stops here
            return 0.0
    too_long = h / 0.8
    if h == first:
        for _ in range(12):
            too_long = min(1.25 * h, longest)
            if too_long <= h:
                return h
            if not _admitted(state, tangent, bounds, too_long):
                break
            h = too_long
    middle = 0.5 * (h + too_long)  # to within 6 %: a finer search costs more than the longer steps save
    return middle if _admitted(state, tangent, bounds, middle) else h


@kernel
def _admitted(state, tangent, bounds, h):
    """Whether a step of ``h`` (and :data:`OVERLAP`) from a point with ``state`` along ``tangent`` is certified with
    an arm-angle bound of at most :data:`ARM_ANGLE_STEP`."""
    radius, tube = certified(state, tangent, bounds, h + OVERLAP, OVERLAP)[:2]
    return tube >= 0.0 and arm_angle_spread(state, bounds, tangent, state[BEND:BEND + 7], h + OVERLAP,
                                            radius) <= ARM_ANGLE_STEP


@kernel
def traced(seed, target, real, model, bounds, real_phase, limits, longest, sense, most, points, tangents, angles,
           rates, signs, inside, spreads, tubes):
    """Follow the self-motion of ``target`` (4, 4) on the real chain from the solution ``seed`` (7,) with certified
    steps (module docstring) of at most ``longest`` [rad of arc length], the arm angle first increasing (``sense``
    +1) or decreasing (-1).

    Writes up to ``most`` points (continuous joint values, not wrapped) into ``points`` (most, 7), their unit
    tangents into ``tangents``, arm angles into ``angles`` and ``d psi / ds`` into ``rates``; for the step from
    point ``k`` to ``k + 1``, its branch signs into ``signs[k]`` (3,) and its limited joints' state into
    ``inside[k]`` (:func:`classified`), the bound of its arm-angle change into ``spreads[k]`` and its tube into
    ``tubes[k]`` (2,): the length ``H`` it is certified for (its overlap included) and the radius ``r*`` (every point
    of its arc lies within ``r*`` of ``points[k] + s tangents[k]`` for some ``s`` in ``[0, H]``).  Where the curve
    closes, its last point is its first (modulo whole turns).  Returns the number of points and :data:`CLOSED`,
    :data:`FULL` or :data:`STUCK` (where a step cannot be certified, or the certificate allows no step longer than
    :data:`SINGULAR_STEP`).
    """
    work = scratch()
    q, tangent, gradient, state = np.empty(7), np.empty(7), np.empty(7), np.empty(STATE)
    if not started(seed, target, real, model, bounds, work, q, tangent, gradient, state):
        return 0, STUCK
    if state[PSI_RATE] * sense < 0.0:
        tangent = -tangent
        state[PSI_RATE] = -state[PSI_RATE]
    first = state[BETA] * state[SIZE]  # beta |F| at the first point
    apart = np.inf
    moved, following, following_gradient, following_state = np.empty(7), np.empty(7), np.empty(7), np.empty(STATE)
    step_signs = np.empty(3, np.int64)
    gap = np.empty(7)
    count = 0
    h = longest
    allowed = 0.0
    event = False
    while True:
        _array_copy.copy_into(points[count], q)
        _array_copy.copy_into(tangents[count], tangent)
        angles[count] = state[PSI]
        rates[count] = state[PSI_RATE]
        count += 1
        if count == most:
            return count, FULL
        allowed = longest_step(state, tangent, bounds, longest, allowed)
        if allowed < SINGULAR_STEP:
            return count, STUCK
        h = allowed if event else min(2.0 * h, allowed)  # past a boundary the tube [C4] clears it at once
        closing = False
        if count > 2:  # within a step of the first point, heading on: the last step is the one onto it
            for j in range(7):
                gap[j] = turns_removed(points[0, j] - q[j] + pi) - pi
            along = np.sum(gap * tangent)
            across = sqrt(max(np.sum(gap * gap) - along * along, 0.0))
            if 0.0 < along <= h and across <= 0.1 * along and np.sum(tangents[0] * tangent) > 0.0:
                h, closing = along, True
        while True:
            if h < SMALLEST_STEP:
                return count, STUCK
            for j in range(7):
                moved[j] = q[j] + h * (tangent[j] + 0.5 * h * state[BEND + j])
            settled, size = corrected(moved, q, tangent, h, target, real, bounds, work)
            if not settled or not described(moved, size, tangent, model, work, following,
                                            following_gradient, following_state):
                h *= 0.5
                closing = False
                continue
            overlap = max(OVERLAP, 2.02 * following_state[BETA] * following_state[SIZE] + 1e-14)
            if closing:  # the first point's own curve point, and the distance to it, within the overlap too
                apart = 0.0
                for j in range(7):
                    apart += (turns_removed(moved[j] - points[0, j] + pi) - pi) ** 2
                overlap = max(overlap, 2.02 * first + sqrt(apart) + 1e-14)
            reach = h + overlap
            radius, tube, near, far = certified(state, tangent, bounds, reach, overlap)
            spread = arm_angle_spread(state, bounds, tangent, state[BEND:BEND + 7], reach, radius)
            off = 0.0
            for j in range(7):
                off += (moved[j] - q[j] - h * (tangent[j] + 0.5 * h * state[BEND + j])) ** 2
            if radius < 0.0 or not spread <= ARM_ANGLE_STEP or sqrt(off) > radius + overlap:
                h *= 0.5
                closing = False
                continue
            state_of_limits, meets, rate = classified(q, tangent, state[BEND:BEND + 7], reach, radius, near, far, model,
                                                      real_phase, limits, step_signs)
            undecided = (step_signs[0] == 0 or step_signs[1] == 0 or step_signs[2] == 0 or state_of_limits == UNDECIDED
                         or state[PSI_RATE] * following_state[PSI_RATE] < 0.0)
            if undecided and spread > RESOLUTION and h > 4.0 * overlap:
                h = _shorter(h, reach, tube, spread, meets, rate)
                closing = False
                continue
            break
        event = undecided
        _array_copy.copy_into(signs[count - 1], step_signs)
        inside[count - 1] = state_of_limits
        spreads[count - 1] = spread
        tubes[count - 1, 0], tubes[count - 1, 1] = reach, tube
        if closing and apart <= 1e-18:  # landed on the first point (to 1e-9 rad)
            _array_copy.copy_into(points[count], moved)
            _array_copy.copy_into(tangents[count], following)
            angles[count] = following_state[PSI]
            rates[count] = following_state[PSI_RATE]
            return count + 1, CLOSED
        _array_copy.copy_into(q, moved)
        _array_copy.copy_into(tangent, following)
        _array_copy.copy_into(gradient, following_gradient)
        _array_copy.copy_into(state, following_state)
