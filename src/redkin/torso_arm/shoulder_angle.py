"""The shoulder angle psi: the redundancy of the torso joint (section 3.2, thesis 001).

Section 3.2 defines psi in words: the plane through the neck ``B`` (base
origin), the shoulder ``S`` and the wrist ``W`` turns about the neck->wrist
axis, and psi = 0 in the posture with ``theta_1 = 0``.  The default here is
exactly that rotation, signed (right-handed about ``n = W / |W|``):

    psi(theta_1) = atan2(n . (s0 x s), s0 . s),

with ``s0``, ``s`` the components of ``S(0)`` and ``S(theta_1)`` orthogonal
to ``n``.  The shoulder circle ``S(theta_1)`` (radius ``L0`` about the torso
axis ``y``) projects onto the plane orthogonal to ``n`` as an ellipse
centred on the axis, so psi is strictly monotone in theta_1 (increasing when
``W_y > 0``, decreasing when ``W_y < 0``) and one turn of theta_1 is one turn
of psi.  The inverse is closed form (:func:`theta1_from_shoulder_angle`).
It is undefined when ``W_y = 0`` (the ellipse degenerates to a segment).

[001 eq. 3.1] instead takes the unsigned angle ``S h' S'`` at the midpoint
``h' = W / 2``; it is not monotone in theta_1 and several theta_1 share one
psi.  It is offered literally, with every root, by
:func:`shoulder_angle_eq31` / :func:`theta1_from_shoulder_angle_eq31`.
"""

from __future__ import annotations

from math import atan2, cos, nan, sin

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel, run_batch
from redkin._validation import as_float_array, check_finite, check_vectors
from redkin.errors import RedkinError
from redkin.torso_arm._kernel_tools import cross, dot, flat, norm, row, scale, shoulder_point

#: Below this ``|W_y| / |W|`` the signed shoulder angle is undefined.
_SHOULDER_TOLERANCE = 1e-9


# ------------------------------------------------------------------ kernels
@kernel
def _reference_basis(wrist):
    """``(n, e1, e2, ok)`` of a right-arm wrist ``W`` (3-tuple): the neck->wrist axis and psi's basis.

    ``n = W / |W|``; ``e1`` is the unit component of ``+x`` orthogonal to
    ``n`` (the shoulder's direction at theta_1 = 0, where psi = 0, section
    3.2) and ``e2 = n x e1``; ``ok`` is false where psi is undefined.
    """
    length = norm(wrist)
    n = scale(wrist, 1.0 / length) if length > 0.0 else wrist
    s0 = (1.0 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2])
    size = norm(s0)
    ok = size > _SHOULDER_TOLERANCE and abs(n[1]) > _SHOULDER_TOLERANCE
    e1 = scale(s0, 1.0 / size) if size > 0.0 else s0
    return n, e1, cross(n, e1), ok


@kernel
def _psi_one(theta1, wrist, L0):
    """psi = ``atan2(S . e2, S . e1)`` of the shoulder ``S(theta_1)`` (section 3.2, signed); NaN where undefined."""
    _, e1, e2, ok = _reference_basis(wrist)
    if not ok:
        return nan
    s = shoulder_point(L0, theta1)
    return atan2(dot(s, e2), dot(s, e1))


@kernel
def _theta1_one(psi, wrist):
    """``(theta_1, defined)`` with ``_psi_one(theta_1, wrist) = psi``: ``atan2(-sgn(n_y) v_x, -sgn(n_y) v_z)``,
    ``v = n x (cos(psi) e1 + sin(psi) e2)``; theta_1 NaN where undefined."""
    n, e1, e2, ok = _reference_basis(wrist)
    if not ok:
        return nan, False
    c, s = cos(psi), sin(psi)
    v = cross(n, (c * e1[0] + s * e2[0], c * e1[1] + s * e2[1], c * e1[2] + s * e2[2]))
    sign = -1.0 if n[1] >= 0.0 else 1.0
    return atan2(sign * v[0], sign * v[2]), True


@kernel
def _shoulder_angles(start, stop, theta1, wrist, L0, out):
    """:func:`_psi_one` for each item: ``theta1`` (N,), ``wrist`` (N, 3) -> ``out`` (N,)."""
    for i in range(start, stop):
        out[i] = _psi_one(theta1[i], row(wrist, i), L0)


@kernel
def _torso_angles(start, stop, psi, wrist, out, defined):
    """:func:`_theta1_one` for each item: ``psi`` (N,), ``wrist`` (N, 3) -> ``out`` (N,), ``defined`` (N,) bool."""
    for i in range(start, stop):
        out[i], defined[i] = _theta1_one(psi[i], row(wrist, i))


# -------------------------------------------------------------- public API
def shoulder_angle(theta1: ArrayLike, wrist: ArrayLike, L0: float = 1.0) -> np.ndarray:
    """Signed shoulder angle psi of the right arm (section 3.2, rotation about the neck->wrist axis).

    Parameters
    ----------
    theta1 : array_like, shape (...)
        Torso angle in radians.
    wrist : array_like, shape (..., 3)
        Wrist position ``W`` in the base frame (metres).
    L0 : float
        Neck-to-shoulder length; psi does not depend on it.

    Returns
    -------
    numpy.ndarray, shape (...)
        psi in ``(-pi, pi]``; NaN where it is undefined (``W_y = 0``; the second value of
        :func:`theta1_from_shoulder_angle` says where it is defined).
    """
    t = as_float_array(theta1, "theta1")
    check_finite(t, "theta1")
    shape, (t, w) = flat((t, 0), (check_vectors(wrist, 3, "wrist"), 1))
    out = np.empty(t.shape[0])
    run_batch(_shoulder_angles, t.shape[0], t, w, float(L0), out)
    return out.reshape(shape)


