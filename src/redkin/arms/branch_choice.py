"""Which of a branch's solutions at one value of the redundancy parameter to report, where a branch has several: a
nearly S-R-S arm next to a stretched elbow or a straight shoulder, where the self-motion turns back (docs/srs.md,
"Nearly S-R-S arms"; :meth:`redkin.arms.Arm.every_solution`).

One rule for :meth:`redkin.arms.Arm.ik` and ``redkin ik``: the solutions within the limits and, in a cell, clear of
it by the margin come first (then those clear, then those within the limits, then any); of those, the one nearest
the configuration ``q0`` to stay near where one is given, else the first (the closed form's row).
"""

from __future__ import annotations

import numpy as np

from redkin.chain import SerialChain

#: How far outside a joint's range [rad] a solution still counts as within it here: the certificate's own rounding
#: (the nearly S-R-S solutions are located to 1e-9), as ``redkin ik --every-solution`` marks them.
_WITHIN_ROUNDING = 1e-9


def candidates(chain: SerialChain, solutions: np.ndarray, q0: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """A branch's solutions ``(K, n)``, each joint moved by whole turns into its range (nearest ``q0`` where given),
    and whether each lies within the limits (to :data:`_WITHIN_ROUNDING`)."""
    moved = chain.nearest_in_range(solutions, near=None if q0 is None else np.broadcast_to(q0, solutions.shape))
    return moved, np.asarray(chain.within_limits(moved, tolerance=_WITHIN_ROUNDING, wrap=True), dtype=bool)


def preferred(solutions: np.ndarray, within: np.ndarray, clear: np.ndarray | None, q0: np.ndarray | None) -> int:
    """The index of the solution to report among one branch's ``solutions`` ``(K, n)``, ``K >= 1``.

    Parameters
    ----------
    solutions : numpy.ndarray, shape (K, n)
        The branch's solutions at one value, the closed form's first (:func:`candidates`).
    within : numpy.ndarray of bool, shape (K,)
        Whether each lies within the joint limits.
    clear : numpy.ndarray of bool, shape (K,), optional
        In a cell, whether each keeps the scene's margin.
    q0 : numpy.ndarray, shape (n,), optional
        The configuration to stay near.

    Returns
    -------
    int
    """
    rank = within.astype(int) if clear is None else 2 * clear.astype(int) + within
    best = np.flatnonzero(rank == rank.max())
    if q0 is None:
        return int(best[0])
    return int(best[np.argmin(np.linalg.norm(solutions[best] - q0, axis=-1))])
