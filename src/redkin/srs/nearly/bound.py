"""How far a nearly S-R-S arm's solution lies from its exact neighbour's: a bound from the offsets and the derivatives.

At an arm angle ``psi`` the neighbour's closed form [000 eqs. 4-19] gives ``q_N`` on a branch: the neighbour's
pose of ``q_N`` is the target ``T`` and its arm angle is ``psi``.  The real arm's solutions are the roots of the 7
equations ``G(q) = [T - FK(q); psi - psi(q)] = 0`` of :mod:`redkin.srs.nearly` (the pose error [N1] of our FK of
the real chain, and the arm angle, which is the neighbour's at the same joint values).  At ``q_N``

- the residual ``r = G(q_N)`` is the two chains' pose difference at ``q_N``, which the dropped offsets make (at most
  the model error :attr:`redkin.srs.nearly.NearlySRS.position_error`, ``.rotation_error``), and zero in the arm
  angle, since ``psi(q_N) = psi_N(q_N) = psi``;
- Newton's first step ``d_0 = J(q_N)^-1 r`` (``J`` the Jacobian of ``G``: the geometric one over the arm angle's
  gradient) is the distance ``|q - q_N|`` to first order in the offsets.

Kantorovich's theorem in its affine-covariant form (P. Deuflhard, *Newton Methods for Nonlinear Problems*, 2004,
ch. 2): if ``|J(q_N)^-1 (J(x) - J(y))| <= omega |x - y|`` near ``q_N`` and ``h = omega |d_0| <= 1/2``, the
equations have a solution within ``(1 - sqrt(1 - 2 h)) / omega <= 2 |d_0|`` of ``q_N``, and no other within
``(1 + sqrt(1 - 2 h)) / omega``.

- ``omega`` is estimated along the first step: ``J(q_N)^-1 G(q_N + t d_0) = (1 - t) d_0 + e_t`` with ``|e_t| =
  omega t^2 |d_0|^2 / 2`` for the equations' second derivatives along ``d_0``, so ``h = 2 |e_t| / (t^2 |d_0|)``,
  the largest over ``t`` in :data:`_ALONG` (the curvature changes along the step: near the wrist on axis 1 it was
  four times larger a quarter of the way than at the end).
- Measured along one line, ``omega`` is not a Lipschitz constant over the ball, so the condition asks ``h <= 1/4``
  (:data:`_CONTRACTION`), which meets Kantorovich's ``1/2`` for an ``omega`` twice the estimate, and a ball of radius
  ``2 |d_0|`` that does not reach the stretched elbow (where ``J`` is singular: the arm angle is undefined).
- The bound is ``2 |d_0|`` (Euclidean, in radians, so it bounds every joint) where both hold, and infinite
  elsewhere: near a singular wrist or shoulder, the stretched elbow or the wrist on axis 1 ``J(q_N)`` is nearly
  singular and the first step says nothing.
- It is an estimate, not a proof; the tests check it against the solutions Newton's steps find from ``q_N``.

Where both arms solve a branch at every arm angle and differ by at most ``d`` in every joint, the real feasible set
lies between the neighbour's exact sets [000 eqs. 20-30] for the limits tightened and loosened by ``d``
(:mod:`redkin.srs.nearly.feasible`, "How far the real set lies from the neighbour's"), and an end of joint ``i``'s
arc moves by about ``d / |dq_i/dpsi|`` (:func:`redkin.srs.nearly.self_motion_rates`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import check_pose
from redkin.circle import wrap_angle
from redkin.errors import RedkinError
from redkin.srs._targets import check_psi
from redkin.srs.branches import Branch, parse_branch
from redkin.srs.ik import reachable, solve
from redkin.srs.nearly import _kernels as _nearly_kernels
from redkin.srs.nearly.arm import NearlySRS

#: Where along Newton's first step ``omega`` is estimated: at ``q_N + t d_0`` for each ``t`` (module docstring).
_ALONG = (0.25, 0.5, 1.0)
#: The largest estimated ``h = omega |d_0|`` that gives a bound: half Kantorovich's 1/2, so that the condition
#: still holds for an ``omega`` twice the one estimated (module docstring).
_CONTRACTION = 0.25


class NeighbourDistance(NamedTuple):
    """How far the real arm's solution lies from the neighbour's at each arm angle (module docstring).

    Attributes
    ----------
    neighbour : numpy.ndarray, shape (M, 7)
        The neighbour's solution ``q_N`` on the branch (NaN where the neighbour does not reach the pose).
    first_step : numpy.ndarray, shape (M,)
        ``|d_0| = |J(q_N)^-1 G(q_N)|`` [rad]: the distance to first order in the offsets.
    contraction : numpy.ndarray, shape (M,)
        ``h = omega |d_0|``, ``omega`` estimated along the first step (infinite where ``J(q_N)`` is singular).
    bound : numpy.ndarray, shape (M,)
        ``2 |d_0|`` [rad] where ``h <=`` :data:`_CONTRACTION` and the ball of that radius does not reach the stretched
        elbow; infinite elsewhere.
    """

    neighbour: np.ndarray
    first_step: np.ndarray
    contraction: np.ndarray
    bound: np.ndarray


def neighbour_distance(arm: NearlySRS, pose: ArrayLike, psi: ArrayLike, branch: str | Branch) -> NeighbourDistance:
    """The bound on ``|q - q_N|`` at arm angles ``psi`` (M,) of a pose on one branch (module docstring).

    Parameters
    ----------
    arm : NearlySRS
        From :func:`redkin.srs.nearly.nearly_srs`.
    pose : array_like, shape (4, 4)
        The target pose of the real arm's tool.
    psi : array_like, shape (M,) or scalar
        Arm angles [rad].
    branch : str or Branch
        The branch, as :func:`redkin.srs.nearly.ik` names it.

    Raises
    ------
    ValueError
        For an arm that is not a :class:`redkin.srs.nearly.NearlySRS`, or a malformed pose, psi or branch.
    """
    if not isinstance(arm, NearlySRS):
        raise RedkinError(f"arm must be a NearlySRS (redkin.srs.nearly_srs), got {type(arm).__name__}")
    target = check_pose(pose)
    angles = np.atleast_1d(check_psi(psi)).astype(float).ravel()
    label = parse_branch(branch)
    count = len(angles)
    if count == 0 or not reachable(arm.geometry, target):
        nothing = np.full(count, np.inf)
        return NeighbourDistance(np.full((count, 7), np.nan), nothing, nothing.copy(), nothing.copy())
    start = np.ascontiguousarray(solve(arm.geometry, target, angles, arm.geometry.kernel_branch(label))[:, 0])
    targets = kernel_array(target, (count, 4, 4))  # writeable, as every caller's: one compile of the kernel
    residual, jacobian = _equations(arm, start, targets, angles)
    first = _solved(jacobian, residual)
    step = np.where(np.isfinite(first), first, 0.0)
    size = np.linalg.norm(first, axis=-1)
    contraction = np.zeros(count)
    for t in _ALONG:  # J(q_N)^-1 G(q_N + t d_0) = (1 - t) d_0 + omega t^2 |d_0|^2 / 2 for curvature omega
        along = _solved(jacobian, _equations(arm, start + t * step, targets, angles)[0]) - (1.0 - t) * step
        with np.errstate(divide="ignore", invalid="ignore"):
            estimate = np.where(size > 0.0, 2.0 * np.linalg.norm(along, axis=-1) / (t * t * size), 0.0)
        contraction = np.maximum(contraction, np.where(np.isfinite(estimate), estimate, np.inf))
    size = np.where(np.isfinite(size), size, np.inf)
    stretch = np.abs(wrap_angle(arm.geometry.theta_of_q(start)[:, 3] - arm.real_phase))
    bound = np.where((contraction <= _CONTRACTION) & (2.0 * size < stretch), 2.0 * size, np.inf)
    return NeighbourDistance(start, size, contraction, bound)


def _equations(arm: NearlySRS, q: np.ndarray, targets: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The residual (M, 7) and Jacobian (M, 7, 7) of the 7 equations at ``q`` (M, 7)
    (:func:`redkin.srs.nearly._kernels.equations`)."""
    count = len(q)
    residual, jacobian = np.empty((count, 7)), np.empty((count, 7, 7))
    run_batch(_nearly_kernels.equations, count, np.ascontiguousarray(q), targets, psi, arm.kernel_real,
              arm.kernel_model, residual, jacobian)
    return residual, jacobian


def _solved(jacobian: np.ndarray, residual: np.ndarray) -> np.ndarray:
    """``J^-1 r`` (M, 7) for each sample; infinite where ``J`` is singular or an entry is not finite."""
    out = np.full(residual.shape, np.inf)
    fine = np.all(np.isfinite(residual), axis=-1) & np.all(np.isfinite(jacobian), axis=(-2, -1))
    if np.any(fine):
        conditioned = np.linalg.cond(jacobian[fine]) < 1e12
        rows = np.flatnonzero(fine)[conditioned]
        out[rows] = np.linalg.solve(jacobian[rows], residual[rows][..., None])[..., 0]
    return out
