"""Capsules and boxes that cover a mesh (issue 40): the body of a link whose description gives its collision shape as
a mesh, and a scene's mesh obstacles.

The compiled distances and the certified sets read primitives only, so a link's mesh is covered by one to three
capsules that contain it (:func:`covering_capsules`; the body's capsules), and an obstacle's by one to three oriented
boxes (:func:`covering_boxes`; a box fits a fixture's flat faces, and a box against a capsule is a compiled
distance), each with how much larger it is.

The fit.
    A capsule around the segment ``a``-``b`` with radius ``r`` contains a convex set when it contains its vertices.
    For an axis direction ``u``, the radius is that of the smallest circle enclosing the vertices projected on the
    plane normal to ``u`` (Welzl's algorithm), and the segment is the shortest one along ``u`` through the circle's
    centre that keeps every vertex within ``r``: a vertex at height ``t`` and distance ``rho <= r`` from the axis
    needs the segment to reach ``t -+ sqrt(r^2 - rho^2)``.  The axis minimises the capsule's volume
    ``pi r^2 L + 4/3 pi r^3``: the principal axes of the vertices and the frame's axes are tried, and the best one is
    refined by Nelder-Mead over its tilt.  The radius is then the greatest distance of a vertex from the segment,
    so the capsule contains every vertex whatever the rounding of the steps before.

Several capsules (or boxes).
    A bent part (an L- or V-shaped casting, a hand with its fingers) is covered badly by one capsule.  The
    mesh is cut by parallel planes into slabs; each slab's part of the surface has for vertices the mesh vertices
    inside the slab and the points where the mesh's edges cross the planes, so the capsule containing those points
    contains that part, and the capsules together contain the whole surface (and the solid it bounds, when the
    mesh is closed: each slab's cap lies in the hull of its rim).  Cuts across the principal axes and the frame's axes
    at several heights are tried; a second and a third capsule are used where each cuts the capsules' summed volume
    by at least a quarter (:data:`_WORTH_ANOTHER`), or where the caller asks for at least that many (``least``: two
    links that nearly touch over a bend may overlap as capsules far more often than as meshes).

What the capsules add.
    :attr:`MeshCapsule.reach` bounds the greatest distance from a point of the capsule to the convex hull of the
    points it covers, within 1 mm.  Distance to a convex set is a convex function, so over a capsule its greatest
    value is on one of the two end spheres.  On each, the distance is measured at the vertices of a subdivided
    icosahedron; no point of a face lies farther from the hull than its corners' farthest plus ``r`` times the
    face's circumradius (a distance changes no faster than the point moves), and faces whose bound is not within
    1 mm of the farthest distance measured are split in four, until none is (or after :data:`_REACH_SPLITS` rounds,
    where the bound, still sound, may be looser).

The meshes are read by :mod:`redkin.collision.mesh_files`; this module sees vertices and faces only.  Computing the
hull's distances needs ``trimesh`` (the ``mesh`` extra).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, NamedTuple, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import use_compiled
from redkin._extras import missing_extra
from redkin.collision._mesh_kernels import capsule_along
from redkin.errors import RedkinError

#: The most points of a piece the cuts are ranked by (a fixed choice among a big mesh's thousands).
_RANKING_POINTS = 400
#: The least edge of a box round a flat part [m] (a box has edges > 0).
_THINNEST = 1e-9
#: A further capsule is used where it cuts the covered volume to at most this fraction of the fewer capsules' one.
_WORTH_ANOTHER = 0.75
#: Heights of the cutting planes tried, as fractions of the mesh's extent along the cut's normal.
_CUT_HEIGHTS = np.linspace(0.15, 0.85, 8)
#: The icosahedron's subdivisions on which the bound of each end sphere's distance to the hull starts (162 vertices).
_SPHERE_SUBDIVISIONS = 2
#: How far above the greatest distance measured the bound of :attr:`MeshCapsule.reach` may be [m].
_REACH_TOLERANCE = 1e-3
#: The most times a face of the icosahedron is split for that bound (beyond, the bound is looser than the tolerance).
_REACH_SPLITS = 8


class MeshCapsule(NamedTuple):
    """A capsule that covers (part of) a mesh, in the mesh's frame.

    Attributes
    ----------
    a, b : numpy.ndarray, shape (3,)
        The segment's ends [m].
    radius : float
        [m]
    reach : float
        An upper bound of the greatest distance from a point of the capsule to the convex hull of the part of the
        mesh it covers [m] (module docstring).
    """

    a: np.ndarray
    b: np.ndarray
    radius: float
    reach: float


class MeshBox(NamedTuple):
    """An oriented box that covers (part of) a mesh, in the mesh's frame.

    Attributes
    ----------
    center : numpy.ndarray, shape (3,)
        [m]
    size : numpy.ndarray, shape (3,)
        Its edge lengths along its axes [m].
    rotation : numpy.ndarray, shape (3, 3)
        Its axes as columns.
    reach : float
        The greatest distance from a point of the box to the convex hull of the part of the mesh it covers [m].
    """

    center: np.ndarray
    size: np.ndarray
    rotation: np.ndarray
    reach: float


def covering_capsules(vertices: ArrayLike, faces: ArrayLike, most: int = 3, *, least: int = 1) -> list[MeshCapsule]:
    """One to ``most`` capsules that together contain a mesh's surface (and its solid, for a closed mesh).

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        [m], finite.
    faces : array_like of int, shape (F, 3)
        Triangles as indices into ``vertices``.
    most : int
        The most capsules to use (1 to 3).
    least : int
        The fewest capsules to use where the mesh can be cut into that many parts (1 to ``most``): more pieces are
        kept even where they do not save a quarter of the volume.

    Returns
    -------
    list of MeshCapsule
        The capsules, each with the bound of how far it reaches beyond the hull of the part it covers.

    Raises
    ------
    RedkinError
        For vertices that are not finite or not an ``(V, 3)`` array, faces that index no vertex, or no faces; and
        where the ``mesh`` extra (trimesh, which measures the reach) is not installed.
    """
    used, edges = _surface(vertices, faces, most)
    if not 1 <= least <= most:
        raise RedkinError(f"least must be 1 to most ({most}) pieces, got {least!r}")
    return _covers(used, edges, most, _capsule, _capsule_volume, _quick_capsule_volume, least)


def covering_boxes(vertices: ArrayLike, faces: ArrayLike, most: int = 3) -> list[MeshBox]:
    """One to ``most`` oriented boxes that together contain a mesh's surface (and its solid, for a closed mesh): an
    obstacle given as a mesh (module docstring).

    Parameters and errors as :func:`covering_capsules`; each box is the least-volume one trimesh finds round its
    part, and its reach is exact (a box's farthest point from a convex set is one of its corners).
    """
    used, edges = _surface(vertices, faces, most)
    return _covers(used, edges, most, _box, _box_volume, _quick_box_volume)


def _surface(vertices: ArrayLike, faces: ArrayLike, most: int) -> tuple[np.ndarray, np.ndarray]:
    """The mesh's vertices that some face uses, and its edges as ``(E, 2, 3)`` end points (checked)."""
    points = np.asarray(vertices, dtype=float)
    triangles = np.asarray(faces)
    if points.ndim != 2 or points.shape[1] != 3 or not np.all(np.isfinite(points)):
        raise RedkinError(f"mesh vertices must be a finite (V, 3) array, got shape {points.shape}")
    if (triangles.ndim != 2 or triangles.shape[1] != 3 or triangles.size == 0
            or not np.issubdtype(triangles.dtype, np.integer)
            or triangles.min() < 0 or triangles.max() >= len(points)):
        raise RedkinError("mesh faces must be a non-empty (F, 3) array of vertex indices")
    if most not in (1, 2, 3):
        raise RedkinError(f"most must be 1, 2 or 3 pieces, got {most!r}")
    edges = np.unique(np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]),
                              axis=1), axis=0)
    return points[np.unique(triangles)], points[edges]


