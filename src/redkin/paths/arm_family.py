"""Which path family answers for an arm (:func:`path_family`): the one its class was built with, read off the
:class:`redkin.arms.Arm` (:mod:`redkin.arms.registry` built it), or made from a class's converted form."""

from __future__ import annotations

from redkin.arms import Arm as ClassifiedArm
from redkin.arms import arm as classified
from redkin.chain import SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.franka.geometry import FrankaGeometry
from redkin.paths.family import ArmAngleFamily, Family, NearlyFamily, Q7Family
from redkin.srs.geometry import SRSGeometry
from redkin.srs.nearly import TOLERANCE_DEFAULT, NearlySRS


def path_family(arm: ClassifiedArm | SerialChain | SRSGeometry | FrankaGeometry | NearlySRS,
                srs_tolerance: float | None = None) -> Family:
    """The class of ``arm`` as path resolution sees it, the one :func:`redkin.arms.classify.arm_angle_class` names:
    S-R-S or offset elbow, the Franka class, or nearly S-R-S within ``srs_tolerance`` (default
    :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).

    Raises
    ------
    NotArmAngleClassError
        For a chain of none of these classes, with the reasons.
    """
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
