"""Manipulability maps over planes of wrist positions (chapter 5, Figs. 5.1-5.6, thesis 001).

``w`` depends on the redundancy, so two kinds of map are offered:

* at a given ``(psi, phi)`` (:func:`manipulability_map`): one IK per grid
  point, ``w`` where the posture exists (and, by default, where some branch
  respects the joint limits of joints 1-5);
* the best ``w`` over the redundancy within limits (:func:`best_manipulability_map`):
  the maximum over a sweep of theta_1 across its limits (equivalent to psi,
  which is a monotone function of theta_1) and of phi around the whole
  elbow circle (so the elbow reference does not matter).

The dual-arm maps use the symmetric two-arm posture (left arm = mirror of
the right arm in the torso's mid-plane, torso joint shared), indexed by the
right wrist position; the measure is
:func:`~redkin.torso_arm.manipulability.stacked_dual_manipulability` unless
another is passed.  :func:`region_above` answers the thesis's practical
question: where does ``w`` stay above a threshold?
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from redkin.torso_arm.branches import OK, wrap_to_limits
from redkin.torso_arm.elbow_angle import (
    ElbowReference,
    _fallback_basis,
    as_reference,
    elbow_circle,
    elbow_position,
    reference_direction,
)
from redkin.torso_arm.geometry import MIRROR, TorsoArm, humanoid_arm
from redkin.torso_arm.manipulability import (
    gram_manipulability,
    stacked_dual_manipulability,
    wrist_jacobian_from_joints,
)
from redkin.torso_arm.position_ik import joints_from_points
from redkin.torso_arm.shoulder_angle import theta1_from_shoulder_angle
from redkin.validation import as_float_array, check_count, check_finite

Progress = Callable[[float], None]
#: Largest number of grid points along one axis of a map (10^6 points in all: about 1 GB, a few seconds).
MAX_RESOLUTION = 1000
#: Largest number of theta_1 or phi samples of a best-over-the-redundancy map.
MAX_SWEEP_SAMPLES = 3600
#: Postures a best map evaluates at once (grid points x phi samples; about 1 KB each).
MAX_BATCH_POSTURES = 4_000_000
#: Postures a best map evaluates in all (grid points x theta_1 x phi samples).
MAX_MAP_POSTURES = 100_000_000
DualMeasure = Callable[[np.ndarray, np.ndarray], np.ndarray]
_AXES = "xyz"


@dataclass(frozen=True)
class PlaneGrid:
    """Wrist positions on an axis-aligned plane.

    Attributes
    ----------
    points : numpy.ndarray, shape (nv, nu, 3)
    fixed_axis : str
        ``"x"``, ``"y"`` or ``"z"``; ``value`` its coordinate.
    axis_names : tuple of str
        Names of the in-plane axes ``(u, v)``, in x-y-z order.
    u, v : numpy.ndarray
        Coordinates along those axes (metres).
    """

    points: np.ndarray
    fixed_axis: str
    value: float
    axis_names: tuple[str, str]
    u: np.ndarray
    v: np.ndarray

    @property
    def label(self) -> str:
        return f"{self.fixed_axis} = {self.value:g} m"

    @property
    def cell_area(self) -> float:
        """Area of one grid cell in square metres."""
        du = (self.u[-1] - self.u[0]) / max(len(self.u) - 1, 1)
        dv = (self.v[-1] - self.v[0]) / max(len(self.v) - 1, 1)
        return float(abs(du * dv))


def parse_plane(plane: str) -> tuple[str, float]:
    """``"z=0"``, ``"x = -0.2"`` -> (axis, value)."""
    match = re.fullmatch(r"\s*([xyzXYZ])\s*=\s*([-+0-9.eE]+)\s*", str(plane))
    if not match:
        raise ValueError(f"plane must look like 'z=0' or 'x=-0.2' (metres), got {plane!r}")
    try:
        value = float(match.group(2))
    except ValueError as exc:
        raise ValueError(f"plane must look like 'z=0' or 'x=-0.2' (metres), got {plane!r}") from exc
    if not np.isfinite(value):
        raise ValueError(f"plane coordinate must be finite, got {plane!r}")
    return match.group(1).lower(), value


def plane_grid(plane: str, extent: ArrayLike, resolution: int | tuple[int, int]) -> PlaneGrid:
    """A grid of wrist positions on ``plane`` (e.g. ``"z=0"``).

    Parameters
    ----------
    plane : str
        ``"<axis>=<value>"`` with the value in metres.
    extent : array_like, shape (4,)
        ``(u_min, u_max, v_min, v_max)`` in metres along the two other axes, in x-y-z order.
    resolution : int or (int, int)
        Points along u and v (2 to :data:`MAX_RESOLUTION` each).
    """
    axis, value = parse_plane(plane)
    box = as_float_array(extent, "extent").reshape(-1)
    if box.shape != (4,):
        raise ValueError(f"extent must be (u_min, u_max, v_min, v_max), got {np.shape(extent)}")
    check_finite(box, "extent")
    if box[0] >= box[1] or box[2] >= box[3]:
        raise ValueError(f"extent must have u_min < u_max and v_min < v_max, got {box.tolist()}")
    counts = (resolution, resolution) if np.isscalar(resolution) else tuple(resolution)
    if len(counts) != 2:
        raise ValueError(f"resolution must be one integer or two, got {resolution!r}")
    nu, nv = (check_count(n, "resolution", 2, MAX_RESOLUTION) for n in counts)
    u, v = np.linspace(box[0], box[1], nu), np.linspace(box[2], box[3], nv)
    others = [a for a in _AXES if a != axis]
    points = np.zeros((nv, nu, 3))
    points[..., _AXES.index(axis)] = value
    points[..., _AXES.index(others[0])] = u[None, :]
    points[..., _AXES.index(others[1])] = v[:, None]
    return PlaneGrid(points, axis, value, (others[0], others[1]), u, v)


def reach_extent(arm: TorsoArm, plane: str, margin: float = 0.05) -> tuple[float, float, float, float]:
    """The default ``extent`` of a map on ``plane``: the box around every wrist position the arm can reach there.

    The shoulder ``S(theta_1)`` runs on a circle of radius ``L0`` about the
    torso axis ``y`` (:meth:`TorsoArm.shoulder`), and the wrist lies within
    ``R = L1 + l_ew`` of it, so every reachable wrist is in the torus
    ``(rho - L0)^2 + y^2 <= R^2`` with ``rho = sqrt(x^2 + z^2)`` (the left arm's
    torus is the same).  The box bounds the torus's section by the plane,
    widened by ``margin`` times ``R`` on every side so that the edge of the
    reach shows.

    Raises
    ------
    ValueError
        If the plane misses the reach altogether.
    """
    axis, value = parse_plane(plane)
    reach = arm.L1 + arm.forearm
    outer = arm.L0 + reach
    pad = margin * reach
    if axis == "y":
        if abs(value) >= reach:
            raise ValueError(f"plane {plane!r} lies outside the arm's reach (|y| < {reach:.4g} m)")
        radius = arm.L0 + np.sqrt(reach**2 - value**2) + pad
        return (-radius, radius, -radius, radius)
    if abs(value) >= outer:
        raise ValueError(f"plane {plane!r} lies outside the arm's reach (|{axis}| < {outer:.4g} m)")
    across = np.sqrt(outer**2 - value**2) + pad  # the other of x and z
    height = reach + pad  # y
    return (-across, across, -height, height) if axis == "z" else (-height, height, -across, across)


@dataclass(frozen=True)
class ManipulabilityMap:
    """A map of ``w`` over a :class:`PlaneGrid`.

    Attributes
    ----------
    values : numpy.ndarray, shape (nv, nu)
        ``w`` (SI: m^3 for the single arm) where ``valid``; NaN elsewhere.
    valid : numpy.ndarray of bool
        The posture exists (and respects the limits, if they were required).
    status : numpy.ndarray of int
        IK status per point (:data:`~redkin.torso_arm.branches.STATUS_NAMES`);
        for best maps, OK where some sampled posture exists.
    description : str
        Which arm(s), measure and redundancy choice.
    """

    grid: PlaneGrid
    values: np.ndarray
    valid: np.ndarray
    status: np.ndarray
    description: str


@dataclass(frozen=True)
class _ArmState:
    jacobian: np.ndarray  # world, (..., 3, 5)
    status: np.ndarray
    feasible: np.ndarray  # some branch within limits


def _arm_state(arm: TorsoArm, points: np.ndarray, theta1_side: np.ndarray, defined: np.ndarray,
               phi: np.ndarray, reference: ElbowReference | None) -> _ArmState:
    """Wrist Jacobian, IK status and limit feasibility of ``arm`` at side-world points (reference None: any basis)."""
    right_points = arm.to_right(points)
    theta1 = np.where(defined, theta1_side if arm.side == "right" else -theta1_side, 0.0)
    shoulder = arm.shoulder(theta1)
    circle = elbow_circle(arm, shoulder, right_points)
    if reference is None:
        e1, exists = _fallback_basis(circle.axis), np.ones(circle.length.shape, bool)
    else:
        e1, exists = reference_direction(arm, circle, reference.mirrored() if arm.side == "left" else reference)
    elbow = elbow_position(circle, e1, phi)
    status = np.where(defined, np.where(circle.reachable, np.where(exists, OK, 2), 1), 3)
    q5 = joints_from_points(arm, theta1, elbow, right_points)
    jac = wrist_jacobian_from_joints(arm, q5[..., 0, :])
    if arm.side == "left":
        q5 = q5 * np.array([-1.0, 1.0, 1.0, 1.0, 1.0])
        jac = MIRROR @ jac * np.array([-1.0, 1.0, 1.0, 1.0, 1.0])
    chain = arm.chain
    q5 = wrap_to_limits(chain, q5, slice(0, 5))
    inside = np.all((q5 >= chain.lower[:5]) & (q5 <= chain.upper[:5]), axis=-1)
    return _ArmState(jac, status, np.any(inside, axis=-1) & (status == OK))


def _finish(grid: PlaneGrid, values: np.ndarray, status: np.ndarray, feasible: np.ndarray,
            within_limits: bool, description: str) -> ManipulabilityMap:
    valid = (status == OK) & (feasible if within_limits else True)
    return ManipulabilityMap(grid, np.where(valid, values, np.nan), valid, status, description)


def manipulability_map(
    arm: TorsoArm,
    grid: PlaneGrid,
    shoulder_angle: float,
    elbow_angle: float,
    reference: "ElbowReference | str | ArrayLike | None" = None,
    within_limits: bool = True,
) -> ManipulabilityMap:
    """``w`` (eq. 5.3) of one arm over ``grid`` at fixed ``(psi, phi)``; vectorised over the grid."""
    psi, phi = float(shoulder_angle), float(elbow_angle)
    if not (np.isfinite(psi) and np.isfinite(phi)):
        raise ValueError(f"shoulder and elbow angles must be finite, got {psi!r}, {phi!r}")
    ref = as_reference(reference)
    right_points = arm.to_right(grid.points)
    theta1, defined = theta1_from_shoulder_angle(np.full(grid.points.shape[:-1], psi), right_points)
    theta1 = theta1 if arm.side == "right" else -theta1
    state = _arm_state(arm, grid.points, theta1, defined, np.asarray(phi), ref)
    values = gram_manipulability(state.jacobian)
    return _finish(grid, values, state.status, state.feasible, within_limits,
                   f"{arm.side} arm, psi = {np.degrees(psi):g} deg, phi = {np.degrees(phi):g} deg ({ref.kind} reference)")


def _sweeps(arm: TorsoArm, grid: PlaneGrid, samples: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    if np.ndim(samples) != 1 or len(samples) != 2:
        raise ValueError(f"samples must be two positive integers (theta_1, phi), got {samples!r}")
    n1, n2 = (check_count(n, "samples", 1, MAX_SWEEP_SAMPLES) for n in samples)
    points = grid.points[..., 0].size
    if points * n2 > MAX_BATCH_POSTURES:
        raise ValueError(f"{points} grid points x {n2} phi samples = {points * n2} postures at once; at most "
                         f"{MAX_BATCH_POSTURES} fit in memory (lower the resolution or the phi samples)")
    if points * n1 * n2 > MAX_MAP_POSTURES:
        raise ValueError(f"{points} grid points x {n1} x {n2} samples = {points * n1 * n2} postures; at most "
                         f"{MAX_MAP_POSTURES} are allowed (about 5 minutes)")
    lower, upper = arm.chain.lower[0], arm.chain.upper[0]
    lower, upper = (max(lower, -np.pi), min(upper, np.pi))
    theta1 = np.linspace(lower, upper, int(n1)) if n1 > 1 else np.array([(lower + upper) / 2])
    phi = np.linspace(-np.pi, np.pi, int(n2), endpoint=False)
    return theta1, phi


def best_manipulability_map(
    arm: TorsoArm,
    grid: PlaneGrid,
    samples: tuple[int, int] = (24, 24),
    within_limits: bool = True,
    progress: Progress | None = None,
) -> ManipulabilityMap:
    """Best ``w`` over the redundancy: max over theta_1 (across its limits) x phi (full circle) samples."""
    def evaluate(points, theta1, ones, phi):
        state = _arm_state(arm, points, theta1, ones, phi, None)
        ok = state.status == OK
        return gram_manipulability(state.jacobian), (state.feasible if within_limits else ok), ok

    return _best_over_sweeps(grid, *_sweeps(arm, grid, samples), evaluate, progress,
                             f"{arm.side} arm, best over theta_1 x phi = {samples[0]} x {samples[1]} samples"
                             + (" within limits" if within_limits else ""))


def _best_over_sweeps(grid, theta1_samples, phi_samples, evaluate, progress, description) -> ManipulabilityMap:
    """Max over theta_1 x phi samples of ``evaluate(points, theta1, ones, phi) -> (w, usable, solved)``."""
    points = grid.points[..., None, :]
    best = np.full(grid.points.shape[:-1], -np.inf)
    reached = np.zeros(grid.points.shape[:-1], bool)
    for index, theta1 in enumerate(theta1_samples):
        ones = np.ones(points.shape[:-2] + (phi_samples.size,), bool)
        w, usable, solved = evaluate(points, np.full(ones.shape, theta1), ones, phi_samples)
        best = np.maximum(best, np.max(np.where(usable, w, -np.inf), axis=-1))
        reached |= np.any(solved, axis=-1)
        if progress is not None:
            progress((index + 1) / theta1_samples.size)
    found = np.isfinite(best)
    return ManipulabilityMap(grid, np.where(found, best, np.nan), found, np.where(reached, OK, 1), description)


def torso_mirror(theta1: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Mirror ``points`` in the torso's mid-plane ``Ry(theta_1) {x = 0}``: ``Ry(theta_1) M Ry(-theta_1) p``."""
    c, s = np.cos(2.0 * theta1), np.sin(2.0 * theta1)
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    c, s, x, y, z = np.broadcast_arrays(c, s, x, y, z)
    return np.stack([-c * x + s * z, y, s * x + c * z], axis=-1)


