"""A paper's printed value beside ours, with the verdict in words and the reason for a disagreement.

Paper values enter the report only as the "paper" side of a
:class:`Comparison`.  A :class:`Note` explains rows: its one-line ``reason``
goes to the report's summary for every row that differs, and its ``detail``
is printed once under the table, however many rows share it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, TypeGuard

from redkin.errors import RedkinError


@dataclass(frozen=True)
class Note:
    """An explanation of one or more rows of a comparison table.

    Parameters
    ----------
    reason : str
        One line, e.g. ``"misprint in the paper"``; the summary shows it beside every differing row.
    detail : str
        The full explanation, printed once under the table.
    """

    reason: str
    detail: str = ""

    def __str__(self) -> str:
        return f"{self.reason}: {self.detail}" if self.detail else self.reason


@dataclass(frozen=True)
class Comparison:
    """One printed number (or statement) of a paper beside ours.

    Parameters
    ----------
    quantity : str
        What is compared, e.g. ``"Psi_2 upper bound [deg]"`` (a unit in brackets).
    paper : float, str or None
        The value printed in the paper (``None`` if the paper prints none).
    ours : float, str or None
        Our recomputed value.
    tolerance : float
        Largest difference counted as agreement (e.g. half the last printed digit).
    note : str or Note
        Explanation, required whenever the values disagree; a plain string is a note without detail.
    """

    quantity: str
    paper: float | str | None
    ours: float | str | None
    tolerance: float = 0.0
    note: str | Note = ""

    def __post_init__(self) -> None:
        if isinstance(self.tolerance, bool) or not isinstance(self.tolerance, (int, float)) or self.tolerance < 0:
            raise RedkinError(f"tolerance of {self.quantity!r} must be a number >= 0, got {self.tolerance!r}")
        if not isinstance(self.note, (str, Note)):
            raise RedkinError(f"note of {self.quantity!r} must be a string or a Note, got {self.note!r}")

    @property
    def agrees(self) -> bool | None:
        """True/False for two numbers or two words (equal words agree), None otherwise."""
        if isinstance(self.paper, str) and isinstance(self.ours, str):
            return self.paper == self.ours
        if not (is_number(self.paper) and is_number(self.ours)):
            return None
        return abs(float(self.paper) - float(self.ours)) <= self.tolerance + 1e-12

    @property
    def difference(self) -> float | None:
        """Ours minus the paper's value, for two numbers."""
        if is_number(self.paper) and is_number(self.ours):
            return float(self.ours) - float(self.paper)
        return None

    @property
    def explanation(self) -> Note | None:
        """The note as a :class:`Note` (``None`` without one)."""
        if isinstance(self.note, Note):
            return self.note
        return Note(self.note) if self.note else None

    def outcome(self) -> str:
        """The verdict without its note: ``agrees``, ``DIFFERS by +x``, ``paper prints no value``, ..."""
        agrees = self.agrees
        if agrees is None:
            return "not comparable as numbers" if self.paper is not None else "paper prints no value"
        if agrees:
            return "agrees" if self.tolerance == 0 else f"agrees (within {self.tolerance:g})"
        difference = self.difference
        return "DIFFERS" if difference is None else f"DIFFERS by {difference:+.6g}"

    def verdict(self) -> str:
        """The comparison in words, with its note (as ``summary.json`` records it)."""
        return f"{self.outcome()}; {self.note}" if self.note else self.outcome()


def is_number(value: Any) -> TypeGuard[float]:
    """A finite int or float that is not a bool."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
