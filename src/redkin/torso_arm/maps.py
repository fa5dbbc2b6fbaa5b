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
from collections.abc import Callable
from dataclasses import dataclass
from math import cos, inf, sin

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import PARALLEL_BATCH, kernel, run_batch
from redkin._constants import TORSO_ARM_MAX_RESOLUTION as MAX_RESOLUTION  # most grid points along one axis
from redkin._validation import as_float_array, check_count, check_finite, check_vectors
from redkin.errors import RedkinError
from redkin.torso_arm._kernel_tools import flat, put, row, shoulder_point
from redkin.torso_arm.branches import NO_REFERENCE, OK, SHOULDER_UNDEFINED, UNREACHABLE, into_limits
from redkin.torso_arm.elbow_angle import (
    ANY_BASIS,
    THETA4,
    VECTOR,
    ElbowReference,
    as_reference,
    circle_one,
    elbow_one,
    reference_one,
)
from redkin.torso_arm.geometry import MIRROR, TorsoArm, humanoid_arm
from redkin.torso_arm.manipulability import (
    dual_one,
    gram_manipulability,
    gram_one,
    stacked_dual_manipulability,
    wrist_jacobian_one,
)
from redkin.torso_arm.position_ik import joints_one
from redkin.torso_arm.shoulder_angle import theta1_from_shoulder_angle

Progress = Callable[[float], None]
#: Largest number of theta_1 or phi samples of a best-over-the-redundancy map.
MAX_SWEEP_SAMPLES = 3600
#: Postures a best map evaluates in all (grid points x theta_1 x phi samples).
_MAX_MAP_POSTURES = 100_000_000
#: Progress reports of a best map (it runs in this many parts when a progress callback is given).
_PROGRESS_STEPS = 50
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


def _parse_plane(plane: str) -> tuple[str, float]:
    """``"z=0"``, ``"x = -0.2"`` -> (axis, value)."""
    match = re.fullmatch(r"\s*([xyzXYZ])\s*=\s*([-+0-9.eE]+)\s*", str(plane))
    if not match:
        raise RedkinError(f"plane must look like 'z=0' or 'x=-0.2' (metres), got {plane!r}")
    try:
        value = float(match.group(2))
    except ValueError as exc:
        raise RedkinError(f"plane must look like 'z=0' or 'x=-0.2' (metres), got {plane!r}") from exc
    if not np.isfinite(value):
        raise RedkinError(f"plane coordinate must be finite, got {plane!r}")
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
    axis, value = _parse_plane(plane)
    box = as_float_array(extent, "extent").reshape(-1)
    if box.shape != (4,):
        raise RedkinError(f"extent must be (u_min, u_max, v_min, v_max), got {np.shape(extent)}")
    check_finite(box, "extent")
    if box[0] >= box[1] or box[2] >= box[3]:
        raise RedkinError(f"extent must have u_min < u_max and v_min < v_max, got {box.tolist()}")
    counts = tuple(resolution) if isinstance(resolution, (tuple, list, np.ndarray)) else (resolution, resolution)
    if len(counts) != 2:
        raise RedkinError(f"resolution must be one integer or two, got {resolution!r}")
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
    axis, value = _parse_plane(plane)
    reach = arm.L1 + arm.forearm
    outer = arm.L0 + reach
    pad = margin * reach
    if axis == "y":
        if abs(value) >= reach:
            raise RedkinError(f"plane {plane!r} lies outside the arm's reach (|y| < {reach:.4g} m)")
        radius = arm.L0 + np.sqrt(reach**2 - value**2) + pad
        return (-radius, radius, -radius, radius)
    if abs(value) >= outer:
        raise RedkinError(f"plane {plane!r} lies outside the arm's reach (|{axis}| < {outer:.4g} m)")
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


