"""Nearly S-R-S arms: arm-angle IK on the real arm through its exact neighbour (docs/srs.md, "Nearly S-R-S arms").

A description whose axes miss the S-R-S conditions by a few millimetres (the
Kinova Gen3's 11.75 mm and 12.75 mm, the ROS-Industrial iiwa's 0.436 mm, a
URDF with rounded angles) has an exact S-R-S **neighbour**
(:func:`redkin.srs.conventions.neighbour_form`): its shoulder and wrist axes
moved through their meeting points, right angles restored, the offsets it
does not have dropped.  The neighbour has paper 000's closed form; the real
arm does not.

The arm angle of the real arm at ``q`` is the neighbour's arm angle at the
same joint values, ``psi(q) = psi_N(q)`` [000 eqs. 5-8]: the elbow's turn
about the shoulder-wrist line, with the shoulder and wrist the meeting points
of the real axis groups.  It is continuous wherever the neighbour's is, and
equals the exact arm angle where the offsets vanish.

Solutions at ``psi``: the neighbour's closed form maps a pose ``T'`` to
``q = IK_N(T', psi)`` on each branch, with ``psi_N(q) = psi`` exactly; the
real arm's pose of that ``q`` is ``G(T') = FK(q)``, near ``T'`` by the model
error.  The target ``T'`` is corrected until ``G(T') = T``: ``T' <- T G(T')^-1 T'``,
a fixed-point iteration whose rate is about the model error over the
lengths of the arm (a few per cent on the Gen3), so a dozen steps reach 1e-9.
Each returned solution is certified on the real chain: its FK within
:data:`TOLERANCE` of the target, and its arm angle within :data:`TOLERANCE` of
``psi``.  A branch whose iteration does not settle (near the stretched elbow,
where the closed form's sensitivity outgrows the contraction) is reported
missing, never returned inaccurate.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_finite, check_pose
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.srs import _nearly_kernels
from redkin.srs.arm_angle import arm_angle_of
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.conventions import departures, model_error, neighbour_form
from redkin.srs.geometry import SRSGeometry, srs_geometry

#: Largest departure (metres between axes that must meet, radians off perpendicular) of a nearly S-R-S arm from
#: its neighbour by default: the Kinova Gen3's 12.75 mm and Jaco2's 11.4 mm are inside, the Panda's 88 mm outside.
TOLERANCE_DEFAULT = 0.02
#: The certificate of a solution: position error [m], rotation angle [rad] and arm-angle error [rad].
TOLERANCE = 1e-9
#: Damped Newton steps on the real arm where the corrections (:mod:`redkin.srs._nearly_kernels`) did not settle.
_NEWTON_ITERATIONS = 30
#: How far from its stretch a Newton start's elbow is opened [rad] (:func:`_elbow_opened`).
_OPENED = 0.05


@dataclass(frozen=True)
class NearlySRS:
    """A nearly S-R-S arm, its exact neighbour and how far apart they are.

    Attributes
    ----------
    chain : SerialChain
        The real arm.
    neighbour : SerialChain
        Its exact S-R-S neighbour in paper 000 Table 1 form, with the real arm's joint values and limits.
    geometry : SRSGeometry
        The neighbour's arm-angle geometry.
    departures : tuple of (str, float, str)
        What was dropped, largest first (:func:`redkin.srs.conventions.departures`).
    position_error, rotation_error : float
        The largest pose difference of the two chains over sample configurations [m, rad].
    """

    chain: SerialChain
    neighbour: SerialChain
    geometry: SRSGeometry
    departures: tuple[tuple[str, float, str], ...]
    position_error: float
    rotation_error: float

    @cached_property
    def kernel_reach(self) -> np.ndarray:
        """The neighbour's reach as :func:`redkin.srs._nearly_kernels.within_reach` takes it: the shortest and
        longest shoulder-wrist distance [000 eq. 11], moved inside by a relative 1e-9, ``d_7`` and the shoulder."""
        geometry = self.geometry
        base = geometry.chain.base
        elbow = geometry.elbow_equation
        low = np.sqrt(max(elbow.mean - elbow.amplitude, 0.0)) * (1.0 + 1e-9)
        high = np.sqrt(elbow.mean + elbow.amplitude) * (1.0 - 1e-9)
        shoulder = base[:3, :3] @ np.array([0.0, 0.0, geometry.d_bs]) + base[:3, 3]
        return np.concatenate([[low, high, geometry.d_wt], shoulder])

    @cached_property
    def kernel_tool_inverse(self) -> np.ndarray:
        """The inverse of the neighbour's tool transform."""
        return np.ascontiguousarray(np.linalg.inv(self.geometry.chain.tool))

    def describe(self) -> str:
        """The neighbour and the model error in one line, in millimetres as users give offsets."""
        dropped = ", ".join(f"{what} {value * 1e3:.4g} mm" if unit == "m" else f"{what} {np.degrees(value):.3g} deg"
                            for what, value, unit in self.departures)
        return (f"its exact S-R-S neighbour drops: {dropped}; poses differ by up to {self.position_error * 1e3:.3g} mm "
                f"and {np.degrees(self.rotation_error):.3g} deg, and solutions are polished on the real arm")


