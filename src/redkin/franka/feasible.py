"""The exact feasible set of q7 under the joint limits, per branch (docs/franka.md, [F8]-[F9]).

A branch's solution is a function of q7 (:mod:`redkin.franka.ik`); it is
feasible where it exists and every joint lies within its limits.  Its
status can change only where some joint meets a limit, where the branch
appears or vanishes, or where a joint jumps (a singular configuration).
Every such q7 is a real root of one of fourteen trigonometric polynomials
in q7 ([F8]: the product, over the four conjugate solutions that the square
roots of [F3] and [F5] give, of a polynomial vanishing where a joint meets
a limit; [F9]: the discriminants of [F3] and [F5]).  Their degrees are
known (at most 8), so each is recovered exactly from 20 samples, and its
real roots are isolated by a subdivision whose every step is a Taylor bound
(or, where that does not settle, found among its complex roots): no
crossing is missed for want of a sample, however narrow the arc it bounds.
Between two consecutive candidates the status of each branch is constant
and is read at the midpoint; each arc's ends are the polished roots, or
found by bisection on the branch itself where a root is not accurate.
docs/franka.md has the argument.
"""

from __future__ import annotations

from typing import NamedTuple, cast

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import run_batch
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.franka import _kernels
from redkin.franka.geometry import FrankaGeometry
from redkin.franka.ik import PARAMETER, as_franka, frames_seven
from redkin.srs.branches import BRANCHES, Branch

#: Arcs per branch and pose kept in the batch's arrays; a pose with more is computed again with room for all.
_ARCS = 16


class FeasibleQ7(NamedTuple):
    """The feasible values of q7 of one pose, per branch.

    Attributes
    ----------
    arcs : tuple of numpy.ndarray
        Per branch of ``branches``, the intervals ``[start, end]`` (K, 2) of
        q7 (the chain's values, increasing, disjoint) on which that branch
        exists and lies within every joint limit.  An empty array: no
        solution of that branch within the limits at any q7.
    domain : tuple of float
        The q7 range searched: joint 7's limits (``[-pi, pi]`` for an unlimited joint 7).
    branches : tuple of Branch
    parameter : str
        ``"q7"``.
    """

    arcs: tuple[np.ndarray, ...]
    domain: tuple[float, float]
    branches: tuple[Branch, ...]
    parameter: str = PARAMETER

    def contains(self, q7: float, branch: int) -> bool:
        """Whether ``q7`` lies in the feasible set of branch index ``branch`` (ends included)."""
        return any(start <= q7 <= end for start, end in self.arcs[branch])


def q7_domain(geometry: FrankaGeometry) -> np.ndarray:
    """Joint 7's range, the set q7 is searched in; ``[-pi, pi]`` where it covers the circle."""
    chain = geometry.chain
    if chain.covers_circle[6] and not chain.limited[6]:
        return np.array([-np.pi, np.pi])
    return np.array([chain.lower[6], chain.upper[6]])


def feasible_q7(arm: SerialChain | FrankaGeometry, pose: ArrayLike) -> FeasibleQ7:
    """The exact feasible q7 set of every branch of one target pose ([F8]-[F9]; module docstring).

    Parameters
    ----------
    arm : SerialChain or FrankaGeometry
        A Franka-class arm.
    pose : array_like, shape (4, 4)
        Target pose of the chain's tool frame in its base frame.

    Raises
    ------
    ValueError
        For a chain not of the Franka class or a malformed pose (a batch: :func:`feasible_q7_batch`).
    """
    if np.shape(pose) != (4, 4):
        raise RedkinError(f"pose must be one 4x4 pose (feasible_q7_batch takes a batch), got shape {np.shape(pose)}")
    return cast(FeasibleQ7, feasible_q7_batch(arm, pose)[()])


def feasible_q7_batch(arm: SerialChain | FrankaGeometry, pose: ArrayLike) -> np.ndarray:
    """:func:`feasible_q7` of a batch of poses ``(..., 4, 4)``: a numpy object array of :class:`FeasibleQ7` with the
    batch's shape, computed on the shared thread pool.

    Raises
    ------
    ValueError
        For a chain not of the Franka class or a malformed pose.
    """
    geometry = as_franka(arm)
    arcs, counts = _feasible_arcs(geometry, pose)
    domain = q7_domain(geometry)
    ends = (float(domain[0]), float(domain[1]))
    flat_arcs, flat_counts = arcs.reshape((-1,) + arcs.shape[-3:]), counts.reshape(-1, len(BRANCHES)).tolist()
    results = np.empty(len(flat_counts), dtype=object)
    for n, per_branch in enumerate(flat_counts):
        results[n] = FeasibleQ7(tuple(flat_arcs[n, b, :count].copy() for b, count in enumerate(per_branch)), ends,
                                BRANCHES)
    return results.reshape(counts.shape[:-1])


def feasible_q7_pieces(arm: SerialChain | FrankaGeometry, pose: ArrayLike) -> tuple[np.ndarray, np.ndarray,
                                                                                    np.ndarray]:
    """The feasible q7 sets of a batch of poses ``(..., 4, 4)`` as arrays, as :class:`redkin.arms.FeasibleSets`
    stores them: ``start, end`` ``(..., 8, K)`` (NaN past a branch's last arc) and ``feasible`` (``True`` on the
    first ``n`` pieces of a branch with ``n`` arcs), ``K`` the most arcs of any branch and pose (at least 1); the
    branches in :data:`BRANCHES`' order.  The sets of :func:`feasible_q7_batch`, without a Python object per pose.

    Raises
    ------
    ValueError
        For a chain not of the Franka class or a malformed pose.
    """
    arcs, counts = _feasible_arcs(as_franka(arm), pose)
    return arcs[..., 0], arcs[..., 1], np.arange(arcs.shape[-2]) < counts[..., None]


def _feasible_arcs(geometry: FrankaGeometry, pose: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's answer for poses ``(..., 4, 4)``: ``arcs`` ``(..., 8, K, 2)`` (NaN past a branch's last arc; ``K``
    the most arcs of any branch and pose, at least 1) and their numbers ``counts`` ``(..., 8)``."""
    t07 = frames_seven(geometry, pose)
    shape = t07.shape[:-2]
    flat = np.ascontiguousarray(t07.reshape(-1, 4, 4))
    count = len(flat)
    arcs = np.full((count, len(BRANCHES), _ARCS, 2), np.nan)
    counts = np.empty((count, len(BRANCHES)), dtype=np.int64)
    kernel_arguments = (geometry.kernel_arm, geometry.kernel_limits, geometry.kernel_joints, geometry.kernel_branches,
                        q7_domain(geometry))
    run_batch(_kernels.feasible_poses, count, flat, *kernel_arguments, arcs, counts)
    crowded = np.flatnonzero(counts[:, 0] < 0)  # more arcs than the batch kept room for: again, with room for all
    if len(crowded):
        most = int(-counts[crowded, 0].min())
        room = np.full((len(crowded), len(BRANCHES), most, 2), np.nan)
        room_counts = np.empty((len(crowded), len(BRANCHES)), dtype=np.int64)
        _kernels.feasible_poses(0, len(crowded), np.ascontiguousarray(flat[crowded]), *kernel_arguments, room,
                                room_counts)
        counts[crowded] = room_counts
        arcs = np.concatenate([arcs, np.full((count, len(BRANCHES), most - _ARCS, 2), np.nan)], axis=2)
        arcs[crowded] = room
    most = max(1, int(counts.max(initial=0)))
    return arcs[:, :, :most].reshape(shape + (len(BRANCHES), most, 2)), counts.reshape(shape + (len(BRANCHES),))
