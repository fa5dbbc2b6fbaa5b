"""Issue 26's targets for path resolution (redkin.paths), measured in one run.

Run:  python benchmarks/bench_paths.py [--long N]

* time of ``resolve_path`` on an iiwa14 path of 1000 waypoints (all 8 branches, the default objective, the
  feasible sets included), warm, at step bounds of 0.2 and 0.05 rad (``--long`` N adds N waypoints at 0.2),
  with the graph's size (nodes; about 100 bytes each at the peak);
* random paths (straight joint-space lines between random in-limit configurations, 30 waypoints, a step bound
  of 1.5 x the line's largest step): how often the global path is found, and how often greedy seeded tracking,
  the fixed arm angle and the clamped per-pose optimum break a limit or the bound there;
* against the sampled DP on a uniform grid (the literature's method) on short random paths: the same yes/no,
  and the clearance difference;
* the narrow passage (a feasible set 1e-4 rad wide at one waypoint): found, and whether the sampled DP finds it.

ssik's ``Manipulator.solve_path`` is not compared yet.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from redkin.models import get_robot
from redkin.paths import (
    clamped_optimum_path,
    fixed_psi_path,
    greedy_path,
    resolve_path,
    sampled_path,
)
from redkin.srs import arm_angle_of

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def line(chain, rng, count, fraction=1.0):
    """A straight joint-space line of ``count`` waypoints between two configurations 0.2 rad inside the limits."""
    lower, upper = chain.lower + 0.2, chain.upper - 0.2
    a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
    q = a + fraction * (b - a) * np.linspace(0.0, 1.0, count)[:, None]
    return q, chain.fk(q)


def timed(function, repeat=3):
    best, result = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def scaling(chain, cases):
    rng = np.random.default_rng(0)
    q, _ = line(chain, rng, 2, 0.3)
    print("| waypoints | step bound (rad) | time (s) | per waypoint (us) | nodes | status |")
    print("|---|---|---|---|---|---|")
    for count, step in cases:
        path = q[0] + (q[1] - q[0]) * np.linspace(0.0, 1.0, count)[:, None]
        poses = chain.fk(path)
        seconds, result = timed(lambda: resolve_path(chain, poses, step), 1)
        print(f"| {count} | {step:.3g} | {seconds:.3f} | {1e6 * seconds / count:.1f} | {result.nodes} | "
              f"{result.status} |", flush=True)


def random_paths(chain, count=20, length=30):
    rng = np.random.default_rng(1)
    found = greedy_bad = fixed_bad = clamped_bad = 0
    where = []
    for _ in range(count):
        q, poses = line(chain, rng, length)
        step = 1.5 * np.abs(np.diff(q, axis=0)).max()
        result = resolve_path(chain, poses, step)
        found += result.ok
        branch = str(arm_angle_of(chain, q[0]).branch_strings())
        psi = float(arm_angle_of(chain, q[0]).psi)
        greedy = greedy_path(chain, poses, step)
        fixed = fixed_psi_path(chain, poses, step, psi, branch)
        clamped = clamped_optimum_path(chain, poses, step, branch)
        greedy_bad += not greedy.ok
        fixed_bad += not fixed.ok
        clamped_bad += not clamped.ok
        if not greedy.ok:
            where.append((greedy.first_failure, float(np.nanmax(greedy.jump))))
    print(f"random paths: {count} lines of {length} waypoints; global path found on {found}; greedy fails on "
          f"{greedy_bad}, fixed psi (the start's) on {fixed_bad}, clamped optimum on {clamped_bad}")
    if where:
        print("greedy's first failure (waypoint, largest step / bound): " +
              ", ".join(f"({k}, {j:.2f})" for k, j in where))


def against_sampled(chain, count=10, spacing_deg=0.1):
    rng = np.random.default_rng(2)
    same = 0
    gaps = []
    for _ in range(count):
        q, _ = line(chain, rng, 5)
        q = q[0] + 0.2 * (q - q[0])
        poses = chain.fk(q)
        step = 1.5 * np.abs(np.diff(q, axis=0)).max()
        ours = resolve_path(chain, poses, step)
        dense = sampled_path(chain, poses, step, np.radians(spacing_deg))
        same += ours.status == dense.status
        if ours.ok and dense.ok:
            gaps.append(ours.clearance - dense.clearance)
    print(f"against the sampled DP ({spacing_deg} deg grid) on {count} short paths: same yes/no on {same}; "
          f"clearance ours - sampled: min {min(gaps):.3g}, max {max(gaps):.3g} rad")


def narrow(chain):
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from tests.test_paths_resolve import _narrow_passage

    limited, q, poses, psi = _narrow_passage()
    step = 2.0 * np.abs(np.diff(q, axis=0)).max(axis=0)
    seconds, result = timed(lambda: resolve_path(limited, poses, step))
    coarse = sampled_path(limited, poses, step, np.radians(0.1))
    print(f"narrow passage (1e-4 rad at waypoint 4): {result.status} in {seconds * 1e3:.1f} ms, psi there "
          f"{result.psi[4] - psi:+.2e} from the passage's middle; sampled DP (0.1 deg): {coarse.status}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--long", type=int, default=0, help="also time a path of this many waypoints")
    args = parser.parse_args()
    chain = get_robot("kuka-iiwa14")
    resolve_path(chain, chain.fk(np.zeros((3, 7)) + 0.3), 0.1)  # load the kernels
    scaling(chain, [(1000, 0.2), (1000, 0.05)] + ([(args.long, 0.2)] if args.long else []))
    random_paths(chain)
    against_sampled(chain)
    narrow(chain)


if __name__ == "__main__":
    main()
