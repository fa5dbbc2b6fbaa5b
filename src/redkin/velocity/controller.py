"""Control-loop entry points: bind the robot once, then one cheap call per step (paper 003, 1 kHz use).

A user's servo loop calls ``step(q, twist)`` a thousand times a second with
the same robot.  The array API
(:func:`~redkin.velocity.proposed.lean_singularity_consistent`) validates
and broadcasts batches on every call; here the chain, the factorisation and
every parameter are checked once in the constructor, and each step

1. checks the shapes of ``q`` and ``twist``,
2. evaluates ``D_e`` (and ``D_i`` only where ``|D_e| < near_zero``), and
3. makes one call of a compiled control step,
   :func:`~redkin.velocity._step_kernels.sc_control` or
   :func:`~redkin.velocity._step_kernels.pinv_control`: it checks that
   ``q`` and ``twist`` are finite (bad input is still a ``ValueError``),
   builds the Jacobian from the chain's own tables (the kernel of
   :mod:`redkin._chain_kernels`) and calls the step of one configuration,
   :func:`~redkin.velocity._step_kernels.sc_one` or
   :func:`~redkin.velocity._step_kernels.least_squares_one` -- the same
   kernels the array API runs over batches, so both give the same numbers.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_nonnegative, check_positive
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.velocity import _step_kernels
from redkin.velocity.baselines import PINV_RCOND
from redkin.velocity.factorisation import Factorisation, singularity_factorisation
from redkin.velocity.proposed import NEAR_ZERO_FRACTION
from redkin.velocity.solution import VelocitySolution

_NO_FACTORS = np.zeros(7)  # D_i, not read by the step where |D_e| >= near_zero


def _read_vector(value: ArrayLike, length: int, name: str) -> np.ndarray:
    """``value`` as a new float array of shape ``(length,)``; ``ValueError`` naming ``name`` otherwise.

    Finiteness is checked by the compiled step (:func:`_finite_or_raise` turns its code into the error).
    """
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise RedkinError(f"{name} must be numeric, got {value!r}") from None
    if array.shape != (length,):
        raise RedkinError(f"{name} must have shape ({length},), got shape {array.shape}")
    return array


def _finite_or_raise(code: int, q: np.ndarray, twist: np.ndarray) -> None:
    """``ValueError`` for a control step's code other than ``DONE`` (:mod:`redkin.velocity._step_kernels`)."""
    if code == _step_kernels.Q_NOT_FINITE:
        raise RedkinError(f"q must be finite, got {q.tolist()}")
    if code == _step_kernels.TWIST_NOT_FINITE:
        raise RedkinError(f"twist must be finite, got {twist.tolist()}")
    if code == _step_kernels.NO_FACTORS:
        raise RedkinError("D_s = sum D_i^2 is zero: every factor D_i vanishes, the method is undefined here")


def _kernel_tables(chain: SerialChain) -> tuple[np.ndarray, np.ndarray, bool]:
    """The chain's link table, base and tool, and convention as :mod:`redkin._chain_kernels` takes them."""
    return chain._links, chain._ends, chain._standard


def _one_redundant_arm(chain: SerialChain) -> SerialChain:
    if not isinstance(chain, SerialChain):
        raise RedkinError(f"chain must be a SerialChain, got {type(chain).__name__}")
    if chain.n != 7:
        raise RedkinError(f"chain must have 7 joints (a 6 x 7 Jacobian), got {chain.n} ({chain.name!r})")
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
        self._tables = _kernel_tables(_one_redundant_arm(chain))

    def __call__(self, q: ArrayLike, twist: ArrayLike) -> VelocitySolution:
        """Joint velocity for joint angles ``q`` ``(7,)`` and twist ``(6,)`` (linear, angular)."""
        values, command = _read_vector(q, 7, "q"), _read_vector(twist, 6, "twist")
        qdot = np.empty(7)
        _finite_or_raise(_step_kernels.pinv_control(values, command, *self._tables, PINV_RCOND, np.empty((6, 7)), qdot),
                        values, command)
        return VelocitySolution(qdot, command)


