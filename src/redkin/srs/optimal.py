"""Optimal arm angle for joint-limit avoidance: paper 000 section 5.2, [000 eqs. 35-40].

The shoulder objective ``f_s(psi) = trace(0R3(psi) 0R3d^T) = a_s sin psi +
b_s cos psi + c_s = 1 + 2 cos phi_s`` [000 eq. 36] measures how close the
shoulder rotation is to the one at the target joint values ``theta^d``; the
wrist objective ``f_w`` [000 eq. 38] likewise with ``4R7``.  The MAXIMISER of
``a sin psi + b cos psi`` is ``psi = atan2(a, b)`` -- the root of [000 eqs. 37, 39,
40] (``tan psi = a / b``) with ``(sin psi, cos psi)`` along ``(a, b)``.
Because ``f`` decreases monotonically with the circular distance from its
maximiser, the best feasible arm angle is the feasible point nearest to it
(section 5.2.2, Fig. 5).

The traces are linear in the coefficient matrices of [000 eqs. 12, 16] (see
:mod:`redkin.srs.coefficients`): ``a_s = sum_ij A_s[i, j] 0R3d[i, j]`` etc.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_vectors
from redkin.chain import SerialChain
from redkin.circle import ArcSet
from redkin.errors import RedkinError
from redkin.srs._rotations import group_rotations
from redkin.srs._targets import as_geometry
from redkin.srs.branches import Branch
from redkin.srs.coefficients import ArmAngleCoefficients, coefficients_for
from redkin.srs.feasible import FeasibleArmAngles, feasible_from_coefficients
from redkin.srs.geometry import SRSGeometry


@dataclass(frozen=True)
class OptimalAngle:
    """An optimal arm angle before and after clamping to the feasible set.

    ``feasible`` is ``None`` when the feasible set is empty.
    """

    unclamped: float
    feasible: float | None


@dataclass(frozen=True)
class OptimalArmAngles:
    """Shoulder-only [000 eq. 37], wrist-only [000 eq. 39] and weighted [000 eq. 40] optimal arm angles.

    Attributes
    ----------
    shoulder, wrist, overall : OptimalAngle
    shoulder_coefficients, wrist_coefficients : tuple of float
        ``(a_s, b_s, c_s)`` of [000 eq. 36] and ``(a_w, b_w, c_w)`` of [000 eq. 38].
    weights : tuple of float
        ``(r_s, r_w)``.
    """

    shoulder: OptimalAngle
    wrist: OptimalAngle
    overall: OptimalAngle
    shoulder_coefficients: tuple[float, float, float]
    wrist_coefficients: tuple[float, float, float]
    weights: tuple[float, float]


def default_target(geometry: SRSGeometry) -> np.ndarray:
    """The middles of the chain's joint ranges (0 for an unlimited joint), in ``q`` (:attr:`SerialChain.middle`)."""
    return geometry.chain.middle


def objective_coefficients(
    coefficients: ArmAngleCoefficients, geometry: SRSGeometry, q_target: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(a_s, b_s, c_s)`` [000 eq. 36] and ``(a_w, b_w, c_w)`` [000 eq. 38], each of shape ``(..., 3)``, for target
    joint values ``q_target`` ``(7,)`` of the chain."""
    shoulder_target, wrist_target = group_rotations(geometry, q_target)
    shoulder = np.einsum("...kij,...ij->...k", coefficients.shoulder, shoulder_target)  # [000 eq. 36]
    wrist = np.einsum("...kij,...ij->...k", coefficients.wrist, wrist_target)  # [000 eq. 38]
    return shoulder, wrist


def maximiser(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The arm angle maximising ``a sin psi + b cos psi`` [000 eqs. 37, 39, 40]; 0 where the objective is flat."""
    return np.arctan2(a, b)


def _clamped(psi: float | np.ndarray, feasible: ArcSet) -> OptimalAngle:
    value = float(psi)
    return OptimalAngle(unclamped=value, feasible=feasible.nearest(value))


def check_weights(weights: ArrayLike) -> tuple[float, float]:
    """``(r_s, r_w)``: two finite numbers >= 0, not both zero."""
    values = check_vectors(weights, 2, "weights").reshape(2)
    if np.any(values < 0) or not np.any(values > 0):
        raise RedkinError(f"weights (r_s, r_w) must be >= 0 and not both 0, got {values.tolist()}")
    return float(values[0]), float(values[1])


def weighted_objective(shoulder: np.ndarray, wrist: np.ndarray, weights: tuple[float, float]) -> np.ndarray:
    """The coefficients of [000 eq. 40]'s combined objective ``r_s f_s + r_w f_w`` (``(..., 3)`` each).

    The weights are divided by the larger one first: neither that nor [000 eq. 40]'s ``1 / (r_s + r_w)`` moves the
    maximiser, and weights such as 1e308 then do not overflow.
    """
    r_s, r_w = weights
    largest = max(r_s, r_w)
    return (r_s / largest) * shoulder + (r_w / largest) * wrist


def optimal_arm_angles(
    arm: SerialChain | SRSGeometry,
    pose: ArrayLike,
    branch: str | Branch = "+++",
    target: ArrayLike | None = None,
    weights: ArrayLike = (0.5, 0.5),
    feasible: ArcSet | None = None,
) -> OptimalArmAngles:
    """Optimal arm angles of one pose for joint-limit avoidance [000 eqs. 36-40].

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
    pose : array_like, shape (4, 4)
    branch : str or Branch
    target : array_like, shape (7,), optional
        Target joint values ``theta^d`` in ``q`` (joint 4 is not used);
        default: the limit midpoints.
    weights : (r_s, r_w)
        Weights of [000 eq. 40].
    feasible : ArcSet, optional
        The feasible set to clamp to; computed when not given.

    Returns
    -------
    OptimalArmAngles
        Each optimum unclamped and clamped to the nearest feasible arm angle.
    """
    geometry = as_geometry(arm)
    chosen = geometry.table1_branch(branch)
    pose = np.asarray(pose, dtype=float)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must have shape (4, 4), got {pose.shape}")
    q_target = default_target(geometry) if target is None else check_vectors(target, 7, "target")
    if q_target.shape != (7,):
        raise RedkinError(f"target must have shape (7,), got {q_target.shape}")
    r_s, r_w = check_weights(weights)
    coefficients = coefficients_for(geometry, pose, chosen.elbow)
    if feasible is None:
        feasible = cast(FeasibleArmAngles, feasible_from_coefficients(coefficients, chosen, geometry)[()]).feasible
    shoulder, wrist = objective_coefficients(coefficients, geometry, q_target)
    combined = weighted_objective(shoulder, wrist, (r_s, r_w))  # [000 eq. 40]
    return OptimalArmAngles(
        shoulder=_clamped(maximiser(shoulder[0], shoulder[1]), feasible),  # [000 eq. 37]
        wrist=_clamped(maximiser(wrist[0], wrist[1]), feasible),  # [000 eq. 39]
        overall=_clamped(maximiser(combined[0], combined[1]), feasible),  # [000 eq. 40]
        shoulder_coefficients=(float(shoulder[0]), float(shoulder[1]), float(shoulder[2])),
        wrist_coefficients=(float(wrist[0]), float(wrist[1]), float(wrist[2])),
        weights=(r_s, r_w),
    )
