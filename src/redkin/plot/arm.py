"""Drawing arms as polylines through their frame origins."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin.chain import SerialChain


def draw_arm_3d(ax, chain: SerialChain, q: ArrayLike, color: str = "C0", label: str | None = None,
                alpha: float = 1.0) -> None:
    """Draw ``chain`` at joints ``q`` on a 3-D axes: links, joints and the tool frame.

    The polyline passes through the base, every frame origin and the tool.
    """
    frames = chain.frames(q)
    points = frames[:, :3, 3]
    ax.plot(points[:, 0], points[:, 1], points[:, 2], "-o", color=color, markersize=3, label=label, alpha=alpha)
    tool = frames[-1]
    scale = 0.08 * max(np.ptp(points, axis=0).max(), 0.1)
    for k, axis_color in enumerate(("r", "g", "b")):
        end = tool[:3, 3] + scale * tool[:3, k]
        ax.plot(*np.stack([tool[:3, 3], end], axis=1), color=axis_color, linewidth=1.5, alpha=alpha)


def draw_arm_2d(ax, chain: SerialChain, q: ArrayLike, color: str = "C0", alpha: float = 1.0,
                label: str | None = None) -> None:
    """Draw a planar arm (x-y plane) at joints ``q``."""
    points = chain.frames(q)[:, :2, 3]
    ax.plot(points[:, 0], points[:, 1], "-o", color=color, markersize=3, alpha=alpha, label=label)


def set_equal_3d(ax, points: np.ndarray) -> None:
    """Give a 3-D axes equal scales around ``points`` of shape ``(m, 3)``."""
    centre = (points.max(axis=0) + points.min(axis=0)) / 2.0
    radius = max(np.ptp(points, axis=0).max() / 2.0, 0.1)
    ax.set_xlim(centre[0] - radius, centre[0] + radius)
    ax.set_ylim(centre[1] - radius, centre[1] + radius)
    ax.set_zlim(centre[2] - radius, centre[2] + radius)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
