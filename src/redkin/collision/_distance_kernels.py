"""Compiled signed distances between two primitives (rows of :mod:`redkin.collision.primitives`), in closed form.

A sphere and a capsule are both a segment ``p .. q`` (a sphere's of length 0) swollen by a radius, so every pair
this module handles is a segment of radius ``r`` against a segment, a plane or a box:

* segment-segment (:func:`segment_parameters`): the squared distance between ``p1 + s d1`` and ``p2 + t d2`` is a
  convex quadratic over the square ``0 <= s, t <= 1``, so its minimum is the interior stationary point or lies on
  one of the four edges, where it is the clamped projection of an end on the other segment.  All five candidates
  are evaluated and the least kept: no case analysis to get wrong for parallel or zero-length segments.  The
  interior point is computed from ``n = d1 x d2`` (``s = r.(n x d2) / n.n``), not from ``a e - b^2``: that form
  loses twice the digits for nearly parallel segments, and the error left in ``s`` moves the point along a
  direction in which the distance grows only by ``sin(angle)`` times the move, i.e. by rounding;
* segment-plane: the least height ``n.(x - p)`` of the two ends (the segment's height is linear);
* segment-box (:func:`segment_box`): the box's signed distance function ``f`` (outside: the Euclidean distance,
  inside: minus the distance to the nearest face) is convex, so along the segment ``g(t) = f(p + t (q - p))`` is a
  convex function of one variable, smooth except where a coordinate (in the box's frame) crosses ``-h, 0, h`` or two
  coordinates' face distances are equal.  Its minimum is at ``t = 0`` or ``1``, at one of those kinks, or at the
  stationary point of a smooth piece: outside the box a piece is the square root of a quadratic (fixed by which
  coordinates are beyond which face) whose vertex is in closed form, inside it is linear.  Every such candidate
  (at most 2 + 9 + 12 + 26) is evaluated and the least kept, so the minimum is exact up to rounding (measured
  within 1e-15 m of coal and of a golden-section search on shapes of a metre; the tests hold it to 1e-13 m).

The signed distance is then that segment distance minus the radius (or radii): positive the Euclidean distance
between the two solids, negative a penetration depth.  For two round shapes and for a round shape against a plane
it is the depth of the least translation that separates them.  Against a box, a capsule being the union of the
balls of its radius about its segment's points, it is the signed distance of the deepest of those balls: for a
sphere the least separating translation again, for a capsule whose segment enters a box possibly less than that
(coal's EPA depth).

Witness points: ``pa = c_a + r_a u`` and ``pb = c_b - r_b u`` (a box's and a plane's radius is 0, and ``u`` is
written beside them), where
``c_a, c_b`` are the points of the two cores (segment, box, plane) that realise the distance and ``u`` the unit
normal from a to b, so that ``pb - pa = d u``.  Separated, they are the closest points of the two surfaces.
Penetrating, moving a by ``pb - pa`` brings the two into contact for round pairs and planes; against a box it
brings the deepest ball into contact, ``pa`` lies on that ball's surface (on a's surface too, except where ``c_a``
is a kink of the SDF along the segment inside the box, where it lies inside a) and ``pb`` on the box's nearest
face.  Where ``u`` has no direction of its own (segments that meet, a sphere's centre on a segment) it is
``(d1 x d2) / |d1 x d2|``, else a direction across the first segment, else ``+x``.  Round pairs are computed in one
order of the two rows whatever the caller's, so swapping ``a`` and ``b`` swaps the witness points and keeps the
distance bit for bit (except for two equal solids: one order for both).

Inputs are trusted (:mod:`redkin.collision.distances` validates them): rows of
:data:`~redkin.collision.primitives.WIDTH` floats, known kind codes, a box's rotation orthonormal.  A plane's
normal is made a unit vector here.
"""

from __future__ import annotations

from math import inf, isfinite, nan, sqrt

