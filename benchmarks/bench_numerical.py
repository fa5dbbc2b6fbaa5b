"""Numerical pose IK (issue 25): redkin.numerical.ik beside TRAC-IK, roboticstoolbox's ik_LM and mink, per arm.

Run: ``python benchmarks/bench_numerical.py`` (10^4 targets per arm, about ten minutes with every peer);
``--targets N``, ``--arms iiwa14 gen3 ...`` (a subset of iiwa14, fr3, gen3, xarm7, sawyer), ``--quick`` (200
targets), ``--mink-targets M`` (mink is timed on the first M targets only, 1000 by default: it iterates a QP
built in Python, about 0.1 ms a step).  Prints the machine, one table per arm and the issue's targets.

The arms are the makers' descriptions written out in ``examples/`` (iiwa14 to ``lbr_iiwa_flange``, FR3 to its
flange ``fr3_link8``, Gen3 to ``tool_frame``, xArm7 to ``link_eef``, Sawyer to ``right_hand``); every peer reads
the same file, and the script checks at start-up that each peer's FK of the file equals ours (the residual is
printed).  Per arm, one ``numpy.random.default_rng(1)`` draws the targets' joint vectors, then the seeds, both
uniform within the limits (an unlimited joint in [-pi, pi]); every solver gets the same targets and seeds.

Success is judged here, by our FK (``chain.fk``), never by a solver's own flag: a returned joint vector counts
when its tool is within 1e-9 m and 1e-9 rad (the angle of R_target^T R) of the target AND it is within the
chain's limits as returned (not modulo 2 pi).  The "claims" column is the solver's own success flag.  Times are
per call (``time.perf_counter`` around each call, failures included; a pose's quaternion or SE3 is formed before
the clock starts): median and 99th percentile.  The machine may be shared: the load average is printed.

Configurations (each peer's best documented one, named again in its row):

* redkin: ``redkin.numerical.ik(chain, pose, q0=seed)``, one call per target, its defaults (tolerance 1e-9,
  restarts 200, rng seed 0); a batch row (all targets in one call; throughput with
  ``redkin._compiled.set_threads(1)`` and with the default threads, best of 3 calls each); a seeded row (seed =
  the joint vector that made the target plus uniform noise of +-1e-3 rad, clipped to the limits).
* TRAC-IK, ``pytracik`` 0.0.3 (TRAC-IK's C++ through pybind11), built from the same URDF: solve type Speed,
  timeout 5 ms (its defaults), at eps 1e-5 (its default), at eps 1e-9 (our tolerance) and at eps 1e-13, the
  tightest at which it still returns a solution for most targets within the 5 ms (it accepts any eps, 0
  included, but from 1e-14 on most calls time out).  ``pytracik.ik`` is called directly with the quaternion
  formed beforehand (its wrapper ``trac_ik.TracIK.ik`` forms it with an eigen-decomposition per call).  Two
  limits of the peer show in the rows: its joint limits are held in single precision (a returned joint can lie
  1e-7 rad outside the URDF's limit), and its error is KDL's twist, whose rotation part is zero below about
  1e-6 rad (``KDL::Rotation::GetRot`` rounds smaller angles to 0), so whatever eps, a returned rotation is
  exact to about 1e-7 rad only.
* roboticstoolbox 1.5 ``ETS.ik_LM`` (C++): the ETS from the same URDF (``URDF_file`` then
  ``Robot(...).ets(start=base, end=tip)``: ``Robot.URDF`` is deprecated in 1.5), its defaults (ilimit 30,
  slimit 100, joint_limits True, k 1, Chan's damping) with ``tol=1e-13``, the issue's measurement, and with
  ``tol=1e-20``: its tol bounds E = e^T e / 2, so 1e-13 leaves |e| up to 4.5e-7 and 1e-20 up to 1.4e-10, the
  loosest that meets 1e-9.
* mink 1.3 (differential IK: one QP per step on MuJoCo's model of the same URDF, compiled with
  ``fusestatic="false"`` so that the tip link stays a body): a ``FrameTask`` on the tip body (position and
  orientation cost 1, ``lm_damping`` 1, as its examples), ``ConfigurationLimit``, the ``daqp`` solver and
  ``solve_ik``'s default damping 1e-12, iterated from the seed with ``integrate_inplace`` until its own error is
  within 1e-9 m and 1e-9 rad or 100 steps, the loop of mink's examples (arm_iiwa.py) with our tolerance.  mink
  has no restarts: from a random seed it is a local method, not a pose solver in the sense of the others, and its
  row says how often a single descent lands.
"""