def _dual_states(right: TorsoArm, points: np.ndarray, theta1: np.ndarray, defined: np.ndarray,
                 phi: np.ndarray, reference: ElbowReference | None) -> tuple[_ArmState, _ArmState]:
    left = TorsoArm(right.right_chain, "left")
    a = _arm_state(right, points, theta1, defined, phi, reference)
    b = _arm_state(left, torso_mirror(np.where(defined, theta1, 0.0), points), theta1, defined, phi, reference)
    return a, b


def dual_arm_map(
    grid: PlaneGrid,
    shoulder_angle: float,
    elbow_angle: float,
    reference: "ElbowReference | str | ArrayLike | None" = None,
    measure: DualMeasure = stacked_dual_manipulability,
    within_limits: bool = True,
    right: TorsoArm | None = None,
) -> ManipulabilityMap:
    """Dual-arm ``measure`` over the right wrist position, in the symmetric two-arm posture.

    The left arm is the mirror image of the right arm in the torso's
    mid-plane (same joints 2-5, theta_1 shared), so its wrist is at
    :func:`torso_mirror` of the grid point; theta_1 comes from the right
    arm's psi.  (Both wrists at one point is impossible within the limits:
    theta_3 >= -5 deg keeps each wrist at least ~17 mm on its own side of the
    mid-plane.)  ``measure(J_right, J_left)`` receives the two world
    ``(..., 3, 5)`` Jacobians w.r.t. (theta_1, q2..q5).
    """
    psi, phi = float(shoulder_angle), float(elbow_angle)
    if not (np.isfinite(psi) and np.isfinite(phi)):
        raise ValueError(f"shoulder and elbow angles must be finite, got {psi!r}, {phi!r}")
    right = right or humanoid_arm("right")
    ref = as_reference(reference)
    theta1, defined = theta1_from_shoulder_angle(np.full(grid.points.shape[:-1], psi), grid.points)
    a, b = _dual_states(right, grid.points, theta1, defined, np.asarray(phi), ref)
    status = np.where(a.status != OK, a.status, b.status)
    return _finish(grid, measure(a.jacobian, b.jacobian), status, a.feasible & b.feasible, within_limits,
                   f"both arms (symmetric posture), psi = {np.degrees(psi):g} deg, phi = {np.degrees(phi):g} deg")


