"""The compiled core of the virtual arms (paper 004): end points of the analytic model and the rate function.

* :func:`virtual_points` -- [004 eq. 1] for the analytic model: positions ``X^k``
  and Jacobians of the virtual end points, from the chain kernels of
  :mod:`redkin._chain_kernels` (one pass of the frames, one Jacobian of a
  point per end point);
* :func:`inputs` -- ``u``, ``theta = G(u)`` and ``G'(u)`` [004 eqs. 13, 25] at the integrated states;
* :func:`rates` -- the subsystems' signals [004 eqs. 12, 17] and [004 eqs. 9-11, 14]
  from any forward model's positions and Jacobians.

The integrator evaluates the rate function on a few states at a time (its
finite-difference Jacobian: one state per free joint and ``log lambda``), so
:func:`inputs` and :func:`rates` loop over them serially; :func:`virtual_points`
also serves large batches (a learned model's training data): it computes
items ``start .. stop - 1``, the chunks :func:`~redkin._compiled.run_batch`
hands out.  Inputs
are trusted: C-contiguous arrays of the documented shapes.
"""

from __future__ import annotations

from math import cos, exp, inf, sin, sqrt

import numpy as np

from redkin import _chain_kernels
from redkin._compiled import kernel

#: Columns of :func:`rates`' ``scalars``.
LAMBDA, LAMBDA_RATE, GAIN, ENERGY, FREE_GRADIENT = range(5)


# ------------------------------------------------------------ analytic model
@kernel
def virtual_points_one(theta, links, ends, standard, frames, local, axes, trig, poses, jac, positions, jacobians):
    """Positions ``X^k`` (p, l) and Jacobians (p, l, m) of the end points at one joint vector ``theta`` [004 eq. 1].

    End point ``k`` is ``local[k]`` (3,) in frame ``frames[k]`` (``0 .. n + 1``,
    ``n + 1`` the tool frame); ``axes`` (l,) picks the task-space rows.
    ``trig`` (n, 2), ``poses`` (n + 2, 4, 4) and ``jac`` (6, n) are scratch.
    """
    n = links.shape[0]
    _chain_kernels.frames_one(theta, links, ends, standard, trig, poses)
    for k in range(frames.shape[0]):
        pose = poses[frames[k]]
        for c in range(axes.shape[0]):
            r = axes[c]
            positions[k, c] = pose[r, 3] + (pose[r, 0] * local[k, 0] + pose[r, 1] * local[k, 1]
                                            + pose[r, 2] * local[k, 2])
        _chain_kernels.jacobian_from_trig(links, ends, standard, min(frames[k], n), frames[k] > n, local[k], trig, jac)
        for c in range(axes.shape[0]):
            for j in range(n):
                jacobians[k, c, j] = jac[axes[c], j]


@kernel
def virtual_points(start, stop, theta, links, ends, standard, frames, local, axes, positions, jacobians):
    """:func:`virtual_points_one` for rows ``start .. stop - 1`` of ``theta`` (N, n); ``positions`` (N, p, l),
    ``jacobians`` (N, p, l, n)."""
    n = links.shape[0]
    trig, poses, jac = np.empty((n, 2)), np.empty((n + 2, 4, 4)), np.empty((6, n))
    for b in range(start, stop):
        virtual_points_one(theta[b], links, ends, standard, frames, local, axes, trig, poses, jac,
                           positions[b], jacobians[b])