from __future__ import annotations

import argparse
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numba
import numpy as np
from timing import load_average, machine_lines  # benchmarks/timing.py (the script's folder is on sys.path)

from redkin import set_threads, thread_count
from redkin.chain import SerialChain
from redkin.numerical import ik
from redkin.urdf import load_urdf

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: Position [m] and rotation [rad] tolerance of the certificate.
TOLERANCE = 1e-9
#: The seeded row: seeds this far (uniform, per joint, radians) from the joint vector that made the target.
NEAR_SEED = 1e-3
#: The seeded row counts "the same solution" when the returned joints are this close (max-abs, radians) to the
#: joint vector that made the target: the nearest point of its self-motion to a seed 1e-3 away is at most
#: 2 x sqrt(7) x 1e-3 from it.
SAME_SOLUTION = 1e-2
TRACIK_TIMEOUT = 0.005
TRACIK_EPS = (1e-5, 1e-9, 1e-13)
RTB_TOL = (1e-13, 1e-20)
MINK_STEPS = 100
MINK_DT = 0.01  # mink's step length; the frame task asks for the whole error each step whatever dt is


class Arm(NamedTuple):
    file: str
    base: str
    tip: str


ARMS = {
    "iiwa14": Arm("iiwa14.urdf", "lbr_iiwa_link_0", "lbr_iiwa_flange"),
    "fr3": Arm("fr3.urdf", "base", "fr3_link8"),
    "gen3": Arm("gen3.urdf", "base_link", "tool_frame"),
    "xarm7": Arm("xarm7.urdf", "link_base", "link_eef"),
    "sawyer": Arm("sawyer.urdf", "right_arm_base_link", "right_hand"),
}


class Problem(NamedTuple):
    """The targets of one arm: the joint vectors that made them, their poses and the seeds."""

    q: np.ndarray
    poses: np.ndarray
    seeds: np.ndarray


class Run(NamedTuple):
    """What one solver returned on a problem: joints (NaN where it returned none), its own flag, seconds per call."""

    name: str
    q: np.ndarray
    claimed: np.ndarray
    seconds: np.ndarray


def load(arm: str) -> SerialChain:
    spec = ARMS[arm]
    return load_urdf(EXAMPLES / spec.file, base=spec.base, tip=spec.tip)


