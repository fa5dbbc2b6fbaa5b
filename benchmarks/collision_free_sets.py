"""Issue 40: certified collision-free sets of the classes without a rigid turn to lean on: q7 of the Franka class
(``redkin.collision.collision_free_q7``) and the arm angles of nearly S-R-S arms (``redkin.collision.nearly_free``),
both through ``redkin.collision.collision_free_set``.

Run: ``python benchmarks/collision_free_sets.py`` (a few minutes on 2 cores); ``--poses N`` (8 per arm).

The setup. The Panda, the FR3, the xArm7 and the Kinova Gen3 with their built-in bodies (capsules fitted to the
makers' collision meshes, with self-collision pairs) in the cell of tests/test_collision_free_q7.py: a post beside the
arm, a table under its reach and a lamp above it, margin 0.01 m. Poses: the FK of configurations drawn uniformly
within the limits (``numpy.random.default_rng(40)``). Per pose, all eight branches at resolution 1e-6 rad, one call
after a warm-up call of the process; the median and quartiles over the poses, and the configurations evaluated.

Beside it, for scale (not a peer: no library computes these sets), what sampling would cost with redkin's own compiled
distances: 10^4 values of the parameter across its domain, the eight branches by one batched ``arm.ik`` and the
clearance of every configuration by one batched ``redkin.collision.clearance``; it proves nothing between samples (on
the Gen3, 10^4 arm angles of the solver polished on the real arm).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import redkin
from redkin.collision import builtin_body, clearance, collision_free_set, scene_of

CELL = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.45, 0.25, -0.2], "b": [0.45, 0.25, 1.2], "radius": 0.05},
    {"name": "table", "type": "box", "center": [0.6, 0, -0.06], "size": [1.2, 1.0, 0.1]},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.4, 0.8], "radius": 0.12}]}
ARMS = ("franka-panda", "franka-fr3", "ufactory-xarm7", "kinova-gen3")
SAMPLES = 10_000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--poses", type=int, default=8, help="poses per arm (default 8)")
    count = parser.parse_args().poses
    scene = scene_of(CELL)
    print(f"{'arm':16} {'ours: median [quartiles] per pose':36} {'evaluations: median (max)':26} sampled 10^4")
    for name in ARMS:
        arm = redkin.arm(name)
        body = builtin_body(name, arm.chain)
        rng = np.random.default_rng(40)
        low, high = np.maximum(arm.chain.lower, -np.pi), np.minimum(arm.chain.upper, np.pi)
        poses = arm.fk(rng.uniform(low, high, (count, 7)))
        collision_free_set(arm, poses[0], body, scene)  # compiles and warms the process
        seconds, evaluations = [], []
        for pose in poses:
            start = time.perf_counter()
            free = collision_free_set(arm, pose, body, scene)
            seconds.append(time.perf_counter() - start)
            evaluations.append(free.evaluations)
        values = np.linspace(*arm.parameter.domain, SAMPLES)
        start = time.perf_counter()
        solutions = arm.ik(poses[0], values)
        clearance(arm.chain, body, scene, solutions.q.reshape(-1, 7))
        sampled = time.perf_counter() - start
        quartiles = np.percentile(seconds, [25, 50, 75]) * 1e3
        print(f"{name:16} {quartiles[1]:7.0f} ms [{quartiles[0]:.0f}, {quartiles[2]:.0f}]{'':15} "
              f"{int(np.median(evaluations)):7d} ({max(evaluations)}){'':12} {sampled * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
