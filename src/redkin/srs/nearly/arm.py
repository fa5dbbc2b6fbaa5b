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
error.  A few corrections of the target, ``T' <- T G(T')^-1 T'``, bring it
within a few per cent of the model error; damped Newton steps on the real
arm for the 7 equations ``FK(q) = T``, ``psi(q) = psi`` (the arm angle's
gradient in closed form) then take it to rounding.  All of it, for every
branch of a pose, is one compiled call (:mod:`redkin.srs.nearly._kernels`).

A branch is named by the real arm's own signs, as an exact arm's are: those of
``theta_2``, of ``theta_4`` minus the real arm's stretched elbow
(:attr:`NearlySRS.real_phase`) and of ``theta_6``, ``theta`` the neighbour's
Table 1 angles at the same joint values.  A row holds at most one solution, of
its own branch; where the real arm has two on one branch (near the stretched
elbow, or near ``theta_2 = +-pi``), one is returned
(:func:`redkin.srs.nearly.self_motion.branch_solutions` gives both).  Each returned solution
is certified on the real chain: its FK within :data:`TOLERANCE` of the
target, and its arm angle within :data:`TOLERANCE` of ``psi``.  A branch
whose solution is not found is reported missing, never returned inaccurate.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin import _chain_kernels
from redkin._compiled import kernel_array, run_batch
from redkin._validation import check_pose
from redkin.chain import Reach, SerialChain
from redkin.circle import HALF_PI, wrap_angle
from redkin.errors import RedkinError
from redkin.srs._ik_kernels import A4, BAD_POSE, D_EW
from redkin.srs._targets import as_poses, check_psi, raise_for_bad_pose
from redkin.srs.branches import BRANCHES, Branch, branch_of_theta, parse_branch
from redkin.srs.conventions import ROUNDING_ROTATION, departures, model_error, neighbour_form
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.srs.nearly import _kernels as _nearly_kernels