_Cover = TypeVar("_Cover")


def _covers(used: np.ndarray, edges: np.ndarray, most: int, cover: Callable[[np.ndarray], _Cover],
            volume: Callable[[_Cover], float], quick: Callable[[np.ndarray], float], least: int = 1) -> list[_Cover]:
    """One to ``most`` shapes ``cover`` makes round the mesh's parts (module docstring, "Several capsules"): the
    cuts ranked by ``quick`` (a fast volume of one part's cover), a further part kept up to ``least`` parts, and
    beyond where the shapes' summed ``volume`` drops to :data:`_WORTH_ANOTHER` of the fewer's.  Its kernels run
    compiled, in a command that runs small work as Python too (:func:`redkin._compiled.use_compiled`): covering a
    maker's mesh takes seconds compiled and minutes as Python."""
    use_compiled()
    covers = [cover(used)]
    axes = _cut_axes(used)
    for count in range(2, most + 1):
        cut = _best_slabs(edges, used, axes, count, quick)
        if cut is None:
            break
        more = [cover(slab) for slab in cut[0]]
        if count > least and sum(map(volume, more)) > _WORTH_ANOTHER * sum(map(volume, covers)):
            break
        covers = more
        axes = cut[1][None]  # a third part: cuts parallel to the second's (every axis again is dear)
    return covers


