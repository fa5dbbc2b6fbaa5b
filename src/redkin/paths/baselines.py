"""The ways of choosing the arm angle along a path that path resolution is measured against.

* :func:`fixed_psi_path` -- the arm angle held fixed on one branch (paper 000 section 6.2.2, ``Gamma_0``);
* :func:`clamped_optimum_path` -- the per-pose optimum [000 eq. 40] clamped to the feasible set (``Gamma``);
* :func:`greedy_path` -- greedy seeded tracking: at each waypoint the solution within the limits nearest the
  previous one (the least largest single-joint move, as ssik ranks them), over a fine arm-angle grid on all
  branches;
* :func:`sampled_path` -- dynamic programming over a uniform arm-angle grid, the samples that satisfy the limits
  (the literature's method), with the same objective and bound as :func:`redkin.paths.resolve_path`.

The first three return a :class:`BaselinePath`: joint values whatever happens, and where they break a limit or
the step bound.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose, check_vectors
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.paths.bounds import step_bound
from redkin.paths.resolve import search_paths
from redkin.paths.result import PathResult
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.srs.ik import ik_all_branches
from redkin.srs.path import arm_angle_path

#: The arm-angle grid of :func:`greedy_path` (radians): 0.1 degree.
GREEDY_SPACING = np.radians(0.1)


@dataclass(frozen=True)
class BaselinePath:
    """Joint values a baseline chose along a path, and where they fail.

    Attributes
    ----------
    method : str
    q : numpy.ndarray, shape (N, 7)
        Joint values (NaN where the method found none).
    psi : numpy.ndarray, shape (N,)
    branch : list of str
    within_limits : numpy.ndarray of bool, shape (N,)
    jump : numpy.ndarray, shape (N - 1,)
        The largest move of a joint between consecutive waypoints relative to its bound (> 1 breaks it).
    """

    method: str
    q: np.ndarray
    psi: np.ndarray
    branch: list[str]
    within_limits: np.ndarray
    jump: np.ndarray

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


def _geometry(arm: SerialChain | SRSGeometry) -> SRSGeometry:
    return arm if isinstance(arm, SRSGeometry) else srs_geometry(arm)


def _path_poses(poses: ArrayLike) -> np.ndarray:
    array = check_pose(poses, "poses")
    if array.ndim != 3 or array.shape[0] == 0:
        raise RedkinError(f"poses must have shape (N, 4, 4) with N >= 1, got shape {array.shape}")
    return array


def _jumps(geometry: SRSGeometry, q: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The largest relative move between consecutive rows of ``q`` (on the circle where a range holds every
    angle)."""
    d = np.abs(np.diff(q, axis=0))
    turned = np.mod(d, 2.0 * np.pi)
    d = np.where(geometry.chain.covers_circle, np.minimum(turned, 2.0 * np.pi - turned), d)
    return (d / step).max(axis=-1, initial=0.0)


def _from_arm_angle_path(method: str, geometry: SRSGeometry, poses: np.ndarray, step: np.ndarray,
                         branch: str | Branch, fixed: float | None) -> BaselinePath:
    path = arm_angle_path(geometry, poses, branch, fixed_psi=fixed)
    within = geometry.chain.within_limits(path.q, tolerance=1e-9, wrap=True) & path.reachable
    return BaselinePath(method, path.q, path.psi, [str(parse_branch(branch))] * len(poses), within,
                        _jumps(geometry, path.q, step))


def fixed_psi_path(arm: SerialChain | SRSGeometry, poses: ArrayLike, max_step: ArrayLike, psi: float,
                   branch: str | Branch = "+++") -> BaselinePath:
    """The arm angle held at ``psi`` on ``branch`` at every waypoint (``Gamma_0`` of paper 000 section 6.2.2)."""
    geometry = _geometry(arm)
    step = step_bound(geometry.chain, max_step)
    return _from_arm_angle_path("fixed psi", geometry, _path_poses(poses), step, branch, float(psi))


def clamped_optimum_path(arm: SerialChain | SRSGeometry, poses: ArrayLike, max_step: ArrayLike,
                         branch: str | Branch = "+++") -> BaselinePath:
    """The per-pose optimum [000 eq. 40] clamped to each feasible set, on ``branch`` (``Gamma``)."""
    geometry = _geometry(arm)
    step = step_bound(geometry.chain, max_step)
    return _from_arm_angle_path("clamped optimum", geometry, _path_poses(poses), step, branch, None)


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
    within = ~np.isnan(q).any(axis=-1)
    return BaselinePath("greedy", q, psi, branch, within, _jumps(geometry, q, step))


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
        count = pieces.start.shape[0]
        waypoint = np.repeat(np.arange(count), 8 * grid.size)
        branch = np.tile(np.repeat(np.arange(8), grid.size), count)
        return waypoint, branch, np.full(waypoint.size, -1), np.tile(grid, 8 * count), np.empty((0, 2))

    return search_paths(geometry, poses[None], step, starts, None, None, uniform, None, 0)[0]