class NearlySolutions(NamedTuple):
    """Certified solutions of a nearly S-R-S arm at arm angles, one row per branch.

    Attributes
    ----------
    q : numpy.ndarray, shape (..., B, 7)
        Joint values of the real arm (zeros where a branch is missing).
    exists : numpy.ndarray of bool, shape (..., B)
        Found and certified (FK and arm angle within :data:`TOLERANCE`).
    within_limits : numpy.ndarray of bool, shape (..., B)
    branches : tuple of Branch
    parameter : str
        ``"psi"``.
    """

    q: np.ndarray
    exists: np.ndarray
    within_limits: np.ndarray
    branches: tuple[Branch, ...]
    parameter: str = "psi"


def nearly_srs(chain: SerialChain, tolerance: float = TOLERANCE_DEFAULT) -> NearlySRS:
    """The exact neighbour of a chain whose axes miss the S-R-S conditions by at most ``tolerance``.

    Derived once per chain and tolerance and cached on the chain.

    Raises
    ------
    NotArmAngleClassError
        For a departure beyond ``tolerance``, naming it.
    """
    if not (np.isfinite(tolerance) and tolerance > 0.0):
        raise RedkinError(f"tolerance must be a positive finite number, got {tolerance!r}")
    cache = chain.__dict__.setdefault(_CACHE_KEY, {})
    if tolerance not in cache:
        neighbour = neighbour_form(chain, tolerance)
        position, rotation = model_error(chain, neighbour)
        dropped = tuple(departures(chain, tolerance))
        cache[tolerance] = NearlySRS(chain, neighbour, srs_geometry(neighbour), dropped, position, rotation)
    return cache[tolerance]


_CACHE_KEY = "_nearly_srs"


def arm_angle(arm: NearlySRS, q: ArrayLike) -> np.ndarray:
    """The real arm's arm angle at joint values ``q`` (..., 7): the neighbour's at the same values (module
    docstring)."""
    return arm_angle_of(arm.geometry, q).psi


