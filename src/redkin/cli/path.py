"""``redkin path``: the redundancy (the arm angle, or q7 on a Franka-class arm) chosen over a whole path of poses,
inside the exact feasible sets (the certified ones of the real arm on a nearly S-R-S arm)."""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import numpy as np

from redkin.cli.cell import (
    CELL_SETS_KERNELS,
    CELL_SETS_SECTIONS,
    add_cell_arguments,
    cell_note_lines,
    cell_notes,
    load_cell,
)
from redkin.cli.common import (
    BRANCH_HELP,
    IMAGE_SUFFIXES,
    UsageError,
    add_force_flag,
    add_output_flags,
    add_robot_argument,
    add_srs_tolerance_argument,
    angle_unit,
    angles_in,
    angles_out,
    compiled_beside,
    fixed,
    format_values,
    joint_vector,
    load_robot,
    output_file,
    plural,
    print_json,
    python_until_compiled,
    read_poses,
    small_work,
)


def register(subparsers: argparse._SubParsersAction) -> None:
    path = subparsers.add_parser(
        "path", help="joint values along a path of poses, as far from the limits as the path allows within a step "
                     "bound, or the waypoint and joint that make it impossible (exit 1)")
    add_robot_argument(path)
    waypoints = path.add_mutually_exclusive_group(required=True)
    waypoints.add_argument("--poses", metavar="FILE",
                           help="the waypoints: .npy (an (N, 4, 4) array of poses), .csv (a header naming the columns "
                                "x,y,z,qx,qy,qz,qw; other columns ignored) or .json (a list of geometry_msgs/Pose "
                                "objects, or {\"poses\": [...]}); docs/paths.md")
    waypoints.add_argument("--through", metavar="FILE",
                           help="key poses (any --poses format) joined by straight lines and slerp at --step and "
                                "--angle-step: the waypoints in between are made")
    path.add_argument("--step", type=float, default=0.005, metavar="M",
                      help="with --through: the largest distance between waypoints (m, default 0.005)")
    path.add_argument("--angle-step", type=float, default=0.05, metavar="A",
                      help="with --through: the largest rotation between waypoints (radians, or degrees with --deg; "
                           "default 0.05 rad)")
    bound = path.add_mutually_exclusive_group()
    bound.add_argument("--max-step", nargs="+", type=float, metavar="A",
                       help="largest move of each joint between waypoints: one value or 7 (radians, or degrees "
                            "with --deg)")
    bound.add_argument("--speed", nargs="+", type=float, metavar="V",
                       help="joint speeds, one value or 7 (rad/s, or deg/s with --deg), with --dt, instead of the "
                            "robot description's velocity limits")
    path.add_argument("--dt", type=float, metavar="T",
                      help="seconds between waypoints: each joint moves at most its speed times T per waypoint, the "
                           "speed being the description's velocity limit (or --speed); give --dt or --max-step")
    path.add_argument("--q0", nargs=7, type=float, metavar="Q", help="the configuration before the first waypoint")
    path.add_argument("--end-branch", metavar="BRANCH", help="branch of the last waypoint: " + BRANCH_HELP)
    path.add_argument("--objective", choices=("clearance", "motion", "time", "obstacle-clearance"),
                      default="clearance",
                      help="clearance: as far from the limits as the path allows, then the least motion (default); "
                           "motion: the least total joint motion, then the largest clearance; time: the shorter timed "
                           "trajectory of those two (implies --timed); obstacle-clearance (with --scene): as far from "
                           "the obstacles and the arm's own links as the path allows, then the least motion")
    path.add_argument("--limits", metavar="FILE",
                      help="joint velocity, acceleration and jerk limits (YAML or JSON: velocity: [...], "
                           "acceleration: [...], in rad/s and rad/s^2, or deg with --deg; or MoveIt's "
                           "joint_limits.yaml) instead of the description's or the model's")
    path.add_argument("--timed", action="store_true",
                      help="time the path: the fastest trajectory within the joints' velocity and acceleration "
                           "limits (TOPP-RA, the timing extra), sampled at --rate")
    path.add_argument("--rate", type=float, metavar="HZ",
                      help="with --timed: samples per second (default 1000)")
    path.add_argument("--playback", metavar="FILE.html",
                      help="write a page that plays the timed path back in a browser (implies --timed): the arm "
                           "moving, a time slider, each joint's value and speed with their limits, the stops marked")
    path.add_argument("--trajectory", metavar="FILE",
                      help="write the timed trajectory here (implies --timed): .json as a "
                           "trajectory_msgs/JointTrajectory (radians, seconds), or .csv (t, then each joint's q, qd "
                           "and qdd)")
    path.add_argument("--allow-stops", action="store_true",
                      help="where no continuous path exists, split it into the fewest continuous segments joined by "
                           "reconfiguration stops (the tool at rest at a waypoint while the arm changes branch or "
                           "swings its elbow), and say where and why")
    path.add_argument("--thorough", action="store_true",
                      help="search the subdivided graph too where the first search already proved its clearance "
                           "optimal: the least motion among such paths on a finer graph (slower)")
    path.add_argument("--plot", metavar="FILE.png",
                      help="save the (waypoint, arm angle) plane of each branch here: the exact feasible arm angles, "
                           "the path (or the failing waypoint), and beside it the fixed arm angle, the clamped "
                           "per-pose optimum and greedy seeded tracking with their first failures (the (waypoint, "
                           "q7) plane without baselines on a Franka-class arm, and without them on a nearly S-R-S "
                           "arm); with --scene, the collision-free sets, and the stretches the cell removes in a "
                           "colour per link and obstacle (no baselines: they do not see the cell)")
    add_srs_tolerance_argument(path)
    add_cell_arguments(path, "every waypoint's redundancy is chosen among the arm angles clear of every obstacle and "
                             "of the arm's own links, and every step between waypoints is proved clear (the search "
                             "leaves out the steps that are not)")
    add_force_flag(path)
    add_output_flags(path)
    path.set_defaults(handler=_run_path, in_python=True)


