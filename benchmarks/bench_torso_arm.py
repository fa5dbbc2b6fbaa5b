"""Map throughput of the thesis 001 manipulability maps (wrist positions per second).

Run: ``python benchmarks/bench_torso_arm.py``.  Target: a 200 x 200 map at
fixed (psi, phi) in under 1 s on one core.  No peer library implements this
arm's shoulder/elbow-angle IK, so there is no side-by-side column.
"""

from __future__ import annotations

import time

from redkin.torso_arm import humanoid_arm
from redkin.torso_arm.maps import best_dual_arm_map, best_manipulability_map, dual_arm_map, manipulability_map, plane_grid


def timed(function, repeats: int = 3) -> float:
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def main() -> None:
    arm = humanoid_arm()
    rows = []
    grid = plane_grid("z=0.3", (-0.3, 1.1, -0.6, 1.0), 200)
    n = grid.points.shape[0] * grid.points.shape[1]
    seconds = timed(lambda: manipulability_map(arm, grid, 0.2, 0.3, reference="theta4"))
    rows.append(("right arm, fixed (psi, phi), theta4 ref", "200 x 200", 1, seconds, n / seconds))
    seconds = timed(lambda: manipulability_map(arm, grid, 0.2, 0.3, reference="vector"))
    rows.append(("right arm, fixed (psi, phi), vector ref", "200 x 200", 1, seconds, n / seconds))
    seconds = timed(lambda: dual_arm_map(grid, 0.2, 0.3, reference="vector"))
    rows.append(("both arms, fixed (psi, phi)", "200 x 200", 1, seconds, n / seconds))
    small = plane_grid("z=0.3", (-0.3, 1.1, -0.6, 1.0), 100)
    m = small.points.shape[0] * small.points.shape[1]
    seconds = timed(lambda: best_manipulability_map(arm, small, (24, 24)), repeats=1)
    rows.append(("right arm, best over 24 x 24 redundancy", "100 x 100", 576, seconds, m * 576 / seconds))
    seconds = timed(lambda: best_dual_arm_map(small, (24, 24)), repeats=1)
    rows.append(("both arms, best over 24 x 24 redundancy", "100 x 100", 576, seconds, m * 576 / seconds))
    print(f"{'map':<44} {'grid':>10} {'IK/point':>9} {'seconds':>9} {'postures/s':>12}")
    for name, size, per_point, secs, rate in rows:
        print(f"{name:<44} {size:>10} {per_point:>9} {secs:>9.3f} {rate:>12.3g}")


if __name__ == "__main__":
    main()
