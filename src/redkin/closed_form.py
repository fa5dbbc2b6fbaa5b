"""One front door to pose IK: the closed forms at a value of the chain's redundancy parameter, or the numerical solver.

The chain's class (:func:`redkin.arms.classify.arm_angle_class`) picks the solver and
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

from redkin.chain import Reach, SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.numerical.solve import NumericalSolutions
from redkin.srs.branches import Branch, parse_branch


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

    ``srs_tolerance`` is the nearly S-R-S tolerance of :func:`redkin.arms.classify.arm_angle_class` (default
    :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).

    Raises
    ------
    NotArmAngleClassError
        For a chain with no closed form, naming the conditions it breaks.
    """
    from redkin.arms import arm

    classified = arm(chain, srs_tolerance=srs_tolerance)
    if classified.parameter is None:
        raise NotArmAngleClassError(f"{chain.name!r} has no closed-form IK: {classified.reason}", chain.name)
    return classified.parameter.name


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
        S-R-S through its exact neighbour (:func:`redkin.arms.classify.arm_angle_class`; default
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
    from redkin import numerical
    from redkin.arms import arm

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
        raise RedkinError(f"{chain.name!r} takes {parameter} as its redundancy parameter; got {' and '.join(given)}")
    at = psi if q7 is None else q7
    assert at is not None  # given == [parameter]
    result = arm(chain, srs_tolerance=srs_tolerance).ik(
        pose, at, branches=None if branch is None else str(parse_branch(branch)))
    return ClosedFormSolutions(result.q, result.exists, result.within_limits,
                               tuple(parse_branch(label) for label in result.branches), parameter,
                               _spread(result.reach, result.exists.shape[:-1]))


def _spread(reach: Reach, shape: tuple[int, ...]) -> Reach:
    """``reach`` of a pose batch broadcast to the batch of a result (poses against parameter values)."""
    return reach._replace(distance=np.broadcast_to(reach.distance, shape), out=np.broadcast_to(reach.out, shape))
