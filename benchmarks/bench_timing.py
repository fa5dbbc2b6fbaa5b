"""Issue 41: timed trajectories (:func:`redkin.paths.time_path`, ``resolve_path(..., timing=HZ)``), in one run.

1. **1000 waypoints on the KUKA iiwa 14**: the poses are the FK of a smooth joint-space curve inside the limits
   (``q(s) = q0 + s dq + 0.1 sin(2 pi s) roll(dq)``, so every pose is reachable), resolved with a step bound of
   0.05 rad, timed and sampled at 1 kHz.  ``resolve_path`` (no timing) and ``time_path`` of its joint values are
   timed separately, each as the best of a few calls after one warm-up call (:func:`timing.best_time`), and their
   sum against the goal of 0.2 s; ``resolve_path(..., timing=1000.0)``, all three in one call, beside them.  The first
   call of each in the process is reported apart: the first ``time_path`` imports toppra (about 0.6-0.8 s here), the
   first ``resolve_path`` loads its compiled kernels from numba's cache.
   **Assumption:** KUKA publishes no joint acceleration limits for the iiwa 14, so this script gives every joint
   10 rad/s^2 (``ASSUMED_IIWA_ACCELERATION``); its velocity limits are KUKA's (``redkin.models.kuka_iiwa14``).
2. **Checks of that trajectory** (the script exits non-zero if one fails): the FK of ``trajectory.at(waypoint_times)``
   within 1e-6 m and 1e-6 rad of each pose; ``|qd| <= velocity`` and ``|qdd| <= acceleration`` at every 1 kHz sample
   (no tolerance: ``time_path`` promises the samples keep the limits); and the same by central differences of the
   sampled ``q`` alone.  The first central difference ``(q[k+1] - q[k-1]) / (t[k+1] - t[k-1])`` is a mean of two
   one-step mean speeds, and a one-step mean of a speed whose ends keep ``v`` and whose slope keeps ``a`` is at most
   ``v + a dt / 4``: allowed ``v (1 + 1e-3) + a dt / 4``.  The second divided difference is a weighted mean of ``qdd``
   over the two steps (no discretisation term): allowed ``a (1 + 1e-3)``, the 1e-3 covering ``qdd`` between samples.
3. **Duration beside TOPP-RA run directly** on the same joint path, in its documented configuration:
   ``toppra.SplineInterpolator(s, q)`` over the cumulative joint-space distance ``s`` of the path's ``q`` (the
   not-a-knot cubic spline, the path ``time_path`` times when it reports ``interpolation == "cubic"``), the joint
   velocity and acceleration constraints at the same limits, ``TOPPRA(..., parametrizer="ParametrizeConstAccel")``
   with its default grid points, ``compute_trajectory(0, 0)``.  Two comparisons, which are not the same thing:

   * *ours / toppra's default run* (goal <= 1.01): toppra constrains its grid points only, so its trajectory may
     exceed the limits between them; the table shows by how much at 1 kHz (the largest ``|qd|/v`` and ``|qdd|/a``).
     Where it does, its shorter duration is that of a trajectory that breaks the limits, not a faster valid one.
   * *ours / toppra on a refined grid* (the fair comparison, goal <= 1.01): every interval of toppra's default grid
     halved, again and again (the grid points doubling), until its 1 kHz samples keep the limits to 1e-9 (relative)
     or ``CAP_DOUBLINGS`` halvings; the last run is the reference.  When the cap is reached first (toppra's excess
     shrinks only as its intervals do), the table says so and gives the excess left: that reference is then still a
     slightly infeasible trajectory, so the ratio against it is, if anything, pessimistic for us.

   ``time_path`` runs toppra itself (limits 0.1 % inside the given ones, a grid of the waypoints and toppra's
   proposed points, refined where a 1 kHz sample exceeds a limit), so its wall time is several toppra runs on a
   finer grid, plus sampling and checking: the table shows toppra's one run (spline, solve, 1 kHz samples) beside it.
   The same comparison is made on the smooth curve that made the poses (not resolved), as a reference.
4. **``objective="time"`` against the default objective** on 20 random smooth joint curves (``q0 + s dq`` between
   random configurations 0.2 rad inside the limits, 0.3 of the way, plus a sine of at most 0.1 rad; 100-200
   waypoints; seed 41) of the Franka Panda at Franka's own velocity and acceleration limits, step bound 0.05 rad,
   1 kHz: the ``time`` objective's duration is never longer (violations counted, a line where it raises or finds no
   path while the default finds one among them; the script exits non-zero if any, or if either call raises), with
   the mean and largest gain in percent over the lines where both are timed.

Timing goals that are missed are reported, not failed (the machine is shared); failed checks exit 1.

    python benchmarks/bench_timing.py            # about a minute on the 2-core machine
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from timing import best_time, machine_lines  # benchmarks/timing.py (the script's folder is on sys.path)

from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.models import franka_panda, kuka_iiwa14
from redkin.paths import PathResult, Trajectory, resolve_path, time_path

#: The iiwa 14's joint acceleration limit assumed here (rad/s^2, every joint): KUKA publishes none.
ASSUMED_IIWA_ACCELERATION = 10.0
#: The control rate of the samples (Hz).
RATE = 1000.0
#: The largest move of a joint between waypoints given to resolve_path (rad).
MAX_STEP = 0.05
#: Goals: the 1000-waypoint path resolved, timed and sampled (s); our duration over toppra's.
GOAL_SECONDS = 0.2
GOAL_RATIO = 1.01
#: The checks' tolerances: FK at the waypoint times (m and rad); the relative slack of the finite differences.
POSE_TOLERANCE = 1e-6
DIFFERENCE_SLACK = 1e-3
#: toppra's refined grids: samples keep the limits to this (relative), or at most this many halvings.
KEEPS = 1e-9
CAP_DOUBLINGS = 9
#: Measurement 4: seed, lines, waypoints per line (inclusive range).
SEED = 41
LINES = 20
LENGTHS = (100, 200)


def iiwa14() -> SerialChain:
    """KUKA's iiwa 14 with the assumed acceleration limit on every joint (:data:`ASSUMED_IIWA_ACCELERATION`)."""
    return kuka_iiwa14().with_motion_limits(acceleration=[ASSUMED_IIWA_ACCELERATION] * 7)


