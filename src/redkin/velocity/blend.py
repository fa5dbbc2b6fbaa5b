"""The singular-region blend of the singularity-consistent methods (paper 003 eqs. 11, 21, 22).

Inside the singular region ``|x| <= eps`` (``x`` is ``det J_i`` for eq. 11
or the singularity index ``D_e`` for eq. 21) the scalar weight must stay
finite; outside it must give exactly the commanded twist.  The realised
twist is ``g(x) t`` with the *twist scale*

    g(x) = x (3 - x^2 / eps^2) / (2 eps)   for |x| <= eps,
    g(x) = sign(x)                           otherwise,

obtained from the weight ``w(x) = g(x) / x`` of eq. 11:
``w = (3 - x^2/eps^2) / (2 eps)`` inside, ``1 / |x|`` outside.

Eq. 21 is garbled in the transcription (it prints ``3 - D_e^2 / (2 D_e^2)``,
``D_i / (2 D_e D_s)`` inside the region -- divergent at ``D_e = 0`` -- and
``D_i / (D_e D_s)`` outside).  We use eq. 11's form with ``D_e`` in place of
``det J_i`` because it is the unique choice (among these cubic blends) that

* is continuous at ``|D_e| = eps`` with a continuous slope (``g'(+-eps) = 0``),
* is finite and changes sign through ``D_e = 0`` (``g`` is odd), so the
  translation reverses on passing the boundary instead of stopping there,
* gives the commanded twist (scale ``+-1``) outside the region.

With ``1 / D_e`` outside instead of ``1 / |D_e|`` the scale would be ``+1``
on both sides outside but ``-1`` at the inside edge ``D_e = -eps``: a jump
of 2 that makes the motion chatter at the region edge and never cross.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from redkin.validation import check_positive


def _cubic_scale(x, e):
    """``x (3 - x^2 / e^2) / (2 e)``: ``g`` inside the region (derived eq. 21); floats or arrays."""
    return x * (3.0 - (x / e) ** 2) / (2.0 * e)


def twist_scale(index: ArrayLike, eps: float) -> np.ndarray:
    """``g(x)``: realised twist = ``g(x)`` times the (modified) commanded twist (derived eq. 21/22)."""
    e = check_positive(eps, "eps")
    x = np.asarray(index, dtype=float)
    return np.where(np.abs(x) <= e, _cubic_scale(x, e), np.sign(x))


def scalar_twist_scale(x: float, eps: float) -> float:
    """:func:`twist_scale` of one float with a trusted ``eps > 0`` (the control-loop path, no numpy calls)."""
    return _cubic_scale(x, eps) if abs(x) <= eps else math.copysign(1.0, x)


def blend_weight(index: ArrayLike, eps: float) -> np.ndarray:
    """``w(x) = g(x) / x``: the weight ``b_ep`` of eq. 11 per unit twist, finite at ``x = 0`` (paper 003 eq. 11)."""
    e = check_positive(eps, "eps")
    x = np.asarray(index, dtype=float)
    inside = (3.0 - (x / e) ** 2) / (2.0 * e)
    return np.where(np.abs(x) <= e, inside, 1.0 / np.where(x == 0.0, 1.0, np.abs(x)))


def rotation_factor(index: ArrayLike, eps: float) -> np.ndarray:
    """Factor ``clip(x / eps, -1, 1)`` applied in advance to the rotational command (paper 003 eq. 22 text).

    The paper multiplies the rotational command by ``D_e`` so that the realised
    rotation goes as ``D_e^2`` near the singularity: it slows and stops at
    ``D_e = 0`` but keeps its axis and sign.  Normalising by ``eps`` and
    clipping to +-1 outside the region (our choice; the paper gives no scale)
    keeps the realised rotation equal to the command outside the region and
    continuous at its edge: realised rotation factor
    ``g(x) clip(x/eps, -1, 1) >= 0``.
    """
    e = check_positive(eps, "eps")
    return np.clip(np.asarray(index, dtype=float) / e, -1.0, 1.0)


def scalar_rotation_factor(x: float, eps: float) -> float:
    """:func:`rotation_factor` of one float with a trusted ``eps > 0`` (the control-loop path)."""
    return min(1.0, max(-1.0, x / eps))
