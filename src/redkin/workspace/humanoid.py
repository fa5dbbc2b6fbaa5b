"""The thesis 001 humanoid's 3-D workspace map: best manipulability over the redundancy per wrist position.

Thesis 001 (chapter 5, Figs. 5.1-5.6) maps the manipulability ``w`` of the
wrist position over planes, for one arm and for both arms; ``w`` depends on
the redundancy, so redkin maps its best value over theta_1 x phi samples
within the limits of joints 1-5 (:func:`redkin.torso_arm.maps.best_over_redundancy`).
This is the same map on a 3-D box, chunk by chunk on Dask into Zarr, on
the machinery of :func:`redkin.workspace.workspace_map` (the grid, the
local scheduler or a ``distributed.Client``, the store's lock, whole-file
writes, and resuming by the per-chunk completion markers).  A plane of it
equals the 2-D map (:func:`~redkin.torso_arm.maps.best_manipulability_map`)
on that plane, value for value.

Layout of the store (zarr format 2, ``xarray.open_zarr``):

* ``best_manipulability`` (x, y, z): m^3, the best ``w = sqrt(det(J J^T))``
  of this arm's wrist ([001 eq. 5.3]) over the samples within the limits; NaN
  where no sampled posture respects them;
* ``best_dual_manipulability`` (x, y, z): m^6, the best stacked dual-arm
  measure (our definition, :func:`~redkin.torso_arm.manipulability.stacked_dual_manipulability`)
  of the symmetric two-arm posture with this arm's wrist at the position;
  for the left arm, by symmetry, the right arm's value at the mirror image
  ``(-x, y, z)``; NaN likewise;
* ``reachable`` (x, y, z): some sampled posture of this arm exists, limits aside;
* coordinates ``x``, ``y``, ``z`` (metres), ``theta1`` (the torso samples
  in this arm's joint values, rad) and ``phi`` (the elbow-angle samples, rad);
* ``chunk_complete`` (chunk_x, chunk_y, chunk_z), as in every workspace map.

A chunk's values read NaN (``reachable`` False) until it is computed.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from redkin import __version__
from redkin._validation import check_count
from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.torso_arm.geometry import MIRROR, TorsoArm
from redkin.torso_arm.maps import (
    MAX_SWEEP_SAMPLES,
    ManipulabilityMap,
    PlaneGrid,
    best_over_redundancy,
    sweep_samples,
)
from redkin.workspace._optional import require
from redkin.workspace.grid import MAX_RESOLUTION, WorkspaceGrid, workspace_grid
from redkin.workspace.run import Progress, match_worker_threads, prepare_store, restore_mmap_threshold, run_chunks
from redkin.workspace.store import arm_description, durable_store, hold_store, write_chunk

#: The variables of a humanoid map, their units and what they hold.
VARIABLES = {
    "best_manipulability": ("m^3", "best w of the wrist position over theta_1 x phi within the limits of joints 1-5 "
                                   "([001 eq. 5.3])"),
    "best_dual_manipulability": ("m^6", "best stacked dual-arm measure, symmetric posture, within the limits"),
    "reachable": ("1", "some sampled posture of the arm exists (limits aside)"),
}
#: theta_1 x phi samples of a map unless told otherwise (those of the 2-D maps).
DEFAULT_SAMPLES = (24, 24)
#: Postures one chunk aims at (positions x samples x 2 measures): about a second of one core.
_CHUNK_POSTURES = 2_000_000


def humanoid_of(chain: SerialChain) -> TorsoArm | None:
    """The thesis 001 arm a chain describes (the Table 2.1 right arm, or its mirror image), or ``None``."""
    try:
        return TorsoArm(chain, "right")
    except ValueError:
        pass
    try:
        return TorsoArm(chain.mirrored(normal=(1.0, 0.0, 0.0), flip_joints=[0]), "left")
    except ValueError:
        return None


def humanoid_grid(extent: ArrayLike, resolution: int, samples: tuple[int, int] = DEFAULT_SAMPLES,
                   chunk: int | None = None) -> WorkspaceGrid:
    """The checked grid of a humanoid map; the default chunk holds about :data:`_CHUNK_POSTURES` postures.

    Raises
    ------
    ValueError
        Naming the malformed or out-of-range argument (``samples``: each ``1..MAX_SWEEP_SAMPLES``).
    """
    if np.ndim(samples) != 1 or len(samples) != 2:
        raise RedkinError(f"samples must be two positive integers (theta_1, phi), got {samples!r}")
    n1, n2 = (check_count(n, "samples", 1, MAX_SWEEP_SAMPLES) for n in samples)
    m = check_count(resolution, "resolution", 2, MAX_RESOLUTION)
    if chunk is None:
        edge = int(np.floor((_CHUNK_POSTURES / (2 * n1 * n2)) ** (1.0 / 3.0) + 1e-9))
        chunk = min(max(edge, 1), m)
    return workspace_grid(extent, m, 1, chunk)


def _humanoid_measures(arm: TorsoArm, positions: np.ndarray, samples: tuple[int, int]) -> dict[str, np.ndarray]:
    """The map's variables at wrist positions ``(..., 3)`` (metres): the per-chunk measure of a humanoid map."""
    best, reached = best_over_redundancy(arm, positions, samples)
    right = TorsoArm(arm.right_chain, "right")
    dual, _ = best_over_redundancy(right, positions if arm.side == "right" else positions @ MIRROR, samples, dual=True)
    return {"best_manipulability": best, "best_dual_manipulability": dual, "reachable": reached}


