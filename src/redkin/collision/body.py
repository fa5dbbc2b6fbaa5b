"""An arm's body (issue 40): capsules fixed in the links of a chain, posed at joint values as rows the compiled
distances read.

A :class:`Body` is a list of capsules (a sphere is a capsule of length 0), each fixed in one frame of the chain:
frame ``k`` of :meth:`redkin.chain.SerialChain.frames`, the frame that joint ``k`` turns (``0``: the base, which no
joint moves; ``n``: the last link and whatever is fixed to it, such as a hand).  Each capsule names the link it
covers, so that messages and self-collision rules can speak of links.

Self-collision pairs.  Two capsules are checked against each other when their links are different, not joined by
one joint (frames ``k`` and ``k + 1``: adjacent links touch at their joint by construction) and not named in
``ignore`` (an SRDF's ``disable_collisions``, or a body file's ``ignore``).  Capsules in one frame are one rigid
body and never checked against each other.

Example
-------
>>> import numpy as np
>>> from redkin.collision.body import BodyCapsule, body_of, posed
>>> from redkin.models import pa10_7c
>>> chain = pa10_7c()
>>> body = body_of([BodyCapsule("upper arm", 3, [0, 0, 0], [0, 0, 0.2], 0.06),
...                 BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.05], 0.04)], chain)
>>> posed(body, chain.frames(np.zeros(7))).shape
(2, 17)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin.chain import SerialChain
from redkin.collision import _body_kernels, primitives
from redkin.errors import RedkinError


class BodyCapsule(NamedTuple):
    """One capsule of a body: the points within ``radius`` of the segment ``a``-``b``, given in chain frame
    ``frame`` (``0 .. n``), covering the link named ``link``."""

    link: str
    frame: int
    a: ArrayLike
    b: ArrayLike
    radius: float


@dataclass(frozen=True, eq=False)
class Body:
    """Capsules fixed in the frames of a chain, and the pairs of them checked for self-collision.

    Build it with :func:`body_of`.

    Attributes
    ----------
    link : tuple of str
        Per capsule, the link it covers.
    frame : numpy.ndarray of int, shape (M,)
        Per capsule, the chain frame (``0 .. n``) it is fixed in.
    a, b : numpy.ndarray, shape (M, 3)
        The segment's ends in that frame [m].
    radius : numpy.ndarray, shape (M,)
    pairs : numpy.ndarray of int, shape (P, 2)
        The capsule pairs ``(i, j)``, ``i < j``, checked against each other (module docstring).
    notes : tuple of str
        What the capsules approximate and by how much (one line each), for the user to read.
    source : str
        Where the body comes from, for messages.
    """

    link: tuple[str, ...]
    frame: np.ndarray
    a: np.ndarray
    b: np.ndarray
    radius: np.ndarray
    pairs: np.ndarray
    notes: tuple[str, ...] = ()
    source: str = ""

    def __len__(self) -> int:
        return len(self.link)

    @property
    def links(self) -> tuple[str, ...]:
        """The links covered, in order of first appearance."""
        return tuple(dict.fromkeys(self.link))


def body_of(capsules: Iterable[BodyCapsule], chain: SerialChain, ignore: Iterable[Sequence[str]] = (), *,
            notes: Sequence[str] = (), source: str = "") -> Body:
    """The body of ``capsules`` on ``chain``, with the self-collision pairs of the module docstring.

    Parameters
    ----------
    capsules : iterable of BodyCapsule
    chain : SerialChain
        The chain whose frames the capsules are fixed in (only its number of joints is read).
    ignore : iterable of (str, str)
        Link pairs never checked against each other, beside the adjacent ones.
    notes, source
        As :class:`Body` keeps them.

    Raises
    ------
    RedkinError
        For a frame outside ``0 .. n``, an end that is not three finite numbers, a negative or non-finite radius,
        or an ``ignore`` entry that is not two link names.
    """
    rows = list(capsules)
    links, frames, ends_a, ends_b, radii = [], [], [], [], []
    for index, capsule in enumerate(rows):
        label = f"capsule {index + 1} (link {capsule.link!r})"
        frame = capsule.frame
        if isinstance(frame, bool) or not isinstance(frame, (int, np.integer)) or not 0 <= frame <= chain.n:
            raise RedkinError(f"{label}: frame must be a whole number from 0 to {chain.n}, got {frame!r}")
        try:
            row = primitives.capsule(capsule.a, capsule.b, capsule.radius)
        except RedkinError as exc:
            raise RedkinError(f"{label}: {exc}") from None
        links.append(str(capsule.link))
        frames.append(int(frame))
        ends_a.append(row[2:5])
        ends_b.append(row[5:8])
        radii.append(row[1])
    skipped = set()
    for entry in ignore:
        pair = tuple(entry)
        if len(pair) != 2 or not all(isinstance(name, str) for name in pair):
            raise RedkinError(f"an ignored pair must be two link names, got {entry!r}")
        skipped.add(frozenset(pair))
    frame_array = np.array(frames, dtype=np.int64)
    first, second = np.triu_indices(len(rows), k=1)
    checked = [(i, j) for i, j in zip(first.tolist(), second.tolist())
               if abs(frames[i] - frames[j]) > 1 and links[i] != links[j]
               and frozenset((links[i], links[j])) not in skipped]
    return Body(
        link=tuple(links), frame=frame_array, a=np.array(ends_a).reshape(-1, 3), b=np.array(ends_b).reshape(-1, 3),
        radius=np.array(radii, dtype=float), pairs=np.array(checked, dtype=np.int64).reshape(-1, 2),
        notes=tuple(notes), source=source,
    )


def posed(body: Body, frames: np.ndarray) -> np.ndarray:
    """The body's capsules in the base frame, as primitive rows, at the chain frames ``frames``.

    Parameters
    ----------
    body : Body
    frames : numpy.ndarray, shape (..., n + 2, 4, 4)
        :meth:`redkin.chain.SerialChain.frames` of the body's chain at some joint values.

    Returns
    -------
    numpy.ndarray, shape (..., M, WIDTH)
        Capsule rows of :mod:`redkin.collision.primitives`.
    """
    frames = np.asarray(frames, dtype=float)
    if frames.ndim < 3 or frames.shape[-2:] != (4, 4):
        raise RedkinError(f"frames must have shape (..., n + 2, 4, 4), got {frames.shape}")
    if len(body) and int(body.frame.max()) >= frames.shape[-3]:
        raise RedkinError(f"the body uses frame {int(body.frame.max())}, but only {frames.shape[-3]} frames were "
                          "given")
    lead = frames.shape[:-3]
    flat = kernel_array(frames.reshape((-1,) + frames.shape[-3:]))
    rows = np.empty((len(flat), len(body), primitives.WIDTH))
    run_batch(_body_kernels.posed_rows, len(flat), flat, kernel_array(body.frame), kernel_array(body.a),
              kernel_array(body.b), kernel_array(body.radius), rows)
    return rows.reshape(lead + (len(body), primitives.WIDTH))


def capsule_ends(shapes: np.ndarray) -> np.ndarray:
    """The two ends ``(..., M, 2, 3)`` of capsule rows ``(..., M, WIDTH)`` (:func:`posed`; a ball's centre twice)."""
    return np.stack([shapes[..., 2:5], shapes[..., 5:8]], axis=-2)
