"""Extrema of the joint angles over the arm angle: paper 000 section 4.2, [000 eqs. 21-28].

For a pose and a branch, each psi-dependent joint (1, 2, 3, 5, 6, 7) is of
one of the two types of section 4.2, read from the entry coefficients of
:func:`redkin.srs.coefficients.arm_angle_coefficients` (rows ``a, b, c`` of
``entry(psi) = a sin psi + b cos psi + c``, layout
:data:`redkin.srs.coefficients.ENTRY_LAYOUT`):

* tangent type [000 eq. 21], joints 1, 3, 5, 7: ``tan theta = N / D`` with
  ``N = a_n s + b_n c + c_n``, ``D = a_d s + b_d c + c_d``
  (joint 1: ``N = y``, ``D = x``; joint 3: ``N = t``, ``D = -r2``; wrist
  likewise).  [000 eq. 23]: ``dtheta/dpsi = (a_t s + b_t c + c_t) / (N^2 + D^2)``
  with ``a_t = b_d c_n - b_n c_d``, ``b_t = a_n c_d - a_d c_n``,
  ``c_t = a_n b_d - a_d b_n`` (checked by differentiating [000 eq. 21]: the
  transcription is correct).  The discriminant ``a_t^2 + b_t^2 - c_t^2``
  [000 eq. 24] gives the case:

  - ``> 0``: *periodic* (section 4.2.1 case (1), Fig. 3a): the two roots
    ``psi_0`` of the numerator ([000 eq. 25], computed as ``phi +- acos(-c_t /
    rho)`` by :func:`redkin.srs._feasible_kernels.sinusoid_roots`, the same roots
    without the division by ``b_t - c_t`` of [000 eq. 25], which fails at
    ``psi_0 = +-pi``) are the global maximum and minimum, told apart by the
    sign of [000 eq. 26], ``(a_t cos psi_0 - b_t sin psi_0) / (N^2 + D^2)``;
  - ``< 0``: *monotonic* (section 4.2.1 case (2), Fig. 3b), increasing when
    ``c_t > 0``;
  - ``= 0`` (within a relative tolerance): *singular*, a case the paper does
    not list.  Then ``(-a_t, -b_t, c_t) = N x D`` (the cross product of the
    coefficient vectors) is parallel to ``(sin psi_s, cos psi_s, 1)``, so ``N``
    and ``D`` vanish together at ``psi_s`` with ``(sin psi_s, cos psi_s) =
    -(a_t, b_t) / c_t``: there ``theta_2`` (or ``theta_6``) is 0 or pi
    (section 5.1) and ``theta`` jumps by pi; elsewhere the numerator
    ``c_t (1 - cos(psi - psi_s))`` keeps the sign of ``c_t``, so ``theta`` is
    monotonic;
  - ``a_t = b_t = c_t = 0`` (relative to the coefficients of ``N`` and
    ``D``, :data:`_CONSTANT_TOLERANCE`): *constant*, ``N`` and ``D`` proportional
    (e.g. joint 1 with the arm stretched, ``theta_4 = 0``);
  - ``N = D = 0`` for every psi: *undefined* (singular at every arm angle,
    :attr:`redkin.srs.SingularArmAngles.shoulder_everywhere`).

* cosine type [000 eq. 22], joints 2 and 6: ``cos theta = a s + b c + c``.
  [000 eq. 27], ``dtheta/dpsi = -(a cos psi - b sin psi) / sin theta``, vanishes at
  ``tan psi_0 = a / b``, i.e. at ``atan2(a, b)`` and ``atan2(-a, -b)``; [000 eq. 28],
  ``d2theta/dpsi2 = (a sin psi_0 + b cos psi_0) / sin theta``, is positive
  (minimum) at ``atan2(a, b)`` when ``sin theta > 0`` (branch sign +), so that
  point is the minimum of ``theta`` on the ``+`` branch and the maximum on the
  ``-`` branch.  *Periodic* (Fig. 4), or *constant* when ``a = b = 0`` (the
  wrist on the joint-1 axis makes ``theta_2`` constant).

The branch sign ``sigma = -1`` turns a tangent-type angle by pi (same
stationary points and kinds) and negates a cosine-type one (kinds swap).
Joint values are reported as the chain's ``q`` exactly as :func:`redkin.srs.ik`
returns them (``q = sign (theta - offset)``; a joint with ``sign = -1`` swaps
maximum and minimum).

Section 4.3 sorts a periodic joint into five cases by where its maximum and
minimum lie relative to its limits (:data:`_LIMIT_CASES`); see
:func:`_limit_case`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.chain import SerialChain
from redkin.circle import TWO_PI
from redkin.errors import RedkinError
from redkin.srs._feasible_kernels import sinusoid_roots
from redkin.srs._targets import as_geometry
from redkin.srs.branches import Branch
from redkin.srs.coefficients import coefficients_for
from redkin.srs.geometry import MEMBERSHIP_TOLERANCE, SRSGeometry
from redkin.srs.ik import theta_at
from redkin.srs.joints import PSI_JOINTS

#: Relative tolerance of the singular case: ``|a_t^2 + b_t^2 - c_t^2| <= tolerance (a_t^2 + b_t^2 + c_t^2)``.
_EXTREMA_TOLERANCE = 1e-9
#: A joint counts as constant when it swings by less than this (radians) between its extrema
#: (cosine type: ``acos(c - rho) - acos(c + rho)``, ``rho = hypot(a, b)``), or, tangent type, when
#: ``|(a_t, b_t, c_t)| = |n x d| <= _CONSTANT_TOLERANCE |n| |d|`` (coefficient vectors of N and D parallel).
_CONSTANT_TOLERANCE = 1e-7
# |n x d| below this is rounding of products of O(1) entries whatever |n| |d| is (e.g. N ~ 1e-33 noise)
_ROUNDING_FLOOR = 1e-30
#: Below this size of the coefficient vectors of both N and D a tangent-type joint is undefined.
_VANISHING_TOLERANCE = 1e-12

#: Columns (index into the 14 entries of ``ENTRY_LAYOUT``) and signs of ``N`` and ``D`` of the
#: tangent-type joints 1, 3, 5, 7 [000 eqs. 13, 15, 17, 19]: ``x, y, z, r0, r1, r2, t`` per group.
_TANGENT = {1: (1, 1.0, 0, 1.0), 3: (6, 1.0, 5, -1.0), 5: (8, 1.0, 7, 1.0), 7: (13, 1.0, 12, -1.0)}
#: Column of ``cos theta`` of the cosine-type joints 2 and 6 [000 eqs. 14, 18].
_COSINE = {2: 2, 6: 9}

#: The five cases of paper 000 section 4.3 for a periodic joint with limits ``[l, u]``.
_LIMIT_CASES = {
    1: "theta_max < l or theta_min > u: no feasible arm angle",
    2: "l <= theta_max <= u and theta_min < l: one feasible region around psi_max, bounded by theta = l",
    3: "theta_max > u and l <= theta_min <= u: one feasible region around psi_min, bounded by theta = u",
    4: "theta_max > u and theta_min < l: all but a region around psi_max and one around psi_min",
    5: "l <= theta_min and theta_max <= u: every arm angle is feasible",
}

_REFERENCES = {
    ("tangent", "periodic"): (
        "[000 eq. 24] holds: section 4.2.1 case (1), periodic, global max and min at the psi_0 of [000 eq. 25] "
        "(Fig. 3a)"
    ),
    ("tangent", "monotonic"): "[000 eq. 24] fails: section 4.2.1 case (2), monotonic (Fig. 3b)",
    ("tangent", "singular"): (
        "[000 eq. 24] with equality (not among the paper's cases): N = D = 0 at one arm angle "
        "(theta_2 or theta_6 = 0 or pi, section 5.1), where theta jumps by pi; monotonic elsewhere"
    ),
    ("tangent", "constant"): (
        "a_t = b_t = c_t = 0 in [000 eq. 23]: N and D of [000 eq. 21] proportional, theta independent of psi"
    ),
    ("tangent", "undefined"): (
        "N = D = 0 in [000 eq. 21] for every psi: singular at every arm angle (arm stretched along the joint-1 "
        "axis, or the wrist counterpart); only the sum or difference with the third joint of the group is "
        "determined"
    ),
    ("cosine", "periodic"): (
        "section 4.2.2: extrema at tan psi_0 = a / b ([000 eq. 27]), max or min by [000 eq. 28] (Fig. 4)"
    ),
    ("cosine", "constant"): "a = b = 0 in [000 eq. 22]: theta independent of psi",
}


@dataclass(frozen=True)
class Stationary:
    """A global extremum of one joint over the arm angle.

    Attributes
    ----------
    psi : float
        Arm angle in ``[-pi, pi)``.
    value : float
        The joint value ``q_i`` there (as :func:`redkin.srs.ik` returns it).
    """

    psi: float
    value: float


@dataclass(frozen=True)
class JointExtrema:
    """How one joint varies with the arm angle (paper 000 section 4.2).

    Attributes
    ----------
    joint : int
        1, 2, 3, 5, 6 or 7.
    kind : str
        ``"tangent"`` [000 eq. 21] or ``"cosine"`` [000 eq. 22].
    case : str
        ``"periodic"``, ``"monotonic"``, ``"singular"``, ``"constant"`` or
        ``"undefined"`` (see the module docstring).
    reference : str
        Where the case is in the paper, in words.
    coefficients : tuple of float
        ``(a_t, b_t, c_t)`` of [000 eq. 23] (tangent) or ``(a, b, c)`` of [000 eq. 22]
        (cosine, branch sign +).
    discriminant : float
        ``a_t^2 + b_t^2 - c_t^2`` [000 eq. 24]; ``a^2 + b^2`` for the cosine type.
    maximum, minimum : Stationary or None
        The global extrema (periodic case only).  A tangent-type joint's
        values are angles on the circle: it sweeps from ``minimum.value`` up
        to ``maximum.value`` modulo ``2 pi`` (the two may straddle ``+-pi``).
    monotonic : bool
        True in the monotonic and singular cases.
    direction : int
        +1 (increasing with psi), -1 (decreasing) when monotonic, else 0.
    jump : float or None
        Singular case: the arm angle where theta jumps by pi (equals the
        shoulder or wrist arm angle of :func:`redkin.srs.singular_arm_angles`
        when that is ``theta_2 = 0`` or ``theta_6 = 0``).
    limit_case : int or None
        Case 1-5 of section 4.3 (:data:`_LIMIT_CASES`) for a periodic joint;
        5 for an unlimited joint; None for monotonic, singular and constant
        joints and when the swept range leaves the limits through ``+-pi``
        and comes back (outside the paper's five cases).
    """

    joint: int
    kind: str
    case: str
    reference: str
    coefficients: tuple[float, float, float]
    discriminant: float
    maximum: Stationary | None
    minimum: Stationary | None
    monotonic: bool
    direction: int
    jump: float | None
    limit_case: int | None


def _tangent_derivative_coefficients(numerator: np.ndarray, denominator: np.ndarray) -> np.ndarray:
    """``(a_t, b_t, c_t)`` of [000 eq. 23] from ``(a_n, b_n, c_n)`` and ``(a_d, b_d, c_d)`` (last axis), batched."""
    a_n, b_n, c_n = np.moveaxis(numerator, -1, 0)
    a_d, b_d, c_d = np.moveaxis(denominator, -1, 0)
    return np.stack([b_d * c_n - b_n * c_d, a_n * c_d - a_d * c_n, a_n * b_d - a_d * b_n], axis=-1)  # [000 eq. 23]


def _tangent_case(
    derivative: np.ndarray, scale: np.ndarray | float = 1.0, tolerance: float = _EXTREMA_TOLERANCE
) -> np.ndarray:
    """Case of tangent-type joints from ``(a_t, b_t, c_t)`` ``(..., 3)``: [000 eq. 24] and its equality.

    ``scale`` is ``|n| |d|`` (see :data:`_CONSTANT_TOLERANCE`).  Returns an
    array of ``"periodic"``, ``"monotonic"``, ``"singular"`` or ``"constant"``.
    """
    size = np.einsum("...i,...i->...", derivative, derivative)
    discriminant = size - 2.0 * derivative[..., 2] ** 2  # [000 eq. 24]
    case = np.where(discriminant > 0.0, "periodic", "monotonic")
    case = np.where(np.abs(discriminant) <= tolerance * size, "singular", case)
    return np.where(np.sqrt(size) <= _CONSTANT_TOLERANCE * scale + _ROUNDING_FLOOR, "constant", case)


def _tangent_cases(
    numerator: np.ndarray, denominator: np.ndarray, tolerance: float = _EXTREMA_TOLERANCE
) -> tuple[np.ndarray, np.ndarray]:
    """``(a_t, b_t, c_t)`` [000 eq. 23] and the case of tangent-type joints from the coefficients of ``N`` and ``D``.

    Adds ``"undefined"`` to the cases of :func:`_tangent_case` where ``N = D = 0`` for every psi.
    """
    derivative = _tangent_derivative_coefficients(numerator, denominator)
    n_size, d_size = np.linalg.norm(numerator, axis=-1), np.linalg.norm(denominator, axis=-1)
    case = _tangent_case(derivative, n_size * d_size, tolerance)
    return derivative, np.where(np.maximum(n_size, d_size) <= _VANISHING_TOLERANCE, "undefined", case)


def _limit_case(maximum: float, minimum: float, lower: float, upper: float, binding: bool) -> int | None:
    """Case 1-5 of paper 000 section 4.3 for a periodic joint sweeping ``[minimum, maximum]`` (modulo 2 pi).

    The comparisons are made modulo ``2 pi`` (limits crossing ``+-pi``
    work) with the slack :data:`redkin.srs.geometry.MEMBERSHIP_TOLERANCE`.
    Returns None when both extremes lie within the limits but the swept
    range leaves them in between (a wide range whose gap the joint crosses:
    two feasible regions, one around each extremum -- not one of the five
    cases, which assume no wrap-around).
    """
    if not binding:  # unlimited, or a range holding every angle modulo 2 pi
        return 5
    slack = MEMBERSHIP_TOLERANCE
    span = upper - lower + 2.0 * slack

    def inside(value: float) -> bool:
        return float(np.mod(value - lower + slack, TWO_PI)) <= span

    width = float(np.mod(maximum - minimum, TWO_PI))

    def crossed(limit: float) -> bool:
        offset = float(np.mod(limit - minimum, TWO_PI))
        return slack < offset < width - slack

    max_in, min_in = inside(maximum), inside(minimum)
    if max_in and min_in:
        return None if crossed(lower) or crossed(upper) else 5
    if max_in:
        return 2
    if min_in:
        return 3
    return 4 if crossed(lower) else 1


def joint_extrema(
    arm: SerialChain | SRSGeometry,
    pose: ArrayLike,
    branch: str | Branch = "+++",
    tolerance: float = _EXTREMA_TOLERANCE,
) -> dict[int, JointExtrema]:
    """Type, case, extrema and monotonicity of each psi-dependent joint for one pose [000 eqs. 21-28].

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
        An S-R-S arm in paper 000 Table 1 form (its limits give ``limit_case``).
    pose : array_like, shape (4, 4)
        One target pose of the tool in the base frame (not batched).
    branch : str or Branch
        Signs of theta_2, theta_4, theta_6, e.g. ``"+-+"``.
    tolerance : float
        Relative tolerance of the singular case (equality in [000 eq. 24]), see :func:`_tangent_case`.

    Returns
    -------
    dict of int to JointExtrema
        Keys 1, 2, 3, 5, 6, 7 (theta_4 does not depend on psi, [000 eq. 11]).

    Raises
    ------
    ValueError
        For a malformed, batched or unreachable pose, a malformed branch or a bad tolerance.

    Examples
    --------
    >>> import numpy as np
    >>> from redkin.models import pa10_7c
    >>> from redkin.srs import joint_extrema, pose_from
    >>> pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    >>> extrema = joint_extrema(pa10_7c(), pose, "+++")
    >>> e = extrema[2]
    >>> e.kind, e.case, e.limit_case, round(float(np.degrees(e.minimum.value)), 3)
    ('cosine', 'periodic', 3, 25.666)
    """
    geometry = as_geometry(arm)
    chosen = geometry.table1_branch(branch)
    if not (np.isfinite(tolerance) and 0.0 <= tolerance < 1.0):
        raise RedkinError(f"tolerance must be a finite number in [0, 1), got {tolerance!r}")
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must have shape (4, 4) (one pose), got {pose.shape}")
    coefficients = coefficients_for(geometry, pose, chosen.elbow)
    entries = coefficients.entries  # (3, 14): rows a, b, c

    tangent_joints = tuple(_TANGENT)
    numerator = np.stack([entries[:, n] * sn for n, sn, _, _ in _TANGENT.values()])  # (4, 3)
    denominator = np.stack([entries[:, d] * sd for _, _, d, sd in _TANGENT.values()])
    derivative, cases = _tangent_cases(numerator, denominator, tolerance)  # (4, 3), (4,)

    stationary = np.zeros((len(PSI_JOINTS), 2))  # per column of PSI_JOINTS: psi of (maximum, minimum) of theta
    for k, joint in enumerate(tangent_joints):
        a_t, b_t, c_t = derivative[k]
        if cases[k] != "periodic":
            continue
        roots = np.array(sinusoid_roots(*(derivative[k] / np.linalg.norm(derivative[k]))))  # [000 eq. 25] (scale-free)
        curvature = a_t * np.cos(roots) - b_t * np.sin(roots)  # numerator of [000 eq. 26]
        stationary[PSI_JOINTS.index(joint)] = roots[np.argsort(curvature)]  # negative first: maximum
    for joint, column in _COSINE.items():
        a, b, _ = entries[:, column]
        sigma = chosen.shoulder if joint == 2 else chosen.wrist
        psi_0 = np.arctan2(a, b)  # [000 eq. 27]; [000 eq. 28] > 0 here when sigma = +1
        both = np.mod(np.array([psi_0, psi_0 + np.pi]) + np.pi, TWO_PI) - np.pi
        stationary[PSI_JOINTS.index(joint)] = both[::-1] if sigma > 0 else both

    theta = theta_at(coefficients, stationary, chosen)  # (6, 2, 7)
    q = geometry.to_chain_q(theta)
    chain = geometry.chain

    results = {}
    for k, joint in enumerate(PSI_JOINTS):
        column = joint - 1
        flip = chain.sign[column] < 0  # q = sign (theta - offset)
        if joint in _TANGENT:
            kind = "tangent"
            index = tangent_joints.index(joint)
            case = str(cases[index])
            a_t, b_t, c_t = (float(v) for v in derivative[index])
            coefficient_tuple = (a_t, b_t, c_t)
            discriminant = a_t * a_t + b_t * b_t - c_t * c_t
            direction = int(np.sign(c_t)) if case in ("monotonic", "singular") else 0
            jump = float(np.arctan2(-a_t / c_t, -b_t / c_t)) if case == "singular" else None
        else:
            kind = "cosine"
            a, b, c = (float(v) for v in entries[:, _COSINE[joint]])
            coefficient_tuple = (a, b, c)
            discriminant = a * a + b * b
            rho = np.sqrt(discriminant)
            swing = np.arccos(max(c - rho, -1.0)) - np.arccos(min(c + rho, 1.0))
            case = "constant" if swing <= _CONSTANT_TOLERANCE else "periodic"
            direction, jump = 0, None
        (psi_max, psi_min), (q_max, q_min) = stationary[k], q[k, :, column]
        if case == "periodic" and abs(np.mod(q_max - q_min + np.pi, TWO_PI) - np.pi) <= _CONSTANT_TOLERANCE:
            case = "constant"  # a swing below the tolerance (e.g. theta_4 = 0 up to rounding)
        maximum = minimum = None
        cut = None
        if case == "periodic":
            if flip:
                psi_max, psi_min, q_max, q_min = psi_min, psi_max, q_min, q_max
            maximum = Stationary(float(psi_max), float(q_max))
            minimum = Stationary(float(psi_min), float(q_min))
            cut = _limit_case(
                maximum.value, minimum.value, float(chain.lower[column]), float(chain.upper[column]),
                not bool(chain.covers_circle[column]),
            )
        results[joint] = JointExtrema(
            joint=joint,
            kind=kind,
            case=case,
            reference=_REFERENCES[(kind, case)],
            coefficients=coefficient_tuple,
            discriminant=discriminant,
            maximum=maximum,
            minimum=minimum,
            monotonic=case in ("monotonic", "singular"),
            direction=-direction if flip else direction,
            jump=jump,
            limit_case=cut,
        )
    return results