# ------------------------------------------------------------------ kernels
# An arm is passed as ``lengths`` (4,) = (L0, L1, l_ew, delta) of the right arm, and per arm ``sign``
# (+1 right, -1 left: the side's theta_1 is sign times the right-problem theta_1) and ``limits`` (2, 5),
# the lower and upper limits of the side's joints 1-5.  Points and theta_1 are the right problem's.
@kernel
def _circle_stage(lengths, kind, vector, theta1, wrist):
    """The part of a posture fixed by theta_1 and the wrist (sections 3.2-3.3): ``(circle, e1, status)``.

    ``circle`` is :func:`~redkin.torso_arm.elbow_angle.circle_one`'s ``(n, centre, radius)``,
    ``e1`` the phi = 0 direction of the reference ``kind``, ``status`` OK, UNREACHABLE or NO_REFERENCE.
    """
    L0, L1, lew = lengths[0], lengths[1], lengths[2]
    shoulder = shoulder_point(L0, theta1)
    n, centre, radius, _, reachable = circle_one(shoulder, wrist, L1, lew)
    e1, exists = reference_one(kind, vector, shoulder, wrist, n, centre, radius, L0, L1)
    status = OK if reachable and exists else (NO_REFERENCE if reachable else UNREACHABLE)
    return (n, centre, radius), e1, status


@kernel
def _elbow_stage(lengths, sign, limits, theta1, wrist, circle, e1, phi, q):
    """The rest of a posture at ``phi``: joints 1-5 of the four branches into ``q`` (4, 5) (section 3.4);
    whether some branch, wrapped into the side's limits, respects them."""
    n, centre, radius = circle
    joints_one(theta1, elbow_one(centre, radius, n, e1, phi), wrist, lengths[0], lengths[1], lengths[3], q)
    for b in range(4):
        inside = True
        for j in range(5):
            value = into_limits(sign * q[b, j] if j == 0 else q[b, j], limits[0, j], limits[1, j])
            inside = inside and limits[0, j] <= value <= limits[1, j]
        if inside:
            return True
    return False


@kernel
def _posture_one(lengths, sign, limits, kind, vector, theta1, wrist, phi, q):
    """One posture of the right problem at ``theta1``, ``wrist`` (3-tuple) and ``phi``: ``(status, feasible)``.

    :func:`_circle_stage` then :func:`_elbow_stage`; joints 1-5 of the four
    branches go into ``q`` (4, 5); ``feasible`` says that the posture exists
    and some branch respects the side's limits.
    """
    circle, e1, status = _circle_stage(lengths, kind, vector, theta1, wrist)
    feasible = _elbow_stage(lengths, sign, limits, theta1, wrist, circle, e1, phi, q)
    return status, status == OK and feasible


@kernel
def _jacobian_of(lengths, q, jacobian):
    """The wrist Jacobian [001 eq. 5.2] of the first branch of ``q`` (4, 5) into ``jacobian`` (3, 5)."""
    wrist_jacobian_one(q[0], lengths[0], lengths[1], lengths[2], lengths[3], jacobian)


@kernel
def _mirror_one(theta1, point):
    """``Ry(theta_1) M Ry(-theta_1) p``: ``p`` mirrored in the torso's mid-plane at theta_1."""
    c, s = cos(2.0 * theta1), sin(2.0 * theta1)
    return (-c * point[0] + s * point[2], point[1], s * point[0] + c * point[2])


@kernel
def _best_one(wrist, thetas, phis, lengths, signs, limits, within, dual, q, jacobians):
    """``(best, reached)``: best ``w`` at a right-problem ``wrist`` over ``thetas`` x ``phis`` (theta_1, phi).

    ``best`` is the largest ``w`` ([001 eq. 5.3]; the stacked dual measure if
    ``dual``) of the postures that exist and, if ``within``, respect the
    limits (-inf if none); ``reached`` says some posture exists.  With
    ``dual`` the second arm is the left arm in the symmetric posture: at
    theta_1 ``t`` its right problem has theta_1 ``-t`` and the wrist
    ``M mirror(t, W)`` (``M``: x -> -x); ``signs``, ``limits`` (2, 2, 5) and
    the scratch arrays ``q`` (2, 4, 5) and ``jacobians`` (2, 3, 5) hold both arms.
    """
    best, reached = -inf, False
    kind = int(ANY_BASIS)  # not a literal: the compiled _circle_stage of the state kernel serves
    for t in thetas:
        circle, e1, status = _circle_stage(lengths, kind, (0.0, 1.0, 0.0), t, wrist)
        if status != OK:  # the wrist is out of reach at this theta_1, whatever phi
            continue
        left, circle_left, e1_left = wrist, circle, e1
        if dual:
            left = _mirror_one(t, wrist)
            left = (-left[0], left[1], left[2])
            circle_left, e1_left, status = _circle_stage(lengths, kind, (0.0, 1.0, 0.0), -t, left)
            if status != OK:
                continue
        reached = True
        for phi in phis:
            usable = _elbow_stage(lengths, signs[0], limits[0], t, wrist, circle, e1, phi, q[0]) or not within
            if dual and usable:
                usable = _elbow_stage(lengths, signs[1], limits[1], -t, left, circle_left, e1_left, phi, q[1]) \
                    or not within
            if usable:
                _jacobian_of(lengths, q[0], jacobians[0])
                if dual:
                    _jacobian_of(lengths, q[1], jacobians[1])
                    best = max(best, dual_one(jacobians[0], jacobians[1]))
                else:
                    best = max(best, gram_one(jacobians[0]))
    return best, reached


