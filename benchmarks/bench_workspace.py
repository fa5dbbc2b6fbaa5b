"""Workspace-map throughput (redkin.workspace): per core, 2 workers over 1, and the 1 cm iiwa map on paper.

Run: ``python benchmarks/bench_workspace.py`` (needs ``pip install -e ".[workspace]"``).  It
computes one coarse map of the KUKA iiwa 14 over the box that holds its
reach (the 1 cm map's box, at a coarse resolution, so that the chunks mix
reachable and unreachable poses as the 1 cm map's do) on

* one process, chunk by chunk (the cost per chunk and per core),
* a ``distributed.LocalCluster`` of 1 and of 2 single-threaded worker processes,
* Dask's local threaded scheduler (the default of ``redkin workspace``),

and extrapolates the measured cost per pose to the 1 cm / 500-orientation map
on 100 workers.  No peer computes exact feasible arm-angle sets, so there is
no side-by-side column; the peers' maps sample IK instead.
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

from redkin.models import get_robot
from redkin.srs import BRANCHES
from redkin.workspace import workspace_grid, workspace_map

#: The box of the iiwa's reach: the shoulder at 0.36 m, shoulder to flange at most 0.42 + 0.40 + 0.126 m.
IIWA_BOX = (-0.95, 0.95, -0.95, 0.95, -0.59, 1.31)
FINE_STEP = 0.01  # metres: the 1 cm map
FINE_ORIENTATIONS = 500
WORKERS_ON_PAPER = 100
#: The worker environment docs/workspace.md advises: numpy temporaries up to 32 MB come from the heap.
WORKER_ENVIRONMENT = {"MALLOC_MMAP_THRESHOLD_": 33554432}


def timed_map(folder: Path, name: str, resolution: int, orientations: int, client=None) -> float:
    """Seconds of one whole map into a fresh store."""
    start = time.perf_counter()
    run = workspace_map(get_robot("kuka-iiwa14"), folder / f"{name}.zarr", IIWA_BOX, resolution, orientations,
                        client=client)
    seconds = time.perf_counter() - start
    assert run.computed == run.chunks
    return seconds


def cluster_seconds(folder: Path, name: str, workers: int, resolution: int, orientations: int,
                    mmap_threshold: bool = True) -> float:
    """Seconds of the map on a LocalCluster of ``workers`` single-threaded processes (started before timing).

    Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which
    turns off glibc's dynamic mmap threshold: every numpy temporary above
    128 kB is then mapped and unmapped anew.  ``mmap_threshold`` also sets
    ``MALLOC_MMAP_THRESHOLD_`` (:data:`WORKER_ENVIRONMENT`), as docs/workspace.md advises.
    """
    import dask
    from distributed import Client, LocalCluster

    environment = WORKER_ENVIRONMENT if mmap_threshold else {}
    with dask.config.set({f"distributed.nanny.pre-spawn-environ.{k}": v for k, v in environment.items()}), LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("redkin.workspace.run"))  # imports before the clock starts
        return timed_map(folder, name, resolution, orientations, client)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=12, help="grid points per axis of the measured map")
    parser.add_argument("--orientations", type=int, default=FINE_ORIENTATIONS)
    args = parser.parse_args()
    grid = workspace_grid(IIWA_BOX, args.resolution, args.orientations)
    poses = args.resolution ** 3 * args.orientations
    chunks = len(grid.chunk_indices())
    print(f"# workspace map benchmark -- {platform.machine()}, python {platform.python_version()}, "
          f"numpy {np.__version__}, {time.strftime('%Y-%m-%d')}")
    print(f"kuka-iiwa14, box {IIWA_BOX} m, {args.resolution}^3 positions x {args.orientations} orientations "
          f"= {poses} poses x 8 branches, {chunks} chunks of {grid.chunk}^3 positions")
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        timed_map(folder, "warm-up", 2, 2)  # imports and first calls out of the clock
        rows = [("local threaded scheduler (default)", timed_map(folder, "threads", args.resolution, args.orientations))]
        rows += [(f"LocalCluster, {n} worker process{'es' if n > 1 else ''}",
                  cluster_seconds(folder, f"cluster{n}", n, args.resolution, args.orientations)) for n in (1, 2)]
        rows.append(("LocalCluster, 1 worker, dask's environment",
                     cluster_seconds(folder, "default", 1, args.resolution, args.orientations, mmap_threshold=False)))
    one = rows[1][1]
    print(f"{'run':<42} {'seconds':>8} {'s/chunk':>8} {'pose-branch/s':>14} {'vs 1 worker':>12}")
    for name, seconds in rows:
        print(f"{name:<42} {seconds:>8.2f} {seconds / chunks:>8.3f} {poses * len(BRANCHES) / seconds:>14.3g} "
              f"{one / seconds:>11.2f}x")
    per_pose = one / poses  # seconds of one core per pose (8 branches), chunk writes and scheduling included
    fine = int(round((IIWA_BOX[1] - IIWA_BOX[0]) / FINE_STEP)) + 1
    fine_grid = workspace_grid(IIWA_BOX, fine, FINE_ORIENTATIONS)
    fine_poses = fine ** 3 * FINE_ORIENTATIONS
    core_seconds = per_pose * fine_poses
    print(f"1 cm map on paper: {fine}^3 positions x {FINE_ORIENTATIONS} orientations = {fine_poses:.3g} poses "
          f"({fine_poses * len(BRANCHES):.3g} pose-branch sets), {len(fine_grid.chunk_indices())} chunks; "
          f"{per_pose * 1e6:.1f} us per pose on one core -> {core_seconds / 3600:.1f} core-hours, "
          f"{core_seconds / WORKERS_ON_PAPER / 60:.1f} min on {WORKERS_ON_PAPER} workers at perfect scaling")


if __name__ == "__main__":
    main()
