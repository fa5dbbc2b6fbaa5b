"""What every class of arm answers (:class:`ArmKind`), over its own kernels; :class:`redkin.arms.Arm` asks it and
nothing else, and :mod:`redkin.arms.registry` picks the class of a chain.

A class implements the methods it can answer and leaves the others to refuse in words (a general chain has no
parameter, the Franka class no singular-value analysis); the shapes are the same for every class:

* :meth:`ArmKind.solve` -- the rows of every requested branch at values of the parameter (:class:`Solutions`);
* :meth:`ArmKind.pieces` -- the feasible sets as pieces ``(N, B, K)``;
* :meth:`ArmKind.read` -- the branch index and parameter of configurations ``(P, n)``;
* :meth:`ArmKind.optimal`, :meth:`ArmKind.singular`, :meth:`ArmKind.every_solution` -- one pose and branch.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.solutions import Solutions
from redkin.chain import SerialChain
from redkin.errors import RedkinError


@dataclass(frozen=True)
class Parameter:
    """The redundancy parameter of a class of arm.

    Attributes
    ----------
    name : str
        ``"psi"`` (the arm angle, [000 eq. 6]) or ``"q7"`` (the value of joint 7, docs/franka.md).
    domain : tuple of float
        The values it takes, radians: ``(-pi, pi)`` for the arm angle, joint 7's range for q7.
    wraps : bool
        Whether it is an angle on the circle (``domain``'s ends are one value).
    """

    name: str
    domain: tuple[float, float]
    wraps: bool


class ArmKind:
    """One class of arm, converted once from its chain (module docstring).

    Attributes
    ----------
    kind : str
        The class's name (:mod:`redkin.arms.classify`'s constants).
    chain : SerialChain
    parameter : Parameter or None
    branches : tuple of str
        The branch labels of the rows; empty on a class without branches.
    exact : bool
        Whether its feasible sets are proved complete.
    family : redkin.paths.family.Family or None
        The class as path resolution sees it (:func:`redkin.paths.family.path_family` returns it); ``None`` for a
        class without a parameter.
    """

    kind: str
    chain: SerialChain
    parameter: Parameter | None = None
    branches: tuple[str, ...] = ()
    exact: bool = False
    family: Any = None

    def solve(self, poses: ArrayLike, t: np.ndarray, rows: np.ndarray | None) -> Solutions:
        """The rows ``rows`` (indices into :attr:`branches`; ``None`` all) of ``poses`` ``(..., 4, 4)`` at values
        ``t`` of the parameter, broadcast against the batch shape."""
        raise self._refusal("solutions at a value of the redundancy parameter")

    def pieces(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``start, end, feasible`` ``(N, B, K)`` of poses ``(N, 4, 4)`` (:class:`redkin.arms.FeasibleSets`): the
        :attr:`family`'s pieces."""
        if self.family is None:
            raise self._refusal("feasible sets")
        pieces = self.family.pieces(poses)
        return pieces.start, pieces.end, pieces.feasible

    def read(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The branch indices ``(P,)`` and parameter values ``(P,)`` of configurations ``q`` ``(P, n)``: the
        :attr:`family`'s reading."""
        if self.family is None:
            raise self._refusal("a configuration's branch and parameter")
        branch, value = self.family.parameter_of(q)
        return branch, value

    def optimal(self, pose: np.ndarray, row: int, target: np.ndarray | None,
                weights: tuple[float, float] | None) -> tuple[float, float]:
        """The limit-avoiding value of one pose ``(4, 4)`` and branch, nearest ``target`` (joint values; ``None``: the
        middle of each range), the shoulder and wrist weighed by ``weights`` where the class weighs them: within
        the feasible set (``nan`` where it is empty) and over every value at which the branch exists (``nan`` where
        none)."""
        raise self._refusal("a limit-avoiding value of the parameter")

    def joint_sets(self, pose: np.ndarray, row: int) -> dict[int, list[tuple[float, float]]]:
        """Per joint (1-based), the arcs of the parameter at which one pose and branch's joint lies within its
        limits."""
        raise self._refusal("per-joint feasible sets")

    def singular(self, pose: np.ndarray, row: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The parameter's values at which one pose and branch's shoulder and wrist are singular."""
        raise self._refusal("singular values of the parameter")

    def every_solution(self, pose: np.ndarray, t: float, row: int) -> np.ndarray:
        """Every solution ``(K, n)`` of one pose ``(4, 4)`` and branch at ``t``: the branch's row where it exists, on
        a class with one solution per branch and value."""
        result = self.solve(pose, np.asarray(t, dtype=float), np.array([row]))
        return result.q[result.exists]

    def _refusal(self, what: str) -> RedkinError:
        return RedkinError(f"{what}: {self.chain.name!r} has no such answer as {self.kind}")
