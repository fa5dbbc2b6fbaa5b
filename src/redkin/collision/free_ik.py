"""Collision-free numerical IK on any chain (issue 40): certified solutions of a pose that keep a scene's margin.

The numerical solver (:func:`redkin.numerical.ik`, [N1]-[N5]) finds distinct certified solutions of a pose from
its seed and random starts.  :func:`collision_free_ik` asks it for as many candidates as wanted (or ``candidates``),
measures each candidate's clearance (:func:`redkin.collision.clearance`: every body capsule against every obstacle
and the body's self pairs, exact distances between capsules and shapes) and keeps those at least the scene's margin
clear, in the solver's order (with a seed, nearest the seed first).  Where fewer than wanted are clear and the solver
found every candidate it was asked for, that pose is asked again for four times as many (from its own starts, so the
candidates of its last round include the earlier ones), until enough are clear, the solver runs out of starts (its
``restarts`` budget, per round) or 1000 are asked.  In a batch only the poses still short of clear solutions go on to
the next round, together; pose ``i`` always starts from the solver's stream ``i``, as in
:func:`redkin.numerical.ik` (:func:`redkin.numerical.solve.start_streams`).

What is certified: each returned solution reaches the pose within the tolerance (the solver's certificate) and is
clear by the margin (its clearance, computed at that configuration).  What is not: that a pose with no clear
solution found has none; the result says how many candidates were found and how many collide, and the clearest
of those that collide.  On S-R-S and offset-elbow arms, :func:`redkin.collision.collision_free_arm_angles` gives the
exact collision-free sets instead.
"""

from __future__ import annotations

import copy
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_count
from redkin.chain import SerialChain
from redkin.collision.body import Body
from redkin.collision.clearance import Clearance, clearance
from redkin.collision.scene import Scene
from redkin.numerical.solve import RESTARTS, SEPARATION, TOLERANCE, NumericalSolutions, ik, start_streams

#: Most candidates asked per pose (the solver's own limit of distinct solutions).
_MAX_CANDIDATES = 1000


class FreeSolutions(NamedTuple):
    """Certified solutions of target poses that keep a scene's margin (:func:`collision_free_ik`).

    Attributes
    ----------
    q : numpy.ndarray, shape (..., count, n)
        Collision-free solutions, within the joint limits, in the solver's order (zeros where ``found`` is false).
    found : numpy.ndarray of bool, shape (..., count)
    clearance : numpy.ndarray, shape (..., count)
        Each solution's least distance [m] to the obstacles and between the checked links (``inf`` with no pair to
        check; 0 where not found).
    link, against : numpy.ndarray of str (object), shape (..., count)
        The body link and the obstacle (or other link) that have that least distance ("" where not found).
    candidates : numpy.ndarray of int, shape (...)
        How many distinct certified solutions the solver found, clear or not.
    blocked : numpy.ndarray of int, shape (...)
        How many of those do not keep the margin.
    blocked_clearance : numpy.ndarray, shape (...)
        The largest clearance of a blocked candidate [m] (``-inf`` where none is blocked), with its pair in
        ``blocked_link`` and ``blocked_against``: how near the best refused solution came.
    blocked_link, blocked_against : numpy.ndarray of str (object), shape (...)
    asked : numpy.ndarray of int, shape (...)
        How many candidates the solver was asked for each pose in the last round that asked it.
    solver : NumericalSolutions
        The solver's result of each pose's last round (its ``closest``, ``error``, ``starts`` and ``reach``: a pose
        out of reach is not searched), its candidates padded to the most asked of a pose.
    """

    q: np.ndarray
    found: np.ndarray
    clearance: np.ndarray
    link: np.ndarray
    against: np.ndarray
    candidates: np.ndarray
    blocked: np.ndarray
    blocked_clearance: np.ndarray
    blocked_link: np.ndarray
    blocked_against: np.ndarray
    asked: np.ndarray
    solver: NumericalSolutions


