"""Control-loop entry points: bind the robot once, then one cheap call per step (paper 003, 1 kHz use).

A user's servo loop calls ``step(q, twist)`` a thousand times a second with
the same robot.  The array API (:func:`~redkin.velocity.lean_step.lean_singularity_consistent`)
validates and broadcasts on every call and pays numpy's per-call overhead on
tiny arrays; here the chain, the factorisation and every parameter are
checked once in the constructor, and each step

1. checks ``q`` and ``twist`` (shape and finite: still a ``ValueError`` on bad input),
2. builds the Jacobian with ``chain.jacobian`` (the compiled kernel of :mod:`redkin.chain_kernels`),
3. evaluates ``D_e`` in scalar arithmetic (``Factorisation.scalar_index``),
4. scales the twist with the scalar forms of the blend (:mod:`redkin.velocity.blend`), and
5. solves the minimum-norm problem ``J q_dot = target`` with one LAPACK
   ``dgelss`` call (SVD-based, so as accurate as the SVD path).

The SC step is the lean step of :mod:`redkin.velocity.lean_step`,
``q_dot = b_ep g(D_e) J^+ t'`` (eqs. 17-22 combined).  Where ``|D_e| <
near_zero`` it takes the exact route of
:func:`~redkin.velocity.proposed.singularity_consistent` (eqs. 15, 21, 22),
with ``sum_i D_i n_i`` from one 7 x 7 adjugate
(:func:`~redkin.velocity.proposed.adjugate_factor_sum`) instead of the 49
determinants of the Cramer construction.
"""

from __future__ import annotations

from math import isfinite

import numpy as np
from numpy.typing import ArrayLike
from scipy.linalg import lapack

from redkin.chain import SerialChain
from redkin.validation import check_positive
from redkin.velocity._inputs import nonnegative
from redkin.velocity.baselines import PINV_RCOND
from redkin.velocity.blend import scalar_rotation_factor, scalar_twist_scale
from redkin.velocity.cofactors import self_motion_vector
from redkin.velocity.factorisation import Factorisation, singularity_factorisation
from redkin.velocity.lean_step import NEAR_ZERO_FRACTION
from redkin.velocity.proposed import adjugate_factor_sum, blended_step
from redkin.velocity.solution import VelocitySolution

_WORKSPACE = int(lapack.dgelss_lwork(6, 7, 1)[0])


def minimum_norm_solution(jacobian: np.ndarray, target: list[float], rcond: float) -> np.ndarray:
    """``J^+ target`` for one trusted ``6 x 7`` Jacobian: LAPACK ``dgelss`` (SVD, minimum norm).

    Singular values ``<= rcond * sigma_max`` count as zero (``rcond < 0``:
    machine precision), as in :func:`~redkin.velocity.baselines.pseudoinverse`.
    """
    _, solution, _, _, _, info = lapack.dgelss(jacobian, np.array(target + [0.0]), cond=rcond, lwork=_WORKSPACE)
    if info != 0:
        raise np.linalg.LinAlgError(f"SVD did not converge (LAPACK dgelss info = {info})")
    return solution