@kernel
def _best_points(start, stop, points, thetas, phis, lengths, signs, limits, within, dual, best, reached):
    """:func:`_best_one` for each of ``points`` (N, 3) -> ``best`` (N,), ``reached`` (N,) bool."""
    q, jacobians = np.empty((2, 4, 5)), np.empty((2, 3, 5))
    for i in range(start, stop):
        best[i], reached[i] = _best_one(row(points, i), thetas, phis, lengths, signs, limits, within, dual, q,
                                        jacobians)


@kernel
def states(start, stop, points, theta1, defined, phi, lengths, sign, limits, kind, vector, jacobian, status, feasible):
    """:func:`_posture_one` for each item: ``points`` (N, 3), ``theta1``, ``phi`` (N,), ``defined`` (N,) bool
    -> ``jacobian`` (N, 3, 5), ``status`` (N,) (SHOULDER_UNDEFINED where not ``defined``), ``feasible`` (N,)."""
    q = np.empty((4, 5))
    for i in range(start, stop):
        _state_item(points, theta1, defined, phi, lengths, sign, limits, kind, vector, jacobian, status, feasible, q, i)


@kernel
def _state_item(points, theta1, defined, phi, lengths, sign, limits, kind, vector, jacobian, status, feasible, q, i):
    t = theta1[i] if defined[i] else 0.0
    code, feasible[i] = _posture_one(lengths, sign, limits, kind, (vector[0], vector[1], vector[2]), t,
                                    row(points, i), phi[i], q)
    _jacobian_of(lengths, q, jacobian[i])
    status[i] = code if defined[i] else SHOULDER_UNDEFINED


@kernel
def _mirrors(start, stop, theta1, points, out):
    """:func:`_mirror_one` for each item: ``theta1`` (N,), ``points`` (N, 3) -> ``out`` (N, 3)."""
    for i in range(start, stop):
        put(out, i, _mirror_one(theta1[i], row(points, i)))


# ----------------------------------------------------------------- wrappers
def _lengths(arm: TorsoArm) -> np.ndarray:
    return np.array([arm.L0, arm.L1, arm.forearm, arm.delta])


def _limits(arm: TorsoArm) -> np.ndarray:
    """The side's limits of joints 1-5, (2, 5)."""
    chain = arm.chain
    return np.ascontiguousarray(np.stack([chain.lower[:5], chain.upper[:5]]))


def _sign(arm: TorsoArm) -> float:
    return 1.0 if arm.side == "right" else -1.0


@dataclass(frozen=True)
class _ArmState:
    jacobian: np.ndarray  # world, (..., 3, 5)
    status: np.ndarray
    feasible: np.ndarray  # some branch within limits