def ik(
    arm: NearlySRS,
    pose: ArrayLike,
    psi: ArrayLike,
    branch: str | Branch | tuple[int, int, int] | None = None,
) -> NearlySolutions:
    """Every solution (or one branch's) of target poses at arm angles on the real arm, certified.

    Parameters
    ----------
    arm : NearlySRS
        From :func:`nearly_srs`.
    pose : array_like, shape (..., 4, 4)
        Target poses of the real arm's tool in its base frame.
    psi : array_like, broadcast against the poses' batch shape
        Arm angles (:func:`arm_angle`).
    branch : str or Branch, optional
        One branch; default all eight, in the order of :data:`redkin.srs.BRANCHES`.

    Raises
    ------
    ValueError
        For a malformed pose, psi or branch.
    """
    chosen = BRANCHES if branch is None else (parse_branch(branch),)
    poses = check_pose(pose)
    angles = as_float_array(psi, "psi")
    check_finite(angles, "psi")
    try:
        shape = np.broadcast_shapes(poses.shape[:-2], angles.shape)
    except ValueError:
        raise RedkinError(f"psi of shape {angles.shape} does not broadcast against the pose batch "
                          f"{poses.shape[:-2]}") from None
    target = kernel_array(poses, shape + (4, 4)).reshape(-1, 4, 4)
    angles = kernel_array(angles, shape).reshape(-1)
    count = len(target)
    signs = np.ascontiguousarray([arm.geometry.kernel_branch(label)[0] for label in chosen])
    q = np.zeros((count, len(chosen), 7))
    error = np.empty((count, len(chosen), 2))
    run_batch(_nearly_kernels.settle, count, target, angles, signs, *arm.geometry.kernel_tables, arm.chain._links,
              arm.chain._ends, arm.chain._standard, arm.kernel_tool_inverse, arm.kernel_reach, q, error)
    exists = np.all(error <= TOLERANCE, axis=-1)
    for column in range(len(chosen)):  # Newton where the corrections did not settle
        rows = np.flatnonzero(~exists[:, column])
        for start in ("best iterate", "elbow opened"):
            if rows.size == 0:
                break
            signs_b = signs[column:column + 1]
            guess = q[rows, column] if start == "best iterate" else _elbow_opened(arm, q[rows, column], signs_b)
            polished, settled = _newton(arm, guess, target[rows], angles[rows], signs_b)
            q[rows[settled], column], exists[rows[settled], column] = polished[settled], True
            rows = rows[~settled]
    exists &= _certified(arm, q, target, angles)
    q[~exists] = 0.0
    within = exists & arm.chain.within_limits(q, tolerance=1e-9, wrap=True)
    return NearlySolutions(q.reshape(shape + q.shape[1:]), exists.reshape(shape + exists.shape[1:]),
                           within.reshape(shape + within.shape[1:]), tuple(chosen))


