"""Feasible arm angles under box joint limits: paper 000 section 4, [000 eqs. 20-30].

For each joint ``i`` the set ``Psi_i`` of arm angles at which
``theta_i(psi)`` lies within its limits [000 eq. 29] is a union of closed arcs,
and the feasible set is ``Psi = intersection of the Psi_i`` [000 eq. 30].

Closed form, never missing a narrow arc: every arm angle where
``theta_i(psi)`` equals a limit solves a linear equation in
``(sin psi, cos psi)`` (:func:`redkin.srs.joints.limit_equation_table`, derived
from [000 eqs. 21, 22]), which has at most two roots in closed form
(:func:`redkin.srs._feasible_kernels.sinusoid_roots`).  Between consecutive roots
``theta_i`` stays on one side of each limit (it is continuous there: its
only discontinuities, where the tangent-type numerator and denominator both
vanish, are roots of every limit equation), so one evaluation at the middle
of each piece classifies it.  The evaluation needs no joint angle: the
signs of the joint's two limit equations there decide, through a table
built once per arm and branch sign
(:func:`redkin.srs.joints.limit_sign_membership`).  This covers the five
cases of section 4.3 (none, around psi_max, around psi_min, the complement
of both, all) and limits that cross ``+-pi`` alike, because the table is
filled by testing membership modulo ``2 pi``.  The pieces between all
joints' cut points refine every joint's own pieces, so one classification
gives the per-joint sets [000 eq. 29] and their intersection [000 eq. 30].
Isolated touching points (a limit reached at a single arm angle from
outside) and pieces shorter than :data:`PIECE_TOLERANCE` are not reported.

The work is done by the compiled kernels of :mod:`redkin.srs._feasible_kernels`
(one pose-branch per inner call, batches on all cores); the functions here
validate and call them.  From poses, one compiled call checks each pose and
computes [000 eqs. 4-19] (:func:`redkin.srs._ik_kernels.coefficients_one`) and
[000 eqs. 20-30]; from coefficients computed beforehand (:func:`_overall_pieces`,
:func:`feasible_from_coefficients`, :func:`_all_branch_pieces`) it does eqs.
20-30 alone.  The cuts and signs of one elbow sign serve its four
branches, so :func:`feasible_pieces_all_branches` costs little more than
two single branches.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple, cast

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import run_batch
from redkin.chain import SerialChain
from redkin.circle import ArcSet
from redkin.errors import RedkinError
from redkin.srs import _feasible_kernels as kernels
from redkin.srs import _ik_kernels
from redkin.srs._targets import as_geometry, as_poses, raise_for_status
from redkin.srs.branches import Branch, parse_branch
from redkin.srs.coefficients import ArmAngleCoefficients
from redkin.srs.geometry import SRSGeometry

PIECE_TOLERANCE = kernels.PIECE_TOLERANCE
_CACHE_KEY = "_feasible_limit_tables"
_GROUP = _ik_kernels.GROUP  # entries per group (shoulder, wrist): x, y, z, r0, r1, r2, t


@dataclass(frozen=True, eq=False, repr=False)
class FeasibleArmAngles:
    """Feasible arm angles of one pose and branch.

    Holds the classified pieces the kernel computed; the :class:`ArcSet` s
    are made on first access (building eight of them costs more than
    computing the pieces), then kept.

    Attributes
    ----------
    branch : Branch
    theta4 : float
        The elbow DH angle (independent of psi, [000 eq. 11]).
    per_joint : dict of int to ArcSet
        ``Psi_i`` for joints 1..7 [000 eq. 29]; joint 4 is the full circle or empty.
    feasible : ArcSet
        ``Psi``, the intersection [000 eq. 30]; empty means the pose is unreachable
        within the limits on this branch.
    """

    branch: Branch
    theta4: float
    _start: np.ndarray  # the pieces (24,) and which of them each row keeps (7, 24): overall, then PSI_JOINTS
    _end: np.ndarray
    _keep: np.ndarray
    _elbow_inside: bool

    def _rows(self, rows: slice) -> list[ArcSet]:
        """The :class:`ArcSet` s of some rows of the pieces' classification."""
        start, end = self._start.reshape(1, kernels.PIECES), self._end.reshape(1, kernels.PIECES)
        keep = np.ascontiguousarray(self._keep[rows])
        return _arc_sets(start, end, keep.reshape((1,) + keep.shape))[0]

    @cached_property
    def feasible(self) -> ArcSet:
        """``Psi`` [000 eq. 30]."""
        return self._rows(slice(0, 1))[0]

    @cached_property
    def per_joint(self) -> dict[int, ArcSet]:
        """``Psi_i`` for joints 1..7 [000 eq. 29]."""
        first, second, third, fifth, sixth, seventh = self._rows(slice(1, 7))
        elbow = ArcSet.full() if self._elbow_inside else ArcSet.empty()
        return {1: first, 2: second, 3: third, 4: elbow, 5: fifth, 6: sixth, 7: seventh}

    @property
    def is_empty(self) -> bool:
        """True when no arm angle satisfies every limit."""
        return self.feasible.is_empty

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, FeasibleArmAngles):
            return NotImplemented
        return (self.branch == other.branch and self.theta4 == other.theta4 and self.feasible == other.feasible
                and self.per_joint == other.per_joint)

    __hash__ = None  # type: ignore[assignment]  # mutable-looking value: equal by content, like the dataclass was

    def __repr__(self) -> str:
        return f"FeasibleArmAngles(branch={self.branch!r}, theta4={self.theta4!r}, feasible={self.feasible!r})"


