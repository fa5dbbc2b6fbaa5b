"""The ways of choosing the arm angle along a path that path resolution is measured against.

* :func:`fixed_psi_path` -- the arm angle held fixed on one branch (paper 000 section 6.2.2, ``Gamma_0``);
* :func:`clamped_optimum_path` -- the per-pose optimum [000 eq. 40] clamped to the feasible set (``Gamma``);
* :func:`greedy_path` -- greedy seeded tracking: at each waypoint the solution within the limits nearest the
  previous one (the least largest single-joint move, as ssik ranks them), over a fine arm-angle grid on all
  branches;
* :func:`sampled_path` -- dynamic programming over a uniform arm-angle grid, the samples that satisfy the limits
  (the literature's method), with the same objective and bound as :func:`redkin.paths.resolve_path`.

The first three return a :class:`BaselinePath`: joint values whatever happens, and where they break a limit or
the step bound, judged by :func:`judge_path` (which judges joint values from anywhere, e.g. another library's).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import as_float_array, check_pose, check_vectors
from redkin.chain import SerialChain
from redkin.circle import TWO_PI
from redkin.errors import RedkinError
from redkin.franka.geometry import FrankaGeometry
from redkin.paths.arm_family import path_family
from redkin.paths.bounds import step_bound
from redkin.paths.resolve import FK_TOLERANCE, search_paths
from redkin.paths.result import PathResult
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.srs.ik import ik_all_branches
from redkin.srs.path import arm_angle_path

#: The arm-angle grid of :func:`greedy_path` (radians): 0.1 degree.
GREEDY_SPACING = np.radians(0.1)
#: Slack beyond a joint limit that a baseline's joint values are allowed (radians), as rounding.
LIMIT_SLACK = 1e-9
#: What breaks a baseline first, by :attr:`BaselinePath.reason`.
BASELINE_REASONS = {
    "no-solution": "the method gives no joint values here",
    "pose": "the joint values miss the pose by more than FK_TOLERANCE",
    "limit": "a joint is outside its limits",
    "step": "a joint moves more than its bound from the waypoint before",
}


@dataclass(frozen=True)
class BaselinePath:
    """Joint values a baseline chose along a path, and where they fail.

    Attributes
    ----------
    method : str
    q : numpy.ndarray, shape (N, 7)
        Joint values (NaN where the method found none).
    psi : numpy.ndarray, shape (N,)
        Arm angle per waypoint (NaN where unknown).
    branch : list of str
        Branch per waypoint (``""`` where unknown).
    within_limits : numpy.ndarray of bool, shape (N,)
        Joint values exist, reach the pose (where the poses were given) and keep every limit (within
        :data:`LIMIT_SLACK`).
    jump : numpy.ndarray, shape (N - 1,)
        The largest move of a joint between consecutive waypoints relative to its bound (> 1 breaks it).
    clearance : numpy.ndarray, shape (N,)
        The smallest distance of a joint with a range narrower than ``2 pi`` to a limit, per waypoint, radians
        (as :attr:`PathResult.clearance`): negative outside the limits, ``inf`` where no joint has such a range,
        NaN where the method found no joint values.
    reason : str or None
        What breaks first at :attr:`first_failure` (:data:`BASELINE_REASONS`), ``None`` for a lawful path.
    joint : int or None
        The joint that breaks it (1-based): the one furthest outside its limits, or the one moving most
        relative to its bound; ``None`` for ``"no-solution"`` and ``"pose"``.
    excess : float or None
        By how much: radians outside the limit (``"limit"``), radians over the bound (``"step"``), or the FK
        error, the largest entry of the 4x4 difference (``"pose"``).
    """

    method: str
    q: np.ndarray
    psi: np.ndarray
    branch: list[str]
    within_limits: np.ndarray
    jump: np.ndarray
    clearance: np.ndarray
    reason: str | None = None
    joint: int | None = None
    excess: float | None = None

    @property
    def first_failure(self) -> int | None:
        """The first waypoint that breaks a limit or is reached by a step over the bound, or ``None``."""
        bad = ~self.within_limits
        bad[1:] |= ~(self.jump <= 1.0)
        where = np.flatnonzero(bad)
        return int(where[0]) if where.size else None

    @property
    def ok(self) -> bool:
        """Whether the whole path keeps the limits and the bound."""
        return self.first_failure is None

    @property
    def message(self) -> str:
        """One line: where the baseline first fails, why, the joint and by how much."""
        k = self.first_failure
        if k is None or self.reason is None:
            return f"{self.method}: keeps every limit and the bound"
        text = f"{self.method}: waypoint {k}: {BASELINE_REASONS[self.reason]}"
        if self.joint is not None:
            text += f" (joint {self.joint}"
        if self.excess is not None:
            unit = "" if self.reason == "pose" else " rad"
            text += f"{', ' if self.joint is not None else ' ('}by {self.excess:.3g}{unit}"
        return text + (")" if self.joint is not None or self.excess is not None else "")


def _geometry(arm: SerialChain | SRSGeometry) -> SRSGeometry:
    return arm if isinstance(arm, SRSGeometry) else srs_geometry(arm)


def _path_poses(poses: ArrayLike) -> np.ndarray:
    array = check_pose(poses, "poses")
    if array.ndim != 3 or array.shape[0] == 0:
        raise RedkinError(f"poses must have shape (N, 4, 4) with N >= 1, got shape {array.shape}")
    return array


def _outside(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """How far each joint value lies outside its range (..., 7), radians; 0 inside and for an unlimited joint.
    The values are taken as they would be commanded, not modulo ``2 pi``."""
    below = np.where(np.isfinite(chain.lower), chain.lower - q, 0.0)
    above = np.where(np.isfinite(chain.upper), q - chain.upper, 0.0)
    return np.maximum(np.maximum(below, above), 0.0)


def judge_path(arm: SerialChain | SRSGeometry | FrankaGeometry, q: ArrayLike, max_step: ArrayLike,
               poses: ArrayLike | None = None, method: str = "given", psi: ArrayLike | None = None,
               branch: Sequence[str] | None = None) -> BaselinePath:
    """Judge joint values along a path as the baselines are judged: limits, the step bound, and the poses.

    Parameters
    ----------
    arm : SerialChain, SRSGeometry or FrankaGeometry
        The arm with its joint limits (an S-R-S, offset-elbow or Franka-class arm).
    q : array_like, shape (N, 7)
        Joint values per waypoint as they would be commanded (a limit is not met modulo ``2 pi``), NaN where the
        method gave none.
    max_step : float or array_like of shape (7,)
        The bound on each joint's move between waypoints (radians); moves are taken on the circle for a joint
        whose range holds every angle (as :func:`redkin.paths.resolve_path` takes them).
    poses : array_like, shape (N, 4, 4), optional
        The waypoints: joint values that miss their pose by more than :data:`redkin.paths.FK_TOLERANCE` fail
        (``"pose"``).
    method : str
        The name the result carries.
    psi : array_like, shape (N,), optional
    branch : sequence of str, optional
        The method's arm angle and branch per waypoint, if it has them.

    Returns
    -------
    BaselinePath
        With the first failure's ``reason``, ``joint`` and ``excess``.
    """
    chain = path_family(arm).chain
    step = step_bound(chain, max_step)
    values = as_float_array(q, "q")
    if values.ndim != 2 or values.shape[1] != 7 or values.shape[0] == 0:
        raise RedkinError(f"q must have shape (N, 7) with N >= 1, got shape {values.shape}")
    count = values.shape[0]
    found = np.all(np.isfinite(values), axis=-1)
    filled = np.where(found[:, None], values, 0.0)
    error = np.zeros(count)
    if poses is not None:
        targets = _path_poses(poses)
        if targets.shape[0] != count:
            raise RedkinError(f"poses must have one pose per row of q ({count}), got {targets.shape[0]}")
        error = np.abs(chain.fk(filled) - targets).max(axis=(-2, -1))
    outside = _outside(chain, filled)
    within = found & (error <= FK_TOLERANCE) & np.all(outside <= LIMIT_SLACK, axis=-1)
    d = np.abs(np.diff(values, axis=0))
    turned = np.mod(d, TWO_PI)
    moves = np.where(chain.covers_circle, np.minimum(turned, TWO_PI - turned), d)
    jump = (moves / step).max(axis=-1, initial=0.0)
    angles = np.full(count, np.nan) if psi is None else as_float_array(psi, "psi").reshape(count)
    names = [""] * count if branch is None else list(branch)
    binding = ~chain.covers_circle
    inside = np.minimum(values - chain.lower, chain.upper - values)[:, binding]
    clearance = inside.min(axis=-1, initial=np.inf)
    clearance[~found] = np.nan
    path = BaselinePath(method, values, angles, names, within, jump, clearance)
    k = path.first_failure
    if k is None:
        return path
    if not found[k]:
        reason, joint, excess = "no-solution", None, None
    elif error[k] > FK_TOLERANCE:
        reason, joint, excess = "pose", None, float(error[k])
    elif not within[k]:
        joint = int(np.argmax(outside[k]))
        reason, excess, joint = "limit", float(outside[k, joint]), joint + 1
    else:
        relative = moves[k - 1] / step
        joint = int(np.argmax(relative))
        reason, excess, joint = "step", float(moves[k - 1, joint] - step[joint]), joint + 1
    return BaselinePath(method, values, angles, names, within, jump, clearance, reason, joint, excess)


def _from_arm_angle_path(method: str, geometry: SRSGeometry, poses: np.ndarray, step: np.ndarray,
                         branch: str | Branch, fixed: float | None, target: ArrayLike | None = None,
                         weights: ArrayLike = (0.5, 0.5)) -> BaselinePath:
    path = arm_angle_path(geometry, poses, branch, target=target, weights=weights, fixed_psi=fixed)
    q = path.q.copy()
    if np.all(np.isfinite(q[0])):  # the first waypoint as srs.ik gives it; the later ones follow it into range
        q[0] = geometry.chain.nearest_in_range(q[0])
    return judge_path(geometry, q, step, method=method, psi=path.psi,
                      branch=[str(parse_branch(branch))] * len(poses))


def fixed_psi_path(arm: SerialChain | SRSGeometry, poses: ArrayLike, max_step: ArrayLike, psi: float,
                   branch: str | Branch = "+++") -> BaselinePath:
    """The arm angle held at ``psi`` on ``branch`` at every waypoint (``Gamma_0`` of paper 000 section 6.2.2)."""
    geometry = _geometry(arm)
    step = step_bound(geometry.chain, max_step)
    return _from_arm_angle_path("fixed psi", geometry, _path_poses(poses), step, branch, float(psi))


def clamped_optimum_path(arm: SerialChain | SRSGeometry, poses: ArrayLike, max_step: ArrayLike,
                         branch: str | Branch = "+++", target: ArrayLike | None = None,
                         weights: ArrayLike = (0.5, 0.5)) -> BaselinePath:
    """The per-pose optimum [000 eq. 40] clamped to each feasible set, on ``branch`` (``Gamma``); ``target`` and
    ``weights`` as in :func:`redkin.srs.optimal_arm_angles` (default: the middles of the limits)."""
    geometry = _geometry(arm)
    step = step_bound(geometry.chain, max_step)
    return _from_arm_angle_path("clamped optimum", geometry, _path_poses(poses), step, branch, None, target,
                                weights)


def greedy_path(arm: SerialChain | SRSGeometry, poses: ArrayLike, max_step: ArrayLike, q0: ArrayLike | None = None,
                spacing: float = GREEDY_SPACING) -> BaselinePath:
    """Greedy seeded tracking: at each waypoint, of the solutions within the limits on an arm-angle grid of all
    eight branches, the one whose largest single-joint move from the previous waypoint's (or from ``q0``) is
    least; the first waypoint without ``q0`` takes the one farthest from the limits.  A waypoint without a
    solution within the limits gets NaN, and the next one starts afresh."""
    geometry = _geometry(arm)
    chain = geometry.chain
    step = step_bound(chain, max_step)
    poses = _path_poses(poses)
    previous = None if q0 is None else check_vectors(q0, 7, "q0").reshape(7)
    grid = np.arange(-np.pi, np.pi, float(spacing))
    count = len(poses)
    q, psi = np.full((count, 7), np.nan), np.full(count, np.nan)
    branch = [""] * count
    circle = chain.covers_circle
    binding = ~circle
    for k in range(count):
        solutions = ik_all_branches(geometry, poses[k], grid)  # (G, 8, 7)
        inside = chain.within_limits(solutions)
        if not inside.any():
            previous = None
            continue
        rows, columns = np.nonzero(inside)
        candidates = solutions[rows, columns]
        if previous is None:
            lower, upper = chain.lower[binding], chain.upper[binding]
            score = -np.minimum(candidates[:, binding] - lower, upper - candidates[:, binding]).min(axis=-1,
                                                                                                 initial=np.inf)
        else:
            d = np.abs(candidates - previous)
            turned = np.mod(d, 2.0 * np.pi)
            score = np.where(circle, np.minimum(turned, 2.0 * np.pi - turned), d).max(axis=-1)
        best = int(np.argmin(score))
        q[k], psi[k], branch[k] = candidates[best], grid[rows[best]], str(BRANCHES[columns[best]])
        previous = q[k]
    return judge_path(geometry, q, step, method="greedy", psi=psi, branch=branch)


def sampled_path(arm: SerialChain | SRSGeometry, poses: ArrayLike, max_step: ArrayLike, spacing: float,
                 q0: ArrayLike | None = None) -> PathResult:
    """Dynamic programming over the arm angles ``-pi + k spacing`` of every branch that satisfy the limits: the
    objective and bound of :func:`redkin.paths.resolve_path` without the exact sets (no arc ends, no
    refinement), as the literature samples the self-motion."""
    geometry = _geometry(arm)
    step = step_bound(geometry.chain, max_step)
    poses = _path_poses(poses)
    if not (np.isfinite(spacing) and 0.0 < spacing <= np.pi):
        raise RedkinError(f"spacing must be in (0, pi] radians, got {spacing!r}")
    starts = None if q0 is None else check_vectors(q0, 7, "q0").reshape(1, 7)
    grid = np.arange(-np.pi, np.pi, float(spacing))

    def uniform(pieces) -> tuple[np.ndarray, ...]:
        """Every branch at every grid angle of every waypoint, sorted as a graph's nodes (nodes alone: piece -1),
        nothing shared."""
        count = pieces.start.shape[0]
        waypoint = np.repeat(np.arange(count), 8 * grid.size)
        branch = np.tile(np.arange(8), grid.size * count)
        psi = np.tile(np.repeat(grid, 8), count)
        return waypoint, branch, np.full(waypoint.size, -1), psi, np.arange(waypoint.size), np.empty((0, 2))

    return search_paths(path_family(geometry), poses[None], step, starts, None, None, uniform, None, 0,
                        polish=False)[0]
