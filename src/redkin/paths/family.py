"""What path resolution needs of an arm's class: the exact feasible pieces of its redundancy parameter along a
path, the joint values of a node, the parameter of a configuration, and the pieces once the limits move in.

Two classes have exact feasible sets of their redundancy parameter, and so take part:

* S-R-S and offset-elbow arms (paper 000): the arm angle psi, whose pieces are [000 eq. 30]'s
  (:func:`redkin.srs.feasible_pieces_all_branches`), the nodes the closed form [000 eqs. 11-19];
* the Franka class (docs/franka.md): the value q7 of joint 7, whose arcs are [F8]-[F9]'s
  (:func:`redkin.franka.feasible_q7_pieces`), the nodes the closed form at q7 [F1]-[F7].

Nearly S-R-S arms (docs/srs.md, "Nearly S-R-S arms") take part too, with the real arm's arm angle: their feasible
sets are located on the polished solutions (:func:`redkin.srs.feasible_arm_angles_nearly`), certified but not
proved complete, and the nodes are the polished solutions (:func:`redkin.srs.nearly.ik`).  Their family is not
:attr:`Family.exact`: no clearance is proved optimal and no failure proved from their sets.

:func:`path_family` picks the class of a chain; :mod:`redkin.paths.resolve` is written once for all three.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from redkin._compiled import run_batch
from redkin.chain import SerialChain
from redkin.circle import TWO_PI, wrap_angle
from redkin.errors import RedkinError
from redkin.franka.feasible import feasible_q7_pieces
from redkin.franka.geometry import FrankaGeometry, franka_geometry
from redkin.franka.ik import PARAMETER as Q7
from redkin.franka.ik import frames_seven
from redkin.franka.ik import ik as franka_ik
from redkin.franka.ik import reach as q7_reach
from redkin.paths import _dp_kernels
from redkin.paths.failure import empty_blocker
from redkin.paths.graph import _CLIP_TOLERANCE, Arm, joint_moves
from redkin.srs import _feasible_kernels, _ik_kernels
from redkin.srs.arm_angle import arm_angle_of
from redkin.srs.branches import BRANCHES, Branch
from redkin.srs.coefficients import coefficient_arrays
from redkin.srs.feasible import FeasiblePieces, feasible_pieces_all_branches
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.srs.ik import reachable
from redkin.srs.nearly import NearlySRS, ik_continued, nearly_srs
from redkin.srs.nearly import arm_angle as nearly_arm_angle
from redkin.srs.nearly import branch_of as nearly_branch_of
from redkin.srs.nearly import reach as nearly_reach
from redkin.srs.nearly.feasible import feasible_arm_angles_nearly_all

if TYPE_CHECKING:  # for the type alone: only a family in a cell (paths.collision_family) checks steps
    from redkin.collision.steps import StepClearance

#: The arm angle's name in results.
PSI = "psi"


@dataclass(frozen=True)
class _ArmAngleArm(Arm):
    """An S-R-S or offset-elbow arm along a path: the IK coefficients of every waypoint for both elbow signs.

    Attributes
    ----------
    geometry : SRSGeometry
    entries, theta4 : numpy.ndarray, shapes (W, 2, 3, 14), (W, 2)
        [000 eqs. 11, 12, 16] per waypoint, for the Table 1 elbow signs ``+1, -1``.
    """

    geometry: SRSGeometry
    entries: np.ndarray
    theta4: np.ndarray

    def rows(self, waypoint: np.ndarray, branch: np.ndarray, parameter: np.ndarray,
             shared: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`Arm.rows` at arm angles ``parameter``: the closed form of :func:`redkin.srs.ik` [000 eqs. 11,
        13-15, 17-19], the shoulder's and wrist's angles once per sample (the nodes that ``shared`` makes one
        sample share them; :func:`redkin.paths._dp_kernels.sample_angles`), then each node's branch signs and
        joint values (:func:`redkin.paths._dp_kernels.node_rows`); each waypoint's coefficients are read in place."""
        size = len(parameter)
        waypoint = np.ascontiguousarray(waypoint, dtype=np.int64)
        branch = np.ascontiguousarray(branch, dtype=np.int64)
        parameter = np.ascontiguousarray(parameter, dtype=float)
        if shared is None:
            leaders, sample = np.arange(size), np.arange(size)
        else:
            leaders = np.flatnonzero(shared == np.arange(size))
            index = np.empty(size, dtype=np.int64)
            index[leaders] = np.arange(len(leaders))
            sample = index[shared]
        table = self.geometry.kernel_branches
        angles = np.empty((len(leaders), 7))
        run_batch(_dp_kernels.sample_angles, len(leaders), leaders, waypoint, branch, self.entries, parameter, table,
                  angles)
        q, clearance = np.empty((size, 7)), np.empty(size)
        run_batch(_dp_kernels.node_rows, size, sample, angles, waypoint, branch, self.theta4, table,
                  self.geometry.kernel_joints, self.chain.lower, self.chain.upper, self.circle, q, clearance)
        return q, clearance

    def take(self, waypoints: np.ndarray) -> _ArmAngleArm:
        return replace(self, entries=self.entries[waypoints], theta4=self.theta4[waypoints])

    def pose_fixed(self, waypoint: int) -> np.ndarray:
        """Joint 4, the elbow, at each Table 1 elbow sign: the pose fixes ``theta_4`` [000 eq. 11] whatever the arm
        angle (none where the waypoint is out of reach)."""
        joints = self.geometry.kernel_joints
        elbow = self.theta4[waypoint]
        values = np.full((len(elbow), self.chain.n), np.nan)
        values[:, 3] = joints[_ik_kernels.SIGN, 3] * (elbow - joints[_ik_kernels.OFFSET, 3])
        return values[np.isfinite(elbow)]


