"""The Zarr store of a workspace map: its layout, its attributes and its per-chunk completion markers.

Layout (zarr format 2, readable with ``xarray.open_zarr``):

* ``measure`` (x, y, z, orientation, branch): radians, branches in the order of :data:`redkin.srs.BRANCHES`;
* ``reachability``, ``redundancy`` (x, y, z): dimensionless, in ``[0, 1]``;
* coordinates ``x``, ``y``, ``z`` (metres) and ``rotation`` (orientation, row, column);
* ``chunk_complete`` (chunk_x, chunk_y, chunk_z): set once a chunk's values are written, after them.

A chunk's values are NaN until it is computed.  The map's parameters (arm,
grid, orientations, chunk) are stored as attributes; a run on an existing
store with the same parameters resumes it, one with others is refused.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from redkin import __version__
from redkin.chain import SerialChain
from redkin.srs import BRANCHES
from redkin.workspace._optional import require
from redkin.workspace.grid import WorkspaceGrid

#: The file name of the map inside the output directory of ``redkin workspace``.
MAP_NAME = "map.zarr"
_ORIENTATION_SET = "super-Fibonacci spiral on SO(3) (Alexa, CVPR 2022), deterministic in the count"


def arm_description(chain: SerialChain) -> dict[str, Any]:
    """The chain as JSON values: its DH table, joint senses, limits (``None``: unlimited), base and tool."""
    def values(array: np.ndarray) -> list:
        return [float(v) if np.isfinite(v) else None for v in np.asarray(array, dtype=float).ravel()]

    return {
        "name": chain.name, "source": chain.source, "convention": chain.convention,
        "joint_names": list(chain.joint_names),
        **{key: values(getattr(chain, key)) for key in ("a", "alpha", "d", "offset", "sign", "lower", "upper")},
        "base": values(chain.base), "tool": values(chain.tool),
        "units": "lengths in m, angles in rad; base and tool as 4x4 row by row",
    }


def map_parameters(chain: SerialChain, grid: WorkspaceGrid, orientations: int) -> str:
    """What makes two maps the same map, as canonical JSON (compared when a run resumes)."""
    return json.dumps({
        "arm": arm_description(chain), "extent": list(grid.extent), "resolution": grid.resolution,
        "orientations": orientations, "chunk": grid.chunk,
    }, sort_keys=True)


def create_store(path: Path, chain: SerialChain, grid: WorkspaceGrid, rotations: np.ndarray) -> None:
    """Write the metadata and coordinates of an empty map at ``path`` (values NaN, no chunk complete)."""
    xr = require("xarray")
    da = require("dask.array")
    m, n, c = grid.resolution, len(rotations), grid.chunk
    x, y, z = grid.axes
    position = ("x", "y", "z")
    # lazy templates of one Dask chunk each (a graph of a few tasks, never computed); the store's chunks are set
    # by the encoding: one per map chunk (13 824 Dask chunks per array made the 1 cm map's metadata take 30 s)
    data = {
        "measure": (position + ("orientation", "branch"), da.zeros((m, m, m, n, len(BRANCHES)), chunks=-1),
                    {"units": "rad", "long_name": "measure of the feasible arm-angle set ([000 eq. 30])",
                     "branches": [str(b) for b in BRANCHES]}),
        "reachability": (position, da.zeros((m, m, m), chunks=-1),
                         {"units": "1",
                          "long_name": "fraction of orientations with a feasible arm angle on some branch"}),
        "redundancy": (position, da.zeros((m, m, m), chunks=-1),
                       {"units": "1",
                        "long_name": "mean over reachable orientations of the largest branch measure / 2 pi"}),
        "chunk_complete": (("chunk_x", "chunk_y", "chunk_z"), da.zeros(grid.chunk_counts, dtype=bool, chunks=-1),
                           {"long_name": "whether the chunk's values are written"}),
    }
    encoding = {"measure": {"chunks": (c, c, c, n, len(BRANCHES))}, "reachability": {"chunks": (c, c, c)},
                "redundancy": {"chunks": (c, c, c)}, "chunk_complete": {"chunks": (1, 1, 1)}}
    coords = {
        "x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"}), "z": ("z", z, {"units": "m"}),
        "rotation": (("orientation", "row", "column"), rotations,
                     {"units": "1", "long_name": "tool orientation in the base frame", "set": _ORIENTATION_SET}),
    }
    attrs = {
        "title": f"workspace map of {chain.name}: exact feasible arm angles (paper 000)",
        "robot": chain.name, "arm": arm_description(chain), "branches": [str(b) for b in BRANCHES],
        "parameters": map_parameters(chain, grid, len(rotations)), "redkin_version": __version__,
    }
    dataset = xr.Dataset({name: xr.Variable(*spec) for name, spec in data.items()},
                         coords={name: xr.Variable(*spec) for name, spec in coords.items()}, attrs=attrs)
    dataset.to_zarr(path, mode="w", compute=False, zarr_format=2, encoding=encoding, safe_chunks=False)


def stored_parameters(path: Path) -> str | None:
    """The ``parameters`` attribute of the map at ``path``, or ``None`` where there is no map."""
    zarr = require("zarr")
    try:
        group = zarr.open_group(path, mode="r")
    except (FileNotFoundError, zarr.errors.GroupNotFoundError):
        return None
    return group.attrs.get("parameters")


def completed_chunks(path: Path) -> np.ndarray:
    """``chunk_complete`` of the map at ``path``, shape ``grid.chunk_counts``, from the names of its marker files.

    A marker is written (true) after its chunk's values and never written
    false, so a chunk is complete exactly where its marker file ``i.j.k``
    exists (zarr format 2).  One listing of the folder takes milliseconds;
    reading the markers one by one, most of them absent, took 26 s for the
    13 824 chunks of the 1 cm iiwa map.
    """
    complete = np.zeros(require("zarr").open_array(path, path="chunk_complete", mode="r").shape, dtype=bool)
    for entry in os.scandir(Path(path) / "chunk_complete"):
        index = entry.name.split(".")
        if len(index) == complete.ndim and all(part.isdigit() for part in index):
            complete[tuple(int(part) for part in index)] = True
    return complete


def write_chunk(path: Path, grid: WorkspaceGrid, index: tuple[int, int, int],
                measure: np.ndarray, reachability: np.ndarray, redundancy: np.ndarray) -> None:
    """Write one chunk's values, then mark it complete (a chunk interrupted between the two is recomputed)."""
    zarr = require("zarr")
    where = grid.chunk_slices(index)
    for name, values in (("measure", measure), ("reachability", reachability), ("redundancy", redundancy)):
        zarr.open_array(path, path=name, mode="r+")[where] = values
    zarr.open_array(path, path="chunk_complete", mode="r+")[index] = True
