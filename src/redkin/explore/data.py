"""Every number the explorer page shows, from what the arm answers about one pose.

:func:`explorer_data` takes the chain as an arm (:func:`redkin.arms.arm`, classified once), asks it what the
pose's redundancy holds (:meth:`redkin.arms.Arm.analyse`) and fills the page's one form
(:mod:`redkin.explore.curves`) branch by branch over the arm's redundancy parameter (:mod:`redkin.explore.grid`):
the arm angle psi of S-R-S, offset-elbow and nearly S-R-S arms (on the real arm), q7 of the Franka class.  It never
asks which class the arm is.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.chain import SerialChain
from redkin.errors import RedkinError, UnreachablePoseError
from redkin.explore.curves import BranchCurves, ExplorerData
from redkin.so3 import matrix_to_axis_angle
from redkin.srs import BRANCHES, parse_branch

if TYPE_CHECKING:  # a cell's types: the collision package is read where one is given
    from redkin.collision.body import Body
    from redkin.collision.scene import Scene

#: Values of the dense grid over the parameter's domain before the special ones are merged in (0.5 deg apart over
#: a full turn).
GRID_SAMPLES = 721
#: Stated limits of ``samples``.
MIN_SAMPLES, MAX_SAMPLES = 16, 20_000


#: The largest pose error [m, rad] of a configuration ``q`` said to be at the explored pose.
_REACHES = 1e-6


def explorer_data(
    chain: SerialChain,
    pose: ArrayLike,
    branch: str | None = None,
    target: ArrayLike | None = None,
    weights: ArrayLike | None = None,
    samples: int = GRID_SAMPLES,
    srs_tolerance: float | None = None,
    q: ArrayLike | None = None,
    body: Body | None = None,
    scene: Scene | None = None,
) -> ExplorerData:
    """The numbers of an explorer page for ``chain`` at ``pose``, all eight branches over its redundancy parameter.

    Parameters
    ----------
    chain : SerialChain
        An arm with closed-form IK over a redundancy parameter: an S-R-S, offset-elbow or nearly S-R-S arm (the
        arm angle psi, :mod:`redkin.srs`; a nearly S-R-S arm's numbers on the real arm, its neighbour and model
        error in ``remarks``) or a Franka-class arm (q7, :mod:`redkin.franka`), in any description.
    pose : array_like, shape (4, 4)
        The tool pose in the base frame.
    branch : str, optional
        The branch shown first (three signs, e.g. ``"+-+"``), at its optimal value within the limits (or its
        unclamped optimum).  Default: the branch of ``q``, else the branch with a feasible set whose clamped optimum
        keeps every joint farthest from its limits (the largest smallest distance, radians), else the first branch
        with a solution.
    target : array_like, shape (7,), optional
        Joint values the optimal parameter value stays nearest to (default: the middle of each range), as
        :func:`redkin.srs.optimal_arm_angles` or :func:`redkin.franka.optimal_q7` takes them.
    weights : array_like, shape (2,), optional
        The shoulder and wrist weights of the optimal arm angle [000 eq. 40] (default 0.5, 0.5); arm-angle
        classes only.
    samples : int
        Points of the dense grid over the parameter's domain (``[-pi, pi]`` for psi, joint 7's range for q7),
        from 16 to 20000.
    srs_tolerance : float, optional
        The largest departure (metres, radians off perpendicular) of an arm drawn as nearly S-R-S through its exact
        neighbour (:func:`redkin.arms.classify.arm_angle_class`; default :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).
    q : array_like, shape (7,), optional
        A configuration at ``pose`` (within :data:`_REACHES`) to open the page at: its branch, at its own value of
        the parameter (merged into the grid).
    body, scene : Body and Scene, optional
        A cell (every class above): the page draws the obstacles and the body, shades the
        values of the parameter the obstacles remove by cause, and says at each value how far the body is from them
        (:func:`redkin.explore.cell.cell_view`).

    Returns
    -------
    ExplorerData
        With ``opening``, a sentence saying where the page opens and why.

    Raises
    ------
    ValueError
        For an arm without closed-form IK (within ``srs_tolerance`` of an S-R-S neighbour), a malformed or
        unreachable pose, a malformed branch, target or weights (or weights for q7), ``samples`` out of range, a
        tolerance that is not a finite number > 0, a ``q`` that is malformed, not at ``pose`` or on another
        branch than ``branch``, a body without a scene (or the reverse), or a cell on an arm of another class.
    """
    if (isinstance(samples, bool) or not isinstance(samples, (int, np.integer))
            or not MIN_SAMPLES <= samples <= MAX_SAMPLES):
        raise RedkinError(f"samples must be an integer from {MIN_SAMPLES} to {MAX_SAMPLES}, got {samples!r}")
    first = None if branch is None else parse_branch(branch)
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one 4x4 pose, got shape {pose.shape}")
    from redkin.arms import arm
    from redkin.errors import NotArmAngleClassError
    from redkin.explore.grid import branch_curves

    classified = arm(chain, srs_tolerance=srs_tolerance)
    if classified.parameter is None:
        raise NotArmAngleClassError(f"{chain.name!r} has no closed-form IK: {classified.reason}", chain.name)
    own = None if q is None else _own_place(classified, pose, q)
    if own is not None and first is not None and own[0] != BRANCHES.index(first):
        raise RedkinError(f"q is on branch {BRANCHES[own[0]]}, not on the branch {first} asked for: give one of them")
    analysis = classified.analyse(pose, target=target, weights=weights)
    parameter = analysis.parameter
    low, high = parameter.domain
    grid = np.union1d(np.linspace(low, high, int(samples)), [value for value in (own[1:] if own else ())
                                                             if low <= value <= high])
    branches = tuple(branch_curves(classified, pose, analysis, branch, grid) for branch in analysis.branches)
    if not any(curves.exists.any() for curves in branches):
        raise UnreachablePoseError(f"{chain.name} cannot reach this pose: no branch has a {analysis.solution} at any "
                                   f"of {samples} {parameter.plural}")
    kinds = ("feasible", "singular", "optimal") if any(b.singular is not None for b in analysis.branches) else (
        "feasible", "optimal")
    if own is not None:
        initial = own[0]
        shown = branches[initial]
        place = int(np.argmin(np.abs(shown.values - own[1])))
        branches = branches[:initial] + (replace(shown, start=place),) + branches[initial + 1:]
        opening = f"Opened at the given configuration: branch {shown.branch}, at its own {parameter.symbol}."
    elif first is not None:
        initial = BRANCHES.index(first)
        opening = f"Opened on branch {first}, as asked, at its optimal {parameter.symbol}."
    else:
        initial, opening = _best_branch(branches, chain, parameter)
    if (body is None) != (scene is None):
        raise RedkinError("a cell needs both the arm's body and the scene")
    cell = None
    if body is not None and scene is not None:
        from redkin.explore.cell import cell_view, clearest

        cell = cell_view(classified, pose, body, scene, branches)
        if own is None and first is None:  # the default opening: where the arm keeps farthest from the obstacles
            initial, place, opening = clearest(cell, branches, parameter, initial, opening)
            branches = branches[:initial] + (replace(branches[initial], start=place),) + branches[initial + 1:]
    return ExplorerData(
        robot=chain.name,
        joint_names=tuple(chain.joint_names),
        pose=pose,
        lower=np.asarray(chain.lower, dtype=float),
        upper=np.asarray(chain.upper, dtype=float),
        parameter=parameter,
        method=analysis.method,
        kinds=kinds,
        branches=branches,
        initial=initial,
        remarks=analysis.remarks,
        opening=opening,
        cell=cell,
    )


def _own_place(classified, pose: np.ndarray, q: ArrayLike) -> tuple[int, float]:
    """The branch (index into :data:`BRANCHES`) and parameter value of a configuration ``q`` at ``pose``."""
    chain = classified.chain
    q = np.asarray(q, dtype=float)
    if q.shape != (chain.n,) or not np.all(np.isfinite(q)):
        raise RedkinError(f"q must be {chain.n} finite joint values, got shape {q.shape}"
                          + ("" if q.shape != (chain.n,) else " with a non-finite value"))
    reached = chain.fk(q)
    position = float(np.linalg.norm(reached[:3, 3] - pose[:3, 3]))
    rotation = float(matrix_to_axis_angle(reached[:3, :3].T @ pose[:3, :3])[1])
    if max(position, rotation) > _REACHES:
        raise RedkinError(f"q is not at the pose: its tool is {position:.3g} m and {rotation:.3g} rad away "
                          f"(at most {_REACHES:g} allowed)")
    return classified.branches.index(str(classified.branch_of(q))), float(classified.parameter_of(q))


def _best_branch(branches: tuple[BranchCurves, ...], chain: SerialChain, parameter) -> tuple[int, str]:
    """The branch the page opens on without a branch or configuration asked for, and the sentence saying why:
    among branches with a feasible set, the one whose configuration at its start (the clamped optimum) is farthest
    from its limits; else the first branch with a solution."""
    clearance = np.full(len(branches), -np.inf)
    for k, curves in enumerate(branches):
        if len(curves.arcs) and curves.exists[curves.start]:
            q = curves.q[curves.start]
            clearance[k] = float(np.min(np.minimum(q - chain.lower, chain.upper - q)))
    feasible = int(np.count_nonzero(np.isfinite(clearance)))
    if feasible:
        best = int(np.argmax(clearance))
        among = ("the only branch with a feasible set" if feasible == 1 else
                 f"of the {feasible} branches with a feasible set, its joints are farthest from their limits there")
        return best, (f"Opened on branch {branches[best].branch} at its optimal {parameter.symbol} within the limits: "
                      f"{among}.")
    best = next((k for k, curves in enumerate(branches) if curves.exists.any()), 0)
    return best, (f"No branch has a feasible set at this pose: opened on branch {branches[best].branch}, the "
                  f"first with a solution, at its optimal {parameter.symbol}.")