@dataclass(frozen=True)
class FeasiblePieces:
    """Batched feasible sets as pieces between sorted cut points.

    Piece ``j`` of a pose runs from ``start[..., j]`` to ``end[..., j]``
    (``end`` may exceed ``pi``: the piece then wraps); ``feasible[..., j]``
    says whether it satisfies the limits.  Unused slots have ``feasible``
    false and a NaN start.
    """

    start: np.ndarray
    end: np.ndarray
    feasible: np.ndarray

    def arc_set(self, index: tuple[int, ...] = ()) -> ArcSet:
        """The :class:`ArcSet` of one pose (``index`` into the batch shape)."""
        pieces = self.start.shape[-1]
        start = np.ascontiguousarray(self.start[index], dtype=float).reshape(1, pieces)
        end = np.ascontiguousarray(self.end[index], dtype=float).reshape(1, pieces)
        keep = np.ascontiguousarray(self.feasible[index], dtype=bool).reshape(1, 1, pieces)
        return _arc_sets(start, end, keep)[0][0]

    @property
    def nonempty(self) -> np.ndarray:
        """Whether each pose has a feasible arm angle (a feasible piece longer than :data:`PIECE_TOLERANCE`)."""
        return np.any(self.feasible & (self.end - self.start > PIECE_TOLERANCE), axis=-1)


def _arc_sets(start: np.ndarray, end: np.ndarray, keep: np.ndarray) -> list[list[ArcSet]]:
    """The :class:`ArcSet` of each row of ``keep`` (N, R, K) on the pieces ``start``, ``end`` (N, K)
    (:func:`redkin.srs._feasible_kernels.batch_arc_runs`)."""
    arcs = np.empty((keep.shape[0], keep.shape[1] * keep.shape[2], 2))
    counts: np.ndarray = np.empty(keep.shape[:2], dtype=np.int64)
    kernels.batch_arc_runs(start, end, keep, arcs, counts)
    sets = []
    for b, numbers in enumerate(counts.tolist()):
        runs = arcs[b, :sum(numbers)].tolist()
        rows, used = [], 0
        for n in numbers:
            rows.append(ArcSet(runs[used:used + n]) if n else ArcSet.empty())
            used += n
        sets.append(rows)
    return sets


class LimitTables(NamedTuple):
    """An arm's joint limits as :mod:`redkin.srs._feasible_kernels` reads them (see its module docstring).

    Attributes
    ----------
    equations : numpy.ndarray, shape (2, 17, 12)
        The usual and the stretched limit-equation table, weights over offsets.
    membership : numpy.ndarray of bool, shape (2, 2, 6, 4)
        Limit membership by branch signs and limit-equation signs.
    elbow : numpy.ndarray, shape (3,)
        ``start, span, free`` of joint 4.
    """

    equations: np.ndarray
    membership: np.ndarray
    elbow: np.ndarray


