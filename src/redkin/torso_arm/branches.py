"""Branch flags, status codes and angle wrapping shared by the torso-arm solvers."""

from __future__ import annotations

import numpy as np

from redkin.chain import SerialChain

#: Position branches, in the order of the solution axis: (theta_3 flag, theta_5 flag).
#: theta_3 flag +1: cos(theta_3) >= 0 (``asin``), -1: cos(theta_3) <= 0 (``pi - asin``);
#: theta_5 flag +1: ``asin(k) - delta`` (eq. 3.19), -1: ``pi - asin(k) - delta`` (second branch).
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


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Angles mapped into ``(-pi, pi]``: ``angle + 2 pi floor((pi - angle) / 2 pi)``.

    Angles already in that range come back unchanged, bit for bit; the floor
    form is also an order of magnitude faster than ``np.mod`` on large maps.
    """
    turns = np.subtract(np.pi, angle)
    turns /= 2.0 * np.pi
    np.floor(turns, out=turns)
    turns *= 2.0 * np.pi
    turns += angle
    return turns


def wrap_to_limits(chain: SerialChain, q: np.ndarray, joints: slice = slice(None)) -> np.ndarray:
    """Angles in ``(-pi, pi]``, shifted by ``+-2 pi`` where that brings a joint inside its limits.

    (theta_3 of thesis 001 ranges over -5..185 deg, beyond pi.)
    """
    q = wrap_angle(q)
    lower, upper = chain.lower[joints], chain.upper[joints]
    # only a joint whose range leaves (-pi, pi] can gain from a shift: work on those columns alone
    columns = np.flatnonzero((lower < -np.pi) | (upper > np.pi))
    if columns.size == 0:
        return q
    part, lower, upper = q[..., columns], lower[columns], upper[columns]
    for shift in (2.0 * np.pi, -2.0 * np.pi):
        inside = (part >= lower) & (part <= upper)
        moved = part + shift
        part = np.where(~inside & (moved >= lower) & (moved <= upper), moved, part)
    q[..., columns] = part
    return q
