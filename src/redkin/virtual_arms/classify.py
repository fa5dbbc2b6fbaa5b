"""The classification of section 2 and Fig. 2 of paper 004: redundant, over-constrained or singular.

For stacked virtual end points ``X_0 = f(theta)`` ([004 eq. 2], ``l n`` rows, ``m``
joints) the kind of problem follows from the generic rank ``r`` of the
stacked Jacobian ``J_0`` [004 eq. 18]:

* ``r = l n < m``: **redundant** (Fig. 2 (a)); every virtual end point can reach
  its goal and ``m - r`` degrees of freedom remain;
* ``r = l n = m``: **determined** (no redundancy left, still solvable);
* ``r = m < l n``: **over-constrained** (Fig. 2 (b)); generally no posture meets
  every goal, the network converges to the weighted least-squares one;
* ``r < l n`` and ``r < m``: **singular** (Fig. 2 (c)); redundant and
  over-constrained parts at once, e.g. a point just before the end with only
  one joint between them.

The generic rank is the largest rank over random joint vectors.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin.errors import RedkinError

_KINDS = ("redundant", "determined", "over-constrained", "singular")


@dataclass(frozen=True)
class Classification:
    """Kind of a virtual-arm problem.

    Attributes
    ----------
    kind : {"redundant", "determined", "over-constrained", "singular"}
    rank : int
        Generic rank of the stacked Jacobian ``J_0``.
    rows : int
        ``l n``: task coordinates of all virtual end points.
    joints : int
        ``m``.
    """

    kind: str
    rank: int
    rows: int
    joints: int

    @property
    def redundancy(self) -> int:
        """Degrees of freedom left after the goals (``m - rank``)."""
        return self.joints - self.rank


def _classify_jacobians(jacobians: np.ndarray, tolerance: float = 1e-9) -> Classification:
    """Classify from stacked Jacobians ``J_0`` [004 eq. 18] at several generic postures, shape ``(k, rows, m)``."""
    jac = np.asarray(jacobians, dtype=float)
    if jac.ndim != 3:
        raise RedkinError(f"jacobians must have shape (k, rows, m), got {jac.shape}")
    _, rows, joints = jac.shape
    singular_values = np.linalg.svd(jac, compute_uv=False)
    scale = np.maximum(singular_values[:, :1], 1e-300)
    rank = int(np.max(np.sum(singular_values > tolerance * scale, axis=-1)))
    if rank == rows:
        kind = "redundant" if rank < joints else "determined"
    else:
        kind = "over-constrained" if rank == joints else "singular"
    return Classification(kind, rank, rows, joints)


def classify(model, samples: int = 5, seed: int | np.random.Generator = 0) -> Classification:
    """Classify the virtual end points of a forward model (section 2, Fig. 2).

    Parameters
    ----------
    model : ForwardModel
        E.g. :class:`~redkin.virtual_arms.analytic.AnalyticModel` with the chosen points.
    samples : int
        Random joint vectors (uniform in ``[-pi, pi]``) over which the rank is maximised.
    seed : int or numpy.random.Generator
    """
    rng = np.random.default_rng(seed)
    theta = rng.uniform(-np.pi, np.pi, size=(int(samples), model.joints))
    _, jac = model.evaluate(theta)
    return _classify_jacobians(jac.reshape(samples, -1, model.joints))
