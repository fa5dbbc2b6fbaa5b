"""``redkin explore``: the interactive explorer of an arm's redundancy parameter at a pose (the arm angle of S-R-S,
offset-elbow and nearly S-R-S arms, q7 of Franka-class arms), as one offline HTML page."""

from __future__ import annotations

import argparse

import numpy as np

from redkin.cli.cell import add_cell_arguments, cell_note_lines, cell_notes, load_cell
from redkin.cli.common import (
    BRANCH_HELP,
    UsageError,
    add_force_flag,
    add_output_flags,
    add_robot_argument,
    add_srs_tolerance_argument,
    add_target_arguments,
    angle_unit,
    angles_out,
    joint_vector,
    load_robot,
    output_file,
    print_json,
    python_until_compiled,
    small_work,
    target_pose,
)


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "explore", help="an interactive explorer of the redundancy at a pose, one HTML page: the arm angle of an "
                        "S-R-S, offset-elbow or nearly S-R-S arm (the Gen3, on the real arm), q7 of a Franka-class arm "
                        "(Panda, FR3, xArm7)"
    )
    add_robot_argument(parser)
    add_target_arguments(parser, required=False)
    parser.add_argument("--branch", help=f"branch shown first, at its optimum: {BRANCH_HELP} (default: the branch of "
                                         "--q, else the one whose optimum within the limits keeps the joints "
                                         "farthest from them)")
    parser.add_argument("--q", nargs="+", type=float, metavar="Q",
                        help="open the page at this configuration (one value per joint; radians, or degrees with "
                             "--deg): its branch and its own arm angle or q7; without --position and a rotation the "
                             "pose is its forward kinematics")
    parser.add_argument("--path", metavar="RESULT.json",
                        help="instead of a pose: play a timed path back (a `redkin path --trajectory FILE.json` "
                             "JointTrajectory, or the `redkin path --timed --json` report with its stops)")
    parser.add_argument("--out", required=True, metavar="FILE.html", help="the page to write")
    add_force_flag(parser)
    add_srs_tolerance_argument(parser)
    add_cell_arguments(parser, "the page draws the obstacles and the arm's capsules, shades the arm angles (q7 on "
                               "the Franka class) they remove by cause, and says how far the arm is from them at the "
                               "slider's value; with --path, the "
                               "playback draws them at each frame and says the least distance at the slider's time "
                               "(any arm)")
    add_output_flags(parser)
    parser.set_defaults(handler=run, in_python=True)


def run(args: argparse.Namespace) -> int:
    from redkin.explore import explorer_data, explorer_html

    out = output_file(args.out, "--out", {".html", ".htm"}, args.force)
    chain = load_robot(args)
    if args.path is not None:
        small_work(False)
        return _playback(args, chain, out, load_cell(args, chain))
    q = None if args.q is None else joint_vector(chain, args.q, args.deg, "--q values")
    if args.position is not None or args.rotation is not None or args.quat is not None:
        pose = target_pose(args)
    elif q is not None:
        pose = chain.fk(q)
    else:
        raise UsageError("give the pose (--position and --rotation or --quat), or a configuration --q to explore "
                         "at its pose")
    cell = load_cell(args, chain)
    page = None if cell is not None else _page_parameter(chain, args.srs_tolerance)
    small_work(page is not None and python_until_compiled(_PAGE_KERNELS[page], "this explorer page",
                                                          _PAGE_SECTIONS[page]))
    data = explorer_data(chain, pose, args.branch, srs_tolerance=args.srs_tolerance, q=q,
                         body=None if cell is None else cell[0], scene=None if cell is None else cell[1])
    from redkin._files import write_durably

    write_durably(out, explorer_html(data, degrees=args.deg).encode("utf-8"))
    parameter = data.parameter
    shown = data.branches[data.initial]
    opens = float(angles_out(shown.values[shown.start], args.deg))
    feasible = {b.branch: [angles_out(arc, args.deg).tolist() for arc in b.arcs] for b in data.branches}
    notes = None if cell is None else cell_notes(chain, cell)
    if args.json:
        wraps = {b.branch: [bool(lo > hi) for lo, hi in b.arcs] for b in data.branches}
        print_json({"robot": chain.name, "out": str(out), "parameter": parameter.name,
                    "domain": angles_out(parameter.domain, args.deg).tolist(),
                    "units": {"feasible": angle_unit(args.deg), "domain": angle_unit(args.deg)},
                    "grid_points": {b.branch: len(b.values) for b in data.branches}, "feasible": feasible,
                    "feasible_wraps": wraps, "opens": {"branch": shown.branch, parameter.name: opens,
                                                       "why": data.opening},
                    **({} if data.cell is None else {"collision_free": _cell_sets(data, args.deg), "cell": notes})})
    else:
        reachable = sum(bool(arcs) for arcs in feasible.values())
        print(f"wrote {out}: {chain.name}, feasible {parameter.plural} on {reachable} of {len(feasible)} branches; "
              "open it in a browser")
        print(f"{data.opening} ({parameter.name} = {opens:.6f} {angle_unit(args.deg)})")
        for line in cell_note_lines(notes):
            print(line)
    return 0


