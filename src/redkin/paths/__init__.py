"""The redundancy parameter chosen over a whole path of poses, inside the exact feasible sets (docs/paths.md).

* :func:`resolve_path`, :func:`resolve_paths` -- joint values along a path, as far from the limits as the path
  allows and within a bound on each joint's move per waypoint, or the first waypoint where none exist and why
* :func:`step_bound` -- the bound from a maximum step, or from joint speeds and a time step
* :class:`PathResult`, :class:`PathFailure` -- what they return
* the baselines it is measured against: :func:`fixed_psi_path` (paper 000's ``Gamma_0``),
  :func:`clamped_optimum_path` (``Gamma``), :func:`greedy_path` (seeded tracking), :func:`sampled_path`
  (dynamic programming on a uniform grid), the first three returning a :class:`BaselinePath`
"""

from redkin.paths.baselines import (
    GREEDY_SPACING,
    BaselinePath,
    clamped_optimum_path,
    fixed_psi_path,
    greedy_path,
    sampled_path,
)
from redkin.paths.bounds import step_bound
from redkin.paths.resolve import (
    DEFAULT_CONNECT,
    DEFAULT_REFINEMENTS,
    DEFAULT_SPACING,
    FK_TOLERANCE,
    resolve_path,
    resolve_paths,
)
from redkin.paths.result import REASONS, PathFailure, PathResult

__all__ = [
    "BaselinePath",
    "DEFAULT_CONNECT",
    "DEFAULT_REFINEMENTS",
    "DEFAULT_SPACING",
    "FK_TOLERANCE",
    "GREEDY_SPACING",
    "PathFailure",
    "PathResult",
    "REASONS",
    "clamped_optimum_path",
    "fixed_psi_path",
    "greedy_path",
    "resolve_path",
    "resolve_paths",
    "sampled_path",
    "step_bound",
]
