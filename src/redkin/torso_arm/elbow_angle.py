"""The elbow angle phi: rotation of the shoulder-elbow-wrist plane (section 3.3, thesis 001).

With the shoulder ``S`` and the wrist ``W`` fixed, the elbow ``E`` lies on a
circle about the axis ``n = (W - S) / l`` (``l = |W - S|``): centre
``h = S + n L1 cos(ESW)`` (section 3.3.1), radius ``r = |hE| = 2 Area / l``
(eqs. 3.2-3.3, Heron).  The elbow at angle phi is

    E(phi) = h + r (cos(phi) e1 + sin(phi) e2),   e2 = n x e1,

i.e. phi turns **right-handed about the shoulder->wrist axis** (this fixes
the +/- of eq. 3.12: the thesis's ``I_b = I_a x SW / |.|`` equals ``-e2``,
so our sense is the lower sign of eq. 3.12 in the thesis's basis).

Eqs. 3.4-3.6 hold for every point of the circle, so they do not fix the
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
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from redkin.torso_arm.geometry import TorsoArm
from redkin.validation import check_vectors

#: Elbow circles with a smaller radius (metres) count as a single elbow point.
RADIUS_TOLERANCE = 1e-12
#: Below this length a projected reference vector counts as zero.
REFERENCE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class ElbowReference:
    """Where phi = 0: ``kind="theta4"`` (thesis rule) or ``kind="vector"`` with ``vector`` (world)."""

    kind: Literal["theta4", "vector"] = "theta4"
    vector: tuple[float, float, float] = (0.0, 1.0, 0.0)

    def __post_init__(self) -> None:
        if self.kind not in ("theta4", "vector"):
            raise ValueError(f"elbow reference kind must be 'theta4' or 'vector', got {self.kind!r}")
        v = check_vectors(self.vector, 3, "reference vector").reshape(-1)
        if v.shape != (3,) or np.linalg.norm(v) < REFERENCE_TOLERANCE:
            raise ValueError(f"reference vector must be one non-zero 3-vector, got {self.vector!r}")
        object.__setattr__(self, "vector", tuple(float(x) for x in v))

    def mirrored(self) -> "ElbowReference":
        """The reference of the mirror image in ``x = 0``."""
        x, y, z = self.vector
        return ElbowReference(self.kind, (-x, y, z))


def as_reference(value: "ElbowReference | str | ArrayLike | None") -> ElbowReference:
    """``None`` or ``"theta4"`` -> thesis rule; ``"vector"`` -> +y; a 3-vector -> that vector."""
    if value is None:
        return ElbowReference()
    if isinstance(value, ElbowReference):
        return value
    if isinstance(value, str):
        if value not in ("theta4", "vector"):
            raise ValueError(f"reference must be 'theta4', 'vector' or a 3-vector, got {value!r}")
        return ElbowReference(value)
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


def elbow_circle(arm: TorsoArm, shoulder: np.ndarray, wrist: np.ndarray) -> ElbowCircle:
    """The elbow circle (sections 3.3.1-3.3.2) for right-arm shoulders and wrists."""
    shoulder, wrist = np.broadcast_arrays(shoulder, wrist)
    sw = wrist - shoulder
    l = np.linalg.norm(sw, axis=-1)
    L1, lew = arm.L1, arm.forearm
    tol = 1e-12 * (L1 + lew)
    reachable = (l >= abs(L1 - lew) - tol) & (l <= L1 + lew + tol) & (l > 0)
    safe_l = np.where(l > 0, l, 1.0)
    n = sw / safe_l[..., None]
    cos_s = np.clip((L1**2 + safe_l**2 - lew**2) / (2 * L1 * safe_l), -1.0, 1.0)  # law of cosines in SEW
    centre = shoulder + n * (L1 * cos_s)[..., None]
    radius = L1 * np.sqrt(1.0 - cos_s**2)
    return ElbowCircle(shoulder, wrist, n, centre, radius, l, reachable)


def _perpendicular_unit(vector: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    v = vector - np.sum(vector * n, axis=-1, keepdims=True) * n
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(norm > 0, norm, 1.0), norm[..., 0] > REFERENCE_TOLERANCE


def _fallback_basis(n: np.ndarray) -> np.ndarray:
    """A unit vector orthogonal to ``n``: the +y projection, or +z where ``n`` is along y."""
    e1, ok = _perpendicular_unit(np.broadcast_to([0.0, 1.0, 0.0], n.shape), n)
    e1z, _ = _perpendicular_unit(np.broadcast_to([0.0, 0.0, 1.0], n.shape), n)
    return np.where(ok[..., None], e1, e1z)


def reference_direction(arm: TorsoArm, circle: ElbowCircle, reference: ElbowReference) -> tuple[np.ndarray, np.ndarray]:
    """Unit vector ``e1`` (phi = 0) orthogonal to the axis, and whether it exists.

    Returns
    -------
    e1 : numpy.ndarray, shape (..., 3)
    exists : numpy.ndarray of bool, shape (...)
        False means "no reference": no elbow angle can be measured there.
    """
    n = circle.axis
    if reference.kind == "vector":
        e1, exists = _perpendicular_unit(np.broadcast_to(reference.vector, n.shape), n)
        return e1, exists
    b1 = _fallback_basis(n)
    b2 = np.cross(n, b1)
    S, W, h, r = circle.shoulder, circle.wrist, circle.centre, circle.radius
    L1 = arm.L1
    a = S / arm.L0  # joint-2 axis z2
    kappa = (np.sum((W - h) * (h - S), axis=-1) - r**2) / L1  # f . u, constant on the circle
    alpha1, alpha2 = np.sum(b1 * a, axis=-1), np.sum(b2 * a, axis=-1)
    amplitude = np.hypot(alpha1, alpha2)
    scale = r * (1.0 + kappa / L1)
    rhs = np.sum((W - h) * a, axis=-1) - kappa * np.sum(a * (h - S), axis=-1) / L1
    safe = (amplitude > REFERENCE_TOLERANCE) & (np.abs(scale) > RADIUS_TOLERANCE)
    ratio = np.where(safe, rhs / np.where(safe, scale * amplitude, 1.0), 2.0)
    real = safe & (np.abs(ratio) <= 1.0)
    centre_angle = np.arctan2(alpha2, alpha1)
    spread = np.arccos(np.clip(ratio, -1.0, 1.0))
    best_e1 = np.zeros(n.shape)
    best_cos = np.full(n.shape[:-1], -np.inf)
    for root in (centre_angle + spread, centre_angle - spread):
        rho = np.cos(root)[..., None] * b1 + np.sin(root)[..., None] * b2
        elbow = h + r[..., None] * rho
        u = (elbow - S) / L1
        f = W - elbow
        theta4_zero = np.sum(f * np.cross(a, u), axis=-1) > 0.0  # theta_4 = 0, not pi, in the principal branch
        better = real & theta4_zero & (np.cos(root) > best_cos)
        best_e1 = np.where(better[..., None], rho, best_e1)
        best_cos = np.where(better, np.cos(root), best_cos)
    exists = np.isfinite(best_cos)
    point = circle.radius <= RADIUS_TOLERANCE  # a single elbow: any reference will do
    e1 = np.where(point[..., None], b1, best_e1)
    return e1, exists | point


def elbow_position(circle: ElbowCircle, e1: np.ndarray, phi: ArrayLike) -> np.ndarray:
    """``E(phi) = h + r (cos(phi) e1 + sin(phi) n x e1)`` (eqs. 3.8-3.14, sense fixed right-handed)."""
    phi = np.asarray(phi, dtype=float)
    e2 = np.cross(circle.axis, e1)
    rho = np.cos(phi)[..., None] * e1 + np.sin(phi)[..., None] * e2
    return circle.centre + circle.radius[..., None] * rho


def elbow_angle(arm: TorsoArm, shoulder: ArrayLike, elbow: ArrayLike, wrist: ArrayLike,
                reference: "ElbowReference | str | ArrayLike | None" = None) -> tuple[np.ndarray, np.ndarray]:
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