#: The kernels an explorer page calls (with theirs) on an S-R-S or offset-elbow arm, and on the Franka class: a page
#: of either runs them as Python while they are not compiled (about 2 and 3 s, against 17-25 s of compiling on a
#: fresh install and about 1.2 s from the cache).
_PAGE_KERNELS = {
    "psi": ("redkin.srs._feasible_kernels.poses_feasible", "redkin.srs._feasible_kernels.batch_arc_runs",
            "redkin.srs._ik_kernels.solve_poses"),
    "q7": ("redkin.franka._kernels.feasible_poses", "redkin.franka._kernels.solve_poses",
           "redkin.franka._kernels.solve_single"),
}
#: How far past a joint's limit [rad] a played point may lie: the rounding of a trajectory written to a file.
_RANGE_ROUNDING = 1e-9
#: The sections of :mod:`redkin.warm_up` that compile :data:`_PAGE_KERNELS` (in the background, on a fresh cache).
_PAGE_SECTIONS = {"psi": ("srs ik", "srs sets"), "q7": ("franka",)}


def _page_parameter(chain, srs_tolerance: float | None) -> str | None:
    """The key of :data:`_PAGE_KERNELS` for the chain's class (its redundancy parameter); ``None`` for a nearly S-R-S
    arm (its certified self-motion takes a minute as Python) or a chain of no arm-angle class (the page refuses
    it)."""
    from redkin.errors import NotArmAngleClassError
    from redkin.paths.arm_family import path_family
    from redkin.paths.family import NearlyFamily

    try:
        family = path_family(chain, srs_tolerance)
    except NotArmAngleClassError:
        return None
    return None if isinstance(family, NearlyFamily) else family.parameter


def _cell_sets(data, degrees: bool) -> dict:
    """Per branch, the collision-free arcs and every stretch the cell removes with its cause, in the command's unit."""
    assert data.cell is not None
    return {curves.branch: {"feasible": [angles_out(arc, degrees).tolist() for arc in cell.free],
                            "blocked": [{"arc": angles_out(np.array([lo, hi]), degrees).tolist(), "cause": text}
                                        for lo, hi, text in cell.blocked]}
            for curves, cell in zip(data.branches, data.cell.branches, strict=True)}