@dataclass(frozen=True)
class _Q7Arm(Arm):
    """A Franka-class arm along a path: frame 7 of every waypoint in the solver's frame 0.

    Attributes
    ----------
    geometry : FrankaGeometry
    frames : numpy.ndarray, shape (W, 4, 4)
    """

    geometry: FrankaGeometry
    frames: np.ndarray

    def rows(self, waypoint: np.ndarray, branch: np.ndarray, parameter: np.ndarray,
             shared: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`Arm.rows` at joint 7 values ``parameter``: one branch of the closed form at q7 [F1]-[F7] by
        :func:`redkin.paths._dp_kernels.q7_node_rows` (each node on its own: ``shared`` is not used)."""
        q, clearance = np.empty((len(parameter), 7)), np.empty(len(parameter))
        geometry = self.geometry
        run_batch(_dp_kernels.q7_node_rows, len(parameter), np.ascontiguousarray(waypoint, dtype=np.int64),
                  np.ascontiguousarray(branch, dtype=np.int64), self.frames,
                  np.ascontiguousarray(parameter, dtype=float), geometry.kernel_arm, geometry.kernel_branches,
                  geometry.kernel_joints, self.chain.lower, self.chain.upper, self.circle, q, clearance)
        return q, clearance

    def take(self, waypoints: np.ndarray) -> _Q7Arm:
        return replace(self, frames=self.frames[waypoints])


class Family:
    """An arm's class as path resolution sees it (:class:`ArmAngleFamily`, :class:`Q7Family`).

    Attributes
    ----------
    parameter : str
        The redundancy parameter's name in results: ``"psi"`` or ``"q7"``.
    wraps : bool
        Whether the parameter is an angle on the circle, reported in ``[-pi, pi)`` (the arm angle), or a joint
        value reported as the joint has it (q7).
    exact : bool
        Whether the feasible sets are a closed form's, exact enough to prove a clearance optimal or a pose
        infeasible.
    baselines : bool
        Whether the per-pose baselines of :mod:`redkin.paths.baselines` (the fixed arm angle, the clamped optimum,
        greedy tracking; each the closed form of an exact arm angle) apply to the class.
    """

    parameter: str = PSI
    wraps: bool = True
    exact: bool = True
    baselines: bool = False

    @property
    def chain(self) -> SerialChain:
        """The chain whose joint values the nodes hold."""
        raise NotImplementedError

    def arm(self, poses: np.ndarray, step: np.ndarray) -> tuple[np.ndarray, Arm]:
        """Whether each pose ``(W, 4, 4)`` is within reach (W,), and the :class:`Arm` along all of them.

        Raises
        ------
        RedkinError
            For a pose that is not a proper rigid transform.
        """
        raise NotImplementedError

    @property
    def proves_optimal(self) -> bool:
        """Whether a clearance can be proved optimal from these sets (:func:`redkin.paths.resolve._bottleneck`):
        where they are :attr:`exact` (or, in a cell, certified on an exact class: among the certified sets)."""
        return self.exact

    def proved_empty(self, poses: np.ndarray) -> np.ndarray:
        """Per pose ``(W, 4, 4)``, whether its sets are empty on every branch, as far as they prove it: the exact
        pieces' emptiness (a cell's certified sets add that they are complete)."""
        return np.asarray(~self.pieces(poses).feasible.any(axis=(-2, -1)))

    def pieces(self, poses: np.ndarray) -> FeasiblePieces:
        """The exact feasible pieces ``(W, 8, K)`` of poses within reach, per branch of :data:`BRANCHES`: intervals
        of the parameter on which the branch exists, lies within every limit and is continuous."""
        raise NotImplementedError

    def parameter_of(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The branch (index into :data:`BRANCHES`) and parameter of configurations ``q`` (P, 7)."""
        raise NotImplementedError

    def sample_groups(self) -> np.ndarray | None:
        """Per branch of :data:`BRANCHES`, a group label: the branches of one group have their pieces' ends slot
        for slot, and their nodes at one value of the parameter share part of their work (:meth:`Arm.rows` with
        ``shared``); ``None``: no such groups."""
        return None

    def inner(self, level: float) -> Family | None:
        """The same class with every limit of a range under ``2 pi`` moved ``level`` inwards; ``None`` where such a
        range is narrower than ``2 level`` (no configuration is that far from its limits)."""
        limited = ~self.chain.covers_circle
        chain = self.chain
        if np.any(limited & (chain.upper - chain.lower < 2.0 * level)):
            return None
        return self._with(chain.with_limits(np.where(limited, chain.lower + level, chain.lower),
                                            np.where(limited, chain.upper - level, chain.upper)))

    def _with(self, chain: SerialChain) -> Family:
        raise NotImplementedError

    def model(self) -> str | None:
        """What the feasible sets rest on where they are not exact, in one line (``None`` for an exact class)."""
        return None

    def blocker(self, pose: np.ndarray) -> tuple[int | None, dict[str, int | None], bool]:
        """Why a pose within reach has no feasible sample: the joint that empties its feasible set on most branches
        (``None`` where not known), the blocking joint per branch, and whether the exact sets prove it empty."""
        raise NotImplementedError

    def emptied(self, pose: np.ndarray) -> tuple[str, tuple[str, str] | None]:
        """What empties the sets of a pose within reach: the reason of :data:`redkin.paths.result.REASONS`
        (``"empty"``: the joint limits) and the body's link and the obstacle that block it (``None`` here)."""
        return "empty", None

    def distances(self, q: np.ndarray) -> np.ndarray | None:
        """In the family's cell, the least signed distance of each configuration of ``q`` (N, 7) between the body
        and the obstacles or its own checked links (:func:`redkin.collision.clearance`); ``None`` without a
        cell."""
        return None

    def moving_distances(self, q: np.ndarray) -> np.ndarray | None:
        """:meth:`distances` over the pairs with a capsule that the redundancy moves at the configuration's pose
        (``inf`` where none does): what the objective ``"obstacle-clearance"`` makes largest; ``None`` without a
        cell."""
        return None

    def steps(self, start: np.ndarray, end: np.ndarray) -> StepClearance | None:
        """What is proved of the steps from each configuration of ``start`` (N, 7) to the same row of ``end`` in the
        family's cell (:func:`redkin.collision.steps_between`); ``None`` without a cell: every step is allowed."""
        return None


