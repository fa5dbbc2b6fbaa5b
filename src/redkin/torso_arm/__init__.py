"""Thesis 001 (Hamada): the 8-DOF torso + arm of a dual-arm humanoid.

Shoulder-angle / elbow-angle inverse kinematics, wrist inverse kinematics and
wrist-position manipulability maps.  Modules:

* :mod:`~redkin.torso_arm.geometry` -- the arm, its lengths and landmark points, mirroring;
* :mod:`~redkin.torso_arm.shoulder_angle` -- psi (section 3.2, [001 eq. 3.1]);
* :mod:`~redkin.torso_arm.elbow_angle` -- phi and its reference (section 3.3);
* :mod:`~redkin.torso_arm.position_ik` -- joints 1-5 (section 3.4, repaired);
* :mod:`~redkin.torso_arm.wrist_ik` -- joints 6-8 (chapter 4, re-derived);
* :mod:`~redkin.torso_arm.ik` -- hand pose + (psi, phi) -> all 8 solutions;
* :mod:`~redkin.torso_arm.manipulability` -- w of the wrist position (chapter 5), dual-arm measure;
* :mod:`~redkin.torso_arm.maps` -- maps over planes, best over the redundancy, threshold regions.

Each equation is one compiled kernel (numba) beside the public function that
validates its input and calls it; :mod:`~redkin.torso_arm._kernel_tools` holds
what the kernels share.
"""

from redkin.torso_arm.branches import POSITION_BRANCHES, STATUS_NAMES, WRIST_BRANCHES
from redkin.torso_arm.elbow_angle import ElbowReference, elbow_angle
from redkin.torso_arm.geometry import TorsoArm, humanoid_arm
from redkin.torso_arm.ik import BRANCHES, IKSolution, ik, redundancy_parameters
from redkin.torso_arm.position_ik import PositionSolution, position_ik, position_ik_from_theta1
from redkin.torso_arm.shoulder_angle import (
    shoulder_angle,
    shoulder_angle_eq31,
    theta1_from_shoulder_angle,
    theta1_from_shoulder_angle_eq31,
)

__all__ = [
    "BRANCHES", "POSITION_BRANCHES", "WRIST_BRANCHES", "STATUS_NAMES",
    "ElbowReference", "IKSolution", "PositionSolution", "TorsoArm",
    "elbow_angle", "humanoid_arm", "ik", "position_ik", "position_ik_from_theta1",
    "redundancy_parameters", "shoulder_angle", "shoulder_angle_eq31",
    "theta1_from_shoulder_angle", "theta1_from_shoulder_angle_eq31",
]