def _arm_state(arm: TorsoArm, right_points: np.ndarray, theta1: np.ndarray, defined: np.ndarray,
               phi: np.ndarray, reference: ElbowReference | None) -> _ArmState:
    """Wrist Jacobian (in the side's world), IK status and limit feasibility of ``arm`` at right-problem points
    and theta_1 (where ``defined``), for ``reference`` given in the side's world (None: any basis)."""
    shape, (points, t1, ok, angle) = flat((right_points, 1), (theta1, 0), (defined, 0), (phi, 0))
    count = points.shape[0]
    if reference is None:
        kind, vector = ANY_BASIS, np.zeros(3)
    else:
        reference = reference.mirrored() if arm.side == "left" else reference
        kind, vector = (VECTOR if reference.kind == "vector" else THETA4), np.array(reference.vector)
    jacobian, status, feasible = np.empty((count, 3, 5)), np.empty(count, dtype=np.int64), np.empty(count, dtype=bool)
    run_batch(states, count, points, t1, ok.astype(bool), angle, _lengths(arm), _sign(arm),
              _limits(arm), kind, vector, jacobian, status, feasible)
    if arm.side == "left":  # the mirror image's Jacobian: rows x -> -x, theta_1 column in the left's sense
        jacobian = MIRROR @ jacobian * np.array([-1.0, 1.0, 1.0, 1.0, 1.0])
    return _ArmState(jacobian.reshape(shape + (3, 5)), status.reshape(shape), feasible.reshape(shape))


def _finish(grid: PlaneGrid, values: np.ndarray, status: np.ndarray, feasible: np.ndarray,
            within_limits: bool, description: str) -> ManipulabilityMap:
    valid = (status == OK) & (feasible if within_limits else True)
    return ManipulabilityMap(grid, np.where(valid, values, np.nan), valid, status, description)


def _fixed_angles(shoulder_angle: float, elbow_angle: float) -> tuple[float, float]:
    psi, phi = float(shoulder_angle), float(elbow_angle)
    if not (np.isfinite(psi) and np.isfinite(phi)):
        raise RedkinError(f"shoulder and elbow angles must be finite, got {psi!r}, {phi!r}")
    return psi, phi


def manipulability_map(
    arm: TorsoArm,
    grid: PlaneGrid,
    shoulder_angle: float,
    elbow_angle: float,
    reference: ElbowReference | str | ArrayLike | None = None,
    within_limits: bool = True,
) -> ManipulabilityMap:
    """``w`` [001 eq. 5.3] of one arm over ``grid`` at fixed ``(psi, phi)`` (sections 3.2-3.3), a posture per point."""
    psi, phi = _fixed_angles(shoulder_angle, elbow_angle)
    ref = as_reference(reference)
    right_points = arm.to_right(grid.points)
    theta1, defined = theta1_from_shoulder_angle(np.full(grid.points.shape[:-1], psi), right_points)
    state = _arm_state(arm, right_points, theta1, defined, np.asarray(phi), ref)
    return _finish(grid, gram_manipulability(state.jacobian), state.status, state.feasible, within_limits,
                   f"{arm.side} arm, psi = {np.degrees(psi):g} deg, phi = {np.degrees(phi):g} deg "
                   f"({ref.kind} reference)")