def joint_curve(chain: SerialChain, count: int, start: np.ndarray, move: np.ndarray, bend: np.ndarray,
                waves: float) -> np.ndarray:
    """``count`` joint vectors ``start + s move + bend sin(pi waves s)``, ``s`` from 0 to 1; a ValueError if one
    leaves the limits."""
    s = np.linspace(0.0, 1.0, count)[:, None]
    q = start + s * move + bend * np.sin(np.pi * waves * s)
    if not chain.within_limits(q).all():
        raise ValueError("the joint curve leaves the limits")
    return q


def long_curve(chain: SerialChain, count: int) -> np.ndarray:
    """Measurement 1's curve: from 0.3..1.0 rad off the middle of each range, 0.4-0.9 rad per joint, a 0.1 bend."""
    move = np.array([0.8, -0.4, 0.6, -0.5, 0.7, 0.5, -0.9])
    start = 0.5 * (chain.lower + chain.upper) + np.array([0.3, 0.5, -0.2, 1.0, 0.4, -0.6, 0.2])
    return joint_curve(chain, count, start, move, 0.1 * np.roll(move, 1), 2.0)


def random_curve(chain: SerialChain, rng: np.random.Generator, count: int) -> np.ndarray:
    """Measurement 4's curves: 0.3 of the way between two configurations 0.2 rad inside the limits, plus a sine of
    at most 0.1 rad (so 0.1 rad inside the limits everywhere)."""
    low, high = chain.lower + 0.2, chain.upper - 0.2
    start, end = rng.uniform(low, high), rng.uniform(low, high)
    bend = rng.uniform(-0.1, 0.1, chain.n)
    return joint_curve(chain, count, start, 0.3 * (end - start), bend, float(rng.integers(1, 4)))


