"""Issue 26's targets for path resolution (redkin.paths), measured in one run.

Run:  python benchmarks/bench_paths.py [--long N ...]

* time of ``resolve_path`` on an iiwa14 path of 1000 waypoints (all 8 branches, the default objective, the
  feasible sets included), warm, at step bounds of 0.2 and 0.05 rad (``--long`` N adds N waypoints at 0.2),
  with the graph's size (nodes over both stages and every refinement), whether the clearance was proved
  optimal, the peak memory allocated (tracemalloc) and the time with ``thorough=True``;
* random paths (straight joint-space lines between random in-limit configurations, 30 waypoints, a step bound
  of 1.5 x the line's largest step): how often the global path is found, and how often greedy seeded tracking,
  the fixed arm angle and the clamped per-pose optimum break a limit or the bound there; and with each joint
  bound by 1.5 x its own largest step (a few milliradians on some joints): the time per path;
* against the sampled DP on a uniform grid (the literature's method) on 100 short random paths and 20 whose
  limits are tightened around them (narrow feasible sets): the same yes/no, and the clearance difference where
  ours is proved optimal and where it is not;
* the narrow passage (a feasible set 1e-4 rad wide at one waypoint): found, and whether the sampled DP finds it;
* ssik 8.2's ``Manipulator.solve_path`` (its prebuilt iiwa14, ``Manipulator.from_prebuilt("iiwa14")``, native)
  on the same poses, in its documented configuration: ``q0`` the configuration the path starts from (the branch
  through it is continued by label, its swivel angle held fixed), and without ``q0`` (every branch, each from
  the middle of its domain; a path counts as found if any of the eight tracks passes).  ssik's tracks know no
  joint limits and no step bound, so every track is judged as redkin's baselines are
  (:func:`redkin.paths.judge_path`): FK within 1e-9 of each pose, our limits, the same bound.  ssik's iiwa14 is
  our ``kuka-iiwa14`` (same joint values, FK, limits: checked at the start);
* the Franka class (q7): random FR3 lines, beside ssik's prebuilt ``fr3`` ``solve_path`` (its FK is our
  ``franka-fr3``'s, checked; its tracks judged by our limits).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
import tracemalloc
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


def peak_memory(function):
    """The peak of memory allocated during ``function()`` (numpy's arrays included; tracemalloc), bytes."""
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def fresh_memory_cost(size=1 << 30):
    """Seconds per 4 KiB page for a new process to map and touch ``size`` bytes (in a process of its own, so that
    this one's memory stays as it was): what a call pays for memory beyond the most its process has held."""
    code = (f"import time, numpy as np; start = time.perf_counter(); np.ones({size // 8}); "
            f"print((time.perf_counter() - start) / {size // 4096})")
    return float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout)


