"""Mid-plane slices of a workspace map's reachability and redundancy indices."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

#: The planes drawn: the fixed axis and the two in-plane axes (horizontal, vertical).
MID_PLANES = (("z", "x", "y"), ("y", "x", "z"), ("x", "y", "z"))


def save_mid_plane_slices(dataset: Any, name: str, path: "str | Path") -> None:
    """Save ``dataset[name]`` on the three mid-planes (x-y, x-z, y-z) side by side as one image.

    Parameters
    ----------
    dataset : xarray.Dataset
        A workspace map (``xarray.open_zarr`` of its store).
    name : {"reachability", "redundancy"}
        The index to draw, in ``[0, 1]``.
    path : str or Path
        The image file.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    values = dataset[name]
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), constrained_layout=True)
    try:
        for ax, (fixed, across, up) in zip(axes, MID_PLANES):
            middle = values.sizes[fixed] // 2
            plane = values.isel({fixed: middle}).transpose(up, across)
            u, v = dataset[across].values, dataset[up].values
            image = ax.pcolormesh(u, v, np.asarray(plane.values), vmin=0.0, vmax=1.0, cmap="viridis", shading="nearest")
            ax.set_aspect("equal")
            ax.set_xlabel(f"{across} [m]")
            ax.set_ylabel(f"{up} [m]")
            ax.set_title(f"{fixed} = {float(dataset[fixed].values[middle]):.3f} m")
        fig.colorbar(image, ax=axes, label=f"{name} index", shrink=0.9)
        fig.suptitle(f"{dataset.attrs.get('robot', '')}: {name} ({values.attrs.get('long_name', '')})", fontsize=10)
        fig.savefig(path, dpi=110)
    finally:
        plt.close(fig)