def sweep_samples(arm: TorsoArm, samples: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The redundancy samples of a best map: ``samples = (n1, n2)``, each ``1..MAX_SWEEP_SAMPLES``.

    Returns
    -------
    theta1 : numpy.ndarray, shape (n1,)
        The arm's joint 1 evenly across its limits (clipped to one turn), ends included (the middle if n1 = 1).
    phi : numpy.ndarray, shape (n2,)
        The elbow angle evenly around the circle from -pi.
    """
    if np.ndim(samples) != 1 or len(samples) != 2:
        raise RedkinError(f"samples must be two positive integers (theta_1, phi), got {samples!r}")
    n1, n2 = (check_count(n, "samples", 1, MAX_SWEEP_SAMPLES) for n in samples)
    lower, upper = arm.chain.lower[0], arm.chain.upper[0]
    lower, upper = (max(lower, -np.pi), min(upper, np.pi))
    theta1 = np.linspace(lower, upper, n1) if n1 > 1 else np.array([(lower + upper) / 2])
    return theta1, np.linspace(-np.pi, np.pi, n2, endpoint=False)


def _check_total(points: int, samples: tuple[int, int]) -> None:
    total = points * samples[0] * samples[1]
    if total > _MAX_MAP_POSTURES:
        raise RedkinError(f"{points} grid points x {samples[0]} x {samples[1]} samples = {total} postures; at most "
                          f"{_MAX_MAP_POSTURES} are allowed (about a minute on two cores)")


def best_over_redundancy(
    arm: TorsoArm,
    points: ArrayLike,
    samples: tuple[int, int] = (24, 24),
    within_limits: bool = True,
    dual: bool = False,
    progress: Progress | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Best ``w`` over the redundancy at wrist positions: max over theta_1 x phi samples (chapter 5).

    theta_1 is swept across its limits (within one turn; equivalent to a
    sweep of psi, a monotone function of theta_1, section 3.2) and phi
    around the whole elbow circle (section 3.3), so the elbow reference
    does not matter.

    Parameters
    ----------
    arm : TorsoArm
        The arm; with ``dual``, the right arm of the symmetric two-arm posture (``arm.side`` must be "right").
    points : array_like, shape (..., 3)
        Wrist positions in the arm's world, metres (the right wrist's with ``dual``).
    samples : (int, int)
        theta_1 and phi samples, 1 to :data:`MAX_SWEEP_SAMPLES` each.
    within_limits : bool
        Count only postures where some branch respects the limits of joints 1-5.
    dual : bool
        The stacked dual-arm measure (:func:`~redkin.torso_arm.manipulability.stacked_dual_manipulability`)
        of the symmetric posture instead of one arm's ``w`` [001 eq. 5.3].
    progress : callable, optional
        ``progress(fraction)`` as the points are done.

    Returns
    -------
    best : numpy.ndarray, shape (...)
        m^3 for one arm, m^6 for both; NaN where no sampled posture counts.
    reached : numpy.ndarray of bool, shape (...)
        Some sampled posture exists (limits aside).
    """
    wrists = check_vectors(points, 3, "points")
    if dual and arm.side != "right":
        raise RedkinError(f"the dual-arm measure is indexed by the right wrist: arm must be the right arm, "
                          f"got {arm.side!r}")
    thetas, phis = sweep_samples(arm, samples)
    shape, (flat_points,) = flat((arm.to_right(wrists), 1))
    count = flat_points.shape[0]
    left = TorsoArm(arm.right_chain, "left")
    signs = np.array([_sign(arm), -1.0])
    limits = np.ascontiguousarray(np.stack([_limits(arm), _limits(left)]))
    thetas = np.ascontiguousarray(thetas * _sign(arm))  # the right problem's theta_1
    best, reached = np.empty(count), np.empty(count, dtype=bool)
    step = count if progress is None else max(PARALLEL_BATCH, -(-count // _PROGRESS_STEPS))
    for start in range(0, count, step):
        part = slice(start, min(count, start + step))
        run_batch(_best_points, part.stop - start, flat_points[part], thetas, phis,
                  _lengths(arm), signs, limits, bool(within_limits), bool(dual), best[part], reached[part])
        if progress is not None:
            progress(part.stop / count)
    best[~np.isfinite(best)] = np.nan
    return best.reshape(shape), reached.reshape(shape)


def best_manipulability_map(
    arm: TorsoArm,
    grid: PlaneGrid,
    samples: tuple[int, int] = (24, 24),
    within_limits: bool = True,
    progress: Progress | None = None,
) -> ManipulabilityMap:
    """Best ``w`` over the redundancy (:func:`best_over_redundancy`) on ``grid``."""
    thetas, phis = sweep_samples(arm, samples)
    _check_total(grid.points[..., 0].size, (thetas.size, phis.size))
    best, reached = best_over_redundancy(arm, grid.points, samples, within_limits, progress=progress)
    return _best_map(grid, best, reached, f"{arm.side} arm, best over theta_1 x phi = {samples[0]} x {samples[1]} "
                     "samples" + (" within limits" if within_limits else ""))


def _best_map(grid: PlaneGrid, best: np.ndarray, reached: np.ndarray, description: str) -> ManipulabilityMap:
    found = np.isfinite(best)
    return ManipulabilityMap(grid, best, found, np.where(reached, OK, UNREACHABLE), description)


def _torso_mirror(theta1: ArrayLike, points: ArrayLike) -> np.ndarray:
    """Mirror ``points`` (..., 3) in the torso's mid-plane ``Ry(theta_1) {x = 0}``: ``Ry(theta_1) M Ry(-theta_1) p``."""
    shape, (t1, p) = flat((theta1, 0), (points, 1))
    out = np.empty((p.shape[0], 3))
    run_batch(_mirrors, p.shape[0], t1, p, out)
    return out.reshape(shape + (3,))


def _dual_states(right: TorsoArm, points: np.ndarray, theta1: np.ndarray, defined: np.ndarray,
                 phi: np.ndarray, reference: ElbowReference | None) -> tuple[_ArmState, _ArmState]:
    """Both arms of the symmetric posture at right wrists ``points`` and the right arm's theta_1."""
    left = TorsoArm(right.right_chain, "left")
    theta1 = np.where(defined, theta1, 0.0)
    a = _arm_state(right, points, theta1, defined, phi, reference)
    b = _arm_state(left, left.to_right(_torso_mirror(theta1, points)), -theta1, defined, phi, reference)
    return a, b


def dual_arm_map(
    grid: PlaneGrid,
    shoulder_angle: float,
    elbow_angle: float,
    reference: ElbowReference | str | ArrayLike | None = None,
    measure: DualMeasure = stacked_dual_manipulability,
    within_limits: bool = True,
    right: TorsoArm | None = None,
) -> ManipulabilityMap:
    """Dual-arm ``measure`` over the right wrist position, in the symmetric two-arm posture.

    The left arm is the mirror image of the right arm in the torso's
    mid-plane (same joints 2-5, theta_1 shared), so its wrist is at
    :func:`_torso_mirror` of the grid point; theta_1 comes from the right
    arm's psi.  (Both wrists at one point is impossible within the limits:
    theta_3 >= -5 deg keeps each wrist at least ~17 mm on its own side of the
    mid-plane.)  ``measure(J_right, J_left)`` receives the two world
    ``(..., 3, 5)`` Jacobians w.r.t. (theta_1, q2..q5).
    """
    psi, phi = _fixed_angles(shoulder_angle, elbow_angle)
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
    """Best dual-arm ``measure`` (symmetric posture, see :func:`dual_arm_map`) over theta_1 x phi samples.

    The stacked measure runs compiled (:func:`best_over_redundancy` with
    ``dual``); another ``measure`` is evaluated on the two arms' Jacobians,
    one theta_1 sample at a time.
    """
    right = right or humanoid_arm("right")
    thetas, phis = sweep_samples(right, samples)
    _check_total(grid.points[..., 0].size, (thetas.size, phis.size))
    description = (f"both arms (symmetric posture), best over theta_1 x phi = {samples[0]} x {samples[1]} samples"
                   + (" within limits" if within_limits else ""))
    if measure is stacked_dual_manipulability:
        best, reached = best_over_redundancy(right, grid.points, samples, within_limits, dual=True, progress=progress)
        return _best_map(grid, best, reached, description)
    points = np.broadcast_to(grid.points[..., None, :], grid.points.shape[:-1] + (phis.size, 3))
    best = np.full(grid.points.shape[:-1], -np.inf)
    reached = np.zeros(grid.points.shape[:-1], bool)
    for index, theta1 in enumerate(thetas):
        a, b = _dual_states(right, points, np.full(points.shape[:-1], theta1), np.ones(points.shape[:-1], bool),
                            phis, None)
        ok = (a.status == OK) & (b.status == OK)
        usable = (a.feasible & b.feasible) if within_limits else ok
        best = np.maximum(best, np.max(np.where(usable, measure(a.jacobian, b.jacobian), -np.inf), axis=-1))
        reached |= np.any(ok, axis=-1)
        if progress is not None:
            progress((index + 1) / thetas.size)
    return _best_map(grid, np.where(np.isfinite(best), best, np.nan), reached, description)


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
        raise RedkinError(f"threshold must be a finite number >= 0, got {threshold!r}")
    mask = result.valid & (np.nan_to_num(result.values, nan=-1.0) >= threshold)
    count = int(result.valid.sum())
    return Region(mask, float(mask.sum()) * result.grid.cell_area, mask.sum() / count if count else 0.0, threshold)
