"""A small multilayer network in plain numpy (paper 004 section 3.1, Fig. 3).

Linear input and output units and one hidden layer of sigmoid units, or of
trigonometric (sine) units, which the paper suggests because forward
kinematics is built from sines and cosines.  The error of [004 eq. 8],
``E = 1/2 |X - o|^2`` averaged over the samples, is differentiated by
back-propagation; :meth:`MLP.input_jacobian` gives ``d o / d theta``, the
quantity the trajectory-generation mode back-propagates to the input units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from redkin.errors import RedkinError

_ACTIVATIONS = ("sigmoid", "sine")


def _activate(kind: str, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Hidden outputs and their derivatives."""
    if kind == "sine":
        return np.sin(h), np.cos(h)
    y = 0.5 * (1.0 + np.tanh(0.5 * h))  # the logistic sigmoid, overflow-free
    return y, y * (1.0 - y)


@dataclass
class MLP:
    """``o = W2 a(W1 x + b1) + b2`` with ``a`` the hidden activation.

    Parameters
    ----------
    w1 : numpy.ndarray, shape (H, m)
    b1 : numpy.ndarray, shape (H,)
    w2 : numpy.ndarray, shape (l, H)
    b2 : numpy.ndarray, shape (l,)
    activation : {"sigmoid", "sine"}
    """

    w1: np.ndarray
    b1: np.ndarray
    w2: np.ndarray
    b2: np.ndarray
    activation: str = "sigmoid"

    @classmethod
    def initial(cls, inputs: int, hidden: int, outputs: int, activation: str, rng: np.random.Generator) -> MLP:
        """Random weights of a fresh network (scaled by fan-in)."""
        if activation not in _ACTIVATIONS:
            raise RedkinError(f"activation must be one of {_ACTIVATIONS}, got {activation!r}")
        if hidden < 1:
            raise RedkinError(f"hidden must be a positive number of units, got {hidden!r}")
        return cls(
            rng.normal(0.0, 1.0 / np.sqrt(inputs), (hidden, inputs)),
            rng.uniform(-np.pi, np.pi, hidden) if activation == "sine" else np.zeros(hidden),
            rng.normal(0.0, 1.0 / np.sqrt(hidden), (outputs, hidden)),
            np.zeros(outputs),
            activation,
        )

    # ------------------------------------------------------------ parameters
    def _shapes(self) -> list[tuple[int, ...]]:
        return [self.w1.shape, self.b1.shape, self.w2.shape, self.b2.shape]

    def parameters(self) -> np.ndarray:
        """All weights as one flat vector."""
        return np.concatenate([self.w1.ravel(), self.b1, self.w2.ravel(), self.b2])

    def with_parameters(self, flat: np.ndarray) -> MLP:
        """A copy with the weights of a flat vector."""
        parts, start = [], 0
        for shape in self._shapes():
            size = int(np.prod(shape))
            parts.append(flat[start : start + size].reshape(shape))
            start += size
        w1, b1, w2, b2 = parts
        return MLP(w1, b1, w2, b2, activation=self.activation)

    # --------------------------------------------------------------- forward
    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Outputs for inputs ``x`` of shape ``(..., m)``: shape ``(..., l)``."""
        hidden, _ = _activate(self.activation, x @ self.w1.T + self.b1)
        return hidden @ self.w2.T + self.b2

    def input_jacobian(self, x: np.ndarray) -> np.ndarray:
        """``d o / d x`` of shape ``(..., l, m)``, by back-propagation to the input units."""
        _, slope = _activate(self.activation, x @ self.w1.T + self.b1)
        return np.einsum("lh,...h,hm->...lm", self.w2, slope, self.w1)

    # ---------------------------------------------------------------- training
    def loss_and_gradient(self, x: np.ndarray, target: np.ndarray) -> tuple[float, np.ndarray]:
        """Mean of [004 eq. 8] over the samples and its gradient in the weights (back-propagation)."""
        count = x.shape[0]
        hidden, slope = _activate(self.activation, x @ self.w1.T + self.b1)
        error = hidden @ self.w2.T + self.b2 - target  # (N, l)
        loss = 0.5 * float(np.sum(error**2)) / count
        grad_w2 = error.T @ hidden / count
        grad_b2 = error.sum(axis=0) / count
        back = (error @ self.w2) * slope  # error signal at the hidden units
        grad_w1 = back.T @ x / count
        grad_b1 = back.sum(axis=0) / count
        return loss, np.concatenate([grad_w1.ravel(), grad_b1, grad_w2.ravel(), grad_b2])

    def trained(self, x: np.ndarray, target: np.ndarray, iterations: int = 500) -> MLP:
        """The network after minimising [004 eq. 8] on ``(x, target)``.

        The gradient comes from back-propagation (:meth:`loss_and_gradient`);
        the descent steps use L-BFGS instead of fixed-rate steepest descent,
        which reaches the same kind of minimum in far fewer passes.
        """
        result = minimize(
            lambda flat: self.with_parameters(flat).loss_and_gradient(x, target),
            self.parameters(),
            jac=True,
            method="L-BFGS-B",
            options={"maxiter": int(iterations), "gtol": 1e-12, "ftol": 1e-15},
        )
        return self.with_parameters(result.x)