def _cell_report(chain, cell, result) -> dict:
    """What the path keeps from the cell's obstacles and from itself: the least distance over its waypoints and
    where, and over the steps between them (each proved clear, :mod:`redkin.paths.clear_steps`)."""
    from redkin.collision import clearance

    body, scene = cell
    apart = clearance(chain, body, scene, result.q)
    worst = int(np.argmin(apart.distance))
    steps = result.steps
    return {"scene": scene.source, "margin": scene.margin, "least": float(apart.distance[worst]),
            "closest": [str(apart.link[worst]), str(apart.against[worst])], "waypoint": worst,
            "steps": {"certified": int(steps.certified.sum()), "of": len(steps.certified),
                      "least": float(steps.least.min(initial=np.inf))}}


def _failure_line(failure, degrees: bool) -> str:
    """The failure in one line, its angle in the command's unit, and whether the exact sets prove it."""
    text = f"no path: waypoint {failure.waypoint}: {failure.reason_text}"
    if failure.pair is not None:
        text += f" ({failure.pair[0]} meets {failure.pair[1]} on most of them)"
    if failure.joint is not None and failure.needed is not None:
        needed = fixed(float(angles_out(failure.needed, degrees)))
        text += f" (joint {failure.joint} must move {needed} {angle_unit(degrees)})"
    elif failure.joint is not None:
        text += f" (joint {failure.joint} blocks it)"
    proof = {"out-of-reach": "the arm's reach", "step": "the joint values the poses fix",
             "start": "the joint values the pose fixes"}.get(failure.reason, "the exact feasible sets")
    return text + (f" [proved by {proof}]" if failure.exact else " [on the searched graph]")


