"""The eight IK branches of an S-R-S arm: the signs of theta_2, theta_4 and theta_6.

A branch is written as three characters, e.g. ``"+-+"`` for theta_2 >= 0,
theta_4 < 0, theta_6 >= 0 (paper 000 section 3.3: eight solutions per pose
and arm angle).  On an offset elbow the middle sign is that of ``theta_4 -
phi``, ``phi`` the elbow angle of the longest reach
(:class:`redkin.srs.geometry.ElbowEquation`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from redkin.errors import RedkinError


class Branch(NamedTuple):
    """Signs (+1 or -1) of theta_2 (shoulder), theta_4 (elbow) and theta_6 (wrist)."""

    shoulder: int
    elbow: int
    wrist: int

    def __str__(self) -> str:
        return "".join("+" if s > 0 else "-" for s in self)


#: All eight branches, ``+++`` first.
BRANCHES: tuple[Branch, ...] = tuple(
    Branch(s2, s4, s6) for s2 in (1, -1) for s4 in (1, -1) for s6 in (1, -1)
)

_BY_TEXT = {str(branch): branch for branch in BRANCHES}


def parse_branch(value: str | Branch | tuple[int, int, int]) -> Branch:
    """A :class:`Branch` from ``"+-+"`` or a triple of signs.

    Raises
    ------
    ValueError
        Unless ``value`` is three of ``+``/``-`` or three signs +-1.
    """
    if isinstance(value, Branch):
        return value
    if isinstance(value, str):
        if value in _BY_TEXT:
            return _BY_TEXT[value]
        if len(value) != 3 or any(ch not in "+-" for ch in value):
            raise RedkinError(
                f"branch must be three signs of theta2, theta4, theta6 such as '+++' or '+-+', got {value!r}"
            )
        return Branch(*(1 if ch == "+" else -1 for ch in value))
    try:
        signs = [int(v) for v in value]
    except (TypeError, ValueError):
        raise RedkinError(f"branch must be a string like '+-+' or three signs, got {value!r}") from None
    if len(signs) != 3 or any(s not in (1, -1) for s in signs):
        raise RedkinError(f"branch must be three signs (+1 or -1), got {value!r}")
    return Branch(*signs)


def branch_of_theta(theta: np.ndarray, elbow_phase: float = 0.0) -> np.ndarray:
    """Branch signs ``(..., 3)`` of DH angles ``(..., 7)``: of theta_2, ``theta_4 - elbow_phase`` and theta_6.

    Each angle is taken modulo 2 pi into ``[-pi, pi)``; zero counts as ``+``.
    ``elbow_phase`` is ``phi`` of an offset elbow
    (:class:`redkin.srs.geometry.ElbowEquation`), 0 on an S-R-S arm.
    """
    picked = np.mod(theta[..., [1, 3, 5]] - np.array([0.0, elbow_phase, 0.0]) + np.pi, 2.0 * np.pi) - np.pi
    return np.where(picked < 0.0, -1, 1)