def limit_tables(geometry: SRSGeometry) -> LimitTables:
    """The :class:`LimitTables` of an arm, built from :attr:`SRSGeometry.psi_joint_limits` once per geometry."""
    cached = geometry.__dict__.get(_CACHE_KEY)
    if cached is None:
        limits = geometry.psi_joint_limits
        equations = np.stack([np.concatenate([limits.weights, limits.offset]),
                              np.concatenate([limits.stretched_weights, limits.stretched_offset])])
        cached = LimitTables(equations, np.ascontiguousarray(limits.membership.reshape(2, 2, 6, 4)),
                             np.array([limits.elbow_start, limits.elbow_span, float(limits.elbow_free)]))
        for array in cached:
            array.setflags(write=False)
        object.__setattr__(geometry, _CACHE_KEY, cached)
    return cached


def _classified(entries: np.ndarray, theta4: np.ndarray, branch: Branch, geometry: SRSGeometry, per_joint: bool):
    """Run :func:`redkin.srs._feasible_kernels.branches` (serial) on coefficients of batch shape ``theta4.shape``.

    Returns ``start, end`` (..., 24), ``keep`` (..., R, 24) (``R = 7`` with
    ``per_joint``, else 1) and whether theta_4 is within its limits (...).
    """
    shape = theta4.shape
    flat = np.ascontiguousarray(entries, dtype=float).reshape(-1, 3, 2 * _GROUP)
    count = flat.shape[0]
    start, end = np.empty((count, kernels.PIECES)), np.empty((count, kernels.PIECES))
    keep = np.empty((count, 7 if per_joint else 1, kernels.PIECES), dtype=bool)
    elbow_inside = np.empty(count, dtype=bool)
    tables = limit_tables(geometry)
    kernels.branches(flat, np.ascontiguousarray(theta4, dtype=float).reshape(count), int(branch.shoulder < 0),
                     int(branch.wrist < 0), tables.equations, tables.membership, tables.elbow, start, end, keep,
                     elbow_inside)
    if shape == (count,):
        return start, end, keep, elbow_inside
    pieces = shape + (kernels.PIECES,)
    return start.reshape(pieces), end.reshape(pieces), keep.reshape(shape + keep.shape[1:]), elbow_inside.reshape(shape)


def _from_poses(pose: ArrayLike, branches: np.ndarray, geometry: SRSGeometry, per_joint: bool):
    """Run :func:`redkin.srs._feasible_kernels.poses_feasible` ([000 eqs. 4-30], one compiled call) on validated
    poses, for the Table 1 signs ``branches`` (B, 3) (:meth:`SRSGeometry.kernel_branch`,
    :attr:`SRSGeometry.kernel_branches`).

    Returns ``start, end`` (..., B, 24), ``keep`` (..., B, R, 24) (``R = 7``
    with ``per_joint``, else 1), theta_4 and whether it is within its limits
    (..., B).

    Raises
    ------
    ValueError
        For a malformed or unreachable pose (the kernel flags it; the message is worded by
        :func:`redkin.srs.coefficients.raise_for_status`).
    """
    pose = as_poses(pose)
    shape = pose.shape[:-2]
    poses = np.ascontiguousarray(pose).reshape(-1, 4, 4)
    count, rows = poses.shape[0], branches.shape[0]
    status, distance = np.empty(count, dtype=np.int64), np.empty(count)
    theta4, elbow_inside = np.empty((count, rows)), np.empty((count, rows), dtype=bool)
    start, end = np.empty((count, rows, kernels.PIECES)), np.empty((count, rows, kernels.PIECES))
    keep = np.empty((count, rows, 7 if per_joint else 1, kernels.PIECES), dtype=bool)
    tables = limit_tables(geometry)
    if run_batch(kernels.poses_feasible, count, poses, branches, geometry.kernel_arm, geometry.kernel_ends,
                 tables.equations, tables.membership, tables.elbow, status, distance, theta4, elbow_inside, start, end,
                 keep):
        raise_for_status(geometry, pose, status.reshape(shape), distance.reshape(shape))
    pieces = shape + (rows, kernels.PIECES)
    return (start.reshape(pieces), end.reshape(pieces), keep.reshape(shape + keep.shape[1:]),
            theta4.reshape(shape + (rows,)), elbow_inside.reshape(shape + (rows,)))


