"""One interface for every velocity-IK method, as used by the tracking simulation and the CLI.

A method is *bound* to a chain and an initial configuration (the SC method
reads the side of the singularity it starts on) and then maps
``(q, J, twist)`` to a :class:`~redkin.velocity.solution.VelocitySolution`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from redkin._constants import VELOCITY_METHOD_NAMES as METHOD_NAMES  # the methods by name
from redkin._validation import check_positive
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.velocity.baselines import adaptive_damped_least_squares, damped_least_squares, pseudoinverse
from redkin.velocity.controller import SingularityConsistentController
from redkin.velocity.factorisation import Factorisation, singularity_factorisation
from redkin.velocity.proposed import lean_singularity_consistent, singularity_consistent
from redkin.velocity.solution import VelocitySolution

Step = Callable[[np.ndarray, np.ndarray, np.ndarray], VelocitySolution]


class Method(Protocol):
    """A velocity-IK method: ``bind(chain, q0)`` returns ``step(q, J, twist)``."""

    @property
    def label(self) -> str:
        """The method's name in tables and plots (read-only: the methods are frozen dataclasses)."""
        ...

    def bind(self, chain: SerialChain, q0: np.ndarray) -> Step: ...


@dataclass(frozen=True)
class Pseudoinverse:
    """``q_dot = J^+ v``; promises the commanded twist (unbounded near singularities)."""

    label: str = "pinv"

    def bind(self, chain: SerialChain, q0: np.ndarray) -> Step:
        return lambda q, jac, twist: VelocitySolution(pseudoinverse(jac, twist), twist)


@dataclass(frozen=True)
class DampedLeastSquares:
    """Constant damping ``lambda``; promises the commanded twist, realises it only approximately."""

    damping: float = 0.05
    label: str = "dls"

    def __post_init__(self) -> None:
        check_positive(self.damping, "damping")

    def bind(self, chain: SerialChain, q0: np.ndarray) -> Step:
        return lambda q, jac, twist: VelocitySolution(damped_least_squares(jac, twist, self.damping), twist)


@dataclass(frozen=True)
class AdaptiveDampedLeastSquares:
    """Damping growing to ``max_damping`` as the smallest singular value (or manipulability) falls below
    ``threshold``."""

    threshold: float = 0.05
    max_damping: float = 0.05
    measure: str = "sigma"
    label: str = "dls-adaptive"

    def __post_init__(self) -> None:
        check_positive(self.threshold, "threshold")
        check_positive(self.max_damping, "max_damping")
        if self.measure not in ("sigma", "manipulability"):
            raise RedkinError(f"measure must be 'sigma' or 'manipulability', got {self.measure!r}")

    def bind(self, chain: SerialChain, q0: np.ndarray) -> Step:
        return lambda q, jac, twist: VelocitySolution(
            adaptive_damped_least_squares(jac, twist, self.threshold, self.max_damping, self.measure), twist
        )


@dataclass(frozen=True)
class SingularityConsistent:
    """The proposed method (paper 003 section 3) with singular-region threshold ``eps`` on ``|D_e|``.

    ``factorisation`` defaults to :func:`~redkin.velocity.factorisation.singularity_factorisation`
    (the closed form of a WAM-shaped chain, ``sin(theta_4)`` for an S-R-S arm);
    ``direction`` (``b_ep`` of [003 eq. 22]) defaults to the sign of ``D_e(q0)``,
    so the command is realised as given at the start.  ``lean`` (default)
    steps with the kernel of :func:`~redkin.velocity.proposed.lean_singularity_consistent`
    (one pseudoinverse, same result to ~1e-12; for one configuration through
    :meth:`~redkin.velocity.controller.SingularityConsistentController.solve`),
    which takes the exact adjugate path only where ``|D_e| < eps / 100``;
    otherwise with :func:`~redkin.velocity.proposed.singularity_consistent`.
    The bound step takes one configuration or a batch (``q`` (..., 7),
    ``jac`` (..., 6, 7)).
    """

    eps: float
    factorisation: Factorisation | None = None
    direction: float | None = None
    self_motion: float = 0.0
    modify_rotation: bool = True
    lean: bool = True
    label: str = "sc"

    def __post_init__(self) -> None:
        check_positive(self.eps, "eps")

    def resolve(self, chain: SerialChain) -> Factorisation:
        """The factorisation in use for ``chain``."""
        return self.factorisation if self.factorisation is not None else singularity_factorisation(chain)

    def bind(self, chain: SerialChain, q0: np.ndarray) -> Step:
        factorisation = self.resolve(chain)
        direction = self.direction
        if direction is None:
            start = float(factorisation.index(q0))
            direction = -1.0 if start < 0.0 else 1.0
        if self.lean:
            controller = SingularityConsistentController(
                chain, q0, self.eps, factorisation, direction, self.self_motion, self.modify_rotation
            )

            def lean_step(q: np.ndarray, jac: np.ndarray, twist: np.ndarray) -> VelocitySolution:
                if np.ndim(q) == 1:  # one configuration (tracking): the controller's step, without the batch handling
                    return controller.solve(*(np.ascontiguousarray(a, dtype=float) for a in (q, jac, twist)))
                return lean_singularity_consistent(
                    jac, twist, factorisation.index(q), lambda: factorisation.factors(q, jac), self.eps,
                    direction, self.self_motion, self.modify_rotation,
                )

            return lean_step

        def step(q: np.ndarray, jac: np.ndarray, twist: np.ndarray) -> VelocitySolution:
            return singularity_consistent(
                jac, twist, factorisation.index(q), factorisation.factors(q, jac), self.eps,
                direction=direction, self_motion=self.self_motion, modify_rotation=self.modify_rotation,
            )

        return step


def make_method(name: str, eps: float = 0.1, damping: float = 0.05) -> Method:
    """A method by CLI name: ``sc`` (threshold ``eps``), ``pinv``, ``dls`` / ``dls-adaptive`` (damping ``damping``).

    ``dls-adaptive`` uses the least singular value with threshold ``eps`` and
    maximum damping ``damping``.
    """
    if name == "sc":
        return SingularityConsistent(eps=eps)
    if name == "pinv":
        return Pseudoinverse()
    if name == "dls":
        return DampedLeastSquares(damping=damping)
    if name == "dls-adaptive":
        return AdaptiveDampedLeastSquares(threshold=eps, max_damping=damping)
    raise RedkinError(f"method must be one of {', '.join(METHOD_NAMES)}, got {name!r}")
