"""Which arm-angle class a chain belongs to: S-R-S, S-R-S with an offset elbow, or a general chain.

The arm-angle functions (paper 000) serve the first two classes; a general
chain has FK, Jacobian, velocity IK and virtual arms, but no arm angle.
"""

from __future__ import annotations

from typing import NamedTuple

from redkin.chain import SerialChain
from redkin.srs.geometry import srs_geometry

#: The classes, in the words ``redkin robots`` prints.
SRS, OFFSET_ELBOW, GENERAL = "S-R-S", "S-R-S, offset elbow", "general chain"


class ArmClass(NamedTuple):
    """A chain's arm-angle class and why, in one line."""

    kind: str
    reason: str


def arm_angle_class(chain: SerialChain) -> ArmClass:
    """Whether ``chain`` has closed-form arm-angle IK, and which kind (see :data:`SRS`, :data:`OFFSET_ELBOW`,
    :data:`GENERAL`).

    The reason of a general chain is the first condition it violates, with
    its distance or angle (the message :func:`redkin.srs.srs_geometry` raises).
    """
    try:
        geometry = srs_geometry(chain)
    except ValueError as exc:
        return ArmClass(GENERAL, str(exc))
    lengths = f"d_se {geometry.d_se:.6g} m, d_ew {geometry.d_ew:.6g} m"
    if geometry.offset_elbow:
        return ArmClass(OFFSET_ELBOW, f"joints 1-3 and 5-7 meet in points, joints 3-5 do not: {lengths}, elbow offsets "
                                      f"a_3 {geometry.a3:.6g} m, a_4 {geometry.a4:.6g} m")
    return ArmClass(SRS, f"joints 1-3, 3-5 and 5-7 meet in points: {lengths}")
