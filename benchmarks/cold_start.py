"""Cold start: the first call of every compiled path of redkin in a new process with an empty numba cache, in seconds.

Run:  python benchmarks/cold_start.py [--repeat N]

A new process with a fresh ``NUMBA_CACHE_DIR`` imports redkin and calls each
public function that runs a compiled kernel once on one item and once on a
batch of 1000 (past ``redkin._compiled.PARALLEL_BATCH``, so a batch takes
the multi-threaded path), section by section: the chain (FK, frames,
Jacobian, manipulability, joint ranges), S-R-S IK (one branch, all eight,
reachability, coefficients), the S-R-S feasible sets, extrema, singular and
optimal arm angles and a path, the torso arm (IK, position IK, shoulder and
elbow angles, the four manipulability maps), the velocity steps (pinv, DLS,
adaptive DLS, minors, SC exact and lean, both controllers) and the virtual
arms (the analytic model and one generated trajectory).  Every kernel is
compiled there once (numba compiles on the first call of each argument
type) and written to the cache.  The same script then runs again on that
cache (warm: loading, not compiling).  Each line prints the seconds spent in
that section, wall-clock and the process's CPU time (compiling is serial:
on an idle machine the two agree, on a busy one the CPU time is the steadier
measure of the compile bill); the last line, the total from before
``import redkin`` to the end.  With ``--repeat N`` the cold run is made N
times (a fresh directory each time) and each run's times are listed.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile

FIRST_CALLS = r'''
import json, time
marks = [("start", time.perf_counter(), time.process_time())]
def mark(name):
    marks.append((name, time.perf_counter(), time.process_time()))

import numpy as np
import redkin
from redkin import models, srs, torso_arm, velocity, virtual_arms
from redkin.torso_arm import maps
mark("import")

rng = np.random.default_rng(0)
BATCH = 1000
for arm in (models.pa10_7c(), models.franka_panda()):  # standard and modified DH
    one, many = rng.uniform(-1, 1, 7), rng.uniform(-1, 1, (BATCH, 7))
    for q in (one, many):
        arm.fk(q), arm.frames(q), arm.jacobian(q), arm.jacobian(q, frame=4, offset=[0.0, 0.0, 0.1])
        arm.manipulability(q), arm.nearest_in_range(q)
mark("chain")

arm = models.pa10_7c().with_limits(np.full(7, -2.5), np.full(7, 2.5))
poses = arm.fk(rng.uniform(-1, 1, (BATCH, 7)))
for target in (poses[0], poses):
    srs.ik(arm, target, 0.1, "+-+"), srs.ik_all_branches(arm, target, 0.1), srs.reachable(arm, target)
    srs.coefficients.coefficients_for(arm, target, 1)
mark("srs ik")

for target in (poses[0], poses):
    srs.feasible_pieces(arm, target, "+-+"), srs.feasible_pieces_all_branches(arm, target)
    srs.feasible_arm_angles_batch(arm, target, "+-+")
srs.feasible_arm_angles(arm, poses[0]), srs.feasible_arm_angles(arm, poses[0], "+-+")
srs.joint_extrema(arm, poses[0], "+-+"), srs.singular_arm_angles(arm, poses[0], "+-+")
srs.optimal_arm_angles(arm, poses[0], "+-+")
srs.arm_angle_path(arm, poses[:20], "+-+")
mark("srs sets")

right = torso_arm.humanoid_arm("right")
wrists = right.chain.frames(rng.uniform(-0.5, 0.5, (BATCH, 8)))[:, 6, :3, 3]
for wrist in (wrists[0], wrists):
    solution = torso_arm.position_ik(right, wrist, 0.2, 0.1)
    torso_arm.ik(right, wrist, 0.2, 0.1, rotation=np.eye(3))
    theta1 = np.zeros(np.shape(wrist)[:-1])
    torso_arm.shoulder_angle(theta1, wrist), torso_arm.theta1_from_shoulder_angle(0.2, wrist)
    shoulder = right.shoulder(theta1)
    torso_arm.elbow_angle(right, shoulder, (shoulder + wrist) / 2, wrist)
for side in ("right", "left"):
    grid = maps.plane_grid("z=0.3", (0.0, 1.0, -0.4, 0.8), 40)  # 1600 points
    maps.manipulability_map(torso_arm.humanoid_arm(side), grid, 0.2, 0.1)
    maps.best_manipulability_map(torso_arm.humanoid_arm(side), maps.plane_grid("z=0.3", (0.0, 1.0, -0.4, 0.8), 4),
                                 samples=(4, 4))
maps.dual_arm_map(grid, 0.2, 0.1)
maps.best_dual_arm_map(maps.plane_grid("z=0.3", (0.0, 1.0, -0.4, 0.8), 4), samples=(4, 4))
mark("torso arm")

wam = models.barrett_wam()
factor = velocity.WamFactorisation.from_chain(wam)
twist = np.array([0.15, 0.0, 0.0, 0.0, 0.1, 0.0])
for q in (rng.uniform(-1, 1, 7), rng.uniform(-1, 1, (BATCH, 7))):
    jac = wam.jacobian(q)
    velocity.pseudoinverse(jac, twist), velocity.damped_least_squares(jac, twist, 0.1)
    velocity.adaptive_damped_least_squares(jac, twist, 0.1, 0.1)
    velocity.column_minors(jac)
    velocity.singularity_consistent(jac, twist, factor.index(q), factor.factors(q), 0.1)
    velocity.lean_singularity_consistent(jac, twist, factor.index(q), lambda: factor.factors(q), 0.1)
q = np.radians([30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0])
velocity.SingularityConsistentController(wam, q, eps=0.1)(q, twist)
velocity.PseudoinverseController(wam)(q, twist)
mark("velocity")

model = virtual_arms.AnalyticModel(models.pa10_7c(), [virtual_arms.VirtualPoint.end()])
model.evaluate(np.zeros(7)), model.evaluate(rng.uniform(-1, 1, (BATCH, 7)))
planar = virtual_arms.AnalyticModel(models.planar_arm(), [virtual_arms.VirtualPoint.end()])
virtual_arms.generate_trajectory(planar, np.radians([30.0] * 5), [[0.6, 1.2]])
mark("virtual arms")

print(json.dumps([(name, t - marks[i][1], c - marks[i][2]) for i, (name, t, c) in enumerate(marks[1:])]
                 + [("total", marks[-1][1] - marks[0][1], marks[-1][2] - marks[0][2])]))
'''


def run(cache: str) -> list[tuple[str, float, float]]:
    """The sections' seconds (wall, CPU) of one run of :data:`FIRST_CALLS` with ``NUMBA_CACHE_DIR=cache``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    result = subprocess.run([sys.executable, "-c", FIRST_CALLS], env=env, capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(result.stderr)
    return [tuple(pair) for pair in json.loads(result.stdout.strip().splitlines()[-1])]


def main() -> None:
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 1
    print(f"# cold start -- {platform.machine()}, {os.cpu_count()} cores, python {platform.python_version()}, "
          f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    colds = []
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as cache:
            colds.append(run(cache))
            warm = run(cache)
    print(f"{'section':<14} {'cold wall (s)':>14} {'cold CPU (s)':>13} {'warm wall (s)':>14}")
    for k, (name, seconds, _) in enumerate(warm):
        wall = " ".join(f"{c[k][1]:.1f}" for c in colds)
        cpu = " ".join(f"{c[k][2]:.1f}" for c in colds)
        print(f"{name:<14} {wall:>14} {cpu:>13} {seconds:>14.2f}")


if __name__ == "__main__":
    main()
