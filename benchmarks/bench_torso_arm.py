"""Throughput of the thesis 001 manipulability maps (wrist positions and postures per second).

Run: ``python benchmarks/bench_torso_arm.py``.  Targets: a 200 x 200 map at
fixed (psi, phi) in under 1 s; the best map over the redundancy, compiled
(issue 13), on both cores.  No peer library implements this arm's
shoulder/elbow-angle IK, so there is no side-by-side column; the "before"
numbers of benchmarks/README.md come from the same script run on the numpy
version (commit a22aa14) in the same session.
"""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import best_time

from redkin._compiled import default_threads, set_threads
from redkin.torso_arm import humanoid_arm
from redkin.torso_arm.maps import (
    best_dual_arm_map,
    best_manipulability_map,
    dual_arm_map,
    manipulability_map,
    plane_grid,
)


def map_rows() -> list[tuple[str, str, int, float]]:
    """(name, grid, postures per point, seconds) of the 2-D maps."""
    arm = humanoid_arm()
    grid = plane_grid("z=0.3", (-0.3, 1.1, -0.6, 1.0), 200)
    small = plane_grid("z=0.3", (-0.3, 1.1, -0.6, 1.0), 100)
    return [
        ("right arm, fixed (psi, phi), theta4 ref", "200 x 200", 1,
         best_time(lambda: manipulability_map(arm, grid, 0.2, 0.3, reference="theta4"), repeat=5)),
        ("right arm, fixed (psi, phi), vector ref", "200 x 200", 1,
         best_time(lambda: manipulability_map(arm, grid, 0.2, 0.3, reference="vector"), repeat=5)),
        ("both arms, fixed (psi, phi)", "200 x 200", 1,
         best_time(lambda: dual_arm_map(grid, 0.2, 0.3, reference="vector"), repeat=5)),
        ("right arm, best over 24 x 24 redundancy", "100 x 100", 576,
         best_time(lambda: best_manipulability_map(arm, small, (24, 24)), repeat=2)),
        ("both arms, best over 24 x 24 redundancy", "100 x 100", 576,
         best_time(lambda: best_dual_arm_map(small, (24, 24)), repeat=2)),
    ]


def scaling_rows() -> list[tuple[str, str, int, float]]:
    """The best map on one thread and on all (redkin's batch pool; results are the same bit for bit)."""
    arm = humanoid_arm()
    grid = plane_grid("z=0.3", (-0.3, 1.1, -0.6, 1.0), 60)
    rows = []
    for threads in (1, default_threads()):
        set_threads(threads)
        rows.append((f"right arm, best 24 x 24, {threads} thread(s)", "60 x 60", 576,
                     best_time(lambda: best_manipulability_map(arm, grid, (24, 24)), repeat=3)))
    set_threads(None)
    return rows


def workspace_row() -> list[tuple[str, str, int, float]]:
    """The 3-D humanoid map (both measures) on Dask's local scheduler, if the workspace extra is installed."""
    try:
        from redkin.models import get_robot
        from redkin.workspace.humanoid import humanoid_map
    except ImportError:
        return []
    chain = get_robot("humanoid-right")
    folder = Path(tempfile.mkdtemp())
    try:
        def run() -> None:
            shutil.rmtree(folder / "map.zarr", ignore_errors=True)
            humanoid_map(chain, folder / "map.zarr", (-0.3, 1.1, -0.9, 0.9, -0.9, 0.9), 20, (24, 24))

        seconds = best_time(run, repeat=2)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return [("3-D map, both measures, local scheduler", "20^3", 576, seconds)]


def main() -> None:
    rows = map_rows() + scaling_rows() + workspace_row()
    print(f"load average {os.getloadavg()[0]:.2f} (1 min), {os.cpu_count()} cores")
    print(f"{'map':<44} {'grid':>10} {'IK/point':>9} {'seconds':>9} {'postures/s':>12}")
    for name, size, per_point, seconds in rows:
        sides = [int(s) for s in size.replace("^3", "").split(" x ")]
        points = sides[0] ** 3 if size.endswith("^3") else sides[0] * sides[1]
        print(f"{name:<44} {size:>10} {per_point:>9} {seconds:>9.3f} {points * per_point / seconds:>12.3g}")


if __name__ == "__main__":
    main()
