"""Feasible arm angles under box joint limits: paper 000 section 4, eqs. 20-30.

For each joint ``i`` the set ``Psi_i`` of arm angles at which
``theta_i(psi)`` lies within its limits (eq. 29) is a union of closed arcs,
and the feasible set is ``Psi = intersection of the Psi_i`` (eq. 30).

Closed form, never missing a narrow arc: every arm angle where
``theta_i(psi)`` equals a limit solves a linear equation in
``(sin psi, cos psi)`` (:func:`redkin.srs.joints.limit_equation_table`, derived
from eqs. 21 and 22), which has at most two roots in closed form
(:func:`redkin.srs.joints.sinusoid_roots`).  Between consecutive roots
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
gives the per-joint sets (eq. 29) and their intersection (eq. 30).
Isolated touching points (a limit reached at a single arm angle from
outside) and pieces shorter than :data:`PIECE_TOLERANCE` are not reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.circle import ArcSet
from redkin.srs.branches import Branch
from redkin.srs.coefficients import ArmAngleCoefficients
from redkin.srs.geometry import SRSGeometry
from redkin.srs.ik import as_geometry, coefficients_for
from redkin.srs.joints import STRETCHED_TOLERANCE, PSI_JOINTS, first_joint_coefficients, sinusoid_roots, within

TWO_PI = 2.0 * np.pi
#: Pieces shorter than this (radians) are dropped: they are repeated roots split by
#: rounding, or a singular arm angle itself, where theta_1/3 or theta_5/7 are undefined.
PIECE_TOLERANCE = 1e-12
_TABLE_ROWS = 4 * np.arange(6)  # row offsets of the six joints in a flattened membership table
_EQUATION_GROUP = np.repeat([0, 1], 6)  # limit-equation columns of the shoulder (0) and the wrist (1)


@dataclass(frozen=True)
class FeasibleArmAngles:
    """Feasible arm angles of one pose and branch.

    Attributes
    ----------
    branch : Branch
    theta4 : float
        The elbow DH angle (independent of psi, eq. 11).
    per_joint : dict of int to ArcSet
        ``Psi_i`` for joints 1..7 (eq. 29); joint 4 is the full circle or empty.
    feasible : ArcSet
        ``Psi``, the intersection (eq. 30); empty means the pose is unreachable
        within the limits on this branch.
    """

    branch: Branch
    theta4: float
    per_joint: dict[int, ArcSet]
    feasible: ArcSet

    @property
    def is_empty(self) -> bool:
        """True when no arm angle satisfies every limit."""
        return self.feasible.is_empty


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
        return _arc_set(self.start[index].tolist(), self.end[index].tolist(), self.feasible[index].tolist())

    @property
    def nonempty(self) -> np.ndarray:
        """Whether each pose has a feasible arm angle (a feasible piece longer than :data:`PIECE_TOLERANCE`)."""
        return np.any(self.feasible & (self.end - self.start > PIECE_TOLERANCE), axis=-1)


def _arc_set(starts: list[float], ends: list[float], keep: list[bool]) -> ArcSet:
    """The arcs of the runs of kept pieces (each piece ends where the next starts), dropping runs
    shorter than :data:`PIECE_TOLERANCE`."""
    runs: list[list[float]] = []
    previous = False
    for start, end, kept in zip(starts, ends, keep):
        if kept and previous:
            runs[-1][1] = end
        elif kept:
            runs.append([start, end])
        previous = kept
    return ArcSet([(a, b) for a, b in runs if b - a > PIECE_TOLERANCE])


def limit_equations(coefficients: ArmAngleCoefficients, geometry: SRSGeometry) -> np.ndarray:
    """Rows ``(p, q, r)`` of the twelve limit equations ``p sin psi + q cos psi + r = 0``, shape ``(..., 3, 12)``.

    Column ``2 k + j`` is joint ``PSI_JOINTS[k]`` at its lower (``j = 0``) or
    upper limit (eqs. 21, 22 set equal to the limit; all twelve in one
    matrix product, :func:`redkin.srs.joints.limit_equation_table`).  A
    group singular at every arm angle (:func:`redkin.srs.joints.first_joint_coefficients`,
    e.g. the home pose of an arm stretched along the joint-1 axis) gets the
    stretched table: eq. 15 (19) is 0/0 there for every psi, while the
    third joint the IK returns still turns with psi.
    """
    limits = geometry.psi_joint_limits
    equations = coefficients.entries @ limits.weights + limits.offset
    size = first_joint_coefficients(coefficients.entries)
    # cheap test first: a stretched group has all six at zero; the sin and cos rows alone, because
    # c of the wrist's y is zero on every pose (the elbow axis is normal to u_sw)
    if size.size and size[..., :2, :, :].min() <= STRETCHED_TOLERANCE:
        stretched = size.max(axis=(-3, -1)) <= STRETCHED_TOLERANCE  # (..., 2): shoulder, wrist
        alternative = coefficients.entries @ limits.stretched_weights + limits.stretched_offset
        equations = np.where(stretched[..., None, _EQUATION_GROUP], alternative, equations)
    return equations


def cut_points(equations: np.ndarray) -> np.ndarray:
    """Every arm angle where a joint reaches a limit, shape ``(..., 6, 4)`` (NaN: none).

    Row ``k`` holds the roots of the :func:`limit_equations` of joint
    ``PSI_JOINTS[k]``: two for its lower and two for its upper limit.
    Unlimited joints have none.
    """
    roots = sinusoid_roots(equations[..., 0, :], equations[..., 1, :], equations[..., 2, :])  # (..., 12, 2)
    return roots.reshape(roots.shape[:-2] + (6, 4))


def _pieces(cuts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cuts ``(..., M)`` (NaN: none) -> starts and ends of the pieces between consecutive cuts.

    The last piece of a pose wraps to its first cut plus ``2 pi``; a pose
    without cuts gets one whole-circle piece ``[-pi, pi]``.  Unused slots
    have a NaN start.
    """
    cuts = np.sort(cuts, axis=-1)  # NaN last
    np.fmax(cuts[..., 0], -np.pi, out=cuts[..., 0])  # no cut at all (NaN): start the whole circle at -pi
    wrap = cuts[..., :1] + TWO_PI
    # the next cut, or the wrapped first one after the last (fmin skips the NaN of unused slots)
    end = np.fmin(np.concatenate([cuts[..., 1:], wrap], axis=-1), wrap)
    return cuts, end


