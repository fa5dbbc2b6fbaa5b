"""Figures for paper 000: joint angles over the arm angle with limits and feasible bands, reachable rotations."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np

from redkin.circle import ArcSet


def _shade_arcs(ax, arc_set: ArcSet, color: str = "C2", alpha: float = 0.15, degrees: bool = True) -> None:
    """Shade the arcs of ``arc_set`` as vertical bands over the x axis (arm angle)."""
    scale = np.degrees if degrees else (lambda v: v)
    for lo, hi in arc_set.intervals:
        ax.axvspan(scale(lo), scale(hi), color=color, alpha=alpha, linewidth=0)


def plot_joint_curves(
    axes: Sequence,
    psi: np.ndarray,
    theta: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    per_joint: dict[int, ArcSet],
    feasible: ArcSet,
    joints: Sequence[int] = (1, 2, 3, 5, 6, 7),
) -> None:
    """theta_i(psi) in degrees with the limits (dashed), Psi_i (green) and Psi (blue) bands (paper Figs. 3, 4).

    ``theta`` has shape ``(len(psi), 7)`` in radians; jumps of the wrapped angle are not joined.
    """
    x = np.degrees(psi)
    for ax, joint in zip(axes, joints):
        y = np.degrees(theta[:, joint - 1])
        y = np.where(np.r_[False, np.abs(np.diff(y)) > 180.0], np.nan, y)
        ax.plot(x, y, color="k", linewidth=1.2)
        for limit in (lower[joint - 1], upper[joint - 1]):
            if np.isfinite(limit):
                ax.axhline(np.degrees(limit), color="C3", linestyle="--", linewidth=1)
        _shade_arcs(ax, per_joint[joint], color="C2", alpha=0.15)
        _shade_arcs(ax, feasible, color="C0", alpha=0.15)
        ax.set_ylabel(f"theta_{joint} [deg]")
        ax.set_xlim(-180, 180)
        ax.set_ylim(-190, 190)
    axes[-1].set_xlabel("arm angle psi [deg]")


def plot_reachable_rotations(
    ax,
    gamma: np.ndarray,
    feasible: Sequence[ArcSet],
    controlled_psi: np.ndarray,
    controlled_ok: np.ndarray,
    fixed_psi: float,
    fixed_ok: np.ndarray,
) -> None:
    """Feasible arm angles over the tool rotation gamma, with psi fixed and psi controlled (section 6.2.2)."""
    g = np.degrees(gamma)
    step = np.median(np.diff(g)) if g.size > 1 else 1.0
    for value, arc_set in zip(g, feasible):
        for lo, hi in arc_set.intervals:
            ax.plot([value, value], np.degrees([lo, hi]), color="C2", linewidth=max(1.0, step), alpha=0.5)
    ax.plot(g[fixed_ok], np.full(fixed_ok.sum(), np.degrees(fixed_psi)), ".", color="C3", markersize=3,
            label="psi fixed (reachable)")
    ax.plot(g[controlled_ok], np.degrees(controlled_psi[controlled_ok]), ".", color="C0", markersize=3,
            label="psi controlled, [000 eq. 40]")
    ax.set_xlabel("tool rotation gamma [deg]")
    ax.set_ylabel("arm angle psi [deg]")
    ax.set_ylim(-180, 180)
    ax.legend(loc="lower left", fontsize=8)


def plot_arm_angles_along_path(ax, time: np.ndarray, psi: np.ndarray, feasible: Sequence[ArcSet],
                               within: np.ndarray) -> None:
    """The feasible arm angles at each sample of a path (bars) and the path's own arm angle (dots), in degrees.

    ``within`` marks the samples whose joint values are within the limits (drawn filled, the others hollow).
    """
    step = float(np.median(np.diff(time))) if len(time) > 1 else 1.0
    for t, arcs in zip(time, feasible):
        for lo, hi in arcs.intervals:
            ax.add_patch(plt.Rectangle((t - step / 2, np.degrees(lo)), step, np.degrees(hi - lo),
                                       color="C2", alpha=0.35, linewidth=0))
    degrees = np.degrees(psi)
    if within.any():
        ax.plot(time[within], degrees[within], "o", color="C0", markersize=2.5, label="run's psi, joints within limits")
    if not within.all():
        ax.plot(time[~within], degrees[~within], "o", markerfacecolor="none", color="C3", markersize=3,
                label="run's psi, a joint outside its range")
    ax.plot([], [], "s", color="C2", alpha=0.35, label="feasible arm angles (exact)")
    ax.set_xlim(time[0] - step, time[-1] + step)
    ax.set_ylim(-180, 180)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("arm angle psi [deg]")
