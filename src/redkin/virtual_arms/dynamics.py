"""The trajectory-generation dynamics of paper 004 (section 3.2, [004 eqs. 9-14]).

All subsystems integrate the same equations from the same initial values and
exchange the same signals, so their copies ``u^i``, ``theta^i`` and
``lambda^i`` stay equal (the paper uses this in deriving [004 eq. 16]); we
integrate one copy.  With ``delta = sum_k delta^k`` and
``g = lambda delta + (theta(0) - theta)``:

* [004 eq. 9]:  ``du/ds = eta A G' g``
* [004 eq. 10]: ``A = (1/2 |lambda delta|^2 + c_A |delta| |theta(0) - theta|) / |G' g|^2``
* [004 eq. 11]: ``dlambda/ds = eta c_lambda |delta| |theta(0) - theta| / sum_k E^k``
* [004 eq. 13]: ``theta = G(u)``
* [004 eq. 14]: ``V = lambda sum_k E^k + 1/2 |theta(0) - theta|^2``

Checked problems of the printed equations (our derivation; tests confirm):

1. The paper prints ``c_A = 1/2`` in [004 eq. 10] and ``c_lambda = 1`` in [004 eq. 11].
   Then ``dV/ds = -eta/2 lambda^2 |delta|^2 + eta (c_lambda - c_A) |delta|
   |theta(0) - theta|``: [004 eq. 16] (``dV/ds = -eta/2 lambda^2 |delta|^2``) holds
   only when ``c_A = c_lambda``.
2. As ``lambda`` grows, ``theta`` approaches the point where ``g = 0`` (the
   minimiser of ``V`` at fixed ``lambda``), where the numerator of [004 eq. 10] stays
   positive while its denominator vanishes: ``A`` diverges, ``|du/ds|`` grows
   like ``1 / |G' g|`` and the state chatters across ``g = 0``; every
   integrator's step size collapses there.

The laws below: ``"literal"`` ([004 eqs. 10-11] as printed, unbounded; kept to
show the stall), ``"consistent"`` (``c_A = c_lambda = 1/2``, unbounded: [004 eq. 16]
holds exactly, but it still stalls), and ``"bounded"`` (the default:
consistent constants and the smooth bound ``A = N / (|G' g|^2 + N / A_max)``
with ``A_max = 10``: within 10 % of [004 eq. 10] where ``|G' g|^2 >= N``, and at
most ``A_max`` near ``g = 0``).  A smaller bound makes the equations less
stiff: on the Fig. 6 cases ``A_max = 10`` takes about half the integrator work
of ``A_max = 1000`` and never stalled in our runs, while the end posture is
the same (it is set by the growth of ``lambda``, not by ``A``).  With the
bound, ``theta`` follows the minimiser of ``V`` as ``lambda`` grows
exponentially (the penalty-method path), which converges to the joint vector
closest to ``theta(0)`` among those minimising ``sum_k E^k``.

Joints clamped by [004 eq. 27] (``du_j/ds = 0``) are not integrated at all, so they
stay exactly fixed; ``delta`` and ``G' g`` above are taken over the free
joints only, which keeps the [004 eq. 16] identity for the joints that move.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin.virtual_arms import _kernels as kernels
from redkin.virtual_arms.output_function import OutputFunction


@dataclass(frozen=True)
class GainLaw:
    """Constants of [004 eqs. 10, 11] and the optional bound on ``A``.

    Attributes
    ----------
    name : str
    gain_constant : float
        ``c_A`` in the numerator of [004 eq. 10].
    lambda_constant : float
        ``c_lambda`` in [004 eq. 11].
    a_max : float or None
        Bound on ``A`` (``None``: unbounded, as printed).
    """

    name: str
    gain_constant: float
    lambda_constant: float
    a_max: float | None


GAIN_LAWS = {
    "bounded": GainLaw("bounded", 0.5, 0.5, 10.0),
    "consistent": GainLaw("consistent", 0.5, 0.5, None),
    "literal": GainLaw("literal", 0.5, 1.0, None),
}


@dataclass(frozen=True)
class State:
    """Everything the dynamics computes at states ``y`` of shape ``(..., free + 1)``."""

    u: np.ndarray  # (..., m)
    theta: np.ndarray  # (..., m)
    lam: np.ndarray  # (...)
    delta: np.ndarray  # per subsystem, (..., p, m)
    error: np.ndarray  # per subsystem, (..., p)
    positions: np.ndarray  # (..., p, l)
    gain: np.ndarray  # A, (...)
    du: np.ndarray  # du/ds on the free joints, (..., free)
    dlam: np.ndarray  # dlambda/ds, (...)
    energy: np.ndarray  # V, [004 eq. 14], (...)
    free_gradient: np.ndarray  # |G' delta| over the free joints (stopping measure), (...)


class Dynamics:
    """Right-hand side of [004 eqs. 9-13] for the free input states and ``log lambda``.

    The integrated vector is ``y = [u_free, log lambda]``: ``lambda`` grows
    exponentially along the run, and its logarithm keeps the integrator's
    error control well scaled (``d log lambda / ds = (dlambda/ds) / lambda``;
    the path is the same).  Everything is batched over leading axes of ``y``,
    so the integrator's finite-difference Jacobian costs one model call.
    The equations are the compiled kernels :func:`~redkin.virtual_arms._kernels.inputs`
    and :func:`~redkin.virtual_arms._kernels.rates`, around one call of the
    evaluator's forward model.
    """

    def __init__(self, evaluator, goals: np.ndarray, weights: np.ndarray, active: np.ndarray,
                 theta0: np.ndarray, output: OutputFunction, free: np.ndarray, eta: float, law: GainLaw):
        self.evaluator = evaluator
        self.goals = np.ascontiguousarray(goals, dtype=float)
        self.weights = np.ascontiguousarray(weights, dtype=float)
        self.active = active
        self.theta0 = np.ascontiguousarray(theta0, dtype=float)
        self.output = output
        self.free = np.ascontiguousarray(free, dtype=bool)
        self.eta = eta
        self.law = law
        self.u0 = output.state(theta0)
        limited = np.asarray(output.limited, dtype=bool)
        self._limits = (np.where(limited, (output.upper - output.lower) / 2.0, 1.0),
                        np.where(limited, output.lower, 0.0), np.ascontiguousarray(limited))

    def initial(self, lambda0: float) -> np.ndarray:
        """``y(0) = [G^{-1}(theta(0)) on the free joints, log lambda(0)]``."""
        return np.append(self.u0[self.free], np.log(lambda0))

    def state(self, y: np.ndarray) -> State:
        """Evaluate the subsystems and [004 eqs. 9-14] at ``y`` (shape ``(..., free + 1)``)."""
        lead = y.shape[:-1]
        flat = np.ascontiguousarray(y, dtype=float).reshape(-1, y.shape[-1])
        count, m, (p, dims) = flat.shape[0], self.theta0.shape[0], self.goals.shape
        u, theta, slope = np.empty((count, m)), np.empty((count, m)), np.empty((count, m))
        kernels.inputs(flat, self.u0, self.free, *self._limits, self.theta0, u, theta, slope)
        positions, jacobians = self.evaluator(theta, self.active)
        positions = np.ascontiguousarray(np.reshape(positions, (count, p, dims)), dtype=float)
        delta, error = np.empty((count, p, m)), np.empty((count, p))
        du, scalars = np.empty((count, int(self.free.sum()))), np.empty((count, 5))
        a_max = np.inf if self.law.a_max is None else float(self.law.a_max)
        kernels.rates(flat, theta, slope, positions,
                      np.ascontiguousarray(np.reshape(jacobians, (count, p, dims, m)), dtype=float),
                      self.goals, self.weights, np.ascontiguousarray(self.active, dtype=bool), self.theta0, self.free,
                      float(self.eta), float(self.law.gain_constant), float(self.law.lambda_constant), a_max,
                      delta, error, du, scalars)
        lam, dlam, gain, energy, gradient = (scalars[:, c].reshape(lead) for c in range(5))
        return State(u.reshape(lead + (m,)), theta.reshape(lead + (m,)), lam, delta.reshape(lead + (p, m)),
                     error.reshape(lead + (p,)), positions.reshape(lead + (p, dims)), gain,
                     du.reshape(lead + du.shape[1:]), dlam, energy, gradient)

    def rates(self, s: float, y: np.ndarray) -> np.ndarray:
        """``dy/ds`` for the integrator; ``y`` of shape ``(free + 1,)`` or ``(free + 1, k)`` (vectorized)."""
        st = self.state(y.T)
        return np.concatenate([st.du, (st.dlam / st.lam)[..., None]], axis=-1).T

    def energy_rate(self, y: np.ndarray) -> float:
        """``dV/ds`` by the chain rule [004 eq. 15]: ``-g . G' du/ds + (sum_k E^k) dlambda/ds``."""
        st = self.state(y)
        g = st.lam * st.delta.sum(axis=0)[self.free] + (self.theta0 - st.theta)[self.free]
        slope = self.output.slope(st.u)[self.free]
        return float(-(g * slope) @ st.du + st.error.sum() * st.dlam)