def _playback(args: argparse.Namespace, chain, out, cell) -> int:
    """``--path``: the playback page of a timed path (:mod:`redkin.explore.playback`), in the ``cell`` where given."""
    from redkin._files import write_durably
    from redkin.explore.playback import StopSpan, playback_html

    if args.position is not None or args.rotation is not None or args.quat is not None or args.q is not None:
        raise UsageError("--path plays a timed path back: give it without a pose or --q")
    message, report = _read_path_file(args.path)
    names = message.get("joint_names")
    points = message.get("points")
    if not isinstance(names, list) or not isinstance(points, list) or not points:
        raise UsageError(f"--path {args.path!r}: no JointTrajectory in it (joint_names and points); time the path "
                         "with redkin path --timed --json, or --trajectory FILE.json")
    if len(names) != chain.n:
        raise UsageError(f"--path {args.path!r}: the trajectory has {len(names)} joints, {chain.name} has {chain.n}")
    if [str(name) for name in names] != list(chain.joint_names):
        raise UsageError(f"--path {args.path!r}: the trajectory moves the joints {', '.join(map(str, names))}; "
                         f"{chain.name}'s are {', '.join(chain.joint_names)} (another robot's path?)")
    made_for = report.get("robot")  # a named model's joints are "joint 1" .. "joint n", not names of their own
    if isinstance(made_for, str) and made_for != chain.name and not chain.own_joint_names.any():
        raise UsageError(f"--path {args.path!r}: the path was made for {made_for}, not {chain.name}")
    for index, point in enumerate(points):  # each list as long as the joints (velocities may be left empty)
        for key in ("positions", "velocities"):
            values = point.get(key) if isinstance(point, dict) else None
            if isinstance(values, list) and len(values) != chain.n and (values or key == "positions"):
                raise UsageError(f"--path {args.path!r}: point {index} has {len(values)} {key}, {chain.name} has "
                                 f"{chain.n} joints")
    try:
        t = np.array([p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"] for p in points],
                     dtype=float)
        q = np.array([p["positions"] for p in points], dtype=float)
        qd = np.array([p.get("velocities") or [0.0] * chain.n for p in points], dtype=float)
    except (KeyError, TypeError, ValueError) as exc:
        raise UsageError(f"--path {args.path!r}: a point is malformed ({exc!r}); each needs positions, velocities "
                         "and time_from_start {sec, nanosec}") from None
    outside = np.argwhere(~chain.joints_within_limits(q, _RANGE_ROUNDING))
    if outside.size:
        point, joint = outside[0].tolist()
        raise UsageError(f"--path {args.path!r}: point {point} puts joint {joint + 1} at {q[point, joint]:.6g} rad, "
                         f"outside {chain.name}'s range [{chain.lower[joint]:.6g}, {chain.upper[joint]:.6g}] "
                         "(another robot's path?)")
    timing = report.get("trajectory") or {}
    stops = [StopSpan(float(a), float(b), str(stop.get("message", ""))) for (a, b), stop in
             zip(timing.get("stop_spans") or [], report.get("stops") or [])]
    write_durably(out, playback_html(chain, t, q, qd, stops, cell=cell).encode("utf-8"))
    print(f"wrote {out}: {chain.name}, a trajectory of {t[-1] - t[0]:.3f} s"
          + (f" with {len(stops)} stop{'' if len(stops) == 1 else 's'}" if stops else "") + "; open it in a browser")
    for line in cell_note_lines(None if cell is None else cell_notes(chain, cell)):
        print(line)
    return 0


def _read_path_file(file: str) -> tuple[dict, dict]:
    """The JointTrajectory message of ``file`` and the report around it (empty for a bare message): the message is
    the file itself, the report's ``trajectory.joint_trajectory``, or the file its ``trajectory.file`` names."""
    import json
    from pathlib import Path

    def load(path: str) -> dict:
        try:
            data = json.loads(Path(path).read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise UsageError(f"--path {path!r}: cannot read it as JSON ({exc})") from None
        if not isinstance(data, dict):
            raise UsageError(f"--path {path!r}: expected a JSON object")
        return data

    data = load(file)
    if "points" in data:
        return data, {}
    timing: dict = data["trajectory"] if isinstance(data.get("trajectory"), dict) else {}
    if timing.get("joint_trajectory"):
        return timing["joint_trajectory"], data
    if timing.get("file"):
        named = Path(timing["file"])
        return load(str(named if named.is_absolute() else Path(file).parent / named)), data
    return {}, data
