"""Whether the steps between configurations are collision-free (issue 40): the joint values moving linearly from one
configuration to the next, as a controller interpolates between waypoints.

What is proved.  On a step from ``q_a`` to ``q_b``, a point fixed in link ``k`` at ``p`` (its frame's coordinates)
moves by at most ``sum_j |dq_j| R_jk`` where ``R_jk = sum_{i=j..k} sqrt(a_i^2 + d_i^2) + |p|`` bounds its distance
from axis ``j`` in every configuration (each link transform of the chain translates by ``sqrt(a_i^2 + d_i^2)``,
and axis ``j`` passes through the origin of a frame among them).  A signed distance moves no faster than the
points of either shape, so a pair whose distances at the two ends are ``c_a`` and ``c_b`` keeps at least
``(c_a + c_b - D) / 2`` on the whole step, ``D`` the sum of the two shapes' bounds.  A step where that is below the
margin for some pair is halved (its middle configuration measured), down to 2^-20 of the step; a step is
**certified** where every pair is proved to keep the margin on every part, and **blocked** where a configuration
measured on it does not keep it.

Example
-------
>>> import numpy as np
>>> from redkin.collision import BodyCapsule, body_of, primitives, Scene
>>> from redkin.collision.steps import step_clearance
>>> from redkin.models import kuka_iiwa14
>>> chain = kuka_iiwa14()
>>> body = body_of([BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.06)], chain)
>>> post = Scene(("post",), primitives.capsule([0.4, 0.3, 0], [0.4, 0.3, 1.2], 0.05)[None], 0.01)
>>> steps = step_clearance(chain, body, post, np.linspace(np.zeros(7), np.full(7, 0.2), 5))
>>> steps.certified.tolist()
[True, True, True, True]
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain
from redkin.collision.body import Body
from redkin.collision.clearance import checked_pairs, clearance_inputs, pair_clearances
from redkin.collision.scene import Scene
from redkin.errors import RedkinError

#: How many times a step is halved at most before it is left unproved.
_DEPTH = 20


class StepClearance(NamedTuple):
    """What :func:`step_clearance` proves of each step.

    Attributes
    ----------
    certified : numpy.ndarray of bool, shape (N - 1,)
        Every configuration of the step keeps the margin from every obstacle and between the checked links.
    blocked : numpy.ndarray of bool, shape (N - 1,)
        A configuration measured on the step does not keep the margin.
    least : numpy.ndarray, shape (N - 1,)
        On a certified step, the least clearance proved (>= the margin); otherwise the least measured.
    link, against : numpy.ndarray of str, shape (N - 1,)
        On a blocked step, the pair found closer than the margin: the body's link and the obstacle (or the other
        link); ``""`` on the other steps.
    """

    certified: np.ndarray
    blocked: np.ndarray
    least: np.ndarray
    link: np.ndarray
    against: np.ndarray


def step_clearance(chain: SerialChain, body: Body, scene: Scene, q: ArrayLike) -> StepClearance:
    """Whether each step between consecutive configurations ``q`` ``(N, n)``, the joints moving linearly, keeps
    the scene's margin from every obstacle and between the body's checked links (module docstring).

    Raises
    ------
    RedkinError
        For joint values that are not ``(N, n)`` with ``N >= 1`` and finite.
    """
    q = chain.check_q(q)
    if q.ndim != 2:
        raise RedkinError(f"q must be configurations of shape (N, {chain.n}), got shape {q.shape}")
    return _steps(chain, body, scene, q[:-1], q[1:])


def steps_between(chain: SerialChain, body: Body, scene: Scene, start: ArrayLike, end: ArrayLike) -> StepClearance:
    """:func:`step_clearance` of the steps from each configuration of ``start`` ``(N, n)`` to the same row of
    ``end``, each step on its own (the joints moving linearly, as given: a joint on the circle is not taken the
    shorter way round).

    Raises
    ------
    RedkinError
        For joint values that are not ``(N, n)`` and finite, or of two shapes.
    """
    start, end = chain.check_q(start), chain.check_q(end)
    if start.ndim != 2 or start.shape != end.shape:
        raise RedkinError(f"start and end must be configurations of one shape (N, {chain.n}), got shapes "
                          f"{start.shape} and {end.shape}")
    return _steps(chain, body, scene, start, end)


def _steps(chain: SerialChain, body: Body, scene: Scene, start: np.ndarray, end: np.ndarray) -> StepClearance:
    """The steps from ``start`` to ``end`` (validated, ``(N, n)`` each; module docstring)."""
    pairs = checked_pairs(body, scene)
    steps = len(start)
    link, against = np.full(steps, "", dtype=object), np.full(steps, "", dtype=object)
    if steps < 1 or not len(pairs.names):
        return StepClearance(np.ones(steps, bool), np.zeros(steps, bool), np.full(steps, np.inf), link, against)
    reach = _reach(chain, body)  # (n, M)
    along = reach[:, pairs.capsule] + np.where(pairs.other >= 0, reach[:, np.maximum(pairs.other, 0)], 0.0)

    inputs = clearance_inputs(body, scene, pairs)

    def measured(configurations: np.ndarray) -> np.ndarray:
        return pair_clearances(chain, inputs, configurations, margin=scene.margin)

    ends = measured(np.concatenate([start, end]))
    owner = np.arange(steps)
    qa, qb, ca, cb = start, end, ends[:steps], ends[steps:]
    certified, blocked = np.ones(steps, bool), np.zeros(steps, bool)
    least = np.minimum(ca, cb).min(axis=1) + scene.margin
    proved = np.full(steps, np.inf)
    for _ in range(_DEPTH + 1):
        if not len(owner):
            break
        sweep = np.abs(qb - qa) @ along  # (K, P): how far each pair can close on the part
        bound = (ca + cb - sweep) / 2.0  # a lower bound of each pair's clearance on the part
        hit = np.any(np.minimum(ca, cb) < 0.0, axis=1)
        blocked[owner[hit]] = True
        for k, pair in zip(owner[hit].tolist(), np.argmin(np.minimum(ca, cb)[hit], axis=1).tolist(), strict=True):
            link[k], against[k] = pairs.names[pair]
        keep = np.any(bound < 0.0, axis=1) & ~hit
        done = ~keep & ~hit
        np.minimum.at(proved, owner[done], bound[done].min(axis=1) + scene.margin)
        if not keep.any():
            owner = owner[:0]
            break
        owner, qa, qb, ca, cb = owner[keep], qa[keep], qb[keep], ca[keep], cb[keep]
        middle = (qa + qb) / 2.0
        cm = measured(middle)
        np.minimum.at(least, owner, cm.min(axis=1) + scene.margin)
        owner = np.concatenate([owner, owner])
        qa, qb = np.concatenate([qa, middle]), np.concatenate([middle, qb])
        ca, cb = np.concatenate([ca, cm]), np.concatenate([cm, cb])
    certified[np.unique(owner)] = False  # still open after the deepest halving
    certified &= ~blocked
    return StepClearance(certified, blocked, np.where(certified, proved, least), link, against)


def _reach(chain: SerialChain, body: Body) -> np.ndarray:
    """``R[j, c]``: how far a point of capsule ``c`` can be from axis ``j + 1`` (0 where the joint does not move
    it), the module docstring's bound."""
    lengths = np.hypot(chain.a, chain.d)  # each link transform's translation
    extent = np.maximum(np.linalg.norm(body.a, axis=1), np.linalg.norm(body.b, axis=1))
    reach = np.zeros((chain.n, len(body)))
    for c, frame in enumerate(body.frame.tolist()):
        for j in range(frame):  # joints 1 .. frame move it
            reach[j, c] = lengths[j:frame].sum() + extent[c]
    return reach
