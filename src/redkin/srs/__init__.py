"""Arm-angle inverse kinematics of 7-DOF S-R-S arms with joint limits (paper 000, Shimizu et al.).

* :func:`ik`, :func:`ik_all_branches` -- joint values for a pose and an arm angle [000 eqs. 4-19]
* :func:`arm_angle_of` -- arm angle and branch of joint values
* :func:`reachable` -- which poses of a batch the wrist can reach (filter before the others)
* :func:`feasible_arm_angles` -- per-joint and overall feasible arm angles of one pose, closed form
  [000 eqs. 20-22, 29-30]; :func:`feasible_arm_angles_batch` for a batch (an object array of them)
* :func:`feasible_pieces`, :func:`feasible_pieces_all_branches` -- the same as arrays, one branch or all eight
* :func:`joint_extrema` -- type, case, extrema and monotonicity of each joint over psi [000 eqs. 21-28]
* :func:`singular_arm_angles` -- shoulder and wrist singular arm angles [000 eqs. 31-34]
* :func:`nearly_srs`, :func:`feasible_arm_angles_nearly` (:func:`feasible_arm_angles_nearly_all` for every branch
  at once), :func:`singular_arm_angles_nearly`, :func:`optimal_arm_angles_nearly` -- nearly S-R-S arms (the Kinova
  Gen3): the exact neighbour, feasible (certified), singular and optimal arm angles on the real arm
* :func:`neighbour_distance` -- how far a nearly S-R-S arm's solution lies from its neighbour's: a bound from the
  offsets and the derivatives
* :func:`self_motion`, :func:`self_motions`, :func:`branch_solutions` -- a nearly S-R-S arm's certified self-motion
  at a pose (one curve, or every curve), and every solution of a branch at an arm angle on it (two where the arm
  angle turns back along the self-motion)
* :func:`optimal_arm_angles` -- joint-limit-avoiding arm angles [000 eqs. 36-40]
* :func:`arm_angle_path` -- arm-angle control along a path (section 6.2.2)

Offset elbows (docs/srs.md) are served by every function above.
"""

from redkin.srs.arm_angle import ArmAngleState, arm_angle_of
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.extrema import JointExtrema, Stationary, joint_extrema
from redkin.srs.feasible import (
    FeasibleArmAngles,
    FeasiblePieces,
    feasible_arm_angles,
    feasible_arm_angles_batch,
    feasible_pieces,
    feasible_pieces_all_branches,
)
from redkin.srs.geometry import SRSGeometry, pose_from, srs_geometry
from redkin.srs.ik import ik, ik_all_branches, reachable
from redkin.srs.nearly import NearlySolutions, NearlySRS, nearly_srs
from redkin.srs.nearly.bound import NeighbourDistance, neighbour_distance
from redkin.srs.nearly.feasible import NearlyFeasible, feasible_arm_angles_nearly, feasible_arm_angles_nearly_all
from redkin.srs.nearly.optimal import NearlyOptimal, optimal_arm_angles_nearly
from redkin.srs.nearly.self_motion import SelfMotion, branch_solutions, self_motion, self_motions
from redkin.srs.nearly.singular import Alignment, NearlySingular, alignment_angles, singular_arm_angles_nearly
from redkin.srs.optimal import OptimalAngle, OptimalArmAngles, optimal_arm_angles
from redkin.srs.path import ArmAnglePath, arm_angle_path
from redkin.srs.singular import SINGULAR_TOLERANCE, SingularArmAngles, singular_arm_angles

__all__ = [
    "Alignment",
    "ArmAnglePath",
    "ArmAngleState",
    "BRANCHES",
    "Branch",
    "FeasibleArmAngles",
    "FeasiblePieces",
    "JointExtrema",
    "NearlyFeasible",
    "NearlyOptimal",
    "NearlySRS",
    "NearlySingular",
    "NearlySolutions",
    "NeighbourDistance",
    "OptimalAngle",
    "OptimalArmAngles",
    "SINGULAR_TOLERANCE",
    "SRSGeometry",
    "SelfMotion",
    "SingularArmAngles",
    "Stationary",
    "alignment_angles",
    "arm_angle_of",
    "arm_angle_path",
    "branch_solutions",
    "feasible_arm_angles",
    "feasible_arm_angles_batch",
    "feasible_arm_angles_nearly",
    "feasible_arm_angles_nearly_all",
    "feasible_pieces",
    "feasible_pieces_all_branches",
    "ik",
    "ik_all_branches",
    "joint_extrema",
    "nearly_srs",
    "neighbour_distance",
    "optimal_arm_angles",
    "optimal_arm_angles_nearly",
    "parse_branch",
    "pose_from",
    "reachable",
    "self_motion",
    "self_motions",
    "singular_arm_angles",
    "singular_arm_angles_nearly",
    "srs_geometry",
]
