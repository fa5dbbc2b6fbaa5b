"""One result type of pose IK for every class of arm: :class:`Solutions`, one row per branch (or per solution found on
a chain without branches), the same fields whether a closed form or the numerical solver answered."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from redkin.chain import Reach

if TYPE_CHECKING:  # the type alone: the collision package reads the arms, and is read only in a cell
    from redkin.collision.clearance import Clearance

#: ``method`` of a closed form's rows and of the numerical solver's.
CLOSED_FORM, NUMERICAL = "closed form", "numerical"


@dataclass(eq=False)
class Solutions:
    """Solutions of target poses, one row per branch, batched over the poses' leading axes (read-only by
    convention: not frozen, which would cost a microsecond a call).

    Attributes
    ----------
    q : numpy.ndarray, shape (..., B, n)
        Joint values in the chain's conventions (zeros where a row does not exist).
    exists : numpy.ndarray of bool, shape (..., B)
        Whether the row holds a solution.
    within_limits : numpy.ndarray of bool, shape (..., B)
        Exists and lies within the chain's joint limits.
    branches : tuple of str
        The branch of each row (``"+-+"``); on a chain without branches (a general chain), ``"1"``, ``"2"`` ...: the
        solutions found, in the solver's order.
    method : str
        ``"closed form"`` (at a value of the parameter) or ``"numerical"``.
    reach : Reach
        The poses against the arm's reach, shape ``(...)``: where ``reach.out``, no row exists at any value of the
        parameter (computed when first read).
    clearance : Clearance or None
        In a cell (``body`` and ``scene`` given), each row's least signed distance [m] over the checked pairs and
        the pair that has it (:func:`redkin.collision.clearance`), shape ``(..., B)``: ``nan`` and ``""`` where the
        row does not exist; ``None`` without a cell.
    collision_free : numpy.ndarray of bool or None
        In a cell, whether each row exists and keeps the scene's margin, shape ``(..., B)``; ``None`` without one.
    """

    q: np.ndarray
    exists: np.ndarray
    within_limits: np.ndarray
    branches: tuple[str, ...]
    method: str
    _value: np.ndarray = field(repr=False)
    _out: Callable[[], np.ndarray] = field(repr=False)
    _reach: Callable[[], Reach] = field(repr=False)
    _missing: str = field(repr=False, default="no solution of the branch at this value of the parameter")
    clearance: Clearance | None = None
    collision_free: np.ndarray | None = None

    @cached_property
    def parameter(self) -> np.ndarray:
        """The value of the redundancy parameter of each row, shape ``(..., B)``: the value given, or on the
        numerical solver's rows the solution's own (``nan`` where a row does not exist or the arm has none)."""
        value = np.asarray(self._value, dtype=float)
        return np.broadcast_to(value if value.shape == self.exists.shape else value[..., None], self.exists.shape)

    @cached_property
    def reach(self) -> Reach:
        return self._reach()

    @cached_property
    def reason(self) -> np.ndarray:
        """Why each row does not exist, shape ``(..., B)`` of str (``""`` where it does): the pose out of the arm's
        reach (with the distance and the range), or that the branch has no solution there."""
        out = np.broadcast_to(np.asarray(self._out(), dtype=bool)[..., None], self.exists.shape)
        reason = np.full(self.exists.shape, "", dtype=object)
        if out.any():
            reach = self.reach
            distance = np.broadcast_to(reach.distance[..., None], self.exists.shape)
            for index in zip(*np.nonzero(out), strict=True):
                reason[index] = (f"out of reach: {reach.measure} is {distance[index]:.6g} m, outside "
                                 f"[{reach.lower:.6g}, {reach.upper:.6g}] m")
        reason[~self.exists & ~out] = self._missing
        return reason

    def row(self, branch: str) -> int:
        """The row index of ``branch`` (a label of :attr:`branches`).

        Raises
        ------
        ValueError
            For a label that is not one of :attr:`branches`.
        """
        from redkin.errors import RedkinError

        try:
            return self.branches.index(str(branch))
        except ValueError:
            raise RedkinError(f"no row of branch {branch!r}: the rows are {', '.join(self.branches)}") from None
