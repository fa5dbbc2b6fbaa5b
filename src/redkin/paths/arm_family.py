"""Which path family answers for an arm (:func:`path_family`): the one its class was built with, read off the
:class:`redkin.arms.Arm` (:mod:`redkin.arms.registry` built it), or made from a class's converted form."""

from __future__ import annotations

from typing import TYPE_CHECKING

from redkin.arms import Arm as ClassifiedArm
from redkin.arms import arm as classified
from redkin.chain import SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.franka.geometry import FrankaGeometry
from redkin.paths.collision_family import collision_free_family
from redkin.paths.family import ArmAngleFamily, Family, NearlyFamily, Q7Family
from redkin.srs.geometry import SRSGeometry
from redkin.srs.nearly import TOLERANCE_DEFAULT, NearlySRS

if TYPE_CHECKING:  # the cell's types: read where one is given
    from redkin.collision.body import Body
    from redkin.collision.scene import Scene


def path_family(arm: ClassifiedArm | SerialChain | SRSGeometry | FrankaGeometry | NearlySRS,
                srs_tolerance: float | None = None, body: Body | None = None, scene: Scene | None = None) -> Family:
    """The class of ``arm`` as path resolution sees it, the one :func:`redkin.arms.classify.arm_angle_class` names:
    S-R-S or offset elbow, the Franka class, or nearly S-R-S within ``srs_tolerance`` (default
    :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`); in the cell of the arm's ``body`` and ``scene`` where they are
    given, its pieces cut to the certified collision-free sets
    (:func:`redkin.paths.collision_family.collision_free_family`).

    Raises
    ------
    NotArmAngleClassError
        For a chain of none of these classes, with the reasons.
    RedkinError
        For a body without a scene, or a scene without a body.
    """
    family = _class_family(arm, srs_tolerance)
    if scene is None and body is None:
        return family
    if scene is None or body is None:
        raise RedkinError("a cell needs both the arm's body and the scene")
    return collision_free_family(family, body, scene)


def _class_family(arm: ClassifiedArm | SerialChain | SRSGeometry | FrankaGeometry | NearlySRS,
                  srs_tolerance: float | None) -> Family:
    """:func:`path_family` without a cell."""
    if isinstance(arm, SRSGeometry):
        return ArmAngleFamily(arm)
    if isinstance(arm, FrankaGeometry):
        return Q7Family(arm)
    if isinstance(arm, NearlySRS):
        return NearlyFamily(arm, TOLERANCE_DEFAULT if srs_tolerance is None else srs_tolerance)
    if not isinstance(arm, (SerialChain, ClassifiedArm)):
        raise RedkinError(f"arm must be a SerialChain or an Arm, got {type(arm).__name__}")
    chosen = arm if isinstance(arm, ClassifiedArm) else classified(arm, srs_tolerance=srs_tolerance)
    family: Family | None = chosen.implementation.family
    if family is None:
        raise NotArmAngleClassError(f"path resolution needs an arm-angle or q7 parameterisation: {chosen.chain.name!r} "
                                    f"is a general chain ({chosen.reason})", chosen.chain.name)
    return family