def _capsule(points: np.ndarray) -> MeshCapsule:
    """The refined capsule of one piece's points, with its reach."""
    a, b, radius = _fit(points, refine=True)
    return MeshCapsule(a, b, radius, _reach(a, b, radius, points))


def _capsule_volume(capsule: MeshCapsule) -> float:
    return _volume(capsule.radius, float(np.linalg.norm(capsule.b - capsule.a)))


def _quick_capsule_volume(points: np.ndarray) -> float:
    """The volume of the unrefined capsule round the points."""
    a, b, radius = _fit(points, refine=False)
    return _volume(radius, float(np.linalg.norm(b - a)))


def _box(points: np.ndarray) -> MeshBox:
    """The least-volume oriented box trimesh finds round the points, made to hold them exactly, with its reach: the
    farthest of its corners from the points' hull."""
    trimesh = _trimesh()
    try:
        with np.errstate(divide="ignore", invalid="ignore"):  # a flat part's mass properties: 0 / 0 in trimesh
            to_box, _ = trimesh.bounds.oriented_bounds(points)
        rotation = np.linalg.inv(to_box)[:3, :3]
    except Exception:  # a flat or straight part, where trimesh's hull fails: the frame's axes
        rotation = np.eye(3)
    if not np.all(np.isfinite(rotation)):
        rotation = np.eye(3)
    if np.linalg.det(rotation) < 0.0:
        rotation[:, 2] *= -1.0
    local = points @ rotation
    low, high = local.min(axis=0), local.max(axis=0)
    size = np.maximum(high - low, _THINNEST)
    center = rotation @ ((low + high) / 2.0)
    corners = center + (np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
                        * size) @ rotation.T
    return MeshBox(center, size, rotation, float(np.max(_hull_distances(corners, _hull(points)))))


def _box_volume(box: MeshBox) -> float:
    return float(np.prod(box.size))


def _quick_box_volume(points: np.ndarray) -> float:
    """The volume of the box round the points along their principal axes."""
    local = points @ _candidate_axes(points)[:3].T
    return float(np.prod(np.maximum(local.max(axis=0) - local.min(axis=0), _THINNEST)))


def _best_slabs(edges: np.ndarray, points: np.ndarray, axes: np.ndarray, count: int,
                quick: Callable[[np.ndarray], float]) -> tuple[list[np.ndarray], np.ndarray] | None:
    """The cut into ``count`` slabs (across one of ``axes``, at :data:`_CUT_HEIGHTS`) whose covers have the least
    total ``quick`` volume: the slabs' points and the cut's axis (``None`` where no cut leaves every slab points)."""
    best: tuple[list[np.ndarray], np.ndarray, float] | None = None
    for axis in axes:
        heights = points @ axis
        low, high = heights.min(), heights.max()
        if high - low <= 0.0:
            continue
        cuts = low + _CUT_HEIGHTS * (high - low)
        for chosen in _increasing(len(cuts), count - 1):
            slabs = _slabs(edges, points, axis, cuts[list(chosen)])
            if any(len(slab) < 2 for slab in slabs):
                continue
            total = sum(quick(_thinned(slab)) for slab in slabs)
            if best is None or total < best[2]:
                best = (slabs, axis, total)
    return None if best is None else best[:2]


def _thinned(points: np.ndarray) -> np.ndarray:
    """At most :data:`_RANKING_POINTS` of the points, a fixed choice, to rank the cuts by (each cut's pieces are then
    covered whole)."""
    if len(points) <= _RANKING_POINTS:
        return points
    return points[np.random.default_rng(0).choice(len(points), _RANKING_POINTS, replace=False)]


def _increasing(size: int, count: int) -> list[tuple[int, ...]]:
    """Every increasing ``count``-tuple of ``range(size)``."""
    if count == 0:
        return [()]
    return [(first,) + rest for first in range(size) for rest in _increasing(size, count - 1)
            if not rest or rest[0] > first]