def best_dual_arm_map(
    grid: PlaneGrid,
    samples: tuple[int, int] = (24, 24),
    measure: DualMeasure = stacked_dual_manipulability,
    within_limits: bool = True,
    right: TorsoArm | None = None,
    progress: Progress | None = None,
) -> ManipulabilityMap:
    """Best dual-arm ``measure`` (symmetric posture, see :func:`dual_arm_map`) over theta_1 x phi samples."""
    right = right or humanoid_arm("right")

    def evaluate(points, theta1, ones, phi):
        a, b = _dual_states(right, points, theta1, ones, phi, None)
        ok = (a.status == OK) & (b.status == OK)
        return measure(a.jacobian, b.jacobian), ((a.feasible & b.feasible) if within_limits else ok), ok

    return _best_over_sweeps(grid, *_sweeps(right, grid, samples), evaluate, progress,
                             f"both arms (symmetric posture), best over theta_1 x phi = {samples[0]} x {samples[1]} samples"
                             + (" within limits" if within_limits else ""))


@dataclass(frozen=True)
class Region:
    """Grid points where ``w >= threshold``: ``mask``, its ``area`` (m^2) and ``fraction`` of valid points."""

    mask: np.ndarray
    area: float
    fraction: float
    threshold: float


def region_above(result: ManipulabilityMap, threshold: float) -> Region:
    """The part of a map where ``w`` stays at or above ``threshold`` (section 5 / chapter 6 question)."""
    threshold = float(threshold)
    if not np.isfinite(threshold) or threshold < 0:
        raise ValueError(f"threshold must be a finite number >= 0, got {threshold!r}")
    mask = result.valid & (np.nan_to_num(result.values, nan=-1.0) >= threshold)
    count = int(result.valid.sum())
    return Region(mask, float(mask.sum()) * result.grid.cell_area, mask.sum() / count if count else 0.0, threshold)