def collision_free_ik(
    chain: SerialChain,
    body: Body,
    scene: Scene,
    pose: ArrayLike,
    *,
    q0: ArrayLike | None = None,
    count: int = 1,
    candidates: int | None = None,
    tolerance: float | tuple[float, float] = TOLERANCE,
    restarts: int = RESTARTS,
    separation: float = SEPARATION,
    rng: int | np.random.Generator | None = None,
) -> FreeSolutions:
    """Certified solutions of target poses within the limits whose body keeps the scene's margin (module docstring).

    Parameters
    ----------
    chain : SerialChain
        Any chain of revolute joints.
    body : Body
        The arm's body on the chain's frames (:func:`redkin.collision.body_of`, :func:`redkin.collision.read_body`).
    scene : Scene
        The obstacles and the margin to keep (:func:`redkin.collision.read_scene`).
    pose : array_like, shape (..., 4, 4)
        Target poses of the tool in the base frame.
    q0 : array_like, shape (..., n), optional
        Seeds, as :func:`redkin.numerical.ik` takes them: the clear solution nearest the seed comes first.
    count : int
        Collision-free solutions wanted per pose (distinct by ``separation``).
    candidates : int, optional
        Solutions asked of the solver in the first round (default and at least ``count``; at most 1000).
    tolerance, restarts, separation, rng
        As :func:`redkin.numerical.ik` takes them; ``restarts`` is the budget of starts of each round.

    Returns
    -------
    FreeSolutions

    Raises
    ------
    ValueError
        For what :func:`redkin.numerical.ik` refuses, ``count`` or ``candidates`` not a whole number from 1 to
        1000, or a body on frames the chain does not have.
    """
    count = check_count(count, "count", 1, _MAX_CANDIDATES)
    first = max(count, check_count(count if candidates is None else candidates, "candidates", 1, _MAX_CANDIDATES))
    source = copy.deepcopy(rng) if isinstance(rng, np.random.Generator) else rng  # the streams the first round draws
    solver = ik(chain, pose, q0=q0, count=first, tolerance=tolerance, restarts=restarts, separation=separation,
                rng=rng)
    assert solver.reach is not None  # the solver always measures the poses' reach
    shape = solver.found.shape[:-1]
    size = int(np.prod(shape, dtype=np.int64))
    poses = np.broadcast_to(np.asarray(pose, dtype=float), shape + (4, 4)).reshape(size, 4, 4)
    seeds = None if q0 is None else np.broadcast_to(np.asarray(q0, dtype=float), shape + (chain.n,)).reshape(size, -1)
    streams = start_streams(source, size)
    rounds = _Rounds(chain.n, size, solver)
    todo, asked = np.arange(size), first
    while True:
        measured = clearance(chain, body, scene, solver.q)
        found = solver.found.reshape(-1, asked)
        clear = found & (measured.distance.reshape(-1, asked) >= scene.margin)
        rounds.record(todo, solver, measured, clear)
        done = (clear.sum(axis=1) >= count) | (found.sum(axis=1) < asked) | rounds.out[todo]
        todo = todo[~done]
        if not len(todo) or asked == _MAX_CANDIDATES:
            break
        asked = min(4 * asked, _MAX_CANDIDATES)
        solver = ik(chain, poses[todo], q0=None if seeds is None else seeds[todo], count=asked, tolerance=tolerance,
                    restarts=restarts, separation=separation, rng=streams[todo])
    merged, measured, clear = rounds.merged(shape)
    return _kept(chain.n, merged, measured, clear, count, shape, rounds.asked.reshape(shape))


