"""One front door to pose IK: the closed forms at a value of the chain's redundancy parameter, or the numerical solver.

The chain's class (:func:`redkin.srs.arm_angle_class`) picks the solver and
the parameter: the arm angle ``psi`` of S-R-S and offset-elbow arms
(:mod:`redkin.srs`, paper 000) and of nearly S-R-S arms (their exact
neighbour's closed form polished on the real arm, :mod:`redkin.srs.nearly`),
``q7`` of Franka-class arms (:mod:`redkin.franka`).  Giving the other parameter is an error that names
the right one, so that no arm-angle function ever reads a q7 as an arm
angle, nor the other way round.

    >>> from redkin import get_robot, ik
    >>> result = ik(get_robot("franka-fr3"), pose, q7=0.5)      # result.parameter == "q7"
    >>> result = ik(get_robot("kuka-iiwa14"), pose, psi=0.3)    # result.parameter == "psi"
    >>> result = ik(get_robot("kinova-gen3"), pose)              # result.method == "numerical"

Without ``psi`` or ``q7`` any chain is solved numerically
(:func:`redkin.numerical.ik`: certified solutions within the limits), and the
result says so in its ``method``.

Either result carries the poses' :class:`~redkin.chain.Reach`: a pose beyond
the arm's reach (or inside its shortest) is told apart from one the solver
found no solution for, and is not searched.  Each class measures its own
distance: the shoulder-wrist distance of S-R-S and offset-elbow arms
[000 eq. 11] and of the Franka class over every q7, the tool point's distance
from joint 1's axis against the links' lengths on nearly S-R-S arms and in the
numerical solver (:meth:`redkin.chain.SerialChain.reach`).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import as_float_array, check_finite, check_pose
from redkin.chain import Reach, SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.numerical.solve import NumericalSolutions
from redkin.srs.branches import BRANCHES, Branch, parse_branch


class ClosedFormSolutions(NamedTuple):
    """Solutions of poses at values of the redundancy parameter, one row per branch.

    Attributes
    ----------
    q : numpy.ndarray, shape (..., B, 7)
        Joint values in the chain's conventions (zeros where a branch has no solution).
    exists : numpy.ndarray of bool, shape (..., B)
        Whether the branch has a solution (an S-R-S pose out of the wrist's reach has none on any branch; on a
        nearly S-R-S arm, whether one was found and certified on the real arm).
    within_limits : numpy.ndarray of bool, shape (..., B)
        Exists and lies within the chain's joint limits.
    branches : tuple of Branch
        The branch of each row (``B = 8``, or 1 for one branch).
    parameter : str
        ``"psi"`` or ``"q7"``: what the given value was.
    reach : Reach
        The poses against the reach of the chain's class, batch shape as ``exists``: where ``reach.out``, no
        branch has a solution at any value of the parameter.
    """

    q: np.ndarray
    exists: np.ndarray
    within_limits: np.ndarray
    branches: tuple[Branch, ...]
    parameter: str
    reach: Reach


def redundancy_parameter(chain: SerialChain, srs_tolerance: float | None = None) -> str:
    """``"psi"`` for an S-R-S, offset-elbow or nearly S-R-S arm, ``"q7"`` for a Franka-class arm.

    ``srs_tolerance`` is the nearly S-R-S tolerance of :func:`redkin.srs.arm_angle_class` (default
    :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).

    Raises
    ------
    NotArmAngleClassError
        For a chain with no closed form, naming the conditions it breaks.
    """
    from redkin.srs.arm_class import FRANKA, GENERAL, arm_angle_class

    kind, reason = arm_angle_class(chain, srs_tolerance)
    if kind == GENERAL:
        raise NotArmAngleClassError(f"{chain.name!r} has no closed-form IK: {reason}", chain.name)
    return "q7" if kind == FRANKA else "psi"


def ik(
    chain: SerialChain,
    pose: ArrayLike,
    *,
    psi: ArrayLike | None = None,
    q7: ArrayLike | None = None,
    branch: str | Branch | tuple[int, int, int] | None = None,
    srs_tolerance: float | None = None,
    **solver: Any,
) -> ClosedFormSolutions | NumericalSolutions:
    """Every solution (or one branch's) of target poses at a value of the chain's redundancy parameter, or
    certified numerical solutions of any chain where neither ``psi`` nor ``q7`` is given.

    Parameters
    ----------
    chain : SerialChain
        An S-R-S, offset-elbow or Franka-class arm, in any description.
    pose : array_like, shape (..., 4, 4)
        Target poses of the chain's tool in its base frame.
    psi, q7 : array_like, broadcast against the poses' batch shape
        The arm angle (S-R-S arms, [000 eq. 6]) or the value of joint 7 (Franka class, docs/franka.md): exactly
        the one of the chain's class.
    branch : str or Branch, optional
        One branch (three signs, e.g. ``"+-+"``); default all eight, in the order of :data:`redkin.srs.BRANCHES`.
    srs_tolerance : float, optional
        With ``psi`` or ``q7``: the largest departure (metres, radians off perpendicular) of an arm solved as nearly
        S-R-S through its exact neighbour (:func:`redkin.srs.arm_angle_class`; default
        :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).
    **solver
        Without ``psi`` and ``q7``: the keyword arguments of :func:`redkin.numerical.ik` (``q0``, ``count``,
        ``tolerance``, ``restarts``, ``separation``, ``rng``).

    Returns
    -------
    ClosedFormSolutions or NumericalSolutions
        The closed form's rows per branch (``parameter`` names the parameter), or the numerical solver's
        certified solutions (``method == "numerical"``).

    Raises
    ------
    ValueError
        For a parameter given to a chain without a closed form, the other class's parameter or both, a branch,
        ``srs_tolerance`` or numerical keywords mixed with the other kind of call, a malformed pose, parameter,
        branch or tolerance.
    """
    from redkin import franka, numerical, srs
    from redkin.franka.ik import reach as franka_reach
    from redkin.srs.ik import reach as srs_reach

    if psi is None and q7 is None:
        for name, value in (("branch", branch), ("srs_tolerance", srs_tolerance)):
            if value is not None:
                raise RedkinError(f"{name} applies to the closed forms: give psi or q7 with it")
        return numerical.ik(chain, pose, **solver)
    if solver:
        raise RedkinError(f"{', '.join(sorted(solver))}: keywords of the numerical solver, which runs without "
                          "psi and q7")

    parameter = redundancy_parameter(chain, srs_tolerance)
    given = [name for name, value in (("psi", psi), ("q7", q7)) if value is not None]
    if given != [parameter]:
        right = "the arm angle psi" if parameter == "psi" else "q7 (the value of joint 7)"
        raise RedkinError(f"{chain.name!r} takes {right} as its redundancy parameter; got {' and '.join(given)}")
    if q7 is not None:
        result = franka.ik(chain, pose, q7, branch)
        return ClosedFormSolutions(result.q, result.exists, result.within_limits, result.branches, "q7",
                                   _spread(franka_reach(chain, pose), result.exists.shape[:-1]))
    from redkin.srs.arm_class import NEARLY_SRS, arm_angle_class
    from redkin.srs.nearly import TOLERANCE as NEARLY_TOLERANCE
    from redkin.srs.nearly import ik as nearly_ik
    from redkin.srs.nearly import nearly_srs

    nearly = arm_angle_class(chain, srs_tolerance).kind == NEARLY_SRS
    if nearly:  # the links' bound, with the slack of the real arm's certificate
        reach = chain.reach(check_pose(pose), tolerance=NEARLY_TOLERANCE)
    else:
        geometry = srs.srs_geometry(chain)
        reach = srs_reach(geometry, pose)
    chosen = BRANCHES if branch is None else (parse_branch(branch),)
    assert psi is not None  # given == ["psi"]
    psi = as_float_array(psi, "psi")
    check_finite(psi, "psi")
    try:
        shape = np.broadcast_shapes(reach.out.shape, psi.shape)
    except ValueError:
        raise RedkinError(f"psi of shape {psi.shape} does not broadcast against the pose batch "
                          f"{reach.out.shape}") from None
    reach = _spread(reach, shape)
    inside = ~reach.out
    angles = np.broadcast_to(psi, shape)[inside]
    poses = np.broadcast_to(np.asarray(pose, dtype=float), shape + (4, 4))[inside]
    q = np.zeros(shape + (len(chosen), 7))
    exists = np.zeros(shape + (len(chosen),), dtype=bool)
    within = np.zeros(shape + (len(chosen),), dtype=bool)
    if inside.any() and nearly:  # the real arm's solutions, searched only for poses within reach
        arm = nearly_srs(chain) if srs_tolerance is None else nearly_srs(chain, srs_tolerance)
        solutions = nearly_ik(arm, poses, angles, branch)
        q[inside], exists[inside], within[inside] = solutions.q, solutions.exists, solutions.within_limits
    elif inside.any():
        q[inside] = np.stack([srs.ik(geometry, poses, angles, b) for b in chosen], axis=-2)
        exists[inside] = True
        within = exists & chain.within_limits(q, tolerance=1e-9, wrap=True)
    return ClosedFormSolutions(q, exists, within, chosen, "psi", reach)


def _spread(reach: Reach, shape: tuple[int, ...]) -> Reach:
    """``reach`` of a pose batch broadcast to the batch of a result (poses against parameter values)."""
    return reach._replace(distance=np.broadcast_to(reach.distance, shape), out=np.broadcast_to(reach.out, shape))
