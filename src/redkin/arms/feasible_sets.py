"""One result type of the feasible sets of every class of arm: :class:`FeasibleSets`, per pose and branch the values
of the redundancy parameter at which the branch's solution exists and lies within every joint limit."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin.circle import TWO_PI, circle_arcs, owner_runs
from redkin.errors import RedkinError

#: Slack (radians) of :meth:`FeasibleSets.contains` at the ends of an arc: the solvers' own rounding at a limit.
CONTAINS_TOLERANCE = 1e-12


class Arcs(NamedTuple):
    """The arcs of one feasible set.

    Attributes
    ----------
    bounds : numpy.ndarray, shape (k, 2)
        ``[start, end]`` in the parameter's units, sorted by ``start``, disjoint.
    wraps : numpy.ndarray of bool, shape (k,)
        The arc runs from ``start`` up through ``+-pi`` to ``end`` (then ``start > end``); only on a parameter that
        is an angle on the circle (the arm angle), never on a joint's value (q7).
    """

    bounds: np.ndarray
    wraps: np.ndarray


class ArcArrays(NamedTuple):
    """The arcs of many owners (a pose's branch, ``owner = pose * B + branch``) in three arrays, as :class:`Arcs`
    holds one owner's, sorted by owner and, within one, as :class:`Arcs` orders them.

    Attributes
    ----------
    bounds : numpy.ndarray, shape (A, 2)
    wraps : numpy.ndarray of bool, shape (A,)
    owner : numpy.ndarray of int, shape (A,)
    """

    bounds: np.ndarray
    wraps: np.ndarray
    owner: np.ndarray

    def split(self, owners: int) -> list[Arcs]:
        """The :class:`Arcs` of each owner ``0 .. owners - 1``."""
        ends = np.cumsum(np.bincount(self.owner, minlength=owners)).tolist()
        return [Arcs(self.bounds[start:end], self.wraps[start:end])
                for start, end in zip(([0] + ends)[:-1], ends, strict=True)]


@dataclass(frozen=True, eq=False)
class FeasibleSets:
    """Feasible sets of poses ``(...)`` and branches ``B``, stored as pieces ``(..., B, K)``.

    Piece ``j`` runs from ``start[..., j]`` to ``end[..., j]`` and is in the set where ``feasible[..., j]``; on a
    parameter that :attr:`wraps`, ``end`` may exceed ``pi`` (the piece passes through the seam). Read them with
    :meth:`arcs`, :meth:`union` and :meth:`contains`.

    Attributes
    ----------
    start, end : numpy.ndarray, shape (..., B, K)
    feasible : numpy.ndarray of bool, shape (..., B, K)
    branches : tuple of str
    parameter : str
        ``"psi"`` or ``"q7"``.
    wraps : bool
        Whether the parameter is an angle on the circle.
    exact : bool
        Whether the sets are a closed form's, proved complete (false on nearly S-R-S arms: each arc is certified,
        none proved missing).
    """

    start: np.ndarray
    end: np.ndarray
    feasible: np.ndarray
    branches: tuple[str, ...]
    parameter: str
    wraps: bool
    exact: bool

    @property
    def shape(self) -> tuple[int, ...]:
        """The poses' batch shape."""
        return self.feasible.shape[:-2]

    def index(self, branch: str | int) -> int:
        """The index of ``branch``: a label of :attr:`branches` or an index into them.

        Raises
        ------
        ValueError
            For any other value.
        """
        if isinstance(branch, (int, np.integer)) and not isinstance(branch, bool):
            if -len(self.branches) <= branch < len(self.branches):
                return int(branch) % len(self.branches)
        elif str(branch) in self.branches:
            return self.branches.index(str(branch))
        raise RedkinError(f"branch must be one of {', '.join(self.branches)} or an index below {len(self.branches)}, "
                          f"got {branch!r}")

    def _pose(self, at: int | tuple[int, ...]) -> tuple[int, ...]:
        at = (at,) if isinstance(at, (int, np.integer)) else tuple(at)
        if len(at) != len(self.shape) or not all(-s <= i < s for i, s in zip(at, self.shape, strict=True)):
            raise RedkinError(f"at must index one pose of the batch shape {self.shape}, got {at}")
        return at

    def arcs(self, branch: str | int, at: int | tuple[int, ...] = ()) -> Arcs:
        """The arcs of one branch at one pose (``at``, an index into :attr:`shape`; ``()`` for a single pose)."""
        b, at = self.index(branch), self._pose(at)
        keep = self.feasible[at + (b,)]
        return self._arcs(self.start[at + (b,)][keep], self.end[at + (b,)][keep])

    def union(self, at: int | tuple[int, ...] = ()) -> Arcs:
        """The values at which some branch is feasible, at one pose."""
        at = self._pose(at)
        keep = self.feasible[at]
        return self._arcs(self.start[at][keep], self.end[at][keep])

    def _arcs(self, start: np.ndarray, end: np.ndarray) -> Arcs:
        return owner_arcs(start, end, np.zeros(len(start), dtype=np.int64), self.wraps).split(1)[0]

    def every_arcs(self) -> list[tuple[Arcs, ...]]:
        """:meth:`arcs` of every branch at every pose, in one pass: per pose (the batch flattened in C order), the
        arcs of each branch of :attr:`branches`."""
        branches = len(self.branches)
        owners = int(np.prod(self.shape, dtype=np.int64)) * branches
        arcs = self.arc_arrays().split(owners)
        return [tuple(arcs[p * branches:(p + 1) * branches]) for p in range(owners // branches)]

    def arc_arrays(self) -> ArcArrays:
        """:meth:`every_arcs` as arrays: the arcs of owner ``pose * B + branch`` (the batch flattened in C order)."""
        owners = int(np.prod(self.shape, dtype=np.int64)) * len(self.branches)
        if not owners:
            return ArcArrays(np.empty((0, 2)), np.empty(0, dtype=bool), np.empty(0, dtype=np.int64))
        keep = self.feasible.reshape(owners, -1)
        owner = np.repeat(np.arange(owners), keep.sum(axis=1))
        return owner_arcs(self.start.reshape(owners, -1)[keep], self.end.reshape(owners, -1)[keep], owner, self.wraps)

    def contains(self, t: ArrayLike, branch: str | int) -> np.ndarray:
        """Whether values ``t`` (broadcast against the poses' batch shape) lie in ``branch``'s feasible sets, ends
        included (with the slack :data:`CONTAINS_TOLERANCE`)."""
        from redkin._validation import as_float_array, check_finite

        b = self.index(branch)
        t = as_float_array(t, "t")
        check_finite(t, "t")
        try:
            shape = np.broadcast_shapes(t.shape, self.shape)
        except ValueError:
            raise RedkinError(f"t of shape {t.shape} does not broadcast against the poses' shape {self.shape}") \
                from None
        value = np.broadcast_to(t, shape)[..., None]
        start, end, keep = (np.broadcast_to(part[..., b, :], shape + part.shape[-1:])
                            for part in (self.start, self.end, self.feasible))
        inside = (value >= start - CONTAINS_TOLERANCE) & (value <= end + CONTAINS_TOLERANCE)
        if self.wraps:
            turned = value + TWO_PI  # a piece through the seam holds its part beyond -pi one turn up
            inside |= (turned >= start - CONTAINS_TOLERANCE) & (turned <= end + CONTAINS_TOLERANCE)
        return np.any(inside & keep, axis=-1)

    @property
    def nonempty(self) -> np.ndarray:
        """Whether each pose and branch has a feasible value, shape ``(..., B)``."""
        return np.any(self.feasible, axis=-1)


def merged_intervals(start: np.ndarray, end: np.ndarray) -> Arcs:
    """Intervals ``[start, end]`` of a parameter that is not an angle on the circle (q7) as disjoint, sorted,
    merged arcs that never wrap."""
    return owner_arcs(start, end, np.zeros(len(start), dtype=np.int64), False).split(1)[0]


def owner_arcs(start: ArrayLike, end: ArrayLike, owner: ArrayLike, wraps: bool) -> ArcArrays:
    """The intervals ``[start, end]`` of each owner as its disjoint, sorted arcs, in arrays: on a parameter that
    ``wraps`` (an angle) merged on the circle as :class:`redkin.circle.ArcSet` merges
    (:func:`redkin.circle.circle_arcs`), else merged where they touch and never wrapping."""
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    if wraps:
        return ArcArrays(*circle_arcs(start, end, np.asarray(owner, dtype=np.int64)))
    lo, hi, arc_owner = owner_runs(start, end, np.asarray(owner, dtype=np.int64))
    return ArcArrays(np.stack([lo, hi], axis=-1).reshape(-1, 2), np.zeros(len(lo), dtype=bool), arc_owner)