# 1. wall time


@dataclass
class LongPath:
    """Measurement 1: the poses, the timed result and the seconds (first calls, then the best of ``repeat``)."""

    q: np.ndarray
    poses: np.ndarray
    result: PathResult
    first_resolve: float
    first_timing: float
    resolve: float
    timing: float
    combined: float


def once(function: Callable[[], object]) -> tuple[float, object]:
    """Seconds of one call, and what it returned."""
    start = time.perf_counter()
    value = function()
    return time.perf_counter() - start, value


def measure_long_path(chain: SerialChain, count: int = 1000, repeat: int = 5, max_step: float = MAX_STEP) -> LongPath:
    """Resolve the FK of :func:`long_curve` (``count`` waypoints, step bound ``max_step``) and time it at
    :data:`RATE`: the first calls of the process and the best of ``repeat`` after a warm-up, for ``resolve_path``,
    ``time_path`` and the two in one call."""
    q = long_curve(chain, count)
    poses = chain.fk(q)
    first_resolve, plain = once(lambda: resolve_path(chain, poses, max_step))
    if not plain.ok:
        raise RuntimeError(f"resolve_path found no path through the curve's poses: {plain.failure}")
    first_timing, _ = once(lambda: time_path(chain, plain.q, rate=RATE))
    resolve = best_time(lambda: resolve_path(chain, poses, max_step), repeat)
    timing = best_time(lambda: time_path(chain, plain.q, rate=RATE), repeat)
    combined = best_time(lambda: resolve_path(chain, poses, max_step, timing=RATE), repeat)
    result = resolve_path(chain, poses, max_step, timing=RATE)
    return LongPath(q, poses, result, first_resolve, first_timing, resolve, timing, combined)


# 2. checks


@dataclass
class Check:
    """One check: its name, the value found, what is allowed (as text) and whether it passed."""

    name: str
    value: float
    allowed: str
    passed: bool


