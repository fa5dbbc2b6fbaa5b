"""How far an arm's body is from a scene's obstacles and from itself, at joint values (issue 40).

The pairs checked are every capsule of the body against every obstacle, then the body's self-collision pairs
(:class:`redkin.collision.body.Body`); :func:`checked_pairs` lists them once, in that order, for every caller.
Capsules fixed in frame 0 (the base, which no joint moves) are checked against the arm's other links but not against
the obstacles: their distance from an obstacle is the same in every configuration, so it can decide nothing about
the redundancy, and where it is short of the margin (the base standing on the table, a capsule round the base
reaching below the floor) it would block every configuration.  :func:`base_contacts` says where that happens.
:func:`clearance` gives, per configuration, the least signed distance over those pairs and the pair that has it:
where it is at least the scene's margin, the configuration is collision-free.

Example
-------
>>> import numpy as np
>>> from redkin.collision import BodyCapsule, body_of, primitives, Scene
>>> from redkin.collision.clearance import clearance
>>> from redkin.models import kuka_iiwa14
>>> chain = kuka_iiwa14()
>>> body = body_of([BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.06)], chain)
>>> post = Scene(("post",), primitives.capsule([0.4, 0.3, 0], [0.4, 0.3, 1.2], 0.05)[None])
>>> result = clearance(chain, body, post, np.zeros(7))
>>> round(float(result.distance), 6), result.link.item(), result.against.item()
(0.302311, 'forearm', 'post')
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin.chain import SerialChain
from redkin.collision import _clearance_kernels
from redkin.collision.body import Body, posed
from redkin.collision.distances import trusted_distances
from redkin.collision.scene import Scene
from redkin.errors import RedkinError


class CheckedPairs(NamedTuple):
    """The pairs a body and a scene check, in order: each capsule that moves (frame > 0) against each obstacle, then
    the self pairs.

    Attributes
    ----------
    capsule : numpy.ndarray of int, shape (P,)
        The body capsule of each pair.
    obstacle : numpy.ndarray of int, shape (P,)
        The obstacle of an arm-obstacle pair, ``-1`` for a self pair.
    other : numpy.ndarray of int, shape (P,)
        The other capsule of a self pair, ``-1`` for an arm-obstacle pair.
    names : list of (str, str)
        The link and the obstacle (or the other link) of each pair.
    """

    capsule: np.ndarray
    obstacle: np.ndarray
    other: np.ndarray
    names: list[tuple[str, str]]


class Clearance(NamedTuple):
    """The least distance between the checked pairs of each configuration (:func:`clearance`).

    Attributes
    ----------
    distance : numpy.ndarray, shape (...)
        The least signed distance [m] (negative: penetrating); ``inf`` where nothing is checked.
    link, against : numpy.ndarray of str, shape (...)
        The pair that has it: a link of the body, and an obstacle or another link (``""`` where nothing is checked).
    """

    distance: np.ndarray
    link: np.ndarray
    against: np.ndarray


def checked_pairs(body: Body, scene: Scene) -> CheckedPairs:
    """The pairs of ``body`` and ``scene`` (the class docstring of :class:`CheckedPairs`)."""
    moving = np.flatnonzero(np.asarray(body.frame) > 0)
    obstacles = len(scene)
    return CheckedPairs(
        capsule=np.concatenate([np.repeat(moving, obstacles), body.pairs[:, 0]]).astype(np.int64),
        obstacle=np.concatenate([np.tile(np.arange(obstacles), len(moving)),
                                 np.full(len(body.pairs), -1)]).astype(np.int64),
        other=np.concatenate([np.full(len(moving) * obstacles, -1), body.pairs[:, 1]]).astype(np.int64),
        names=([(body.link[i], name) for i in moving.tolist() for name in scene.names]
               + [(body.link[i], body.link[j]) for i, j in body.pairs.tolist()]),
    )


def base_contacts(chain: SerialChain, body: Body, scene: Scene) -> list[tuple[str, str, float]]:
    """The base's capsules (frame 0) closer than the margin to an obstacle, which :func:`checked_pairs` does not
    check (module docstring): ``(link, obstacle, distance)`` each, nearest first."""
    base = np.flatnonzero(np.asarray(body.frame) == 0)
    if not len(base) or not len(scene):
        return []
    shapes = posed(body, chain.frames(np.zeros(chain.n)))[base]
    pairs = [(i, o) for i in range(len(base)) for o in range(len(scene))]
    apart = trusted_distances(shapes[[i for i, _ in pairs]], scene.shapes[[o for _, o in pairs]])
    found = [(body.link[base[i]], scene.names[o], float(d)) for (i, o), d in zip(pairs, apart) if d < scene.margin]
    return sorted(found, key=lambda contact: contact[2])


class ClearanceInputs(NamedTuple):
    """A body, a scene and their checked pairs as the clearance kernels take them
    (:mod:`redkin.collision._clearance_kernels`): one conversion for many calls."""

    body: tuple[np.ndarray, ...]  # frame, a, b, radius
    obstacles: np.ndarray
    pairs: tuple[np.ndarray, ...]  # capsule, obstacle, other

    @property
    def checked(self) -> int:
        """How many pairs are checked."""
        return len(self.pairs[0])


def clearance_inputs(body: Body, scene: Scene, pairs: CheckedPairs | None = None) -> ClearanceInputs:
    """``body``, ``scene`` and their checked pairs (:func:`checked_pairs` unless given) as the kernels take them."""
    pairs = checked_pairs(body, scene) if pairs is None else pairs
    arrays = (body.frame, body.a, body.b, body.radius)
    return ClearanceInputs(tuple(kernel_array(np.asarray(array)) for array in arrays), kernel_array(scene.shapes),
                           tuple(_indices(array) for array in pairs[:3]))


def pair_clearances(chain: SerialChain, inputs: ClearanceInputs, q: np.ndarray, active: np.ndarray | None = None,
                    margin: float = 0.0, floor: np.ndarray | None = None) -> np.ndarray:
    """Per configuration of ``q`` ``(N, n)`` (trusted) and checked pair of ``inputs``, its signed distance minus
    ``margin`` ``(N, P)``, in one compiled pass (:func:`redkin.collision._clearance_kernels.clearances`); with
    ``active`` ``(N, P)``, only the active pairs are measured (``inf`` for the others, and a configuration without
    one is not posed); with ``floor`` ``(N, P)`` (>= 0), a pair whose cheap lower bound minus the margin exceeds its
    floor gets that bound instead of its distance (a pair that a bound proves clear by more than the floor)."""
    q = kernel_array(np.asarray(q, dtype=float))
    shape = (len(q), inputs.checked)
    active = np.ones(shape, dtype=bool) if active is None else kernel_array(active)
    floor = np.full(shape, np.inf) if floor is None else kernel_array(np.asarray(floor, dtype=float), shape)
    out = np.empty(shape)
    if len(q):
        run_batch(_clearance_kernels.clearances, len(q), q, chain._links, chain._ends, chain._standard, *inputs.body,
                  inputs.obstacles, *inputs.pairs, float(margin), active, floor, out)
    return out


def _indices(values: np.ndarray) -> np.ndarray:
    """Indices as the kernels take them: C-contiguous, writeable int64 (one compiled signature)."""
    return kernel_array(np.asarray(values, dtype=np.int64))


def clearance(chain: SerialChain, body: Body, scene: Scene, q: ArrayLike) -> Clearance:
    """The least signed distance over every checked pair (each body capsule against each obstacle, and the body's
    self pairs) at joint values ``q`` ``(..., n)``, and the pair that has it, in one compiled pass
    (:func:`redkin.collision._clearance_kernels.least`: a pair whose cheap lower bound is no less than the least so
    far is not measured).

    Raises
    ------
    RedkinError
        For joint values of the wrong shape or not finite, or a body on frames the chain does not have.
    """
    q = chain.check_q(q)
    shape = q.shape[:-1]
    check_frames(chain, body)
    pairs = checked_pairs(body, scene)
    inputs = clearance_inputs(body, scene, pairs)
    rows = kernel_array(q.reshape(-1, chain.n))
    distance, closest = np.empty(len(rows)), np.empty(len(rows), dtype=np.int64)
    if len(rows):
        run_batch(_clearance_kernels.least, len(rows), rows, chain._links, chain._ends, chain._standard,
                  *inputs.body, inputs.obstacles, *inputs.pairs, distance, closest)
    return named_clearance(distance.reshape(shape), closest.reshape(shape), pairs)


def named_clearance(distance: np.ndarray, closest: np.ndarray, pairs: CheckedPairs) -> Clearance:
    """Least distances and the index of the pair of ``pairs`` that has each (-1: none checked, its names "") as a
    :class:`Clearance`."""
    names = np.array([("", ""), *pairs.names], dtype=object)[closest + 1]
    return Clearance(distance, names[..., 0], names[..., 1])


def least_pair(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row of a :func:`pair_table` ``(N, P)``, the least distance and the column of the pair that has it:
    ``inf`` and ``-1`` where no pair is checked (``P = 0``)."""
    if not table.shape[1]:
        return np.full(len(table), np.inf), np.full(len(table), -1)
    closest = np.argmin(table, axis=1)
    return table[np.arange(len(table)), closest], closest


def pair_table(chain: SerialChain, body: Body, scene: Scene, q: np.ndarray) -> tuple[np.ndarray, CheckedPairs]:
    """The signed distance of every checked pair at each configuration of ``q`` ``(N, n)`` (checked), ``(N, P)``,
    and the pairs (:func:`checked_pairs`)."""
    check_frames(chain, body)
    pairs = checked_pairs(body, scene)
    return pair_clearances(chain, clearance_inputs(body, scene, pairs), q), pairs


def check_frames(chain: SerialChain, body: Body) -> None:
    """Refuse a body on frames the chain does not have."""
    if len(body) and int(body.frame.max()) > chain.n:
        raise RedkinError(f"the body uses frame {int(body.frame.max())}, but {chain.name} has {chain.n} joints")
