"""The graph path resolution searches: arm-angle samples inside the exact feasible arcs, per waypoint and branch.

A node is one arm angle on one branch at one waypoint, with its joint values
(the closed-form IK [000 eqs. 11-19]) and its clearance (the smallest
distance of a joint to a limit).  Nodes lie in the *pieces* of the exact
feasible sets [000 eq. 30] (:func:`redkin.srs.feasible_pieces_all_branches`):
the arcs between consecutive limit crossings, inside which every joint is a
continuous function of the arm angle.  Each piece contributes its two ends,
its middle and the points of a uniform grid inside it, so no feasible arc is
missed however narrow.  :func:`connect` then splits evenly every interval
between neighbouring nodes of a piece across which some joint moves more than
a fraction of its step bound, and :func:`window` samples finer around
the nodes a search chose.

Joints whose range holds every angle (:attr:`SerialChain.covers_circle`) are
compared on the circle; the others as plain differences of the joint values
inside their ranges.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin.chain import SerialChain
from redkin.circle import TWO_PI
from redkin.errors import SizeLimitError
from redkin.paths import _dp_kernels
from redkin.srs.feasible import PIECE_TOLERANCE, FeasiblePieces

#: Clearance below this (radians) drops a node: an arc end computed a few ulps outside its limit is clipped back,
#: anything further out is not a feasible sample.
_CLIP_TOLERANCE = 1e-9
#: A refinement window (:func:`window`) samples this many arm angles on each side of the chosen node.
_WINDOW_SIDE = 2
#: Intervals of a piece are not halved below this width (radians of arm angle).
_MIN_SPACING = 1e-9
#: The most nodes a path's graph holds (:func:`piece_samples`, :func:`connect`): about 180 bytes each at the search's
#: peak, 7 GB in all (100 000 iiwa14 waypoints hold 3e7 nodes at first, and the search peaks at 5.5 GB).
_MOST_NODES = 40_000_000


@dataclass(frozen=True)
class Graph:
    """Nodes sorted by waypoint, piece and arm angle.

    Attributes
    ----------
    offsets : numpy.ndarray of int, shape (W + 1,)
        The nodes of waypoint ``w`` are ``offsets[w] .. offsets[w + 1] - 1``.
    piece : numpy.ndarray of int, shape (K,)
        The piece a node lies in (numbered over all waypoints and branches); -1 for a node that stands alone.
    branch : numpy.ndarray of int, shape (K,)
        Index into :data:`redkin.srs.BRANCHES` (the chain's senses).
    psi, q, clearance : numpy.ndarray, shapes (K,), (K, 7), (K,)
    """

    offsets: np.ndarray
    piece: np.ndarray
    branch: np.ndarray
    psi: np.ndarray
    q: np.ndarray
    clearance: np.ndarray

    @property
    def waypoint(self) -> np.ndarray:
        """The waypoint of each node."""
        return np.repeat(np.arange(len(self.offsets) - 1), np.diff(self.offsets))


@dataclass(frozen=True)
class Arm:
    """What the graph needs of an arm along a path: its chain, the per-joint bounds, which joints are compared on the
    circle, and the joint values of its nodes (:meth:`rows`, given by the arm's class:
    :mod:`redkin.paths.family`).

    Attributes
    ----------
    chain : SerialChain
        The chain whose joint values the nodes hold.
    step : numpy.ndarray, shape (7,)
    circle : numpy.ndarray of bool, shape (7,)
    """

    chain: SerialChain
    step: np.ndarray
    circle: np.ndarray

    def rows(self, waypoint: np.ndarray, branch: np.ndarray, parameter: np.ndarray,
             shared: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Joint values ``(K, 7)`` and clearance ``(K,)`` of nodes (waypoint, branch index, value of the redundancy
        parameter).  The clearance is the smallest distance of a joint with a range narrower than ``2 pi`` to a
        limit (negative outside, ``inf`` where no joint has such a range; ``-inf`` where the branch does not exist
        there); such joints are clipped into their limits.  ``shared`` (K,): per node, a node with the same
        waypoint, elbow sign and parameter (at most its own index, itself where it is the first), whose work a
        class may share (:func:`piece_samples`); ``None``: nothing shared."""
        raise NotImplementedError

    def take(self, waypoints: np.ndarray) -> Arm:
        """The same arm along the waypoints ``waypoints`` only, numbered from 0."""
        raise NotImplementedError

    def clearance(self, q: np.ndarray) -> np.ndarray:
        """The smallest distance of a joint with a range narrower than ``2 pi`` to a limit, per row of ``q``
        (``inf`` where no joint has such a range)."""
        chain = self.chain
        binding = ~self.circle
        if not binding.any():
            return np.full(q.shape[:-1], np.inf)
        inside = np.minimum(q[..., binding] - chain.lower[binding], chain.upper[binding] - q[..., binding])
        return inside.min(axis=-1)

    def moves(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """How far each joint moves between ``a`` and ``b`` (..., 7): :func:`joint_moves` with :attr:`circle`."""
        return joint_moves(a, b, self.circle)

    def pose_fixed(self, waypoint: int) -> np.ndarray:
        """The values ``(E, 7)`` that the pose of ``waypoint`` leaves a joint, one row per choice (NaN for a joint
        the redundancy moves): none here (``(0, 7)``); an S-R-S arm's elbow has one value per elbow sign."""
        return np.empty((0, self.chain.n))


def least_moves(arm: Arm, before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """A lower bound of how far each joint moves between any configuration whose fixed joints take one row of
    ``before`` ``(A, 7)`` and any whose take one of ``after`` ``(B, 7)`` (:meth:`Arm.pose_fixed`; NaN: free): the
    least such move on the circle, which no shift of a value by a turn makes smaller; 0 for a joint free in either
    or where a side has no row."""
    if not len(before) or not len(after):
        return np.zeros(arm.chain.n)
    moves = joint_moves(before[:, None], after[None], np.ones(arm.chain.n, dtype=bool))
    return np.nan_to_num(moves, nan=0.0).min(axis=(0, 1))


def joint_moves(a: np.ndarray, b: np.ndarray, circle: np.ndarray) -> np.ndarray:
    """How far each joint moves between ``a`` and ``b`` (..., n): on the circle (the shorter way round) for the
    joints of ``circle`` (as :func:`redkin.paths._dp_kernels.gap`), plain differences for the others."""
    d = np.abs(a - b)
    turned = np.mod(d, TWO_PI)
    return np.where(circle, np.minimum(turned, TWO_PI - turned), d)


def piece_samples(pieces: FeasiblePieces, spacing: float, groups: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """The initial samples of every feasible piece of every waypoint and branch, sorted as :class:`Graph` sorts its
    nodes (by waypoint, piece and arm angle).

    Parameters
    ----------
    pieces : FeasiblePieces
        Of shape ``(W, 8, S)``.
    spacing : float
        The grid: arm angles ``-pi + k spacing`` (shifted by ``2 pi`` into a piece that wraps).
    groups : numpy.ndarray, shape (8,), optional
        A label per branch (:meth:`redkin.paths.family.Family.sample_groups`): the branches of one group have their
        pieces' ends slot for slot, so the nodes of one slot share their samples.  ``None``: nothing shared.

    Returns
    -------
    waypoint, branch, piece, psi : numpy.ndarray, shape (K,)
        Each piece's ends, its middle and the grid points inside it.
    shared : numpy.ndarray of int, shape (K,)
        The node whose sample each node shares (the same waypoint, group and parameter; itself for the first such
        node), as :meth:`Arm.rows` takes it.
    bounds : numpy.ndarray, shape (pieces, 2)
        The ends of each piece (``piece`` indexes it).

    Raises
    ------
    SizeLimitError
        Where the samples would be more than :data:`_MOST_NODES` nodes.
    """
    keep = pieces.feasible & (pieces.end - pieces.start > PIECE_TOLERANCE)
    waypoint, branch, slot = np.nonzero(keep)
    lo, hi = pieces.start[keep], pieces.end[keep]
    first = np.floor((lo + np.pi) / spacing).astype(np.int64) + 1
    last = np.ceil((hi + np.pi) / spacing).astype(np.int64) - 1
    grid = np.maximum(last - first + 1, 0)
    count = grid + 3  # the start, the grid points and the middle, the end
    offsets = np.concatenate([[0], np.cumsum(count)])
    leader = np.arange(lo.size)  # a piece with the same ends, whose samples a piece shares
    if groups is not None:
        numbered = np.full(keep.shape, -1, dtype=np.int64)
        numbered[keep] = leader
        for label in np.unique(groups):
            group = np.flatnonzero(groups == label)
            mine = np.isin(branch, group)
            first_keeper = group[np.argmax(keep[:, group, :], axis=1)]  # (W, S): the group's first branch keeping it
            leader[mine] = numbered[waypoint[mine], first_keeper[waypoint[mine], slot[mine]], slot[mine]]
    size = offsets[-1]
    if size > _MOST_NODES:
        raise SizeLimitError(f"a path of {pieces.start.shape[0]:,} waypoints needs {size:,} nodes in its graph, more "
                             f"than {_MOST_NODES:,} (a size too large to compute): give fewer waypoints (a larger "
                             "--step with --through)", "nodes", size, _MOST_NODES)
    nodes = (np.empty(size, dtype=np.int64), np.empty(size, dtype=np.int64), np.empty(size, dtype=np.int64),
             np.empty(size), np.empty(size, dtype=np.int64))
    _dp_kernels.piece_nodes(0, lo.size, lo, hi, first, grid, spacing, offsets, leader, waypoint, branch, *nodes)
    return (*nodes, np.stack([lo, hi], axis=-1))


def build(arm: Arm, waypoint: np.ndarray, branch: np.ndarray, piece: np.ndarray, psi: np.ndarray,
          count: int, ordered: bool = False, shared: np.ndarray | None = None) -> Graph:
    """The graph of the nodes given over ``count`` waypoints: joint values, clearance, sorted by waypoint, piece
    and arm angle (``ordered``: they already are; ``shared`` as in :meth:`Arm.rows`).  A node more than
    :data:`_CLIP_TOLERANCE` outside a limit is dropped, the others clipped into the limits."""
    q, clearance = arm.rows(waypoint, branch, psi, shared)
    good = clearance >= -_CLIP_TOLERANCE
    if not good.all():
        waypoint, branch, piece, psi, q, clearance = (a[good] for a in (waypoint, branch, piece, psi, q, clearance))
    if not ordered:
        order = np.lexsort((psi, piece, waypoint))
        waypoint, branch, piece, psi, q, clearance = (a[order] for a in (waypoint, branch, piece, psi, q, clearance))
    offsets = np.searchsorted(waypoint, np.arange(count + 1))
    return Graph(offsets, piece, branch, psi, q, np.maximum(clearance, 0.0))



def connect(arm: Arm, graph: Graph, fraction: float, rounds: int = 40) -> Graph:
    """Subdivide each interval between neighbouring nodes of a piece across which some joint moves more than
    ``fraction`` of its bound, evenly into as many parts as that move needs, until none does (or an interval is
    :data:`_MIN_SPACING` wide): rounds of :func:`redkin.paths._dp_kernels.split_counts`, the new nodes' joint values
    (:meth:`Arm.rows`), and each new node put in its place between the ends of its interval.  A new node more than
    :data:`_CLIP_TOLERANCE` outside a limit, or where its branch does not exist, is dropped.

    A round after the first looks only at the intervals the last one cut (an interval not cut is not cut again):
    each cut interval's nodes, its ends and the new nodes kept, form a run of its own (its own number in place of
    the piece, so that no interval spans two runs), and the new nodes of every round are put in the graph once, at
    the end.

    Raises
    ------
    SizeLimitError
        Where the graph would hold more than :data:`_MOST_NODES` nodes.
    """
    size = len(graph.psi)
    waypoint = graph.waypoint
    # the runs of the current round: nodes (parameter, joint values, run number) and, per node, the graph's node
    # at the start of the interval it lies in
    psi, q, run, origin = graph.psi, graph.q, graph.piece, np.arange(size)
    added: list[tuple[np.ndarray, ...]] = []  # per round: origin, parameter, joint values, clearance of new nodes
    for _ in range(rounds):
        parts = np.ones(max(len(psi) - 1, 0), dtype=np.int64)
        _dp_kernels.split_counts(psi, run, q, arm.step, arm.circle, fraction, _MIN_SPACING, parts)
        extra = parts - 1
        count = int(extra.sum())
        if count == 0:
            break
        if size + sum(len(more[0]) for more in added) + count > _MOST_NODES:
            raise SizeLimitError(f"a step bound this small needs more than {_MOST_NODES:,} nodes in the path's graph "
                                 "(a size too large to compute): give a larger step bound (max_step: --max-step, or "
                                 "--dt), or fewer waypoints", "nodes", size + count, _MOST_NODES)
        left = np.repeat(np.arange(len(psi) - 1), extra)  # the interval each new node cuts
        j = np.arange(count) - np.repeat(np.cumsum(extra) - extra, extra) + 1  # 1 .. parts - 1 within it
        new_psi = psi[left] + (psi[left + 1] - psi[left]) * (j / parts[left])
        owner = origin[left]
        new_q, clearance = arm.rows(waypoint[owner], graph.branch[owner], new_psi)
        kept = ~(clearance < -_CLIP_TOLERANCE)
        added.append((owner[kept], new_psi[kept], new_q[kept], np.maximum(clearance[kept], 0.0)))
        # the next round's runs: each cut interval's two ends and the new nodes kept between them, in order
        cut = np.flatnonzero(extra)
        which = np.searchsorted(cut, left[kept])  # the run of each new node kept
        inside = np.bincount(which, minlength=len(cut))
        lengths = 2 + inside
        starts = np.cumsum(lengths) - lengths
        rank = np.arange(len(which)) - np.repeat(np.cumsum(inside) - inside, inside)  # its place among them
        place = np.concatenate([starts, starts + lengths - 1, starts[which] + 1 + rank])
        total = int(lengths.sum())
        next_psi, next_q = np.empty(total), np.empty((total, q.shape[1]))
        next_origin = np.empty(total, dtype=np.int64)
        next_psi[place] = np.concatenate([psi[cut], psi[cut + 1], new_psi[kept]])
        next_q[place] = np.concatenate([q[cut], q[cut + 1], new_q[kept]])
        next_origin[place] = np.concatenate([origin[cut], origin[cut], owner[kept]])  # the left end's interval
        psi, q, origin = next_psi, next_q, next_origin
        run = np.repeat(np.arange(len(cut)), lengths)
    if not added:
        return graph
    owner, new_psi, new_q, clearance = (np.concatenate(column) for column in zip(*added, strict=True))
    order = np.lexsort((np.concatenate([np.full(size, -np.inf), new_psi]),
                        np.concatenate([np.arange(size), owner])))  # each new node after its interval's start
    every_waypoint = np.concatenate([waypoint, waypoint[owner]])[order]
    return Graph(np.searchsorted(every_waypoint, np.arange(len(graph.offsets))),
                 np.concatenate([graph.piece, graph.piece[owner]])[order],
                 np.concatenate([graph.branch, graph.branch[owner]])[order],
                 np.concatenate([graph.psi, new_psi])[order], np.concatenate([graph.q, new_q])[order],
                 np.concatenate([graph.clearance, clearance])[order])


def window(arm: Arm, graph: Graph, chosen: np.ndarray, width: float, bounds: np.ndarray, count: int,
           frozen: np.ndarray | None = None) -> Graph:
    """A graph of the parameters ``psi_c + width j / 2`` (``j = -2 .. 2``) of each chosen node ``c``, in its piece
    (``bounds`` (pieces, 2): each piece's ends) and on its branch: the chosen path stays in it, and neighbouring
    paths up to ``width`` away are sampled twice finer.  A node outside any piece (``q0``'s own), or ``frozen``
    (per chosen node: its path is refined no further), is kept alone."""
    offsets = np.arange(-_WINDOW_SIDE, _WINDOW_SIDE + 1)
    node = np.repeat(chosen, offsets.size)
    piece = graph.piece[node]
    psi = graph.psi[node] + width * np.tile(offsets / _WINDOW_SIDE, chosen.size)
    alone = piece < 0
    if frozen is not None:
        alone |= np.repeat(frozen, offsets.size)
    inside = alone | ((psi >= bounds[piece, 0]) & (psi <= bounds[piece, 1]))
    inside &= ~alone | (np.tile(offsets, chosen.size) == 0)
    psi = np.where(alone, graph.psi[node], psi)
    # one chosen node per waypoint, in order, and its samples in increasing psi: already sorted
    return build(arm, graph.waypoint[node][inside], graph.branch[node][inside], piece[inside], psi[inside], count,
                 ordered=True)