def pose_errors(chain: SerialChain, q: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position (m) and rotation (rad, the angle of ``R^T R_pose``) errors of ``chain.fk(q)`` against ``poses``."""
    reached = chain.fk(q)
    position = np.linalg.norm(reached[..., :3, 3] - poses[..., :3, 3], axis=-1)
    relative = np.swapaxes(reached[..., :3, :3], -1, -2) @ poses[..., :3, :3]
    skew = np.stack([relative[..., 2, 1] - relative[..., 1, 2], relative[..., 0, 2] - relative[..., 2, 0],
                     relative[..., 1, 0] - relative[..., 0, 1]], axis=-1)
    cosine = 0.5 * (np.trace(relative, axis1=-2, axis2=-1) - 1.0)
    return position, np.arctan2(0.5 * np.linalg.norm(skew, axis=-1), cosine)


def finite_differences(t: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Central differences of samples ``q`` at times ``t`` (any spacing) at the inner samples: the velocity
    ``(q[k+1] - q[k-1]) / (t[k+1] - t[k-1])``, the acceleration (the second divided difference) and the longer of
    the two steps around each sample."""
    step = np.diff(t)[:, None]
    mean_speed = np.diff(q, axis=0) / step
    span = step[:-1] + step[1:]
    velocity = (q[2:] - q[:-2]) / span
    acceleration = 2.0 * np.diff(mean_speed, axis=0) / span
    return velocity, acceleration, np.maximum(step[:-1], step[1:])


def check_trajectory(chain: SerialChain, poses: np.ndarray, trajectory: Trajectory) -> list[Check]:
    """Measurement 2's checks (the module's docstring): the poses at the waypoint times, the limits at the samples,
    and the limits by finite differences of the sampled ``q``."""
    v, a = trajectory.velocity, trajectory.acceleration
    at, _, _ = trajectory.at(trajectory.waypoint_times)
    position, angle = pose_errors(chain, at, poses)
    speed, acceleration, step = finite_differences(trajectory.t, trajectory.q)
    speed_allowed = v * (1.0 + DIFFERENCE_SLACK) + a * step / 4.0
    checks = [Check("FK at the waypoint times: position (m)", float(position.max()), f"<= {POSE_TOLERANCE:g}",
                    bool(position.max() <= POSE_TOLERANCE)),
              Check("FK at the waypoint times: rotation (rad)", float(angle.max()), f"<= {POSE_TOLERANCE:g}",
                    bool(angle.max() <= POSE_TOLERANCE)),
              Check("samples: max |qd| / velocity", float((np.abs(trajectory.qd) / v).max()), "<= 1",
                    bool(np.all(np.abs(trajectory.qd) <= v))),
              Check("samples: max |qdd| / acceleration", float((np.abs(trajectory.qdd) / a).max()), "<= 1",
                    bool(np.all(np.abs(trajectory.qdd) <= a))),
              Check("central differences: max |dq/dt| / velocity", float((np.abs(speed) / v).max()),
                    f"<= 1 + {DIFFERENCE_SLACK:g} + a dt / (4 v) = {float((speed_allowed / v).max()):.6f}",
                    bool(np.all(np.abs(speed) <= speed_allowed))),
              Check("central differences: max |d2q/dt2| / acceleration", float((np.abs(acceleration) / a).max()),
                    f"<= 1 + {DIFFERENCE_SLACK:g}", bool(np.all(np.abs(acceleration) <= a * (1.0 + DIFFERENCE_SLACK))))]
    return checks


# 3. beside TOPP-RA


@dataclass
class ToppraRun:
    """One toppra run: its grid points, duration (s), the largest ``|qd|/v`` and ``|qdd|/a`` of its 1 kHz samples,
    and its seconds (spline, solve and samples)."""

    gridpoints: int
    duration: float
    velocity: float
    acceleration: float
    seconds: float

    @property
    def keeps(self) -> bool:
        """Whether its samples keep the limits to :data:`KEEPS` (relative)."""
        return max(self.velocity, self.acceleration) <= 1.0 + KEEPS


@dataclass
class Comparison:
    """Measurement 3 on one joint path: our trajectory, toppra's default run (timed best of ``repeat``) and its runs
    on the refined grids (the last is the fair reference)."""

    label: str
    waypoints: int
    ours: Trajectory
    ours_seconds: float
    default: ToppraRun
    refined: list[ToppraRun] = field(default_factory=list)

    @property
    def reference(self) -> ToppraRun:
        return self.refined[-1] if self.refined else self.default


def samples(duration: float, rate: float) -> np.ndarray:
    """``0, 1/rate, ...`` up to the duration, and the duration itself (as :class:`Trajectory` samples)."""
    t = np.arange(int(np.floor(duration * rate + 1e-9)) + 1) / rate
    return t if np.isclose(t[-1], duration, rtol=0.0, atol=1e-12) else np.r_[t, duration]


def toppra_run(chain: SerialChain, q: np.ndarray, gridpoints: np.ndarray | None = None,
               rate: float = RATE) -> tuple[ToppraRun, np.ndarray]:
    """TOPP-RA on the cubic spline through ``q`` over its cumulative joint-space distance, at the chain's limits,
    ``ParametrizeConstAccel``, rest to rest, sampled at ``rate``; and the grid points it used."""
    import toppra
    import toppra.constraint as constraint

    start = time.perf_counter()
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))]
    path = toppra.SplineInterpolator(s, q)
    v, a = chain.velocity, chain.acceleration
    constraints = [constraint.JointVelocityConstraint(np.c_[-v, v]),
                   constraint.JointAccelerationConstraint(np.c_[-a, a])]
    solver = toppra.algorithm.TOPPRA(constraints, path, gridpoints=gridpoints, parametrizer="ParametrizeConstAccel")
    trajectory = solver.compute_trajectory(0, 0)
    if trajectory is None:
        raise RuntimeError("toppra found no parametrisation")
    t = samples(trajectory.duration, rate)
    speeds, accelerations = trajectory(t, 1), trajectory(t, 2)
    seconds = time.perf_counter() - start
    run = ToppraRun(len(solver.gridpoints), float(trajectory.duration), float((np.abs(speeds) / v).max()),
                    float((np.abs(accelerations) / a).max()), seconds)
    return run, np.asarray(solver.gridpoints)


