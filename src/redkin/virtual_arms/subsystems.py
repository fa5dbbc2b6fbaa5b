"""Subsystems of paper 004: one per virtual arm, each with its own forward model, goal and weight.

A subsystem ``k`` knows only its own virtual end point: it evaluates its own
forward model at the shared joint vector and returns its steepest-descent
direction ``delta^k = -dE^k / d theta = J_k^T W^k (X^k* - X^k)`` and its
error ``E^k = 1/2 (X^k* - X^k)^T W^k (X^k* - X^k)`` (eqs. 12 and 17).  The
network exchanges only these signals.

Two evaluators give the same numbers: :class:`OneByOne` asks every
subsystem in turn through its own model; :class:`Together` evaluates all
points in one batched call of a joint model.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, Sequence

import numpy as np


class ForwardModel(Protocol):
    """Positions of virtual end points and their Jacobians (analytic or learned)."""

    @property
    def dims(self) -> int: ...

    @property
    def count(self) -> int: ...

    @property
    def joints(self) -> int: ...

    def evaluate(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...

    def split(self) -> list["ForwardModel"]: ...


@dataclass
class Signals:
    """What the subsystems report at one joint vector.

    Attributes
    ----------
    delta : numpy.ndarray, shape (..., p, m)
        ``delta^k`` of every subsystem (zero rows for dropped ones).
    error : numpy.ndarray, shape (..., p)
        ``E^k`` (eq. 12), zero for dropped ones.
    positions : numpy.ndarray, shape (..., p, l)
        Virtual end points ``X^k`` as the subsystems' models see them.
    """

    delta: np.ndarray
    error: np.ndarray
    positions: np.ndarray


def _signals(positions: np.ndarray, jacobians: np.ndarray, goals: np.ndarray, weights: np.ndarray,
             active: np.ndarray) -> Signals:
    residual = goals - positions  # (p, l)
    weighted = weights * residual
    delta = np.einsum("...plm,...pl->...pm", jacobians, weighted) * active[:, None]  # eq. 17
    error = 0.5 * np.sum(residual * weighted, axis=-1) * active  # eq. 12
    return Signals(delta, error, positions)


class Together:
    """All subsystems evaluated in one call of a joint forward model."""

    def __init__(self, model: ForwardModel):
        self.model = model

    def __call__(self, theta: np.ndarray, goals: np.ndarray, weights: np.ndarray, active: np.ndarray) -> Signals:
        positions, jacobians = self.model.evaluate(theta)
        return _signals(positions, jacobians, goals, weights, active)


class OneByOne:
    """Every subsystem evaluated by itself, through its own single-point forward model."""

    def __init__(self, models: Sequence[ForwardModel]):
        self.models = list(models)

    def __call__(self, theta: np.ndarray, goals: np.ndarray, weights: np.ndarray, active: np.ndarray) -> Signals:
        parts = []
        for k, model in enumerate(self.models):
            if not active[k]:  # a dropped subsystem sends nothing
                lead = theta.shape[:-1]
                parts.append(Signals(np.zeros(lead + (1, theta.shape[-1])), np.zeros(lead + (1,)),
                                     np.full(lead + (1, goals.shape[1]), np.nan)))
                continue
            positions, jacobians = model.evaluate(theta)
            parts.append(_signals(positions, jacobians, goals[k : k + 1], weights[k : k + 1], active[k : k + 1]))
        return Signals(
            np.concatenate([p.delta for p in parts], axis=-2),
            np.concatenate([p.error for p in parts], axis=-1),
            np.concatenate([p.positions for p in parts], axis=-2),
        )
