"""Issue 40: collision-free numerical IK on a chain without a redundancy parameter (the Sawyer), beside the same
solver without the scene.

Run: ``python benchmarks/collision_free_ik.py`` (about a minute on 2 cores); ``--poses N`` (200).

The setup.  ``redkin.arm("sawyer.urdf")`` (the example Sawyer, solved numerically: its shoulder and wrist axes do not
meet).  Its body: seven capsules, one per moving link, each from its frame's origin to the next frame's at the zero
configuration, radius 0.06 m, no self-collision pairs (APPROXIMATIONS FOR TIMING ONLY, not Rethink's geometry: the
example URDF has no collision elements).  The scene: the ten obstacles of ``benchmarks/collision_free.py`` (a floor,
four boxes, three capsules, two spheres), margin 0.01 m.  Targets: the FK of configurations drawn uniformly within
the limits whose own body clears the scene by the margin, so that every target has a collision-free solution
("reachable collision-free targets"; ``numpy.random.default_rng(40)``).

Measured, all targets in one batch, best of 3 calls after a warm-up call:

* without the scene: ``redkin.numerical.ik(chain, poses, count=1, rng=0)``;
* with it: ``redkin.collision.collision_free_ik(chain, body, scene, poses, count=1, rng=0)``.

Certified: a target whose returned solution reaches it (the solver's certificate, checked again by our FK to 1e-9 m
and 1e-9 in the rotation), lies within the limits and keeps the margin (its least distance measured again).

Targets (issue 40): at least 99 % of the targets certified, in at most 2 x the time without the scene.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from collision_free import cell, draw_poses

import redkin
from redkin.chain import SerialChain
from redkin.collision import BodyCapsule, body_of, clearance, collision_free_ik
from redkin.collision.body import Body
from redkin.numerical import ik

TARGET_SHARE, TARGET_RATIO = 0.99, 2.0
RADIUS = 0.06


def sawyer_body(chain: SerialChain) -> Body:
    """One capsule per moving link, from its frame's origin to the next frame's at the zero configuration (module
    docstring: approximate, for timing only), without self-collision pairs."""
    frames = chain.frames(np.zeros(chain.n))
    capsules = []
    for k in range(1, chain.n + 1):
        there = np.linalg.solve(frames[k], frames[k + 1][:, 3])[:3]  # the next frame's origin in frame k
        capsules.append(BodyCapsule(f"link {k}", k, [0.0, 0.0, 0.0], there.tolist(), RADIUS))
    links = [capsule.link for capsule in capsules]
    every_pair = [(first, second) for i, first in enumerate(links) for second in links[i + 1:]]
    return body_of(capsules, chain, ignore=every_pair, notes=("approximate capsules for timing only",),
                   source="benchmarks/collision_free_ik.py")


def best(call, repeats: int = 3) -> tuple[float, object]:
    """The best wall time of ``repeats`` calls, and the last result."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = call()
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--poses", type=int, default=200, help="targets (default 200)")
    count = parser.parse_args().poses
    arm = redkin.arm("sawyer.urdf")
    chain = arm.chain
    body, scene = sawyer_body(chain), cell()
    poses = draw_poses(arm, body, scene, count)
    print(f"python benchmarks/collision_free_ik.py --poses {count}; {os.cpu_count()} cores; load at start "
          f"{', '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print(f"{chain.name}: {len(body)} capsules (approximate, for timing only), {len(scene)} obstacles, margin "
          f"{scene.margin} m; {count} targets whose drawn configuration clears the scene")
    ik(chain, poses[:2], count=1, rng=0)  # compiles and warms the process
    collision_free_ik(chain, body, scene, poses[:2], count=1, rng=0)
    plain_seconds, plain = best(lambda: ik(chain, poses, count=1, rng=0))
    free_seconds, free = best(lambda: collision_free_ik(chain, body, scene, poses, count=1, rng=0))
    q, found = free.q[:, 0], free.found[:, 0]
    error = np.abs(chain.fk(q) - poses)
    reaches = (error[:, :3, 3].max(axis=1) <= 1e-9) & (error[:, :3, :3].max(axis=(1, 2)) <= 1e-9)
    within = chain.within_limits(q)
    clear = clearance(chain, body, scene, q).distance >= scene.margin
    certified = found & reaches & within & clear
    share, ratio = certified.mean(), free_seconds / plain_seconds
    print(f"without the scene: {plain_seconds * 1e3:8.1f} ms ({plain_seconds / count * 1e6:.0f} us a target), "
          f"{plain.found[:, 0].mean() * 100:.1f} % found")
    print(f"with the scene:    {free_seconds * 1e3:8.1f} ms ({free_seconds / count * 1e6:.0f} us a target); "
          f"the first candidate clear on {int((free.candidates == 1).sum())} of {count} targets, the others "
          f"examined up to {int(free.candidates.max())} ({int(free.candidates.sum())} in all)")
    print(f"{'measurement':52} {'value':>9} {'target':>9}")
    print(f"{'targets certified collision-free':52} {share * 100:8.1f}% {'>= 99 %':>9} "
          f"{'met' if share >= TARGET_SHARE else 'MISSED'}")
    print(f"{'time with the scene / without':52} {ratio:8.2f}x {'<= 2 x':>9} "
          f"{'met' if ratio <= TARGET_RATIO else 'MISSED'}")
    print(f"load at the end {', '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