def _save_plot(file, chain, poses: np.ndarray, result, q0: np.ndarray | None, srs_tolerance: float | None,
               cell=None) -> None:
    """The figure of :func:`redkin.plot.paths.path_plane_figure`: the path (or its failure) beside the baselines
    that start where it starts (the fixed arm angle and the clamped optimum on its first branch, or on ``q0``'s
    without a path; greedy tracking from ``q0``), drawn where every pose is within reach; a Franka-class arm's
    (waypoint, q7) plane has no baselines (they choose arm angles), nor a nearly S-R-S arm's (they use the exact
    closed form).  In the ``cell`` (body, scene): the collision-free sets and the stretches the cell removes
    (:func:`redkin.paths.removed_along_path`), without baselines (they do not see the cell)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from redkin.paths import cell_along_path, clamped_optimum_path, feasible_along_path, fixed_psi_path, greedy_path
    from redkin.paths.arm_family import path_family
    from redkin.plot.paths import path_plane_figure
    from redkin.srs import arm_angle_of, reachable

    baselines = []
    family = path_family(chain, srs_tolerance)
    if cell is None and family.baselines and reachable(chain, poses).all():  # they choose arm angles in closed form
        start = None
        if result.ok:
            start = (float(result.psi[0]), result.branch[0])
        elif q0 is not None:
            state = arm_angle_of(chain, q0)
            start = (float(state.psi), str(state.branch_strings()))
        if start is not None:
            baselines += [fixed_psi_path(chain, poses, result.step, *start),
                          clamped_optimum_path(chain, poses, result.step, start[1])]
        baselines.append(greedy_path(chain, poses, result.step, q0=q0))
    if cell is None:
        fig = path_plane_figure(feasible_along_path(chain, poses, srs_tolerance), result, baselines,
                                exact=family.exact, title=f"{chain.name}: {len(poses)} waypoints")
    else:
        body, scene = cell
        in_cell = cell_along_path(chain, poses, body, scene, srs_tolerance)
        fig = path_plane_figure(in_cell.free, result, exact=family.exact,
                                title=f"{chain.name}: {len(poses)} waypoints in a cell", removed=in_cell.removed)
    image = io.BytesIO()
    fig.savefig(image, format=Path(file).suffix[1:].lower(), dpi=120, bbox_inches="tight")
    plt.close(fig)
    from redkin._files import write_durably

    write_durably(Path(file), image.getbuffer())  # whole or not at all, and a full disk names the file


#: Waypoints of a path that ``redkin path`` resolves with the kernels run as Python, cached or not
#: (:func:`redkin.cli.common.small_work`): on an S-R-S or offset-elbow arm without a cell, whose paths take about 10 ms
#: a waypoint as Python (0.5 s for 21 on the iiwa14, with the start) against 0.9 s compiled from the cache, most of it
#: loading numba.
_SMALL_PATH = 32
#: Waypoints of a path that runs as Python while the kernels it calls are not compiled yet (compiling them in the
#: background meanwhile, :func:`redkin.cli.common.python_until_compiled`), at most, where that is quicker than
#: compiling first: an S-R-S or offset-elbow arm's path without a cell, one in a cell, and the Franka class's without
#: one.  From a fresh cache, the compile in the background beside it, 2 cores (2026-12-07), as Python against compiled
#: first: 501 iiwa14 waypoints 6.0 against 14.2 s, 1001 10.9 against 13.6 s; in a cell of a table, a post and a lamp
#: 301 took 10.5 against 16.8 s; 501 Panda waypoints 22.5 against 26.1 s (earlier: 21/51/101/201 iiwa14 waypoints
#: 0.5/0.7/1.3/2.1 s, in the cell 51/101/201 3.2/6.0/11.5 s, 21/51/101 Panda waypoints 1.5/2.7/4.7 s).  The Franka
#: class's paths in a cell stay compiled (161 s as Python for 21), and so do longer paths, timed ones and
#: ``--thorough``.
_PYTHON_PATH, _PYTHON_CELL_PATH, _PYTHON_FRANKA_PATH = 1000, 400, 500
#: The kernels a path of an S-R-S or offset-elbow arm without a cell calls (with theirs): the limit sets, the IK's
#: coefficients, and the path graph's samples, rows and sweep; and the sections of :mod:`redkin.warm_up` that compile
#: them.
_SRS_PATH_KERNELS = ("redkin.srs._feasible_kernels.poses_feasible", "redkin.srs._ik_kernels.coefficients",
                     "redkin.paths._dp_kernels.sample_angles", "redkin.paths._dp_kernels.node_rows",
                     "redkin.paths._dp_kernels.sweep")
_SRS_PATH_SECTIONS = ("srs ik", "srs sets", "paths")
#: The kernels a path of the Franka class calls (with theirs): its q7 sets, and the path graph's rows and sweep.
_FRANKA_PATH_KERNELS = ("redkin.franka._kernels.feasible_poses", "redkin.franka._kernels.seventh_frames",
                        "redkin.paths._dp_kernels.q7_node_rows", "redkin.paths._dp_kernels.sweep")
#: The sections of :mod:`redkin.warm_up` that compile them (in the background, on a fresh cache).
_FRANKA_PATH_SECTIONS = ("franka", "paths")
#: The kernels of a path that compiles from its first call which a second process compiles while the command
#: compiles the rest (:func:`redkin.cli.common.compiled_beside`), and the sections of :mod:`redkin.warm_up` that call
#: them alone: the path graph's search, and on a nearly S-R-S arm the certified self-motion (the command compiles the
#: IK's), in a cell the distances (the command compiles the limit sets', and then the collision-free sets' own steps
#: once the other process ends).  Elsewhere one tree of kernels takes most of the time (the q7 sets, or the limit
#: sets and the IK): splitting off the search alone saved nothing measurable on 51 waypoints of the Panda and the
#: iiwa14.
_BESIDE_KERNELS = {"nearly": ("redkin.srs.nearly._self_motion_kernels.traced", "redkin.paths._dp_kernels.sweep"),
                   "in a cell": ("redkin.collision._clearance_kernels.clearances", "redkin.paths._dp_kernels.sweep")}
_BESIDE_SECTIONS = {"nearly": ("nearly self-motion", "path search"),
                    "in a cell": ("collision distances", "path search")}
#: The kernels of a path in a cell beside its sets' (:data:`redkin.cli.cell.CELL_SETS_KERNELS`, whose clearances
#: also measure the steps between waypoints): the path graph's sweep.
_CELL_PATH_KERNELS = ("redkin.paths._dp_kernels.sweep",)


def _parameter(chain, srs_tolerance: float | None) -> str:
    """The redundancy parameter path resolution uses on the chain: ``"psi"`` or ``"q7"``."""
    from redkin.paths.arm_family import path_family

    return path_family(chain, srs_tolerance).parameter


def _compile_in_two(chain, srs_tolerance: float | None, in_cell: bool) -> None:
    """On a fresh cache, the kernels of a path that compiles from its first call compiled in two processes
    (:data:`_BESIDE_KERNELS`): this one compiles the IK's, at a pose of the arm's own, on a nearly S-R-S arm by the
    self-motion's seeds (:func:`redkin.srs.nearly.self_motion.seed_solutions`); in a cell, of the Franka class its q7
    sets' (:func:`redkin.franka.feasible_q7_pieces`), of an S-R-S or offset-elbow arm its limit sets' and
    configurations' (:meth:`redkin.paths.family.ArmAngleFamily.pieces`, :func:`redkin.srs.ik_all_branches`);
    elsewhere nothing."""
    from redkin.paths.arm_family import path_family
    from redkin.paths.family import ArmAngleFamily, NearlyFamily

    family = path_family(chain, srs_tolerance)
    nearly = isinstance(family, NearlyFamily)
    if not (nearly or in_cell):
        return

    def first() -> None:
        pose = chain.fk(np.clip(np.zeros_like(chain.lower), chain.lower, chain.upper))  # the frames compile here
        if isinstance(family, NearlyFamily):
            from redkin.srs.nearly.self_motion import seed_solutions

            seed_solutions(family.nearly, pose)
        elif isinstance(family, ArmAngleFamily):
            from redkin.srs import ik_all_branches

            family.pieces(pose[None])
            ik_all_branches(family.geometry, pose[None], np.zeros(1))
        else:
            from redkin.franka import feasible_q7_pieces

            feasible_q7_pieces(chain, pose)

    key = "nearly" if nearly else "in a cell"
    compiled_beside(_BESIDE_KERNELS[key], _BESIDE_SECTIONS[key], "the certified self-motion's and the search's kernels"
                    if nearly else "the distances' and the search's kernels", first)


def _model_line(chain, srs_tolerance: float | None) -> str | None:
    """What a nearly S-R-S arm's path rests on, in one line (its neighbour and model error); ``None`` for an arm of
    an exact class."""
    from redkin.paths.arm_family import path_family

    return path_family(chain, srs_tolerance).model()


#: What the objective prefers, in words, by ``--objective``.
_PREFERS = {"clearance": "the largest clearance from the limits, then the least motion",
            "motion": "the least total motion, then the largest clearance",
            "time": "the shorter timed trajectory of the paths of those two objectives",
            "obstacle-clearance": "the largest least distance from the obstacles and the arm's own links, then the "
                                  "least motion"}


def _start(chain, result, q0: np.ndarray | None, objective: str, srs_tolerance: float | None) -> dict:
    """Which branch the path starts on and why: ``--q0``'s own (the first waypoint is within one step of it), or,
    without ``--q0``, the objective's choice among every branch; with ``--q0``, its branch as well."""
    from redkin.arms import arm
    from redkin.srs import BRANCHES

    start: dict = {"branch": result.branch[0], "why": "objective" if q0 is None else "q0"}
    if q0 is not None:
        start["q0_branch"] = str(arm(chain, srs_tolerance=srs_tolerance).branch_of(q0))
        start["text"] = (f"starts on branch {start['branch']}, within one step of --q0"
                         + (" (its own branch)" if start["q0_branch"] == start["branch"] else
                            f" (which is on branch {start['q0_branch']} at its own pose)"))
    else:
        start["text"] = (f"starts on branch {start['branch']}: no --q0, so the search chose among all "
                         f"{len(BRANCHES)} branches by {_PREFERS[objective]}; --q0 Q starts from your configuration")
    return start


