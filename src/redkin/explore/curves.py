"""What the explorer page draws, in one form for every arm class: a redundancy parameter and each branch over it.

The page reads the arm's :class:`redkin.arms.Parameter` (its name, symbols, domain and words) and, per branch, a
grid of parameter values with the joint values, postures, limit flags, feasible arcs and marked values on it
(:class:`BranchCurves`, filled by :mod:`redkin.explore.grid`).  It never asks which arm class it holds.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from redkin.arms import Parameter
from redkin.chain import SerialChain

if TYPE_CHECKING:  # a page in a cell only: the collision package is read where one is given
    from redkin.explore.cell import CellView

#: A joint value this far [rad] beyond a limit counts as within it (the value at a set's end, rounded).
_LIMIT_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Mark:
    """A special parameter value on a branch's grid: its kind (``feasible``, ``optimal``, ``singular``), label,
    index and note."""

    kind: str
    label: str
    index: int
    note: str = ""


@dataclass(frozen=True)
class BranchCurves:
    """One branch over the redundancy parameter.

    Attributes
    ----------
    branch : str
        The branch's three signs, e.g. ``"+-+"``.
    values : numpy.ndarray, shape (G,)
        Sorted parameter values in the domain [rad]: the dense grid and the special values, merged in exactly.
    q : numpy.ndarray, shape (G, n)
        Joint values of the chain at each value [rad]; NaN where the branch has no solution.
    exists : numpy.ndarray of bool, shape (G,)
        Whether the branch has a solution at each value (always, for an arm angle of a reachable pose).
    origins : numpy.ndarray, shape (G, n + 2, 3)
        Base, joint-frame and tool origins of the posture [m] (``SerialChain.frames``); NaN where no solution.
    within : numpy.ndarray of bool, shape (G, n)
        Whether each joint value exists and is within its limits (to :data:`_LIMIT_TOLERANCE`).
    feasible_at : numpy.ndarray of bool, shape (G,)
        Whether each value lies in the exact feasible set ``arcs``.
    arcs : numpy.ndarray, shape (K, 2)
        The feasible set as ``[start, end]`` arcs; ``start > end`` only on a parameter that wraps, for an arc through
        its ends.
    full : bool
        Whether the feasible set is the whole domain.
    per_joint : tuple of numpy.ndarray or None
        Per joint, the arcs (same form) on which that joint alone is within its limits; ``None`` where the class
        gives no per-joint sets.
    marks : tuple of Mark
        The feasible-set ends, singular and optimal values, with their indices into ``values``.
    start : int
        Index shown first.
    notes : tuple of str
        Sentences about the branch as a whole (a part singular at every value, no solution anywhere).
    """

    branch: str
    values: np.ndarray
    q: np.ndarray
    exists: np.ndarray
    origins: np.ndarray
    within: np.ndarray
    feasible_at: np.ndarray
    arcs: np.ndarray
    full: bool
    per_joint: tuple[np.ndarray, ...] | None
    marks: tuple[Mark, ...]
    start: int
    notes: tuple[str, ...]


@dataclass(frozen=True)
class ExplorerData:
    """The explorer's numbers for one arm and one pose: the parameter, what computed the numbers (``method``) and
    the kinds of marks they set (``feasible``, ``singular``, ``optimal``), every branch, the limits, the branch shown
    first, sentences about the arm that the page states (a nearly S-R-S arm's neighbour and model error), the
    sentence saying where the page opens and why, and in a cell the obstacles, the body and the collision-free sets
    (:class:`redkin.explore.cell.CellView`)."""

    robot: str
    joint_names: tuple[str, ...]
    pose: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    parameter: Parameter
    method: str
    kinds: tuple[str, ...]
    branches: tuple[BranchCurves, ...]
    initial: int
    remarks: tuple[str, ...] = ()
    opening: str = ""
    cell: CellView | None = None


def postures(chain: SerialChain, q: np.ndarray, exists: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The frame origins ``(G, n + 2, 3)`` of joint values ``q`` (NaN rows where ``exists`` is false) and whether
    each joint value is within its limits ``(G, n)``."""
    origins = chain.frames(np.where(exists[:, None], q, 0.0))[..., :3, 3]
    origins[~exists] = np.nan
    within = exists[:, None] & (q >= chain.lower - _LIMIT_TOLERANCE) & (q <= chain.upper + _LIMIT_TOLERANCE)
    return origins, within