from redkin._compiled import kernel
from redkin.collision.primitives import BOX, CAPSULE, PLANE, SPHERE

#: What :func:`pair_distance` returns.
OK, UNSUPPORTED = 0, 1
#: Length of one output row: the signed distance, then ``pa`` (3), ``pb`` (3) and the unit normal ``u`` (3).
OUT = 10
#: A gap [m] at most this gives no direction (a unit vector divided out of it would be rounding).
_NO_DIRECTION = 1e-100
#: Two segments whose angle has a sine at most this are parallel for the witness normal of segments that meet
#: (their cross product gives no direction of its own).
_PARALLEL = 1e-12


@kernel
def _round(kind):
    """Whether ``kind`` is a sphere or a capsule (a segment with a radius)."""
    return kind == SPHERE or kind == CAPSULE


@kernel
def _gap2(a, b, s, t):
    """Squared distance between the point at ``s`` of a's segment and the point at ``t`` of b's."""
    total = 0.0
    for k in range(3):
        x = a[2 + k] + s * (a[5 + k] - a[2 + k]) - (b[2 + k] + t * (b[5 + k] - b[2 + k]))
        total += x * x
    return total


@kernel
def _clamp01(value):
    """``value`` clamped to ``[0, 1]`` (NaN to 0)."""
    if value >= 1.0:
        return 1.0
    if value > 0.0:
        return value
    return 0.0


@kernel
def segment_parameters(a, b):
    """``(s, t)``: the points ``p1 + s d1`` of a's segment and ``p2 + t d2`` of b's closest to each other.

    The least of five candidates (module docstring): the interior stationary point (its ``s`` from the cross
    product, then ``t`` the best for that ``s``) and the four edges ``s = 0, 1`` and ``t = 0, 1`` of the square,
    each with the other parameter the clamped projection.  A zero-length segment (``d = 0``) keeps parameter 0.
    """
    d1x, d1y, d1z = a[5] - a[2], a[6] - a[3], a[7] - a[4]
    d2x, d2y, d2z = b[5] - b[2], b[6] - b[3], b[7] - b[4]
    rx, ry, rz = a[2] - b[2], a[3] - b[3], a[4] - b[4]
    aa = d1x * d1x + d1y * d1y + d1z * d1z
    ee = d2x * d2x + d2y * d2y + d2z * d2z
    bb = d1x * d2x + d1y * d2y + d1z * d2z
    cc = d1x * rx + d1y * ry + d1z * rz
    ff = d2x * rx + d2y * ry + d2z * rz
    best, best_s, best_t = inf, 0.0, 0.0
    for k in range(5):
        if k == 0:  # interior: s from n = d1 x d2, then the best t for it
            nx, ny, nz = d1y * d2z - d1z * d2y, d1z * d2x - d1x * d2z, d1x * d2y - d1y * d2x
            nn = nx * nx + ny * ny + nz * nz
            if not nn > 0.0:
                continue
            mx, my, mz = ny * d2z - nz * d2y, nz * d2x - nx * d2z, nx * d2y - ny * d2x  # n x d2
            s = _clamp01((rx * mx + ry * my + rz * mz) / nn)
            t = _clamp01((ff + s * bb) / ee)
        elif k <= 2:  # s = 0, 1: t the clamped projection of that end of a on b
            s = float(k - 1)
            t = _clamp01((ff + s * bb) / ee) if ee > 0.0 else 0.0
        else:  # t = 0, 1: s the clamped projection of that end of b on a
            t = float(k - 3)
            s = _clamp01((t * bb - cc) / aa) if aa > 0.0 else 0.0
        gap = _gap2(a, b, s, t)
        if gap < best:
            best, best_s, best_t = gap, s, t
    return best_s, best_t