def _bound(args: argparse.Namespace, chain) -> tuple[np.ndarray, np.ndarray | None, str | None]:
    """The step bound of the options, and the joint speeds (rad/s) it is made of with where they come from
    (``"--speed"``, or with ``--dt`` alone ``"description"``: its velocity limits); no speeds for ``--max-step``."""
    from redkin.paths import step_bound
    from redkin.paths.bounds import missing_speeds

    if args.max_step is not None:
        if args.dt is not None:
            raise UsageError("--dt goes with --speed, or alone for the description's velocity limits; --max-step is "
                             "already a step per waypoint")
        return step_bound(chain, angles_in(args.max_step, args.deg)), None, None
    if args.dt is None:
        if args.speed is not None:
            raise UsageError("--speed needs --dt, the seconds between waypoints")
        raise UsageError("give the bound on joint motion: --max-step A, or --dt T (with the description's velocity "
                         "limits, or --speed V)")
    if args.speed is not None:
        speed = angles_in(args.speed, args.deg)
        step = step_bound(chain, speed=speed, dt=args.dt)
        return step, np.broadcast_to(speed.reshape(-1), step.shape), "--speed"
    missing = missing_speeds(chain)
    if missing:
        raise UsageError(f"{chain.name} has no velocity limit on {missing} in its description: give --speed V with "
                         "--dt, or --max-step A")
    return step_bound(chain, dt=args.dt), chain.velocity, "description"