def _certified(arm: NearlySRS, q: np.ndarray, target: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """The certificate of joint values (N, B, 7) as returned: their pose within :data:`TOLERANCE` of the targets
    (N, 4, 4) and their arm angle of ``psi`` (N,)."""
    count, branches = q.shape[:2]
    flat = q.reshape(-1, 7)
    goals = np.repeat(target, branches, axis=0)
    position, rotation = _pose_error(arm.chain.fk(flat), goals)
    angle = np.abs(_wrapped(arm_angle(arm, flat) - np.repeat(psi, branches)))
    return ((position <= TOLERANCE) & (rotation <= TOLERANCE) & (angle <= TOLERANCE)).reshape(count, branches)


def _elbow_opened(arm: NearlySRS, q: np.ndarray, signs: np.ndarray) -> np.ndarray:
    """Joint values (N, 7) with the elbow opened to at least :data:`_OPENED` rad from the neighbour's stretched (or
    folded) elbow, on the side of the branch ``signs``: near the stretch the iterate lies where the arm angle's
    gradient vanishes, a start from which Newton's steps go nowhere."""
    theta = arm.geometry.theta_of_q(q)
    phase = arm.geometry.elbow_equation.phase
    theta[:, 3] = phase + signs[0, 1] * np.maximum(np.abs(_wrapped(theta[:, 3] - phase)), _OPENED)
    return arm.geometry.q_of_theta(theta)


def _newton(arm: NearlySRS, q: np.ndarray, target: np.ndarray, psi: np.ndarray,
            signs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Damped Newton steps on the real arm for the 7 equations ``FK(q) = T`` and ``psi(q) = psi`` from ``q``
    (N, 7), the arm angle's gradient by central differences; joint values and whether each settled on the
    branch ``signs`` (Table 1 signs, (1, 3))."""
    step = 1e-7
    q = q.copy()
    active = np.arange(len(q))  # rows still stepping: not yet at rounding, not diverging
    first = np.full(len(q), np.inf)
    for _ in range(_NEWTON_ITERATIONS):
        if active.size == 0:
            break
        now = q[active]
        reached = arm.chain.fk(now)
        residual = np.concatenate([_pose_residual(reached, target[active]),
                                   _wrapped(psi[active] - arm_angle(arm, now))[:, None]], axis=-1)
        size = np.linalg.norm(residual, axis=-1)
        first[active] = np.minimum(first[active], np.where(np.isinf(first[active]), size, np.inf))
        keep = (size > _nearly_kernels.FINE) & (size <= 10.0 * first[active])  # on to rounding; drop a divergence
        active, now, residual = active[keep], now[keep], residual[keep]
        if active.size == 0:
            break
        jacobian = np.empty((len(now), 7, 7))
        jacobian[:, :6] = arm.chain.jacobian(now)
        moved = np.repeat(now[None], 14, axis=0)  # the 14 central-difference rows of every joint, in one call
        for j in range(7):
            moved[2 * j, :, j] += step
            moved[2 * j + 1, :, j] -= step
        angles = arm_angle(arm, moved).reshape(7, 2, len(now))
        jacobian[:, 6, :] = (_wrapped(angles[:, 0] - angles[:, 1]) / (2.0 * step)).T
        damping = 0.05 * np.sum(residual * residual, axis=-1)[:, None, None] * np.eye(7) + 1e-12 * np.eye(7)
        transposed = np.swapaxes(jacobian, -1, -2)
        q[active] = now + np.linalg.solve(transposed @ jacobian + damping, (transposed @ residual[..., None]))[..., 0]
    reached = arm.chain.fk(q)
    position, rotation = _pose_error(reached, target)
    settled = (position <= TOLERANCE) & (rotation <= TOLERANCE) & (np.abs(_wrapped(psi - arm_angle(arm, q)))
                                                                    <= TOLERANCE)
    theta = arm.geometry.theta_of_q(q)
    same = np.all(_branch_signs(arm, theta) == signs[0], axis=-1)
    return q, settled & same


def _branch_signs(arm: NearlySRS, theta: np.ndarray) -> np.ndarray:
    """Table 1 branch signs (N, 3) of DH angles (N, 7) of the neighbour."""
    from redkin.srs.branches import branch_of_theta

    return branch_of_theta(theta, arm.geometry.elbow_equation.phase)


def _pose_residual(reached: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``[p_t - p; rotation vector of R_t R^T]`` (N, 6), the world-referred pose error of Newton's step."""
    relative = target[:, :3, :3] @ np.swapaxes(reached[:, :3, :3], -1, -2)
    skew = np.stack([relative[:, 2, 1] - relative[:, 1, 2], relative[:, 0, 2] - relative[:, 2, 0],
                     relative[:, 1, 0] - relative[:, 0, 1]], axis=-1)
    size = np.linalg.norm(skew, axis=-1)
    angle = np.arctan2(0.5 * size, 0.5 * (np.trace(relative, axis1=-2, axis2=-1) - 1.0))
    scale = np.where(size > 0.0, angle / np.where(size > 0.0, size, 1.0), 0.5)
    return np.concatenate([target[:, :3, 3] - reached[:, :3, 3], scale[:, None] * skew], axis=-1)


def _wrapped(angle: np.ndarray) -> np.ndarray:
    """Angles into ``(-pi, pi]``."""
    return np.angle(np.exp(1j * angle))


def _pose_error(reached: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error [m] and rotation angle [rad] of poses (N, 4, 4) against targets."""
    position = np.linalg.norm(reached[:, :3, 3] - target[:, :3, 3], axis=-1)
    relative = np.einsum("nji,njk->nik", target[:, :3, :3], reached[:, :3, :3])
    skew = np.stack([relative[:, 2, 1] - relative[:, 1, 2], relative[:, 0, 2] - relative[:, 2, 0],
                     relative[:, 1, 0] - relative[:, 0, 1]], axis=-1)
    cosine = 0.5 * (np.trace(relative, axis1=-2, axis2=-1) - 1.0)
    return position, np.arctan2(0.5 * np.linalg.norm(skew, axis=-1), cosine)
