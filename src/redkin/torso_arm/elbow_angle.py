"""The elbow angle phi: rotation of the shoulder-elbow-wrist plane (section 3.3, thesis 001).

With the shoulder ``S`` and the wrist ``W`` fixed, the elbow ``E`` lies on a
circle about the axis ``n = (W - S) / l`` (``l = |W - S|``): centre
``h = S + n L1 cos(ESW)`` (section 3.3.1), radius ``r = |hE| = 2 Area / l``
([001 eqs. 3.2-3.3], Heron).  The elbow at angle phi is

    E(phi) = h + r (cos(phi) e1 + sin(phi) e2),   e2 = n x e1,

i.e. phi turns **right-handed about the shoulder->wrist axis** (this fixes
the +/- of [001 eq. 3.12]: the thesis's ``I_b = I_a x SW / |.|`` equals ``-e2``,
so our sense is the lower sign of [001 eq. 3.12] in the thesis's basis).

[001 eqs. 3.4-3.6] hold for every point of the circle, so they do not fix the
reference ``e1`` (phi = 0).  Two explicit references are offered
(:class:`ElbowReference`):

* ``"theta4"`` (the thesis's rule "phi = 0 at theta_4 = 0"): the elbow where
  the principal branch (``cos theta_3 >= 0``, ``theta_5 = asin(k) - delta``)
  has ``theta_4 = 0``.  ``theta_4`` is 0 or pi exactly when the forearm
  ``f = W - E`` lies in the plane of the upper arm ``u`` and the joint-3
  axis, i.e. ``f . (z2 - (z2 . u) u) = 0`` with ``z2 = S / L0`` the joint-2
  axis.  On the circle this is ``alpha1 cos(phi) + alpha2 sin(phi) = rho``
  (derived here; 0 or 2 roots).  The root with ``theta_4 = 0`` (not pi) has
  ``f . (z2 x u) > 0``.  If no root qualifies there is **no reference**; if
  two do, the one nearer the ``+y`` projection is taken.
* ``"vector"``: ``e1`` is the component of a fixed world vector orthogonal
  to ``n``; no reference when the vector is parallel to ``n``.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import acos, atan2, cos, inf, sin, sqrt
from typing import Literal, cast

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel, run_batch
from redkin._validation import check_vectors
from redkin.errors import RedkinError
from redkin.torso_arm._kernel_tools import add, cross, dot, flat, norm, put, row, scale, sub
from redkin.torso_arm.geometry import TorsoArm

#: Elbow circles with a smaller radius (metres) count as a single elbow point.
_RADIUS_TOLERANCE = 1e-12
#: Where an elbow angle phi = 0 is measured from (see :class:`ElbowReference`).
ReferenceKind = Literal["theta4", "vector"]
#: Below this length a projected reference vector counts as zero.
_REFERENCE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class ElbowReference:
    """Where phi = 0: ``kind="theta4"`` (thesis rule) or ``kind="vector"`` with ``vector`` (world)."""

    kind: ReferenceKind = "theta4"
    vector: tuple[float, float, float] = (0.0, 1.0, 0.0)

    def __post_init__(self) -> None:
        if self.kind not in ("theta4", "vector"):
            raise RedkinError(f"elbow reference kind must be 'theta4' or 'vector', got {self.kind!r}")
        v = check_vectors(self.vector, 3, "reference vector").reshape(-1)
        if v.shape != (3,) or np.linalg.norm(v) < _REFERENCE_TOLERANCE:
            raise RedkinError(f"reference vector must be one non-zero 3-vector, got {self.vector!r}")
        object.__setattr__(self, "vector", tuple(float(x) for x in v))

    def mirrored(self) -> ElbowReference:
        """The reference of the mirror image in ``x = 0``."""
        x, y, z = self.vector
        return ElbowReference(self.kind, (-x, y, z))


def as_reference(value: ElbowReference | str | ArrayLike | None) -> ElbowReference:
    """``None`` or ``"theta4"`` -> thesis rule; ``"vector"`` -> +y; a 3-vector -> that vector."""
    if value is None:
        return ElbowReference()
    if isinstance(value, ElbowReference):
        return value
    if isinstance(value, str):
        if value not in ("theta4", "vector"):
            raise RedkinError(f"reference must be 'theta4', 'vector' or a 3-vector, got {value!r}")
        return ElbowReference(cast(ReferenceKind, value))
    return ElbowReference("vector", tuple(np.asarray(value, dtype=float).reshape(-1)))


@dataclass(frozen=True)
class ElbowCircle:
    """The circle of elbow positions for shoulders ``S`` and wrists ``W`` (arrays ``(..., 3)``).

    ``reachable`` is false where ``l`` is outside ``[|L1 - l_ew|, L1 + l_ew]``.
    """

    shoulder: np.ndarray
    wrist: np.ndarray
    axis: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    length: np.ndarray
    reachable: np.ndarray


#: Codes of the phi = 0 reference in the kernels: a fixed world vector, the thesis's theta_4 = 0 rule,
#: or any basis (the +y projection, +z where the axis is along y) for work that sweeps the whole circle.
VECTOR, THETA4, ANY_BASIS = 0, 1, 2


# ------------------------------------------------------------------ kernels
@kernel
def circle_one(shoulder, wrist, L1, lew):
    """The elbow circle (sections 3.3.1-3.3.2) of a shoulder and a wrist (3-tuples).

    Returns ``(n, centre, radius, length, reachable)``: the axis ``n = (W - S) / l``,
    the centre ``h = S + n L1 cos(ESW)`` (law of cosines in the triangle SEW),
    the radius ``r = L1 sin(ESW)`` (``= 2 Area / l``, [001 eqs. 3.2-3.3]), ``l = |W - S|``
    and whether ``l`` lies in ``[|L1 - l_ew|, L1 + l_ew]`` (to ``1e-12 (L1 + l_ew)``).
    """
    sw = sub(wrist, shoulder)
    length = norm(sw)
    tol = 1e-12 * (L1 + lew)
    reachable = length >= abs(L1 - lew) - tol and length <= L1 + lew + tol and length > 0.0
    safe = length if length > 0.0 else 1.0
    n = scale(sw, 1.0 / safe)
    cos_s = min(max((L1 * L1 + safe * safe - lew * lew) / (2.0 * L1 * safe), -1.0), 1.0)
    return n, add(shoulder, scale(n, L1 * cos_s)), L1 * sqrt(1.0 - cos_s * cos_s), length, reachable


@kernel
def _perpendicular_unit(vector, n):
    """``(e, ok)``: the unit component of ``vector`` orthogonal to the unit ``n``; ``ok`` if it is not ~0."""
    v = sub(vector, scale(n, dot(vector, n)))
    size = norm(v)
    return (scale(v, 1.0 / size) if size > 0.0 else v), size > _REFERENCE_TOLERANCE


@kernel
def _any_basis(n):
    """A unit vector orthogonal to ``n``: the +y projection, or +z where ``n`` is along y."""
    e1, ok = _perpendicular_unit((0.0, 1.0, 0.0), n)
    return e1 if ok else _perpendicular_unit((0.0, 0.0, 1.0), n)[0]


@kernel
def reference_one(kind, vector, shoulder, wrist, n, centre, radius, L0, L1):
    """``(e1, exists)``: where phi = 0 on one elbow circle, for the reference ``kind`` (:data:`VECTOR` ...).

    ``THETA4`` solves ``alpha1 cos(phi) + alpha2 sin(phi) = rho`` on the circle
    (module docstring) and keeps the root with ``f . (z2 x u) > 0`` nearest
    the +y projection; a circle of radius ~0 takes any basis.
    """
    if kind == VECTOR:
        return _perpendicular_unit(vector, n)
    b1 = _any_basis(n)
    if kind == ANY_BASIS:
        return b1, True
    if radius <= _RADIUS_TOLERANCE:  # a single elbow: any reference will do
        return b1, True
    b2 = cross(n, b1)
    a = scale(shoulder, 1.0 / L0)  # joint-2 axis z2
    to_wrist, from_shoulder = sub(wrist, centre), sub(centre, shoulder)
    kappa = (dot(to_wrist, from_shoulder) - radius * radius) / L1  # f . u, constant on the circle
    alpha1, alpha2 = dot(b1, a), dot(b2, a)
    amplitude = sqrt(alpha1 * alpha1 + alpha2 * alpha2)
    size = radius * (1.0 + kappa / L1)
    rhs = dot(to_wrist, a) - kappa * dot(a, from_shoulder) / L1
    if not (amplitude > _REFERENCE_TOLERANCE and abs(size) > _RADIUS_TOLERANCE):
        return b1, False
    ratio = rhs / (size * amplitude)
    if abs(ratio) > 1.0:
        return b1, False
    middle, spread = atan2(alpha2, alpha1), acos(ratio)
    best, best_cos = b1, -inf
    for root in (middle + spread, middle - spread):
        c, s = cos(root), sin(root)
        rho = (c * b1[0] + s * b2[0], c * b1[1] + s * b2[1], c * b1[2] + s * b2[2])
        elbow = add(centre, scale(rho, radius))
        u = scale(sub(elbow, shoulder), 1.0 / L1)
        # theta_4 = 0, not pi, in the principal branch; the root nearer the +y projection wins
        if dot(sub(wrist, elbow), cross(a, u)) > 0.0 and c > best_cos:
            best, best_cos = rho, c
    return best, best_cos > -inf


@kernel
def elbow_one(centre, radius, n, e1, phi):
    """``E(phi) = h + r (cos(phi) e1 + sin(phi) n x e1)`` ([001 eqs. 3.8-3.14], sense fixed right-handed), with
    ``e2 = n x e1 = -I_b`` of [001 eq. 3.7]."""
    e2 = cross(n, e1)
    c, s = cos(phi), sin(phi)
    return add(centre, scale((c * e1[0] + s * e2[0], c * e1[1] + s * e2[1], c * e1[2] + s * e2[2]), radius))


@kernel
def circles(start, stop, shoulder, wrist, L1, lew, axis, centre, radius, length, reachable):
    """:func:`circle_one` for each item: ``shoulder``, ``wrist`` (N, 3) -> the fields of :class:`ElbowCircle`."""
    for i in range(start, stop):
        _circle_item(shoulder, wrist, L1, lew, axis, centre, radius, length, reachable, i)


@kernel
def _circle_item(shoulder, wrist, L1, lew, axis, centre, radius, length, reachable, i):
    n, h, radius[i], length[i], reachable[i] = circle_one(row(shoulder, i), row(wrist, i), L1, lew)
    put(axis, i, n)
    put(centre, i, h)


@kernel
def references(start, stop, kind, vector, shoulder, wrist, axis, centre, radius, L0, L1, e1, exists):
    """:func:`reference_one` for each item (arrays as in :func:`circles`) -> ``e1`` (N, 3), ``exists`` (N,)."""
    for i in range(start, stop):
        _reference_item(kind, vector, shoulder, wrist, axis, centre, radius, L0, L1, e1, exists, i)


@kernel
def _reference_item(kind, vector, shoulder, wrist, axis, centre, radius, L0, L1, e1, exists, i):
    e, exists[i] = reference_one(kind, (vector[0], vector[1], vector[2]), row(shoulder, i), row(wrist, i),
                                 row(axis, i), row(centre, i), radius[i], L0, L1)  # a 3-tuple, as the maps pass it
    put(e1, i, e)


@kernel
def elbows(start, stop, centre, radius, axis, e1, phi, out):
    """:func:`elbow_one` for each item: ``centre``, ``axis``, ``e1`` (N, 3), ``radius``, ``phi`` (N,) ->
    ``out`` (N, 3)."""
    for i in range(start, stop):
        put(out, i, elbow_one(row(centre, i), radius[i], row(axis, i), row(e1, i), phi[i]))


# -------------------------------------------------------------- public API
def elbow_circle(arm: TorsoArm, shoulder: np.ndarray, wrist: np.ndarray) -> ElbowCircle:
    """The elbow circle (sections 3.3.1-3.3.2) for right-arm shoulders and wrists ``(..., 3)`` (trusted)."""
    shape, (S, W) = flat((shoulder, 1), (wrist, 1))
    count = S.shape[0]
    axis, centre = np.empty((count, 3)), np.empty((count, 3))
    radius, length, reachable = np.empty(count), np.empty(count), np.empty(count, dtype=bool)
    run_batch(circles, count, S, W, arm.L1, arm.forearm, axis, centre, radius, length, reachable)
    return ElbowCircle(*(a.reshape(shape + a.shape[1:]) for a in (S, W, axis, centre, radius, length, reachable)))


def reference_direction(arm: TorsoArm, circle: ElbowCircle, reference: ElbowReference) -> tuple[np.ndarray, np.ndarray]:
    """Unit vector ``e1`` (phi = 0) orthogonal to the axis, and whether it exists.

    Returns
    -------
    e1 : numpy.ndarray, shape (..., 3)
    exists : numpy.ndarray of bool, shape (...)
        False means "no reference": no elbow angle can be measured there.
    """
    shape, arrays = flat(*((getattr(circle, name), 1) for name in ("shoulder", "wrist", "axis", "centre")),
                         (circle.radius, 0))
    count = arrays[0].shape[0]
    e1, exists = np.empty((count, 3)), np.empty(count, dtype=bool)
    kind = VECTOR if reference.kind == "vector" else THETA4
    run_batch(references, count, kind, np.array(reference.vector), *arrays,
              arm.L0, arm.L1, e1, exists)
    return e1.reshape(shape + (3,)), exists.reshape(shape)


def elbow_position(circle: ElbowCircle, e1: np.ndarray, phi: ArrayLike) -> np.ndarray:
    """``E(phi) = h + r (cos(phi) e1 + sin(phi) n x e1)`` [001 eqs. 3.8-3.14], right-handed, ``(..., 3)``."""
    shape, (centre, radius, axis, basis, angle) = flat((circle.centre, 1), (circle.radius, 0), (circle.axis, 1),
                                                      (e1, 1), (phi, 0))
    out = np.empty((centre.shape[0], 3))
    run_batch(elbows, centre.shape[0], centre, radius, axis, basis, angle, out)
    return out.reshape(shape + (3,))


def elbow_angle(arm: TorsoArm, shoulder: ArrayLike, elbow: ArrayLike, wrist: ArrayLike,
                reference: ElbowReference | str | ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Elbow angle phi of a right-arm posture given by its shoulder, elbow and wrist points.

    Returns
    -------
    phi : numpy.ndarray, shape (...)
        In ``(-pi, pi]``, NaN where there is no reference.
    exists : numpy.ndarray of bool, shape (...)
    """
    S = check_vectors(shoulder, 3, "shoulder")
    E = check_vectors(elbow, 3, "elbow")
    W = check_vectors(wrist, 3, "wrist")
    circle = elbow_circle(arm, S, W)
    e1, exists = reference_direction(arm, circle, as_reference(reference))
    radial = E - circle.centre
    phi = np.arctan2(np.sum(np.cross(e1, radial) * circle.axis, axis=-1), np.sum(e1 * radial, axis=-1))
    return np.where(exists, phi, np.nan), exists
