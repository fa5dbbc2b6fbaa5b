"""Figures for the Franka class: the joint values of one branch over q7, with the limits and the feasible q7 set."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def plot_q7_curves(
    axes: Sequence,
    q7: np.ndarray,
    q: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    arcs: np.ndarray,
    domain: tuple[float, float],
) -> None:
    """q_i(q7) in degrees, one axes per joint, with the limits (dashed) and the feasible q7 arcs (shaded blue).

    Parameters
    ----------
    axes : sequence of matplotlib Axes
        One per joint, top to bottom.
    q7 : numpy.ndarray, shape (G,)
        Sorted values of q7 [rad].
    q : numpy.ndarray, shape (G, 7)
        The branch's joint values at each [rad] (:func:`redkin.franka.ik`), NaN where it has no solution there
        (not drawn); jumps of a wrapped value by more than 180 deg are not joined.
    lower, upper : numpy.ndarray, shape (7,)
        The joint limits [rad].
    arcs : numpy.ndarray, shape (K, 2)
        The branch's feasible q7 set (:func:`redkin.franka.feasible_q7`) [rad].
    domain : tuple of float
        The range of q7 drawn [rad].
    """
    x = np.degrees(q7)
    for joint, ax in enumerate(axes):
        y = np.degrees(q[:, joint])
        y = np.where(np.r_[False, np.abs(np.diff(y)) > 180.0], np.nan, y)
        ax.plot(x, y, color="k", linewidth=1.2)
        for limit in (lower[joint], upper[joint]):
            if np.isfinite(limit):
                ax.axhline(np.degrees(limit), color="C3", linestyle="--", linewidth=1)
        for start, end in arcs:
            ax.axvspan(np.degrees(start), np.degrees(end), color="C0", alpha=0.2, linewidth=0)
        ax.set_ylabel(f"q{joint + 1} [deg]")
        ax.set_xlim(*np.degrees(domain))
    axes[-1].set_xlabel("q7 [deg]")