def _parameters(chain: SerialChain, grid: WorkspaceGrid, samples: tuple[int, int]) -> str:
    """What makes two humanoid maps the same map, as canonical JSON (compared when a run resumes)."""
    return json.dumps({
        "kind": "humanoid best manipulability", "arm": arm_description(chain),
        "extent": list(grid.extent), "resolution": grid.resolution, "samples": list(samples), "chunk": grid.chunk,
    }, sort_keys=True)


def _create_store(path: Path, chain: SerialChain, arm: TorsoArm, grid: WorkspaceGrid, samples: tuple[int, int]) -> None:
    """Write the metadata and coordinates of an empty humanoid map at ``path``."""
    xr = require("xarray")
    da = require("dask.array")
    m, c = grid.resolution, grid.chunk
    thetas, phis = sweep_samples(arm, samples)
    data = {name: (("x", "y", "z"), da.zeros((m, m, m), dtype=bool if name == "reachable" else float, chunks=c),
                   {"units": unit, "long_name": text}) for name, (unit, text) in VARIABLES.items()}
    data["chunk_complete"] = (("chunk_x", "chunk_y", "chunk_z"), da.zeros(grid.chunk_counts, dtype=bool, chunks=1),
                              {"long_name": "whether the chunk's values are written"})
    x, y, z = grid.axes
    coords = {
        "x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"}), "z": ("z", z, {"units": "m"}),
        "theta1": ("theta1", thetas, {"units": "rad", "long_name": "torso angle samples (this arm's joint 1)"}),
        "phi": ("phi", phis, {"units": "rad", "long_name": "elbow angle samples (the whole circle)"}),
    }
    attrs = {
        "title": f"workspace map of {chain.name}: best manipulability over the redundancy (thesis 001)",
        "robot": chain.name, "side": arm.side, "arm": arm_description(chain),
        "parameters": _parameters(chain, grid, samples), "redkin_version": __version__,
    }
    dataset = xr.Dataset({name: xr.Variable(*spec) for name, spec in data.items()},
                         coords={name: xr.Variable(*spec) for name, spec in coords.items()}, attrs=attrs)
    dataset.to_zarr(durable_store(path), mode="w", compute=False, zarr_format=2)


def _compute_humanoid_chunk(arm: TorsoArm, grid: WorkspaceGrid, samples: tuple[int, int], path: Path,
                           index: tuple[int, int, int]) -> tuple[int, int, int]:
    """Compute chunk ``index`` of a humanoid map, write it, then mark it complete, each file whole (one Dask task).

    On a dask.distributed worker it first fits the worker as every map's chunk task does
    (:func:`~redkin.workspace.run.match_worker_threads`, :func:`~redkin.workspace.run.restore_mmap_threshold`).
    """
    restore_mmap_threshold()
    match_worker_threads()
    write_chunk(path, grid, index, _humanoid_measures(arm, grid.chunk_positions(index), samples))
    return index


@dataclass(frozen=True)
class HumanoidRun:
    """What a run of :func:`humanoid_map` did and what the map holds.

    Attributes
    ----------
    path : Path
        The Zarr store.
    positions, chunks, computed : int
        Grid positions, chunks of the map, chunks computed by this run.
    samples : (int, int)
        theta_1 x phi samples per position.
    reachable_positions, feasible_positions : float
        Fractions of positions where some sampled posture exists, and where one respects the limits.
    max_manipulability, mean_manipulability : float
        Largest and mean ``best_manipulability`` over the feasible positions (m^3; 0 if none).
    max_dual_manipulability : float
        Largest ``best_dual_manipulability`` (m^6; 0 if none).
    seconds : float
        Wall time of the run.
    """

    path: Path
    positions: int
    chunks: int
    computed: int
    samples: tuple[int, int]
    reachable_positions: float
    feasible_positions: float
    max_manipulability: float
    mean_manipulability: float
    max_dual_manipulability: float
    seconds: float


