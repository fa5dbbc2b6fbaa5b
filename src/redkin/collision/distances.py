"""Signed distances between primitives (spheres, capsules, boxes, planes), batched and in closed form (issue 40).

:func:`signed_distance` takes two batches of primitive rows (:mod:`redkin.collision.primitives`) that broadcast
against each other (one obstacle against every body of an arm: ``(WIDTH,)`` against ``(N, WIDTH)``) and returns,
per pair, the signed distance and a witness point on each shape.

What it handles: a sphere or a capsule against a sphere, a capsule, a box or a plane, in either order (an arm's
body is spheres and capsules).  Box-box, box-plane and plane-plane pairs are refused.

What it computes, and how exactly (the compiled kernels, :mod:`redkin.collision._distance_kernels`, give the
derivations):

* the distance is *signed*: positive, the Euclidean distance between the two solids; negative, a penetration
  depth; zero, touching;
* sphere or capsule against sphere or capsule: the distance between the two segments (a sphere's of length 0)
  minus both radii, exact up to rounding, also for parallel and zero-length segments and when negative (it is
  then the depth of the least separating translation);
* against a plane (the solid half-space below it, column ``q`` its outward normal): the least height of the
  segment's two ends above the plane minus the radius, exact up to rounding;
* against a box (solid): the least of the box's exact signed distance function along the segment (outside: the
  Euclidean distance to the box; inside: minus the distance to the nearest face) minus the radius.  That least
  value is found in closed form among at most 49 candidate points of the segment (its ends, the kinks of the
  function and the stationary points of its smooth pieces), so it is exact up to rounding: within 1e-15 m of a
  golden-section search on the convex function (random and axis-aligned shapes of a metre) and of coal (hpp-fcl's
  successor) on random ones; the tests hold it to 1e-13 m.  Penetrating, a capsule being the union of the balls of
  its radius about its segment's points, this is the signed distance of the deepest of those balls: for a sphere
  the least translation that separates the two (coal's depth), for a capsule whose segment enters the box possibly
  less than that (coal's EPA depth); both are 0 at contact and negative inside, and ours is the least of a signed
  distance function along the segment.

Witness points: ``point_b - point_a = distance * u``, ``u`` a unit normal from ``a`` towards ``b``; each lies a
radius (0 for a box or a plane) along ``u`` from the point of its shape's core (segment, box, plane) that realises
the distance.  Separated, they are the closest points of the two surfaces (any of them where several are).
Penetrating, they lie on the two surfaces and moving ``a`` by ``point_b - point_a`` brings the two into contact,
except against a box: there ``point_b`` lies on the box's nearest face and ``point_a`` on the surface of the deepest
ball (inside ``a`` where the ball's centre is a kink of the box's signed distance along the segment), and the move
brings that ball into contact.  Swapping ``a`` and ``b`` gives the same distance, bit for bit, with the points
swapped (except for two equal solids).

Example
-------
>>> from redkin.collision import primitives
>>> from redkin.collision.distances import signed_distance
>>> body = primitives.capsule([0.0, 0.0, 0.0], [0.0, 0.0, 0.5], 0.05)
>>> result = signed_distance(body, primitives.box([0.3, 0.0, 0.25], [0.2, 0.2, 0.2]))
>>> round(float(result.distance), 12), result.point_b.round(12).tolist()
(0.15, [0.2, 0.0, 0.15])
"""

from __future__ import annotations

from math import prod
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_finite, check_rotation
from redkin.collision import _distance_kernels
from redkin.collision.primitives import BOX, CAPSULE, KIND_NAMES, PLANE, SPHERE, WIDTH
from redkin.errors import RedkinError

__all__ = ["Distance", "signed_distance", "trusted_distances"]

#: A plane's normal shorter than this [m] gives no direction (the kernel makes the normal a unit vector).
_SHORTEST_NORMAL = 1e-9


class Distance(NamedTuple):
    """The signed distances of pairs of primitives and their witness points (module docstring).

    Attributes
    ----------
    distance : numpy.ndarray, shape (...)
        Signed distance [m]: > 0 apart, 0 touching, < 0 penetrating (minus the depth).
    point_a : numpy.ndarray, shape (..., 3)
        The witness point on the surface of ``a`` (of its deepest ball where a capsule penetrates a box).
    point_b : numpy.ndarray, shape (..., 3)
        The witness point on the surface of ``b``; ``point_b - point_a = distance * u``, ``u`` a unit normal from
        ``a`` towards ``b``.
    """

    distance: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray


def signed_distance(a: ArrayLike, b: ArrayLike) -> Distance:
    """Signed distances and witness points of the primitives ``a`` and ``b``, pair by pair.

    Parameters
    ----------
    a, b : array_like, shape (..., WIDTH)
        Primitive rows (:mod:`redkin.collision.primitives`: :func:`~redkin.collision.primitives.sphere`,
        :func:`~redkin.collision.primitives.capsule`, :func:`~redkin.collision.primitives.box`,
        :func:`~redkin.collision.primitives.plane`); their batch axes broadcast against each other.  In each pair,
        one of the two must be a sphere or a capsule.

    Returns
    -------
    Distance
        ``distance`` (...), ``point_a`` (..., 3) and ``point_b`` (..., 3) over the broadcast batch axes.

    Raises
    ------
    redkin.errors.RedkinError
        A :class:`ValueError`, for rows of another width, NaN or infinity, an unknown kind code, a negative radius
        (a box's or a plane's must be 0), a sphere whose second point is not its centre, a box size that is not
        > 0, a box rotation that is not a proper rotation (within 1e-6), a plane normal shorter than 1e-9, batch
        axes that do not broadcast, or a pair of two shapes neither of which is a sphere or a capsule.
    """
    rows_a, rows_b = _rows(a, "a"), _rows(b, "b")
    try:
        shape = np.broadcast_shapes(rows_a.shape[:-1], rows_b.shape[:-1])
    except ValueError:
        raise RedkinError(f"a of shape {rows_a.shape} and b of shape {rows_b.shape} do not broadcast: their batch "
                          f"axes {rows_a.shape[:-1]} and {rows_b.shape[:-1]} differ") from None
    size = prod(shape)
    flat_a = kernel_array(rows_a, shape + (WIDTH,)).reshape(size, WIDTH)
    flat_b = kernel_array(rows_b, shape + (WIDTH,)).reshape(size, WIDTH)
    out, unsupported = _measured(flat_a, flat_b)
    if unsupported:
        _refuse_pair(flat_a[:, 0], flat_b[:, 0], shape)
    return Distance(out[:, 0].reshape(shape), out[:, 1:4].reshape(shape + (3,)), out[:, 4:7].reshape(shape + (3,)))


def trusted_distances(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The signed distances ``(N,)`` of rows a caller made itself, without :func:`signed_distance`'s checks: ``a`` and
    ``b`` are ``(N, WIDTH)`` float64 rows of valid primitives, each pair with a sphere or a capsule (a posed body
    against a :class:`~redkin.collision.scene.Scene`'s obstacles).  An unsupported pair is ``nan``."""
    return _measured(kernel_array(a), kernel_array(b))[0][:, 0]


def _measured(flat_a: np.ndarray, flat_b: np.ndarray) -> tuple[np.ndarray, int]:
    """The kernels' rows ``(N, 7)`` (distance, then the two witness points) and how many pairs were unsupported."""
    out = np.empty((len(flat_a), _distance_kernels.OUT))
    return out, run_batch(_distance_kernels.distances, len(flat_a), flat_a, flat_b, out)


def _rows(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as finite primitive rows (..., WIDTH) whose columns mean what their kind says, or a
    :class:`~redkin.errors.RedkinError` naming the first row at fault and what it lacks."""
    rows = as_float_array(value, name)
    if rows.ndim == 0 or rows.shape[-1] != WIDTH:
        raise RedkinError(f"{name} must be primitive rows of shape (..., {WIDTH}) (redkin.collision.primitives), "
                          f"got shape {rows.shape}")
    check_finite(rows, name)
    flat = rows.reshape(-1, WIDTH)
    kind, radius, p, q = flat[:, 0], flat[:, 1], flat[:, 2:5], flat[:, 5:8]
    codes = ", ".join(f"{code} ({word})" for code, word in KIND_NAMES.items())
    faults = (
        (~np.isin(kind, list(KIND_NAMES)), f"a kind code in column 0 (the kinds are {codes})"),
        (np.where(kind <= CAPSULE, radius < 0.0, radius != 0.0),
         "a radius in column 1 that is >= 0 on a sphere or a capsule and 0 on a box or a plane"),
        ((kind == SPHERE) & np.any(q != p, axis=-1), "a sphere's centre repeated in columns 5:8"),
        ((kind == BOX) & np.any(q <= 0.0, axis=-1), "a box's half sizes > 0 in columns 5:8"),
        ((kind == PLANE) & (np.linalg.norm(q, axis=-1) < _SHORTEST_NORMAL), "a plane's non-zero normal in columns 5:8"),
    )
    for bad, needed in faults:
        if bad.any():
            raise RedkinError(f"{_row_name(name, rows.shape[:-1], int(np.argmax(bad)))} is not a primitive row "
                              f"(redkin.collision.primitives): it needs {needed}")
    boxes = np.flatnonzero(kind == BOX)
    for index in boxes:  # each box's rotation, worded by the library's check
        check_rotation(flat[index, 8:].reshape(3, 3), f"the rotation (columns 8:17) of the box "
                                                      f"{_row_name(name, rows.shape[:-1], int(index))}")
    return rows


def _row_name(name: str, shape: tuple[int, ...], index: int) -> str:
    """``name[i, j]``: the row ``index`` of the flattened batch ``shape`` (``name`` alone for one row)."""
    if not shape:
        return name
    return f"{name}[{', '.join(str(int(i)) for i in np.unravel_index(index, shape))}]"


def _refuse_pair(kind_a: np.ndarray, kind_b: np.ndarray, shape: tuple[int, ...]) -> None:
    """Raise for the first pair the kernel did not handle (neither shape a sphere nor a capsule)."""
    bad = (kind_a > CAPSULE) & (kind_b > CAPSULE)
    index = int(np.argmax(bad))
    where = tuple(int(i) for i in np.unravel_index(index, shape))
    at = f" (pair {where[0] if len(where) == 1 else where} of the batch)" if where else ""
    raise RedkinError(f"a {KIND_NAMES[int(kind_a[index])]} against a {KIND_NAMES[int(kind_b[index])]}{at} has no "
                      f"signed distance here: one shape of each pair must be a sphere or a capsule")
