"""How far the shapes of an arm's body move, relative to each other and to the obstacles, when its joints move by at
most given amounts at a fixed pose of the tool (issue 40, item 4): the bound that certifies the collision-free sets
of the classes without a rigid structure to lean on (the Franka class, :mod:`redkin.collision.q7_free`; nearly S-R-S
arms, :mod:`redkin.collision.nearly_free`).

Let ``delta_j`` bound ``|q_j - q'_j|`` between two configurations ``q, q'`` of one pose.  A point of link ``k`` then
moves, relative to the base, by at most ``sum_{j <= k} delta_j L_j``, ``L_j`` a bound of its distance from axis
``j`` in every configuration: the length of the path from it through the joints' axis points ``k, k - 1, .., j``,
each leg fixed on one link (turning a point by ``d`` about an axis at distance ``r`` moves it by at most ``r d``;
moving the joints one after the other, each turn moves it by at most its lever times its angle).  Relative to the
tool, which the pose holds still in both configurations, it moves by at most ``sum_{j > k} delta_j L'_j`` (the path
through axes ``k + 1 .. j``); the smaller bound is kept.  Two links ``k1 < k2`` move relative to each other only
through joints ``k1 + 1 .. k2`` (levers from either link), and by no more than the sum of their displacements in the
base frame; the smaller is kept.  A pair's signed distance changes by no more than the two shapes' displacements.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin.chain import SerialChain
from redkin.collision.body import Body, capsule_ends, posed
from redkin.collision.clearance import CheckedPairs


def _joint_levers(chain: SerialChain, body: Body) -> tuple[np.ndarray, np.ndarray]:
    """Per capsule and joint ``(M, n)``: bounds of the distance of the capsule's segment from the joint's axis in
    every configuration, along the path through the axes from the capsule's link down to the joint (base side, joints
    ``j <= k`` of a capsule on frame ``k``; 0 for the others) and up to it (tip side, joints ``j > k``)."""
    frames = chain.frames(np.zeros(chain.n))
    _, points = chain.joint_axes_in(frames)  # (n, 3): a point on each axis, fixed on the links on both its sides
    legs = np.linalg.norm(np.diff(points, axis=0), axis=1)  # legs[i]: axis i + 1 to axis i + 2 (on link i + 1)
    ends = capsule_ends(posed(body, frames))  # (M, 2, 3)
    base = np.zeros((len(body), chain.n))
    tip = np.zeros((len(body), chain.n))
    for c, k in enumerate(body.frame.tolist()):
        for j in range(1, chain.n + 1):
            if 1 <= j <= k:  # from the capsule to axis k (on link k), then down the legs to axis j
                own = np.linalg.norm(ends[c] - points[k - 1], axis=1).max()
                base[c, j - 1] = own + legs[j - 1 : k - 1].sum()
            elif j > k:  # from the capsule to axis k + 1 (on link k), then up the legs to axis j
                own = np.linalg.norm(ends[c] - points[k], axis=1).max()
                tip[c, j - 1] = own + legs[k : j - 1].sum()
    return base, tip


@dataclass(frozen=True)
class PairLevers:
    """The levers of a body's checked pairs (:func:`pair_levers`): per capsule and joint ``(M, n)`` the base-side and
    tip-side levers of :func:`_joint_levers`; per checked pair its capsule ``capsule`` ``(P,)``; the self pairs
    ``own`` (indices into the pairs), their two capsules ``first`` and ``second``, and per self pair and joint the
    levers of their relative motion ``outer`` and ``inner`` ``(S, n)`` (base side from the outer link, tip side from
    the inner one), zero outside the joints between the two links."""

    base: np.ndarray
    tip: np.ndarray
    capsule: np.ndarray
    own: np.ndarray
    first: np.ndarray
    second: np.ndarray
    outer: np.ndarray
    inner: np.ndarray


def pair_levers(chain: SerialChain, body: Body, pairs: CheckedPairs) -> PairLevers:
    """The levers :func:`pair_displacements` weighs the joints' bounds by, for ``body``'s checked ``pairs`` on
    ``chain``: computed once per body and scene."""
    base, tip = _joint_levers(chain, body)
    own = np.flatnonzero(pairs.other >= 0)
    first, second = pairs.capsule[own], pairs.other[own]
    k1, k2 = body.frame[first], body.frame[second]
    joints = np.arange(1, chain.n + 1)[None, :]
    between = (joints > np.minimum(k1, k2)[:, None]) & (joints <= np.maximum(k1, k2)[:, None])
    outer = np.where((k1 >= k2)[:, None], base[first], base[second]) * between
    inner = np.where((k1 >= k2)[:, None], tip[second], tip[first]) * between
    return PairLevers(base, tip, pairs.capsule, own, first, second, outer, inner)


def pair_displacements(delta: np.ndarray, levers: PairLevers) -> np.ndarray:
    """Per row of joint bounds ``delta`` ``(N, n)`` and checked pair ``(N, P)``, a bound of how much the pair's
    signed distance changes between two configurations of one pose whose joints differ by at most ``delta``
    (module docstring): each sum of levers times joint bounds as one ``einsum`` (its own loops, the same sums
    whatever ``N``; a ``delta`` of ``inf`` gives ``nan`` where its lever is 0)."""
    shift = np.minimum(np.einsum("nj,mj->nm", delta, levers.base),  # each capsule's displacement in the base frame
                       np.einsum("nj,mj->nm", delta, levers.tip))
    total = shift[:, levers.capsule]
    if len(levers.own):
        relative = np.minimum(np.einsum("nj,sj->ns", delta, levers.outer),
                              np.einsum("nj,sj->ns", delta, levers.inner))
        total[:, levers.own] = np.minimum(relative, shift[:, levers.first] + shift[:, levers.second])
    return total