# ------------------------------------------------------------- rate function
@kernel
def inputs(y, u0, free, half, lower, limited, theta0, u, theta, slope):
    """For each state ``y`` (N, f + 1) = ``[u_free, log lambda]``: ``u`` (N, m), ``theta = G(u)`` and ``G'(u)`` (N, m).

    Clamped joints keep ``u0`` and ``theta0`` exactly [004 eq. 27]; a limited
    joint follows [004 eq. 25], ``theta = h sin(u) + h + theta_min`` with ``h``
    half its range; the others ``theta = u`` [004 eq. 13].
    """
    for b in range(y.shape[0]):
        k = 0
        for j in range(u0.shape[0]):
            if free[j]:
                u[b, j] = y[b, k]
                k += 1
            else:
                u[b, j] = u0[j]
            if limited[j]:
                theta[b, j] = half[j] * sin(u[b, j]) + half[j] + lower[j]
                slope[b, j] = half[j] * cos(u[b, j])
            else:
                theta[b, j] = u[b, j]
                slope[b, j] = 1.0
            if not free[j]:
                theta[b, j] = theta0[j]


@kernel
def rates(y, theta, slope, positions, jacobians, goals, weights, active, theta0, free, eta, gain_constant,
          lambda_constant, a_max, delta, error, du, scalars):
    """[004 eqs. 9-12, 14, 17] for each state ``y`` (N, f + 1) from the model's ``positions`` (N, p, l) and
    ``jacobians`` (N, p, l, m).

    Writes ``delta^k`` (N, p, m) and ``E^k`` (N, p) of every subsystem (zero
    for dropped ones), ``du/ds`` (N, f) on the free joints, and per state
    ``lambda, dlambda/ds, A, V, |G' delta|`` into ``scalars`` (N, 5).  With
    ``delta = sum_k delta^k`` and ``g = lambda delta + (theta(0) - theta)``
    over the free joints: ``A = N / (|G' g|^2 + N / a_max)`` with ``N = 1/2
    |lambda delta|^2 + c_A |delta| |theta(0) - theta|`` ([004 eq. 10], bounded;
    ``a_max = inf``: as printed, infinite where ``G' g = 0``).
    """
    p, dims = goals.shape
    m = theta0.shape[0]
    for b in range(y.shape[0]):
        lam = exp(y[b, y.shape[1] - 1])
        total_error = 0.0
        for k in range(p):
            for j in range(m):
                delta[b, k, j] = 0.0
            error[b, k] = 0.0
            if not active[k]:  # a dropped subsystem sends nothing
                continue
            for c in range(dims):
                residual = goals[k, c] - positions[b, k, c]
                weighted = weights[k, c] * residual
                error[b, k] += residual * weighted
                for j in range(m):
                    delta[b, k, j] += jacobians[b, k, c, j] * weighted  # [004 eq. 17]
            error[b, k] *= 0.5  # [004 eq. 12]
            total_error += error[b, k]
        delta_square = moved_square = slope_g_square = gradient_square = 0.0
        f = 0
        for j in range(m):
            if not free[j]:
                continue
            total = 0.0
            for k in range(p):
                total += delta[b, k, j]
            displacement = theta0[j] - theta[b, j]
            du[b, f] = slope[b, j] * (lam * total + displacement)  # G' g, scaled below
            f += 1
            delta_square += total * total
            moved_square += displacement * displacement
            slope_g_square += du[b, f - 1] ** 2
            gradient_square += (slope[b, j] * total) ** 2
        delta_norm, moved = sqrt(delta_square), sqrt(moved_square)
        numerator = 0.5 * lam**2 * delta_norm**2 + gain_constant * delta_norm * moved  # [004 eq. 10]
        denominator = slope_g_square + numerator / a_max
        gain = 0.0 if numerator == 0.0 else (numerator / denominator if denominator > 0.0 else inf)
        for f in range(du.shape[1]):
            du[b, f] *= eta * gain  # [004 eq. 9]
        scalars[b, LAMBDA] = lam
        scalars[b, LAMBDA_RATE] = (eta * lambda_constant * delta_norm * moved / total_error
                                   if total_error > 0.0 else 0.0)  # [004 eq. 11]
        scalars[b, GAIN] = gain
        scalars[b, ENERGY] = lam * total_error + 0.5 * moved**2  # [004 eq. 14] with equal copies
        scalars[b, FREE_GRADIENT] = sqrt(gradient_square)
