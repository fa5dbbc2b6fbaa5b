"""Obstacle avoidance by local goal planning in every subsystem (paper 004 section 4, Fig. 8).

The paper says only that each subsystem plans its own goal from local
information around its virtual end point -- the real end point combines the
direction to the goal with repulsion from nearby obstacles, the other virtual
end points are repelled -- and defers the details to its ref. 11, which is not
available.  The planning law below is therefore ours.

Once per *period*, with ``X^k`` the current virtual end points:

* the real end point's goal is ``X^e + d + r(X^e)``: ``d`` points to the final
  goal with length ``min(step, distance)``; within ``influence`` of an
  obstacle the part of ``d`` heading into it is removed (the point slides
  round the obstacle instead of stopping in front of it);
* every other virtual end point's goal is ``X^k + r(X^k)`` with weight
  ``virtual_weight``, or weight 0 (no goal) when no obstacle is within
  ``influence``;
* the repulsion ``r(X) = sum_o gain (1 - c_o(X) / influence) n_o(X)`` over the
  obstacles with clearance ``c_o < influence`` (``n_o`` the outward normal).

The network then runs the trajectory-generation dynamics ([004 eqs. 9-13], via
:func:`~redkin.virtual_arms.generate.generate_trajectory`) from the current
posture towards these goals for at most ``period_steps`` integrator steps.
A guard checks the recorded path of the period, densified to at most
``max_joint_step`` of joint motion between checks, against the whole arm's
skeleton (every link segment): the period's path is kept up to its last record
whose interval stays ``margin`` away from every obstacle, so the kept path has
clearance of at least ``margin`` everywhere by construction.  When the end
point is within ``step`` of the goal (or there are no obstacles) the end point
alone is sent to the final goal and the dynamics run to equilibrium; if that
path is clear the run ends there, which makes a run without obstacles the
plain :func:`generate_trajectory` run.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._constants import VIRTUAL_ARMS_MAX_STEPS as MAX_STEPS  # largest step budget of one run
from redkin._validation import MAX_LENGTH, check_magnitude, check_positive, check_vectors
from redkin.chain import SerialChain
from redkin.errors import RedkinError, SizeLimitError
from redkin.virtual_arms.analytic import AnalyticModel
from redkin.virtual_arms.clearance import Obstacle, arm_clearance, as_obstacles, densify
from redkin.virtual_arms.generate import generate_trajectory
from redkin.virtual_arms.output_function import OutputFunction
from redkin.virtual_arms.points import VirtualPoint


def monitored_points(chain: SerialChain, per_link: int = 3) -> list[VirtualPoint]:
    """Virtual end points that watch for obstacles: joint origins 2..n and ``per_link`` points inside every link."""
    if int(per_link) != per_link or per_link < 0:
        raise RedkinError(f"per_link must be a non-negative integer, got {per_link!r}")
    points = [VirtualPoint.joint(j) for j in range(2, chain.n + 1)]
    fractions = np.arange(1, per_link + 1) / (per_link + 1)
    points += [VirtualPoint.on_link(j, float(t)) for j in range(1, chain.n + 1) for t in fractions]
    return points


def repulsion(points: np.ndarray, obstacles: Sequence[Obstacle], influence: float, gain: float) -> np.ndarray:
    """Repulsion ``r(X)`` of ``points`` (p, l): ``gain (1 - c / influence)`` along the outward normal, per
    obstacle nearer than ``influence``."""
    push = np.zeros_like(points)
    for obstacle in obstacles:
        away = points - obstacle.centre
        distance = np.maximum(np.linalg.norm(away, axis=-1, keepdims=True), 1e-12)
        strength = gain * np.clip(1.0 - (distance - obstacle.radius) / influence, 0.0, None)
        push += strength * away / distance
    return push


def _tangent(normal: np.ndarray, towards: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to ``normal``, on the side of ``towards`` when it has one."""
    side = towards - (towards @ normal) * normal
    if np.linalg.norm(side) < 1e-9:  # heading straight at the centre: go round on a fixed side
        side = np.array([-normal[1], normal[0]]) if len(normal) == 2 else np.cross(normal, [0.0, 0.0, 1.0])
        if np.linalg.norm(side) < 1e-9:
            side = np.cross(normal, [1.0, 0.0, 0.0])
    return side / np.linalg.norm(side)


