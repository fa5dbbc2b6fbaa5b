"""Subsystems of paper 004: one per virtual arm, each with its own forward model, goal and weight.

A subsystem ``k`` knows only its own virtual end point: it evaluates its own
forward model at the shared joint vector and returns its steepest-descent
direction ``delta^k = -dE^k / d theta = J_k^T W^k (X^k* - X^k)`` and its
error ``E^k = 1/2 (X^k* - X^k)^T W^k (X^k* - X^k)`` [004 eqs. 12, 17].  The
network exchanges only these signals, which the compiled rate function
(:func:`~redkin.virtual_arms._kernels.rates`) forms from the end points and
Jacobians an evaluator returns.

Two evaluators give the same numbers: :class:`OneByOne` asks every
subsystem in turn through its own model; :class:`Together` evaluates all
points in one batched call of a joint model.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

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

    def split(self) -> Sequence[ForwardModel]: ...


class Together:
    """All subsystems evaluated in one call of a joint forward model."""

    def __init__(self, model: ForwardModel):
        self.model = model

    def __call__(self, theta: np.ndarray, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions ``(..., p, l)`` and Jacobians ``(..., p, l, m)`` of every virtual end point at ``theta``."""
        return self.model.evaluate(theta)


class OneByOne:
    """Every subsystem evaluated by itself, through its own single-point forward model."""

    def __init__(self, models: Sequence[ForwardModel]):
        self.models = list(models)

    def __call__(self, theta: np.ndarray, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """As :meth:`Together.__call__`; a dropped subsystem (``active`` false) sends nothing: NaN positions, zero
        Jacobians."""
        lead, m = theta.shape[:-1], theta.shape[-1]
        parts = []
        for k, model in enumerate(self.models):
            if active[k]:
                parts.append(model.evaluate(theta))
            else:
                parts.append((np.full(lead + (1, model.dims), np.nan), np.zeros(lead + (1, model.dims, m))))
        return np.concatenate([x for x, _ in parts], axis=-2), np.concatenate([j for _, j in parts], axis=-3)
