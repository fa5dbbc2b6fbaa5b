"""The shapes of a cell and of an arm's body, as rows of one float array the compiled distances read (issue 40).

Every shape is one row of :data:`WIDTH` numbers, so that a scene or a body is one ``(N, WIDTH)`` array and a kernel
takes any pair without Python objects:

===========  ======================================================================================================
column       meaning
===========  ======================================================================================================
``0``        the kind: :data:`SPHERE`, :data:`CAPSULE`, :data:`BOX` or :data:`PLANE`
``1``        the radius (a sphere's, a capsule's; 0 for a box and a plane)
``2:5``      ``p``: a sphere's centre, a capsule's first end ``a``, a box's centre, a point of a plane
``5:8``      ``q``: a capsule's second end ``b`` (a sphere's centre again), a box's half sizes along its axes, a plane's
             unit normal (pointing out of the solid: the solid is the half-space below the plane)
``8:17``     a box's rotation, row by row (its columns are the box's axes in the frame of the row); the identity on the
             other kinds
===========  ======================================================================================================

A sphere is stored as a capsule whose two ends are one point (``q = p``), so a kernel may treat the two alike.
Lengths are metres, in the frame the rows are given in (a scene's: the arm's base frame).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_rotation, check_vectors
from redkin.errors import RedkinError

#: The kinds, column 0 of a row.
SPHERE, CAPSULE, BOX, PLANE = 0, 1, 2, 3
#: The kinds' names, by code.
KIND_NAMES = {SPHERE: "sphere", CAPSULE: "capsule", BOX: "box", PLANE: "plane"}
#: Numbers per row.
WIDTH = 17
#: The smallest length of a plane's normal before it is made a unit vector [m]: a shorter one gives no direction.
_SHORTEST_NORMAL = 1e-9


def sphere(center: ArrayLike, radius: float) -> np.ndarray:
    """A sphere's row: ``center`` (3,) and ``radius`` >= 0 (a point for 0)."""
    point = _point(center, "sphere center")
    return _row(SPHERE, _radius(radius, "sphere radius"), point, point)


def capsule(a: ArrayLike, b: ArrayLike, radius: float) -> np.ndarray:
    """A capsule's row: the points within ``radius`` >= 0 of the segment from ``a`` (3,) to ``b`` (3,)."""
    return _row(CAPSULE, _radius(radius, "capsule radius"), _point(a, "capsule end a"), _point(b, "capsule end b"))


def box(center: ArrayLike, size: ArrayLike, rotation: ArrayLike | None = None) -> np.ndarray:
    """A box's row: its ``center`` (3,), its edge lengths ``size`` (3,) > 0 along its axes, and ``rotation`` (3, 3)
    whose columns are those axes (default: the frame's)."""
    sizes = _point(size, "box size")
    if np.any(sizes <= 0.0):
        raise RedkinError(f"box size must be three lengths > 0, got {sizes.tolist()}")
    turn = np.eye(3) if rotation is None else check_rotation(rotation, "box rotation")
    if turn.shape != (3, 3):
        raise RedkinError(f"box rotation must be one 3x3 matrix, got shape {turn.shape}")
    return _row(BOX, 0.0, _point(center, "box center"), sizes / 2.0, turn)


def plane(point: ArrayLike, normal: ArrayLike) -> np.ndarray:
    """A plane's row: the solid half-space below the plane through ``point`` (3,) with outward ``normal`` (3,),
    made a unit vector."""
    direction = _point(normal, "plane normal")
    length = float(np.linalg.norm(direction))
    if length < _SHORTEST_NORMAL:
        raise RedkinError(f"plane normal must be a non-zero vector, got {direction.tolist()}")
    return _row(PLANE, 0.0, _point(point, "plane point"), direction / length)


def _row(kind: int, radius: float, p: np.ndarray, q: np.ndarray, rotation: np.ndarray | None = None) -> np.ndarray:
    row = np.zeros(WIDTH)
    row[0], row[1], row[2:5], row[5:8] = kind, radius, p, q
    row[8:17] = (np.eye(3) if rotation is None else rotation).ravel()
    return row


def _point(value: ArrayLike, name: str) -> np.ndarray:
    if _holds_no_number(value):  # YAML's true, false and quoted text are no coordinates, though numpy reads them
        raise RedkinError(f"{name} must be three numbers, got {value!r}")
    array = check_vectors(value, 3, name)
    if array.shape != (3,):
        raise RedkinError(f"{name} must be three numbers, got shape {array.shape}")
    return array


def _radius(value: float, name: str) -> float:
    if _holds_no_number(value):
        raise RedkinError(f"{name} must be a number >= 0, got {value!r}")
    try:
        radius = float(value)
    except (TypeError, ValueError):
        raise RedkinError(f"{name} must be a number >= 0, got {value!r}") from None
    if not (np.isfinite(radius) and radius >= 0.0):
        raise RedkinError(f"{name} must be a finite number >= 0, got {value!r}")
    return radius


def _holds_no_number(value: object) -> bool:
    """Whether ``value`` is a bool or text (``true``, ``'0.1'``: numpy reads them as 1 and 0.1), or a list or tuple
    holding one (at any depth)."""
    if isinstance(value, bool | np.bool_ | str | bytes):
        return True
    return isinstance(value, list | tuple) and any(_holds_no_number(item) for item in value)