@kernel
def _across(dx, dy, dz):
    """A unit vector perpendicular to ``(dx, dy, dz)`` (``+x`` for the zero vector)."""
    ax, ay, az = abs(dx), abs(dy), abs(dz)
    if ax == 0.0 and ay == 0.0 and az == 0.0:
        return 1.0, 0.0, 0.0
    if ax <= ay and ax <= az:  # d x e_x
        ux, uy, uz = 0.0, dz, -dy
    elif ay <= az:  # d x e_y
        ux, uy, uz = -dz, 0.0, dx
    else:  # d x e_z
        ux, uy, uz = dy, -dx, 0.0
    length = sqrt(ux * ux + uy * uy + uz * uz)
    return ux / length, uy / length, uz / length


@kernel
def _first(a, b):
    """Whether row ``a`` comes first in the order round pairs are computed in (the lexicographic order of the
    radius and the segment's ends, not the kind: a zero-length capsule is a sphere), so that ``(a, b)`` and
    ``(b, a)`` take the same arithmetic."""
    for k in range(1, 8):
        if a[k] != b[k]:
            return a[k] < b[k]
    return True


@kernel
def round_round(a, b, out):
    """Signed distance of two round shapes (sphere or capsule): the segments' distance minus both radii, exact;
    witness points ``c_a + r_a u`` and ``c_b - r_b u`` from the segments' closest points ``c_a, c_b``, ``u`` from
    ``c_a`` to ``c_b`` (module docstring where they meet).  Computed in :func:`_first`'s order."""
    if _first(a, b):
        _round_round_ordered(a, b, out)
    else:
        _round_round_ordered(b, a, out)
        _swapped(out)


@kernel
def _swapped(out):
    """The witness points of ``out`` swapped and its normal reversed: the pair's output in the other order."""
    for k in range(3):
        out[1 + k], out[4 + k] = out[4 + k], out[1 + k]
        out[7 + k] = -out[7 + k]


@kernel
def _round_round_ordered(a, b, out):
    """:func:`round_round` in the order given."""
    s, t = segment_parameters(a, b)
    cax, cay, caz = a[2] + s * (a[5] - a[2]), a[3] + s * (a[6] - a[3]), a[4] + s * (a[7] - a[4])
    cbx, cby, cbz = b[2] + t * (b[5] - b[2]), b[3] + t * (b[6] - b[3]), b[4] + t * (b[7] - b[4])
    vx, vy, vz = cbx - cax, cby - cay, cbz - caz
    gap = sqrt(vx * vx + vy * vy + vz * vz)
    if gap > _NO_DIRECTION:
        ux, uy, uz = vx / gap, vy / gap, vz / gap
    else:
        d1x, d1y, d1z = a[5] - a[2], a[6] - a[3], a[7] - a[4]
        d2x, d2y, d2z = b[5] - b[2], b[6] - b[3], b[7] - b[4]
        nx, ny, nz = d1y * d2z - d1z * d2y, d1z * d2x - d1x * d2z, d1x * d2y - d1y * d2x
        length = sqrt(nx * nx + ny * ny + nz * nz)
        scale = sqrt((d1x * d1x + d1y * d1y + d1z * d1z) * (d2x * d2x + d2y * d2y + d2z * d2z))
        if length > _NO_DIRECTION and length > _PARALLEL * scale:
            ux, uy, uz = nx / length, ny / length, nz / length
        elif d1x != 0.0 or d1y != 0.0 or d1z != 0.0:
            ux, uy, uz = _across(d1x, d1y, d1z)
        else:
            ux, uy, uz = _across(d2x, d2y, d2z)
    ra, rb = a[1], b[1]
    out[0] = gap - ra - rb
    out[1], out[2], out[3] = cax + ra * ux, cay + ra * uy, caz + ra * uz
    out[4], out[5], out[6] = cbx - rb * ux, cby - rb * uy, cbz - rb * uz
    out[7], out[8], out[9] = ux, uy, uz


