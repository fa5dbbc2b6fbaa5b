"""The Franka class: closed-form IK with q7 as the redundancy parameter (docs/franka.md).

Arms whose shoulder is spherical, whose elbow is offset as on the WAM, whose
axes 5 and 6 meet and whose axis 7 is offset from axis 6 (the Franka Panda
and FR3, the UFactory xArm7) have, at a given value of joint 7, at most
eight solutions in closed form.

* :func:`franka_geometry` -- detection in any description, and the solver's form of the arm
* :func:`ik` -- every solution (or one branch's) of poses at values of q7 [F1]-[F7]
* :func:`feasible_q7` -- the exact feasible q7 set of every branch under the joint limits [F8]-[F9];
  :func:`feasible_q7_batch` for a batch of poses, :func:`feasible_q7_pieces` the same as arrays
* :func:`optimal_q7` -- the q7 that keeps the joints farthest from their limits, within the feasible set
"""

from redkin.franka.feasible import FeasibleQ7, feasible_q7, feasible_q7_batch, feasible_q7_pieces
from redkin.franka.geometry import FrankaGeometry, franka_geometry
from redkin.franka.ik import PARAMETER, Q7Solutions, ik
from redkin.franka.optimal import OptimalQ7, optimal_q7
from redkin.srs.branches import BRANCHES

__all__ = [
    "BRANCHES",
    "FeasibleQ7",
    "FrankaGeometry",
    "OptimalQ7",
    "PARAMETER",
    "Q7Solutions",
    "feasible_q7",
    "feasible_q7_batch",
    "feasible_q7_pieces",
    "franka_geometry",
    "ik",
    "optimal_q7",
]
