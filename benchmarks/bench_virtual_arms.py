"""Benchmark of the virtual-arm trajectory generation (paper 004).

Run: ``python benchmarks/bench_virtual_arms.py``.  Prints, per run of the
paper-004 report section (Fig. 6 (a)-(d), a clamped joint, Fig. 7, the literal
eq. 10 gain), the wall time to equilibrium against the 2 s target, the obstacle
runs (Fig. 8 (a)-(c), the PA10 elbow case; no target), and the time
to train the learned end-point model to the stated held-out accuracy (RMS
below 5 mm for joints in [-1.5, 1.5] rad, sine hidden units).
"""

from __future__ import annotations

import time

from redkin.models import planar_arm
from redkin.reproduce.paper_004 import run_cases, run_obstacle_cases
from redkin.virtual_arms import VirtualPoint, learn_forward_model

TARGET_SECONDS = 2.0
STATED_RMS = 5e-3


def main() -> None:
    print(f"{'case':<44} {'status':<10} {'steps':>6} {'evals':>7} {'time [s]':>9}  target < {TARGET_SECONDS:g} s")
    for case in run_cases():
        run = case.run
        verdict = "ok" if run.seconds < TARGET_SECONDS else "SLOWER"
        print(f"{case.name:<44} {run.status:<10} {run.steps:>6} {run.evaluations:>7} {run.seconds:>9.3f}  {verdict}")
    print()
    print(f"{'obstacle case':<44} {'status':<10} {'steps':>6} {'periods':>7} {'time [s]':>9}  min clearance [mm]")
    for case in run_obstacle_cases():
        run = case.run
        print(f"{case.name:<44} {run.status:<10} {run.steps:>6} {run.periods:>7} {run.seconds:>9.3f}  "
              f"{run.min_clearance * 1000:.1f}")
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
        print(f"{'12 sine units, 400 L-BFGS iterations':<44} {samples:>7} {rms * 1000:>18.3f} {seconds:>15.3f}  {verdict}")


if __name__ == "__main__":
    main()