@kernel
def round_plane(a, b, out):
    """Signed distance of a round shape ``a`` and the half-space ``b``: the least height of a's segment ends above
    the plane minus a's radius, exact.  ``pa`` lies a radius below the lower end (the first on a tie), ``pb`` is
    that end's projection on the plane; ``u = -n``."""
    nx, ny, nz = b[5], b[6], b[7]
    length = sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx / length, ny / length, nz / length
    low = nx * (a[2] - b[2]) + ny * (a[3] - b[3]) + nz * (a[4] - b[4])
    end = 2
    high = nx * (a[5] - b[2]) + ny * (a[6] - b[3]) + nz * (a[7] - b[4])
    if high < low:
        low, end = high, 5
    radius = a[1]
    out[0] = low - radius
    out[1], out[2], out[3] = a[end] - radius * nx, a[end + 1] - radius * ny, a[end + 2] - radius * nz
    out[4], out[5], out[6] = a[end] - low * nx, a[end + 1] - low * ny, a[end + 2] - low * nz
    out[7], out[8], out[9] = -nx, -ny, -nz


@kernel
def box_sdf(x, y, z, hx, hy, hz):
    """The signed distance function of the box ``|x| <= hx, |y| <= hy, |z| <= hz`` at ``(x, y, z)`` (its frame)."""
    ux, uy, uz = abs(x) - hx, abs(y) - hy, abs(z) - hz
    ox, oy, oz = max(ux, 0.0), max(uy, 0.0), max(uz, 0.0)
    return sqrt(ox * ox + oy * oy + oz * oz) + min(max(ux, max(uy, uz)), 0.0)


@kernel
def _lower(l0, dl, h, t, best_t, best):
    """``(t, f(l0 + t dl))`` where ``t`` is in ``[0, 1]`` and the box SDF there is below ``best``, else
    ``(best_t, best)``."""
    if isfinite(t) and 0.0 <= t <= 1.0:
        value = box_sdf(l0[0] + t * dl[0], l0[1] + t * dl[1], l0[2] + t * dl[2], h[0], h[1], h[2])
        if value < best:
            return t, value
    return best_t, best


