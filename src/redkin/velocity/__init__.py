"""Velocity IK through singularities (paper 003, Miyata, Sato, Kanemiya).

Baselines (pseudoinverse, damped least squares with constant or adaptive
damping), the cofactor building blocks of the column-augmented Jacobian, the
adjugate direction, the proposed singularity-consistent method with its
singular-region blend, singularity factorisations (closed form for the
Barrett WAM, numerical for others), and a fixed-step RK4 tracking simulation.
The steps themselves (pseudoinverse, damped least squares, the SC step) are
compiled once, in :mod:`redkin.velocity._step_kernels`, and serve single
configurations, batches and the control-loop controllers alike.
"""

from redkin.velocity.adjugate_method import adjugate_direction
from redkin.velocity.baselines import (
    adaptive_damped_least_squares,
    adaptive_damping,
    damped_least_squares,
    pseudoinverse,
)
from redkin.velocity.blend import blend_weight, rotation_factor, twist_scale
from redkin.velocity.cofactors import (
    adjugate,
    column_minors,
    fixed_joint_vectors,
    self_motion_vector,
    weighted_sum,
)
from redkin.velocity.column_augmented import algorithmic_singularity, fixed_joint_sc
from redkin.velocity.controller import PseudoinverseController, SingularityConsistentController
from redkin.velocity.factorisation import (
    ElbowSine,
    FactorCheck,
    NumericalFactorisation,
    WamFactorisation,
    check_single_parameter,
    singularity_factorisation,
    wam_cofactors,
    wam_singularity_index,
)
from redkin.velocity.methods import (
    METHOD_NAMES,
    AdaptiveDampedLeastSquares,
    DampedLeastSquares,
    Pseudoinverse,
    SingularityConsistent,
    make_method,
)
from redkin.velocity.proposed import (
    lean_singularity_consistent,
    minimum_norm_weights,
    pseudoinverse_weights,
    singularity_consistent,
    weighted_sum_direction,
)
from redkin.velocity.solution import VelocitySolution
from redkin.velocity.tracking import TrackingResult, simulate

__all__ = [
    "AdaptiveDampedLeastSquares", "DampedLeastSquares", "ElbowSine", "FactorCheck", "METHOD_NAMES",
    "NumericalFactorisation", "Pseudoinverse", "PseudoinverseController", "SingularityConsistent",
    "SingularityConsistentController", "TrackingResult", "VelocitySolution", "WamFactorisation",
    "adaptive_damped_least_squares", "adaptive_damping", "adjugate", "adjugate_direction", "algorithmic_singularity",
    "blend_weight", "check_single_parameter", "column_minors", "damped_least_squares", "fixed_joint_sc",
    "fixed_joint_vectors", "lean_singularity_consistent", "make_method", "minimum_norm_weights", "pseudoinverse",
    "pseudoinverse_weights", "rotation_factor", "self_motion_vector", "simulate", "singularity_consistent",
    "singularity_factorisation", "twist_scale", "wam_cofactors", "wam_singularity_index", "weighted_sum",
    "weighted_sum_direction",
]