def _waypoints(args: argparse.Namespace) -> np.ndarray:
    """The poses of ``--poses``, or the line through the key poses of ``--through`` (one line for a bad file)."""
    from redkin.paths.waypoints import through

    if args.poses is not None:
        return read_poses(args.poses)
    return through(read_poses(args.through, "--through"), step=args.step,
                   angle_step=float(angles_in([args.angle_step], args.deg)[0]))


def _write_trajectory(file, trajectory) -> None:
    """The trajectory into ``file``, whole or not at all: a ``trajectory_msgs/JointTrajectory`` in JSON, or CSV."""
    import io
    import json

    from redkin._files import write_durably

    if file.suffix.lower() == ".json":
        text = json.dumps(trajectory.joint_trajectory(), allow_nan=False)
    else:
        names = trajectory.joint_names
        header = ["t"] + [f"{kind}_{name}".replace(" ", "_") for kind in ("q", "qd", "qdd") for name in names]
        buffer = io.StringIO()
        np.savetxt(buffer, np.column_stack([trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd]),
                   delimiter=",", header=",".join(header), comments="", fmt="%.17g")
        text = buffer.getvalue()
    write_durably(file, text.encode())


def _stop_report(stop, degrees: bool) -> dict:
    """A reconfiguration stop in JSON, angles in the command's unit."""
    return {"waypoint": stop.waypoint, "reason": stop.reason, "branch_before": stop.branch_before,
            "branch_after": stop.branch_after, "parameter_before": angles_out(stop.parameter_before, degrees),
            "parameter_after": angles_out(stop.parameter_after, degrees), "joint": stop.joint,
            "move": angles_out(stop.move, degrees), "motion": stop.motion,
            "q_after": angles_out(stop.path[-1], degrees), "message": stop.message, **_stop_in_cell(stop)}


#: A joint speed at most this [rad/s] is at rest (the timing's rest is 0 up to rounding).
_AT_REST = 1e-9


