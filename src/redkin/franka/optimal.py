"""The limit-avoiding q7 of a Franka-class arm, in the spirit of paper 000 section 5.2 ([000 eqs. 35-40]).

Paper 000 chooses the arm angle whose joint values are nearest given target
values (the middle of each range by default), then clamps it into the
feasible set.  Here the measure is the joints' squared distances from the
targets, each in units of its half range [F10]:

    ``f(q7) = sum_i ((q_i(q7) - t_i) / h_i)^2``, ``h_i = (upper_i - lower_i) / 2`` (1 for an unlimited joint),

over its feasible set (``feasible``, ``None`` where that is empty) and over
every q7 at which the branch exists (``unclamped``).  ``f`` has no
closed-form minimiser, so it is sampled densely over each feasible arc and
over joint 7's range, and the best sample refined by a bounded scalar
search (Brent's method, :func:`redkin.bounded_minimum.bounded_minimum`)
between its neighbours; the unclamped optimum is the better of that and
the feasible one, so that it is never worse than it (a branch may exist
only on arcs narrower than the samples' spacing).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_vectors
from redkin.bounded_minimum import bounded_minimum
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.franka.feasible import FeasibleQ7, feasible_q7, q7_domain
from redkin.franka.geometry import FrankaGeometry
from redkin.franka.ik import PARAMETER, as_franka, ik
from redkin.srs.branches import BRANCHES, Branch

#: Samples of q7 over the whole range, and over each feasible arc, before the refinement.
_SAMPLES = 361
#: How far inside an interval its end samples are taken (radians).
_INSIDE = 1e-12
#: How many of the lowest sampled local minima are refined.
_REFINED = 4


@dataclass(frozen=True)
class OptimalQ7:
    """The limit-avoiding q7 of one pose and branch [F10].

    Attributes
    ----------
    unclamped : float or None
        The minimiser of ``f`` over every q7 at which the branch exists (``None`` if it exists nowhere).
    feasible : float or None
        The minimiser over the feasible set (``None`` if that is empty); equal to ``unclamped`` where that is feasible.
    value, feasible_value : float or None
        ``f`` at each.
    parameter : str
        ``"q7"``.
    """

    unclamped: float | None
    feasible: float | None
    value: float | None
    feasible_value: float | None
    parameter: str = PARAMETER


def optimal_q7(
    arm: SerialChain | FrankaGeometry,
    pose: ArrayLike,
    branch: str | Branch | tuple[int, int, int],
    target: ArrayLike | None = None,
    feasible: FeasibleQ7 | None = None,
) -> OptimalQ7:
    """The q7 of one pose and branch whose joint values are nearest ``target`` in units of the half ranges [F10].

    Parameters
    ----------
    arm : SerialChain or FrankaGeometry
    pose : array_like, shape (4, 4)
    branch : str or Branch
    target : array_like, shape (7,), optional
        Joint values to stay near (default: the middle of each range, 0 for an unlimited joint).
    feasible : FeasibleQ7, optional
        The pose's feasible sets, if already computed (:func:`redkin.franka.feasible_q7`).

    Raises
    ------
    ValueError
        For a chain not of the Franka class, a malformed pose, branch or target.
    """
    geometry = as_franka(arm)
    pose = np.asarray(pose, dtype=float)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one 4x4 pose, got shape {pose.shape}")
    index = geometry.branch_index(branch)
    chain = geometry.chain
    limited = chain.limited
    middle = np.where(limited, 0.5 * (chain.lower + chain.upper), 0.0)
    goal = middle if target is None else check_vectors(target, 7, "target")
    half = np.where(limited, 0.5 * (chain.upper - chain.lower), 1.0)
    sets = feasible if feasible is not None else feasible_q7(geometry, pose)

    def objective(q7: np.ndarray) -> np.ndarray:
        solutions = ik(geometry, pose, q7, BRANCHES[index])
        cost = np.sum(((solutions.q[..., 0, :] - goal) / half) ** 2, axis=-1)
        return np.where(solutions.exists[..., 0], cost, np.inf)

    low, high = q7_domain(geometry)
    best = _minimise(objective, [(float(a), float(b)) for a, b in sets.arcs[index]])
    unclamped = _minimise(objective, [(float(low), float(high))])
    if best[1] is not None and (unclamped[1] is None or best[1] <= unclamped[1]):
        unclamped = best
    elif unclamped[0] is not None and sets.contains(unclamped[0], index):
        best = unclamped  # the whole-range search found a better feasible point than the arcs' own
    return OptimalQ7(unclamped[0], best[0], unclamped[1], best[1])


def _minimise(objective, pieces: list[tuple[float, float]]) -> tuple[float | None, float | None]:
    """The minimiser of ``objective`` over the union of intervals and its value, or ``(None, None)``.

    Each sampled local minimum among the :data:`_REFINED` lowest is refined, not only the lowest sample: where a
    branch's solution jumps (``q_2`` through 0 turns ``q_1`` and ``q_3`` by pi) ``f`` jumps too, and its infimum
    can sit at the jump, next to a sample no lower than others far away.
    """
    best_q7, best_value = None, np.inf
    for low, high in pieces:
        grid = np.linspace(low, high, _SAMPLES if high > low else 1)
        values = objective(grid)
        if high - low > 4.0 * _INSIDE:  # an end where the branch vanishes has no solution itself: just inside it
            for k, inside in ((0, low + _INSIDE), (-1, high - _INSIDE)):
                if not np.isfinite(values[k]):
                    grid[k], values[k] = inside, objective(np.array(inside))
        inner = np.concatenate([[np.inf], values, [np.inf]])
        minima = np.flatnonzero((values <= inner[:-2]) & (values <= inner[2:]) & np.isfinite(values))
        for k in minima[np.argsort(values[minima])][:_REFINED]:
            candidate, value = float(grid[k]), float(values[k])
            if high > low:
                left, right = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
                ceiling = value + 1e6  # in place of inf where the branch does not exist (Brent needs numbers)

                def capped(x: float, top: float = ceiling) -> float:
                    return min(float(objective(np.array(x))), top)

                x, refined = bounded_minimum(capped, float(left), float(right), xatol=1e-10)
                if refined < value:
                    candidate, value = x, refined
            if value < best_value:
                best_q7, best_value = candidate, value
    return (best_q7, best_value) if best_q7 is not None else (None, None)