def humanoid_map(
    chain: SerialChain,
    path: str | Path,
    extent: ArrayLike,
    resolution: int,
    samples: tuple[int, int] = DEFAULT_SAMPLES,
    *,
    chunk: int | None = None,
    client: Any = None,
    progress: Progress | None = None,
) -> HumanoidRun:
    """Best manipulability of the thesis 001 humanoid over a box of wrist positions, into a Zarr store.

    Parameters
    ----------
    chain : SerialChain
        The humanoid's arm: ``humanoid-right``, ``humanoid-left`` (:func:`redkin.models.get_robot`) or a chain
        of the same form (:func:`humanoid_of`).
    path : str or Path
        The Zarr store; resumed if it holds the same map, created if absent.
    extent : array_like, shape (6,)
        ``xmin, xmax, ymin, ymax, zmin, zmax`` of the box of wrist positions, metres.
    resolution : int
        Grid points per axis (``2..1000``), ends included.
    samples : (int, int)
        theta_1 x phi samples per position (each ``1..3600``; default 24 x 24, as the 2-D maps).
    chunk : int, optional
        Grid points per axis of a chunk (default: about :data:`_CHUNK_POSTURES` postures per chunk).
    client : distributed.Client, optional
        Run on this cluster instead of Dask's local threaded scheduler.
    progress : callable, optional
        ``progress(done, total)`` after each chunk computed.

    Returns
    -------
    HumanoidRun

    Raises
    ------
    ValueError
        For a chain that is not the humanoid's arm, a malformed size, extent or sample count,
        or a path that holds something else.
    MapStoreError
        A ``ValueError`` too: another run holds the store (``reason="in use"``), or the disk filled
        (``reason="no space"``; the chunks complete so far are kept, and the same call resumes).
    ImportError
        Without the ``workspace`` extra, in one line saying how to install it.
    """
    started = time.perf_counter()
    require("dask")
    require("zarr")
    arm = humanoid_of(chain)
    if arm is None:
        raise RedkinError(f"{chain.name!r} is not the thesis 001 humanoid's arm (Table 2.1 form or its mirror image)")
    grid = humanoid_grid(extent, resolution, samples, chunk)
    samples = (int(samples[0]), int(samples[1]))
    store = Path(path)
    parameters = _parameters(chain, grid, samples)
    with hold_store(store):
        prepare_store(store, parameters, lambda folder: _create_store(folder, chain, arm, grid, samples))
        computed = run_chunks(_compute_humanoid_chunk, (arm, grid, samples, store.absolute()), store, grid,
                              "humanoid-chunk", parameters, client, progress)
    return _summary(store, grid, samples, computed, time.perf_counter() - started)


def _summary(store: Path, grid: WorkspaceGrid, samples: tuple[int, int], computed: int, seconds: float) -> HumanoidRun:
    """Read the map back into a :class:`HumanoidRun`."""
    xr = require("xarray")
    with xr.open_zarr(store) as dataset:
        best = dataset["best_manipulability"]
        feasible = best.notnull()
        values = require("dask").compute(
            dataset["reachable"].mean().data, feasible.mean().data, best.max().data, best.mean().data,
            dataset["best_dual_manipulability"].max().data, scheduler="threads")
    values = [float(v) if np.isfinite(v) else 0.0 for v in values]
    return HumanoidRun(
        path=store, positions=grid.resolution ** 3, chunks=len(grid.chunk_indices()), computed=computed,
        samples=samples, reachable_positions=values[0], feasible_positions=values[1], max_manipulability=values[2],
        mean_manipulability=values[3], max_dual_manipulability=values[4], seconds=seconds,
    )


def mid_plane_maps(dataset: Any, name: str) -> list[ManipulabilityMap]:
    """A stored map's variable ``name`` on its three mid-planes (z, y, x fixed) as 2-D maps, for drawing."""
    axes = [np.asarray(dataset[a].values) for a in "xyz"]
    values = np.asarray(dataset[name].values, dtype=float)
    maps = []
    for fixed in (2, 1, 0):
        middle = axes[fixed].size // 2
        u_axis, v_axis = (a for a in range(3) if a != fixed)
        plane = np.take(values, middle, axis=fixed).T  # (v, u)
        points = np.zeros(plane.shape + (3,))
        points[..., fixed] = axes[fixed][middle]
        points[..., u_axis] = axes[u_axis][None, :]
        points[..., v_axis] = axes[v_axis][:, None]
        grid = PlaneGrid(points, "xyz"[fixed], float(axes[fixed][middle]), ("xyz"[u_axis], "xyz"[v_axis]),
                         axes[u_axis], axes[v_axis])
        valid = np.isfinite(plane)
        maps.append(ManipulabilityMap(grid, plane, valid, np.where(valid, 0, 1),
                                      f"{dataset.attrs.get('robot', '')}: {name}"))
    return maps
