"""Joint lines to DH rows: the standard DH chain whose joints turn about given lines.

Joint ``k`` of a revolute chain turns the rest of the chain about a line.
Standard DH rows reproduce any chain of such lines exactly: frame ``k - 1``
has its z axis on line ``k`` and its x axis on the common normal of lines
``k - 1`` and ``k``; with ``theta_k = offset_k + q_k`` turning about the same
line by the same angle, every downstream body moves the same way.  Parallel
lines take the common normal through the previous frame's origin (``d = 0``),
intersecting lines their intersection (``a = 0``), and the same line repeats
the previous frame.  The last row is a pure turn (``a = d = alpha = 0``).

Used by the URDF import (:mod:`redkin.urdf`), to bring an S-R-S arm in any
convention to paper 000's Table 1 form (:mod:`redkin.srs.conventions`) and a
Franka-class arm to its solver's form (:mod:`redkin.franka.geometry`); the
last two share :func:`meeting_point` and :func:`certify_same_poses`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # the chain module imports nothing from here; typing only
    from redkin.chain import SerialChain

#: ``|sin|`` of the angle between two joint axes below which they count as parallel.  Axes tilted by ``t``
#: off parallel have their common normal ``offset / t`` away, and the chain built on it loses about
#: ``eps * offset^2 / t^2`` to rounding (measured: 2.5e-4 m at t = 1e-7, 3.8e-6 m at 1e-6, 1.3e-8 m at 1e-5,
#: for a 0.5 m offset); counted as parallel they lose ``t * length``.  The two meet near 2e-6, where the
#: error is largest: a few micrometres per metre.
PARALLEL_TOLERANCE = 2e-6
_DISTANCE_TOLERANCE = 1e-12


def dh_rows_from_lines(
    points: np.ndarray, directions: np.ndarray, alpha_signs: np.ndarray | None = None, origin: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Standard DH rows whose joints turn about the given lines, with the poses of frames 0 and n.

    Parameters
    ----------
    points, directions : numpy.ndarray, shape (n, 3)
        A point on each joint line and its unit direction (positive turns by the right hand).
    alpha_signs : numpy.ndarray, shape (n,), optional
        Wanted sign of each row's twist ``alpha``: where the computed twist has
        the other sign, the row's x axis (the common normal) is turned over,
        which is as valid a DH frame (``a`` and ``alpha`` change sign).
    origin : numpy.ndarray, shape (3,), optional
        The point of line 1 where frame 0 starts (default ``points[0]``).

    Returns
    -------
    rows : numpy.ndarray, shape (n, 4)
        ``(a, alpha, d, offset)`` per row, ``offset`` the DH angle at ``q = 0``.
    frame0, frame_n : numpy.ndarray, shape (4, 4)
        Poses of frames 0 and n at ``q = 0`` (the base, and what the tool maps from).
    """
    n = len(points)
    z = directions[0]
    x = _perpendicular(z)
    frames = [_frame(x, z, points[0] if origin is None else origin)]
    rows = np.zeros((n, 4))
    for k in range(n):
        previous = frames[-1]
        o, x0, z0 = previous[:3, 3], previous[:3, 0], previous[:3, 2]
        if k + 1 < n:
            start, x1, z1 = _next_frame(o, x0, z0, points[k + 1], directions[k + 1])
        else:  # the last row: a pure turn about line n
            start, x1, z1 = o, x0, z0
        alpha = float(np.arctan2(np.cross(z0, z1) @ x1, z0 @ z1))
        if alpha_signs is not None and alpha * alpha_signs[k] < 0.0:
            x1, alpha = -x1, -alpha
        d = float((start - o) @ z0)  # along z0 to the foot of the common normal (x1 is normal to z0)
        a = float((start - o) @ x1)
        offset = float(np.arctan2(np.cross(x0, x1) @ z0, x0 @ x1))
        rows[k] = a, alpha, d, offset
        frames.append(_frame(x1, z1, start))
    return rows, frames[0], frames[-1]


def _next_frame(o, x0, z0, point, direction):
    """Origin, x and z of the frame whose z lies on the next joint line (standard DH)."""
    z1 = direction
    normal = np.cross(z0, z1)
    if np.linalg.norm(normal) > PARALLEL_TOLERANCE:  # skew or intersecting lines: the common normal
        x1 = normal / np.linalg.norm(normal)
        # feet of the common normal: o + s z0 and point + t z1 with (o + s z0) - (point + t z1) parallel to x1
        matrix = np.column_stack([z0, -z1, -x1])
        _, t, _ = np.linalg.solve(matrix, point - o)
        return point + t * z1, x1, z1
    # parallel lines: the common normal through o (d = 0)
    offset = point - o
    across = offset - (offset @ z0) * z0
    distance = np.linalg.norm(across)
    foot = point - (offset @ z1) * z1  # the point of the next line closest to o
    if distance <= _DISTANCE_TOLERANCE:  # the same line: repeat the frame, a = 0
        return o, x0, z1
    return foot, across / distance, z1


def _perpendicular(z: np.ndarray) -> np.ndarray:
    """A unit vector normal to ``z``: the base link's x axis projected, else its y axis."""
    for guess in (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        x = guess - (guess @ z) * z
        if np.linalg.norm(x) > 0.1:
            return x / np.linalg.norm(x)
    raise AssertionError("unreachable: x or y is far from any unit z")


def _frame(x: np.ndarray, z: np.ndarray, origin: np.ndarray) -> np.ndarray:
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 2] = x, z
    frame[:3, 1] = np.cross(z, x)
    frame[:3, 3] = origin
    return frame


def meeting_point(points: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, float]:
    """The point closest to the lines (least squares) and the largest distance of a line from it."""
    projectors = np.eye(3) - directions[:, :, None] * directions[:, None, :]
    point = np.linalg.lstsq(projectors.sum(axis=0), np.einsum("kij,kj->i", projectors, points), rcond=None)[0]
    distances = np.linalg.norm(np.einsum("kij,kj->ki", projectors, point - points), axis=-1)
    return point, float(distances.max())


def certify_same_poses(chain: SerialChain, converted: SerialChain, form: str) -> None:
    """A chain rewritten in another form (``form`` names it) must give the original's poses, checked on fixed
    sample configurations; a failure is a bug in the conversion."""
    from redkin.errors import RedkinError

    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (16, chain.n))
    error = float(np.max(np.abs(converted.fk(q) - chain.fk(q))))
    scale = max(1.0, float(np.max(np.abs(chain.fk(q)[..., :3, 3]))))
    if error > 1e-9 * scale:  # pragma: no cover - a failure here is a bug in the conversion
        raise RedkinError(f"{chain.name!r}: its {form} differs from it by {error:.3g} m; please report this")
