"""Sets of closed arcs on the circle of angles ``[-pi, pi)``.

An :class:`ArcSet` is a finite union of closed arcs.  To the user an arc is a
pair ``(lo, hi)`` of angles in ``[-pi, pi]`` read counter-clockwise from
``lo`` to ``hi``; an arc through ``+-pi`` is ONE arc and is printed with
``lo > hi`` (e.g. ``(3.0, -3.0)``).  The full circle and the empty set are
ordinary values (:meth:`ArcSet.full`, :meth:`ArcSet.empty`).

Internally the set is kept as sorted, disjoint closed intervals of the line
segment ``[-pi, pi]`` (an arc through ``+-pi`` is cut in two there); the
public :attr:`ArcSet.arcs` joins the two pieces again.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from redkin.errors import RedkinError

_PI = float(np.pi)
#: The angle constants, defined once for every module of redkin.
TWO_PI = 2.0 * _PI
HALF_PI = 0.5 * _PI
#: Gaps narrower than this (radians) are closed when arcs are merged: they are
#: rounding left by wrapping at the +-pi seam, far below any physical angle.
_SEAM_TOLERANCE = 1e-12


def wrap_angle(angle: np.ndarray | float) -> np.ndarray | float:
    """Angles mapped to ``[-pi, pi)``.

    A Python float comes back as a float, computed with Python's ``%``
    (the same floor modulo as ``np.mod``, without numpy's per-call cost).
    """
    if type(angle) is float:
        return (angle + _PI) % TWO_PI - _PI
    return np.mod(np.asarray(angle, dtype=float) + _PI, TWO_PI) - _PI


def arc_length(start: float, end: float) -> float:
    """The length [rad] of the arc from ``start`` up to ``end``, through +-pi where ``start > end``, as redkin writes
    an arc's or a removed stretch's ends: ``(-pi, pi)`` is the whole circle (2 pi), ``start == end`` a point (0).
    (``(end - start) mod 2 pi`` reads the whole circle as 0.)"""
    return end - start if end >= start else end - start + TWO_PI


def _seamed(lo: float, hi: float) -> tuple[float, float]:
    """An interval of ``[-pi, pi]`` whose ends within :data:`_SEAM_TOLERANCE` of the seam are on it: the set then
    holds +-pi wherever :attr:`ArcSet.arcs` shows an arc through it (an end 1e-13 short of pi was drawn through the
    seam, yet did not hold pi)."""
    return (-_PI if lo <= -_PI + _SEAM_TOLERANCE else lo), (_PI if hi >= _PI - _SEAM_TOLERANCE else hi)


def _merge(intervals: Iterable[tuple[float, float]]) -> tuple[tuple[float, float], ...]:
    """Sorted union of closed line intervals (touching ones, within :data:`_SEAM_TOLERANCE`, are merged; ends that
    near the seam are put on it, :func:`_seamed`)."""
    ordered = sorted(_seamed(float(lo), float(hi)) for lo, hi in intervals)
    merged: list[list[float]] = []
    for lo, hi in ordered:
        if merged and lo <= merged[-1][1] + _SEAM_TOLERANCE:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    return tuple((lo, hi) for lo, hi in merged)


class ArcSet:
    """A finite union of closed arcs of the circle.

    Parameters
    ----------
    arcs : sequence of (lo, hi)
        Arcs read counter-clockwise from ``lo`` to ``hi`` (radians, any real
        values; they are wrapped).  ``lo > hi`` after wrapping means the arc
        passes through ``+-pi``.  An arc with ``hi - lo >= 2 pi`` before
        wrapping is the full circle.
    """

    __slots__ = ("_intervals",)

    def __init__(self, arcs: Sequence[Sequence[float]] = ()) -> None:
        pieces: list[tuple[float, float]] = []
        for arc in arcs:
            if len(arc) != 2:
                raise RedkinError(f"an arc must be a pair (lo, hi), got {arc!r}")
            lo, hi = float(arc[0]), float(arc[1])
            if not (math.isfinite(lo) and math.isfinite(hi)):
                raise RedkinError(f"arc ends must be finite, got ({lo}, {hi})")
            if hi - lo >= TWO_PI:
                pieces.append((-_PI, _PI))
                continue
            start = (lo + _PI) % TWO_PI - _PI  # wrap_angle(lo), without the call
            length = (hi - lo) % TWO_PI if hi != lo else 0.0
            end = start + length
            if end <= _PI:
                pieces.append((start, end))
            else:
                pieces.append((start, _PI))
                pieces.append((-_PI, end - TWO_PI))
        # one interval is merged already, and needs only its ends put on the seam
        self._intervals = (tuple(_seamed(*piece) for piece in pieces) if len(pieces) < 2 else _merge(pieces))

    # ----------------------------------------------------------- constructors
    @classmethod
    def full(cls) -> ArcSet:
        """The whole circle (one shared instance: an ArcSet never changes)."""
        return _FULL

    @classmethod
    def empty(cls) -> ArcSet:
        """The empty set (one shared instance)."""
        return _EMPTY

    @classmethod
    def _from_intervals(cls, intervals: Iterable[tuple[float, float]]) -> ArcSet:
        result = cls.__new__(cls)
        result._intervals = _merge(intervals)
        return result

    # ------------------------------------------------------------- properties
    @property
    def intervals(self) -> tuple[tuple[float, float], ...]:
        """Sorted disjoint closed intervals of ``[-pi, pi]`` (arcs through ``+-pi`` cut in two)."""
        return self._intervals

    @property
    def is_empty(self) -> bool:
        """True for the empty set."""
        return not self._intervals

    @property
    def is_full(self) -> bool:
        """True for the whole circle."""
        return (
            len(self._intervals) == 1
            and self._intervals[0][0] <= -_PI + _SEAM_TOLERANCE
            and self._intervals[0][1] >= _PI - _SEAM_TOLERANCE
        )

    @property
    def arcs(self) -> list[tuple[float, float]]:
        """The arcs as ``(lo, hi)``; an arc through ``+-pi`` is one pair with ``lo > hi``.

        The full circle is ``[(-pi, pi)]``.
        """
        pieces = list(self._intervals)
        if self.is_full or len(pieces) < 2:
            return pieces
        if pieces[0][0] <= -_PI + _SEAM_TOLERANCE and pieces[-1][1] >= _PI - _SEAM_TOLERANCE:
            joined = (pieces[-1][0], pieces[0][1])
            return pieces[1:-1] + [joined]
        return pieces

    @property
    def length(self) -> float:
        """Total length of the arcs in radians."""
        return float(sum(hi - lo for lo, hi in self._intervals))

    # ------------------------------------------------------------- operations
    def union(self, other: ArcSet) -> ArcSet:
        """Points in either set."""
        return ArcSet._from_intervals(self._intervals + other._intervals)

    def intersection(self, other: ArcSet) -> ArcSet:
        """Points in both sets."""
        result: list[tuple[float, float]] = []
        i = j = 0
        a, b = self._intervals, other._intervals
        while i < len(a) and j < len(b):
            lo = max(a[i][0], b[j][0])
            hi = min(a[i][1], b[j][1])
            if lo <= hi:
                result.append((lo, hi))
            if a[i][1] < b[j][1]:
                i += 1
            else:
                j += 1
        return ArcSet._from_intervals(result)

    def complement(self) -> ArcSet:
        """The closure of the points not in this set (closed arcs share their ends with this set)."""
        result: list[tuple[float, float]] = []
        start = -_PI
        for lo, hi in self._intervals:
            if lo > start:
                result.append((start, lo))
            start = hi
        if start < _PI:
            result.append((start, _PI))
        return ArcSet._from_intervals(result)

    def contains(self, angle: np.ndarray | float, tolerance: float = 0.0) -> np.ndarray | bool:
        """Whether each angle (any real value, wrapped) lies in the set, within ``tolerance``."""
        values = wrap_angle(angle)
        inside = np.zeros(np.shape(values), dtype=bool)
        for lo, hi in self._intervals:
            inside |= (values >= lo - tolerance) & (values <= hi + tolerance)
            # an angle just below +pi wraps to -pi: check both images near the seam
            inside |= (values + TWO_PI >= lo - tolerance) & (values + TWO_PI <= hi + tolerance)
            inside |= (values - TWO_PI >= lo - tolerance) & (values - TWO_PI <= hi + tolerance)
        return bool(inside) if np.ndim(inside) == 0 else inside

    def nearest(self, angle: float) -> float | None:
        """The point of the set nearest to ``angle`` on the circle (``None`` if the set is empty).

        An angle inside the set is returned wrapped to ``[-pi, pi)``.
        """
        if self.is_empty:
            return None
        value = float(wrap_angle(angle))
        if self.contains(value):
            return value
        ends = np.array([end for interval in self._intervals for end in interval])
        distance = np.abs(wrap_angle(ends - value))
        return float(wrap_angle(ends[int(np.argmin(distance))]))

    # ------------------------------------------------------------- dunder
    def __eq__(self, other: object) -> bool:
        return isinstance(other, ArcSet) and self._intervals == other._intervals

    def __hash__(self) -> int:
        return hash(self._intervals)

    def __repr__(self) -> str:
        if self.is_empty:
            return "ArcSet.empty()"
        if self.is_full:
            return "ArcSet.full()"
        return "ArcSet([" + ", ".join(f"({lo:.6g}, {hi:.6g})" for lo, hi in self.arcs) + "])"

    def isclose(self, other: ArcSet, tolerance: float = 1e-9) -> bool:
        """Same arcs with ends equal within ``tolerance``."""
        a, b = self._intervals, other._intervals
        return len(a) == len(b) and all(
            abs(x[0] - y[0]) <= tolerance and abs(x[1] - y[1]) <= tolerance for x, y in zip(a, b)
        )


_FULL = ArcSet._from_intervals(((-_PI, _PI),))
_EMPTY = ArcSet._from_intervals(())


def _intersect_all(sets: Iterable[ArcSet]) -> ArcSet:
    """Intersection of several arc sets (the full circle for none)."""
    result = ArcSet.full()
    for arc_set in sets:
        result = result.intersection(arc_set)
    return result


def owner_runs(lo: np.ndarray, hi: np.ndarray, owner: np.ndarray,
               tolerance: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The union of closed line intervals ``[lo, hi]`` of each owner, as its disjoint runs ``(lo, hi, owner)``
    sorted by owner and start: two intervals of one owner join where the later starts at most ``tolerance`` beyond
    the furthest end so far (as :class:`ArcSet` merges, one owner at a time, in numpy)."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    owner = np.asarray(owner, dtype=np.int64)
    order = np.lexsort((hi, lo, owner))
    lo, hi, owner = lo[order], hi[order], owner[order]
    count = len(lo)
    if not count:
        return lo, hi, owner
    rank = np.empty(count, dtype=np.int64)  # hi's rank: the furthest end so far of one owner, exactly, as integers
    by_end = np.argsort(hi, kind="stable")
    rank[by_end] = np.arange(count)
    furthest = np.maximum.accumulate(owner * count + rank) - owner * count  # an owner's keys exceed every earlier's
    reach = hi[by_end][furthest]
    first = np.ones(count, dtype=bool)
    first[1:] = (owner[1:] != owner[:-1]) | (lo[1:] > reach[:-1] + tolerance)
    starts = np.flatnonzero(first)
    ends = np.append(starts[1:] - 1, count - 1)
    return lo[starts], reach[ends], owner[starts]


def circle_arcs(lo: np.ndarray, hi: np.ndarray, owner: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each owner's arcs ``[lo, hi]`` (read counter-clockwise, any real values) as :attr:`ArcSet.arcs` gives them,
    for many owners in numpy: ``(bounds (A, 2), wraps (A,), arc_owner (A,))``, sorted by owner and, within one,
    as :attr:`ArcSet.arcs` orders them (an arc through ``+-pi``, ``start > end`` and ``wraps``, last)."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    owner = np.asarray(owner, dtype=np.int64)
    full = hi - lo >= TWO_PI
    start = np.mod(lo + _PI, TWO_PI) - _PI
    end = start + np.where(hi != lo, np.mod(hi - lo, TWO_PI), 0.0)
    split = ~full & (end > _PI)  # through the seam: cut in two there
    piece_lo = np.concatenate([np.where(full, -_PI, start), np.full(int(split.sum()), -_PI)])
    piece_hi = np.concatenate([np.where(full | split, _PI, end), end[split] - TWO_PI])
    piece_lo = np.where(piece_lo <= -_PI + _SEAM_TOLERANCE, -_PI, piece_lo)  # ends this near the seam are on it
    piece_hi = np.where(piece_hi >= _PI - _SEAM_TOLERANCE, _PI, piece_hi)
    run_lo, run_hi, run_owner = owner_runs(piece_lo, piece_hi, np.concatenate([owner, owner[split]]), _SEAM_TOLERANCE)
    first = np.ones(len(run_lo), dtype=bool)
    first[1:] = run_owner[1:] != run_owner[:-1]
    last = np.ones(len(run_lo), dtype=bool)
    last[:-1] = first[1:]
    first_of, last_of = np.flatnonzero(first), np.flatnonzero(last)  # each owner's first and last run
    joined = (first_of != last_of) & (run_lo[first_of] <= -_PI + _SEAM_TOLERANCE) & \
        (run_hi[last_of] >= _PI - _SEAM_TOLERANCE)  # the two pieces of an arc through the seam
    keep = np.ones(len(run_lo), dtype=bool)
    keep[first_of[joined]] = keep[last_of[joined]] = False
    bounds = np.concatenate([np.stack([run_lo[keep], run_hi[keep]], axis=-1),
                             np.stack([run_lo[last_of[joined]], run_hi[first_of[joined]]], axis=-1)]).reshape(-1, 2)
    arc_owner = np.concatenate([run_owner[keep], run_owner[first_of[joined]]])
    through = np.concatenate([np.zeros(int(keep.sum()), dtype=bool), np.ones(int(joined.sum()), dtype=bool)])
    order = np.lexsort((bounds[:, 0], through, arc_owner))
    return bounds[order], through[order], arc_owner[order]
