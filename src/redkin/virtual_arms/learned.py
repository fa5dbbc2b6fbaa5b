"""Learning mode (paper 004 section 3.1): one network per subsystem learns its virtual arm's [004 eq. 1].

Each subsystem owns a :class:`~redkin.virtual_arms.mlp.MLP` from the joint
vector to its virtual end point, trained independently by back-propagation on
sampled joint vectors [004 eq. 8].  :class:`LearnedModel` then serves positions
and input Jacobians with the same interface as the analytic model.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_vectors
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.virtual_arms.analytic import AnalyticModel
from redkin.virtual_arms.mlp import MLP
from redkin.virtual_arms.points import VirtualPoint


@dataclass(frozen=True)
class LearningReport:
    """Errors of the learned networks, per virtual end point, in metres.

    ``train_rms`` and ``held_out_rms`` are root-mean-square Euclidean position
    errors; ``held_out_max`` the largest held-out error.
    """

    labels: list[str]
    train_rms: np.ndarray
    held_out_rms: np.ndarray
    held_out_max: np.ndarray
    samples: int
    held_out: int


class LearnedModel:
    """Virtual end points served by one trained network per subsystem."""

    def __init__(self, networks: Sequence[MLP], points: Sequence[VirtualPoint], axes: tuple[int, ...], joints: int):
        self.networks = list(networks)
        self.points = list(points)
        self.axes = tuple(axes)
        self._joints = int(joints)

    @property
    def dims(self) -> int:
        return len(self.axes)

    @property
    def count(self) -> int:
        return len(self.networks)

    @property
    def joints(self) -> int:
        return self._joints

    def evaluate(self, theta: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Network outputs and input Jacobians, shapes ``(..., p, l)`` and ``(..., p, l, m)``."""
        theta = check_vectors(theta, self._joints, "theta")
        positions = np.stack([net(theta) for net in self.networks], axis=-2)
        jacobians = np.stack([net.input_jacobian(theta) for net in self.networks], axis=-3)
        return positions, jacobians

    def split(self) -> list[LearnedModel]:
        """One single-network model per virtual end point (the subsystems' own models)."""
        return [LearnedModel([net], [p], self.axes, self._joints) for net, p in zip(self.networks, self.points)]


def _sample_joints(chain: SerialChain, count: int, rng: np.random.Generator, lower: ArrayLike | None = None,
                  upper: ArrayLike | None = None) -> np.ndarray:
    """Uniform joint vectors in ``[lower, upper]`` (default: the chain's limits, ``+-pi`` where unlimited)."""
    low = (np.where(np.isfinite(chain.lower), chain.lower, -np.pi) if lower is None
           else check_vectors(lower, chain.n, "lower"))
    high = (np.where(np.isfinite(chain.upper), chain.upper, np.pi) if upper is None
            else check_vectors(upper, chain.n, "upper"))
    if np.any(high <= low):
        raise RedkinError("sampling range must have upper > lower for every joint")
    return rng.uniform(low, high, size=(int(count), chain.n))


def learn_forward_model(
    chain: SerialChain,
    points: Sequence[VirtualPoint],
    samples: int = 1000,
    held_out: int = 500,
    hidden: int = 12,
    activation: str = "sine",
    iterations: int = 400,
    lower: ArrayLike | None = None,
    upper: ArrayLike | None = None,
    axes: tuple[int, ...] | None = None,
    seed: int | np.random.Generator = 0,
) -> tuple[LearnedModel, LearningReport]:
    """Train one network per virtual end point on sampled joint vectors (paper 004 section 3.1, [004 eq. 8]).

    Parameters
    ----------
    chain, points :
        The real arm and its virtual end points.
    samples, held_out : int
        Training joint vectors and held-out joint vectors (never trained on).
    hidden : int
        Hidden units per network.
    activation : {"sine", "sigmoid"}
        Hidden-unit function (the paper's sigmoid, or its suggested trigonometric units).
    iterations : int
        L-BFGS iterations on back-propagated gradients.
    lower, upper : array_like, optional
        Sampling range of the joints.
    seed : int or numpy.random.Generator

    Returns
    -------
    LearnedModel, LearningReport
    """
    if samples < 1 or held_out < 1:
        raise RedkinError(f"samples and held_out must be positive, got {samples} and {held_out}")
    rng = np.random.default_rng(seed)
    truth = AnalyticModel(chain, points, axes)
    train_q = _sample_joints(chain, samples, rng, lower, upper)
    test_q = _sample_joints(chain, held_out, rng, lower, upper)
    train_x, _ = truth.evaluate(train_q)
    test_x, _ = truth.evaluate(test_q)
    networks, train_rms, test_rms, test_max = [], [], [], []
    for k in range(truth.count):
        net = MLP.initial(chain.n, hidden, truth.dims, activation, rng).trained(train_q, train_x[:, k], iterations)
        networks.append(net)
        train_err = np.linalg.norm(net(train_q) - train_x[:, k], axis=-1)
        test_err = np.linalg.norm(net(test_q) - test_x[:, k], axis=-1)
        train_rms.append(np.sqrt(np.mean(train_err**2)))
        test_rms.append(np.sqrt(np.mean(test_err**2)))
        test_max.append(test_err.max())
    model = LearnedModel(networks, points, truth.axes, chain.n)
    report = LearningReport([p.label for p in points], np.array(train_rms), np.array(test_rms), np.array(test_max),
                            int(samples), int(held_out))
    return model, report