def _middle_trig(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """``(sin psi, cos psi, 1)`` at the middle of each piece, shape ``(..., 3)``."""
    middle = 0.5 * (start + end)
    trig = np.empty(middle.shape + (3,))
    np.sin(middle, out=trig[..., 0])
    np.cos(middle, out=trig[..., 1])
    trig[..., 2] = 1.0
    return trig


def _inside(values: np.ndarray, branch: Branch, geometry: SRSGeometry) -> np.ndarray:
    """Whether each joint is within its limits, from its limit-equation values ``(..., 6, 2)`` -> ``(..., 6)``.

    Off the cut points the signs of a joint's two limit equations decide
    (:func:`redkin.srs.joints.limit_sign_membership`).
    """
    positive = values > 0.0
    pattern = 2 * positive[..., 0] + positive[..., 1] + _TABLE_ROWS
    return geometry.psi_joint_limits.membership[int(branch.shoulder < 0), int(branch.wrist < 0)][pattern]


def elbow_within(coefficients: ArmAngleCoefficients, geometry: SRSGeometry) -> np.ndarray:
    """Whether theta_4 (independent of psi) is within its limits, batched."""
    limits = geometry.psi_joint_limits
    return within(coefficients.theta4, limits.elbow_start, limits.elbow_span, limits.elbow_free)


def _piece_membership(
    coefficients: ArmAngleCoefficients, branch: Branch, geometry: SRSGeometry
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pieces between all joints' cut points and, per piece, which joints are within their limits.

    Returns ``start, end`` ``(..., 24)`` (see :func:`_pieces`) and ``inside``
    ``(..., 24, 6)`` for the columns of :data:`PSI_JOINTS`.  The pieces refine
    every joint's own pieces, so they serve eq. 29 and eq. 30 alike.
    """
    equations = limit_equations(coefficients, geometry)
    cuts = cut_points(equations)
    start, end = _pieces(cuts.reshape(cuts.shape[:-2] + (24,)))
    values = _middle_trig(start, end) @ equations  # (..., 24, 12)
    return start, end, _inside(values.reshape(values.shape[:-1] + (6, 2)), branch, geometry)


def overall_pieces(coefficients: ArmAngleCoefficients, branch: Branch, geometry: SRSGeometry) -> FeasiblePieces:
    """Eq. 30 for a batch: pieces between all joints' cut points, classified for every joint at once."""
    start, end, inside = _piece_membership(coefficients, branch, geometry)
    used = (start == start) & elbow_within(coefficients, geometry)[..., None]  # start is NaN in unused slots
    return FeasiblePieces(start, end, inside.all(axis=-1) & used)


def feasible_pieces(
    arm: "SerialChain | SRSGeometry", pose: ArrayLike, branch: "str | Branch" = "+++"
) -> FeasiblePieces:
    """Batched feasible sets (eq. 30) as arrays, for speed; see :func:`feasible_arm_angles`."""
    geometry = as_geometry(arm)
    chosen = geometry.table1_branch(branch)
    return overall_pieces(coefficients_for(geometry, pose, chosen.elbow), chosen, geometry)


def feasible_from_coefficients(
    coefficients: ArmAngleCoefficients, branch: Branch, geometry: SRSGeometry
) -> "FeasibleArmAngles | np.ndarray":
    """:class:`FeasibleArmAngles` from precomputed coefficients (object array for a batch)."""
    start, end, inside = _piece_membership(coefficients, branch, geometry)
    used = start == start  # start is NaN in unused slots
    elbow_ok = elbow_within(coefficients, geometry)
    overall = inside.all(axis=-1) & used & elbow_ok[..., None]
    by_joint = inside.swapaxes(-1, -2) & used[..., None, :]  # (..., 6, 24): eq. 29 on the shared pieces
    keep = np.concatenate([overall[..., None, :], by_joint], axis=-2)  # (..., 7, 24)
    shape = coefficients.theta4.shape
    results = np.empty(shape, dtype=object)
    for index in np.ndindex(*shape):
        starts, ends = start[index].tolist(), end[index].tolist()
        sets = [_arc_set(starts, ends, kept) for kept in keep[index].tolist()]
        per_joint = dict(zip(PSI_JOINTS, sets[1:]))
        per_joint[4] = ArcSet.full() if elbow_ok[index] else ArcSet.empty()
        results[index] = FeasibleArmAngles(
            branch=geometry.table1_branch(branch),  # as the caller named it
            theta4=float(coefficients.theta4[index]),
            per_joint=dict(sorted(per_joint.items())),
            feasible=sets[0],
        )
    return results[()] if shape == () else results


def feasible_arm_angles(
    arm: "SerialChain | SRSGeometry", pose: ArrayLike, branch: "str | Branch" = "+++"
) -> "FeasibleArmAngles | np.ndarray":
    """Per-joint and overall feasible arm angles (paper 000 eqs. 29, 30).

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
        S-R-S arm with its joint limits (ranges of width >= 2 pi are unlimited).
    pose : array_like, shape (4, 4) or (..., 4, 4)
    branch : str or Branch
        Signs of theta_2, theta_4, theta_6.

    Returns
    -------
    FeasibleArmAngles, or an object array of them with the batch shape.

    Raises
    ------
    ValueError
        For a malformed or unreachable pose or a malformed branch.
    """
    geometry = as_geometry(arm)
    chosen = geometry.table1_branch(branch)
    coefficients = coefficients_for(geometry, pose, chosen.elbow)
    return feasible_from_coefficients(coefficients, chosen, geometry)