def compare_with_toppra(chain: SerialChain, q: np.ndarray, label: str, repeat: int = 5,
                        cap: int = CAP_DOUBLINGS) -> Comparison:
    """Measurement 3 on the joint path ``q``: ``time_path`` (best of ``repeat``), toppra's default run (best of
    ``repeat``), then toppra with every grid interval halved until its samples keep the limits or ``cap`` halvings."""
    ours = time_path(chain, q, rate=RATE)
    ours_seconds = best_time(lambda: time_path(chain, q, rate=RATE), repeat)
    runs = [toppra_run(chain, q) for _ in range(repeat)]
    default, grid = runs[0][0], runs[0][1]
    default.seconds = min(run.seconds for run, _ in runs)
    comparison = Comparison(label, len(q), ours, ours_seconds, default)
    run = default
    for _ in range(cap):
        if run.keeps:
            break
        grid = np.union1d(grid, 0.5 * (grid[1:] + grid[:-1]))
        run, grid = toppra_run(chain, q, grid)
        comparison.refined.append(run)
    return comparison


# 4. the time objective


@dataclass
class ObjectiveComparison:
    """Measurement 4: per line, its waypoints and the default and ``time`` objectives' durations (``nan``: no path
    or an error), the seconds of each call, and the errors raised (``"line k, objective: message"``)."""

    waypoints: list[int] = field(default_factory=list)
    default: list[float] = field(default_factory=list)
    fastest: list[float] = field(default_factory=list)
    default_seconds: list[float] = field(default_factory=list)
    fastest_seconds: list[float] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)

    @property
    def found(self) -> np.ndarray:
        return np.isfinite(self.default)

    @property
    def violations(self) -> int:
        """Lines where the default objective found a path and ``time`` found none or a longer one."""
        default, fastest = np.array(self.default), np.array(self.fastest)
        found = self.found
        return int(np.sum(found & ~(fastest <= default)))

    @property
    def gains(self) -> np.ndarray:
        """Percent by which ``time`` is shorter than the default, on the lines where both found a path."""
        default, fastest = np.array(self.default), np.array(self.fastest)
        both = self.found & np.isfinite(fastest)
        return 100.0 * (default[both] - fastest[both]) / default[both]


def duration(result: PathResult | None) -> float:
    """A timed result's duration; ``nan`` for no path (or no result)."""
    ok = result is not None and result.ok and result.trajectory is not None
    return result.trajectory.duration if ok else float("nan")


def compare_objectives(chain: SerialChain, lines: int = LINES, lengths: Sequence[int] = LENGTHS,
                       seed: int = SEED) -> ObjectiveComparison:
    """``resolve_path(..., timing=RATE)`` with the default objective (``"clearance"``) and with ``objective="time"``
    on ``lines`` random curves (:func:`random_curve`) of ``lengths[0]..lengths[1]`` waypoints; an error raised by
    either call is recorded, its duration ``nan``."""
    rng = np.random.default_rng(seed)
    comparison = ObjectiveComparison()
    for _ in range(lines):
        count = int(rng.integers(lengths[0], lengths[1] + 1))
        poses = chain.fk(random_curve(chain, rng, count))
        comparison.waypoints.append(count)
        for objective, durations, seconds in (("clearance", comparison.default, comparison.default_seconds),
                                              ("time", comparison.fastest, comparison.fastest_seconds)):
            start = time.perf_counter()
            try:
                result = resolve_path(chain, poses, MAX_STEP, objective=objective, timing=RATE)
            except RedkinError as error:  # reported and failed, not hidden
                comparison.errors.append(f"line {len(comparison.waypoints) - 1}, objective {objective!r}: {error}")
                result = None
            seconds.append(time.perf_counter() - start)
            durations.append(duration(result))
    return comparison