def scaling(chain, cases):
    """The long line at each (waypoints, bound): the first call and the best of the calls after it (3 up to 10^4
    waypoints, 1 beyond), nodes, proof, peak memory (tracemalloc) and ``thorough=True``."""
    rng = np.random.default_rng(0)
    q, _ = line(chain, rng, 2, 0.3)
    print(f"fresh memory on this machine: {1e6 * fresh_memory_cost():.2f} us per 4 KiB page")
    print("| waypoints | step bound (rad) | first call (s) | time (s) | per waypoint (us) | nodes | proved optimal | "
          "peak memory (MB) | thorough (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for count, step in cases:
        path = q[0] + (q[1] - q[0]) * np.linspace(0.0, 1.0, count)[:, None]
        poses = chain.fk(path)
        first, _ = timed(lambda: resolve_path(chain, poses, step), 1)
        seconds, result = timed(lambda: resolve_path(chain, poses, step), 3 if count <= 10_000 else 1)
        memory = peak_memory(lambda: resolve_path(chain, poses, step)) / 1e6
        thorough = ""
        if count <= 10_000:
            thorough = f"{timed(lambda: resolve_path(chain, poses, step, thorough=True), 1)[0]:.2f}"
        print(f"| {count} | {step:.3g} | {first:.3f} | {seconds:.3f} | {1e6 * seconds / count:.1f} | {result.nodes} | "
              f"{result.optimal} | {memory:.0f} | {thorough} |", flush=True)


def ssik_arm(chain, name="iiwa14"):
    """ssik's prebuilt ``name`` as a Manipulator (its chart API), checked against ``chain`` (FK; the limits are ours,
    judged by :func:`redkin.paths.judge_path`); None when ssik is missing."""
    try:
        import ssik
    except ImportError:
        return None
    arm = ssik.Manipulator.from_prebuilt(name)
    q = np.random.default_rng(9).uniform(-2.0, 2.0, (20, 7))
    assert max(float(np.abs(arm.fk(x) - chain.fk(x)).max()) for x in q) < 1e-12, f"{name} models differ"
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


def random_line_path(chain, rng, length):
    """A random joint-space line of ``length`` waypoints, its poses, a bound of 1.5 x its largest step, and
    ``resolve_path``'s answer with its time (seconds)."""
    q, poses = line(chain, rng, length)
    step = 1.5 * np.abs(np.diff(q, axis=0)).max()
    start = time.perf_counter()
    result = resolve_path(chain, poses, step)
    return q, poses, step, result, time.perf_counter() - start


def per_joint_bounds(chain, count=40, length=30):
    """Lines of ``length`` waypoints over 0.3 of the way between two random configurations, each joint bound by
    1.5 x its own largest step (+ 1e-3 rad): bounds of a few milliradians on some joints, as speed limits times a
    short time step give; the time of ``resolve_path`` per path and how often its clearance is proved."""
    rng = np.random.default_rng(1)
    seconds, tightest, found, proved = [], [], 0, 0
    for _ in range(count):
        q, poses = line(chain, rng, length, 0.3)
        step = 1.5 * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3
        tightest.append(step.min())
        start = time.perf_counter()
        result = resolve_path(chain, poses, step)
        seconds.append(time.perf_counter() - start)
        found += result.ok
        proved += result.optimal
    print(f"per-joint bounds: {count} lines of {length} waypoints, each line's tightest bound {np.min(tightest):.4f}"
          f"-{np.max(tightest):.4f} rad (median {np.median(tightest):.4f}); found {found}, proved {proved}; time per "
          f"path mean {np.mean(seconds):.2f} s, median {np.median(seconds):.2f} s, max {np.max(seconds):.2f} s",
          flush=True)


def random_paths(chain, arm, count=20, length=30):
    rng = np.random.default_rng(1)
    found = proved = greedy_bad = fixed_bad = clamped_bad = 0
    where = []
    ssik_start, ssik_any, ssik_time, ours_time = [], 0, 0.0, 0.0
    for _ in range(count):
        q, poses, step, result, seconds = random_line_path(chain, rng, length)
        ours_time += seconds
        found += result.ok
        proved += result.optimal
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
    print(f"random paths: {count} lines of {length} waypoints; global path found on {found} ({proved} with the "
          f"clearance proved optimal), {1e3 * ours_time / count:.1f} ms per path; greedy fails on "
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


def tightened(chain, q, rng):
    """``chain`` with three joints' limits moved to within 1e-4 .. 1e-2 rad of the range joint-space path ``q``
    sweeps: the path stays feasible, and the feasible sets along it become narrow."""
    lower, upper = chain.lower.copy(), chain.upper.copy()
    for joint in rng.choice(7, 3, replace=False):
        margin = 10.0 ** rng.uniform(-4.0, -2.0)
        lower[joint] = max(lower[joint], q[:, joint].min() - margin)
        upper[joint] = min(upper[joint], q[:, joint].max() + margin)
    return chain.with_limits(lower, upper)


def against_sampled(chain, count=100, constructed_count=20, spacing_deg=0.01):
    """The issue's comparison with the literature's dynamic programming on a uniform grid: ``count`` short random
    lines, and ``constructed_count`` lines whose chain has three joints' limits tightened around them (narrow
    feasible sets; the line itself stays a path)."""
    rng = np.random.default_rng(2)
    rows = []
    for k in range(count + constructed_count):
        q, _ = line(chain, rng, 5)
        q = q[0] + 0.2 * (q - q[0])
        arm = chain if k < count else tightened(chain, q, rng)
        poses = arm.fk(q)
        step = 1.5 * np.abs(np.diff(q, axis=0)).max()
        ours = resolve_path(arm, poses, step)
        dense = sampled_path(arm, poses, step, np.radians(spacing_deg))
        rows.append((k < count, ours, dense))
    for name, which in (("random", True), ("constructed (tightened limits)", False)):
        group = [(ours, dense) for random, ours, dense in rows if random == which]
        same = sum(ours.status == dense.status for ours, dense in group)
        only = sum(ours.ok and not dense.ok for ours, dense in group)
        proved = [ours.clearance - dense.clearance for ours, dense in group if ours.ok and dense.ok and ours.optimal]
        other = [ours.clearance - dense.clearance for ours, dense in group if ours.ok and dense.ok and not ours.optimal]
        print(f"against the sampled DP ({spacing_deg} deg grid), {len(group)} {name} short paths: same yes/no on "
              f"{same} (a path only we found: {only}); clearance ours - sampled where ours is proved optimal "
              f"({len(proved)}): min {min(proved, default=np.nan):.3g}; where not proved ({len(other)}): min "
              f"{min(other, default=np.nan):.3g}, max {max(other, default=np.nan):.3g} rad")


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


def into_range(chain, q):
    """``q`` with each joint moved by whole turns into its range where one fits (a peer that returns joint values
    modulo 2 pi, judged charitably)."""
    turns = np.ceil((chain.lower - q) / (2.0 * np.pi))
    moved = q + 2.0 * np.pi * turns
    return np.where(np.isfinite(moved) & (moved <= chain.upper), moved, q)


def franka(count=20, length=30):
    """The Franka class (q7 the parameter) on random FR3 lines, beside ssik's prebuilt ``fr3`` solve_path from the
    line's start (its tracks judged by our limits, FK and bound, as returned and with every joint moved by whole
    turns into its range: ssik returns some FR3 joint 4 values 2 pi above the range)."""
    chain = get_robot("franka-fr3")
    resolve_path(chain, chain.fk(np.zeros((3, 7)) + 0.3), 0.1)  # load (or compile) the q7 kernels first
    arm = ssik_arm(chain, "fr3")
    rng = np.random.default_rng(3)
    found = proved = ssik_pass = ssik_turned = 0
    ours_time = ssik_time = 0.0
    failures, turned_failures = [], []
    for _ in range(count):
        q, poses, step, result, seconds = random_line_path(chain, rng, length)
        ours_time += seconds
        found += result.ok
        proved += result.optimal
        if arm is not None:
            start = time.perf_counter()
            track = arm.solve_path(poses, q0=q[0])
            ssik_time += time.perf_counter() - start
            rows = np.full((length, 7), np.nan)
            values = np.asarray(track.q(next(iter(track.tracks))))
            rows[: len(values)] = values
            judged = judge_path(chain, rows, step, poses, "ssik solve_path")
            turned = judge_path(chain, into_range(chain, rows), step, poses, "ssik solve_path, into range")
            ssik_pass += judged.ok
            ssik_turned += turned.ok
            if not judged.ok:
                failures.append(_failure(judged))
            if not turned.ok:
                turned_failures.append(_failure(turned))
    print(f"FR3 (q7): {count} random lines of {length} waypoints; path found on {found} ({proved} proved optimal), "
          f"{1e3 * ours_time / count:.1f} ms per path")
    if arm is not None:
        print(f"  ssik solve_path (prebuilt fr3) from the line's start, {1e3 * ssik_time / count:.1f} ms per path: "
              f"passes on {ssik_pass} of {count} as returned (" + ", ".join(failures[:5]) + ", ...); on "
              f"{ssik_turned} of {count} with its joints turned into their ranges (" + ", ".join(turned_failures)
              + ")")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--long", type=int, nargs="*", default=[], help="also time paths of these many waypoints")
    args = parser.parse_args()
    chain = get_robot("kuka-iiwa14")
    resolve_path(chain, chain.fk(np.zeros((3, 7)) + 0.3), 0.1)  # load the kernels
    arm = ssik_arm(chain)
    scaling(chain, [(1000, 0.2), (1000, 0.05)] + [(n, 0.2) for n in args.long])
    long_path(chain, arm)
    random_paths(chain, arm)
    per_joint_bounds(chain)
    constructed(chain, arm)
    against_sampled(chain)
    narrow(chain, arm)
    franka()


if __name__ == "__main__":
    main()