class _Rounds:
    """Each pose's candidates from the last round that asked it (:func:`collision_free_ik`), padded to the most asked
    of any pose, and its solver's other answers from that round."""

    def __init__(self, n: int, size: int, first: NumericalSolutions) -> None:
        assert first.reach is not None
        self.reach, self.out = first.reach, np.asarray(first.reach.out).reshape(-1)
        self.asked = np.zeros(size, dtype=np.int64)
        self.parts: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Clearance]] = []
        self.closest, self.error = np.zeros((size, n)), np.zeros((size, 2))
        self.starts = np.zeros(size, dtype=np.int64)

    def record(self, which: np.ndarray, solver: NumericalSolutions, measured: Clearance, clear: np.ndarray) -> None:
        """The round's answers for the poses ``which``."""
        asked = clear.shape[1]
        self.asked[which] = asked
        self.closest[which] = solver.closest.reshape(len(which), -1)
        self.error[which] = solver.error.reshape(len(which), 2)
        self.starts[which] = np.reshape(solver.starts, -1)
        self.parts.append((which, solver.q.reshape(len(which), asked, -1), solver.found.reshape(len(which), asked),
                           clear, Clearance(*(np.reshape(part, (len(which), asked)) for part in measured))))

    def merged(self, shape: tuple[int, ...]) -> tuple[NumericalSolutions, Clearance, np.ndarray]:
        """One solver result of every pose's last round, its candidates' clearances and which are clear, padded
        (``found`` and ``clear`` false) to the most candidates asked of a pose."""
        size, width, n = len(self.asked), int(self.asked.max()), self.closest.shape[1]
        q, found, clear = np.zeros((size, width, n)), np.zeros((size, width), dtype=bool), np.zeros((size, width),
                                                                                                       dtype=bool)
        distance = np.full((size, width), np.inf)
        link, against = np.full((size, width), "", dtype=object), np.full((size, width), "", dtype=object)
        for which, part_q, part_found, part_clear, measured in self.parts:  # later rounds, wider, overwrite
            asked = part_q.shape[1]
            q[which, :asked], found[which, :asked], clear[which, :asked] = part_q, part_found, part_clear
            distance[which, :asked], link[which, :asked], against[which, :asked] = measured
        solver = NumericalSolutions(q.reshape(shape + (width, n)), found.reshape(shape + (width,)),
                                    self.closest.reshape(shape + (n,)), self.error.reshape(shape + (2,)),
                                    self.starts.reshape(shape), reach=self.reach)
        return solver, Clearance(distance, link, against), clear


def _kept(n: int, solver: NumericalSolutions, measured: Clearance, clear: np.ndarray, count: int,
          shape: tuple[int, ...], asked: np.ndarray) -> FreeSolutions:
    """The first ``count`` clear candidates of each pose (``clear`` (P, width)) and the clearest blocked one, from the
    solver's candidates and their clearance ``measured``; ``asked`` per pose is kept in the result."""
    poses, width = clear.shape
    candidates_q = solver.q.reshape(poses, width, n)
    found_all = solver.found.reshape(poses, width)
    distances, links, others = (np.reshape(a, (poses, width)) for a in measured)
    order = np.argsort(~clear, axis=1, kind="stable")[:, :count]  # clear candidates first, in the solver's order
    rows = np.arange(poses)[:, None]
    found = clear[rows, order]
    q = np.where(found[..., None], candidates_q[rows, order], 0.0)
    distance = np.where(found, distances[rows, order], 0.0)
    link = np.where(found, links[rows, order], "")
    against = np.where(found, others[rows, order], "")
    refused = found_all & ~clear
    scores = np.where(refused, distances, -np.inf)
    best = np.argmax(scores, axis=1)
    best_distance = scores[np.arange(poses), best]
    some = np.isfinite(best_distance)
    blocked_link = np.where(some, links[np.arange(poses), best], "")
    blocked_against = np.where(some, others[np.arange(poses), best], "")
    return FreeSolutions(
        q.reshape(shape + (count, n)), found.reshape(shape + (count,)), distance.reshape(shape + (count,)),
        link.reshape(shape + (count,)).astype(object), against.reshape(shape + (count,)).astype(object),
        found_all.sum(axis=1).reshape(shape), refused.sum(axis=1).reshape(shape), best_distance.reshape(shape),
        blocked_link.reshape(shape).astype(object), blocked_against.reshape(shape).astype(object), asked, solver)
