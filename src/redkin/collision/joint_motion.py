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

Along the normal (:func:`tightened`).  Those displacements are the points' whole motion; what moves a pair's
distance is their motion along its normal, often a small part of it (two joints whose turns cancel along the
self-motion, a link sliding past a post).  Let ``p`` be a point of a capsule turned by joints ``j_1, j_2, ..``
(ordered from a link held still: the base, the tool, or the other link of a self pair), each by ``Delta_j``,
``|Delta_j| <= delta_j``.  Along the straight path ``s Delta`` in joint space its velocity is ``sum_j Delta_j w_j x
(p - o_j)`` (the axes ``w_j`` through ``o_j``, each moved by the joints before it), and differentiating again, its
acceleration is at most ``sum_j delta_j (2 A_j l_j + B_j)``, with ``l_j`` the lever bounding ``|p - o_j|`` in every
configuration, ``A_j = sum_(i before j) delta_i`` (how fast axis ``j`` turns) and ``B_j = sum_(i from j on)
delta_i l_i``.  So for any unit ``u``, ``u . (p(Delta) - p)`` is at most ``sum_j |u . (w_j x (p - o_j))| delta_j``
(the axes at the first configuration) plus half that bound.  For two convex shapes ``A`` and ``B`` and any unit
``u``, ``min_B u . b - max_A u . a`` bounds their distance from below; with ``u`` their witness normal it equals the
distance, and as ``A``'s capsule ends move it falls by no more than their rise along ``u`` (the moving shape's
support is at an end).  Where the pair is within the margin, its distance is at most that of two points on the
cores, ``x = c_b - c_a``, less the radii, and ``|x + dx| <= |x| + x/|x| . dx + |dx|^2 / (2 |x|)``, ``|dx|`` at most
the displacement bound above: a bound of the rise that is first-order exact too (against a plane, the height of the
lowest end).  Each bound adds what its support gap or core distance lacks of the measured distance, so it holds
whatever the witness points' rounding.  The smaller of the two bounds of each pair is kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin._compiled import kernel_array, run_batch
from redkin.chain import SerialChain
from redkin.collision import _joint_motion_kernels
from redkin.collision.body import Body, capsule_ends, posed
from redkin.collision.clearance import CheckedPairs, ClearanceInputs


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
    return PairLevers(kernel_array(base), kernel_array(tip), pairs.capsule, own, first, second, outer, inner)


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


def _normal_reaches(chain: SerialChain, inputs: ClearanceInputs, levers: PairLevers, q: np.ndarray,
                    delta: np.ndarray, reach: np.ndarray, want: np.ndarray, margin: float) -> np.ndarray:
    """Per configuration ``q`` ``(N, n)`` and checked pair of ``inputs`` ``(N, P)``, a bound of how far the pair's
    clearance moves from its value at ``q`` towards the margin, down where the pair is farther apart than ``margin``
    there and up where it is not, over configurations of the same pose whose joints differ from ``q`` by at most
    ``delta`` ``(N, n)``, read along the pair's normal (module docstring, "Along the normal"), for the pairs ``want``
    ``(N, P)`` (``inf`` for the others, and where no such bound is given); ``reach`` ``(N, P)`` is
    :func:`pair_displacements` at ``delta``.  One compiled pass (:func:`redkin.collision._joint_motion_kernels.
    reaches`)."""
    out = np.empty(want.shape)
    if len(q):
        run_batch(_joint_motion_kernels.reaches, len(q), kernel_array(q), chain._links, chain._ends,
                  chain._standard, *inputs.body, inputs.obstacles, *inputs.pairs, float(margin), levers.base,
                  levers.tip, kernel_array(delta), kernel_array(reach), kernel_array(want), out)
    return out


def tightened(chain: SerialChain, inputs: ClearanceInputs, levers: PairLevers, q: np.ndarray, delta: np.ndarray,
              moved: np.ndarray, clearance: np.ndarray, active: np.ndarray, margin: float) -> np.ndarray:
    """``moved`` ``(N, P)``, :func:`pair_displacements` at the bands ``delta`` ``(N, n)`` about ``q`` ``(N, n)``,
    lowered to :func:`_normal_reaches` on the ``active`` pairs it leaves undecided (``|clearance| <= moved``, the
    clearances at ``q``): the bound a decision reads, towards the margin (down where a clearance is positive, up
    where it is not)."""
    with np.errstate(invalid="ignore"):  # nan or inf where a band is not bounded: not tightened
        want = active & np.isfinite(moved) & (np.abs(clearance) <= moved)
    rows = np.flatnonzero(want.any(axis=1))
    if not len(rows):
        return moved
    out = moved.copy()
    out[rows] = np.minimum(moved[rows], _normal_reaches(chain, inputs, levers, q[rows], delta[rows], moved[rows],
                                                       want[rows], margin))
    return out
