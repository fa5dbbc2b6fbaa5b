"""Heat maps of the thesis 001 manipulability maps, with the robot's base drawn in."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from redkin.torso_arm.maps import ManipulabilityMap

_AXES = "xyz"


def draw_manipulability_map(
    ax,
    result: ManipulabilityMap,
    landmarks: Mapping[str, ArrayLike] | None = None,
    unit: str = "m^3",
    scale: float = 1.0,
    threshold: float | None = None,
    cmap: str = "viridis",
):
    """Draw ``result.values * scale`` as a heat map on its plane, with a colour bar.

    Parameters
    ----------
    landmarks : mapping of name -> point (3,), optional
        Base points to mark (e.g. neck and shoulders), projected onto the plane;
        points that land on one spot share one label.
    unit : str
        Unit of the (scaled) values.  When they are below 1e-2 or reach 1e3, the
        colour bar shows them in a power of ten of it (``w [1e-2 m^6]``),
        never as an offset on top of the bar.
    threshold : float, optional
        Draw the contour ``w = threshold`` (in scaled units).

    Returns
    -------
    The image artist.
    """
    grid = result.grid
    values = np.ma.masked_invalid(result.values * scale)
    top = float(np.abs(values).max()) if values.count() else 0.0
    power = int(np.floor(np.log10(top))) if top > 0.0 and not 1e-2 <= top < 1e3 else 0
    values = values / 10.0**power
    extent = (grid.u[0], grid.u[-1], grid.v[0], grid.v[-1])
    image = ax.imshow(values, origin="lower", extent=extent, cmap=cmap, aspect="equal", interpolation="nearest")
    cbar = ax.figure.colorbar(image, ax=ax, shrink=0.85)
    cbar.formatter.set_useOffset(False)
    cbar.set_label(f"w [{unit}]" if power == 0 else f"w [1e{power} {unit}]")
    if threshold is not None and np.isfinite(values.filled(np.nan)).any():
        ax.contour(grid.u, grid.v, values.filled(0.0), levels=[threshold / 10.0**power], colors="w", linewidths=1.0)
    iu, iv = (_AXES.index(a) for a in grid.axis_names)
    spots: dict[tuple[float, float], list[str]] = {}
    for name, point in (landmarks or {}).items():
        p = np.asarray(point, dtype=float)
        spots.setdefault((round(float(p[iu]), 6), round(float(p[iv]), 6)), []).append(name)
    for index, ((u, v), names) in enumerate(spots.items()):
        ax.plot(u, v, marker="s" if index == 0 else "o", color="red", markersize=6, linestyle="none")
        ax.annotate(", ".join(names), (u, v), textcoords="offset points", xytext=(5, 5), color="red", fontsize=8,
                    bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.75, "linewidth": 0})
    if landmarks is not None and len(landmarks) > 1:
        pts = np.array([np.asarray(p, float) for p in landmarks.values()])
        ax.plot(pts[:, iu], pts[:, iv], "-", color="red", linewidth=2)
    ax.set_xlabel(f"{grid.axis_names[0]} [m]")
    ax.set_ylabel(f"{grid.axis_names[1]} [m]")
    ax.set_title(f"{grid.label}\n{result.description}", fontsize=8)
    return image


def save_mid_plane_maps(maps: Sequence[ManipulabilityMap], path: str | Path, unit: str, title: str) -> None:
    """Save 2-D maps (a 3-D map's mid-planes, :func:`redkin.workspace.humanoid.mid_plane_maps`) side by side.

    Parameters
    ----------
    maps : sequence of ManipulabilityMap
        One heat map per panel, drawn by :func:`draw_manipulability_map`.
    path : str or Path
        The image file.
    unit : str
        Unit of the values (``"m^3"``, ``"m^6"``).
    title : str
        The figure's title.
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(maps), figsize=(5.2 * len(maps), 4.6), constrained_layout=True, squeeze=False)
    try:
        for ax, result in zip(axes[0], maps):
            draw_manipulability_map(ax, result, unit=unit)
        fig.suptitle(title, fontsize=10)
        fig.savefig(path, dpi=110)
    finally:
        plt.close(fig)
