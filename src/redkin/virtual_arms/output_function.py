"""The output function ``theta = G(u)`` of the input units [004 eqs. 13, 25].

Unlimited joints use the identity.  Limited joints use the sine function of
[004 eq. 25], ``g(u) = (r / 2) sin(u) + r / 2 + theta_min`` with
``r = theta_max - theta_min``, whose range is exactly ``[theta_min,
theta_max]``: whatever the input state ``u`` does, the joint never leaves its
range [004 eq. 26].  The initial state is ``u(0) = G^{-1}(theta(0))`` on the
branch ``|u| <= pi / 2``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from redkin.errors import RedkinError


@dataclass(frozen=True)
class OutputFunction:
    """Per-joint output functions: sine [004 eq. 25] where ``limited``, identity elsewhere.

    Parameters
    ----------
    lower, upper : numpy.ndarray, shape (m,)
        Joint ranges; only used where ``limited`` is true.
    limited : numpy.ndarray of bool, shape (m,)
    """

    lower: np.ndarray
    upper: np.ndarray
    limited: np.ndarray

    @classmethod
    def identity(cls, m: int) -> OutputFunction:
        """No limits: ``theta = u``."""
        return cls(np.full(m, -np.inf), np.full(m, np.inf), np.zeros(m, dtype=bool))

    @classmethod
    def sine(cls, lower: np.ndarray, upper: np.ndarray) -> OutputFunction:
        """[004 eq. 25] on every joint with a finite range, identity on the others: ``theta`` stays within
        ``[lower, upper]`` [004 eq. 26] by construction."""
        lower = np.asarray(lower, dtype=float)
        upper = np.asarray(upper, dtype=float)
        limited = np.isfinite(lower) & np.isfinite(upper)
        if np.any(limited & (upper <= lower)):
            raise RedkinError("joint limits must satisfy lower < upper for every limited joint")
        return cls(lower, upper, limited)

    @property
    def _half_range(self) -> np.ndarray:
        return np.where(self.limited, (self.upper - self.lower) / 2.0, 1.0)

    def theta(self, u: np.ndarray) -> np.ndarray:
        """``theta = G(u)`` [004 eq. 13]: [004 eq. 25] where limited, ``u`` elsewhere."""
        half = self._half_range
        sine = half * np.sin(u) + half + np.where(self.limited, self.lower, 0.0)
        return np.where(self.limited, sine, u)

    def slope(self, u: np.ndarray) -> np.ndarray:
        """The diagonal of ``G'(u) = d theta / d u``."""
        return np.where(self.limited, self._half_range * np.cos(u), 1.0)

    def state(self, theta: np.ndarray) -> np.ndarray:
        """``u = G^{-1}(theta)`` with ``|u| <= pi / 2`` on limited joints.

        Raises
        ------
        ValueError
            If a limited joint is outside its range.
        """
        theta = np.asarray(theta, dtype=float)
        outside = self.limited & ((theta < self.lower) | (theta > self.upper))
        if np.any(outside):
            j = int(np.flatnonzero(outside)[0])
            raise RedkinError(
                f"theta0 joint {j + 1} = {np.degrees(theta[j]):.6g} deg is outside its range "
                f"[{np.degrees(self.lower[j]):.6g}, {np.degrees(self.upper[j]):.6g}] deg"
            )
        half = self._half_range
        ratio = np.clip((theta - np.where(self.limited, self.lower, 0.0)) / half - 1.0, -1.0, 1.0)
        return np.where(self.limited, np.arcsin(ratio), theta)