# the table


def verdict(value: float, goal: float) -> str:
    return "met" if value <= goal else "MISSED"


def long_path_lines(long: LongPath) -> list[str]:
    trajectory = long.result.trajectory
    total = long.resolve + long.timing
    rows = [("first call: resolve_path (kernels from numba's cache)", f"{long.first_resolve:.3f} s", "", ""),
            ("first call: time_path (imports toppra)", f"{long.first_timing:.3f} s", "", ""),
            ("resolve_path, best after a warm-up", f"{long.resolve:.3f} s", "", ""),
            ("time_path at 1 kHz, best after a warm-up", f"{long.timing:.3f} s", "", ""),
            ("  sum", f"{total:.3f} s", f"<= {GOAL_SECONDS:g} s", verdict(total, GOAL_SECONDS)),
            ("resolve_path(..., timing=1000.0), one call", f"{long.combined:.3f} s", f"<= {GOAL_SECONDS:g} s",
             verdict(long.combined, GOAL_SECONDS)),
            ("trajectory: duration, samples, interpolation",
             f"{trajectory.duration:.4f} s, {len(trajectory.t)}, {trajectory.interpolation}", "", "")]
    return [f"{name:<52} {value:>28} {goal:>10} {met:>7}" for name, value, goal, met in rows]


def check_lines(checks: list[Check]) -> list[str]:
    lines = [f"{'check':<52} {'value':>12} {'allowed':<44} {'':>6}"]
    lines += [f"{c.name:<52} {c.value:12.4g} {c.allowed:<44} {'ok' if c.passed else 'FAILED':>6}" for c in checks]
    return lines


def comparison_lines(comparison: Comparison) -> list[str]:
    ours = comparison.ours
    v, a = ours.velocity, ours.acceleration
    lines = [f"{comparison.label}: {comparison.waypoints} waypoints; ours along the {ours.interpolation} path"
             + ("" if ours.interpolation == "cubic" else " (toppra's path is the cubic spline: not the same path)"),
             f"{'run':<36} {'grid pts':>9} {'duration s':>11} {'ours/it':>8} {'max|qd|/v':>10} {'max|qdd|/a':>11} "
             f"{'seconds':>8}",
             f"{'ours: time_path':<36} {'':>9} {ours.duration:11.4f} {1.0:8.4f} "
             f"{float((np.abs(ours.qd) / v).max()):10.6f} {float((np.abs(ours.qdd) / a).max()):11.6f} "
             f"{comparison.ours_seconds:8.3f}"]
    runs = [("toppra, default grid", comparison.default)]
    runs += [(f"toppra, grid halved x{k}", run) for k, run in enumerate(comparison.refined, 1)]
    for name, run in runs:
        lines.append(f"{name:<36} {run.gridpoints:9d} {run.duration:11.4f} {ours.duration / run.duration:8.4f} "
                     f"{run.velocity:10.6f} {run.acceleration:11.6f} {run.seconds:8.3f}")
    default, reference = comparison.default, comparison.reference
    first = ours.duration / default.duration
    fair = ours.duration / reference.duration
    lines.append(f"  ours / toppra's default run: {first:.4f} (goal <= {GOAL_RATIO:g}: {verdict(first, GOAL_RATIO)})"
                 + ("" if default.keeps else
                    f"; toppra's samples exceed the limits by up to "
                    f"{100.0 * (max(default.velocity, default.acceleration) - 1.0):.4g} %"))
    if reference.keeps:
        keeps = f"its samples keep the limits to {KEEPS:g}"
    else:
        keeps = (f"cap of {len(comparison.refined)} halvings reached, its samples still exceed the limits by up to "
                 f"{max(reference.velocity, reference.acceleration) - 1.0:.2e} (relative)")
    lines.append(f"  ours / toppra on {reference.gridpoints} grid points (the fair comparison): {fair:.4f} "
                 f"(goal <= {GOAL_RATIO:g}: {verdict(fair, GOAL_RATIO)}); {keeps}")
    return lines


