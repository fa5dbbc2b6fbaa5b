"""The redundancy parameter chosen over a whole path of poses, inside the exact feasible sets (docs/paths.md).

* :func:`resolve_path`, :func:`resolve_paths` -- joint values along a path, as far from the limits as the path
  allows and within a bound on each joint's move per waypoint, or the first waypoint where none exist and why
* :func:`step_bound` -- the bound from a maximum step, or from joint speeds and a time step
* :class:`PathResult`, :class:`PathFailure` -- what they return
* :func:`line`, :func:`through`, :func:`read_poses` -- the waypoints from what users have: a straight line (and
  slerp) between poses, key poses joined by lines, a ``.npy``, CSV or JSON file (:mod:`redkin.paths.waypoints`)
* :class:`Stop`, :data:`STOP_REASONS` -- the reconfiguration stops of ``resolve_path(..., allow_stops=True)``: the
  fewest that join continuous segments where no continuous path exists (:mod:`redkin.paths.stops`)
* :func:`time_path` -- a path's joint values timed within the joints' velocity and acceleration limits and sampled
  at a control rate (TOPP-RA, the ``timing`` extra): a :class:`Trajectory`
* the baselines it is measured against: :func:`fixed_psi_path` (paper 000's ``Gamma_0``),
  :func:`clamped_optimum_path` (``Gamma``), :func:`greedy_path` (seeded tracking), :func:`sampled_path`
  (dynamic programming on a uniform grid), the first three returning a :class:`BaselinePath`, as
  :func:`judge_path` returns it for joint values from anywhere
* :func:`feasible_along_path` -- the exact feasible pieces of every waypoint and branch (the figures' plane), in a
  cell the collision-free ones; :func:`removed_along_path` -- the stretches a cell removes, each named by its cause;
  :func:`cell_along_path` -- both from one computation of the cell's sets (:class:`InCell`)
* :func:`path_family` -- the arm's class as path resolution sees it: :class:`ArmAngleFamily` (S-R-S and
  offset-elbow arms, the arm angle psi) or :class:`Q7Family` (the Franka class, q7)
"""

from redkin.paths.arm_family import path_family
from redkin.paths.baselines import (
    BASELINE_REASONS,
    GREEDY_SPACING,
    LIMIT_SLACK,
    BaselinePath,
    clamped_optimum_path,
    fixed_psi_path,
    greedy_path,
    judge_path,
    sampled_path,
)
from redkin.paths.bounds import step_bound
from redkin.paths.family import ArmAngleFamily, Family, Q7Family
from redkin.paths.plane import InCell, Removed, cell_along_path, feasible_along_path, removed_along_path
from redkin.paths.resolve import (
    DEFAULT_CONNECT,
    DEFAULT_REFINEMENTS,
    DEFAULT_SPACING,
    FK_TOLERANCE,
    OBJECTIVES,
    OPTIMALITY_MARGIN,
    resolve_path,
    resolve_paths,
)
from redkin.paths.result import REASONS, STOP_REASONS, PathFailure, PathResult, Stop
from redkin.paths.timing import Trajectory, time_path
from redkin.paths.waypoints import (
    MAX_POSES,
    QUATERNION_TOLERANCE,
    line,
    read_poses,
    through,
    write_poses_csv,
    write_poses_json,
)

__all__ = [
    "ArmAngleFamily",
    "BASELINE_REASONS",
    "BaselinePath",
    "DEFAULT_CONNECT",
    "DEFAULT_REFINEMENTS",
    "DEFAULT_SPACING",
    "FK_TOLERANCE",
    "Family",
    "GREEDY_SPACING",
    "LIMIT_SLACK",
    "OBJECTIVES",
    "OPTIMALITY_MARGIN",
    "PathFailure",
    "PathResult",
    "Q7Family",
    "REASONS",
    "clamped_optimum_path",
    "feasible_along_path",
    "removed_along_path",
    "Removed",
    "cell_along_path",
    "InCell",
    "fixed_psi_path",
    "greedy_path",
    "judge_path",
    "path_family",
    "resolve_path",
    "resolve_paths",
    "sampled_path",
    "step_bound",
    "STOP_REASONS",
    "Stop",
    "Trajectory",
    "time_path",
    "MAX_POSES",
    "QUATERNION_TOLERANCE",
    "line",
    "read_poses",
    "through",
    "write_poses_csv",
    "write_poses_json",
]