@kernel
def segment_box(l0, dl, h):
    """``(t, g)``: the least ``g = f(l0 + t dl)`` over ``0 <= t <= 1`` of the box SDF ``f`` (half sizes ``h``; the
    segment ``l0 + t dl`` in the box's frame; 3-tuples), and the first ``t`` that attains it.

    The candidates of the module docstring: ``t = 0, 1``; each coordinate at ``-h_i, 0, h_i``; each two
    coordinates at equal face distance (``s_i l_i - h_i = s_j l_j - h_j``, four sign pairs); and the vertex of
    ``sum (s_i l_i - h_i)^2`` over each of the 26 choices of a sign ``s_i`` or "within the slab" per coordinate
    (not all within), where ``f`` is the square root of that sum.  Candidates out of ``[0, 1]`` are skipped: a
    convex function's minimum over a piece whose vertex lies beyond the piece is at the piece's end, itself a
    candidate.
    """
    best_t, best = 0.0, box_sdf(l0[0], l0[1], l0[2], h[0], h[1], h[2])
    best_t, best = _lower(l0, dl, h, 1.0, best_t, best)
    for i in range(3):  # coordinate i at -h_i, 0, h_i
        if dl[i] != 0.0:
            for level in range(-1, 2):
                best_t, best = _lower(l0, dl, h, (level * h[i] - l0[i]) / dl[i], best_t, best)
    for i in range(2):  # coordinates i < j at equal face distance
        for j in range(i + 1, 3):
            for si in (-1.0, 1.0):
                for sj in (-1.0, 1.0):
                    den = si * dl[i] - sj * dl[j]
                    if den != 0.0:
                        t = (h[i] - h[j] - si * l0[i] + sj * l0[j]) / den
                        best_t, best = _lower(l0, dl, h, t, best_t, best)
    for m in range(27):  # the vertex of each piece outside the box: base-3 digits of m = (-, within, +) per axis
        num, den = 0.0, 0.0
        for i in range(3):
            sign = (m // (1, 3, 9)[i]) % 3 - 1.0
            if sign != 0.0:
                num += dl[i] * (sign * h[i] - l0[i])
                den += dl[i] * dl[i]
        if den > 0.0:
            best_t, best = _lower(l0, dl, h, num / den, best_t, best)
    return best_t, best


@kernel
def round_round_gap(a, b):
    """A lower bound of the signed distance of two round shapes ``a`` and ``b`` (:func:`round_round`'s), cheap beside
    it: the distance from the middle of the shorter segment to the longer segment, minus the shorter's half length
    and both radii (every point of the shorter segment lies within its half length of its middle), so that a short
    link's capsule beside a long post is bounded by its own length, not the post's."""
    ax, ay, az = a[5] - a[2], a[6] - a[3], a[7] - a[4]
    bx, by, bz = b[5] - b[2], b[6] - b[3], b[7] - b[4]
    if ax * ax + ay * ay + az * az <= bx * bx + by * by + bz * bz:
        return _middle_to_segment(a, b) - a[1] - b[1]
    return _middle_to_segment(b, a) - a[1] - b[1]


@kernel
def _middle_to_segment(a, b):
    """The distance from the middle of round shape ``a``'s segment to ``b``'s segment, minus ``a``'s half length."""
    ax, ay, az = a[5] - a[2], a[6] - a[3], a[7] - a[4]
    bx, by, bz = b[5] - b[2], b[6] - b[3], b[7] - b[4]
    rx, ry, rz = a[2] + 0.5 * ax - b[2], a[3] + 0.5 * ay - b[3], a[4] + 0.5 * az - b[4]
    along, length2 = rx * bx + ry * by + rz * bz, bx * bx + by * by + bz * bz
    if along <= 0.0:  # the nearest point of b's segment: its first end, its second, or between
        t = 0.0
    elif along >= length2:
        t = 1.0
    else:
        t = along / length2
    ex, ey, ez = rx - t * bx, ry - t * by, rz - t * bz
    return sqrt(ex * ex + ey * ey + ez * ez) - 0.5 * sqrt(ax * ax + ay * ay + az * az)


@kernel
def _in_box_frame(a, b):
    """The segment of the round shape ``a`` in the frame of the box ``b``: its first end ``l0`` and ``dl``, the
    second end minus the first (3-tuples)."""
    ex, ey, ez = a[2] - b[2], a[3] - b[3], a[4] - b[4]
    fx, fy, fz = a[5] - a[2], a[6] - a[3], a[7] - a[4]
    # local = R^T world: column j of R (entries b[8 + 3 i + j]) is box axis j
    l0 = (b[8] * ex + b[11] * ey + b[14] * ez, b[9] * ex + b[12] * ey + b[15] * ez,
          b[10] * ex + b[13] * ey + b[16] * ez)
    dl = (b[8] * fx + b[11] * fy + b[14] * fz, b[9] * fx + b[12] * fy + b[15] * fz,
          b[10] * fx + b[13] * fy + b[16] * fz)
    return l0, dl


@kernel
def round_box_gap(a, b):
    """A lower bound of the signed distance of a round shape ``a`` and the box ``b`` (:func:`round_box`'s), cheap
    beside it: the widest gap between the projections of a's segment and of the box on one of the box's axes,
    minus a's radius.  Every point of the box and of the segment is that far apart along that axis, so no two are
    closer; where the projections overlap on all three axes the bound is minus the radius, which is not a bound of
    a depth inside the box: use it only where it is positive."""
    l0, dl = _in_box_frame(a, b)
    gap = 0.0
    for i in range(3):
        low, high = min(l0[i], l0[i] + dl[i]), max(l0[i], l0[i] + dl[i])
        gap = max(gap, low - b[5 + i], -b[5 + i] - high)
    return gap - a[1]


@kernel
def round_box(a, b, out):
    """Signed distance of a round shape ``a`` and the box ``b``: the least of the box's SDF along a's segment
    (:func:`segment_box`) minus a's radius.  At the segment's point ``x`` of that least value, ``pb`` is the
    box's closest surface point (``x`` outside) or ``x``'s projection on the nearest face (inside; the first of
    equally near faces), ``u`` the box's inward normal there (``-`` outward), and ``pa = x + r u``."""
    l0, dl = _in_box_frame(a, b)
    h = (b[5], b[6], b[7])
    t, value = segment_box(l0, dl, h)
    lx, ly, lz = l0[0] + t * dl[0], l0[1] + t * dl[1], l0[2] + t * dl[2]
    # the closest point of the box, in its frame; the outward normal
    px, py, pz = min(max(lx, -h[0]), h[0]), min(max(ly, -h[1]), h[1]), min(max(lz, -h[2]), h[2])
    wx, wy, wz = lx - px, ly - py, lz - pz
    gap = sqrt(wx * wx + wy * wy + wz * wz)
    if value > 0.0 and gap > _NO_DIRECTION:
        wx, wy, wz = wx / gap, wy / gap, wz / gap
    else:  # on or in the box: the nearest face (the first of equals)
        axis, depth = 0, abs(lx) - h[0]
        if abs(ly) - h[1] > depth:
            axis, depth = 1, abs(ly) - h[1]
        if abs(lz) - h[2] > depth:
            axis = 2
        wx, wy, wz = 0.0, 0.0, 0.0
        if axis == 0:
            wx = 1.0 if lx >= 0.0 else -1.0
            px = wx * h[0]
        elif axis == 1:
            wy = 1.0 if ly >= 0.0 else -1.0
            py = wy * h[1]
        else:
            wz = 1.0 if lz >= 0.0 else -1.0
            pz = wz * h[2]
    radius = a[1]
    for k in range(3):
        normal = b[8 + 3 * k] * wx + b[9 + 3 * k] * wy + b[10 + 3 * k] * wz
        out[1 + k] = a[2 + k] + t * (a[5 + k] - a[2 + k]) - radius * normal
        out[4 + k] = b[2 + k] + b[8 + 3 * k] * px + b[9 + 3 * k] * py + b[10 + 3 * k] * pz
        out[7 + k] = -normal
    out[0] = value - radius


@kernel
def pair_distance(a, b, out):
    """Signed distance of the primitives ``a`` and ``b`` (rows of WIDTH) into ``out`` (:data:`OUT`,): the distance,
    then ``pa`` on a, ``pb`` on b and the unit normal ``u`` from a to b (module docstring).  Returns :data:`OK`, or
    :data:`UNSUPPORTED` for a pair without a sphere or a capsule (or an unknown kind), with ``out`` NaN."""
    kind_a, kind_b = a[0], b[0]
    if _round(kind_a):
        if _round(kind_b):
            round_round(a, b, out)
            return OK
        if kind_b == BOX:
            round_box(a, b, out)
            return OK
        if kind_b == PLANE:
            round_plane(a, b, out)
            return OK
    elif _round(kind_b) and (kind_a == BOX or kind_a == PLANE):
        if kind_a == BOX:
            round_box(b, a, out)
        else:
            round_plane(b, a, out)
        _swapped(out)
        return OK
    for k in range(OUT):
        out[k] = nan
    return UNSUPPORTED


@kernel
def distances(start, stop, a, b, out):
    """:func:`pair_distance` of rows ``start .. stop - 1`` of ``a`` (N, WIDTH) and ``b`` (N, WIDTH) into ``out``
    (N, OUT); returns how many of those pairs are unsupported."""
    unsupported = 0
    for n in range(start, stop):
        unsupported += pair_distance(a[n], b[n], out[n])
    return unsupported
