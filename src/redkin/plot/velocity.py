"""Figures of tracking runs (paper 003 Fig. 1): time series with the singular region shaded, and the x-y path.

Plotting only: every kinematic quantity (runs, workspace boundary) is
computed by the caller.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np

from redkin.velocity.tracking import TrackingResult


def _shade_singular(ax, time: np.ndarray, index: np.ndarray, eps: float, label: str | None = "|D_e| <= D_eps") -> None:
    """Shade the time spans where ``|index| <= eps``."""
    inside = np.abs(index) <= eps
    edges = np.flatnonzero(np.diff(np.r_[0, inside.astype(int), 0]))
    for start, stop in zip(edges[::2], edges[1::2]):
        ax.axvspan(time[start], time[min(stop, len(time) - 1)], color="0.85", zorder=0, label=label)
        label = None


def tracking_figure(
    run: TrackingResult,
    eps: float,
    boundaries: Sequence[tuple[str, np.ndarray]] = (),
    title: str = "",
) -> plt.Figure:
    """Six panels of paper 003 Fig. 1: (a) joint velocities, (b) end-point velocity, (c) angular velocity,
    (d) ``D_e``, (e) end-point position, (f) x-y path with workspace boundaries ``(label, (k, 2) points)``."""
    fig, axes = plt.subplots(3, 2, figsize=(10, 9.5))
    t = run.time
    panels = [
        (axes[0, 0], run.joint_velocity, [f"q{i + 1}" for i in range(run.q.shape[1])], "(a) joint velocity [rad/s]"),
        (axes[0, 1], run.realised[:, :3], ["vx", "vy", "vz"], "(b) end-point velocity [m/s]"),
        (axes[1, 0], run.realised[:, 3:], ["wx", "wy", "wz"], "(c) angular velocity [rad/s]"),
        (axes[2, 0], run.position, ["x", "y", "z"], "(e) end-point position [m]"),
    ]
    for ax, data, names, heading in panels:
        for k, name in enumerate(names):
            ax.plot(t, data[:, k], label=name, linewidth=1.2)
        ax.set_title(heading, fontsize=10)
        ax.legend(fontsize=7, ncol=4, loc="best")
    ax = axes[1, 1]
    if run.index is not None:
        ax.plot(t, run.index, color="k", label="D_e")
        ax.axhline(eps, color="r", linestyle=":", linewidth=1)
        ax.axhline(-eps, color="r", linestyle=":", linewidth=1, label="+-D_eps")
        ax.axhline(0.0, color="0.5", linewidth=0.8)
        ax.legend(fontsize=7)
    ax.set_title("(d) singularity index D_e", fontsize=10)
    if run.index is not None:
        for ax in (axes[0, 0], axes[0, 1], axes[1, 0], axes[1, 1], axes[2, 0]):
            _shade_singular(ax, t, run.index, eps, label=None)
    for ax in (axes[0, 0], axes[0, 1], axes[1, 0], axes[1, 1], axes[2, 0]):
        ax.set_xlabel("t [s]")
    ax = axes[2, 1]
    for k, (label, points) in enumerate(boundaries):
        ax.plot(points[:, 0], points[:, 1], color="g", linestyle="-" if k == 0 else "--", linewidth=1, label=label)
    ax.plot(run.position[:, 0], run.position[:, 1], color="r", linewidth=2, label="end-point path")
    ax.plot(*run.position[0, :2], "ko", markersize=4, label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7)
    ax.set_title("(f) x-y path at the commanded height", fontsize=10)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def comparison_figure(runs: Mapping[str, TrackingResult], eps: float) -> plt.Figure:
    """Methods overlaid on one scenario: ``||q_dot||``, ``v_x``, ``omega_y``, ``D_e`` and ``x`` over time.

    One panel per quantity with a line per run; grey marks where the first
    run is inside its singular region ``|D_e| <= eps``.
    """
    fig, axes = plt.subplots(3, 2, figsize=(10, 9), sharex=True)
    panels = [
        (lambda run: np.linalg.norm(run.joint_velocity, axis=1), "||q_dot|| [rad/s] (log scale)", True),
        (lambda run: run.realised[:, 0], "end-point velocity v_x [m/s]", False),
        (lambda run: run.realised[:, 4], "angular velocity omega_y [rad/s]", False),
        (lambda run: run.index, "singularity index D_e", False),
        (lambda run: run.position[:, 0], "end-point position x [m]", False),
    ]
    first = next(iter(runs.values()))
    for ax, (series, title, log) in zip(axes.ravel(), panels):
        for k, (name, run) in enumerate(runs.items()):
            data = series(run)
            if data is not None:
                ax.plot(run.time, data, color=f"C{k}", linewidth=1.1, label=name)
        if first.index is not None:
            _shade_singular(ax, first.time, first.index, eps, label=None)
        if log:
            ax.set_yscale("log")
        else:
            ax.ticklabel_format(axis="y", useOffset=False, style="plain")
        ax.set_title(title, fontsize=10)
        ax.grid(True, linewidth=0.3)
    axes[1, 1].axhline(0.0, color="0.5", linewidth=0.8)
    legend_axes = axes[2, 1]
    legend_axes.axis("off")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    legend_axes.legend(handles, labels, loc="center", fontsize=10, title="method")
    for ax in (axes[2, 0], axes[1, 1]):
        ax.set_xlabel("t [s]")
        ax.xaxis.set_tick_params(labelbottom=True)
    fig.tight_layout()
    return fig