def read_vector(value: ArrayLike, length: int, name: str) -> list[float]:
    """``value`` as ``length`` finite floats; ``ValueError`` naming ``name`` otherwise (one cheap check per step)."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric, got {value!r}") from None
    if array.shape != (length,):
        raise ValueError(f"{name} must have shape ({length},), got shape {array.shape}")
    values = array.tolist()
    if not all(map(isfinite, values)):
        raise ValueError(f"{name} must be finite, got {values}")
    return values


def _one_redundant_arm(chain: SerialChain) -> SerialChain:
    if not isinstance(chain, SerialChain):
        raise ValueError(f"chain must be a SerialChain, got {type(chain).__name__}")
    if chain.n != 7:
        raise ValueError(f"chain must have 7 joints (a 6 x 7 Jacobian), got {chain.n} ({chain.name!r})")
    return chain


class PseudoinverseController:
    """``q_dot = J^+ v`` for one configuration per call (the baseline, same entry point as the SC controller).

    Equals :func:`~redkin.velocity.baselines.pseudoinverse` (singular values
    below ``PINV_RCOND * sigma_max`` dropped).

    Examples
    --------
    >>> from redkin.models import barrett_wam
    >>> step = PseudoinverseController(barrett_wam())
    >>> step([0.5, 0.3, 0.2, 1.2, 0.4, 0.9, 0.0], [0.1, 0, 0, 0, 0, 0]).joint_velocity.shape
    (7,)
    """

    def __init__(self, chain: SerialChain) -> None:
        self._chain = _one_redundant_arm(chain)

    def __call__(self, q: ArrayLike, twist: ArrayLike) -> VelocitySolution:
        """Joint velocity for joint angles ``q`` ``(7,)`` and twist ``(6,)`` (linear, angular)."""
        values = read_vector(q, 7, "q")
        command = read_vector(twist, 6, "twist")
        qdot = minimum_norm_solution(self._chain.jacobian(values), command, PINV_RCOND)
        return VelocitySolution(qdot, np.array(command))


class SingularityConsistentController:
    """The singularity-consistent step (paper 003 eqs. 17-22) for one configuration per call.

    Same result as :class:`~redkin.velocity.methods.SingularityConsistent`
    bound to ``chain`` at ``q0`` (to ~1e-12), in about a fifth of the time.

    Parameters
    ----------
    chain : SerialChain
        A 7-joint arm.
    q0 : array_like, shape (7,)
        Start configuration: ``b_ep`` (``direction``) defaults to the sign of ``D_e(q0)``.
    eps : float
        Singular-region threshold ``D_eps`` on ``|D_e|`` (> 0).
    factorisation : Factorisation, optional
        ``D_e`` and ``D_i``; default
        :func:`~redkin.velocity.factorisation.singularity_factorisation` (WAM
        closed form, or ``sin(theta_4)`` for S-R-S arms; ``ValueError`` for
        arms whose singularities do not factor through one parameter).
    direction : {+1, -1}, optional
        ``b_ep`` of eq. 22; overrides the sign of ``D_e(q0)``.
    self_motion : float
        ``b_sm`` of eq. 9 (costs the 7 column minors per step when non-zero).
    modify_rotation : bool
        Pre-multiply the rotational command by ``b_ep clip(D_e / eps, -1, 1)`` (eq. 22 text).
    near_zero : float, optional
        ``|D_e|`` below which the exact cofactor path is used; default ``eps / 100``.

    Examples
    --------
    >>> import numpy as np
    >>> from redkin.models import barrett_wam
    >>> q0 = np.radians([30, 20, 50, 70, 40, 100, 0])
    >>> step = SingularityConsistentController(barrett_wam(), q0, eps=0.1)
    >>> step(q0, [0.15, 0, 0, 0, 0.1, 0]).target_twist   # outside the region: the command
    array([0.15, 0.  , 0.  , 0.  , 0.1 , 0.  ])
    """

    def __init__(
        self,
        chain: SerialChain,
        q0: ArrayLike,
        eps: float = 0.1,
        factorisation: Factorisation | None = None,
        direction: float | None = None,
        self_motion: float = 0.0,
        modify_rotation: bool = True,
        near_zero: float | None = None,
    ) -> None:
        self._chain = _one_redundant_arm(chain)
        self.factorisation = singularity_factorisation(chain) if factorisation is None else factorisation
        if not isinstance(self.factorisation, Factorisation):
            raise ValueError(f"factorisation must be a Factorisation, got {type(self.factorisation).__name__}")
        start = read_vector(q0, 7, "q0")
        self.eps = check_positive(eps, "eps")
        if direction is None:
            direction = -1.0 if self.factorisation.scalar_index(start) < 0.0 else 1.0
        if direction not in (1, -1):
            raise ValueError(f"direction must be +1 or -1, got {direction!r}")
        self.direction = float(direction)
        self.self_motion = float(self_motion)
        if not isfinite(self.self_motion):
            raise ValueError(f"self_motion must be finite, got {self_motion!r}")
        self.modify_rotation = bool(modify_rotation)
        self.near_zero = NEAR_ZERO_FRACTION * self.eps if near_zero is None else nonnegative(near_zero, "near_zero")

    def __call__(self, q: ArrayLike, twist: ArrayLike) -> VelocitySolution:
        """Joint velocity and realised twist for joint angles ``q`` ``(7,)`` and commanded twist ``(6,)``."""
        values = read_vector(q, 7, "q")
        return self.solve(values, self._chain.jacobian(values), read_vector(twist, 6, "twist"))

    def solve(self, values: list[float], jac: np.ndarray, command: list[float]) -> VelocitySolution:
        """The step for trusted inputs: 7 finite joint values, their ``6 x 7`` Jacobian, 6 finite twist values.

        For callers that already hold the Jacobian (e.g. the tracking simulation); no input checks.
        """
        d_e = self.factorisation.scalar_index(values)
        if abs(d_e) < self.near_zero:  # eqs. 15, 21 with sum_i D_i n_i from one adjugate: exact on D_e = 0
            factors = np.asarray(self.factorisation.factors(np.array(values), jac), dtype=float)
            if not np.all(np.isfinite(factors)):
                raise ValueError("factors D_i must be finite, got NaN or infinity")
            return blended_step(jac, np.array(command), np.float64(d_e), factors, self.eps, self.direction,
                                self.self_motion, self.modify_rotation, adjugate_factor_sum)
        linear = self.direction * scalar_twist_scale(d_e, self.eps)  # b_ep g(D_e), eq. 22
        angular = linear * self.direction * scalar_rotation_factor(d_e, self.eps) if self.modify_rotation else linear
        vx, vy, vz, wx, wy, wz = command
        target = [linear * vx, linear * vy, linear * vz, angular * wx, angular * wy, angular * wz]
        qdot = minimum_norm_solution(jac, target, -1.0)  # J^+ (b_ep g t'), eqs. 18, 21
        if self.self_motion:
            qdot = qdot + self.self_motion * self_motion_vector(jac)
        return VelocitySolution(qdot, np.array(target))