def _end_step(position: np.ndarray, goal: np.ndarray, obstacles: Sequence[Obstacle], step: float,
             influence: float) -> np.ndarray:
    """``d`` of the real end point: towards ``goal``, at most ``step`` long, sliding round obstacles within
    ``influence``."""
    towards = goal - position
    length = min(step, float(np.linalg.norm(towards)))
    if length == 0.0:
        return towards
    direction = towards / np.linalg.norm(towards)
    for obstacle in obstacles:
        away = position - obstacle.centre
        normal = away / max(np.linalg.norm(away), 1e-12)
        if np.linalg.norm(away) - obstacle.radius < influence and direction @ normal < 0.0:
            direction = _tangent(normal, direction)
    return length * direction


@dataclass
class ObstacleRun:
    """The path of an obstacle-avoiding run.

    Attributes
    ----------
    theta : numpy.ndarray, shape (K, m)
        Joint vectors along the kept path (accepted integrator records of every period).
    positions : numpy.ndarray, shape (K, p, l)
        Virtual end points along the path in the subsystems' view (point 0 is the real end point).
    clearance : numpy.ndarray, shape (K,)
        Smallest clearance of the arm's skeleton to any obstacle at every record (``inf`` without obstacles).
    min_clearance : float
        Smallest clearance along the whole path, densified between records (checked, not just sampled).
    status : {"reached", "blocked", "max_periods"}
        ``"blocked"``: the end point made no progress (by ``progress_tol``) for ``patience`` periods
        (a local minimum of the local planner, or a goal the clamped arm cannot reach).
    message : str
    end_error : float
        Distance of the real end point (on the chain) to the goal at the end.
    periods, steps : int
        Planning periods and integrator steps over all periods (including discarded ones).
    seconds : float
    goal : numpy.ndarray, shape (l,)
    obstacles : list of Obstacle
    points : list of VirtualPoint
    fixed : numpy.ndarray of bool, shape (m,)
    """

    theta: np.ndarray
    positions: np.ndarray
    clearance: np.ndarray
    min_clearance: float
    status: str
    message: str
    end_error: float
    periods: int
    steps: int
    seconds: float
    goal: np.ndarray
    obstacles: list
    points: list
    fixed: np.ndarray

    @property
    def reached(self) -> bool:
        return self.status == "reached"

    @property
    def final_theta(self) -> np.ndarray:
        return self.theta[-1]


class _Guard:
    """Keeps the part of a period's path whose skeleton stays ``margin`` away from every obstacle."""

    def __init__(self, chain: SerialChain, obstacles: list[Obstacle], axes: tuple[int, ...], margin: float,
                 max_joint_step: float):
        self.chain, self.obstacles, self.axes = chain, obstacles, axes
        self.margin, self.max_joint_step = margin, max_joint_step

    def clearance(self, theta: np.ndarray) -> np.ndarray:
        return arm_clearance(self.chain, theta, self.obstacles, self.axes)

    def safe_records(self, theta: np.ndarray) -> tuple[int, float]:
        """Number of leading records (the first included) whose intervals are clear, and the kept path's clearance."""
        dense, record = densify(theta, self.max_joint_step)
        clear = self.clearance(dense)
        bad = np.flatnonzero(clear < self.margin)
        keep = len(theta) if bad.size == 0 else int(record[bad[0]])
        kept = clear[record < keep] if keep > 0 else clear[:0]
        return keep, float(kept.min(initial=np.inf))