def theta1_from_shoulder_angle(psi: ArrayLike, wrist: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form inverse of :func:`shoulder_angle`.

    The shoulder ``S(theta_1)`` must lie in the half-plane spanned by ``n``
    and ``u(psi) = cos(psi) e1 + sin(psi) e2``: ``S . (n x u) = 0`` gives
    ``tan(theta_1) = v_x / v_z`` with ``v = n x u``, and ``S . u > 0``
    picks the root ``theta_1 = atan2(-sgn(n_y) v_x, -sgn(n_y) v_z)``
    (``S . u`` is proportional to ``-(u x v)_y = -n_y`` on that root's opposite).

    Returns
    -------
    theta1 : numpy.ndarray, shape (...)
        In ``(-pi, pi]``; NaN where not ``defined``.
    defined : numpy.ndarray of bool, shape (...)
    """
    p = as_float_array(psi, "psi")
    check_finite(p, "psi")
    shape, (p, w) = flat((p, 0), (check_vectors(wrist, 3, "wrist"), 1))
    out, defined = np.empty(p.shape[0]), np.empty(p.shape[0], dtype=bool)
    run_batch(_torso_angles, p.shape[0], p, w, out, defined)
    return out.reshape(shape), defined.reshape(shape)


# ----------------------------------------------------- [001 eq. 3.1], literal
def shoulder_angle_eq31(theta1: ArrayLike, wrist: ArrayLike, L0: float) -> np.ndarray:
    """[001 eq. 3.1] literally: the unsigned angle ``S h' S'`` in ``[0, pi]`` at ``h' = W / 2``.

    ``S = (L0, 0, 0)`` is the shoulder at theta_1 = 0 and ``S' = S(theta_1)``.
    The law of cosines of [001 eq. 3.1] is evaluated as the angle between
    ``S - h'`` and ``S' - h'`` (the same number, without cancellation).
    """
    t = as_float_array(theta1, "theta1")
    check_finite(t, "theta1")
    w = check_vectors(wrist, 3, "wrist")
    half = w / 2.0
    s0 = np.array([L0, 0.0, 0.0]) - half
    s1 = np.stack([L0 * np.cos(t), np.zeros_like(t), -L0 * np.sin(t)], axis=-1) - half
    cross = np.linalg.norm(np.cross(s0, s1), axis=-1)
    return np.arctan2(cross, np.sum(s0 * s1, axis=-1))


def theta1_from_shoulder_angle_eq31(psi: float, wrist: ArrayLike, L0: float) -> np.ndarray:
    """Every theta_1 in ``(-pi, pi]`` with :func:`shoulder_angle_eq31` equal to ``psi`` (one wrist).

    With ``a = S - h'`` and ``b = S' - h'``, [001 eq. 3.1] is ``a . b = cos(psi) |a| |b|``.
    Squared, it is a trigonometric polynomial of degree 2 in theta_1,
    solved exactly as a quartic in ``z = exp(i theta_1)``; the roots on the
    unit circle are polished and those satisfying the unsquared equation are kept.

    Returns
    -------
    numpy.ndarray, shape (k,)
        Sorted roots, ``0 <= k <= 4`` (empty when no theta_1 gives ``psi``).
    """
    psi = float(psi)
    if not np.isfinite(psi) or not 0.0 <= psi <= np.pi:
        raise RedkinError(f"psi of [001 eq. 3.1] must be an angle in [0, pi], got {psi!r}")
    w = check_vectors(wrist, 3, "wrist").reshape(-1)
    if w.shape != (3,):
        raise RedkinError(f"wrist must be one position of shape (3,), got {np.shape(wrist)}")
    h = w / 2.0
    a = np.array([L0, 0.0, 0.0]) - h
    P, Q, R0 = L0 * a[0], -L0 * a[2], -float(a @ h)  # a . b = P c + Q s + R0
    U, V, C = -2 * L0 * h[0], 2 * L0 * h[2], L0**2 + float(h @ h)  # |b|^2 = U c + V s + C
    K = np.cos(psi) ** 2 * float(a @ a)
    a0 = (P * P + Q * Q) / 2 + R0 * R0 - K * C
    a1, b1 = 2 * P * R0 - K * U, 2 * Q * R0 - K * V
    a2, b2 = (P * P - Q * Q) / 2, P * Q
    coefficients = [(a2 - 1j * b2) / 2, (a1 - 1j * b1) / 2, a0, (a1 + 1j * b1) / 2, (a2 + 1j * b2) / 2]
    if np.allclose(np.abs(coefficients), 0.0):  # [001 eq. 3.1] holds for every theta_1 (degenerate wrist)
        return np.array([])
    roots = np.roots(coefficients)
    candidates = np.angle(roots[np.abs(np.abs(roots) - 1.0) < 1e-3])
    found: list[float] = []
    for theta in candidates:
        for _ in range(30):  # Newton on f(theta) = psi_eq31(theta) - psi (unsquared)
            value = shoulder_angle_eq31(theta, w, L0) - psi
            step = 1e-7
            slope = (shoulder_angle_eq31(theta + step, w, L0) - shoulder_angle_eq31(theta - step, w, L0)) / (2 * step)
            if abs(slope) < 1e-12:
                break
            theta = theta - value / slope
        theta = float(np.angle(np.exp(1j * theta)))
        if abs(shoulder_angle_eq31(theta, w, L0) - psi) < 1e-9 and all(
            abs(np.angle(np.exp(1j * (theta - f)))) > 1e-7 for f in found
        ):
            found.append(theta)
    return np.sort(np.array(found))
