"""Tracking simulation: integrate a velocity-IK method along a commanded twist (paper 003 section 4).

Fixed-step classical Runge-Kutta (RK4) on the joint angles.  The commanded
twist is constant or a function ``twist(t, q)``.  With ``gain > 0`` a
reference pose is integrated from the command alongside, and the method is
fed ``v + gain * e`` (closed-loop correction, ``e`` = position error and the
small-angle orientation error of the reference relative to the actual end
pose).  The reference follows the *command*, not the SC method's deliberate
slow-down inside the singular region, so keep ``gain = 0`` (open loop, as in
the paper) for runs through a singularity.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_nonnegative, check_positive, check_vectors
from redkin.chain import SerialChain
from redkin.errors import RedkinError, SizeLimitError
from redkin.so3 import skew
from redkin.velocity.methods import Method

_TwistCommand = Callable[[float, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class TrackingResult:
    """Time series of a tracking run, sampled at ``time`` (``N + 1`` grid points).

    Attributes
    ----------
    time : (N + 1,)
    q, joint_velocity : (N + 1, n)
        Joint angles and the method's joint velocity at each grid point.
    commanded, target, realised : (N + 1, 6)
        Twist fed to the method, twist it promises (``J q_dot`` by
        construction; [003 eq. 22] for SC) and twist ``J q_dot`` realised.
    index : (N + 1,) or None
        Singularity index ``D_e`` if an index function was given.
    position : (N + 1, 3)
        End-point path.
    rotation : (N + 1, 3, 3)
    """

    time: np.ndarray
    q: np.ndarray
    joint_velocity: np.ndarray
    commanded: np.ndarray
    target: np.ndarray
    realised: np.ndarray
    index: np.ndarray | None
    position: np.ndarray
    rotation: np.ndarray


#: Largest number of RK4 steps of one run (every step is recorded: about 1 KB each for a 7-joint arm).
MAX_STEPS = 2_000_000


def simulate(
    chain: SerialChain,
    q0: ArrayLike,
    twist: ArrayLike | _TwistCommand,
    duration: float,
    method: Method,
    dt: float = 1e-3,
    gain: float = 0.0,
    index: Callable[[np.ndarray], np.ndarray] | None = None,
) -> TrackingResult:
    """Integrate ``q_dot = method(q, J(q), v)`` with fixed-step RK4 from ``q0`` for ``duration`` seconds.

    Parameters
    ----------
    chain : SerialChain
    q0 : array_like, shape (n,)
    twist : array_like, shape (6,), or callable ``twist(t, q) -> (6,)``
        Commanded end-point twist (linear m/s, angular rad/s, world frame).
    duration : float
        Simulated time in seconds (> 0); the step count is ``round(duration / dt)``,
        at most :data:`MAX_STEPS`.
    method : Method
        E.g. :class:`~redkin.velocity.methods.SingularityConsistent`.
    dt : float
        RK4 step (> 0, at most ``duration``).
    gain : float
        Closed-loop correction gain in 1/s (>= 0).
    index : callable, optional
        ``D_e(q)`` to record (e.g. ``WamFactorisation.index``).
    """
    q_start = check_vectors(q0, chain.n, "q0").reshape(chain.n)
    total = check_positive(duration, "duration")
    step_size = check_positive(dt, "dt")
    if step_size > total:
        raise RedkinError(f"dt must be at most duration ({total:g} s), got {step_size:g}")
    k_gain = check_nonnegative(gain, "gain")
    ratio = total / step_size  # inf for duration 1e308 and dt 1e-3: compared before it becomes a count
    if not ratio <= MAX_STEPS + 0.5:
        raise SizeLimitError(f"duration / dt gives {ratio:.3g} RK4 steps; at most {MAX_STEPS} are allowed "
                             "(the run is kept in memory)", name="duration / dt", value=ratio, maximum=MAX_STEPS)
    steps = max(1, int(round(ratio)))
    if callable(twist):
        command = twist
    else:
        fixed = check_vectors(twist, 6, "twist").reshape(6)
        command = lambda t, q: fixed  # noqa: E731
    solve = method.bind(chain, q_start)
    pose0 = chain.fk(q_start)
    # State: q, then (closed loop only) reference position and rotation.
    y = np.concatenate([q_start, pose0[:3, 3], pose0[:3, :3].ravel()]) if k_gain else q_start.copy()
    n = chain.n

    def evaluate(t: float, state: np.ndarray):
        q = state[:n]
        jac = chain.jacobian(q)
        v = np.asarray(command(t, q), dtype=float)
        fed = v
        if k_gain:
            pose = chain.fk(q)
            p_ref, r_ref = state[n : n + 3], state[n + 3 :].reshape(3, 3)
            r_err = r_ref @ pose[:3, :3].T
            e_rot = 0.5 * np.array([r_err[2, 1] - r_err[1, 2], r_err[0, 2] - r_err[2, 0], r_err[1, 0] - r_err[0, 1]])
            fed = v + k_gain * np.concatenate([p_ref - pose[:3, 3], e_rot])
        solution = solve(q, jac, fed)
        derivative = solution.joint_velocity
        if k_gain:
            derivative = np.concatenate([derivative, v[:3], (skew(v[3:]) @ r_ref).ravel()])
        return derivative, jac, fed, solution

    records = []
    for k in range(steps + 1):
        t = k * step_size
        k1, jac, fed, solution = evaluate(t, y)
        records.append((y[:n].copy(), solution.joint_velocity, fed, solution.target_twist,
                        jac @ solution.joint_velocity))
        if k == steps:
            break
        k2 = evaluate(t + 0.5 * step_size, y + 0.5 * step_size * k1)[0]
        k3 = evaluate(t + 0.5 * step_size, y + 0.5 * step_size * k2)[0]
        k4 = evaluate(t + step_size, y + step_size * k3)[0]
        y = y + (step_size / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    q_path, qdot, fed, target, realised = (np.array(column) for column in zip(*records))
    poses = chain.fk(q_path)
    return TrackingResult(
        time=np.arange(steps + 1) * step_size,
        q=q_path,
        joint_velocity=qdot,
        commanded=fed,
        target=target,
        realised=realised,
        index=None if index is None else np.asarray(index(q_path), dtype=float),
        position=poses[:, :3, 3],
        rotation=poses[:, :3, :3],
    )