def _slabs(edges: np.ndarray, points: np.ndarray, axis: np.ndarray, planes: np.ndarray) -> list[np.ndarray]:
    """The points of each slab between consecutive ``planes`` (heights along ``axis``, increasing; the first and last
    slabs unbounded): the vertices in it and the points where the edges (``(E, 2, 3)``) cross its planes."""
    heights = points @ axis
    ends = edges @ axis  # (E, 2)
    crossings = []
    for plane in planes:
        first, second = ends[:, 0] - plane, ends[:, 1] - plane
        across = first * second < 0.0
        share = first[across] / (first[across] - second[across])
        crossings.append(edges[across, 0] + share[:, None] * (edges[across, 1] - edges[across, 0]))
    bounds = np.concatenate([[-np.inf], planes, [np.inf]])
    slabs = []
    for k in range(len(bounds) - 1):
        inside = points[(heights >= bounds[k]) & (heights <= bounds[k + 1])]
        rims = [crossings[j] for j in (k - 1, k) if 0 <= j < len(planes)]
        slabs.append(np.concatenate([inside, *rims]))
    return slabs


def _candidate_axes(points: np.ndarray) -> np.ndarray:
    """The principal axes of the points, then the frame's x, y and z: ``(6, 3)`` unit rows."""
    centred = points - points.mean(axis=0)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    return np.concatenate([vectors.T[::-1], np.eye(3)])


def _cut_axes(points: np.ndarray) -> np.ndarray:
    """The normals of the cuts tried: the candidate axes, and the two halfway between each pair of principal axes and
    each pair of the frame's axes (a bend's cut is oblique): ``(18, 3)`` unit rows."""
    axes = _candidate_axes(points)
    between = [(axes[i] + sign * axes[j]) / np.sqrt(2.0) for group in (0, 3) for i, j in ((0, 1), (0, 2), (1, 2))
               for i, j in [(group + i, group + j)] for sign in (1.0, -1.0)]
    return np.concatenate([axes, between])


def _fit(points: np.ndarray, refine: bool) -> tuple[np.ndarray, np.ndarray, float]:
    """The least-volume capsule containing the points over the candidate axes (refined by Nelder-Mead over the best
    one's tilt when ``refine``): its ends and radius (module docstring)."""
    points = np.ascontiguousarray(points)
    best = min((_along(points, axis) for axis in _candidate_axes(points)), key=lambda fit: fit[3])
    if refine:
        from scipy.optimize import minimize

        axis = best[1] - best[0]
        start = axis / np.linalg.norm(axis) if np.linalg.norm(axis) > 0.0 else np.array([0.0, 0.0, 1.0])
        first, second = _normal_pair(start)

        def volume(tilt: np.ndarray) -> float:
            return _along(points, start + tilt[0] * first + tilt[1] * second)[3]

        found = minimize(volume, np.zeros(2), method="Nelder-Mead",
                         options={"xatol": 1e-4, "fatol": 1e-12, "initial_simplex": [[0, 0], [0.1, 0], [0, 0.1]]})
        tilted = _along(points, start + found.x[0] * first + found.x[1] * second)
        best = min(best, tilted, key=lambda fit: fit[3])
    a, b = best[0], best[1]
    return a, b, float(np.max(_distance_to_segment(points, a, b)))


