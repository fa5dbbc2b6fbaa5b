"""Singularities that factor through one parameter: ``det J_i = D_e D_i`` ([003 eqs. 19-20], section 3.3).

The proposed method needs a *singularity index* ``D_e(q)`` common to every
column minor ``det J_i`` of the 6 x 7 Jacobian, and the remaining factors
``D_i = det J_i / D_e``.  This module gives

* :class:`WamFactorisation` -- the Barrett WAM (paper 003 Table 1, standard DH):
  ``D_e = a (d3 + d5) C4 + (a^2 - d3 d5) S4`` and every ``D_i`` in closed form,
* :class:`NumericalFactorisation` -- any arm with a known index function:
  ``D_i = det J_i / D_e``, and at (or very near) ``D_e = 0`` the limit of that
  ratio by l'Hopital along the gradient of ``D_e``,
* :func:`check_single_parameter` -- a numerical test of whether an index
  really factors every ``det J_i`` (S-R-S arms with ``sin q4``: yes; the WAM
  with its ``D_e``: yes; the WAM with ``sin q4``: no).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from math import cos, sin
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel
from redkin.chain import SerialChain
from redkin.circle import HALF_PI
from redkin.velocity.cofactors import column_minors

_WAM_ALPHA = np.array([-HALF_PI, HALF_PI, -HALF_PI, HALF_PI, -HALF_PI, HALF_PI, 0.0])


def wam_singularity_index(q: ArrayLike, a: float, d3: float, d5: float) -> np.ndarray:
    """``D_e = a (d3 + d5) cos q4 + (a^2 - d3 d5) sin q4`` (paper 003 section 3.3), shape ``(...)``.

    Zero exactly at the elbow-stretch singularity (the workspace boundary).
    """
    return _wam(q, a, d3, d5)[0]


def wam_cofactors(q: ArrayLike, a: float, d3: float, d5: float) -> np.ndarray:
    """Closed-form ``D_i`` with ``det J_i = D_e D_i`` for the Barrett WAM [003 eq. 19], shape ``(..., 7)``.

    Derived with sympy (development aid, not a dependency) from the geometric
    Jacobian of paper 003 Table 1: every minor contains ``D_e`` as a factor.
    ``det J_i`` does not depend on the reference point, the base frame, ``d7``,
    ``q1`` or ``q7``.  ``D_4 = 0``: with the elbow joint fixed the remaining
    six joints are always singular (shoulder and wrist both spherical).
    """
    return _wam(q, a, d3, d5)[1]


def _wam(q: ArrayLike, a: float, d3: float, d5: float) -> tuple[np.ndarray, np.ndarray]:
    """``D_e`` (...) and ``D_i`` (..., 7) from the kernel :func:`_wam_index_and_factors`."""
    values = np.asarray(q, dtype=float)
    flat = np.ascontiguousarray(values.reshape(-1, values.shape[-1]))
    index, factors = np.empty(flat.shape[0]), np.empty((flat.shape[0], 7))
    _wam_index_and_factors(flat, float(a), float(d3), float(d5), index, factors)
    return index.reshape(values.shape[:-1]), factors.reshape(values.shape[:-1] + (7,))


@kernel
def _wam_index_and_factors(q, a, d3, d5, index, factors):
    """``D_e`` into ``index`` (N,) and ``D_i`` into ``factors`` (N, 7) for each row of ``q`` (N, 7) [003 eq. 19]."""
    for b in range(q.shape[0]):
        s2, s3, s4, s5, s6 = sin(q[b, 1]), sin(q[b, 2]), sin(q[b, 3]), sin(q[b, 4]), sin(q[b, 5])
        c2, c3, c4, c5, c6 = cos(q[b, 1]), cos(q[b, 2]), cos(q[b, 3]), cos(q[b, 4]), cos(q[b, 5])
        index[b] = a * (d3 + d5) * c4 + (a * a - d3 * d5) * s4
        shoulder = a * (c4 - 1.0) - d5 * s4
        wrist = a * (c4 - 1.0) - d3 * s4
        factors[b, 0] = shoulder * s6 * c3
        factors[b, 1] = shoulder * s2 * s3 * s6
        factors[b, 2] = (a * s2 * s4 - a * c2 * c3 * c4 + a * c2 * c3 + d3 * s2 + d5 * s2 * c4 + d5 * s4 * c2 * c3) * s6
        factors[b, 3] = 0.0
        factors[b, 4] = (-a * s4 * s6 + a * c4 * c5 * c6 - a * c5 * c6 - d3 * s4 * c5 * c6 - d3 * s6 * c4
                         - d5 * s6) * s2
        factors[b, 5] = -wrist * s2 * s5 * s6
        factors[b, 6] = -wrist * s2 * c5


@runtime_checkable
class Factorisation(Protocol):
    """A singularity factorisation (the plug-in of the SC method, a ``Protocol`` like
    :class:`redkin.velocity.methods.Method`): ``index(q)`` -> ``D_e`` ``(...)``;
    ``factors(q, jacobian)`` -> ``D_i`` ``(..., n)``.

    ``jacobian`` is the Jacobian at ``q`` where the caller holds it, or
    ``None`` (the control loop's exact path): then a factorisation that needs
    it builds it.
    """

    def index(self, q: np.ndarray) -> np.ndarray: ...

    def factors(self, q: np.ndarray, jacobian: np.ndarray | None) -> np.ndarray: ...


@dataclass(frozen=True)
class WamFactorisation(Factorisation):
    """Closed-form ``D_e`` and ``D_i`` of a Barrett-WAM-shaped chain (paper 003 Table 1)."""

    a: float
    d3: float
    d5: float

    @classmethod
    def from_chain(cls, chain: SerialChain) -> WamFactorisation:
        """Read ``a, d3, d5`` from a chain with the WAM's DH pattern; ``ValueError`` otherwise."""
        a = chain.a
        pattern_ok = (
            chain.n == 7
            and chain.convention == "dh"
            and np.allclose(chain.alpha, _WAM_ALPHA)
            and np.allclose(a[[0, 1, 4, 5, 6]], 0.0)
            and np.isclose(a[3], -a[2])
            and np.allclose(chain.d[[0, 1, 3, 5]], 0.0)
            and np.allclose(chain.offset, 0.0)
            and np.allclose(chain.sign, 1.0)
        )
        if not pattern_ok:
            raise ValueError(
                f"chain {chain.name!r} does not have the Barrett WAM DH pattern of paper 003 Table 1 "
                "(7 standard-DH rows, alpha = -+-+-+0 quarter turns, a = (0,0,a,-a,0,0,0), d = (0,0,d3,0,d5,0,d7)); "
                "use NumericalFactorisation with your own index"
            )
        return cls(a=float(a[2]), d3=float(chain.d[2]), d5=float(chain.d[4]))

    def index(self, q: np.ndarray) -> np.ndarray:
        return wam_singularity_index(q, self.a, self.d3, self.d5)

    def factors(self, q: np.ndarray, jacobian: np.ndarray | None = None) -> np.ndarray:
        return wam_cofactors(q, self.a, self.d3, self.d5)


@dataclass(frozen=True)
class NumericalFactorisation(Factorisation):
    """``D_i = det J_i / D_e`` for any chain with a user-given index ``D_e(q)`` [003 eq. 19].

    Where ``|D_e| < near_zero`` the ratio is 0/0; there ``D_i`` is taken as
    the l'Hopital limit along the unit gradient ``u`` of ``D_e``:
    ``(det J_i(q + h u) - det J_i(q - h u)) / (D_e(q + h u) - D_e(q - h u))``.
    Valid only if the index really factors the minors
    (see :func:`check_single_parameter`).
    """

    chain: SerialChain
    index_function: Callable[[np.ndarray], np.ndarray]
    near_zero: float = 1e-6
    step: float = 1e-5

    def index(self, q: np.ndarray) -> np.ndarray:
        return np.asarray(self.index_function(q), dtype=float)

    def factors(self, q: np.ndarray, jacobian: np.ndarray | None = None) -> np.ndarray:
        q = self.chain.check_q(q)
        jac = self.chain.jacobian(q) if jacobian is None else jacobian
        index = self.index(q)
        minors = column_minors(jac)
        small = np.abs(index) < self.near_zero
        ratio = minors / np.where(small, 1.0, index)[..., None]
        if np.any(small):
            u = _index_gradient(self.index_function, q, self.step)
            u = u / np.maximum(np.linalg.norm(u, axis=-1, keepdims=True), 1e-300)
            plus, minus = q + self.step * u, q - self.step * u
            d_minor = column_minors(self.chain.jacobian(plus)) - column_minors(self.chain.jacobian(minus))
            d_index = self.index(plus) - self.index(minus)
            limit = d_minor / d_index[..., None]
            ratio = np.where(small[..., None], limit, ratio)
        return ratio


@dataclass(frozen=True)
class ElbowSine:
    """``D_e = sin(theta_4)``, the elbow index of an S-R-S arm (``theta_4 = offset + sign * q_4``; paper 003
    section 3.3).

    Zero where the elbow is stretched or folded: there the shoulder and wrist
    centres and the elbow axis are coplanar and every column minor vanishes.
    """

    offset: float
    sign: float

    def __call__(self, q: np.ndarray) -> np.ndarray:
        return np.sin(self.offset + self.sign * np.asarray(q, dtype=float)[..., 3])


def singularity_factorisation(chain: SerialChain, seed: int | np.random.Generator = 0) -> Factorisation:
    """The factorisation ``det J_i = D_e D_i`` of a 7-joint chain, found automatically (paper 003 section 3.3).

    A chain with the Barrett WAM's DH pattern gets the closed form
    (:class:`WamFactorisation`); otherwise the S-R-S index ``sin(theta_4)``
    is tried with :func:`check_single_parameter` and, if it factors every
    minor, used through :class:`NumericalFactorisation`.

    Raises
    ------
    ValueError
        If the chain does not have 7 joints, or if neither index factors its
        minors (its singularities do not go through one parameter, e.g. an
        offset elbow or wrist, as on the European Robotic Arm).
    """
    if chain.n != 7:
        raise ValueError(f"chain must have 7 joints (a 6 x 7 Jacobian), got {chain.n} ({chain.name!r})")
    try:
        return WamFactorisation.from_chain(chain)
    except ValueError:
        pass
    elbow = ElbowSine(float(chain.offset[3]), float(chain.sign[3]))
    if check_single_parameter(chain, elbow, seed=seed).factors:
        return NumericalFactorisation(chain, elbow)
    raise ValueError(
        f"chain {chain.name!r}: its singularities do not factor through one parameter "
        "(neither the Barrett WAM closed form nor sin(theta_4) divides every column minor det J_i), "
        "so the singularity-consistent method has no index D_e for it"
    )


def _index_gradient(
    index_function: Callable[[np.ndarray], np.ndarray], q: np.ndarray, step: float = 1e-6
) -> np.ndarray:
    """Central-difference gradient of an index function, shape ``(..., n)``."""
    q = np.asarray(q, dtype=float)
    n = q.shape[-1]
    grad = np.empty(q.shape)
    for k in range(n):
        e = np.zeros(n)
        e[k] = step
        grad[..., k] = (np.asarray(index_function(q + e)) - np.asarray(index_function(q - e))) / (2.0 * step)
    return grad


@dataclass(frozen=True)
class FactorCheck:
    """Outcome of :func:`check_single_parameter`.

    ``factors`` is true when, on every sampled point of ``D_e = 0``, the
    Jacobian is rank deficient (all minors vanish) and every ratio
    ``det J_i / D_e`` has the same limit from both sides (``worst_ratio_jump``
    is the largest difference between the two sides relative to the largest ratio).
    """

    factors: bool
    samples: int
    worst_minor_on_set: float
    worst_ratio_jump: float


def check_single_parameter(
    chain: SerialChain,
    index_function: Callable[[np.ndarray], np.ndarray],
    samples: int = 32,
    seed: int | np.random.Generator = 0,
    tolerance: float = 1e-5,
) -> FactorCheck:
    """Test numerically whether ``D_e`` factors every column minor: ``det J_i = D_e D_i`` (paper 003 section 3.3).

    Random configurations are moved onto ``D_e = 0`` by Newton steps along
    the gradient.  There, the minors must vanish (relative to their size at
    the start) and ``det J_i / D_e`` evaluated at ``+-h`` along the gradient
    must agree (a simple common zero, no other factor changing sign) and
    stay bounded (no higher-order zero of ``D_e``).
    """
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (samples, chain.n))
    scale = np.max(np.abs(column_minors(chain.jacobian(q))), axis=-1)
    for _ in range(50):
        value = np.asarray(index_function(q), dtype=float)
        grad = _index_gradient(index_function, q)
        norm2 = np.maximum(np.sum(grad * grad, axis=-1), 1e-300)
        q = q - (value / norm2)[..., None] * grad
    value = np.asarray(index_function(q), dtype=float)
    on_set = np.abs(value) < 1e-10
    grad = _index_gradient(index_function, q)
    unit = grad / np.maximum(np.linalg.norm(grad, axis=-1, keepdims=True), 1e-300)
    h = 1e-4
    worst_minor = float(np.max(np.abs(column_minors(chain.jacobian(q))).max(axis=-1) / scale))
    def ratios_at(distance: float) -> np.ndarray:
        qh = q + distance * unit
        return column_minors(chain.jacobian(qh)) / np.asarray(index_function(qh))[..., None]

    near_plus, near_minus, far = ratios_at(h), ratios_at(-h), ratios_at(10.0 * h)
    # A common simple zero leaves det J_i / D_e continuous (jump O(h)) and
    # bounded; a minor that vanishes without the factor makes the ratio flip
    # sign (jump ~ its size), an index vanishing to higher order makes it blow up.
    size = max(float(np.max(np.abs(near_plus))), float(np.max(np.abs(near_minus))), 1e-300)
    worst_jump = float(np.max(np.abs(near_plus - near_minus)) / size)
    growth = size / max(float(np.max(np.abs(far))), 1e-300)
    factors = bool(np.all(on_set) and worst_minor < tolerance and worst_jump < 100.0 * h and growth < 2.0)
    return FactorCheck(factors=factors, samples=samples, worst_minor_on_set=worst_minor, worst_ratio_jump=worst_jump)