def _trajectory_in_cell(result) -> tuple[dict, str | None]:
    """In a cell, whether the timed trajectory's samples and the steps between them are proved clear (JSON
    ``clear``, and ``blocked_at``: the first step not proved, in seconds, with the pair found; ``at_rest_at_waypoints``:
    it stops at every waypoint, the timing's last resort for steps that graze the margin), and the line printed;
    else nothing."""
    steps, trajectory = result.trajectory_steps, result.trajectory
    if steps is None or trajectory is None:
        return {}, None
    clear = bool(steps.certified.all())
    inner = trajectory.waypoint_times[1:-1]
    resting = bool(len(inner)) and bool(np.all(np.abs(trajectory.at(inner)[1]) <= _AT_REST))
    if clear:
        text = (f"in the cell: the timed trajectory's {len(trajectory.t)} samples and the steps between them are "
                f"proved clear of the obstacles (at least {float(steps.least.min(initial=np.inf)):.4g} m)"
                + ("; it comes to rest at every waypoint: the path's steps graze the margin, and no spline beside "
                   "them keeps it" if resting else ""))
        return {"clear": True, "blocked_at": None, "at_rest_at_waypoints": resting}, text
    first = int(np.flatnonzero(~steps.certified)[0])
    pair = [str(steps.link[first]), str(steps.against[first])] if steps.blocked[first] else None
    text = (f"in the cell: the timed trajectory is NOT proved clear of the obstacles from t = {trajectory.t[first]:.4f}"
            f" s" + (f" ({pair[0]} meets {pair[1]})" if pair else " (a step not proved)")
            + ": the spline swings wide of the steps proved between waypoints; give more waypoints")
    return {"clear": False, "blocked_at": {"t": float(trajectory.t[first]), "pair": pair},
            "at_rest_at_waypoints": resting}, text


def _stop_in_cell(stop) -> dict:
    """In a cell, whether a stop's reconfiguration is proved clear and the pairs found blocking it; else nothing."""
    steps = stop.steps
    if steps is None:
        return {}
    pairs = zip(steps.link[steps.blocked].tolist(), steps.against[steps.blocked].tolist(), strict=True)
    return {"clear": bool(steps.certified.all()), "blocked_by": [list(pair) for pair in sorted(set(pairs))]}


def _jerk_ratio(trajectory, chain) -> float | None:
    """The largest joint jerk between samples relative to the joint's jerk limit (``None`` where no limit is
    known, or for fewer than two samples): the timing does not limit it."""
    known = np.isfinite(chain.jerk)
    if not known.any() or len(trajectory.t) < 2:
        return None
    return float(np.abs(trajectory.jerk[:, known] / chain.jerk[known]).max())


def _timing_lines(trajectory, source: str, file, jerk: float | None) -> list[str]:
    """What the timing found, in words."""
    lines = [f"timed: {trajectory.duration:.6g} s at {trajectory.rate:g} Hz ({len(trajectory.t)} samples), every "
             f"joint within its velocity and acceleration limits ({source}); joint path: "
             + ("the cubic spline through the waypoints" if trajectory.interpolation == "cubic" else
                "the shape-keeping PCHIP interpolant (the cubic spline would leave a joint's range)"
                if trajectory.interpolation == "pchip" else "one configuration, at rest")]
    if jerk is not None:
        lines.append(f"jerk not limited: the largest between samples is {jerk:.3g} x the joint's jerk limit"
                     + (" (a controller with a jerk limit must filter it, as libfranka's rate limiter does)"
                        if jerk > 1.0 else ""))
    if file is not None:
        lines.append(f"trajectory written to {file}")
    return lines


def stop_spans(result) -> list:
    """The stops of a timed result as spans of its time axis, with their words (for the playback page)."""
    from redkin.explore.playback import StopSpan

    assert result.trajectory is not None
    return [StopSpan(float(start), float(end), stop.message)
            for (start, end), stop in zip(result.trajectory.stop_spans, result.stops)]


