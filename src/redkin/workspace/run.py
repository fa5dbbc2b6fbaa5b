"""Computing a workspace map chunk by chunk on Dask, into its Zarr store, resuming where a run stopped.

Each chunk (a cube of grid positions with every orientation and branch) is
one task of a Dask graph: it computes its measures
(:func:`redkin.workspace.measure.feasible_measures`) and indices, writes them
into the store and then marks the chunk complete, each file whole or not at
all (:func:`redkin.workspace.store.write_chunk`).  The same graph runs on
Dask's local scheduler (the default: threads of this process, nothing to
start) or, given a ``distributed.Client``, on a cluster whose workers can
write the store's path (the same machine or a shared file system).  A run
holds the store for itself (:func:`redkin.workspace.store.hold_store`; a
second run is refused) and, on a store that already holds the same map,
computes only the chunks not marked complete; a task lost with a dying
worker is rescheduled by Dask, and writing a chunk twice writes the same
values.  A full disk stops the run with one line
(:class:`redkin.errors.MapStoreError`), keeping every chunk complete so far.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import json
import os
import platform
import shutil
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import default_threads, set_threads
from redkin._validation import check_count
from redkin.arms import Arm
from redkin.arms import arm as redkin_arm
from redkin.chain import SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.srs import BRANCHES, NearlySRS
from redkin.workspace._optional import require
from redkin.workspace.grid import MAX_RESOLUTION, WorkspaceGrid, workspace_grid
from redkin.workspace.measure import feasible_measures, reachability_index, redundancy_index, whole_range
from redkin.workspace.orientations import MAX_ORIENTATIONS, super_fibonacci_rotations
from redkin.workspace.store import (
    MODEL_CERTIFIED,
    MODEL_EXACT,
    MODEL_NEARLY,
    completed_chunks,
    create_store,
    hold_store,
    map_parameters,
    no_space_errors,
    remove_partial_files,
    stored_parameters,
    write_chunk,
)

if TYPE_CHECKING:
    from redkin.collision import Body, Scene
    from redkin.workspace.measure import Cell

#: glibc's ``mallopt`` parameter number of the mmap threshold, and the threshold's dynamic maximum on 64-bit Linux.
M_MMAP_THRESHOLD, MMAP_THRESHOLD = -3, 32 * 1024 * 1024
#: Grid points per axis of one Dask task of the summary (a map of 1000^3 positions reads in 512 of them).
_SUMMARY_SPAN = 128
#: Poses per chunk of a map in a cell by default, by the redundancy parameter's name (``"nearly"`` for a nearly S-R-S
#: arm's arm angles), so that a chunk is seconds to a minute of work: a pose's certified collision-free arm angles
#: take milliseconds (0.5-2 s per thousand poses on the worked cell, most of a box being out of reach), its q7 sets
#: on the Franka class 0.2-0.8 s, a nearly S-R-S arm's 0.1-0.2 s and up to seconds (benchmarks/README.md).
_CELL_CHUNK_POSES = {"psi": 4096, "q7": 64, "nearly": 64}
#: Seconds a failed run on a cluster waits for the chunks its workers hold to be written.
_DRAIN_SECONDS = 300
#: ``progress(done, total)`` after each chunk of a run (``total`` counts the chunks this run computes).
Progress = Callable[[int, int], None]


@dataclass(frozen=True)
class WorkspaceRun:
    """What a run of :func:`workspace_map` did and what the map holds.

    Attributes
    ----------
    path : Path
        The Zarr store.
    positions, orientations, chunks : int
        Grid positions (``resolution ** 3``), orientations per position, chunks of the map.
    computed : int
        Chunks computed by this run (the others were complete already).
    reachable_positions : float
        Fraction of positions with a feasible arm angle at some orientation and branch.
    reachable_poses : float
        Fraction of position-orientation pairs with one (the mean reachability index).
    mean_redundancy : float
        Mean redundancy index over the reachable positions (0 if there are none).
    seconds : float
        Wall time of the run.
    model : str
        Whose feasible sets the map holds: ``"exact"`` (the arm's own), ``"nearly S-R-S neighbour"`` (a nearly
        S-R-S arm's exact neighbour) or ``"certified, the real arm"`` (a nearly S-R-S arm's own certified sets, in a
        cell; :data:`redkin.workspace.store.MODEL_EXACT`, ``MODEL_NEARLY``, ``MODEL_CERTIFIED``).
    model_error : str
        For a nearly S-R-S arm, what its neighbour drops and how far their poses differ
        (:meth:`redkin.srs.NearlySRS.describe`); empty for an exact arm.
    """

    path: Path
    positions: int
    orientations: int
    chunks: int
    computed: int
    reachable_positions: float
    reachable_poses: float
    mean_redundancy: float
    seconds: float
    model: str
    model_error: str

    @property
    def pose_branch_evaluations(self) -> int:
        """Exact feasible sets in the map: positions x orientations x 8 branches."""
        return self.positions * self.orientations * len(BRANCHES)


@functools.cache
def restore_mmap_threshold() -> bool:
    """Give glibc's malloc back its mmap threshold of 32 MiB where ``MALLOC_TRIM_THRESHOLD_`` took it away.

    Dask's nanny starts every worker with ``MALLOC_TRIM_THRESHOLD_=65536``.
    Setting any malloc threshold from the environment turns off glibc's
    dynamic mmap threshold, which otherwise rises to 32 MiB with the first
    large blocks freed: every numpy temporary above 128 kB is then mapped and
    unmapped anew, and its pages faulted in again, chunk after chunk (a
    chunk took 1.4-1.7 times the CPU time of a plain process; in a
    virtual machine the faults also stall).  This sets the threshold to the
    32 MiB the dynamic one reaches, once per process; trimming stays as the
    environment asks.  Nothing is changed where ``MALLOC_MMAP_THRESHOLD_``
    is set, where the trim threshold is not, or off glibc.

    Returns
    -------
    bool
        Whether the threshold was set.
    """
    if ("MALLOC_TRIM_THRESHOLD_" not in os.environ or "MALLOC_MMAP_THRESHOLD_" in os.environ
            or platform.libc_ver()[0] != "glibc"):
        return False
    return ctypes.CDLL(None).mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1


def match_worker_threads() -> int | None:
    """In a dask.distributed worker, give the process's compiled batches as many threads as the worker has.

    A worker's thread count is its share of the machine's cores (``dask
    worker`` and ``LocalCluster`` split the cores among the worker
    processes).  redkin's batch pool (:func:`redkin._compiled.run_batch`)
    would otherwise take every core in every worker process, so two
    single-threaded workers on two cores would run four threads.  The
    setting is the process's (:func:`redkin._compiled.set_threads`), and a
    worker process is the worker's own; the results do not depend on it.
    Outside a worker (Dask's local threaded scheduler) nothing changes.

    Returns
    -------
    int or None
        The threads set, or ``None`` outside a worker.
    """
    try:
        from distributed import get_worker

        worker = get_worker()
    except (ImportError, ValueError):  # ValueError: not in a worker
        return None
    threads = max(1, min(worker.state.nthreads, default_threads()))
    set_threads(threads)
    return threads


def _compute_chunk(arm: Arm, grid: WorkspaceGrid, rotations: np.ndarray, cell: Cell | None, path: Path,
                   index: tuple[int, int, int]) -> tuple[int, int, int]:
    """Compute chunk ``index`` of the map (in the ``cell``, where given) and write it into the store at ``path`` (one
    Dask task)."""
    restore_mmap_threshold()
    match_worker_threads()
    positions = grid.chunk_positions(index)
    shape = positions.shape[:3] + (len(rotations), len(arm.branches))
    measure = feasible_measures(arm, positions.reshape(-1, 3), rotations, cell).reshape(shape)
    write_chunk(path, grid, index, {"measure": measure, "reachability": reachability_index(measure),
                                    "redundancy": redundancy_index(measure, whole_range(arm))})
    return index


def _chunk_tasks(function: Callable, shared: tuple, indices: list[tuple[int, int, int]], name: str) -> list:
    """One Dask task ``function(*shared, index)`` per chunk index, as ``dask.delayed`` objects of one graph.

    The graph is one layer written out directly: the shared values are
    ``dask.delayed`` once each, and each task refers to them by key.  A
    ``dask.delayed`` call per chunk merged their graphs anew every time,
    about 0.6 ms per task (7-10 s for the 13 824 chunks of the 1 cm iiwa
    map on a loaded machine).

    Parameters
    ----------
    function : callable
        Called as ``function(*shared, index)``.
    shared : tuple
        Values passed to every task (stored once in the graph).
    indices : list of tuple of int
        The chunks, one task each.
    name : str
        The tasks' key prefix; key ``f"{name}-{index}"``.
    """
    dask = require("dask")
    from dask.delayed import Delayed
    from dask.highlevelgraph import HighLevelGraph
    from dask.typing import Key

    values = [dask.delayed(value, pure=True) for value in shared]
    references = [value.key for value in values]
    layer: dict[Key, tuple[Any, ...]] = {f"{name}-{index}": (function, *references, tuple(index)) for index in indices}
    graph = HighLevelGraph.from_collections(name, layer, dependencies=values)
    return [Delayed(key, graph, layer=name) for key in layer]


def prepare_store(path: Path, parameters: str, create: Callable[[Path], None]) -> None:
    """Create the store whole (or not at all), or check that the one at ``path`` holds this map (to resume it).

    Call it holding the store (:func:`~redkin.workspace.store.hold_store`): no other run then creates,
    resumes or writes it, so a creation an earlier run left unfinished (``NAME.creating``) and the
    ``*.partial`` files a killed writer left are garbage, and are removed here.

    Parameters
    ----------
    path : Path
        The store.
    parameters : str
        The map's parameters as the store records them (``stored_parameters`` reads them back).
    create : callable
        ``create(folder)`` writes a new, empty store into ``folder``; it is renamed to ``path`` once whole.

    Raises
    ------
    ValueError
        A path that holds something else, or a map with other parameters.
    MapStoreError
        ``reason="no space"``: the disk filled while the store was created (nothing of it is left).
    """
    stored = stored_parameters(path)
    if stored is None and path.exists():
        raise RedkinError(f"{str(path)!r} exists and is not a workspace map; choose another path")
    if stored is None:
        creating = path.with_name(path.name + ".creating")  # a store appears whole or not at all
        shutil.rmtree(creating, ignore_errors=True)
        try:
            with no_space_errors(path, "nothing was written; free space and run again"):
                create(creating)
        except BaseException:
            shutil.rmtree(creating, ignore_errors=True)
            raise
        creating.rename(path)
    elif stored != parameters:
        raise RedkinError(f"{str(path)!r} holds a map with other parameters (another {_differing(stored, parameters)})"
                          "; choose another path or remove it")
    else:
        remove_partial_files(path)


#: How the error of :func:`prepare_store` names each parameter of a stored map (its ``map_parameters`` keys).
_PARAMETER_WORDS = {"cell": "cell (the body, the scene or its margin)", "model": "model (exact, nearly S-R-S or "
                    "certified)"}


def _differing(stored: str, parameters: str) -> str:
    """The parameters (canonical JSON objects, as stores record them) on which a stored map and this one differ, in
    words."""
    old, new = json.loads(stored), json.loads(parameters)
    keys = sorted(key for key in set(old) | set(new) if old.get(key) != new.get(key))
    return ", ".join(_PARAMETER_WORDS.get(key, key) for key in keys)


def run_chunks(function: Callable, shared: tuple, path: Path, grid: WorkspaceGrid, name: str, parameters: str,
               client: Any, progress: Progress | None) -> int:
    """Compute the chunks of the store at ``path`` not yet marked complete, one Dask task each; returns how many.

    ``function(*shared, index)`` computes, writes and marks chunk ``index``; the tasks' keys are
    ``name`` with a token of the store and ``parameters``, so a resumed map reuses none of another map's.
    ``client`` (a ``distributed.Client``) runs them on a cluster, ``None`` on Dask's local threaded scheduler.
    Call it holding the store (:func:`~redkin.workspace.store.hold_store`).

    Raises
    ------
    MapStoreError
        ``reason="no space"``: the disk filled; the chunks complete so far are kept, and a run with space resumes.
    """
    dask = require("dask")
    complete = completed_chunks(path)
    missing = [index for index in grid.chunk_indices() if not complete[index]]
    token = dask.base.tokenize(str(path.resolve()), parameters)
    tasks = _chunk_tasks(function, shared, missing, f"{name}-{token}")

    def state() -> str:
        return (f"{int(completed_chunks(path).sum())} of {complete.size} chunks are complete and kept; "
                "free space and run again to resume")

    with no_space_errors(path, state):
        if client is None:
            _run_local(tasks, progress)
        else:
            _run_distributed(tasks, client, progress)
    return len(missing)


def _run_local(tasks: list, progress: Progress | None) -> None:
    """Compute ``tasks`` on Dask's local threaded scheduler, reporting each finished chunk.

    On an error (or Ctrl-C) the chunks under way are written to the end before it is raised, so nothing
    computed is lost and no thread of this run still writes the store once it returns.
    """
    dask = require("dask")
    from dask.callbacks import Callback

    keys = {task.key for task in tasks}
    done = [0]

    class ChunkProgress(Callback):
        def _posttask(self, key: Any, result: Any, dsk: Any, state: Any, worker_id: Any) -> None:
            if key in keys and progress is not None:
                done[0] += 1
                progress(done[0], len(keys))

    with ChunkProgress(), ThreadPoolExecutor(os.cpu_count() or 1, thread_name_prefix="redkin-map") as pool:
        try:
            dask.compute(*tasks, scheduler="threads", pool=pool)
        except BaseException:
            pool.shutdown(wait=True, cancel_futures=True)
            raise


def _run_distributed(tasks: list, client: Any, progress: Progress | None) -> None:
    """Compute ``tasks`` on a dask.distributed cluster, reporting each finished chunk.

    Everything goes through ``client`` and its event loop, never Dask's default client or scheduler: a client made
    with ``set_as_default=False`` works, and another client that is the default is not touched
    (``distributed.as_completed`` without ``loop`` and ``distributed.wait`` look the default client up).
    On an error (or Ctrl-C) the chunks not started are cancelled and those the workers hold already are
    waited for (:data:`_DRAIN_SECONDS` at most) before it is raised, as on the local scheduler.
    """
    distributed = require("distributed")
    futures = client.compute(tasks)
    try:
        for done, future in enumerate(distributed.as_completed(futures, loop=client.loop), start=1):
            future.result()  # raises the task's error here
            if progress is not None:
                progress(done, len(futures))
    except BaseException:
        _drain(client, futures)
        raise


def _drain(client: Any, futures: list) -> None:
    """Cancel the futures no worker holds, and wait for the ones the workers hold to end (their errors ignored).

    A task running on a worker cannot be stopped: cancelled, it would go on writing after the run had
    returned and let the store go.  Where the scheduler cannot be asked, everything is cancelled.  Like
    :func:`_run_distributed`, it waits on ``client``'s own loop (``distributed.wait`` needs a default client).
    """
    distributed = require("distributed")
    try:
        held = {key for keys in client.processing().values() for key in keys}
    except Exception:  # the scheduler is gone: nothing to wait for
        held = set()
    client.cancel([f for f in futures if not f.done() and f.key not in held])
    with contextlib.suppress(Exception):  # a task's error, or the time up
        for _ in distributed.as_completed([f for f in futures if f.key in held], loop=client.loop,
                                          timeout=_DRAIN_SECONDS):
            pass


def map_model(arm: SerialChain, srs_tolerance: float | None = None) -> tuple[Arm, NearlySRS | None]:
    """The arm whose exact feasible sets make the map of ``arm``, and for a nearly S-R-S arm its neighbour.

    An S-R-S, offset-elbow or Franka-class arm is mapped with its own sets (:meth:`redkin.Arm.feasible`; ``None``
    second).  An arm within ``srs_tolerance`` of an exact neighbour (:func:`redkin.arms.classify.arm_angle_class` says
    nearly S-R-S) is mapped with the neighbour's (:attr:`redkin.srs.NearlySRS.neighbour`): the same kernels at
    the same poses, which is not the real arm's set (docs/workspace.md, "Nearly S-R-S arms").

    Parameters
    ----------
    arm : SerialChain
    srs_tolerance : float, optional
        The nearly S-R-S tolerance (metres between axes that must meet, radians off perpendicular); default
        :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`.  An exact arm does not use it (it is still checked).

    Raises
    ------
    NotArmAngleClassError
        For an arm of none of these classes within the tolerance, with the reasons.
    RedkinError
        For a tolerance that is not a finite number > 0.
    """
    mapped = redkin_arm(arm, srs_tolerance=srs_tolerance)
    if mapped.parameter is None:
        raise NotArmAngleClassError(f"a workspace map needs a redundancy parameter with exact feasible sets: "
                                    f"{arm.name!r} has none ({mapped.reason})", arm.name)
    nearly = mapped.implementation.nearly
    return (mapped, None) if nearly is None else (redkin_arm(nearly.neighbour), nearly)


def workspace_map(
    arm: SerialChain,
    path: str | Path,
    extent: ArrayLike,
    resolution: int,
    orientations: int,
    *,
    chunk: int | None = None,
    client: Any = None,
    progress: Progress | None = None,
    srs_tolerance: float | None = None,
    body: Body | None = None,
    scene: Scene | None = None,
) -> WorkspaceRun:
    """Exact reachability and redundancy map of an arm with arm-angle IK over a box, into a Zarr store.

    With ``body`` and ``scene``, the map of the certified collision-free sets instead: reachability inside the cell
    (:func:`redkin.collision.free_sets_of`; docs/workspace.md, "In a cell").  A chunk then holds about
    :data:`_CELL_CHUNK_POSES` poses by default (4096 arm angles' poses, 64 of the Franka class's or of a nearly
    S-R-S arm's), since a pose takes milliseconds to a second.

    A nearly S-R-S arm (the Kinova Gen3, the Jaco2, the ROS-Industrial iiwa) is mapped with the exact feasible
    sets of its exact S-R-S neighbour at the same poses (:func:`map_model`); the run's ``model`` and
    ``model_error`` and the store's attributes say so.  In a cell it is mapped with its own certified
    collision-free sets (read off the real arm's self-motion; model ``"certified, the real arm"``).

    Parameters
    ----------
    arm : SerialChain
        An arm with arm-angle IK (S-R-S or offset elbow; :func:`redkin.srs.srs_geometry`), or a nearly S-R-S arm
        (:func:`redkin.srs.nearly_srs`).
    path : str or Path
        The Zarr store; resumed if it holds the same map, created if absent.
    extent : array_like, shape (6,)
        ``xmin, xmax, ymin, ymax, zmin, zmax`` of the box of tool positions, metres.
    resolution : int
        Grid points per axis (``2..1000``), ends included.
    orientations : int
        Tool orientations per position (``1..20000``): :func:`super_fibonacci_rotations`.
    chunk : int, optional
        Grid points per axis of a chunk (default: about 262144 poses per chunk,
        :data:`redkin.workspace.grid.CHUNK_POSES`).
    client : distributed.Client, optional
        Run on this cluster instead of Dask's local threaded scheduler.
    progress : callable, optional
        ``progress(done, total)`` after each chunk computed.
    srs_tolerance : float, optional
        The largest departure of an arm mapped as nearly S-R-S through its exact neighbour (metres between axes
        that must meet, radians off perpendicular; default :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).
        Unused by an exact arm.  A store resumes only a map of the same model and neighbour.
    body, scene : Body and Scene, optional
        Together: the arm's body and the cell's obstacles (:mod:`redkin.collision`).  A store resumes only a map of
        the same cell.

    Returns
    -------
    WorkspaceRun

    Raises
    ------
    ValueError
        For an arm without arm-angle IK (within ``srs_tolerance``), a malformed size, extent or tolerance, a path
        that holds something else (another map included: another arm, grid, model, neighbour or cell), a body
        without a scene or a scene without a body.
    MapStoreError
        A ``ValueError`` too: another run holds the store (``reason="in use"``), or the disk filled
        (``reason="no space"``; the chunks complete so far are kept, and the same call resumes).
    ImportError
        Without the ``workspace`` extra, in one line saying how to install it.
    """
    started = time.perf_counter()
    require("dask")
    require("zarr")
    mapped, nearly = map_model(arm, srs_tolerance)
    cell = _cell(body, scene)
    count = check_count(orientations, "orientations", 1, MAX_ORIENTATIONS)
    if chunk is None and cell is not None:
        chunk = cell_chunk(check_count(resolution, "resolution", 2, MAX_RESOLUTION), count, mapped, nearly)
    certified = cell is not None and nearly is not None
    if certified:  # in a cell a nearly S-R-S arm is mapped with its own certified collision-free sets
        mapped, nearly = redkin_arm(arm, srs_tolerance=srs_tolerance), None
    grid = workspace_grid(extent, resolution, count, chunk)
    rotations = super_fibonacci_rotations(count)
    store = Path(path)
    parameters = map_parameters(arm, grid, count, None if nearly is None else nearly.neighbour, cell, certified)
    with hold_store(store):
        prepare_store(store, parameters,
                      lambda folder: create_store(folder, arm, grid, rotations, mapped, nearly, cell, certified))
        # workers write the absolute path: a cluster's workers need not share this process's working directory
        computed = run_chunks(_compute_chunk, (mapped, grid, rotations, cell, store.absolute()), store, grid,
                              "workspace-chunk", parameters, client, progress)
    return _summary(store, grid, count, computed, time.perf_counter() - started, nearly, certified)


def cell_chunk(resolution: int, orientations: int, mapped: Arm, nearly: NearlySRS | None) -> int:
    """Grid points per axis of a chunk of a map in a cell of the arm ``mapped, nearly`` of :func:`map_model`: about
    :data:`_CELL_CHUNK_POSES` poses."""
    assert mapped.parameter is not None  # map_model refuses an arm without one
    poses = _CELL_CHUNK_POSES["nearly" if nearly is not None else mapped.parameter.name]
    return max(1, min(int(round((poses / orientations) ** (1.0 / 3.0))), resolution))



def _cell(body: Body | None, scene: Scene | None) -> Cell | None:
    """The body and the scene of a map in a cell, checked (:func:`workspace_map`'s errors), or ``None``."""
    if body is None and scene is None:
        return None
    if body is None or scene is None:
        raise RedkinError("a map in a cell needs both the arm's body and the scene")
    return body, scene


def _summary(store: Path, grid: WorkspaceGrid, orientations: int, computed: int, seconds: float,
             nearly: NearlySRS | None, certified: bool) -> WorkspaceRun:
    """Read the map's indices back (chunked) into a :class:`WorkspaceRun`."""
    xr = require("xarray")
    span = grid.chunk * max(1, _SUMMARY_SPAN // grid.chunk)  # whole store chunks, few Dask tasks
    with xr.open_zarr(store, chunks={axis: span for axis in "xyz"}) as dataset:
        reach = dataset["reachability"]
        reached = reach > 0.0
        fractions = [float(value) for value in
                     require("dask").compute(reached.mean().data, reach.mean().data, reached.sum().data,
                                             dataset["redundancy"].where(reached, 0.0).sum().data, scheduler="threads")]
    return WorkspaceRun(
        path=store, positions=grid.resolution ** 3, orientations=orientations, chunks=len(grid.chunk_indices()),
        computed=computed, reachable_positions=fractions[0], reachable_poses=fractions[1],
        mean_redundancy=fractions[3] / fractions[2] if fractions[2] else 0.0, seconds=seconds,
        model=MODEL_CERTIFIED if certified else MODEL_EXACT if nearly is None else MODEL_NEARLY,
        model_error="" if nearly is None else nearly.describe(),
    )
