"""What every class of arm answers (:class:`ArmKind`), over its own kernels; :class:`redkin.arms.Arm` asks it and
nothing else, and :mod:`redkin.arms.registry` picks the class of a chain.

A class implements the methods it can answer and leaves the others to refuse in words (a general chain has no
parameter, the Franka class no singular-value analysis); the shapes are the same for every class:

* :meth:`ArmKind.solve` -- the rows of every requested branch at values of the parameter (:class:`Solutions`);
* :meth:`ArmKind.pieces` -- the feasible sets as pieces ``(N, B, K)``;
* :meth:`ArmKind.read` -- the branch index and parameter of configurations ``(P, n)``;
* :meth:`ArmKind.optimal`, :meth:`ArmKind.singular` -- one pose and branch, :meth:`ArmKind.every_solutions` one
  pose and value;
* :meth:`ArmKind.analyse` -- everything one pose's redundancy holds (:class:`redkin.arms.analysis.Analysis`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from redkin.arms.analysis import Analysis
from redkin.arms.feasible_sets import Arcs
from redkin.arms.parameter import Parameter
from redkin.arms.solutions import Solutions
from redkin.chain import SerialChain
from redkin.errors import RedkinError


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
    method : str
        What computes its answers, in words (:attr:`redkin.arms.analysis.Analysis.method`).
    nearly : redkin.srs.NearlySRS or None
        The exact neighbour a class that is not exact stands on (a nearly S-R-S arm's, with what it drops:
        ``describe()``, ``departures``, ``neighbour``); ``None`` on an exact class.
    one_per_branch : bool
        Whether a branch has at most one solution at each value of the parameter (else
        :meth:`every_solutions` may find more).
    family : redkin.paths.family.Family or None
        The class as path resolution sees it (:func:`redkin.paths.family.path_family` returns it); ``None`` for a
        class without a parameter.
    """

    kind: str
    chain: SerialChain
    parameter: Parameter | None = None
    branches: tuple[str, ...] = ()
    exact: bool = False
    method: str = "the numerical pose IK"
    one_per_branch: bool = True
    nearly: Any = None
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
                weights: tuple[float, float] | None, within: Arcs | None = None) -> tuple[float, float]:
        """The limit-avoiding value of one pose ``(4, 4)`` and branch, nearest ``target`` (joint values; ``None``: the
        middle of each range), the shoulder and wrist weighed by ``weights`` where the class weighs them: within
        the feasible set, or the subset ``within`` of it (a collision-free set; ``nan`` where it is empty), and over
        every value at which the branch exists (``nan`` where none)."""
        raise self._refusal("a limit-avoiding value of the parameter")

    def joint_sets(self, pose: np.ndarray, row: int) -> dict[int, list[tuple[float, float]]]:
        """Per joint (1-based), the arcs of the parameter at which one pose and branch's joint lies within its
        limits."""
        raise self._refusal("per-joint feasible sets")

    def singular(self, pose: np.ndarray, row: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The parameter's values at which one pose and branch's shoulder and wrist are singular."""
        raise self._refusal("singular values of the parameter")

    def analyse(self, pose: np.ndarray, rows: np.ndarray, target: np.ndarray | None,
                weights: tuple[float, float] | None) -> Analysis:
        """One pose ``(4, 4)``: the feasible sets of every branch, and of the branches ``rows`` the per-joint sets,
        singular and limit-avoiding values (``target`` and ``weights`` as :meth:`optimal` takes them)."""
        raise self._refusal("an analysis of the redundancy at a pose")

    def every_solutions(self, pose: np.ndarray, t: float, rows: np.ndarray) -> tuple[np.ndarray, ...]:
        """Per branch of ``rows``, every solution ``(K, n)`` of one pose ``(4, 4)`` at ``t``: on a class with
        :attr:`one_per_branch`, the branch's row where it exists."""
        result = self.solve(pose, np.asarray(t, dtype=float), rows)
        return tuple(result.q[k][None] if result.exists[k] else result.q[k][:0] for k in range(len(rows)))

    def _refusal(self, what: str) -> RedkinError:
        return RedkinError(f"{what}: {self.chain.name!r} has no such answer as {self.kind}")