def avoid_obstacles(
    chain: SerialChain,
    theta0: ArrayLike,
    goal: ArrayLike,
    obstacles: Sequence[Obstacle | ArrayLike],
    *,
    points: Sequence[VirtualPoint] | None = None,
    model=None,
    output: OutputFunction | None = None,
    fixed: Sequence[int] = (),
    step: float = 0.05,
    influence: float = 0.1,
    gain: float = 0.03,
    virtual_weight: float = 1.0,
    margin: float = 0.01,
    max_joint_step: float = np.radians(1.0),
    goal_tol: float = 1e-4,
    period_steps: int = 20,
    lambda0: float = 1000.0,
    max_periods: int = 300,
    patience: int = 20,
    progress_tol: float = 1e-3,
) -> ObstacleRun:
    """Move the real end point of ``chain`` to ``goal`` while the whole arm keeps clear of ``obstacles`` (Fig. 8).

    Parameters
    ----------
    chain : SerialChain
        The arm; its skeleton (frame origins joined by segments) is what the clearance guard checks.
    theta0 : array_like, shape (m,)
        Initial posture; it must keep at least ``margin`` clearance.
    goal : array_like, shape (l,)
        Goal of the real end point in the task space (x-y for planar chains, else x-y-z).
    obstacles : sequence of Obstacle or rows (x, y, r) / (x, y, z, r)
        Circles (planar task space) or spheres.
    points : sequence of VirtualPoint, optional
        Virtual end points that plan repulsion goals; default :func:`monitored_points`.
    model : ForwardModel, optional
        The subsystems' forward model of ``[end] + points`` (default analytic); e.g. a learned model.
    output : OutputFunction, optional
        Output function; :meth:`OutputFunction.sine` keeps joint limits [004 eq. 25].
    fixed : sequence of int
        Clamped joints, 0-based [004 eq. 27].
    step : float
        Largest planned move of the end point's goal per period, metres.
    influence, gain : float
        Repulsion acts within ``influence`` of an obstacle's surface, up to ``gain`` metres per period.
    virtual_weight : float
        Weight of a virtual end point with a repulsion goal (the real end point has weight 1).
    margin : float
        Clearance the guard keeps along the path, metres (> 0).
    max_joint_step : float
        Largest joint motion between two clearance checks along the path, radians.
    goal_tol : float
        The run ends as ``"reached"`` when the end point is this close to the goal.
    period_steps, max_periods : int
        Integrator steps per planning period; periods in all.
    patience : int
        Periods without ``progress_tol`` of progress towards the goal before the run is ``"blocked"``.

    Returns
    -------
    ObstacleRun

    Raises
    ------
    ValueError
        For bad parameters, a goal within ``margin`` of an obstacle, or a start posture closer than ``margin``.
    """
    started = time.perf_counter()
    probe = AnalyticModel(chain, [VirtualPoint.end()])
    axes, dims = probe.axes, probe.dims
    goal = check_magnitude(check_vectors(goal, dims, "goal").reshape(dims), "goal", MAX_LENGTH, "m")
    theta = check_vectors(theta0, chain.n, "theta0").reshape(chain.n)
    obstacles = as_obstacles(obstacles, dims)
    for name, value in (("step", step), ("influence", influence), ("gain", gain), ("margin", margin),
                        ("max_joint_step", max_joint_step), ("goal_tol", goal_tol), ("progress_tol", progress_tol)):
        check_positive(value, name)
    if not np.isfinite(virtual_weight) or virtual_weight < 0:
        raise RedkinError(f"virtual_weight must be finite and non-negative, got {virtual_weight!r}")
    for name, value in (("period_steps", period_steps), ("max_periods", max_periods), ("patience", patience)):
        if int(value) != value or value < 1:
            raise RedkinError(f"{name} must be a positive integer, got {value!r}")
    if period_steps * max_periods > MAX_STEPS:  # each period runs its steps: the run's budget, checked up front
        raise SizeLimitError(f"period_steps x max_periods = {period_steps * max_periods:g} integrator steps, more than "
                             f"{MAX_STEPS}", "steps", period_steps * max_periods, MAX_STEPS)
    for k, obstacle in enumerate(obstacles):
        if obstacle.clearance(goal) < margin:
            raise RedkinError(f"goal {goal.tolist()} is inside obstacle {k} or within margin = {margin:g} m of it "
                              f"(clearance {float(obstacle.clearance(goal)):.4g} m)")
    points = monitored_points(chain) if points is None else list(points)
    if model is None:
        model = AnalyticModel(chain, [VirtualPoint.end()] + points, axes)
    elif model.count != 1 + len(points) or model.joints != chain.n or model.dims != dims:
        raise RedkinError(f"model must serve the end point and the {len(points)} virtual points of a {chain.n}-joint "
                          f"arm in {dims}-D, got {model.count} points, {model.joints} joints, {model.dims}-D")
    guard = _Guard(chain, obstacles, axes, float(margin), float(max_joint_step))
    start_clearance = float(guard.clearance(theta))
    if start_clearance < margin:
        raise RedkinError(f"theta0 puts the arm within margin = {margin:g} m of an obstacle "
                          f"(clearance {start_clearance:.4g} m)")
    clamped = np.zeros(chain.n, dtype=bool)
    for j in fixed:
        if int(j) != j or not 0 <= j < chain.n:
            raise RedkinError(f"fixed joints must be 0-based indices in 0..{chain.n - 1}, got {j!r}")
        clamped[int(j)] = True
    fixed_joints = [int(j) for j in fixed]

    path_theta, path_positions = [theta[None]], [model.evaluate(theta)[0][None]]
    steps, periods = 0, 0
    status, message = "max_periods", f"{max_periods} periods without reaching the goal"
    best, since_best, planned = np.inf, 0, float(step)
    for periods in range(1, max_periods + 1):
        positions = model.evaluate(theta)[0]
        distance = float(np.linalg.norm(_skeleton_end(chain, theta, axes) - goal))
        if distance <= goal_tol:
            status, message, periods = "reached", f"end point within {goal_tol:g} m of the goal", periods - 1
            break
        if distance < best - progress_tol:
            best, since_best = distance, 0
        else:
            since_best += 1
            if since_best > patience:
                status = "blocked"
                message = (f"no progress of {progress_tol:g} m towards the goal in {patience} periods "
                           f"(end point {distance:.4g} m from it)")
                break
        settle = distance <= step or not obstacles
        goals, weights = positions.copy(), np.zeros(model.count)
        weights[0] = 1.0
        if settle:
            goals[0] = goal
            run = generate_trajectory(model, theta, goals, weights, output=output, fixed=fixed_joints)
        else:
            push = repulsion(positions, obstacles, influence, gain)
            goals = positions + push
            goals[0] += _end_step(positions[0], goal, obstacles, planned, influence)
            weights[1:] = np.where(np.linalg.norm(push[1:], axis=-1) > 0.0, virtual_weight, 0.0)
            run = generate_trajectory(model, theta, goals, weights, gradient_tol=1e-4, max_steps=period_steps,
                                      lambda0=lambda0, output=output, fixed=fixed_joints)
        steps += run.steps
        keep, _ = guard.safe_records(run.theta)
        # a cut period halves the next planned step (repulsion then weighs more); a clear one doubles it back
        planned = min(step, 2.0 * planned) if keep == len(run.theta) else max(step / 16.0, planned / 2.0)
        if keep > 1:
            theta = run.theta[keep - 1]
            path_theta.append(run.theta[1:keep])
            path_positions.append(run.positions[1:keep])
    theta_path = np.concatenate(path_theta)
    _, min_clearance = guard.safe_records(theta_path)
    end_error = float(np.linalg.norm(_skeleton_end(chain, theta_path[-1], axes) - goal))
    if end_error <= goal_tol:
        status, message = "reached", f"end point within {goal_tol:g} m of the goal"
    return ObstacleRun(theta_path, np.concatenate(path_positions), guard.clearance(theta_path), min_clearance,
                       status, message, end_error, periods, steps, time.perf_counter() - started, goal, obstacles,
                       points, clamped)


def _skeleton_end(chain: SerialChain, theta: np.ndarray, axes: Sequence[int]) -> np.ndarray:
    """The real end point (tool origin) in task coordinates."""
    return chain.fk(theta)[..., :3, 3][..., list(axes)]
