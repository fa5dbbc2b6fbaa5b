"""The singular-region blend of the singularity-consistent methods [003 eqs. 11, 21, 22].

Inside the singular region ``|x| <= eps`` (``x`` is ``det J_i`` for [003 eq. 11]
or the singularity index ``D_e`` for [003 eq. 21]) the scalar weight must stay
finite; outside it must give exactly the commanded twist.  The realised
twist is ``g(x) t`` with the *twist scale*

    g(x) = x (3 - x^2 / eps^2) / (2 eps)   for |x| <= eps,
    g(x) = sign(x)                           otherwise,

obtained from the weight ``w(x) = g(x) / x`` of [003 eq. 11]:
``w = (3 - x^2/eps^2) / (2 eps)`` inside, ``1 / |x|`` outside.

[003 eq. 21] is garbled in the transcription (it prints ``3 - D_e^2 / (2 D_e^2)``,
``D_i / (2 D_e D_s)`` inside the region -- divergent at ``D_e = 0`` -- and
``D_i / (D_e D_s)`` outside).  We use [003 eq. 11]'s form with ``D_e`` in place of
``det J_i`` because it is the unique choice (among these cubic blends) that

* is continuous at ``|D_e| = eps`` with a continuous slope (``g'(+-eps) = 0``),
* is finite and changes sign through ``D_e = 0`` (``g`` is odd), so the
  translation reverses on passing the boundary instead of stopping there,
* gives the commanded twist (scale ``+-1``) outside the region.

With ``1 / D_e`` outside instead of ``1 / |D_e|`` the scale would be ``+1``
on both sides outside but ``-1`` at the inside edge ``D_e = -eps``: a jump
of 2 that makes the motion chatter at the region edge and never cross.

The three formulas are compiled once, as scalar kernels of
:mod:`redkin.velocity._step_kernels` that the steps call; the functions here
apply them to arrays.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_positive
from redkin.velocity import _step_kernels


def _blend(index: ArrayLike, eps: float) -> tuple[np.ndarray, ...]:
    """``g``, ``w`` and the rotation factor of every entry of ``index`` (kernel
    :func:`~redkin.velocity._step_kernels.blend`)."""
    e = check_positive(eps, "eps")
    x = np.asarray(index, dtype=float)
    flat = np.ascontiguousarray(x.reshape(-1))
    outputs = tuple(np.empty(flat.shape) for _ in range(3))
    _step_kernels.blend(flat, e, *outputs)
    return tuple(out.reshape(x.shape) if x.ndim else out[0] for out in outputs)


def twist_scale(index: ArrayLike, eps: float) -> np.ndarray:
    """``g(x)``: realised twist = ``g(x)`` times the (modified) commanded twist (derived [003 eqs. 21, 22])."""
    return _blend(index, eps)[0]


def blend_weight(index: ArrayLike, eps: float) -> np.ndarray:
    """``w(x) = g(x) / x``: the weight ``b_ep`` of [003 eq. 11] per unit twist, finite at ``x = 0``."""
    return _blend(index, eps)[1]


def rotation_factor(index: ArrayLike, eps: float) -> np.ndarray:
    """Factor ``clip(x / eps, -1, 1)`` applied in advance to the rotational command ([003 eq. 22] text).

    The paper multiplies the rotational command by ``D_e`` so that the realised
    rotation goes as ``D_e^2`` near the singularity: it slows and stops at
    ``D_e = 0`` but keeps its axis and sign.  Normalising by ``eps`` and
    clipping to +-1 outside the region (our choice; the paper gives no scale)
    keeps the realised rotation equal to the command outside the region and
    continuous at its edge: realised rotation factor
    ``g(x) clip(x/eps, -1, 1) >= 0``.
    """
    return _blend(index, eps)[2]
