"""Collision-free numerical IK on any chain (issue 40): certified solutions of a pose that keep a scene's margin.

The numerical solver's search ([N1]-[N5], :func:`redkin.numerical.ik`: the seed, then random starts, each descent
certified by our FK and kept where distinct) runs with the clearance measured in its kernel
(:mod:`redkin.collision._free_ik_kernels`): each new certified solution's least distance over the checked pairs (every
body capsule against every obstacle and the body's self pairs, exact distances between capsules and shapes,
:func:`redkin.collision.clearance`'s), and the search of a pose stops once ``count`` of its candidates keep the
margin.  A candidate that collides is walked along its self-motion before the next random start: up to ``walk``
steps (default 3), each from the last candidate along the gradient of its closest pair's distance
projected on the null space of the tool's Jacobian, sized to lift that pair to the margin plus 5 cm to first order
(at most 1 rad in a joint, within the limits), and certified by the solver's own descent; the walk ends at a clear
candidate, at one the descent does not certify or that is not distinct, or where a limit blocks the self-motion.
Each step counts as one of the solver's starts.  With ``walk=0`` a pose's candidates are the solver's own, in its
order (with a seed, nearest the seed first): the first ``candidates`` of ``redkin.numerical.ik(...,
count=candidates)`` from the same stream.  The first round examines up to ``candidates`` of each pose (default
``max(count, 16)``); a pose that found that many with too few clear is searched again for four times as many (from
its own starts: the same candidates first), until enough are clear, the solver runs out of starts (its ``restarts``
budget, per round) or 1000 are examined.  In a batch only the poses still short of clear solutions go on to the next
round, together; pose ``i`` always starts from the solver's stream ``i``, as in :func:`redkin.numerical.ik`
(:func:`redkin.numerical.solve.start_streams`).

What is certified: each returned solution reaches the pose within the tolerance (the solver's certificate) and is
clear by the margin (its clearance, computed at that configuration).  What is not: that a pose with no clear
solution found has none; the result says how many candidates were found and how many collide, and the clearest
of those that collide.  On S-R-S and offset-elbow arms, :func:`redkin.collision.collision_free_arm_angles` gives the
exact collision-free sets instead.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import run_batch
from redkin._validation import check_count
from redkin.chain import SerialChain
from redkin.collision import _free_ik_kernels
from redkin.collision.body import Body
from redkin.collision.clearance import (
    Clearance,
    ClearanceInputs,
    check_frames,
    checked_pairs,
    clearance_inputs,
    named_clearance,
)
from redkin.collision.scene import Scene
from redkin.numerical.solve import RESTARTS, SEPARATION, TOLERANCE, Batch, NumericalSolutions, Outputs, batch

#: Most candidates examined per pose (the solver's own limit of distinct solutions).
_MAX_CANDIDATES = 1000
#: Candidates examined per pose in the first round, unless more are wanted.
_FIRST_CANDIDATES = 16
#: Steps along a colliding candidate's self-motion before the next random start (module docstring): on the Sawyer in
#: a dense cell (benchmarks/collision_free_ik.py) 3 cut the search's time by about a sixth; more steps rarely clear.
_WALK = 3
#: Most steps of a walk a caller may ask.
_MAX_WALK = 100


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
        How many distinct certified solutions the solver found and measured, clear or not (the search of a pose stops
        once ``count`` are clear).
    blocked : numpy.ndarray of int, shape (...)
        How many of those do not keep the margin.
    blocked_clearance : numpy.ndarray, shape (...)
        The largest clearance of a blocked candidate [m] (``-inf`` where none is blocked), with its pair in
        ``blocked_link`` and ``blocked_against``: how near the best refused solution came.
    blocked_link, blocked_against : numpy.ndarray of str (object), shape (...)
    asked : numpy.ndarray of int, shape (...)
        The most candidates the last round that searched a pose could examine.
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
    walk: int = _WALK,
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
        The most candidates examined per pose in the first round (default 16; at least ``count``, at most 1000).
    tolerance, restarts, separation, rng
        As :func:`redkin.numerical.ik` takes them; ``restarts`` is the budget of starts of each round.
    walk : int
        Steps along a colliding candidate's self-motion before the next random start (module docstring; 0 to 100):
        0 examines the solver's own candidates, in its order.

    Returns
    -------
    FreeSolutions

    Raises
    ------
    ValueError
        For what :func:`redkin.numerical.ik` refuses, ``count`` or ``candidates`` not a whole number from 1 to
        1000, ``walk`` not one from 0 to 100, or a body on frames the chain does not have.
    """
    count = check_count(count, "count", 1, _MAX_CANDIDATES)
    first = max(count, check_count(_FIRST_CANDIDATES if candidates is None else candidates, "candidates", 1,
                                   _MAX_CANDIDATES))
    walk = check_count(walk, "walk", 0, _MAX_WALK)
    check_frames(chain, body)
    pairs = checked_pairs(body, scene)
    inputs = clearance_inputs(body, scene, pairs)
    every = batch(chain, pose, q0, first, tolerance, restarts, separation, rng)
    shape, size = every.shape, every.size
    todo, asked, rounds = np.arange(size), first, None
    while True:
        part = every if rounds is None else every._replace(shape=(len(todo),), asked=asked, poses=every.poses[todo],
                                                              seeds=every.seeds[todo], streams=every.streams[todo])
        solver, (distance, closest) = _search(chain, part, inputs, float(scene.margin), count, walk)
        measured = named_clearance(distance, closest, pairs)
        if rounds is None:
            rounds = _Rounds(chain.n, size, solver)
        found = solver.found.reshape(-1, asked)
        clear = found & (measured.distance.reshape(-1, asked) >= scene.margin)
        rounds.record(todo, solver, measured, clear)
        done = (clear.sum(axis=1) >= count) | (found.sum(axis=1) < asked) | rounds.out[todo]
        todo = todo[~done]
        if not len(todo) or asked == _MAX_CANDIDATES:
            break
        asked = min(4 * asked, _MAX_CANDIDATES)
    merged, measured, clear = rounds.merged(shape)
    return _kept(chain.n, merged, measured, clear, count, shape, rounds.asked.reshape(shape))


def _search(chain: SerialChain, part: Batch, inputs: ClearanceInputs, margin: float, want: int,
            walk: int) -> tuple[NumericalSolutions, tuple[np.ndarray, np.ndarray]]:
    """The solver's search of the poses of ``part``, each stopped once ``want`` candidates keep ``margin``, a
    colliding candidate walked ``walk`` steps (:func:`redkin.collision._free_ik_kernels.solve`): its solutions, and
    each candidate's least distance and the index of its closest pair (``inf`` and -1 where none was found)."""
    out = Outputs.of(part, chain.n)
    distance = np.full((part.size, part.asked), np.inf)
    closest = np.full((part.size, part.asked), -1, dtype=np.int64)
    with np.errstate(over="ignore"):  # SplitMix64 wraps by design (as in redkin.numerical.ik)
        failed = run_batch(_free_ik_kernels.solve, part.size, *part.inputs(chain), *inputs.body, inputs.obstacles,
                           *inputs.pairs, margin, want, walk, *out, distance, closest)
    return part.solutions(failed, out), (distance, closest)


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
