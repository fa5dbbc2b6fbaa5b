"""Workspace maps drawn: mid-plane slices of the per-position indices, and one line of the measure."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np

#: The planes drawn: the fixed axis and the two in-plane axes (horizontal, vertical), as indices of x, y, z.
_MID_PLANES = ((2, 0, 1), (1, 0, 2), (0, 1, 2))
_AXIS_NAMES = "xyz"


def mid_plane_figure(coordinates: Sequence[np.ndarray], indices: Mapping[str, np.ndarray], title: str) -> plt.Figure:
    """Each index of a map on the three mid-planes (x-y, x-z, y-z), one row per index.

    Parameters
    ----------
    coordinates : sequence of 3 numpy.ndarray
        The grid axes ``x, y, z`` in metres, of lengths ``Mx, My, Mz``.
    indices : mapping of str to numpy.ndarray
        Name (``"reachability"``, ``"redundancy"``) to values of shape ``(Mx, My, Mz)`` in ``[0, 1]``.
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
        The plane through the middle grid point of each axis (the exact centre for an odd count).
    """
    fig, axes = plt.subplots(len(indices), 3, figsize=(13, 4.2 * len(indices)), constrained_layout=True, squeeze=False)
    for row, (name, values) in zip(axes, indices.items()):
        values = np.asarray(values)
        for ax, (fixed, across, up) in zip(row, _MID_PLANES):
            middle = values.shape[fixed] // 2
            plane = np.take(values, middle, axis=fixed)  # the two remaining axes keep their order: across, up
            image = ax.pcolormesh(coordinates[across], coordinates[up], plane.T, vmin=0.0, vmax=1.0, cmap="viridis",
                                  shading="nearest")
            ax.set_aspect("equal")
            ax.set_xlabel(f"{_AXIS_NAMES[across]} [m]")
            ax.set_ylabel(f"{_AXIS_NAMES[up]} [m]")
            level = round(float(coordinates[fixed][middle]), 3) + 0.0  # + 0.0: never "-0.000"
            ax.set_title(f"{name}, {_AXIS_NAMES[fixed]} = {level:.3f} m", fontsize=10)
        fig.colorbar(image, ax=row, label=f"{name} index", shrink=0.9)
    fig.suptitle(title, fontsize=10)
    return fig


def save_mid_plane_slices(dataset: Any, name: str, path: str | Path) -> None:
    """Save ``dataset[name]`` of a stored map on the three mid-planes side by side as one image.

    Parameters
    ----------
    dataset : xarray.Dataset
        A workspace map (``xarray.open_zarr`` of its store).
    name : {"reachability", "redundancy"}
        The index to draw, in ``[0, 1]``.
    path : str or Path
        The image file.
    """
    values = dataset[name].transpose("x", "y", "z")
    coordinates = [dataset[axis].values for axis in _AXIS_NAMES]
    fig = mid_plane_figure(coordinates, {name: values.values},
                           f"{dataset.attrs.get('robot', '')}: {name} ({values.attrs.get('long_name', '')})")
    try:
        fig.savefig(path, dpi=110)
    finally:
        plt.close(fig)


def plot_measure_line(ax: Any, angles: np.ndarray, measure: np.ndarray, branches: Sequence[str], xlabel: str) -> None:
    """The feasible arm-angle measure of each branch along one line of a map (positions or orientations).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    angles : numpy.ndarray, shape (K,)
        The line's parameter, drawn as given (e.g. degrees).
    measure : numpy.ndarray, shape (K, B)
        Radians, one column per branch; drawn in degrees.  Branches that are empty along the whole line are
        named in the legend but not drawn.
    branches : sequence of str
        The ``B`` branch names.
    xlabel : str
        Label of the line's parameter.
    """
    empty = []
    for column, branch in enumerate(branches):
        if np.any(measure[:, column] > 0.0):
            ax.plot(angles, np.degrees(measure[:, column]), label=f"branch {branch}")
        else:
            empty.append(branch)
    if empty:
        ax.plot([], [], " ", label=f"empty all along: {', '.join(empty)}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("measure of the feasible arm angles [deg]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower center")
