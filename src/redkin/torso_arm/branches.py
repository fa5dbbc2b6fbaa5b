"""Branch flags, status codes and angle wrapping (compiled) shared by the torso-arm solvers."""

from __future__ import annotations

from math import floor, pi

import numpy as np
from numpy.typing import ArrayLike

from redkin._chain_kernels import range_middle, representative
from redkin._compiled import kernel, run_batch
from redkin.chain import SerialChain
from redkin.circle import TWO_PI
from redkin.torso_arm._kernel_tools import flat

#: Position branches, in the order of the solution axis: (theta_3 flag, theta_5 flag).
#: theta_3 flag +1: cos(theta_3) >= 0 (``asin``), -1: cos(theta_3) <= 0 (``pi - asin``);
#: theta_5 flag +1: ``asin(k) - delta`` [001 eq. 3.19], -1: ``pi - asin(k) - delta`` (second branch).
POSITION_BRANCHES = ((1, 1), (1, -1), (-1, 1), (-1, -1))

#: Wrist branches: sign of sin(theta_7).
WRIST_BRANCHES = (1, -1)

OK = 0
UNREACHABLE = 1
NO_REFERENCE = 2
SHOULDER_UNDEFINED = 3
#: Names of the status codes.
STATUS_NAMES = {
    OK: "ok",
    UNREACHABLE: "unreachable",
    NO_REFERENCE: "no reference",
    SHOULDER_UNDEFINED: "shoulder angle undefined",
}




@kernel
def _wrap_one(angle):
    """``angle + 2 pi floor((pi - angle) / 2 pi)``: the same angle in ``(-pi, pi]``, unchanged if already there."""
    return floor((pi - angle) / TWO_PI) * TWO_PI + angle


@kernel
def into_limits(angle, lower, upper):
    """:func:`_wrap_one`, then shifted by a multiple of ``2 pi`` where that brings it into ``[lower, upper]``.

    Only a joint whose range leaves ``(-pi, pi]`` can gain from a shift
    (theta_3 of thesis 001 ranges over -5..185 deg, beyond pi); of several
    shifts that land inside (a range wider than ``2 pi``), the one nearest
    the middle of the range (:func:`redkin._chain_kernels.representative`).
    """
    q = _wrap_one(angle)
    if lower < -pi or upper > pi:
        inside = representative(q, lower, upper, range_middle(lower, upper))
        if inside == inside:
            q = inside
    return q


@kernel
def wraps(start, stop, angle, out):
    """:func:`_wrap_one` for each of ``angle`` (N,) -> ``out`` (N,)."""
    for i in range(start, stop):
        out[i] = _wrap_one(angle[i])


@kernel
def _limit_wraps(start, stop, q, lower, upper, out):
    """:func:`into_limits` for each row of ``q`` (N, k), joint ranges ``lower``, ``upper`` (k,) -> ``out`` (N, k)."""
    for i in range(start, stop):
        for j in range(q.shape[1]):
            out[i, j] = into_limits(q[i, j], lower[j], upper[j])


def wrap_angle(angle: ArrayLike) -> np.ndarray:
    """Angles mapped into ``(-pi, pi]`` (:func:`_wrap_one`); angles already there come back bit for bit."""
    shape, (a,) = flat((angle, 0))
    out = np.empty(a.shape[0])
    run_batch(wraps, a.shape[0], a, out)
    return out.reshape(shape)


def wrap_to_limits(chain: SerialChain, q: np.ndarray, joints: slice = slice(None)) -> np.ndarray:
    """Angles ``q`` (..., k) of the chain's ``joints`` in ``(-pi, pi]``, shifted by ``+-2 pi`` where that
    brings a joint inside its limits (:func:`into_limits`)."""
    lower, upper = np.ascontiguousarray(chain.lower[joints]), np.ascontiguousarray(chain.upper[joints])
    shape, (flat_q,) = flat((q, 1))
    out = np.empty(flat_q.shape)
    run_batch(_limit_wraps, flat_q.shape[0], flat_q, lower, upper, out)
    return out.reshape(shape + flat_q.shape[1:])