#: Largest departure (metres between axes that must meet, radians off perpendicular) of a nearly S-R-S arm from
#: its neighbour by default: the Kinova Gen3's 12.75 mm and Jaco2's 11.4 mm are inside, the Panda's 88 mm outside.
TOLERANCE_DEFAULT = 0.02
#: The certificate of a solution: position error [m], rotation angle [rad] and arm-angle error [rad].
TOLERANCE = _nearly_kernels.TOLERANCE


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
    """

    chain: SerialChain
    neighbour: SerialChain
    geometry: SRSGeometry
    departures: tuple[tuple[str, float, str], ...]

    @cached_property
    def _model_error(self) -> tuple[float, float]:
        return model_error(self.chain, self.neighbour)

    @property
    def position_error(self) -> float:
        """The largest position difference [m] of the two chains' tool poses over all joint values
        (:func:`redkin.srs.conventions.model_error`, found on first use and kept on disk)."""
        return self._model_error[0]

    @property
    def rotation_error(self) -> float:
        """The largest rotation angle [rad] between the two chains' tool poses over all joint values."""
        return self._model_error[1]

    @cached_property
    def kernel_reach(self) -> np.ndarray:
        """The neighbour's reach as :func:`redkin.srs.nearly._kernels.within_reach` takes it: the shortest and
        longest shoulder-wrist distance [000 eq. 11], moved inside by a relative 1e-9, ``d_7`` and the shoulder."""
        geometry = self.geometry
        base = geometry.chain.base
        elbow = geometry.elbow_equation
        low = np.sqrt(max(elbow.mean - elbow.amplitude, 0.0)) * (1.0 + 1e-9)
        high = np.sqrt(elbow.mean + elbow.amplitude) * (1.0 - 1e-9)
        shoulder = base[:3, :3] @ np.array([0.0, 0.0, geometry.d_bs]) + base[:3, 3]
        return np.concatenate([[low, high, geometry.d_wt], shoulder])

    @cached_property
    def kernel_real(self) -> tuple[np.ndarray, np.ndarray, bool]:
        """The real chain as :mod:`redkin._chain_kernels` takes it: links, ends and whether it is standard DH."""
        return self.chain._links, self.chain._ends, self.chain._standard

    @cached_property
    def kernel_model(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The neighbour as :func:`redkin.srs.nearly._kernels.arm_angle_one` takes it: its links and ends (standard
        DH, Table 1 form) and its kernel arm and ends (:mod:`redkin.srs._ik_kernels`)."""
        neighbour = self.neighbour
        return neighbour._links, neighbour._ends, self.geometry.kernel_arm, self.geometry.kernel_ends

    @cached_property
    def real_phase(self) -> float:
        """The real arm's stretched elbow as the neighbour's ``theta_4`` [rad]: where the distance of a point of
        axis 3 (its nearest to axis 2) from a point of axis 5 (its nearest to axis 6), ``C + R cos(theta_4 -
        phase)`` as joint 4 turns, is largest.  The neighbour's own phase where its offsets vanish."""
        chain, offset, sign = self.chain, self.neighbour.offset[3], self.neighbour.sign[3]
        angles = np.array([0.0, HALF_PI, np.pi])  # theta_4 of the neighbour; the other joints at zero
        q = np.zeros((3, 7))
        q[:, 3] = sign * (angles - offset)
        frames = chain.frames(q)
        axes = frames[..., :chain.n, :3, 2] if chain._standard else frames[..., 1:chain.n + 1, :3, 2]
        origins = frames[..., :chain.n, :3, 3] if chain._standard else frames[..., 1:chain.n + 1, :3, 3]
        shoulder = _nearest_on(origins[:, 2], axes[:, 2], origins[:, 1], axes[:, 1])
        wrist = _nearest_on(origins[:, 4], axes[:, 4], origins[:, 5], axes[:, 5])
        squared = np.sum((shoulder - wrist) ** 2, axis=-1)  # C + A cos + B sin at 0, pi/2, pi
        mean = 0.5 * (squared[0] + squared[2])
        return float(np.arctan2(squared[1] - mean, squared[0] - mean))

    @cached_property
    def kernel_bounds(self) -> np.ndarray:
        """The constants of the certified self-motion (:mod:`redkin.srs.nearly._self_motion_kernels`, docs/srs.md eqs.
        [C3] and [C5]): the position rows' scale ``c`` (2 over the longest lever arm); ``K``, the Frobenius norm of
        bounds of the 343 third derivatives of ``F``: ``c rho_max(i, j, m)`` for the position rows (``rho_k`` the
        lengths of the links after joint ``k``, the tool's included: no point of the tool lies farther from joint
        ``k``'s axis) and 1 for the rotation rows (the module docstring of
        :mod:`redkin.srs.nearly._self_motion_kernels`); for the arm angle's gradient joints 1-4's lever arms to the
        neighbour's wrist point (the lengths of the neighbour's links from the joint to the wrist) and the forearm's
        ``hypot(a_4, d_ew)``; last, ``c rho_k`` for each joint
        (:func:`redkin.srs.nearly._self_motion_kernels.third_along`)."""
        links, ends, standard = self.kernel_real
        lengths = np.hypot(links[:, _chain_kernels.A], links[:, _chain_kernels.D])
        tool = float(np.linalg.norm(ends[1][:3, 3]))
        first = 0 if standard else 1  # a modified-DH row's translation comes before its joint's axis
        levers = np.array([lengths[k + first:].sum() + tool for k in range(7)])
        scale = 2.0 / levers[0]
        i, j, m = np.meshgrid(np.arange(7), np.arange(7), np.arange(7), indexing="ij")
        position = np.sum((scale * levers[np.maximum(np.maximum(i, j), m)]) ** 2)
        neighbour = self.neighbour._links
        reaching = np.hypot(neighbour[:, _chain_kernels.A], neighbour[:, _chain_kernels.D])
        wrist = np.array([reaching[k:5].sum() for k in range(4)])
        arm = self.geometry.kernel_arm
        return np.concatenate([[scale, np.sqrt(position + 343.0)], wrist, [np.hypot(arm[A4], arm[D_EW])],
                               scale * levers])

    @cached_property
    def kernel_limits(self) -> np.ndarray:
        """The real chain's limits as :func:`redkin.srs.nearly._kernels.within_limits` takes them, (3, 7): lower
        limits, widths and whether a joint covers the circle."""
        chain = self.chain
        anywhere = chain.covers_circle
        return np.ascontiguousarray([np.where(anywhere, 0.0, chain.lower),
                                     np.where(anywhere, 0.0, chain.upper - chain.lower), anywhere], dtype=float)

    @cached_property
    def kernel_tool_inverse(self) -> np.ndarray:
        """The inverse of the neighbour's tool transform."""
        return np.ascontiguousarray(np.linalg.inv(self.geometry.chain.tool))

    def describe(self) -> str:
        """The neighbour and the model error in one line, in millimetres as users give offsets."""
        dropped = ", ".join(f"{what} {value * 1e3:.4g} mm" if unit == "m" else f"{what} {np.degrees(value):.3g} deg"
                            for what, value, unit in self.departures)
        turned = (f"{np.degrees(self.rotation_error):.3g} deg" if self.rotation_error >= ROUNDING_ROTATION
                  else "not in orientation (to rounding)")
        return (f"its exact S-R-S neighbour drops: {dropped}; poses differ by up to {self.position_error * 1e3:.3g} mm "
                f"and {turned}")


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
        cache[tolerance] = NearlySRS(chain, neighbour, srs_geometry(neighbour), tuple(departures(chain, tolerance)))
    return cache[tolerance]


_CACHE_KEY = "_nearly_srs"
#: The rows of :data:`BRANCHES` as :func:`redkin.srs.nearly._kernels.solve` takes them: all, or one.
_ALL_ROWS = np.arange(len(BRANCHES))
_ROWS = tuple(np.array([row]) for row in range(len(BRANCHES)))


def _nearest_on(point: np.ndarray, direction: np.ndarray, other: np.ndarray, other_direction: np.ndarray) -> np.ndarray:
    """The point of each line ``point + t direction`` (..., 3) nearest the line ``other + s other_direction``; the
    line's own point where the two are parallel."""
    across = point - other
    b = np.sum(direction * other_direction, axis=-1)
    d, e = np.sum(direction * across, axis=-1), np.sum(other_direction * across, axis=-1)
    denominator = 1.0 - b * b
    t = np.where(denominator > 1e-12, (b * e - d) / np.where(denominator > 1e-12, denominator, 1.0), 0.0)
    return point + t[..., None] * direction


def arm_angle(arm: NearlySRS, q: ArrayLike) -> np.ndarray:
    """The real arm's arm angle at joint values ``q`` (..., 7): the neighbour's at the same values (module
    docstring), in ``[-pi, pi]``.

    Raises
    ------
    ValueError
        For joint values of the wrong length or not finite.
    """
    values = arm.chain.check_q(q)
    return _arm_angles(arm, values, False)[0].reshape(values.shape[:-1])


def _arm_angles(arm: NearlySRS, q: np.ndarray, with_gradient: bool) -> tuple[np.ndarray, np.ndarray]:
    """The arm angles (M,) of checked joint values ``q`` (..., 7) flattened to (M, 7), and with ``with_gradient``
    their gradients (M, 7) (:func:`redkin.srs.nearly._kernels.arm_angles`)."""
    flat = np.ascontiguousarray(q, dtype=float).reshape(-1, 7)
    out, gradients = np.empty(len(flat)), np.empty((len(flat), 7))
    run_batch(_nearly_kernels.arm_angles, len(flat), flat, arm.kernel_model, out, gradients, with_gradient)
    return out, gradients


def branch_of(arm: NearlySRS, q: ArrayLike) -> np.ndarray:
    """The branch of joint values ``q`` (..., 7) on the real arm, as an index into :data:`redkin.srs.BRANCHES` (the
    row :func:`ik` gives it): the Table 1 signs of the neighbour's ``theta_2``, ``theta_4`` minus the real arm's
    stretched elbow (:attr:`NearlySRS.real_phase`) and ``theta_6`` at the same joint values.

    Raises
    ------
    ValueError
        For joint values of the wrong length or not finite.
    """
    values = arm.chain.check_q(q)
    signs = branch_of_theta(arm.geometry.theta_of_q(values), arm.real_phase)
    return np.argmax(np.all(signs[..., None, :] == arm.geometry.kernel_branches, axis=-1), axis=-1)


def self_motion_rates(arm: NearlySRS, q: ArrayLike) -> np.ndarray:
    """``dq/dpsi`` (..., 7) at joint values ``q`` (..., 7): how each joint turns with the arm angle as the real arm
    moves in its self-motion, the pose held.

    The self-motion's direction is the null vector ``n`` of the real chain's Jacobian, scaled so that the arm
    angle's gradient (in closed form, :func:`redkin.srs.nearly._kernels.arm_angle_one`) gives ``grad psi . n = 1``.
    Infinite where the arm angle stands still along the self-motion (``grad psi . n = 0``); at a singular
    configuration (a null space of two dimensions) one of its directions.

    Raises
    ------
    ValueError
        For joint values of the wrong length or not finite.
    """
    values = arm.chain.check_q(q)
    gradients = _arm_angles(arm, values, True)[1]
    null = np.linalg.svd(arm.chain.jacobian(values.reshape(-1, 7)))[2][:, -1]
    along = np.einsum("mj,mj->m", gradients, null)
    with np.errstate(divide="ignore", invalid="ignore"):
        rates = null / along[:, None]
    return np.where(np.isfinite(rates), rates, np.inf).reshape(values.shape)


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
        One branch; default all eight, in the order of :data:`redkin.srs.BRANCHES`.  A branch is the signs of the
        real arm's joints 2, 4 (from its own stretched elbow, :attr:`NearlySRS.real_phase`) and 6, as an exact
        arm's are defined; a row holds at most one solution, of its own branch.

    Raises
    ------
    ValueError
        For a malformed pose, psi or branch.
    """
    geometry = arm.geometry
    chosen = BRANCHES if branch is None else (parse_branch(branch),)
    rows = _ALL_ROWS if branch is None else _ROWS[BRANCHES.index(chosen[0])]
    poses = as_poses(pose)
    angles = np.asarray(wrap_angle(check_psi(psi)))  # Newton's steps compare arm angles: 1e8 rad is a whole turn's
    try:
        shape = np.broadcast_shapes(poses.shape[:-2], angles.shape)
    except ValueError:
        raise RedkinError(f"psi of shape {angles.shape} does not broadcast against the pose batch "
                          f"{poses.shape[:-2]}") from None
    target = kernel_array(poses, shape + (4, 4)).reshape(-1, 4, 4)
    angles = kernel_array(angles, shape).reshape(-1)
    count = len(target)
    q = np.empty((count, len(rows), 7))
    exists = np.empty((count, len(rows)), dtype=bool)
    within = np.empty((count, len(rows)), dtype=bool)
    bad = run_batch(_nearly_kernels.solve, count, target, angles, rows, geometry.kernel_branches,
                    geometry.kernel_tables, arm.kernel_real, arm.kernel_model, arm.kernel_tool_inverse,
                    arm.kernel_reach, arm.real_phase, arm.kernel_limits, q, exists, within)
    if bad:
        raise_for_bad_pose(poses, np.asarray(BAD_POSE))
    return NearlySolutions(q.reshape(shape + q.shape[1:]), exists.reshape(shape + exists.shape[1:]),
                           within.reshape(shape + within.shape[1:]), tuple(chosen))


def reach(arm: NearlySRS, pose: ArrayLike) -> Reach:
    """Target poses against the real arm's reach: the links' bound (:meth:`redkin.chain.SerialChain.reach`), with the
    slack of the certificate (:data:`TOLERANCE`); a pose ``out`` of it has no solution at any arm angle.

    Raises
    ------
    ValueError
        For poses that are not ``(..., 4, 4)`` arrays with finite positions.
    """
    return arm.chain.reach(pose, tolerance=TOLERANCE)


def ik_continued(arm: NearlySRS, poses: ArrayLike, psi: ArrayLike, rows: ArrayLike,
                 groups: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """One branch's certified solution per item, item ``k`` being pose ``poses[k]`` at ``psi[k]`` on the branch
    ``BRANCHES[rows[k]]``, items of one ``groups`` value sharing their pose and branch: :func:`ik`'s row, except
    that an item within :data:`redkin.srs.nearly._kernels.CONTINUED` of arm angle of the one before it in its
    group (arm angles increasing) starts Newton's steps from that one's solution
    (:func:`redkin.srs.nearly._kernels.solve_continued`), a continuation along the self-motion cheaper than the
    neighbour's starts (1.1-1.4 times on sweeps 0.2-0.03 rad apart, benchmarks/README.md); where its steps are not
    certified on the branch, :func:`ik` solves it.
    Where the branch has one solution at that arm angle both give it; where it has two (next to a stretched elbow or
    a straight shoulder), the continuation keeps to the sheet of the item before.  The path graph's nodes
    (:mod:`redkin.paths.family`) are such items.

    Returns
    -------
    q : numpy.ndarray, shape (K, 7)
        Zeros where the branch has no certified solution there.
    exists : numpy.ndarray of bool, shape (K,)

    Raises
    ------
    ValueError
        For malformed poses or arm angles, or rows that are not branch rows 0-7.
    """
    targets = kernel_array(check_pose(poses))
    angles = kernel_array(check_psi(psi))
    branch = np.asarray(rows, dtype=np.int64)
    group = np.asarray(groups, dtype=np.int64)
    count = len(targets)
    if targets.ndim != 3 or angles.shape != (count,) or branch.shape != (count,) or group.shape != (count,):
        raise RedkinError(f"ik_continued takes K poses (K, 4, 4) and K arm angles, rows and groups, got shapes "
                          f"{targets.shape}, {angles.shape}, {branch.shape}, {group.shape}")
    if count and (branch.min() < 0 or branch.max() >= len(BRANCHES)):
        raise RedkinError(f"rows must be branch rows 0-{len(BRANCHES) - 1}")
    order = np.lexsort((angles, group))
    ordered = group[order]
    firsts = np.append(np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]]), count).astype(np.int64)
    q, exists = np.zeros((count, 7)), np.zeros(count, dtype=bool)
    run_batch(_nearly_kernels.solve_continued, len(firsts) - 1, firsts, order, targets, angles, branch,
              arm.geometry.kernel_branches, arm.geometry.kernel_tables, arm.kernel_real, arm.kernel_model,
              arm.kernel_tool_inverse, arm.kernel_reach, arm.real_phase, q, exists)
    return q, exists