def _feasible_arm_angles(start, end, keep, theta4, elbow_inside, named: Branch) -> np.ndarray:
    """:class:`FeasibleArmAngles` of a batch (an object array with the batch shape, 0-d for one pose) from the pieces
    ``start, end`` (..., 24), their rows ``keep`` (..., 7, 24), theta_4 and its membership (...)."""
    shape = theta4.shape
    count = theta4.size
    start, end, keep = start.reshape(count, -1), end.reshape(count, -1), keep.reshape(count, 7, -1)
    angles = theta4.reshape(count).tolist()
    elbow = elbow_inside.reshape(count).tolist()
    results = np.empty(count, dtype=object)
    for b in range(count):  # rows of keep: [000 eq. 30], then PSI_JOINTS [000 eq. 29]
        results[b] = FeasibleArmAngles(named, angles[b], start[b], end[b], keep[b], elbow[b])
    return results.reshape(shape)


def _overall_pieces(coefficients: ArmAngleCoefficients, branch: Branch, geometry: SRSGeometry) -> FeasiblePieces:
    """[000 eq. 30] for a batch: pieces between all joints' cut points, classified for every joint at once.

    Parameters
    ----------
    coefficients : ArmAngleCoefficients
        Of the poses, for the branch's elbow sign (batch shape ``(...)``).
    branch : Branch
        In paper 000 Table 1 signs (:meth:`SRSGeometry.table1_branch`).
    geometry : SRSGeometry

    Returns
    -------
    FeasiblePieces
        Arrays of shape ``(..., 24)``.
    """
    start, end, keep, _ = _classified(coefficients.entries, coefficients.theta4, branch, geometry, False)
    return FeasiblePieces(start, end, keep[..., 0, :])


def feasible_pieces(
    arm: SerialChain | SRSGeometry, pose: ArrayLike, branch: str | Branch = "+++"
) -> FeasiblePieces:
    """Batched feasible sets [000 eq. 30] as arrays, for speed; see :func:`feasible_arm_angles`."""
    geometry = as_geometry(arm)
    start, end, keep, _, _ = _from_poses(pose, geometry.kernel_branch(branch), geometry, False)
    return FeasiblePieces(start[..., 0, :], end[..., 0, :], keep[..., 0, 0, :])


def feasible_pieces_all_branches(arm: SerialChain | SRSGeometry, pose: ArrayLike) -> FeasiblePieces:
    """The feasible sets [000 eq. 30] of the eight branches as arrays ``(..., 8, 24)``, in the order of
    :data:`BRANCHES`.

    The branches are named in the chain's joint senses, as in
    :func:`redkin.srs.ik_all_branches`; see :func:`_all_branch_pieces`.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
    pose : array_like, shape (4, 4) or (..., 4, 4)

    Returns
    -------
    FeasiblePieces
        ``arc_set((..., k))`` is the feasible set of branch ``BRANCHES[k]``.

    Raises
    ------
    ValueError
        For a malformed or unreachable pose.
    """
    geometry = as_geometry(arm)
    start, end, keep, _, _ = _from_poses(pose, geometry.kernel_branches, geometry, False)
    return FeasiblePieces(start, end, keep[..., 0, :])


