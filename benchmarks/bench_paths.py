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
* the narrow passage (a feasible set 1e-4 rad wide at one waypoint): found, and whether the sampled DP finds it;
* ssik 8.2's ``Manipulator.solve_path`` (its prebuilt iiwa14, ``Manipulator.from_prebuilt("iiwa14")``, native)
  on the same poses, in its documented configuration: ``q0`` the configuration the path starts from (the branch
  through it is continued by label, its swivel angle held fixed), and without ``q0`` (every branch, each from
  the middle of its domain; a path counts as found if any of the eight tracks passes).  ssik's tracks know no
  joint limits and no step bound, so every track is judged as redkin's baselines are
  (:func:`redkin.paths.judge_path`): FK within 1e-9 of each pose, our limits, the same bound.  ssik's iiwa14 is
  our ``kuka-iiwa14`` (same joint values, FK, limits: checked at the start).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from redkin.models import get_robot
from redkin.paths import (
    BaselinePath,
    clamped_optimum_path,
    fixed_psi_path,
    greedy_path,
    judge_path,
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


def ssik_arm(chain):
    """ssik's iiwa14 as a Manipulator (its chart API), checked against ``chain``; None when ssik is missing."""
    try:
        import ssik
    except ImportError:
        return None
    arm = ssik.Manipulator.from_prebuilt("iiwa14")
    q = np.random.default_rng(9).uniform(-2.0, 2.0, (20, 7))
    assert max(float(np.abs(arm.fk(x) - chain.fk(x)).max()) for x in q) < 1e-12, "iiwa14 models differ"
    assert np.allclose(np.array(arm.joint_limits, dtype=float), np.stack([chain.lower, chain.upper], axis=-1),
                       atol=1e-10), "iiwa14 limits differ"
    return arm


def ssik_tracks(chain, arm, poses, step, q0=None):
    """ssik's ``solve_path`` (from ``q0``, or every branch) judged by our FK, limits and bound; a track that
    stopped outside the workspace is padded with NaN rows (no joint values there)."""
    track = arm.solve_path(poses, q0=q0)
    judged = []
    for label in track.tracks:
        q = np.full((len(poses), 7), np.nan)
        rows = track.q(label)
        q[:len(rows)] = rows
        judged.append(judge_path(chain, q, step, poses, f"ssik solve_path {label}"))
    return judged


def _failure(path: BaselinePath) -> str:
    k = path.first_failure
    if k is None:
        return "ok"
    joint = "" if path.joint is None else f" joint {path.joint}"
    excess = "" if path.excess is None else f" by {path.excess:.3g}"
    return f"{path.reason} at {k}{joint}{excess}"


def random_paths(chain, arm, count=20, length=30):
    rng = np.random.default_rng(1)
    found = greedy_bad = fixed_bad = clamped_bad = 0
    where = []
    ssik_start, ssik_any, ssik_time, ours_time = [], 0, 0.0, 0.0
    for _ in range(count):
        q, poses = line(chain, rng, length)
        step = 1.5 * np.abs(np.diff(q, axis=0)).max()
        start = time.perf_counter()
        result = resolve_path(chain, poses, step)
        ours_time += time.perf_counter() - start
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
        if arm is not None:
            start = time.perf_counter()
            (from_start,) = ssik_tracks(chain, arm, poses, step, q[0])
            ssik_time += time.perf_counter() - start
            ssik_start.append(from_start)
            ssik_any += any(t.ok for t in ssik_tracks(chain, arm, poses, step))
    print(f"random paths: {count} lines of {length} waypoints; global path found on {found}; greedy fails on "
          f"{greedy_bad}, fixed psi (the start's) on {fixed_bad}, clamped optimum on {clamped_bad}")
    if where:
        print("greedy's first failure (waypoint, largest step / bound): " +
              ", ".join(f"({k}, {j:.2f})" for k, j in where))
    if arm is None:
        print("ssik: not installed, skipped")
        return
    bad = [t for t in ssik_start if not t.ok]
    print(f"ssik solve_path from the line's start: passes on {count - len(bad)} of {count}, in "
          f"{1e3 * ssik_time / count:.1f} ms per path (resolve_path {1e3 * ours_time / count:.1f} ms); "
          f"the failures: " + ", ".join(_failure(t) for t in bad))
    if bad:
        print("  largest step / bound of the failing tracks: " +
              ", ".join(f"{np.nanmax(t.jump):.2f}" for t in bad) + "; smallest clearance (rad): " +
              ", ".join(f"{np.nanmin(t.clearance):.3g}" for t in bad))
    print(f"ssik solve_path, every branch (no q0): some track passes on {ssik_any} of {count}")


def constructed(chain, arm):
    """docs/paths.md's path: the per-pose baselines fail there."""
    q0 = np.array([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1])
    q1 = np.array([-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9])
    q = q0 + (q1 - q0) * np.linspace(0.0, 1.0, 20)[:, None]
    poses = chain.fk(q)
    result = resolve_path(chain, poses, 0.1)
    print(f"constructed path (docs/paths.md, 20 waypoints, bound 0.1 rad): global {result.status}, clearance "
          f"{result.clearance:.3f} rad; greedy {_failure(greedy_path(chain, poses, 0.1))}")
    if arm is None:
        return
    (from_start,) = ssik_tracks(chain, arm, poses, 0.1, q[0])
    every = ssik_tracks(chain, arm, poses, 0.1)
    print(f"  ssik solve_path from its start: {_failure(from_start)} (largest step / bound "
          f"{np.nanmax(from_start.jump):.2f}); every branch: {sum(t.ok for t in every)} of {len(every)} tracks pass: "
          + ", ".join(_failure(t) for t in every))


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


def narrow(chain, arm):
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from tests.test_paths_resolve import _narrow_passage

    limited, q, poses, psi = _narrow_passage()
    step = 2.0 * np.abs(np.diff(q, axis=0)).max(axis=0)
    seconds, result = timed(lambda: resolve_path(limited, poses, step))
    coarse = sampled_path(limited, poses, step, np.radians(0.1))
    print(f"narrow passage (1e-4 rad at waypoint 4): {result.status} in {seconds * 1e3:.1f} ms, psi there "
          f"{result.psi[4] - psi:+.2e} from the passage's middle; sampled DP (0.1 deg): {coarse.status}")
    if arm is not None:  # ssik's tracks are judged by the narrowed limits
        (from_start,) = ssik_tracks(limited, arm, poses, step, q[0])
        every = ssik_tracks(limited, arm, poses, step)
        print(f"  ssik solve_path from the path's own start: {_failure(from_start)}; every branch: "
              f"{sum(t.ok for t in every)} of {len(every)} tracks pass")


def long_path(chain, arm, count=1000, step=0.2):
    """ssik's solve_path on the 1000-waypoint path of :func:`scaling`, from its start."""
    if arm is None:
        return
    rng = np.random.default_rng(0)
    q, _ = line(chain, rng, 2, 0.3)
    path = q[0] + (q[1] - q[0]) * np.linspace(0.0, 1.0, count)[:, None]
    poses = chain.fk(path)
    seconds, tracks = timed(lambda: ssik_tracks(chain, arm, poses, step, path[0]), 1)
    print(f"ssik solve_path on the {count}-waypoint path from its start: {seconds:.3f} s, {_failure(tracks[0])}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--long", type=int, default=0, help="also time a path of this many waypoints")
    args = parser.parse_args()
    chain = get_robot("kuka-iiwa14")
    resolve_path(chain, chain.fk(np.zeros((3, 7)) + 0.3), 0.1)  # load the kernels
    arm = ssik_arm(chain)
    scaling(chain, [(1000, 0.2), (1000, 0.05)] + ([(args.long, 0.2)] if args.long else []))
    long_path(chain, arm)
    random_paths(chain, arm)
    constructed(chain, arm)
    against_sampled(chain)
    narrow(chain, arm)


if __name__ == "__main__":
    main()