def objective_lines(objectives: ObjectiveComparison) -> list[str]:
    gains = objectives.gains
    found = int(objectives.found.sum())
    shorter = int(np.sum(gains > 0.0))
    rows = [("lines (waypoints)", f"{len(objectives.waypoints)} ({min(objectives.waypoints)}-"
                                  f"{max(objectives.waypoints)})", ""),
            ("paths found by the default objective", f"{found}", ""),
            ("time objective longer than the default, or none", f"{objectives.violations}", "0"),
            ("errors raised (either objective)", f"{len(objectives.errors)}", "0"),
            ("time objective strictly shorter", f"{shorter} of {len(gains)}", ""),
            ("gain, mean over the lines (%)", f"{gains.mean() if gains.size else float('nan'):.2f}", ""),
            ("gain, largest (%)", f"{gains.max() if gains.size else float('nan'):.2f}", ""),
            ("seconds per line: default objective, timed", f"{np.mean(objectives.default_seconds):.3f}", ""),
            ("seconds per line: objective='time'", f"{np.mean(objectives.fastest_seconds):.3f}", "")]
    lines = [f"{name:<52} {value:>16} {goal:>6}" for name, value, goal in rows]
    return lines + [f"  error: {error}" for error in objectives.errors]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--waypoints", type=int, default=1000, help="waypoints of measurement 1's path")
    parser.add_argument("--lines", type=int, default=LINES, help="random lines of measurement 4")
    parser.add_argument("--repeat", type=int, default=5, help="timed calls after the warm-up")
    arguments = parser.parse_args(argv)

    for line in machine_lines(["numpy", "numba", "scipy", "toppra"]):
        print(line)
    print(f"- ASSUMPTION: the iiwa 14's joint acceleration limit is {ASSUMED_IIWA_ACCELERATION:g} rad/s^2 on every "
          f"joint (KUKA publishes none); its velocity limits are KUKA's.  Panda: Franka's velocity and acceleration "
          f"limits.  Step bound {MAX_STEP:g} rad, {RATE:g} Hz.")
    failures = []

    iiwa = iiwa14()
    long = measure_long_path(iiwa, arguments.waypoints, arguments.repeat)
    print(f"\n1. {arguments.waypoints} waypoints, iiwa 14: resolve, time, sample at 1 kHz")
    print("\n".join(long_path_lines(long)))

    trajectory = long.result.trajectory
    checks = check_trajectory(iiwa, long.poses, trajectory)
    print("\n2. checks of that trajectory (central differences over the samples' own spacing; the first difference "
          "allowed 1e-3 relative plus a dt/4, the second 1e-3 relative)")
    print("\n".join(check_lines(checks)))
    failures += [f"check failed: {c.name}" for c in checks if not c.passed]

    print("\n3. duration beside TOPP-RA run directly on the same joint path (its default configuration, then its grid "
          "refined)")
    resolved = compare_with_toppra(iiwa, long.result.q, "the resolved path", arguments.repeat)
    print("\n".join(comparison_lines(resolved)))
    curve = compare_with_toppra(iiwa, long.q, "reference: the smooth curve that made the poses", arguments.repeat)
    print("\n".join(comparison_lines(curve)))
    bend = [float(np.abs(np.diff(q, 2, axis=0)).max()) for q in (long.result.q, long.q)]
    print(f"  largest second difference of the joint values per waypoint: resolved {bend[0]:.2e} rad, "
          f"the curve {bend[1]:.2e} rad")

    print(f"\n4. objective='time' against the default objective, Franka Panda, {arguments.lines} random lines, "
          f"seed {SEED}")
    objectives = compare_objectives(franka_panda(), arguments.lines)
    print("\n".join(objective_lines(objectives)))
    if objectives.violations:
        failures.append(f"objective='time' longer than the default (or no path where it found one) on "
                        f"{objectives.violations} lines")
    failures += [f"error raised: {error}" for error in objectives.errors]

    for failure in failures:
        print(f"FAILED: {failure}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