def in_limits(chain: SerialChain, rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` joint vectors uniform within the limits (an unlimited joint in [-pi, pi])."""
    lower = np.where(np.isfinite(chain.lower), chain.lower, -np.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper, np.pi)
    return rng.uniform(lower, upper, (count, chain.n))


def problem(chain: SerialChain, count: int) -> Problem:
    """Targets from FK of random in-limit q and random in-limit seeds, from one Generator of seed 1."""
    rng = np.random.default_rng(1)
    q = in_limits(chain, rng, count)
    return Problem(q, chain.fk(q), in_limits(chain, rng, count))


def pose_errors(chain: SerialChain, q: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error [m] and rotation angle [rad] of our FK of ``q`` against ``poses`` (inf where q is not finite).

    The angle of E = R_target^T R is atan2(|vee(E - E^T)| / 2, (trace E - 1) / 2), accurate for small angles.
    """
    finite = np.all(np.isfinite(q), axis=-1)
    reached = chain.fk(np.where(finite[..., None], q, 0.0))
    position = np.linalg.norm(reached[..., :3, 3] - poses[..., :3, 3], axis=-1)
    error = np.swapaxes(poses[..., :3, :3], -1, -2) @ reached[..., :3, :3]
    skew = np.stack([error[..., 2, 1] - error[..., 1, 2], error[..., 0, 2] - error[..., 2, 0],
                     error[..., 1, 0] - error[..., 0, 1]], axis=-1)
    angle = np.arctan2(np.linalg.norm(skew, axis=-1) / 2.0, (np.trace(error, axis1=-2, axis2=-1) - 1.0) / 2.0)
    return np.where(finite, position, np.inf), np.where(finite, angle, np.inf)


def certified(chain: SerialChain, q: np.ndarray, poses: np.ndarray, tolerance: float = TOLERANCE) -> np.ndarray:
    """Whether each returned ``q`` is a solution: our FK within ``tolerance`` m and rad, and within the limits."""
    position, angle = pose_errors(chain, q, poses)
    finite = np.all(np.isfinite(q), axis=-1)
    inside = np.all((q >= chain.lower) & (q <= chain.upper), axis=-1) & finite
    return (position <= tolerance) & (angle <= tolerance) & inside


def _timed_loop(name: str, count: int, n: int, solve: Callable[[int], tuple[np.ndarray | None, bool]]) -> Run:
    """Calls ``solve(k)`` for every target, each timed; ``solve`` returns (joints or None, the solver's flag)."""
    q = np.full((count, n), np.nan)
    claimed = np.zeros(count, dtype=bool)
    seconds = np.empty(count)
    for k in range(count):
        start = time.perf_counter()
        joints, flag = solve(k)
        seconds[k] = time.perf_counter() - start
        if joints is not None:
            q[k] = joints
        claimed[k] = flag
    return Run(name, q, claimed, seconds)


# ----------------------------------------------------------------------------- redkin
def redkin_run(chain: SerialChain, targets: Problem, seeds: np.ndarray | None = None,
               name: str = "redkin numerical.ik, one call per target") -> Run:
    """``redkin.numerical.ik`` one target per call, from ``seeds`` (the problem's random seeds by default)."""
    seeds = targets.seeds if seeds is None else seeds
    ik(chain, targets.poses[0], q0=seeds[0])  # compiled (or loaded from the cache) before the clock

    def solve(k):
        result = ik(chain, targets.poses[k], q0=seeds[k])
        found = bool(result.found[0])
        return (result.q[0] if found else None), found

    return _timed_loop(name, len(targets.poses), chain.n, solve)


def near_seeds(chain: SerialChain, targets: Problem) -> np.ndarray:
    """Seeds within :data:`NEAR_SEED` rad of the joint vectors that made the targets, clipped to the limits."""
    noise = np.random.default_rng(2).uniform(-NEAR_SEED, NEAR_SEED, targets.q.shape)
    return np.clip(targets.q + noise, chain.lower, chain.upper)


class BatchRow(NamedTuple):
    one_thread: float  # targets per second
    default_threads: float
    threads: int
    success: float
    machine: float  # what the machine gave a trivial compiled loop on as many threads at the same time (x one)


@numba.njit(nogil=True)
def _spin(count: int) -> float:  # pragma: no cover - compiled
    """A compiled loop that touches no memory: the parallel speedup the cores can give at this moment."""
    total = 0.0
    for i in range(count):
        total += np.sin(i * 1e-6)
    return total


def _spin_seconds(threads: int, count: int = 2_000_000) -> float:
    """Seconds for ``threads`` threads to share ``threads x count`` steps of :func:`_spin`, each ``count``."""
    workers = [threading.Thread(target=_spin, args=(count,)) for _ in range(threads)]
    start = time.perf_counter()
    if threads == 1:
        _spin(count)
        _spin(count)
        return time.perf_counter() - start
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join()
    return (time.perf_counter() - start) * 2 / threads


def redkin_batch(chain: SerialChain, targets: Problem, repeat: int = 7) -> BatchRow:
    """All targets in one ``ik`` call: throughput on one thread and on the default threads, each the best of
    ``repeat`` calls, interleaved so that both meet the same load of the machine; beside them the speedup a
    trivial compiled loop got from the same threads in the same rounds (other jobs on a shared machine take
    cores: where that loop gets no speedup, neither can the batch)."""

    def solve():
        return ik(chain, targets.poses, q0=targets.seeds)

    def seconds(threads: int | None) -> float:
        set_threads(threads)
        start = time.perf_counter()
        solve()
        return time.perf_counter() - start

    threads = thread_count()
    single = several = spin_single = spin_several = np.inf
    solve()
    _spin(1)
    try:
        for _ in range(repeat):
            single = min(single, seconds(1))
            several = min(several, seconds(None))
            spin_single = min(spin_single, _spin_seconds(1))
            spin_several = min(spin_several, _spin_seconds(threads))
    finally:
        set_threads(None)
    result = solve()
    q = np.where(result.found[:, :1], result.q[:, 0], np.nan)
    success = float(np.mean(certified(chain, q, targets.poses)))
    count = len(targets.poses)
    return BatchRow(count / single, count / several, threads, success, spin_single / spin_several)


# ----------------------------------------------------------------------------- peers
def tracik_runs(chain: SerialChain, arm: str, targets: Problem) -> list[Run] | str:
    """TRAC-IK (``pytracik``) at each eps of :data:`TRACIK_EPS`, Speed, 5 ms; a string says why it was skipped."""
    try:
        import pytracik
        from scipy.spatial.transform import Rotation
    except ImportError as exc:
        return f"skipped: {exc.name} is not installed (pip install pytracik==0.0.3)"
    spec = ARMS[arm]
    text = (EXAMPLES / spec.file).read_text()
    quaternions = Rotation.from_matrix(targets.poses[:, :3, :3]).as_quat()  # x, y, z, w
    positions = targets.poses[:, :3, 3]
    runs = []
    for eps in TRACIK_EPS:
        solver = pytracik.TRAC_IK(spec.base, spec.tip, text, TRACIK_TIMEOUT, eps, pytracik.SolveType.Speed)

        def solve(k, solver=solver):
            result = pytracik.ik(solver, targets.seeds[k], *positions[k], *quaternions[k])
            return (result[1:] if result[0] >= 0 else None), bool(result[0] >= 0)

        runs.append(_timed_loop(f"TRAC-IK Speed, 5 ms, eps {eps:g}", len(targets.poses), chain.n, solve))
    return runs


def tracik_fk_residual(chain: SerialChain, arm: str, q: np.ndarray) -> float:
    import pytracik

    spec = ARMS[arm]
    solver = pytracik.TRAC_IK(spec.base, spec.tip, (EXAMPLES / spec.file).read_text(), TRACIK_TIMEOUT, 1e-5,
                              pytracik.SolveType.Speed)
    return float(max(np.abs(pytracik.fk(solver, row) - chain.fk(row)).max() for row in q))


def rtb_ets(arm: str) -> Any:
    """roboticstoolbox's ETS from the base to the tip link of the arm's URDF."""
    import roboticstoolbox as rtb
    from roboticstoolbox.models.URDF.URDFRobot import URDF_file

    spec = ARMS[arm]
    links, name, _ = URDF_file(str(EXAMPLES / spec.file))  # an absolute path: a relative one is read in rtbdata
    return rtb.Robot(links, name=name).ets(start=spec.base, end=spec.tip)


def rtb_runs(chain: SerialChain, arm: str, targets: Problem) -> list[Run] | str:
    """roboticstoolbox's C++ ``ETS.ik_LM`` at each tol of :data:`RTB_TOL`, its other defaults."""
    try:
        import roboticstoolbox as rtb
    except ImportError as exc:
        return f"skipped: {exc.name} is not installed (pip install roboticstoolbox-python)"
    ets = rtb_ets(arm)
    runs = []
    for tol in RTB_TOL:
        def solve(k, tol=tol):
            solution = ets.ik_LM(targets.poses[k], q0=targets.seeds[k], tol=tol)
            return np.asarray(solution.q), bool(solution.success)

        runs.append(_timed_loop(f"roboticstoolbox {rtb.__version__} ETS.ik_LM, tol {tol:g}", len(targets.poses),
                                chain.n, solve))
    return runs


def mink_model(arm: str) -> Any:
    """MuJoCo's model of the arm's URDF, fixed links kept as bodies and the meshless links given a tiny mass."""
    import mujoco

    compiler = ('<mujoco><compiler fusestatic="false" discardvisual="true" boundmass="0.001" boundinertia="1e-6"/>'
                "</mujoco></robot>")
    text = (EXAMPLES / ARMS[arm].file).read_text().replace("</robot>", compiler)
    return mujoco.MjModel.from_xml_string(text)


def mink_fk_residual(chain: SerialChain, arm: str, q: np.ndarray) -> float:
    import mujoco

    model = mink_model(arm)
    data = mujoco.MjData(model)
    body = model.body(ARMS[arm].tip).id
    worst = 0.0
    for row in q:
        data.qpos[:] = row
        mujoco.mj_kinematics(model, data)
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = data.xmat[body].reshape(3, 3), data.xpos[body]
        worst = max(worst, float(np.abs(pose - chain.fk(row)).max()))
    return worst


def mink_run(chain: SerialChain, arm: str, targets: Problem) -> Run | str:
    """mink's ``solve_ik`` iterated from the seed until its error is within :data:`TOLERANCE` (or 100 steps)."""
    try:
        import mink
    except ImportError as exc:
        return f"skipped: {exc.name} is not installed (pip install mink==1.3.0)"
    model = mink_model(arm)
    configuration = mink.Configuration(model)
    task = mink.FrameTask(frame_name=ARMS[arm].tip, frame_type="body", position_cost=1.0, orientation_cost=1.0,
                          lm_damping=1.0)
    limits = [mink.ConfigurationLimit(model=model)]
    goals = [mink.SE3.from_matrix(pose) for pose in targets.poses]

    def solve(k):
        configuration.update(targets.seeds[k])
        task.set_target(goals[k])
        converged = False
        for _ in range(MINK_STEPS):
            velocity = mink.solve_ik(configuration, [task], MINK_DT, "daqp", limits=limits)
            configuration.integrate_inplace(velocity, MINK_DT)
            error = task.compute_error(configuration)
            if np.linalg.norm(error[:3]) <= TOLERANCE and np.linalg.norm(error[3:]) <= TOLERANCE:
                converged = True
                break
        return configuration.q.copy(), converged

    return _timed_loop("mink 1.3 solve_ik loop (one descent, no restarts)", len(targets.poses), chain.n, solve)


# ----------------------------------------------------------------------------- the table
class Row(NamedTuple):
    name: str
    targets: int
    success: float  # certified fraction
    claimed: float
    median: float  # seconds
    p99: float
    ratio: float  # redkin's median on the same targets / this row's median


def table_row(chain: SerialChain, run: Run, targets: Problem, redkin: Run) -> Row:
    count = len(run.q)
    ok = certified(chain, run.q, targets.poses[:count])
    median = float(np.median(run.seconds))
    return Row(run.name, count, float(ok.mean()), float(run.claimed.mean()), median,
               float(np.percentile(run.seconds, 99)), float(np.median(redkin.seconds[:count])) / median)


def frame_checks(chain: SerialChain, arm: str) -> list[str]:
    """Each installed peer's FK of the arm's URDF against ours, at 20 random in-limit q (max abs entry)."""
    q = in_limits(chain, np.random.default_rng(3), 20)
    lines = []
    for peer, residual in (("TRAC-IK", tracik_fk_residual), ("roboticstoolbox", _rtb_fk_residual),
                           ("mink/MuJoCo", mink_fk_residual)):
        try:
            lines.append(f"{peer} FK - ours: {residual(chain, arm, q):.1e}")
        except ImportError:
            continue
    return lines


def _rtb_fk_residual(chain: SerialChain, arm: str, q: np.ndarray) -> float:
    ets = rtb_ets(arm)
    return float(max(np.abs(ets.eval(row) - chain.fk(row)).max() for row in q))


class ArmResult(NamedTuple):
    arm: str
    rows: list[Row]
    skipped: list[str]
    batch: BatchRow
    seeded: Row
    same_solution: float
    frames: list[str]


def measure(arm: str, count: int, mink_count: int) -> ArmResult:
    """Every solver on ``count`` targets of ``arm`` (mink on the first ``mink_count``)."""
    chain = load(arm)
    targets = problem(chain, count)
    redkin = redkin_run(chain, targets)
    runs: list[Run] = [redkin]
    skipped = []
    for peer in (tracik_runs(chain, arm, targets), rtb_runs(chain, arm, targets)):
        if isinstance(peer, str):
            skipped.append(peer)
        else:
            runs.extend(peer)
    first = Problem(*(part[:mink_count] for part in targets))
    mink = mink_run(chain, arm, first)
    if isinstance(mink, str):
        skipped.append(mink)
    else:
        runs.append(mink)
    rows = [table_row(chain, run, targets, redkin) for run in runs]
    seeds = near_seeds(chain, targets)
    near = redkin_run(chain, targets, seeds, f"redkin, seed {NEAR_SEED:g} rad from a solution")
    same = np.all(np.abs(near.q - targets.q) <= SAME_SOLUTION, axis=-1)
    seeded = table_row(chain, near, targets, redkin)
    return ArmResult(arm, rows, skipped, redkin_batch(chain, targets), seeded, float(same.mean()),
                     frame_checks(chain, arm))


def _percent(fraction: float) -> str:
    return f"{100 * fraction:.2f} %"


def _us(seconds: float) -> str:
    return f"{seconds * 1e6:.1f}"


def arm_table(result: ArmResult) -> list[str]:
    lines = [f"### {result.arm} ({ARMS[result.arm].file} to {ARMS[result.arm].tip})", ""]
    lines += [f"- {line}" for line in result.frames + result.skipped]
    lines += ["", "| solver | targets | certified at 1e-9, in limits | claims | median us | p99 us | "
              "redkin / peer (median) |", "|---|---|---|---|---|---|---|"]
    for item in result.rows + [result.seeded]:
        lines.append(f"| {item.name} | {item.targets} | {_percent(item.success)} | {_percent(item.claimed)} | "
                     f"{_us(item.median)} | {_us(item.p99)} | {item.ratio:.3f} |")
    batch = result.batch
    speedup = batch.default_threads / batch.one_thread
    lines += ["", f"- batch, all targets in one call: {batch.one_thread:,.0f} targets/s on one thread, "
              f"{batch.default_threads:,.0f} on {batch.threads} threads ({speedup:.2f} x; a trivial compiled loop got "
              f"{batch.machine:.2f} x from the same threads meanwhile), certified {_percent(batch.success)}",
              f"- seeded {NEAR_SEED:g} rad from the solution: the same solution (within {SAME_SOLUTION:g} rad) "
              f"{_percent(result.same_solution)}", ""]
    return lines


def _find(rows: list[Row], prefix: str) -> Row | None:
    return next((item for item in rows if item.name.startswith(prefix)), None)


def targets_table(results: list[ArmResult]) -> list[str]:
    """The issue's targets, one line per arm; a target whose peer was skipped says so."""
    lines = ["## The issue's targets", "", "| arm | success at 1e-9 (>= 99.9 %) | median vs rtb tol 1e-13 (<= 0.5) | "
             "median vs TRAC-IK eps 1e-5 (<= 0.2) | batch vs one thread (>= 1.8) | seeded median (<= 20 us) |",
             "|---|---|---|---|---|---|"]

    def verdict(value: float, goal: float, at_most: bool, text: str) -> str:
        met = value <= goal if at_most else value >= goal
        return f"{text} {'met' if met else '**not met**'}"

    for result in results:
        redkin = result.rows[0]
        rtb = _find(result.rows, "roboticstoolbox")
        tracik = _find(result.rows, "TRAC-IK")
        cells = [verdict(redkin.success, 0.999, False, _percent(redkin.success)),
                 verdict(rtb.ratio, 0.5, True, f"{rtb.ratio:.3f}") if rtb else "rtb skipped",
                 verdict(tracik.ratio, 0.2, True, f"{tracik.ratio:.3f}") if tracik else "TRAC-IK skipped",
                 verdict(result.batch.default_threads / result.batch.one_thread, 1.8, False,
                         f"{result.batch.default_threads / result.batch.one_thread:.2f} x (a trivial loop "
                         f"{result.batch.machine:.2f} x)"),
                 verdict(result.seeded.median, 20e-6, True, f"{_us(result.seeded.median)} us")]
        lines.append(f"| {result.arm} | " + " | ".join(cells) + " |")
    return lines


def main(argv: Sequence[str] | None = None) -> list[ArmResult]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--targets", type=int, default=10_000, help="targets per arm (default 10000)")
    parser.add_argument("--arms", nargs="+", choices=sorted(ARMS), default=list(ARMS), help="a subset of the arms")
    parser.add_argument("--quick", action="store_true", help="200 targets per arm (for the test suite)")
    parser.add_argument("--mink-targets", type=int, default=1000, help="mink on the first M targets (default 1000)")
    args = parser.parse_args(argv)
    count = 200 if args.quick else args.targets
    if count < 1 or args.mink_targets < 1:
        parser.error("--targets and --mink-targets must be positive")
    print("# Numerical pose IK, issue 25 (benchmarks/bench_numerical.py)\n")
    peers = ("numpy", "numba", "pytracik", "roboticstoolbox-python", "mink", "mujoco")
    print("\n".join(machine_lines(peers)) + "\n", flush=True)
    results = []
    for arm in args.arms:
        results.append(measure(arm, count, min(count, args.mink_targets)))
        print("\n".join(arm_table(results[-1])), flush=True)
    print("\n".join(targets_table(results)))
    load = load_average()
    print(f"\n- load average at the end (1, 5, 15 min): {load}")
    return results


if __name__ == "__main__":
    main()
