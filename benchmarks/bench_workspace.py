"""Workspace-map throughput (redkin.workspace): per core, 2 workers over 1, and the 1 cm iiwa map on paper.

Run: ``python benchmarks/bench_workspace.py`` (needs ``pip install -e ".[workspace]"``).  It
computes one coarse map of the KUKA iiwa 14 over the box that holds its
reach (the 1 cm map's box, at a coarse resolution, so that the chunks mix
reachable and unreachable poses as the 1 cm map's do; by default 24^3
positions, 27 chunks of the default 8^3 positions) on

* Dask's local threaded scheduler (the default of ``redkin workspace``),
* a ``distributed.LocalCluster`` of 1 and of 2 single-threaded worker processes,
  in ``--rounds`` rounds, the order of the two alternating,

with the worker processes' CPU time beside the wall time and the load
average before and after each run (the machine may be shared), and
extrapolates the measured cost per pose to the 1 cm / 500-orientation map on
100 workers.  No peer computes exact feasible arm-angle sets, so there is no
side-by-side column; the peers' maps sample IK instead.
"""

from __future__ import annotations

import argparse
import os
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


def load() -> str:
    """The 1-minute load average."""
    with open("/proc/loadavg") as handle:
        return handle.read().split()[0]


def process_seconds() -> float:
    """CPU seconds (user + system) of the calling process."""
    times = os.times()
    return times.user + times.system


def timed_map(folder: Path, name: str, resolution: int, orientations: int, client=None) -> tuple[float, float]:
    """Wall seconds and CPU seconds (of the worker processes, or of this process) of one whole map into a fresh
    store."""
    cpu = (lambda: sum(client.run(process_seconds).values())) if client is not None else process_seconds
    cpu_start, start = cpu(), time.perf_counter()
    run = workspace_map(get_robot("kuka-iiwa14"), folder / f"{name}.zarr", IIWA_BOX, resolution, orientations,
                        client=client)
    seconds = time.perf_counter() - start
    assert run.computed == run.chunks
    return seconds, cpu() - cpu_start


def cluster_map(folder: Path, name: str, workers: int, resolution: int, orientations: int) -> tuple[float, float]:
    """:func:`timed_map` on a LocalCluster of ``workers`` single-threaded processes (started and warmed before
    timing)."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        timed_map(folder, f"{name}-warm-up", 2, 2, client)  # imports and compiled kernels loaded in every worker
        return timed_map(folder, name, resolution, orientations, client)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, default=24, help="grid points per axis of the measured map")
    parser.add_argument("--orientations", type=int, default=FINE_ORIENTATIONS)
    parser.add_argument("--rounds", type=int, default=2, help="rounds of the 1- and 2-worker runs")
    args = parser.parse_args()
    grid = workspace_grid(IIWA_BOX, args.resolution, args.orientations)
    poses = args.resolution ** 3 * args.orientations
    chunks = len(grid.chunk_indices())
    print(f"# workspace map benchmark -- {platform.machine()}, {os.cpu_count()} cores, python "
          f"{platform.python_version()}, numpy {np.__version__}, {time.strftime('%Y-%m-%d %H:%M')}")
    print(f"kuka-iiwa14, box {IIWA_BOX} m, {args.resolution}^3 positions x {args.orientations} orientations "
          f"= {poses} poses x 8 branches, {chunks} chunks of {grid.chunk}^3 positions")
    print(f"{'run':<36} {'wall s':>7} {'cpu s':>7} {'cpu s/chunk':>11} {'pose-branch/s':>13} {'load':>11}")
    rows: dict[str, list[tuple[float, float]]] = {}

    def row(name: str, measure) -> None:
        before = load()
        seconds, cpu = measure()
        rows.setdefault(name, []).append((seconds, cpu))
        print(f"{name:<36} {seconds:>7.2f} {cpu:>7.2f} {cpu / chunks:>11.3f} {poses * len(BRANCHES) / seconds:>13.3g} "
              f"{before:>5}->{load():<5}", flush=True)

    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        timed_map(folder, "warm-up", 2, 2)  # imports and compiled kernels loaded
        row("local threaded scheduler (default)",
            lambda: timed_map(folder, "threads", args.resolution, args.orientations))
        for round_ in range(args.rounds):
            for workers in ((1, 2) if round_ % 2 == 0 else (2, 1)):
                name = f"LocalCluster, {workers} worker process{'es' if workers > 1 else ''}"
                row(name, lambda: cluster_map(folder, f"cluster{workers}-{round_}", workers, args.resolution,
                                              args.orientations))
    one = [seconds for seconds, _ in rows["LocalCluster, 1 worker process"]]
    two = [seconds for seconds, _ in rows["LocalCluster, 2 worker processes"]]
    print(f"2 workers over 1 (wall): {min(one) / min(two):.2f}x best against best, "
          f"{', '.join(f'{a / b:.2f}x' for a, b in zip(one, two))} round by round")
    # the cost of a pose on a core of its own: the worker's CPU time, chunk writes and scheduling included
    per_pose = min(cpu for _, cpu in rows["LocalCluster, 1 worker process"]) / poses
    fine = int(round((IIWA_BOX[1] - IIWA_BOX[0]) / FINE_STEP)) + 1
    fine_grid = workspace_grid(IIWA_BOX, fine, FINE_ORIENTATIONS)
    fine_chunks = len(fine_grid.chunk_indices())
    fine_poses = fine ** 3 * FINE_ORIENTATIONS
    core_seconds = per_pose * fine_poses
    print(f"1 cm map on paper: {fine}^3 positions x {FINE_ORIENTATIONS} orientations = {fine_poses:.3g} poses "
          f"({fine_poses * len(BRANCHES):.3g} pose-branch sets), {fine_chunks} chunks of {fine_grid.chunk}^3; "
          f"{per_pose * 1e6:.2f} us per pose on one core, {core_seconds / fine_chunks:.2f} s per chunk -> "
          f"{core_seconds / 3600:.2f} core-hours, {core_seconds / WORKERS_ON_PAPER / 60:.1f} min on "
          f"{WORKERS_ON_PAPER} workers at perfect scaling")


if __name__ == "__main__":
    main()
