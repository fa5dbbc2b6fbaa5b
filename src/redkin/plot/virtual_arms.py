"""Stroboscopic drawings of virtual-arm runs (paper 004 Figs. 6-8): the arm at several instants along a run."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.patches import Circle
from matplotlib.ticker import MaxNLocator

from redkin.chain import SerialChain
from redkin.plot.arm import draw_arm_3d, set_equal_3d


def _strobe_indices(count: int, frames: int) -> np.ndarray:
    """Indices of ``frames`` records spread evenly over a run of ``count`` records (first and last included)."""
    return np.unique(np.linspace(0, count - 1, max(2, int(frames))).round().astype(int))


def draw_strobe(ax, chain: SerialChain, theta: np.ndarray, goals: np.ndarray, virtual: np.ndarray | None = None,
                frames: int = 12, title: str | None = None, reach: float | None = None,
                obstacles: Sequence = ()) -> None:
    """Draw a planar arm at ``frames`` instants of a run, its goals and its final virtual end points.

    Parameters
    ----------
    ax : matplotlib axes
    chain : SerialChain
        Planar chain (x-y plane); positions come from ``chain.frames``.
    theta : numpy.ndarray, shape (K, m)
        Joint vectors along the run.
    goals : numpy.ndarray, shape (p, 2)
        Goals of the virtual end points (the first is the real end point's).
    virtual : numpy.ndarray, shape (p, 2), optional
        Final virtual end points, drawn as hollow circles.
    frames : int
        Number of instants drawn; earlier instants are lighter.
    obstacles : sequence of Obstacle
        Circles drawn filled grey (Fig. 8).
    """
    _draw_obstacles(ax, obstacles)
    picks = _strobe_indices(len(theta), frames)
    points = chain.frames(theta[picks])[..., :2, 3]  # (frames, n + 2, 2)
    shades = np.linspace(0.25, 1.0, len(picks))
    for shade, polyline in zip(shades, points):
        ax.plot(polyline[:, 0], polyline[:, 1], "-", color=(0.1, 0.2, 0.6), alpha=float(shade), linewidth=1.0)
    final = points[-1]
    ax.plot(final[:, 0], final[:, 1], "-o", color="C0", markersize=3, linewidth=2.0, label="final posture")
    path = chain.frames(theta)[:, -1, :2, 3]
    ax.plot(path[:, 0], path[:, 1], ":", color="C3", linewidth=1.0, label="end-point path")
    ax.plot(goals[:1, 0], goals[:1, 1], "*", color="C3", markersize=12, label="end goal")
    if len(goals) > 1:
        ax.plot(goals[1:, 0], goals[1:, 1], "x", color="C2", markersize=6, label="virtual goals")
    if virtual is not None and len(virtual) > 1:
        ax.plot(virtual[1:, 0], virtual[1:, 1], "o", mfc="none", color="C2", markersize=6, label="virtual end points")
    ax.plot([0.0], [0.0], "ks", markersize=6)
    if reach is not None:
        ax.set_xlim(-reach, reach)
        ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.grid(True, linewidth=0.3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title:
        ax.set_title(title, fontsize=9)


def fit_planar_view(axes: Sequence, chain: SerialChain, runs: Sequence[np.ndarray], goals: Sequence[np.ndarray],
                    obstacles: Sequence = (), margin: float = 0.08) -> None:
    """Give planar axes one view around what they show: every posture of ``runs``, the goals and the obstacles.

    Parameters
    ----------
    axes : sequence of matplotlib axes
        They all get the same limits (square, so equal aspect fills them).
    runs : sequence of numpy.ndarray, shape (K, m)
        Joint vectors of each run drawn.
    goals : sequence of numpy.ndarray, shape (p, 2)
    obstacles : sequence of Obstacle
    margin : float
        Space around it all, as a fraction of the larger side.
    """
    points = [chain.frames(theta)[..., :2, 3].reshape(-1, 2) for theta in runs]
    points += [np.asarray(g, dtype=float)[:, :2] for g in goals]
    points += [np.array([o.centre[:2] - o.radius, o.centre[:2] + o.radius]) for o in obstacles]
    everything = np.concatenate(points)
    low, high = everything.min(axis=0), everything.max(axis=0)
    half = 0.5 * float(np.max(high - low)) * (1.0 + 2.0 * margin)
    centre = 0.5 * (low + high)
    for ax in axes:
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.xaxis.set_major_locator(MaxNLocator(5))
        ax.yaxis.set_major_locator(MaxNLocator(5))


def legend_below(fig, ax, space: float = 0.07) -> None:
    """One legend for the whole figure, in a row under its panels (where it covers no arm), with the entries of ``ax``.

    ``space`` is the fraction of the figure's height kept for it.
    """
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, space, 1, 1))


def _draw_obstacles(ax, obstacles: Sequence) -> None:
    """Circular obstacles (objects with ``centre`` and ``radius``) as grey discs on a planar plot."""
    for k, obstacle in enumerate(obstacles):
        ax.add_patch(Circle(tuple(obstacle.centre[:2]), obstacle.radius, facecolor="0.6", edgecolor="0.3",
                            alpha=0.8, label="obstacle" if k == 0 else None))


def draw_joint_history(ax, s: np.ndarray, theta: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> None:
    """Joint angles (degrees) against the time ``s`` of the dynamics, with finite limits drawn dashed."""
    for j in range(theta.shape[1]):
        ax.plot(s, np.degrees(theta[:, j]), color=f"C{j}", label=f"theta{j + 1}")
        for bound in (lower[j], upper[j]):
            if np.isfinite(bound) and abs(bound) < np.pi:
                ax.axhline(np.degrees(bound), color=f"C{j}", linestyle="--", linewidth=0.8)
    ax.set_xscale("symlog", linthresh=1e-2)
    ax.set_xlim(left=0.0)
    ax.set_xlabel("s")
    ax.set_ylabel("joint angle [deg]")
    ax.legend(fontsize=7)
    ax.grid(True, linewidth=0.3)


def draw_strobe_3d(ax, chain: SerialChain, theta: np.ndarray, goal: np.ndarray, obstacles: Sequence = (),
                   watched: np.ndarray | None = None, frames: int = 8, title: str | None = None) -> None:
    """Draw a spatial arm at ``frames`` instants of a run, its end goal, spheres and a watched point's path.

    Parameters
    ----------
    ax : matplotlib 3-D axes
    chain : SerialChain
    theta : numpy.ndarray, shape (K, m)
    goal : numpy.ndarray, shape (3,)
    obstacles : sequence of Obstacle
        Spheres drawn as wireframes.
    watched : numpy.ndarray, shape (K, 3), optional
        Path of a virtual end point (e.g. the elbow), drawn dashed.
    """
    picks = _strobe_indices(len(theta), frames)
    shades = np.linspace(0.25, 1.0, len(picks))
    for shade, q in zip(shades, theta[picks]):
        draw_arm_3d(ax, chain, q, color="C0", alpha=float(shade))
    path = chain.frames(theta)[:, -1, :3, 3]
    ax.plot(path[:, 0], path[:, 1], path[:, 2], ":", color="C3", label="end-point path")
    if watched is not None:
        ax.plot(watched[:, 0], watched[:, 1], watched[:, 2], "--", color="C2", label="elbow path")
    ax.scatter(*goal, marker="*", s=120, color="C3", label="end goal")
    u, v = np.meshgrid(np.linspace(0.0, 2.0 * np.pi, 24), np.linspace(0.0, np.pi, 12))
    sphere = np.stack([np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)], axis=-1)
    for obstacle in obstacles:
        surface = obstacle.centre + obstacle.radius * sphere
        ax.plot_wireframe(surface[..., 0], surface[..., 1], surface[..., 2], color="0.4", linewidth=0.4)
    set_equal_3d(ax, np.vstack([chain.frames(theta[picks])[..., :3, 3].reshape(-1, 3), goal[None]]))
    ax.set_box_aspect((1.0, 1.0, 1.0))
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    if title:
        ax.set_title(title, fontsize=9)


def animate_planar(fig, ax, chain: SerialChain, theta: np.ndarray, goals: np.ndarray, frames: int = 40,
                   title: str | None = None, obstacles: Sequence = ()):
    """An animation of a planar run: the arm at ``frames`` instants, the end-point path drawn as it grows.

    Save it with ``animation.save("run.gif", writer=matplotlib.animation.PillowWriter(fps=20))``.

    Parameters
    ----------
    fig, ax : matplotlib figure and axes
    chain : SerialChain
        Planar chain (x-y plane).
    theta : numpy.ndarray, shape (K, m)
        Joint vectors along the run.
    goals : numpy.ndarray, shape (p, 2)
        Goals (the first is the real end point's).
    frames : int
        Number of instants shown (spread evenly over the run, first and last included).
    obstacles : sequence of Obstacle

    Returns
    -------
    matplotlib.animation.FuncAnimation
    """
    from matplotlib.animation import FuncAnimation

    _draw_obstacles(ax, obstacles)
    picks = _strobe_indices(len(theta), frames)
    skeleton = chain.frames(theta)[..., :2, 3]  # (K, n + 2, 2)
    ends = skeleton[:, -1]
    everything = np.concatenate([skeleton.reshape(-1, 2), goals[:, :2]])
    low, high = everything.min(axis=0), everything.max(axis=0)
    margin = 0.1 * float(np.max(high - low)) + 0.05
    ax.set_xlim(low[0] - margin, high[0] + margin)
    ax.set_ylim(low[1] - margin, high[1] + margin)
    ax.set_aspect("equal")
    ax.grid(True, linewidth=0.3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.plot(goals[:1, 0], goals[:1, 1], "*", color="C3", markersize=12, label="end goal")
    if len(goals) > 1:
        ax.plot(goals[1:, 0], goals[1:, 1], "x", color="C2", markersize=6, label="virtual goals")
    ax.plot([0.0], [0.0], "ks", markersize=6)
    (arm,) = ax.plot([], [], "-o", color="C0", markersize=3, linewidth=2.0, label="arm")
    (trace,) = ax.plot([], [], ":", color="C3", linewidth=1.0, label="end-point path")
    if title:
        ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="lower left")

    def show(k: int):
        record = picks[k]
        arm.set_data(skeleton[record, :, 0], skeleton[record, :, 1])
        trace.set_data(ends[: record + 1, 0], ends[: record + 1, 1])
        return arm, trace

    return FuncAnimation(fig, show, frames=len(picks), interval=50, blit=True)
