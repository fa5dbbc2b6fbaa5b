"""Every number the explorer page shows, from the public functions of the arm's class.

:func:`explorer_data` classifies the chain once (:func:`redkin.closed_form.redundancy_parameter`) and fills
the page's one form (:mod:`redkin.explore.curves`) over the class's redundancy parameter: the arm angle psi of
S-R-S and offset-elbow arms (:mod:`redkin.explore.arm_angle`) and of nearly S-R-S arms, on the real arm
(:mod:`redkin.explore.nearly`), q7 of the Franka class (:mod:`redkin.explore.q7`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.chain import SerialChain
from redkin.closed_form import redundancy_parameter
from redkin.errors import RedkinError
from redkin.explore.arm_angle import arm_angle_curves
from redkin.explore.curves import ExplorerData
from redkin.explore.q7 import q7_curves
from redkin.srs import BRANCHES, parse_branch

#: Values of the dense grid over the parameter's domain before the special ones are merged in (0.5 deg apart over
#: a full turn).
GRID_SAMPLES = 721
#: Stated limits of ``samples``.
MIN_SAMPLES, MAX_SAMPLES = 16, 20_000


def explorer_data(
    chain: SerialChain,
    pose: ArrayLike,
    branch: str = "+++",
    target: ArrayLike | None = None,
    weights: ArrayLike | None = None,
    samples: int = GRID_SAMPLES,
    srs_tolerance: float | None = None,
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
    branch : str
        The branch shown first (three signs, e.g. ``"+-+"``).
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
        neighbour (:func:`redkin.srs.arm_angle_class`; default :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).

    Returns
    -------
    ExplorerData

    Raises
    ------
    ValueError
        For an arm without closed-form IK (within ``srs_tolerance`` of an S-R-S neighbour), a malformed or
        unreachable pose, a malformed branch, target or weights (or weights for q7), ``samples`` out of range or a
        tolerance that is not a finite number > 0.
    """
    if (isinstance(samples, bool) or not isinstance(samples, (int, np.integer))
            or not MIN_SAMPLES <= samples <= MAX_SAMPLES):
        raise RedkinError(f"samples must be an integer from {MIN_SAMPLES} to {MAX_SAMPLES}, got {samples!r}")
    first = parse_branch(branch)
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one 4x4 pose, got shape {pose.shape}")
    from redkin.srs.arm_class import NEARLY_SRS, arm_angle_class, check_tolerance
    from redkin.srs.nearly import TOLERANCE_DEFAULT

    tolerance = TOLERANCE_DEFAULT if srs_tolerance is None else check_tolerance(srs_tolerance)
    remarks: tuple[str, ...] = ()
    if arm_angle_class(chain, tolerance).kind == NEARLY_SRS:
        from redkin.explore.nearly import nearly_curves, remarks_of
        from redkin.srs import nearly_srs

        parameter, branches = nearly_curves(chain, pose, int(samples), target, weights, tolerance)
        remarks = remarks_of(nearly_srs(chain, tolerance))
    else:
        curves = q7_curves if redundancy_parameter(chain, tolerance) == "q7" else arm_angle_curves
        parameter, branches = curves(chain, pose, int(samples), target, weights)
    return ExplorerData(
        robot=chain.name,
        joint_names=tuple(chain.joint_names),
        pose=pose,
        lower=np.asarray(chain.lower, dtype=float),
        upper=np.asarray(chain.upper, dtype=float),
        parameter=parameter,
        branches=branches,
        initial=BRANCHES.index(first),
        remarks=remarks,
    )
