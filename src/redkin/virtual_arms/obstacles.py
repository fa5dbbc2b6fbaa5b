"""Obstacle avoidance with local goal planning (paper 004 section 4, Fig. 8).

Each subsystem plans its own goal from local information only, once per
planning period:

* the real end point: a step of at most ``step`` towards the final goal plus a
  repulsion away from every obstacle closer than ``influence``;
* every other virtual end point: the repulsion alone; a point with no
  obstacle nearby has no goal in that period (weight 0).

The network then runs the trajectory-generation dynamics from the current
posture to these goals, and the posture it reaches starts the next period.
Obstacles are circles in the plane (planar arms) or spheres (spatial arms).
The paper defers the details of its planner to its ref. 11; this repulsion law
is ours.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from redkin.validation import check_positive, check_vectors
from redkin.virtual_arms.generate import generate_trajectory
from redkin.virtual_arms.output_function import OutputFunction


@dataclass(frozen=True)
class Obstacle:
    """A circle (2-D task space) or sphere (3-D) with ``centre`` and ``radius`` in metres."""

    centre: np.ndarray
    radius: float

    def clearance(self, points: np.ndarray) -> np.ndarray:
        """Distance from ``points`` (..., l) to the obstacle's surface (negative inside)."""
        return np.linalg.norm(points - self.centre, axis=-1) - self.radius


def repulsion(points: np.ndarray, obstacles: Sequence[Obstacle], influence: float, gain: float) -> np.ndarray:
    """Displacements pushing ``points`` (p, l) away from obstacles nearer than ``influence``.

    Each obstacle adds ``gain * (1 - clearance / influence)`` along the outward
    normal while the clearance is below ``influence``.
    """
    push = np.zeros_like(points)
    for obstacle in obstacles:
        away = points - obstacle.centre
        distance = np.maximum(np.linalg.norm(away, axis=-1, keepdims=True), 1e-12)
        clearance = distance - obstacle.radius
        strength = gain * np.clip(1.0 - clearance / influence, 0.0, None)
        push += strength * away / distance
    return push


@dataclass
class ObstacleRun:
    """The path of an obstacle-avoiding run.

    Attributes
    ----------
    theta : numpy.ndarray, shape (K, m)
        Joint vectors along the whole path (every integrator step of every period).
    positions : numpy.ndarray, shape (K, p, l)
        Virtual end points along the path (models' view).
    periods : int
    reached : bool
        Whether the end point came within ``goal_tol`` of the goal.
    end_error : float
    min_clearance : float
        Smallest clearance of any virtual end point to any obstacle along the path.
    steps : int
        Integrator steps over all periods.
    seconds : float
    """

    theta: np.ndarray
    positions: np.ndarray
    periods: int
    reached: bool
    end_error: float
    min_clearance: float
    steps: int
    seconds: float


def avoid_obstacles(
    model,
    theta0: ArrayLike,
    goal: ArrayLike,
    obstacles: Sequence[Obstacle],
    end_index: int = 0,
    *,
    output: OutputFunction | None = None,
    fixed: Sequence[int] = (),
    step: float = 0.05,
    influence: float = 0.15,
    gain: float = 0.05,
    virtual_weight: float = 1.0,
    goal_tol: float = 1e-4,
    max_periods: int = 200,
) -> ObstacleRun:
    """Move the end point (``model`` point ``end_index``) to ``goal`` among obstacles (Fig. 8).

    Parameters
    ----------
    model : ForwardModel
        All virtual end points; point ``end_index`` is the real end point.
    theta0 : array_like, shape (m,)
    goal : array_like, shape (l,)
    obstacles : sequence of Obstacle
    output, fixed :
        Output function (joint limits) and clamped joints, as in :func:`generate_trajectory`.
    step : float
        Largest step of the end point's goal per period, metres.
    influence, gain : float
        Repulsion acts within ``influence`` of an obstacle's surface, up to ``gain`` metres per period.
    virtual_weight : float
        Weight of a virtual end point with a repulsion goal (the end point has weight 1).
    goal_tol : float
        The run stops when the end point is this close to the goal.
    max_periods : int
    """
    goal = check_vectors(goal, model.dims, "goal").reshape(model.dims)
    for name, value in (("step", step), ("influence", influence), ("gain", gain), ("goal_tol", goal_tol)):
        check_positive(value, name)
    if not 0 <= end_index < model.count:
        raise ValueError(f"end_index must be in 0..{model.count - 1}, got {end_index}")
    theta = check_vectors(theta0, model.joints, "theta0").reshape(model.joints)
    path_theta, path_positions = [theta[None]], [model.evaluate(theta)[0][None]]
    steps, seconds, periods, reached = 0, 0.0, 0, False
    for periods in range(1, max_periods + 1):
        positions = model.evaluate(theta)[0]
        if np.linalg.norm(positions[end_index] - goal) <= goal_tol:
            reached, periods = True, periods - 1
            break
        push = repulsion(positions, obstacles, influence, gain)
        towards = goal - positions[end_index]
        length = np.linalg.norm(towards)
        final = length <= step
        if not final:
            towards *= step / length
        goals = positions + push
        goals[end_index] = positions[end_index] + towards + push[end_index]
        weights = np.where(np.linalg.norm(push, axis=-1) > 0.0, virtual_weight, 0.0)
        weights[end_index] = 1.0
        # intermediate periods need not reach equilibrium: their goals are re-planned next period
        result = generate_trajectory(model, theta, goals, weights, output=output, fixed=fixed,
                                     gradient_tol=1e-6 if final else 1e-4, max_steps=400 if final else 40)
        steps += result.steps
        seconds += result.seconds
        theta = result.final_theta
        path_theta.append(result.theta[1:])
        path_positions.append(result.positions[1:])
    positions = np.concatenate(path_positions)
    end_error = float(np.linalg.norm(model.evaluate(theta)[0][end_index] - goal))
    clearance = min((float(ob.clearance(positions).min()) for ob in obstacles), default=np.inf)
    return ObstacleRun(np.concatenate(path_theta), positions, periods, reached or end_error <= goal_tol, end_error,
                       clearance, steps, seconds)