def _run_path(args: argparse.Namespace) -> int:
    from redkin.paths import resolve_path
    from redkin.paths.timing import DEFAULT_RATE
    plot = None if args.plot is None else output_file(args.plot, "--plot", IMAGE_SUFFIXES, args.force)
    trajectory_file = (None if args.trajectory is None else
                       output_file(args.trajectory, "--trajectory", (".json", ".csv"), args.force))
    playback = None if args.playback is None else output_file(args.playback, "--playback", {".html", ".htm"},
                                                              args.force)
    timed = args.timed or trajectory_file is not None or playback is not None or args.objective == "time"
    if args.rate is not None and not timed:
        raise UsageError("--rate applies to a timed path: give --timed (or --trajectory, --playback, "
                         "--objective time)")
    if args.poses is not None and (args.step != 0.005 or args.angle_step != 0.05):
        raise UsageError("--step and --angle-step go with --through (the key poses joined by lines); --poses are "
                         "the waypoints themselves")
    chain = load_robot(args)
    limits_source = f"{chain.name}'s own"
    if args.limits is not None:
        from redkin.motion_limits import read_motion_limits

        chain = read_motion_limits(args.limits, chain, args.deg)
        limits_source = f"--limits {args.limits}"
    cell = load_cell(args, chain)
    if cell is None and args.objective == "obstacle-clearance":
        raise UsageError("--objective obstacle-clearance needs the cell: give --scene FILE (and --body FILE)")
    step, speed, speed_source = _bound(args, chain)  # from the chain as loaded, whose velocity limits are its own
    poses = _waypoints(args)
    q0 = None if args.q0 is None else joint_vector(chain, args.q0, args.deg, "--q0 values")
    model = _model_line(chain, args.srs_tolerance)
    plain = model is None and not timed and not args.thorough
    small = False
    if plain:
        exact_angle = _parameter(chain, args.srs_tolerance) == "psi"
        count = len(poses)
        if cell is None and exact_angle and count <= _PYTHON_PATH:
            small = count <= _SMALL_PATH or python_until_compiled(_SRS_PATH_KERNELS, "this path", _SRS_PATH_SECTIONS)
        elif cell is None and not exact_angle and count <= _PYTHON_FRANKA_PATH:
            small = python_until_compiled(_FRANKA_PATH_KERNELS, "this path of the Franka class",
                                          _FRANKA_PATH_SECTIONS)
        elif cell is not None and exact_angle and count <= _PYTHON_CELL_PATH:
            small = python_until_compiled((*CELL_SETS_KERNELS["psi"], *_CELL_PATH_KERNELS), "this path in a cell",
                                          (*CELL_SETS_SECTIONS["psi"], "paths"))
    small_work(small)
    if not small:
        _compile_in_two(chain, args.srs_tolerance, cell is not None)
    degrees = args.deg
    unit = angle_unit(degrees)
    if not args.json:  # what the path rests on, before the search (seconds on a nearly S-R-S arm)
        if model is not None:  # the certified sets cost 0.1-0.4 s a waypoint (docs/srs.md, "cost")
            print(f"{model}; certifying the sets of {len(poses)} waypoints, typically 0.1-0.4 s each", flush=True)
        if speed is not None:
            source = "the description's velocity limits" if speed_source == "description" else "--speed"
            print(f"step bound: speed x dt ({args.dt:g} s), speeds [{unit}/s] from {source}: "
                  f"{format_values(angles_out(speed, degrees), 4)}", flush=True)
    result = resolve_path(chain, poses, step, q0=q0, end_branch=args.end_branch, thorough=args.thorough,
                          objective=args.objective, srs_tolerance=args.srs_tolerance,
                          timing=(DEFAULT_RATE if args.rate is None else args.rate) if timed else None,
                          allow_stops=args.allow_stops,
                          body=None if cell is None else cell[0], scene=None if cell is None else cell[1])
    in_cell = None if cell is None or not result.ok else _cell_report(chain, cell, result)
    notes = None if cell is None else cell_notes(chain, cell)
    if plot is not None:
        _save_plot(plot, chain, poses, result, q0, args.srs_tolerance, cell)
    trajectory = result.trajectory
    if trajectory is not None and trajectory_file is not None:
        _write_trajectory(trajectory_file, trajectory)
    if trajectory is not None and playback is not None:
        from redkin._files import write_durably
        from redkin.explore.playback import playback_html

        write_durably(playback, playback_html(chain, trajectory.t, trajectory.q, trajectory.qd, stop_spans(result),
                                              cell=cell).encode("utf-8"))
    failure = result.failure
    if args.json:
        report: dict = {"robot": chain.name, "status": result.status, "unit": angle_unit(degrees),
                        "step": angles_out(result.step, degrees),
                        "speed": angles_out(speed, degrees), "speed_unit": f"{angle_unit(degrees)}/s",
                        "speed_source": speed_source, "dt": args.dt if speed is not None else None,
                        "nodes": result.nodes, "parameter": result.parameter, "objective": args.objective,
                        "model": model}
        if result.ok:
            report.update(q=angles_out(result.q, degrees), branch=result.branch,
                          clearance=None if not np.isfinite(result.clearance) else angles_out(result.clearance,
                                                                                               degrees),
                          motion=angles_out(result.motion, degrees), optimal=result.optimal,
                          bottleneck=result.bottleneck)
            start = _start(chain, result, q0, args.objective, args.srs_tolerance)
            report["start"] = {key: value for key, value in start.items() if key != "text"}
            report[result.parameter] = angles_out(result.psi, degrees)
            report["stops"] = [_stop_report(stop, degrees) for stop in result.stops]
            if in_cell is not None:
                report["collision"] = {**in_cell, **(notes or {})}
            if trajectory is not None:
                report["trajectory"] = {
                    "duration": trajectory.duration, "rate": trajectory.rate, "samples": len(trajectory.t),
                    "interpolation": trajectory.interpolation, "waypoint_times": trajectory.waypoint_times,
                    "limits_source": limits_source, "file": None if trajectory_file is None else str(trajectory_file),
                    "stop_spans": trajectory.stop_spans, "playback": None if playback is None else str(playback),
                    "jerk_ratio": _jerk_ratio(trajectory, chain), **_trajectory_in_cell(result)[0],
                    "joint_trajectory": trajectory.joint_trajectory() if trajectory_file is None else None}
        else:
            assert failure is not None
            report["failure"] = {"waypoint": failure.waypoint, "reason": failure.reason, "joint": failure.joint,
                                 "exact": failure.exact, "message": failure.message,
                                 "needed": None if failure.needed is None else angles_out(failure.needed, degrees),
                                 "pair": None if failure.pair is None else list(failure.pair)}
            if notes is not None:
                report["collision"] = notes
        print_json(report)
        return 0 if result.ok else 1
    if not result.ok:
        assert failure is not None
        print(_failure_line(failure, degrees))
        for line in cell_note_lines(notes):
            print(line)
        return 1
    clearance = fixed(float(angles_out(result.clearance, degrees)))
    motion = fixed(float(angles_out(result.motion, degrees)))
    among = " through the certified collision-free sets" if in_cell is not None else ""
    proof = (f"proved the largest any path{among} keeps, at waypoint {result.bottleneck}" if result.optimal
             else "not proved the largest possible")
    print(f"path of {plural(len(poses), 'waypoint')} on {chain.name}: clearance {clearance} {unit} ({proof}), "
          f"total motion {motion} {unit}")
    print(_start(chain, result, q0, args.objective, args.srs_tolerance)["text"])
    if in_cell is not None:
        steps = in_cell["steps"]
        print(f"in the cell: every waypoint keeps the margin {in_cell['margin']:g} m; the least distance is "
              f"{in_cell['least']:.4g} m ({in_cell['closest'][0]} and {in_cell['closest'][1]}, waypoint "
              f"{in_cell['waypoint']}); all {steps['of']} steps between waypoints proved clear"
              + (f" (at least {steps['least']:.4g} m)" if steps["of"] else ""))
        for line in cell_note_lines(notes):
            print(line)
    if args.allow_stops:
        print(f"{plural(len(result.stops), 'reconfiguration stop')} (the fewest the searched graph allows)"
              + "".join(f"\n  {stop.message}" for stop in result.stops))
    if trajectory is not None:
        print("\n".join(_timing_lines(trajectory, f"{limits_source} limits", trajectory_file,
                                       _jerk_ratio(trajectory, chain))))
        cell_line = _trajectory_in_cell(result)[1]
        if cell_line is not None:
            print(cell_line)
        if playback is not None:
            print(f"playback page written to {playback}: open it in a browser")
    print(f"{'k':>5}  branch  {result.parameter:>10}  q [{unit}]" + ("      t [s]" if trajectory is not None else ""))
    for k in range(len(poses)):
        when = "" if trajectory is None else f"  {trajectory.waypoint_times[k]:9.4f}"
        print(f"{k:>5}  {result.branch[k]:>6}  {fixed(float(angles_out(result.psi[k], degrees)), 6, ' '):>10}  "
              f"{format_values(angles_out(result.q[k], degrees))}{when}")
    return 0
