"""The S-R-S geometry of a chain in the form of paper 000 Table 1.

:func:`srs_geometry` checks that a :class:`~redkin.chain.SerialChain` is a
7-DOF S-R-S arm in the Table 1 form (standard DH, ``a = 0``,
``alpha = (-pi/2, pi/2, -pi/2, pi/2, -pi/2, pi/2, 0)``, ``d = (d_bs, 0, d_se,
0, d_ew, 0, d_wt)``) and extracts the link lengths.  The form extends to an
offset elbow (the Barrett WAM): ``a_3`` and ``a_4`` may be non-zero, the
shoulder (joints 1-3) and the wrist (joints 5-7) still meet in points
(docs/srs.md, "Offset elbows").  The chain's ``base``, ``tool``, joint
``offset`` and ``sign`` are supported: the solver works on the DH angles
``theta = offset + sign * q`` and on the pose of frame 7 in frame 0, and
converts at the edge.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from redkin.chain import SerialChain
from redkin.circle import TWO_PI
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.srs import _ik_kernels
from redkin.srs._ik_kernels import MEMBERSHIP_TOLERANCE
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.conventions import TABLE1_ALPHA, table1_form
from redkin.srs.joints import PSI_JOINTS, limit_equation_table, limit_sign_membership

#: Tolerance on the DH parameters when recognising the Table 1 form.
_GEOMETRY_TOLERANCE = 1e-9


class ElbowEquation(NamedTuple):
    """``|x_sw|^2 = A cos theta_4 + B sin theta_4 + C = C + R cos(theta_4 - phi)`` ([000 eq. 11] with an offset elbow).

    In frame 3 the shoulder-to-wrist vector is ``v(theta_4) = (a_3 + a_4 c4 +
    d_ew s4, -d_se + a_4 s4 - d_ew c4, 0)``, so ``A = 2 (a_3 a_4 + d_se d_ew)``,
    ``B = 2 (a_3 d_ew - d_se a_4)``, ``C = a_3^2 + a_4^2 + d_se^2 + d_ew^2``;
    ``R = sqrt(A^2 + B^2)`` and ``phi = atan2(B, A)``.  Without offsets
    ``phi = 0`` and this is [000 eq. 11] itself.

    Attributes
    ----------
    mean, amplitude, phase : float
        ``C``, ``R`` and ``phi``: ``|x_sw|`` ranges over ``[sqrt(C - R), sqrt(C + R)]``,
        the two elbow solutions are ``theta_4 = phi +- acos((|x_sw|^2 - C) / R)``.
    """

    mean: float
    amplitude: float
    phase: float


class PsiJointLimits(NamedTuple):
    """Limits of the psi-dependent joints 1, 2, 3, 5, 6, 7, prepared once per arm.

    A joint value ``theta`` is within its limits when ``(theta - start) mod
    2 pi <= span`` or the joint is ``free`` (unlimited); ``start`` and
    ``span`` include the membership slack (:func:`redkin.srs.feasible.within`).

    Attributes
    ----------
    start, span : numpy.ndarray, shape (6,)
        Lower DH limit minus the slack and range width plus twice the slack.
    free : numpy.ndarray of bool, shape (6,)
        Unlimited joints (range ``>= 2 pi``).
    weights, offset : numpy.ndarray
        The limit equations (see :func:`redkin.srs.joints.limit_equation_table`).
    stretched_weights, stretched_offset : numpy.ndarray
        The same for a group singular at every arm angle (``stretched=True``).
    membership : numpy.ndarray of bool, shape (2, 2, 24)
        ``[n2, n6]``: for branches with ``sigma_2 < 0`` (``n2 = 1``) or not and
        likewise ``sigma_6``, the flattened ``(6, 4)`` table of
        :func:`redkin.srs.joints.limit_sign_membership`.
    elbow_start, elbow_span : float
    elbow_free : numpy.bool_
        The same for joint 4.
    """

    start: np.ndarray
    span: np.ndarray
    free: np.ndarray
    weights: np.ndarray
    offset: np.ndarray
    stretched_weights: np.ndarray
    stretched_offset: np.ndarray
    membership: np.ndarray
    elbow_start: float
    elbow_span: float
    elbow_free: np.bool_


@dataclass(frozen=True, eq=False)
class SRSGeometry:
    """A 7-DOF S-R-S arm reduced to what the arm-angle solver needs.

    Attributes
    ----------
    chain : SerialChain
        The chain it was built from (joint values ``q`` refer to it).
    d_bs, d_se, d_ew, d_wt : float
        Base-shoulder, shoulder-elbow, elbow-wrist, wrist-tool lengths (Table 1).
    a3, a4 : float
        Offsets of an offset elbow (DH ``a_3``, ``a_4``; 0 on an S-R-S arm,
        0.045 and -0.045 m on the Barrett WAM).
    theta_lower, theta_upper : numpy.ndarray, shape (7,)
        Joint limits on the DH angles ``theta`` modulo ``2 pi``: a joint whose
        range holds every angle (unlimited, or wider than ``2 pi``;
        :attr:`SerialChain.covers_circle`) gets ``(-inf, inf)``.  The joint
        values themselves are chosen inside the chain's own limits
        (:meth:`to_chain_q`).
    """

    chain: SerialChain
    d_bs: float
    d_se: float
    d_ew: float
    d_wt: float
    theta_lower: np.ndarray
    theta_upper: np.ndarray
    a3: float = 0.0
    a4: float = 0.0
    plain_joints: bool = False
    wrap_columns: tuple[int, ...] = ()

    @property
    def theta_limited(self) -> np.ndarray:
        """Which joints have a range narrower than ``2 pi``."""
        return self.theta_upper - self.theta_lower < TWO_PI

    @cached_property
    def branch_senses(self) -> tuple[int, int, int]:
        """Per branch sign (theta_2, theta_4, theta_6), +1 or -1: the chain's own sense of that joint, turned over
        where its zero is nearer ``theta = pi`` (see :meth:`table1_branch`)."""
        sign, offset = self.chain.sign, self.chain.offset
        s2, s4, s6 = (int(sign[k]) * (1 if np.cos(offset[k]) >= 0.0 else -1) for k in (1, 3, 5))
        return s2, s4, s6

    def table1_branch(self, branch: str | Branch | tuple[int, int, int]) -> Branch:
        """The Table 1 branch of a branch named in the chain's joint senses (and back: the map is its own inverse).

        A branch names the signs of theta_2, ``theta_4 - phi`` and theta_6
        (paper 000 section 3.3; ``phi`` of an offset elbow).  On a chain
        whose joint ``k`` turns the other way (``sign = -1``, as joint 4 of
        KUKA's iiwa) or whose zero pose is nearer ``theta = pi``, that sign
        is flipped, so that ``"+++"`` on an iiwa in KUKA's conventions has
        ``q_2, q_4, q_6 >= 0``.

        Raises
        ------
        ValueError
            For a malformed branch (:func:`redkin.srs.branches.parse_branch`).
        """
        chosen = parse_branch(branch)
        if self.branch_senses == (1, 1, 1):
            return chosen
        return Branch(*(int(s) * e for s, e in zip(chosen, self.branch_senses)))

    @cached_property
    def branch_order(self) -> np.ndarray:
        """Index into :data:`BRANCHES` of the Table 1 branch of each branch in :data:`BRANCHES`."""
        return np.array([BRANCHES.index(self.table1_branch(branch)) for branch in BRANCHES])

    @cached_property
    def elbow_equation(self) -> ElbowEquation:
        """The shoulder-wrist distance as a function of theta_4 (see :class:`ElbowEquation`)."""
        return elbow_equation(self.a3, self.a4, self.d_se, self.d_ew)

    @property
    def offset_elbow(self) -> bool:
        """Whether the elbow has offsets (``a_3`` or ``a_4`` non-zero)."""
        return self.a3 != 0.0 or self.a4 != 0.0

    @cached_property
    def psi_joint_limits(self) -> PsiJointLimits:
        """The box limits [000 eq. 20] of joints 1, 2, 3, 5, 6, 7 (and 4) with their limit equations (computed once)."""
        limited = self.theta_limited
        lower = np.where(limited, self.theta_lower, 0.0)
        upper = np.where(limited, self.theta_upper, 0.0)
        start = lower - MEMBERSHIP_TOLERANCE
        span = upper - lower + 2.0 * MEMBERSHIP_TOLERANCE
        free = ~limited
        columns = [j - 1 for j in PSI_JOINTS]
        weights, offset = limit_equation_table(lower[columns], upper[columns], limited[columns])
        stretched = limit_equation_table(lower[columns], upper[columns], limited[columns], stretched=True)
        arrays = (start[columns], span[columns], free[columns])
        by_sign = limit_sign_membership(lower[columns], upper[columns], *arrays)  # (2, 6, 4)
        membership: np.ndarray = np.empty((2, 2, 6, 4), dtype=bool)
        membership[:, :, :3] = by_sign[:, None, :3]  # shoulder joints follow sigma_2
        membership[:, :, 3:] = by_sign[None, :, 3:]  # wrist joints follow sigma_6
        membership = membership.reshape(2, 2, 24)
        for array in arrays + (membership,):
            array.setflags(write=False)
        return PsiJointLimits(*arrays, weights, offset, *stretched, membership, float(start[3]), float(span[3]),
                              free[3])

    def theta_of_q(self, q: np.ndarray) -> np.ndarray:
        """DH angles ``theta = offset + sign * q``."""
        return q if self.plain_joints else self.chain.offset + self.chain.sign * q

    def q_of_theta(self, theta: np.ndarray) -> np.ndarray:
        """Joint values ``q = sign * (theta - offset)`` (``sign`` is +-1)."""
        return theta if self.plain_joints else self.chain.sign * (theta - self.chain.offset)

    def to_chain_q(self, theta: np.ndarray) -> np.ndarray:
        """Joint values of the chain for DH angles ``theta`` ``(..., 7)``.

        Each value is shifted by a multiple of ``2 pi`` into its limit range
        when one such shift lands there (limits that cross ``+-pi``, e.g.
        ``[100, 260]`` deg); where several do (a range wider than ``2 pi``),
        the one nearest the middle of the range; otherwise it is wrapped to
        ``[-pi, pi)`` (:func:`redkin.srs._ik_kernels.chain_values`).  For the
        representative nearest a seed instead, pass the result to
        :meth:`SerialChain.nearest_in_range` with ``near``.
        """
        if self.plain_joints and not self.wrap_columns:
            return theta  # DH angles from atan2 already lie in [-pi, pi] and so do the limits
        flat = np.ascontiguousarray(theta, dtype=float).reshape(-1, 7)
        q = np.empty_like(flat)
        _ik_kernels.joint_values(flat, self.kernel_joints, q)
        return q.reshape(np.shape(theta))

    @cached_property
    def kernel_tables(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(kernel_arm, kernel_ends, kernel_joints)``: the arm as every kernel of :mod:`redkin.srs._ik_kernels`
        takes it."""
        return self.kernel_arm, self.kernel_ends, self.kernel_joints

    @cached_property
    def kernel_arm(self) -> np.ndarray:
        """The arm as :mod:`redkin.srs._ik_kernels` reads it: ``d_bs, d_se, d_ew, d_wt, a_3, a_4, C, R, phi, cos phi,
        sin phi``."""
        equation = self.elbow_equation
        return _read_only(np.array([self.d_bs, self.d_se, self.d_ew, self.d_wt, self.a3, self.a4, *equation,
                                    np.cos(equation.phase), np.sin(equation.phase)]))

    @cached_property
    def kernel_ends(self) -> np.ndarray:
        """``base^-1`` and ``tool^-1`` of the chain, (2, 4, 4): frame 7 in frame 0 is ``base^-1 pose tool^-1``."""
        return _read_only(np.linalg.inv(np.stack([self.chain.base, self.chain.tool])))

    @cached_property
    def kernel_joints(self) -> np.ndarray:
        """The joint-value map of :meth:`to_chain_q` as :mod:`redkin.srs._ik_kernels` reads it, (5, 7)."""
        chain = self.chain
        wrap = np.isin(np.arange(7), self.wrap_columns)
        table = np.stack([chain.offset, chain.sign, wrap, chain.lower, chain.upper]).astype(float)
        return _read_only(table)

    def kernel_branch(self, branch: str | Branch | tuple[int, int, int]) -> np.ndarray:
        """The Table 1 signs of one branch named in the chain's joint senses, (1, 3) float, parsed once per name.

        Raises
        ------
        ValueError
            For a malformed branch (:func:`redkin.srs.branches.parse_branch`).
        """
        try:
            return self._kernel_branch_cache[branch]
        except (KeyError, TypeError):  # a new name, or an unhashable one (a list of signs)
            table = _read_only(np.array([self.table1_branch(branch)], dtype=float))
            if isinstance(branch, (str, tuple)):
                self._kernel_branch_cache[branch] = table
            return table

    @cached_property
    def _kernel_branch_cache(self) -> dict:
        return {}

    @cached_property
    def kernel_branches(self) -> np.ndarray:
        """The Table 1 signs ``(sigma_2, sigma_4, sigma_6)`` of each branch of :data:`BRANCHES`, (8, 3) float."""
        return _read_only(np.array([self.table1_branch(branch) for branch in BRANCHES], dtype=float))


def _read_only(array: np.ndarray) -> np.ndarray:
    array = np.ascontiguousarray(array, dtype=float)
    array.setflags(write=False)
    return array


def elbow_equation(a3: float, a4: float, d_se: float, d_ew: float) -> ElbowEquation:
    """``C``, ``R`` and ``phi`` of ``|x_sw|^2 = C + R cos(theta_4 - phi)`` (see :class:`ElbowEquation`)."""
    a_coefficient = 2.0 * (a3 * a4 + d_se * d_ew)
    b_coefficient = 2.0 * (a3 * d_ew - d_se * a4)
    mean = a3 * a3 + a4 * a4 + d_se * d_se + d_ew * d_ew
    return ElbowEquation(mean, float(np.hypot(a_coefficient, b_coefficient)),
                         float(np.arctan2(b_coefficient, a_coefficient)))


def _table1_violation(chain: SerialChain) -> str | None:
    """The first way a 7-joint chain departs from paper 000 Table 1 form, or ``None`` if it is in that form.

    The form admits an offset elbow (``a_3``, ``a_4``) as long as ``theta_4``
    changes the shoulder-wrist distance (``R > 0`` in :class:`ElbowEquation`).
    """
    if chain.convention != "dh":
        return f"an S-R-S arm in paper 000 Table 1 form uses standard DH, {chain.name!r} uses {chain.convention!r}"
    tol = _GEOMETRY_TOLERANCE
    bad = np.flatnonzero(np.abs(chain.a[[0, 1, 4, 5, 6]]) > tol)
    if bad.size:
        i = int([0, 1, 4, 5, 6][bad[0]])
        return (f"Table 1 form has a_{i + 1} = 0 (only a_3 and a_4 may be elbow offsets), "
                f"{chain.name!r} has {chain.a[i]:g}")
    bad = np.flatnonzero(np.abs(np.mod(chain.alpha - TABLE1_ALPHA + np.pi, TWO_PI) - np.pi) > tol)
    if bad.size:
        i = int(bad[0])
        return (f"Table 1 form has twists (-90, 90, -90, 90, -90, 90, 0) deg, {chain.name!r} has "
                f"alpha_{i + 1} = {np.degrees(chain.alpha[i]):g} deg")
    for i in (1, 3, 5):
        if abs(chain.d[i]) > tol:
            return f"Table 1 form has d_{i + 1} = 0, {chain.name!r} has d_{i + 1} = {chain.d[i]:g}"
    for i, label in ((2, "d_se (d_3)"), (4, "d_ew (d_5)")):
        if chain.d[i] < 0.0:
            return f"Table 1 form has {label} >= 0, {chain.name!r} has {chain.d[i]:g}"
    if elbow_equation(chain.a[2], chain.a[3], chain.d[2], chain.d[4]).amplitude <= tol:
        return (f"{chain.name!r}: the elbow axis passes through the shoulder or the wrist, "
                "so the shoulder-wrist distance does not fix theta_4")
    return None


def srs_geometry(chain: SerialChain) -> SRSGeometry:
    """The arm-angle solver's view of an S-R-S arm, in any description.

    An arm already in paper 000 Table 1 form is used as it is; any other 7R
    chain whose shoulder and wrist axes meet (a URDF, another DH table,
    modified DH, other zero pose or joint senses, an offset elbow) is brought
    to that form with the same joint values and limits
    (:func:`redkin.srs.conventions.table1_form`), as is a Table 1 chain
    whose joint-3 zero is nearer ``theta_3 = pi`` than 0: the arm angle's
    reference plane (``theta_3 = 0``) is then where the chain's own
    ``q_3 = 0``, whatever the description.

    Raises
    ------
    NotArmAngleClassError
        Naming the first violated S-R-S condition, with its distance or angle
        (a ``ValueError``; its ``distance`` attribute holds the measure where one applies).
    RedkinError
        If ``chain`` is not a :class:`~redkin.chain.SerialChain`.
    """
    if not isinstance(chain, SerialChain):
        raise RedkinError(f"chain must be a SerialChain, got {type(chain).__name__}")
    cached = chain.__dict__.get(_CACHE_KEY)
    if cached is None:  # derived once per chain: its arrays are read-only, so it never goes stale
        cached = _derive_geometry(chain)
        object.__setattr__(chain, _CACHE_KEY, cached)
    return cached


_CACHE_KEY = "_srs_geometry"


def _derive_geometry(chain: SerialChain) -> SRSGeometry:
    """:func:`srs_geometry` without the cache."""
    if chain.n != 7:
        raise NotArmAngleClassError(f"an S-R-S arm has 7 joints, {chain.name!r} has {chain.n}", chain.name)
    if _table1_violation(chain) is not None or np.cos(chain.offset[2]) < 0.0:
        chain = table1_form(chain)
        problem = _table1_violation(chain)
        if problem is not None:  # pragma: no cover - table1_form writes Table 1 rows
            raise NotArmAngleClassError(problem, chain.name)
    sign, offset = chain.sign, chain.offset
    lo = np.where(sign > 0, offset + chain.lower, offset - chain.upper)
    hi = np.where(sign > 0, offset + chain.upper, offset - chain.lower)
    free = chain.covers_circle  # every angle has a representative in range: no constraint modulo 2 pi
    theta_lower = np.where(free, -np.inf, lo)
    theta_upper = np.where(free, np.inf, hi)
    for array in (theta_lower, theta_upper):
        array.setflags(write=False)
    plain_joints = bool(np.all(offset == 0.0) and np.all(sign == 1.0))
    outside = (chain.lower < -np.pi) | (chain.upper > np.pi)
    wrap = [k for k in range(7) if not plain_joints or (outside[k] and chain.limited[k])]
    return SRSGeometry(
        chain=chain,
        d_bs=float(chain.d[0]),
        d_se=float(chain.d[2]),
        d_ew=float(chain.d[4]),
        d_wt=float(chain.d[6]),
        theta_lower=theta_lower,
        theta_upper=theta_upper,
        a3=float(chain.a[2]),
        a4=float(chain.a[3]),
        plain_joints=plain_joints,
        wrap_columns=tuple(wrap),
    )


def pose_from(position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """Homogeneous transforms from positions and rotations (batched)."""
    pose = np.zeros(position.shape[:-1] + (4, 4))
    pose[..., :3, :3] = rotation
    pose[..., :3, 3] = position
    pose[..., 3, 3] = 1.0
    return pose
