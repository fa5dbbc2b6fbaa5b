"""The certified collision-free sets of an arm's redundancy parameter, whichever class the arm is (issue 40, items 4
and 5): the one door through which the path search, the explorer and the command line take them.

* S-R-S and offset-elbow arms: the arm angles of :func:`redkin.collision.arm_angle_free.free_arm_angles_of`;
* nearly S-R-S arms: the arm angles of :func:`redkin.collision.nearly_free.free_nearly_of`, read off the pose's
  certified self-motion;
* the Franka class: the values of q7 of :func:`redkin.collision.q7_free.free_q7_of`.

All return :class:`redkin.collision.FreeArmAngles` (its ``parameter`` says which), so what uses the sets is
written once; :func:`free_arcs_of` gives the same sets of many poses as arrays (:class:`FreeArcs`), without a Python
object per pose and branch, for the path search.  Chains solved numerically have no redundancy parameter, so no such
sets, and are refused in words.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.classify import FRANKA, NEARLY_SRS, OFFSET_ELBOW, SRS
from redkin.arms.feasible_sets import ArcArrays
from redkin.arms.front_door import Arm
from redkin.collision.arm_angle_free import (
    FreeArmAngles,
    certified_arm_angles,
    free_arm_angles_of,
    moved_pairs,
    one_pose,
)
from redkin.collision.body import Body
from redkin.collision.clearance import checked_pairs
from redkin.collision.nearly_free import free_nearly_of
from redkin.collision.q7_free import certified_q7, free_q7_of
from redkin.collision.scene import Scene
from redkin.errors import RedkinError

Branches = str | tuple[str, ...] | list[str] | None


def free_sets_of(arm: Arm, poses: ArrayLike, body: Body, scene: Scene, branches: Branches = None, *,
                 resolution: float = 1e-6, budget: int = 100_000, causes: bool = True) -> list[FreeArmAngles]:
    """The certified collision-free sets of each pose of ``poses`` ``(P, 4, 4)`` on each branch (or ``branches``),
    over the arm's redundancy parameter: :func:`redkin.collision.free_arm_angles_of` or
    :func:`redkin.collision.free_q7_of` or :func:`redkin.collision.nearly_free.free_nearly_of` as the arm's class has
    it (same arguments; without ``causes`` the removed stretches are not named: ``blocked`` is empty).

    Raises
    ------
    RedkinError
        For an arm of a class without certified sets (named), and whatever the class's function refuses.
    """
    if arm.kind == FRANKA:
        return free_q7_of(arm, poses, body, scene, branches, resolution=resolution, budget=budget, causes=causes)
    if arm.kind in (SRS, OFFSET_ELBOW):
        return free_arm_angles_of(arm, poses, body, scene, branches, resolution=resolution, budget=budget,
                                  causes=causes)
    if arm.kind == NEARLY_SRS:
        return free_nearly_of(arm, poses, body, scene, branches, resolution=resolution, budget=budget, causes=causes)
    raise RedkinError(f"certified collision-free sets are computed over a redundancy parameter (S-R-S, offset-elbow, "
                      f"nearly S-R-S and Franka-class arms); {arm.chain.name} is {arm.kind}, solved numerically")


class FreeArcs(NamedTuple):
    """The certified collision-free sets of many poses on every branch of the arm, as arrays.

    Attributes
    ----------
    arcs : redkin.arms.feasible_sets.ArcArrays
        The free arcs, each owned by ``pose * B + branch`` over the arm's ``B`` branches.
    complete : numpy.ndarray of bool, shape (P,)
        Per pose, :attr:`redkin.collision.FreeArmAngles.complete`.
    """

    arcs: ArcArrays
    complete: np.ndarray


def free_arcs_of(arm: Arm, poses: ArrayLike, body: Body, scene: Scene, *, resolution: float = 1e-6,
                 budget: int = 100_000) -> FreeArcs:
    """:func:`free_sets_of` of ``poses`` ``(P, 4, 4)`` on every branch, without causes, as arrays: the same arcs.

    Raises
    ------
    RedkinError
        As :func:`free_sets_of`.
    """
    if arm.kind in (SRS, OFFSET_ELBOW, FRANKA):
        certify = certified_q7 if arm.kind == FRANKA else certified_arm_angles
        _, certified = certify(arm, poses, body, scene, resolution=resolution, budget=budget)
        return FreeArcs(certified.free(), certified.complete)
    return free_arcs_from(free_sets_of(arm, poses, body, scene, resolution=resolution, budget=budget, causes=False))


def free_arcs_from(found: list[FreeArmAngles]) -> FreeArcs:
    """The sets of :func:`free_sets_of` on every branch, one per pose, as :class:`FreeArcs` (an arc of pose ``p`` and
    branch ``b`` owned by ``p * B + b``)."""
    every = [arcs for sets in found for arcs in sets.free]
    return FreeArcs(ArcArrays(np.concatenate([arcs.bounds.reshape(-1, 2) for arcs in every] + [np.empty((0, 2))]),
                              np.concatenate([arcs.wraps for arcs in every] + [np.empty(0, dtype=bool)]),
                              np.repeat(np.arange(len(every)), [len(arcs.bounds) for arcs in every]).astype(np.int64)),
                    np.array([sets.complete for sets in found], dtype=bool))


def collision_free_set(arm: Arm, pose: ArrayLike, body: Body, scene: Scene, branches: Branches = None, *,
                       resolution: float = 1e-6, budget: int = 100_000) -> FreeArmAngles:
    """:func:`free_sets_of` of one pose ``(4, 4)``."""
    return free_sets_of(arm, one_pose(arm, pose), body, scene, branches, resolution=resolution, budget=budget)[0]


def redundancy_moves(arm: Arm, body: Body, scene: Scene, q: ArrayLike) -> np.ndarray:
    """Per configuration ``q`` ``(N, 7)`` and checked pair of ``body`` and ``scene``
    (:func:`redkin.collision.clearance.checked_pairs`), whether the pair's distance can change with the redundancy
    parameter at the configuration's pose ``(N, P)``.

    On S-R-S and offset-elbow arms, :func:`redkin.collision.arm_angle_free.moved_pairs`.  On the other classes (the
    Franka class, nearly S-R-S arms), a pair stays put only where both shapes do: on the base (frame 0) or on the
    last link, which the pose holds (an obstacle never moves); every other pair is counted as moving, which may count
    a pair whose distance happens not to change (a capsule along axis 1), never the reverse.
    """
    if arm.kind in (SRS, OFFSET_ELBOW):
        return moved_pairs(arm, body, scene, q)
    chain = arm.chain
    count = len(chain.check_q(q).reshape(-1, chain.n))
    still = (body.frame == 0) | (body.frame >= chain.n)  # (M,)
    pairs = checked_pairs(body, scene)
    fixed = still[pairs.capsule] & ((pairs.other < 0) | still[np.maximum(pairs.other, 0)])
    return np.broadcast_to(~fixed, (count, len(fixed))).copy()