class SingularityConsistentController:
    """The singularity-consistent step [003 eqs. 17-22] for one configuration per call.

    Same result as :class:`~redkin.velocity.methods.SingularityConsistent`
    bound to ``chain`` at ``q0`` (the same kernel), without the batch handling.

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
        ``b_ep`` of [003 eq. 22]; overrides the sign of ``D_e(q0)``.
    self_motion : float
        ``b_sm`` of [003 eq. 9] (costs the 7 column minors per step when non-zero).
    modify_rotation : bool
        Pre-multiply the rotational command by ``b_ep clip(D_e / eps, -1, 1)`` ([003 eq. 22] text).
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
        self._tables = _kernel_tables(chain)
        self.factorisation = singularity_factorisation(chain) if factorisation is None else factorisation
        if not isinstance(self.factorisation, Factorisation):
            raise RedkinError(f"factorisation must have index(q) and factors(q, jacobian) (a Factorisation), "
                              f"got {type(self.factorisation).__name__}")
        start = _read_vector(q0, 7, "q0")
        if not np.isfinite(start).all():
            raise RedkinError(f"q0 must be finite, got {start.tolist()}")
        self.eps = check_positive(eps, "eps")
        if direction is None:
            direction = -1.0 if float(self.factorisation.index(start)) < 0.0 else 1.0
        if direction not in (1, -1):
            raise RedkinError(f"direction must be +1 or -1, got {direction!r}")
        self.direction = float(direction)
        self.self_motion = float(self_motion)
        if not np.isfinite(self.self_motion):
            raise RedkinError(f"self_motion must be finite, got {self_motion!r}")
        self.modify_rotation = bool(modify_rotation)
        self.near_zero = (NEAR_ZERO_FRACTION * self.eps if near_zero is None
                          else check_nonnegative(near_zero, "near_zero"))

    def __call__(self, q: ArrayLike, twist: ArrayLike) -> VelocitySolution:
        """Joint velocity and realised twist for joint angles ``q`` ``(7,)`` and commanded twist ``(6,)``."""
        values, command = _read_vector(q, 7, "q"), _read_vector(twist, 6, "twist")
        d_e, factors = self._index_and_factors(values)
        qdot, target = np.empty(7), np.empty(6)
        code = _step_kernels.sc_control(values, command, *self._tables, d_e, factors, self.eps, self.direction,
                                       self.self_motion, self.modify_rotation, self.near_zero, np.empty((6, 7)),
                                       qdot, target)
        _finite_or_raise(code, values, command)
        return VelocitySolution(qdot, target)

    def solve(self, values: np.ndarray, jac: np.ndarray, command: np.ndarray) -> VelocitySolution:
        """The step for a caller that holds the Jacobian (the bound method of tracking); no input checks.

        ``values`` (7,), ``jac`` (6, 7) and ``command`` (6,): finite, C-contiguous float64 arrays.
        """
        d_e, factors = self._index_and_factors(values)
        qdot, target = np.empty(7), np.empty(6)
        if not _step_kernels.sc_one(jac, command, d_e, factors, self.eps, self.direction, self.self_motion,
                                   self.modify_rotation, self.near_zero, qdot, target):
            _finite_or_raise(_step_kernels.NO_FACTORS, values, command)
        return VelocitySolution(qdot, target)

    def _index_and_factors(self, values: np.ndarray) -> tuple[float, np.ndarray]:
        """``D_e`` at ``values``, and ``D_i`` where the exact path needs them (``|D_e| < near_zero``)."""
        d_e = float(self.factorisation.index(values))  # NaN for a q that is not finite: the kernel reports it
        if not abs(d_e) < self.near_zero:
            return d_e, _NO_FACTORS
        factors = np.ascontiguousarray(self.factorisation.factors(values, None),  # None: builds J if needed
                                       dtype=float)
        if not np.isfinite(factors).all():
            raise RedkinError("factors D_i must be finite, got NaN or infinity")
        return d_e, factors