def _along(points: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The shortest capsule along ``direction`` containing the points: its ends, radius and volume
    (:func:`redkin.collision._mesh_kernels.capsule_along`)."""
    ends, radius, volume = capsule_along(np.ascontiguousarray(points, dtype=float),
                                         direction / np.linalg.norm(direction), _order(len(points)))
    return ends[0], ends[1], radius, volume


@functools.cache
def _order(count: int) -> np.ndarray:
    """A fixed shuffled order of ``count`` points, in which Welzl's algorithm is expected linear."""
    return np.random.default_rng(0).permutation(count)


def _volume(radius: float, length: float) -> float:
    """A capsule's volume."""
    return float(np.pi * radius ** 2 * length + 4.0 / 3.0 * np.pi * radius ** 3)


def _normal_pair(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors normal to the unit ``axis`` and to each other."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    first = np.cross(axis, helper)
    first /= np.linalg.norm(first)
    return first, np.cross(axis, first)


def _distance_to_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Each point's distance from the segment ``a``-``b``."""
    axis = b - a
    length = float(np.dot(axis, axis))
    share = np.zeros(len(points)) if length == 0.0 else np.clip((points - a) @ axis / length, 0.0, 1.0)
    return np.linalg.norm(points - (a + share[:, None] * axis), axis=1)


def _reach(a: np.ndarray, b: np.ndarray, radius: float, points: np.ndarray) -> float:
    """An upper bound, within :data:`_REACH_TOLERANCE`, of the greatest distance from a point of the capsule to the
    points' convex hull (module docstring): over each end sphere, branch and bound on the faces of a subdivided
    icosahedron."""
    hull = _hull(points)
    directions, faces = _icosphere()
    return max(_sphere_reach(centre, radius, hull, directions, faces) for centre in (a, b))


def _hull(points: np.ndarray) -> Any:
    """scipy's convex hull of the points: of its joggled points where they are flat, and where they are fewer than
    four or on a line (a single triangle, a rod), of the points moved a hair (1e-9 of their span, at least 1e-9 m)
    along each axis both ways, so that the over-approximation it measures is short by at most that."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        return ConvexHull(points)
    except QhullError:
        pass
    try:
        return ConvexHull(points, qhull_options="QJ")
    except QhullError:
        hair = 1e-9 * max(float(np.ptp(points, axis=0).max()), 1.0)
        return ConvexHull(np.concatenate([points + hair * way for way in np.concatenate([np.eye(3), -np.eye(3)])]))


def _sphere_reach(centre: np.ndarray, radius: float, hull, directions: np.ndarray, faces: np.ndarray) -> float:
    """The bound of :func:`_reach` over the sphere of ``radius`` round ``centre``.  A face's points lie within its
    circumradius (on the sphere) of a corner, and a distance changes no faster than the point moves, so no point of
    a face is farther from the hull than its corners' farthest plus ``radius`` times that circumradius; faces whose
    bound exceeds the farthest corner measured by more than the tolerance are split in four."""
    directions = directions.copy()
    values = _hull_distances(centre + radius * directions, hull)
    for _ in range(_REACH_SPLITS):
        corners = directions[faces]
        bounds = values[faces].max(axis=1) + radius * _circumradii(corners)
        split = bounds > values.max() + _REACH_TOLERANCE
        if not np.any(split):
            break
        halves = corners[split][:, [0, 1, 2]] + corners[split][:, [1, 2, 0]]
        halves /= np.linalg.norm(halves, axis=2, keepdims=True)  # the midpoints of the edges 01, 12, 20
        first = len(directions)
        directions = np.concatenate([directions, halves.reshape(-1, 3)])
        values = np.concatenate([values, _hull_distances(centre + radius * halves.reshape(-1, 3), hull)])
        mid = first + 3 * np.arange(int(split.sum()))[:, None] + np.arange(3)  # (S, 3): m01, m12, m20
        old = faces[split]
        faces = np.concatenate([faces[~split],
                                np.stack([old[:, 0], mid[:, 0], mid[:, 2]], axis=1),
                                np.stack([mid[:, 0], old[:, 1], mid[:, 1]], axis=1),
                                np.stack([mid[:, 2], mid[:, 1], old[:, 2]], axis=1),
                                mid])
    return float(np.max(values[faces].max(axis=1) + radius * _circumradii(directions[faces])))


def _circumradii(corners: np.ndarray) -> np.ndarray:
    """Per spherical triangle (``(F, 3, 3)`` unit corners, each face acute), the chord from its corners to the point
    of the sphere equally far from all three."""
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals *= np.sign(np.sum(normals * corners[:, 0], axis=1))[:, None]  # the face's side of the sphere
    return np.linalg.norm(normals - corners[:, 0], axis=1)


def _hull_distances(samples: np.ndarray, hull) -> np.ndarray:
    """Each sample's distance to the hull (0 inside): outside, the nearest point of a facet it lies above."""
    trimesh = _trimesh()
    gaps = np.zeros(len(samples))
    sample, facet = np.nonzero(samples @ hull.equations[:, :3].T + hull.equations[:, 3] > 0.0)
    if len(sample):
        nearest = trimesh.triangles.closest_point(hull.points[hull.simplices[facet]], samples[sample])
        found = np.full(len(samples), np.inf)
        np.minimum.at(found, sample, np.linalg.norm(nearest - samples[sample], axis=1))
        gaps = np.where(np.isfinite(found), found, 0.0)
    return gaps


@functools.cache
def _icosphere() -> tuple[np.ndarray, np.ndarray]:
    """The unit vertices and faces of a subdivided icosahedron, where the branch and bound starts."""
    trimesh = _trimesh()
    sphere = trimesh.creation.icosphere(subdivisions=_SPHERE_SUBDIVISIONS)
    directions = sphere.vertices / np.linalg.norm(sphere.vertices, axis=1, keepdims=True)
    directions.flags.writeable = False
    faces = np.asarray(sphere.faces)
    faces.flags.writeable = False
    return directions, faces


def _trimesh() -> Any:
    """The ``trimesh`` module, or the error naming the extra that installs it."""
    try:
        import trimesh
    except ImportError:
        raise RedkinError(missing_extra("covering a mesh with capsules needs trimesh", "mesh")) from None
    return trimesh
