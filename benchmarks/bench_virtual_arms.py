"""Benchmark of the virtual-arm trajectory generation (paper 004).

Run: ``python benchmarks/bench_virtual_arms.py``.  Prints, per run of the
paper-004 report section (Fig. 6 (a)-(d), a clamped joint, Fig. 7, the literal
eq. 10 gain), the wall time to equilibrium against the 2 s target, the obstacle
runs (Fig. 8 (a)-(c), the PA10 elbow case; no target), and the time
to train the learned end-point model to the stated held-out accuracy (RMS
below 5 mm for joints in [-1.5, 1.5] rad, sine hidden units).

The rate function (the analytic model's end points and eqs. 9-14) is
compiled (:mod:`redkin.virtual_arms._kernels`); one short run before the
table loads the kernels (or compiles them on a cold cache; its time is
printed), so the rows time the runs themselves.  The load average is
printed: two runs of this script compare only at similar load.
"""

from __future__ import annotations

import os
import time

import numpy as np

from redkin.models import planar_arm
from redkin.reproduce.paper_004 import _run_cases, _run_obstacle_cases
from redkin.virtual_arms import AnalyticModel, VirtualPoint, generate_trajectory, learn_forward_model

TARGET_SECONDS = 2.0
STATED_RMS = 5e-3


def warm_up() -> float:
    """Seconds of one short run of the planar arm (loads or compiles the kernels)."""
    started = time.perf_counter()
    generate_trajectory(AnalyticModel(planar_arm(), [VirtualPoint.end()]), np.full(5, 0.5), [[0.6, 1.2]], max_steps=5)
    return time.perf_counter() - started


def main() -> None:
    print(f"load average (1, 5, 15 min): {' '.join(f'{v:.2f}' for v in os.getloadavg())}, {os.cpu_count()} cores; "
          f"first run (kernels loaded or compiled): {warm_up():.2f} s")
    print(f"{'case':<44} {'status':<10} {'steps':>6} {'evals':>7} {'time [s]':>9}  target < {TARGET_SECONDS:g} s")
    cases = _run_cases()
    for case in cases:
        run = case.run
        verdict = "ok" if run.seconds < TARGET_SECONDS else "SLOWER"
        print(f"{case.name:<44} {run.status:<10} {run.steps:>6} {run.evaluations:>7} {run.seconds:>9.3f}  {verdict}")
    print(f"{'all Fig. 6 / 7 runs':<44} {'':<10} {'':>6} {'':>7} {sum(c.run.seconds for c in cases):>9.3f}")
    print()
    print(f"{'obstacle case':<44} {'status':<10} {'steps':>6} {'periods':>7} {'time [s]':>9}  min clearance [mm]")
    obstacle_cases = _run_obstacle_cases()
    for case in obstacle_cases:
        run = case.run
        print(f"{case.name:<44} {run.status:<10} {run.steps:>6} {run.periods:>7} {run.seconds:>9.3f}  "
              f"{run.min_clearance * 1000:.1f}")
    print(f"{'all obstacle runs':<44} {'':<10} {'':>6} {'':>7} {sum(c.run.seconds for c in obstacle_cases):>9.3f}")
    arm = planar_arm()
    print()
    print(f"{'learned end-point model':<44} {'samples':>7} {'held-out RMS [mm]':>18} {'train time [s]':>15}")
    for samples in (400, 800):
        started = time.perf_counter()
        _, report = learn_forward_model(arm, [VirtualPoint.end()], samples=samples, held_out=300, hidden=12,
                                        iterations=400, lower=[-1.5] * 5, upper=[1.5] * 5, seed=0)
        seconds = time.perf_counter() - started
        rms = float(report.held_out_rms[0])
        verdict = "meets 5 mm" if rms < STATED_RMS else "misses 5 mm"
        print(f"{'12 sine units, 400 L-BFGS iterations':<44} {samples:>7} {rms * 1000:>18.3f} "
              f"{seconds:>15.3f}  {verdict}")


if __name__ == "__main__":
    main()