@dataclass(frozen=True)
class ArmAngleFamily(Family):
    """S-R-S and offset-elbow arms: the arm angle psi (paper 000)."""

    geometry: SRSGeometry
    baselines: bool = True

    @property
    def chain(self) -> SerialChain:
        return self.geometry.chain

    def arm(self, poses: np.ndarray, step: np.ndarray) -> tuple[np.ndarray, Arm]:
        coefficients, status, _ = coefficient_arrays(self.geometry, poses[:, None], np.array([1.0, -1.0]))
        if np.any(status == _ik_kernels.BAD_POSE):
            raise RedkinError("paths: every pose must have a proper rotation block and last row [0, 0, 0, 1]")
        reach = np.all(status == _ik_kernels.OK, axis=-1)
        return reach, _ArmAngleArm(self.chain, step, self.chain.covers_circle, self.geometry, coefficients.entries,
                                  coefficients.theta4)

    def pieces(self, poses: np.ndarray) -> FeasiblePieces:
        """[000 eq. 30] per branch; a pose out of reach has no feasible piece (``feasible`` false, NaN ends)."""
        shape = (len(poses), len(BRANCHES), _feasible_kernels.PIECES)
        start, end, feasible = np.full(shape, np.nan), np.full(shape, np.nan), np.zeros(shape, dtype=bool)
        inside = reachable(self.geometry, poses)
        if inside.any():
            found = feasible_pieces_all_branches(self.geometry, poses[inside])
            start[inside], end[inside], feasible[inside] = found.start, found.end, found.feasible
        return FeasiblePieces(start, end, feasible)

    def sample_groups(self) -> np.ndarray:
        """The elbow sign: the four branches of one share its cuts [000 eqs. 20-28] and, at one arm angle, the
        shoulder's and wrist's angles up to their signs [000 eqs. 13-15, 17-19]."""
        return self.geometry.kernel_branches[:, 1]

    def parameter_of(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        state = arm_angle_of(self.geometry, q)
        branch = [BRANCHES.index(Branch(*(int(s) for s in signs))) for signs in np.reshape(state.branch, (-1, 3))]
        return np.array(branch, dtype=np.int64), np.reshape(state.psi, -1)

    def _with(self, chain: SerialChain) -> Family:
        return ArmAngleFamily(srs_geometry(chain))

    def blocker(self, pose: np.ndarray) -> tuple[int | None, dict[str, int | None], bool]:
        joint, per_branch = empty_blocker(self.geometry, pose)
        return joint, per_branch, all(b is not None for b in per_branch.values())  # else the samples are empty


@dataclass(frozen=True)
class Q7Family(Family):
    """The Franka class: the value q7 of joint 7 (docs/franka.md)."""

    geometry: FrankaGeometry
    parameter: str = Q7
    wraps: bool = False

    @property
    def chain(self) -> SerialChain:
        return self.geometry.chain

    def arm(self, poses: np.ndarray, step: np.ndarray) -> tuple[np.ndarray, Arm]:
        try:
            frames = np.ascontiguousarray(frames_seven(self.geometry, poses))
        except ValueError as exc:
            raise RedkinError(f"paths: {exc}") from exc
        # a pose out of reach (the shoulder-wrist distance over every q7 against the elbow's range) has no branch
        return ~q7_reach(self.geometry, poses).out, _Q7Arm(self.chain, step, self.chain.covers_circle, self.geometry,
                                                          frames)

    def pieces(self, poses: np.ndarray) -> FeasiblePieces:
        return FeasiblePieces(*feasible_q7_pieces(self.geometry, poses))

    def parameter_of(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """q7 is the configuration's own joint 7; its branch is the one whose solution at that q7 is nearest."""
        solutions = franka_ik(self.geometry, self.chain.fk(q), q[:, 6])
        far = joint_moves(solutions.q, q[:, None, :], self.chain.covers_circle).max(axis=-1)
        branch = np.argmin(np.where(solutions.exists, far, np.inf), axis=-1)
        return branch.astype(np.int64), q[:, 6].copy()

    def _with(self, chain: SerialChain) -> Family:
        return Q7Family(franka_geometry(chain))

    def blocker(self, pose: np.ndarray) -> tuple[int | None, dict[str, int | None], bool]:
        return None, {}, not self.pieces(pose[None]).feasible.any()


@dataclass(frozen=True)
class _NearlyArm(Arm):
    """A nearly S-R-S arm along a path: its neighbour and every waypoint's pose.

    Attributes
    ----------
    nearly : NearlySRS
    poses : numpy.ndarray, shape (W, 4, 4)
    """

    nearly: NearlySRS
    poses: np.ndarray

    def rows(self, waypoint: np.ndarray, branch: np.ndarray, parameter: np.ndarray,
             shared: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`Arm.rows` at the real arm's arm angles ``parameter`` (``shared`` is not used): the certified
        solutions of :func:`redkin.srs.nearly.ik`, each node of a waypoint and branch continued from the one before
        it in arm angle (:func:`redkin.srs.nearly.arm.ik_continued`), each limited joint moved by whole turns to
        just above its lower limit (the solver's values are right modulo whole turns) and the others into ``[-pi,
        pi)``, then clipped as :func:`redkin.paths._dp_kernels._clipped` clips; a joint outside its range is as far
        out as the nearer limit, either way round."""
        q, exists = ik_continued(self.nearly, self.poses[waypoint], parameter, branch,
                                 waypoint * len(BRANCHES) + branch)
        q[:, self.circle] = wrap_angle(q[:, self.circle])  # as the closed forms' nodes, in [-pi, pi)
        limited = ~self.circle
        if not limited.any():
            return q, np.where(exists, np.inf, -np.inf)
        lower, upper = self.chain.lower[limited], self.chain.upper[limited]
        turned = lower + np.mod(q[:, limited] - lower + _CLIP_TOLERANCE, TWO_PI) - _CLIP_TOLERANCE
        room = np.where(turned <= upper, np.minimum(turned - lower, upper - turned),
                        -np.minimum(turned - upper, lower + TWO_PI - turned))
        q[:, limited] = np.clip(turned, lower, upper)
        return q, np.where(exists, room.min(axis=1), -np.inf)

    def take(self, waypoints: np.ndarray) -> _NearlyArm:
        return replace(self, poses=self.poses[waypoints])


@dataclass(frozen=True)
class NearlyFamily(Family):
    """Nearly S-R-S arms: the real arm's arm angle (docs/srs.md, "Nearly S-R-S arms"); not :attr:`Family.exact`."""

    nearly: NearlySRS
    tolerance: float
    exact: bool = False

    @property
    def chain(self) -> SerialChain:
        return self.nearly.chain

    def arm(self, poses: np.ndarray, step: np.ndarray) -> tuple[np.ndarray, Arm]:
        # a pose beyond the links' reach (with the certificate's slack) has no solution at any arm angle
        inside = ~nearly_reach(self.nearly, poses).out
        return inside, _NearlyArm(self.chain, step, self.chain.covers_circle, self.nearly, poses)

    def pieces(self, poses: np.ndarray) -> FeasiblePieces:
        """The real feasible sets of every branch (:func:`redkin.srs.feasible_arm_angles_nearly_all`), an arc through
        ``+-pi`` cut in two."""
        sets = [[result.feasible.intervals for result in feasible_arm_angles_nearly_all(self.nearly, pose)]
                for pose in poses]
        return as_pieces(sets)

    def parameter_of(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The real arm's arm angle (:func:`redkin.srs.nearly.arm_angle`) and its own branch signs."""
        return (np.reshape(nearly_branch_of(self.nearly, q), -1).astype(np.int64),
                np.reshape(nearly_arm_angle(self.nearly, q), -1))

    def _with(self, chain: SerialChain) -> Family:
        return NearlyFamily(nearly_srs(chain, self.tolerance), self.tolerance)

    def model(self) -> str:
        return (f"nearly S-R-S: {self.nearly.describe()}; the feasible sets are certified on the real arm, not "
                "exact, so no clearance is proved optimal")

    def blocker(self, pose: np.ndarray) -> tuple[int | None, dict[str, int | None], bool]:
        return None, {}, False


def as_pieces(sets: list[list], branches: int = len(BRANCHES)) -> FeasiblePieces:
    """:class:`FeasiblePieces` ``(W, branches, K)`` of each waypoint's and branch's sorted intervals ``[(start, end),
    ...]``."""
    most = max([1] + [len(intervals) for per_pose in sets for intervals in per_pose])
    shape = (len(sets), branches, most)
    start, end, feasible = np.full(shape, np.nan), np.full(shape, np.nan), np.zeros(shape, dtype=bool)
    for w, per_pose in enumerate(sets):
        for b, intervals in enumerate(per_pose):
            if len(intervals):
                arcs = np.asarray(intervals, dtype=float)
                start[w, b, : len(arcs)], end[w, b, : len(arcs)] = arcs[:, 0], arcs[:, 1]
                feasible[w, b, : len(arcs)] = True
    return FeasiblePieces(start, end, feasible)
