"""Everything one pose's redundancy holds, in one form for every class of arm (:meth:`redkin.arms.Arm.analyse`):
per branch the feasible set, the per-joint sets and the singular values where the class has them, and the
limit-avoiding values; what the command line's ``redkin arm-angles`` prints and the explorer draws.

A reader shows what the answer holds (a field that is ``None`` or empty is not shown) and never asks which class
the arm is: the class's own words (what marks a singular value, what a stated remark says) come with the answer.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from redkin.arms.parameter import Parameter
from redkin.chain import Reach
from redkin.errors import UnreachablePoseError

#: Values of the parameter closer than this [rad] are one (an optimum that needed no clamping, a value at the end
#: of a set computed from the per-joint ends it came from).
SAME_VALUE = 1e-12


@dataclass(frozen=True)
class SingularPart:
    """The values of the parameter at which one part (shoulder or wrist) of one branch is singular.

    Attributes
    ----------
    values : tuple of float
        Sorted, in the parameter's domain.
    everywhere : bool
        The part is singular at every value (the pose puts it there whatever the parameter).
    configurations : numpy.ndarray, shape (len(values), n), optional
        The configuration at each value where the class locates it on the real arm (the aligned configuration of a
        nearly S-R-S arm); ``None`` where the closed form's solution there is the one to show.
    nearest : tuple of float, optional
        ``(value, angle)``: where the part comes nearest to singular and how near (the angle between the axes'
        lines, radians), where the class measures it.
    marks : str
        What a singular value means for the part, in a few words (``"θ2 = 0 or π"``).
    note : str
        What it means for the joint values shown there, in a sentence.
    """

    values: tuple[float, ...]
    everywhere: bool
    marks: str
    note: str
    configurations: np.ndarray | None = None
    nearest: tuple[float, float] | None = None


@dataclass(frozen=True)
class BranchAnalysis:
    """One branch at one pose.

    Attributes
    ----------
    branch : str
        The label, e.g. ``"+-+"``.
    arcs : numpy.ndarray, shape (K, 2)
        The feasible set as ``[start, end]`` arcs, sorted and disjoint; ``start > end`` only on a parameter that
        wraps, for an arc through ``+-pi``.
    full : bool
        Whether the feasible set is the whole domain.
    optimal : dict of str to tuple of float
        Per part (``"overall"`` last; ``"shoulder"`` and ``"wrist"`` first where the class weighs them
        [000 eq. 40]), the limit-avoiding value ``(unclamped, feasible)``: over every value at which the branch
        exists and within the feasible set, ``nan`` where none.
    per_joint : dict of int to numpy.ndarray, optional
        Per joint (1-based), the arcs ``(k, 2)`` on which that joint alone is within its limits [000 eq. 29];
        ``None`` where the class gives no per-joint sets.
    singular : dict of str to SingularPart, optional
        ``"shoulder"`` and ``"wrist"``; ``None`` where the class has no singular-value analysis.
    fixed : dict of int to float
        Joints (1-based) whose value the pose fixes on this branch, whatever the parameter (the elbow of an S-R-S
        arm).
    """

    branch: str
    arcs: np.ndarray
    full: bool
    optimal: dict[str, tuple[float, float]]
    per_joint: dict[int, np.ndarray] | None = None
    singular: dict[str, SingularPart] | None = None
    fixed: dict[int, float] = field(default_factory=dict)

    @property
    def start(self) -> float:
        """The value to show first: the overall optimum within the feasible set, else over every value, else 0."""
        unclamped, feasible = self.optimal["overall"]
        return feasible if np.isfinite(feasible) else unclamped if np.isfinite(unclamped) else 0.0


@dataclass(frozen=True)
class Analysis:
    """One pose of one arm (module docstring).

    Attributes
    ----------
    parameter : Parameter
        The redundancy parameter, with its words.
    method : str
        What computed the numbers, in words.
    sets : tuple of numpy.ndarray
        Per branch of the arm, the feasible arcs ``(K, 2)`` (as :attr:`BranchAnalysis.arcs`).
    branches : tuple of BranchAnalysis
        The branches asked for.
    complete : bool
        Whether the sets are proved complete (a closed form's) or followed whole (a nearly S-R-S arm's
        self-motion); false where the work budget ran out, so that an arc may be missing.
    samples : int, optional
        Points the sets were located from, where they were located by sampling.
    remarks : tuple of str
        Sentences the class states about the arm (a nearly S-R-S arm's neighbour and what is not computed on it).
    solution : str
        What a solution of the class is called where one may be missing (``"certified solution"`` on a nearly
        S-R-S arm).
    """

    parameter: Parameter
    method: str
    sets: tuple[np.ndarray, ...]
    branches: tuple[BranchAnalysis, ...]
    complete: bool = True
    samples: int | None = None
    remarks: tuple[str, ...] = ()
    solution: str = "solution"


def in_arcs(values: np.ndarray, arcs: np.ndarray, slack: float = SAME_VALUE) -> np.ndarray:
    """Whether each value lies in the arcs ``(K, 2)`` (closed, within ``slack``); an arc with ``start > end`` runs
    through ``+-pi``."""
    values = np.asarray(values, dtype=float)[..., None]
    low, high = arcs[:, 0] - slack, arcs[:, 1] + slack
    plain = (low <= values) & (values <= high)
    seam = (values >= low) | (values <= high)
    return np.any(np.where(arcs[:, 0] <= arcs[:, 1], plain, seam), axis=-1)


def as_arcs(pairs) -> np.ndarray:
    """``[start, end]`` pairs as a float array of shape ``(K, 2)`` (``(0, 2)`` for none)."""
    return np.asarray(pairs, dtype=float).reshape(-1, 2)


def optimal_parts(optimal) -> dict[str, tuple[float, float]]:
    """The ``shoulder``, ``wrist`` and ``overall`` limit-avoiding arm angles [000 eq. 40] of an S-R-S or nearly S-R-S
    arm's result (each with ``unclamped`` and ``feasible``) as :attr:`BranchAnalysis.optimal` holds them."""
    return {name: (float(getattr(optimal, name).unclamped), value(getattr(optimal, name).feasible))
            for name in ("shoulder", "wrist", "overall")}


def value(optional: float | None) -> float:
    """A value that may be missing (``None``) as a float, ``nan`` where missing."""
    return np.nan if optional is None else float(optional)


def check_in_reach(reach: Reach) -> None:
    """Raise where ``reach`` (of one pose) proves the pose out of the arm's reach: the analysis of every class refuses
    such a pose in one line with the distances, before any search (the S-R-S closed form from [000 eq. 11], the
    other classes from their own reach).

    Raises
    ------
    UnreachablePoseError
        Where ``reach.out``.
    """
    if bool(reach.out):
        raise UnreachablePoseError(f"unreachable pose: {reach.measure} is {float(reach.distance):.6g} m, outside "
                                   f"[{reach.lower:.6g}, {reach.upper:.6g}] m")
