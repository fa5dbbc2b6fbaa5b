"""The Zarr store of a workspace map: its layout, its attributes, its per-chunk completion markers and its lock.

Layout (zarr format 2, readable with ``xarray.open_zarr``):

* ``measure`` (x, y, z, orientation, branch): radians, branches in the order of :data:`redkin.srs.BRANCHES`
  (the feasible set of the arm angle, or of q7 on a Franka-class arm: attributes ``parameter``, ``parameter_range``);
* ``reachability``, ``redundancy`` (x, y, z): dimensionless, in ``[0, 1]``;
* coordinates ``x``, ``y``, ``z`` (metres) and ``rotation`` (orientation, row, column);
* ``chunk_complete`` (chunk_x, chunk_y, chunk_z): set once a chunk's values are written, after them.

A chunk's values are NaN until it is computed.  The map's parameters (arm,
grid, orientations, chunk, and for a nearly S-R-S arm the exact neighbour whose
sets the map holds) are stored as attributes; a run on an existing store with
the same parameters resumes it, one with others is refused.  The attribute
``model`` says whose feasible sets the map holds: :data:`MODEL_EXACT` (the
arm's own), :data:`MODEL_NEARLY` (a nearly S-R-S arm's exact neighbour,
with ``model_error``, ``departures`` and ``neighbour`` beside it) or
:data:`MODEL_CERTIFIED` (a nearly S-R-S arm's own certified collision-free
sets, in a cell).  A store written before ``model`` existed is an exact arm's.

What a crash leaves
-------------------
Every file of a chunk (its values in each array, then its marker in
``chunk_complete``) is written whole or not at all: into a temporary file
``.NAME.<random>.partial`` beside it, flushed to the disk (``fsync``), then
renamed over ``NAME`` (``os.replace``, atomic on POSIX) and the folder's
entry flushed too (:func:`write_chunk`).  The marker is written only after
the chunk's values are on the disk, so a process killed at any moment, a
power cut or a full disk leaves each chunk either marked with its whole
values, or unmarked (recomputed by the next run, with the same values), plus
at most a few ``.partial`` files, which the next run removes
(:func:`remove_partial_files`).  A reader of the store meanwhile sees a
chunk's old values or its new ones, never a torn file.

Why atomic files rather than a digest of the data in the marker: a digest
has to be checked against the data on every resume to mean anything, which
reads the whole map (the ``measure`` of the 1 cm iiwa map is about 220 GB)
and still leaves torn files for readers in between; with whole-or-nothing
files the markers' names stay the whole truth, and a resume stays one listing
of a folder (:func:`completed_chunks`).  The ``fsync`` calls cost a few
milliseconds per chunk (docs/workspace.md); they order the writes against a
power cut, where the disk could otherwise keep the marker's rename but not
the values' blocks.  (The writing itself is :mod:`redkin.workspace._durable`.)

One run at a time holds a store (:func:`hold_store`: an exclusive ``flock``
on ``NAME.lock`` beside it, which the kernel releases when the process dies,
so a crashed run never leaves a stale lock); a second run is refused with one
line, :class:`redkin.errors.MapStoreError`.  The store is created and
resumed only under that lock, so two runs started at once on a new path
create it once: one runs, the other is refused.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import socket
import time
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from redkin import __version__
from redkin._constants import PARTIAL_SUFFIX
from redkin._constants import WORKSPACE_MAP_NAME as MAP_NAME  # noqa: F401  (the map's file name; redkin.workspace)
from redkin.arms import Arm
from redkin.chain import SerialChain
from redkin.errors import MapStoreError
from redkin.srs import NearlySRS
from redkin.workspace._optional import require
from redkin.workspace.grid import WorkspaceGrid

if TYPE_CHECKING:
    from redkin.collision import Body, Scene
    from redkin.workspace.measure import Cell

_ORIENTATION_SET = "super-Fibonacci spiral on SO(3) (Alexa, CVPR 2022), deterministic in the count"
#: ``errno`` values of a full disk or an exhausted quota.
_NO_SPACE = (errno.ENOSPC, errno.EDQUOT)
#: The store's ``model``: the map holds the arm's own exact feasible sets, or those of a nearly S-R-S arm's exact
#: neighbour (:func:`redkin.srs.nearly_srs`).
MODEL_EXACT, MODEL_NEARLY, MODEL_CERTIFIED = "exact", "nearly S-R-S neighbour", "certified, the real arm"
_NEARLY_NOTE = ("the measures are the exact feasible arm-angle sets of the arm's exact S-R-S neighbour (attribute "
                "neighbour) at the same poses, not the real arm's; the real sets differ near their ends and near "
                "singular wrists (docs/workspace.md, Nearly S-R-S arms)")


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


def map_parameters(chain: SerialChain, grid: WorkspaceGrid, orientations: int,
                   neighbour: SerialChain | None = None, cell: Cell | None = None, certified: bool = False) -> str:
    """What makes two maps the same map, as canonical JSON (compared when a run resumes).

    ``neighbour`` is the exact S-R-S neighbour whose feasible sets make the map of a nearly S-R-S arm
    (:attr:`redkin.srs.NearlySRS.neighbour`), ``None`` for an arm mapped with its own.  An exact arm's
    parameters have no ``model`` entry (as before nearly S-R-S maps existed, so its stores still resume); a
    nearly S-R-S arm's name the model and the neighbour, so a store of one model, or of another neighbour
    (another tolerance that changes it), is not resumed by the other.  A map in a ``cell`` (the arm's body and a
    scene) names the body's capsules and checked pairs and the scene's obstacles and margin; a map without one has
    no ``cell`` entry.  A nearly S-R-S arm's map in a cell is of the real arm's ``certified`` collision-free sets
    (model :data:`MODEL_CERTIFIED`).
    """
    parameters: dict[str, Any] = {
        "arm": arm_description(chain), "extent": list(grid.extent), "resolution": grid.resolution,
        "orientations": orientations, "chunk": grid.chunk,
    }
    if neighbour is not None:
        parameters["model"] = {"kind": MODEL_NEARLY, "neighbour": arm_description(neighbour)}
    if certified:
        parameters["model"] = {"kind": MODEL_CERTIFIED}
    if cell is not None:
        parameters["cell"] = _cell_description(*cell)
    return json.dumps(parameters, sort_keys=True)


def _cell_description(body: Body, scene: Scene) -> dict[str, Any]:
    """The body and the scene of a map in a cell, as JSON data: everything the map's values depend on (a store
    resumes only the same), and where they come from."""
    return {
        "body": {"source": body.source, "links": list(body.link), "frames": body.frame.tolist(),
                 "a": body.a.tolist(), "b": body.b.tolist(), "radius": body.radius.tolist(),
                 "pairs": body.pairs.tolist()},
        "scene": {"source": scene.source, "obstacles": list(scene.names), "shapes": scene.shapes.tolist(),
                  "margin": scene.margin},
    }


def create_store(path: Path, chain: SerialChain, grid: WorkspaceGrid, rotations: np.ndarray, mapped: Arm,
                 nearly: NearlySRS | None = None, cell: Cell | None = None, certified: bool = False) -> None:
    """Write the metadata and coordinates of an empty map at ``path`` (values NaN, no chunk complete).

    ``mapped`` is the arm whose feasible sets the map holds (:func:`redkin.workspace.run.map_model`): its parameter
    names the measure (``parameter``, ``parameter_range`` attributes).  ``nearly`` is given for a nearly S-R-S arm
    mapped with its exact neighbour's feasible sets: the attributes then say so (``model``, ``model_error``,
    ``departures``, ``neighbour``, ``model_note``).  ``cell`` (the arm's body and a scene) makes it the map of the
    collision-free sets, and the attribute ``cell`` says which (its sources, obstacles, margin and links; all of it
    is in the ``parameters``).  ``certified``: a nearly S-R-S arm's map in a cell, of its own certified sets (model
    :data:`MODEL_CERTIFIED`).
    """
    xr = require("xarray")
    da = require("dask.array")
    m, n, c = grid.resolution, len(rotations), grid.chunk
    x, y, z = grid.axes
    whose = ("" if nearly is None else " of the exact S-R-S neighbour") + ("" if cell is None else
                                                                           ", collision-free in the cell")
    kind = "certified" if certified or cell is not None else "exact"  # a cell's sets: ends to the resolution
    assert mapped.parameter is not None  # map_model refuses an arm without one
    name, equation = mapped.parameter.prefix, mapped.parameter.equation
    low, high = mapped.parameter.domain
    position = ("x", "y", "z")
    # lazy templates of one Dask chunk each (a graph of a few tasks, never computed); the store's chunks are set
    # by the encoding: one per map chunk (13 824 Dask chunks per array made the 1 cm map's metadata take 30 s)
    data = {
        "measure": (position + ("orientation", "branch"), da.zeros((m, m, m, n, len(mapped.branches)), chunks=-1),
                    {"units": "rad", "long_name": f"measure of the feasible {name} set{whose} ({equation})",
                     "branches": list(mapped.branches)}),
        "reachability": (position, da.zeros((m, m, m), chunks=-1),
                         {"units": "1",
                          "long_name": f"fraction of orientations with a feasible {name} value on some branch"}),
        "redundancy": (position, da.zeros((m, m, m), chunks=-1),
                       {"units": "1",
                        "long_name": "mean over reachable orientations of the largest branch measure / the "
                                     f"parameter's range ({high - low:.6g} rad)"}),
        "chunk_complete": (("chunk_x", "chunk_y", "chunk_z"), da.zeros(grid.chunk_counts, dtype=bool, chunks=-1),
                           {"long_name": "whether the chunk's values are written"}),
    }
    encoding = {"measure": {"chunks": (c, c, c, n, len(mapped.branches))}, "reachability": {"chunks": (c, c, c)},
                "redundancy": {"chunks": (c, c, c)}, "chunk_complete": {"chunks": (1, 1, 1)}}
    coords = {
        "x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"}), "z": ("z", z, {"units": "m"}),
        "rotation": (("orientation", "row", "column"), rotations,
                     {"units": "1", "long_name": "tool orientation in the base frame", "set": _ORIENTATION_SET}),
    }
    attrs: dict[str, Any] = {
        "title": f"workspace map of {chain.name}: {kind} feasible {name} sets{whose}",
        "robot": chain.name, "arm": arm_description(chain), "branches": list(mapped.branches),
        "parameter": mapped.parameter.name, "parameter_range": [low, high],
        "parameters": map_parameters(chain, grid, len(rotations), None if nearly is None else nearly.neighbour, cell,
                                     certified),
        "redkin_version": __version__, "model": MODEL_CERTIFIED if certified else MODEL_EXACT,
    }
    if cell is not None:  # what the map is of, to read (all of the cell is in the parameters)
        body, scene = cell
        attrs["cell"] = {"scene": {"source": scene.source, "obstacles": list(scene.names), "margin": scene.margin},
                         "body": {"source": body.source, "links": list(body.link), "self_pairs": len(body.pairs)}}
    if nearly is not None:
        attrs.update({
            "model": MODEL_NEARLY, "model_error": nearly.describe(), "model_note": _NEARLY_NOTE,
            "departures": [{"what": what, "value": float(value), "unit": unit}
                           for what, value, unit in nearly.departures],
            "neighbour": arm_description(nearly.neighbour),
        })
    dataset = xr.Dataset({name: xr.Variable(*spec) for name, spec in data.items()},
                         coords={name: xr.Variable(*spec) for name, spec in coords.items()}, attrs=attrs)
    dataset.to_zarr(durable_store(path), mode="w", compute=False, zarr_format=2, encoding=encoding,
                    safe_chunks=False)


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


def write_chunk(path: Path, grid: WorkspaceGrid, index: tuple[int, int, int], values: Mapping[str, np.ndarray]) -> None:
    """Write one chunk's values into their arrays, then mark it complete; each file whole or not at all.

    Parameters
    ----------
    path : Path
        The store.
    grid : WorkspaceGrid
        Its grid (the chunk's slices).
    index : tuple of int
        The chunk.
    values : mapping of str to ndarray
        The chunk's values by array name, each shaped as the chunk's slice of its array.

    Notes
    -----
    zarr encodes the values and hands each chunk file to the store, which
    writes it durably (:func:`redkin._files.write_durably`); the
    arrays are written one after the other and the marker last, so the marker
    exists only where every value file is whole on the disk.
    """
    zarr = require("zarr")
    store = durable_store(path)
    where = grid.chunk_slices(index)
    for name, array in values.items():
        zarr.open_array(store, path=name, mode="r+")[where] = array
    zarr.open_array(store, path="chunk_complete", mode="r+")[index] = True


def durable_store(path: Path) -> Any:
    """The Zarr store at ``path``, a ``zarr.storage.LocalStore`` that writes every file whole or not at all.

    ``xarray.Dataset.to_zarr`` and ``zarr.open_array`` take it in place of the path
    (:class:`redkin.workspace._durable.DurableStore`; zarr is imported here, on first use).
    """
    require("zarr")
    from redkin.workspace._durable import DurableStore

    return DurableStore(Path(path))


def remove_partial_files(path: Path) -> int:
    """Remove the ``*.partial`` files a killed writer left in the store's arrays; returns how many.

    Called by a run that holds the store (:func:`hold_store`), before it
    writes: no writer of its own is under way, and a file a run killed
    earlier was writing is garbage (its chunk is not marked, so it is
    computed again).
    """
    removed = 0
    for folder in [Path(path), *(Path(entry.path) for entry in os.scandir(path) if entry.is_dir())]:
        for entry in os.scandir(folder):
            if entry.name.endswith(PARTIAL_SUFFIX) and entry.is_file():
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(entry.path)
                    removed += 1
    return removed


@contextlib.contextmanager
def hold_store(path: Path) -> Iterator[None]:
    """Hold the map at ``path`` for this process while the block runs; another run on it is refused.

    The lock is an exclusive ``fcntl.flock`` on ``NAME.lock`` beside the
    store (it can be taken before the store exists, so creating one is
    covered too).  The kernel releases it when the process ends, however it
    ends, so a crashed run never leaves a stale lock: its file, if left,
    is taken by the next run.  The file is removed on release while still
    held; a run that opened it in between sees another file at the name and
    opens that one instead.  It holds one line saying which process holds it
    (for the refusal).  The lock is advisory and local to a machine unless
    the file system shares ``flock`` locks (NFS does, as POSIX locks, on
    Linux).

    Raises
    ------
    MapStoreError
        ``reason="in use"``: another process holds the store.
    """
    import fcntl

    lock = Path(path).with_name(Path(path).name + ".lock")
    lock.parent.mkdir(parents=True, exist_ok=True)
    while True:
        descriptor = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(descriptor, 200, 0).decode(errors="replace").strip() or "starting"
            os.close(descriptor)
            raise MapStoreError(f"{str(path)!r} is in use by another run ({holder}); wait for it to end, or choose "
                                "another path", str(path), "in use") from None
        except BaseException:
            os.close(descriptor)
            raise
        try:
            held = os.fstat(descriptor)
            current = os.stat(lock)
            if (held.st_dev, held.st_ino) == (current.st_dev, current.st_ino):
                break
        except FileNotFoundError:
            pass
        os.close(descriptor)  # the holder removed this file as it finished: take the one now at the name
    try:
        with contextlib.suppress(OSError):  # the note is a courtesy; a full disk must not stop the run here
            note = f"pid {os.getpid()} on {socket.gethostname()} since {time.strftime('%Y-%m-%d %H:%M:%S')}"
            os.ftruncate(descriptor, 0)
            os.pwrite(descriptor, note.encode(), 0)
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(lock)
        os.close(descriptor)


@contextlib.contextmanager
def no_space_errors(path: Path, state: str | Callable[[], str]) -> Iterator[None]:
    """Turn a full disk (or quota) met in the block into one line: :class:`~redkin.errors.MapStoreError`.

    Parameters
    ----------
    path : Path
        What was being written, named in the message.
    state : str or callable
        What the failure leaves and what to do, the end of the message (a callable is asked when the error
        comes, e.g. to count the chunks complete by then).

    Raises
    ------
    MapStoreError
        ``reason="no space"``, e.g. "no space left on device writing '/data/map.zarr': 12 of 27 chunks are
        complete and kept; free space and run again to resume".
    """
    try:
        yield
    except OSError as exc:
        if exc.errno not in _NO_SPACE:
            raise
        end = state() if callable(state) else state
        raise MapStoreError(f"{os.strerror(exc.errno).lower()} writing {str(path)!r}: {end}", str(path),
                            "no space") from None