def _all_branch_pieces(coefficients: ArmAngleCoefficients, geometry: SRSGeometry) -> FeasiblePieces:
    """[000 eq. 30] for the eight branches of a batch of poses, from their coefficients for both elbow signs.

    The cut points and limit-equation signs of each elbow sign are computed
    once and classified for its four branches
    (:func:`redkin.srs._feasible_kernels.pose_all_branches`).

    Parameters
    ----------
    coefficients : ArmAngleCoefficients
        Batch shape ``(..., 2)``: the Table 1 elbow signs ``+1, -1`` last.
    geometry : SRSGeometry

    Returns
    -------
    FeasiblePieces
        Arrays of shape ``(..., 8, 24)``, the branches in the order of
        :data:`BRANCHES` named in the chain's joint senses.
    """
    shape = coefficients.theta4.shape[:-1]
    entries = np.ascontiguousarray(coefficients.entries, dtype=float).reshape(-1, 2, 3, 2 * _GROUP)
    count = entries.shape[0]
    start, end = np.empty((count, 8, kernels.PIECES)), np.empty((count, 8, kernels.PIECES))
    keep = np.empty((count, 8, 1, kernels.PIECES), dtype=bool)
    tables = limit_tables(geometry)
    kernels.all_branches(entries, np.ascontiguousarray(coefficients.theta4, dtype=float).reshape(count, 2),
                         tables.equations, tables.membership, tables.elbow, geometry.branch_order, start, end, keep)
    pieces = shape + (8, kernels.PIECES)
    return FeasiblePieces(start.reshape(pieces), end.reshape(pieces), keep.reshape(pieces))


def feasible_from_coefficients(
    coefficients: ArmAngleCoefficients, branch: Branch, geometry: SRSGeometry
) -> np.ndarray:
    """:class:`FeasibleArmAngles` from precomputed coefficients: an object array with their batch shape (0-d for
    one pose).

    Parameters
    ----------
    coefficients : ArmAngleCoefficients
        Of the poses, for the branch's elbow sign (batch shape ``(...)``).
    branch : Branch
        In paper 000 Table 1 signs (:meth:`SRSGeometry.table1_branch`).
    geometry : SRSGeometry
    """
    start, end, keep, elbow_inside = _classified(coefficients.entries, coefficients.theta4, branch, geometry, True)
    named = geometry.table1_branch(branch)  # as the caller named it
    return _feasible_arm_angles(start, end, keep, coefficients.theta4, elbow_inside, named)


def feasible_arm_angles(
    arm: SerialChain | SRSGeometry, pose: ArrayLike, branch: str | Branch = "+++"
) -> FeasibleArmAngles:
    """Per-joint and overall feasible arm angles of one pose [000 eqs. 29, 30].

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
        S-R-S arm with its joint limits (a range of width >= 2 pi holds every
        arm angle: it constrains the choice of representative, not psi).
    pose : array_like, shape (4, 4)
    branch : str or Branch
        Signs of theta_2, theta_4, theta_6.

    Returns
    -------
    FeasibleArmAngles
        For a batch of poses see :func:`feasible_arm_angles_batch` (the same
        results, as an object array) or :func:`feasible_pieces` (arrays).

    Raises
    ------
    RedkinError
        For a malformed pose or branch, or a batch of poses.
    UnreachablePoseError
        For a wrist position out of reach.
    """
    shape = np.shape(pose)
    if shape != (4, 4):
        raise RedkinError(f"feasible_arm_angles takes one pose of shape (4, 4), got shape {shape}; "
                          "for a batch use feasible_arm_angles_batch or feasible_pieces")
    # the one item of a 0-d object array
    return cast(FeasibleArmAngles, feasible_arm_angles_batch(arm, pose, branch)[()])


def feasible_arm_angles_batch(
    arm: SerialChain | SRSGeometry, pose: ArrayLike, branch: str | Branch = "+++"
) -> np.ndarray:
    """:func:`feasible_arm_angles` of a batch of poses ``(..., 4, 4)``: an object array of
    :class:`FeasibleArmAngles` with the batch shape (0-d for one pose) [000 eqs. 29, 30].

    Raises
    ------
    RedkinError
        For a malformed pose or branch.
    UnreachablePoseError
        For a wrist position out of reach (its ``index`` names the first such pose).
    """
    geometry = as_geometry(arm)
    start, end, keep, theta4, elbow_inside = _from_poses(pose, geometry.kernel_branch(branch), geometry, True)
    return _feasible_arm_angles(start[..., 0, :], end[..., 0, :], keep[..., 0, :, :], theta4[..., 0],
                                elbow_inside[..., 0], parse_branch(branch))
