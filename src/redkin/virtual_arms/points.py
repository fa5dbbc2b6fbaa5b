"""Virtual end points: where each virtual arm of paper 004 (section 2, Fig. 1) ends.

A virtual arm has the same kinematic structure as the real arm but ends at a
joint or on a link of it.  Its end point is therefore a point fixed in one
frame of the chain: :class:`VirtualPoint` stores that frame and the point's
coordinates in it, and is built from the words users think in:

* ``VirtualPoint.joint(j)``: the origin of joint ``j`` (1-based).  In the
  chain's frame numbering this is a point on the axis of joint ``j``, fixed in
  frame ``j - 1`` (so joints ``1 .. j - 1`` move it).
* ``VirtualPoint.on_link(j, t)``: the point a fraction ``t`` along link ``j``,
  from joint ``j`` (``t = 0``) to joint ``j + 1`` (``t = 1``; the end point
  for the last link), fixed in frame ``j``.
* ``VirtualPoint.end()``: the real arm's end point (the tool frame origin).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from redkin.chain import SerialChain
from redkin.errors import RedkinError


@dataclass(frozen=True)
class VirtualPoint:
    """A point on the chain that a virtual arm ends at.

    Parameters
    ----------
    kind : {"joint", "link", "end"}
        How the point was chosen (for labels and parsing).
    index : int
        Joint number (``"joint"``) or link number (``"link"``), 1-based; ``0`` for ``"end"``.
    fraction : float
        Position along the link for ``"link"`` points, in ``[0, 1]``.
    """

    kind: str
    index: int = 0
    fraction: float = 0.0

    @classmethod
    def joint(cls, j: int) -> VirtualPoint:
        """The origin of joint ``j`` (1-based)."""
        return cls("joint", int(j))

    @classmethod
    def on_link(cls, j: int, fraction: float = 0.5) -> VirtualPoint:
        """The point ``fraction`` along link ``j`` (1-based) from joint ``j`` to joint ``j + 1``."""
        return cls("link", int(j), float(fraction))

    @classmethod
    def end(cls) -> VirtualPoint:
        """The real arm's end point (tool origin)."""
        return cls("end")

    @property
    def label(self) -> str:
        """Short text form, the same that :func:`parse_point` reads."""
        if self.kind == "end":
            return "end"
        if self.kind == "joint":
            return f"joint:{self.index}"
        return f"link:{self.index}@{self.fraction:g}"

    def check(self, chain: SerialChain) -> None:
        """Raise ``ValueError`` unless this point exists on ``chain``."""
        if self.kind not in ("joint", "link", "end"):
            raise RedkinError(f"point kind must be 'joint', 'link' or 'end', got {self.kind!r}")
        if self.kind == "end":
            return
        if not 1 <= self.index <= chain.n:
            raise RedkinError(f"point {self.label}: {self.kind} number must be in 1..{chain.n}, got {self.index}")
        if self.kind == "link" and not (np.isfinite(self.fraction) and 0.0 <= self.fraction <= 1.0):
            raise RedkinError(f"point {self.label}: fraction must be in [0, 1], got {self.fraction!r}")

    def anchor(self, chain: SerialChain) -> tuple[int, np.ndarray]:
        """Frame index (``0 .. n + 1``, ``n + 1`` = tool) and the point's coordinates in that frame.

        The coordinates are constant, so they are computed once at ``q = 0``.
        """
        self.check(chain)
        n = chain.n
        if self.kind == "end":
            return n + 1, np.zeros(3)
        if self.kind == "joint":
            return self.index - 1, np.zeros(3)
        frames = chain.frames(np.zeros(n))
        j = self.index
        inner = frames[j - 1, :3, 3]
        outer = frames[n + 1, :3, 3] if j == n else frames[j, :3, 3]
        world = (1.0 - self.fraction) * inner + self.fraction * outer
        rotation, origin = frames[j, :3, :3], frames[j, :3, 3]
        return j, rotation.T @ (world - origin)


_POINT = re.compile(r"^(?:(end)|joint:(\d+)|link:(\d+)(?:@([0-9.eE+-]+))?)$")


def parse_point(text: str) -> VirtualPoint:
    """Read ``end``, ``joint:J`` or ``link:J[@T]`` (``T`` defaults to 0.5).

    Raises
    ------
    ValueError
        For any other text.
    """
    match = _POINT.match(text.strip())
    if not match:
        raise RedkinError(f"point must be 'end', 'joint:J' or 'link:J[@T]', got {text!r}")
    if match.group(1):
        return VirtualPoint.end()
    if match.group(2):
        return VirtualPoint.joint(int(match.group(2)))
    try:
        fraction = 0.5 if match.group(4) is None else float(match.group(4))
    except ValueError as exc:
        raise RedkinError(f"point {text!r}: fraction must be a number, got {match.group(4)!r}") from exc
    return VirtualPoint.on_link(int(match.group(3)), fraction)


def joints_and_midpoints(chain: SerialChain, first_joint: int = 2) -> list[VirtualPoint]:
    """Joint origins from ``first_joint`` on and every link's midpoint (paper 004 Fig. 6 (c), (d)).

    For the 5-link planar arm with ``first_joint = 2`` these are the nine
    virtual points of Fig. 6 (c): joints 2-5 and the centres of links 1-5.
    """
    points = [VirtualPoint.joint(j) for j in range(first_joint, chain.n + 1)]
    points += [VirtualPoint.on_link(j, 0.5) for j in range(1, chain.n + 1)]
    return points
