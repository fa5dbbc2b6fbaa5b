"""``redkin ik`` and ``redkin arm-angles``: closed-form IK over the redundancy parameter -- the arm angle psi of
S-R-S and offset-elbow arms (paper 000), q7 of the Franka class (docs/franka.md)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

import numpy as np

from redkin.cli.background_compile import (
    OverTime,
    background_compiles,
    time_limit_available,
    wait_for_compile,
    within_seconds,
)
from redkin.cli.cell import (
    CELL_SETS_KERNELS,
    CELL_SETS_SECTIONS,
    add_cell_arguments,
    cell_note_lines,
    cell_notes,
    clearance_entry,
    free_report,
    load_cell,
)
from redkin.cli.common import (
    BRANCH_HELP,
    UsageError,
    add_output_flags,
    add_robot_argument,
    add_srs_tolerance_argument,
    add_target_arguments,
    angle_unit,
    angles_in,
    angles_out,
    compiling_later,
    fixed,
    format_values,
    joint_vector,
    kernels_compiled,
    load_robot,
    out_of_reach,
    plural,
    plus_minus,
    print_json,
    python_until_compiled,
    reach_reason,
    read_poses,
    small_work,
    target_pose,
)
from redkin.cli.ik_numerical import add_numerical_arguments, run_numerical
from redkin.errors import RedkinError

#: The kernels that follow a nearly S-R-S pose's certified self-motion for every solution of a branch at one arm
#: angle (:meth:`redkin.arms.nearly_kind.NearlyKind.every_solutions`), ``module.function``.
_SELF_MOTION_KERNELS = ("redkin.srs.nearly._kernels.solve", "redkin.srs.nearly._kernels.arm_angles",
                        "redkin.srs.nearly._self_motion_kernels.traced",
                        "redkin.srs.nearly._self_motion_kernels.corrected",
                        "redkin.srs.nearly._self_motion_kernels.scratch")
#: The sections of :mod:`redkin.warm_up` that compile them, and the chain's kernel that moves joints by whole turns
#: (in the background, on a fresh cache).
_SELF_MOTION_SECTIONS = ("chain", "nearly S-R-S")
#: The kernels a nearly S-R-S pose's sets call (``arm-angles``: :meth:`redkin.arms.Arm.analyse`), ``module.function``,
#: and the sections of :mod:`redkin.warm_up` that compile them.
_NEARLY_SETS_KERNELS = ("redkin._chain_kernels.frames", "redkin._chain_kernels.jacobian",
                        "redkin._chain_kernels.representatives", "redkin.srs._feasible_kernels.batch_arc_runs",
                        "redkin.srs._feasible_kernels.branches", "redkin.srs._ik_kernels.coefficients",
                        "redkin.srs.nearly._kernels.arm_angles", "redkin.srs.nearly._kernels.solve",
                        "redkin.srs.nearly._self_motion_kernels.traced")
_NEARLY_SETS_SECTIONS = ("chain", "srs ik", "srs sets", "nearly S-R-S")
#: How long ``arm-angles`` on a nearly S-R-S arm runs as Python while its kernels compile in the background, before
#: it waits for them: most poses take 10-15 s as Python on a 2-core machine, against about a minute of compiling;
#: next to a singular configuration 30 s and more.
_PYTHON_SECONDS = 20.0


def _nearly_sets_as_python() -> bool:
    """Whether ``arm-angles`` on a nearly S-R-S arm runs as Python first (:data:`_PYTHON_SECONDS`): where its kernels
    are not cached and a compile of them runs in the background (started here, or running already), and the
    command can stop the Python work in time (:func:`redkin.cli.background_compile.time_limit_available`).  It
    says so on stderr.  Elsewhere it runs compiled, compiling in the foreground what is not cached."""
    if kernels_compiled(_NEARLY_SETS_KERNELS) or not time_limit_available() or not background_compiles():
        return False
    print(f"redkin: note: the kernels of a nearly S-R-S arm's sets are not compiled yet, so it runs as Python for "
          f"up to {_PYTHON_SECONDS:.0f} s; {compiling_later(_NEARLY_SETS_SECTIONS)}", file=sys.stderr)
    return True

#: A batch of at most this many poses of an exact closed form runs as Python (``redkin ik --poses``): about 2 ms a
#: pose on the iiwa14, under 1 ms on the Panda, against about 9 s of compiling on a fresh cache (0.6 s of loading
#: numba from it).
_SMALL_BATCH = 256

#: The angle [rad] between two axes' lines at or below which they are aligned: the certificate of a singular arm
#: angle (:func:`redkin.srs.singular_arm_angles_nearly`).
_ALIGNED = 1e-9


def register(subparsers: argparse._SubParsersAction) -> None:
    solve = subparsers.add_parser(
        "ik", help="joint values for a pose (or every pose of --poses): at a redundancy parameter, the arm angle "
                   "--psi of an S-R-S, offset-elbow or nearly S-R-S arm (paper 000; the Gen3 and Jaco2 polished on "
                   "the real arm) or --q7 of a Franka-class arm (Panda, FR3, xArm7); without one, numerically on any "
                   "arm, certified and within the limits (exit 1 where a pose has no solution found)"
    )
    add_robot_argument(solve)
    add_target_arguments(solve, required=False)
    solve.add_argument("--poses", metavar="FILE", help="solve every pose of a file instead of --position and "
                                                      "--rotation or --quat: .npy (an (N, 4, 4) array), .csv or .json "
                                                      "(docs/paths.md)")
    parameter = solve.add_mutually_exclusive_group()
    parameter.add_argument("--psi", type=float,
                           help="arm angle of an S-R-S, offset-elbow or nearly S-R-S arm (radians, or degrees with "
                                "--deg)")
    parameter.add_argument("--q7", type=float, help="value of joint 7 of a Franka-class arm (radians, or degrees "
                                                     "with --deg)")
    group = solve.add_mutually_exclusive_group()
    group.add_argument("--branch", help=BRANCH_HELP.replace("default +++", "default: --q0's branch, else +++"))
    group.add_argument("--all", action="store_true", help="all eight branches")
    solve.add_argument("--every-solution", action="store_true",
                       help="with --psi on a nearly S-R-S arm: every solution of each asked branch, two where the arm "
                            "angle turns back along the real arm's certified self-motion (redkin.srs.branch_solutions, "
                            "about 0.1-1 s per pose); an exact arm has one per branch")
    add_srs_tolerance_argument(solve)
    add_numerical_arguments(solve)
    add_cell_arguments(solve, "at --psi or --q7 each solution is marked with its clearance from every obstacle and "
                              "between the arm's own links (on a nearly S-R-S arm, where a branch has two "
                              "solutions, the one clear within the limits); without them the numerical solver "
                              "returns only solutions clear by the margin")
    add_output_flags(solve)
    solve.set_defaults(handler=run_ik, in_python=True)

    angles = subparsers.add_parser(
        "arm-angles",
        help="feasible, singular and optimal arm angles of an S-R-S, offset-elbow or nearly S-R-S arm for a pose "
             "(paper 000; nearly S-R-S arms on the real arm); feasible and optimal q7 of a Franka-class arm",
    )
    add_robot_argument(angles)
    add_target_arguments(angles)
    angles.add_argument("--branch", help=BRANCH_HELP + "; where +++ has no feasible set, the branches that have one "
                                                      "are named")
    angles.add_argument("--target", nargs=7, type=float, metavar="Q",
                        help="joint values the optimal arm angles stay nearest to (radians, or degrees with --deg; "
                             "default: the middle of each joint's range)")
    angles.add_argument("--weights", nargs=2, type=float, metavar=("RS", "RW"),
                        help="how much the shoulder joints (RS) and the wrist joints (RW) count in the overall "
                             "optimal arm angle, two numbers >= 0, not both 0 (default 0.5 0.5; [000 eq. 40]; "
                             "S-R-S, offset-elbow and nearly S-R-S arms)")
    add_srs_tolerance_argument(angles)
    add_cell_arguments(angles, "the sets become the values of the parameter (psi, or q7 on the Franka class) clear "
                               "of every obstacle and of the arm's own links")
    add_output_flags(angles)
    angles.set_defaults(handler=_run_arm_angles, in_python=True)


def _closed_form_arm(chain, args: argparse.Namespace):
    """The chain as a :class:`redkin.arms.Arm` of a class with a redundancy parameter; a ValueError naming the right
    option where the command line gave the other one, or where the chain has no closed form."""
    from redkin.arms import arm
    from redkin.errors import NotArmAngleClassError

    classified = arm(chain, srs_tolerance=args.srs_tolerance)
    if classified.parameter is None:
        raise NotArmAngleClassError(f"{chain.name!r} has no closed-form IK: {classified.reason}", chain.name)
    name = classified.parameter.name
    given = [option for option in ("psi", "q7") if getattr(args, option, None) is not None]
    if given and given[0] != name:
        raise RedkinError(f"{chain.name}: its redundancy parameter is {classified.parameter.noun} (--{name}), not "
                          f"{given[0]}")
    return classified


def _ik_poses(args: argparse.Namespace) -> tuple[np.ndarray, bool]:
    """The target of ``redkin ik``: ``--position`` and ``--rotation`` or ``--quat``, or the ``--poses`` file (then
    ``True``)."""
    oriented = args.rotation is not None or args.quat is not None
    if args.poses is not None:
        if args.position is not None or oriented:
            raise UsageError("give --poses or --position and --rotation, not both (--quat stands for --rotation)")
        return read_poses(args.poses), True
    if args.position is None or not oriented:
        raise UsageError("the target needs --position X Y Z and --rotation R11 ... R33 (or --poses FILE); "
                         "--quat W X Y Z may stand for --rotation")
    return target_pose(args), False


def run_ik(args: argparse.Namespace) -> int:
    chain = load_robot(args)
    poses, batch = _ik_poses(args)
    if args.every_solution and (args.psi is None or args.numerical):
        raise UsageError("--every-solution lists the solutions at an arm angle: give --psi (without --numerical)")
    if (args.psi is None and args.q7 is None) or args.numerical:
        if args.psi is not None or args.q7 is not None:
            raise UsageError("--numerical solves without a redundancy parameter: drop --psi/--q7")
        if args.srs_tolerance is not None:
            raise UsageError("--srs-tolerance chooses the closed form of --psi or --q7; the numerical solver (without "
                             "them) does not use it")
        from redkin.numerical.solve import RESTARTS

        # one pose, at most the default starts: as Python (10-30 ms found, about 1 s for 200 starts) rather than
        # loading numba (about 0.6 s warm; 20 s of compiling on a fresh cache)
        small_work(not batch and (args.restarts is None or args.restarts <= RESTARTS))
        return run_numerical(chain, poses, args, batch, load_cell(args, chain))
    return _run_closed_form(chain, poses, args, batch)


def _run_closed_form(chain, poses: np.ndarray, args: argparse.Namespace, batch: bool) -> int:
    """``redkin ik --psi|--q7``: the closed form of the chain's class at one parameter value
    (:func:`redkin.closed_form.ik`: S-R-S, offset-elbow and nearly S-R-S arms at psi, the Franka class at q7) for the
    pose, or every pose of ``--poses`` (``batch``, one entry each); the solutions of the asked branches and the
    branches without one.

    A pose without a solution on any asked branch at that value (out of the wrist's reach, or none certified on a
    nearly S-R-S arm) is an answer, printed as such, and the exit code is 1, as the numerical path's for a pose
    whose solution was not found; 0 when every pose has one.
    """
    from redkin.closed_form import ClosedFormSolutions, ik
    from redkin.srs import BRANCHES

    classified = _closed_form_arm(chain, args)
    cell = load_cell(args, chain)
    parameter = classified.parameter.name
    value = float(angles_in(getattr(args, parameter), args.deg))
    q0 = None if args.q0 is None else joint_vector(chain, args.q0, args.deg, "--q0 values")
    traced = _traced(classified, args, batch, q0, cell)
    exact = classified.implementation.one_per_branch
    # one pose (in a cell too: its solutions' clearances), or a small batch of an exact class without a cell
    small_work(not traced and (not batch or (cell is None and exact and poses[..., 0, 0].size <= _SMALL_BATCH)))
    branch, why = _asked_branch(chain, args, q0)
    # every branch where it is asked for, or where the default's line names the others (one pose); else one
    every_branch = branch is None or (why == "default" and not batch)
    every = ik(chain, poses, **{parameter: value}, branch=None if every_branch else branch,
               srs_tolerance=args.srs_tolerance)
    assert isinstance(every, ClosedFormSolutions)  # a parameter was given
    result = _one_branch(every, BRANCHES.index(branch)) if every_branch and branch is not None else every
    q, exists = result.q.reshape(-1, len(result.branches), 7), result.exists.reshape(-1, len(result.branches))
    within = result.within_limits.reshape(exists.shape)
    found = [[[(q[k, b], bool(within[k, b]))] if exists[k, b] else [] for b in range(len(result.branches))]
             for k in range(len(q))]
    reach = result.reach._replace(out=result.reach.out.reshape(-1), distance=result.reach.distance.reshape(-1))
    # how many other solutions each branch has at the value: none on a closed form, unknown (None) where the
    # self-motion is not followed
    others: list[list[int | None]] = [[0 if classified.implementation.one_per_branch else None] * len(result.branches)
                                      for _ in found]
    if traced:
        _add_every_solution(classified, poses.reshape(-1, 4, 4), value, result.branches, found, others, reach.out,
                            q0, args.every_solution, cell)
    if q0 is not None:  # each solution's joint values nearest q0 modulo whole turns
        found = [[[(chain.nearest_in_range(one, near=q0), inside) for one, inside in row] for row in pose_rows]
                 for pose_rows in found]
    entries: list[dict[str, Any]] = [{
        "index": k,
        "solutions": [{"branch": str(label), "q": angles_out(one, args.deg), "within_limits": inside,
                       "others": others[k][b], **clearance_entry(chain, cell, one)}
                      for b, label in enumerate(result.branches) for one, inside in found[k][b]],
        "missing": [str(label) for b, label in enumerate(result.branches) if not found[k][b]],
        **reach_reason(reach, k),
    } for k in range(len(q))]
    code = 0 if all(entry["solutions"] for entry in entries) else 1
    unit = angle_unit(args.deg)
    if not batch and not traced and not classified.implementation.one_per_branch and entries[0]["solutions"]:
        print(f"redkin: note: not checked whether a branch has a second solution at this {parameter} (a nearly "
              "S-R-S arm can have two next to a fold): that follows the pose's self-motion, whose kernels are not "
              f"compiled yet, and --every-solution follows it now; {compiling_later(_SELF_MOTION_SECTIONS)}",
              file=sys.stderr)
    if args.json:
        head = {"robot": chain.name, "parameter": parameter, "units": {parameter: unit, "q": unit, "reach": "m"},
                parameter: angles_out(value, args.deg), "branch_from": why,
                **({} if cell is None else {"cell": cell_notes(chain, cell)})}
        single = {key: value for key, value in entries[0].items() if key != "index"}
        print_json({**head, "poses": entries} if batch else {**head, **single})
        return code
    asked = "branch " + str(branch) if branch is not None else f"any of the {len(BRANCHES)} branches"
    for k, entry in enumerate(entries):
        label = f"pose {entry['index']}: " if batch else ""
        if not entry["solutions"]:
            why = f": {out_of_reach(reach, k)}" if entry["reason"] else ""
            print(f"{label}no solution of {asked} at {parameter} = {fixed(angles_out(value, args.deg))} {unit}{why}")
        for s in entry["solutions"]:
            note = "" if s["within_limits"] else "  (outside limits)"
            if "clearance" in s:
                near = f"{s['closest'][0]} and {s['closest'][1]}"
                note += (f"  (collision-free: {near} {s['clearance']:.4g} m apart)" if s["collision_free"] else
                         f"  (collides: {near} {s['clearance']:.4g} m apart, margin {cell[1].margin:g} m)")
            if s["others"]:
                note += (f"  ({plural(s['others'], 'other solution')} of {s['branch']} at this {parameter}: "
                         "--every-solution lists them)")
            print(f"{label}{s['branch']}  {format_values(s['q'])}  [{unit}]{note}")
    for line in cell_note_lines(None if cell is None else cell_notes(chain, cell)):
        print(line)
    if why == "default" and not batch:
        inside = [str(label) for label, flag in zip(every.branches, every.within_limits.reshape(-1)) if flag]
        if entries[0]["solutions"] and not entries[0]["solutions"][0]["within_limits"] and inside:
            print(f"branch {branch} is the default: {', '.join(inside)} {'is' if len(inside) == 1 else 'are'} within "
                  "the limits here (--branch B picks one, --all lists all eight, --q0 Q takes its branch)")
    return code


def _traced(classified, args: argparse.Namespace, batch: bool, q0: np.ndarray | None, cell) -> bool:
    """Whether ``ik --psi`` follows the pose's certified self-motion for every solution of each branch at that arm
    angle: on a nearly S-R-S arm (a branch may have two near a fold), where ``--every-solution``, ``--q0`` or a
    cell ask which one (a batch too), and on one pose to say whether a branch has another solution, unless the
    self-motion's kernels are not compiled yet: compiling them takes about a minute, which that remark is not worth
    (the solution then comes from the closed form as Python, in about a second, and a note says what was not
    checked)."""
    if classified.implementation.one_per_branch:
        return False
    if args.every_solution or q0 is not None or cell is not None:
        return True
    if batch:
        return False
    return kernels_compiled(_SELF_MOTION_KERNELS)


def _asked_branch(chain, args: argparse.Namespace, q0: np.ndarray | None):
    """The branch ``ik --psi|--q7`` answers and where it comes from: ``None`` with ``--all`` (``"all"``); else
    ``--branch`` (``"--branch"``), or ``--q0``'s own branch (``"q0"``, read off the configuration by its class), or
    ``+++`` (``"default"``)."""
    from redkin.arms import arm
    from redkin.srs import BRANCHES, parse_branch

    if args.all:
        return None, "all"
    if args.branch is not None:
        return parse_branch(args.branch), "--branch"
    if q0 is not None:
        return parse_branch(str(arm(chain, srs_tolerance=args.srs_tolerance).branch_of(q0))), "q0"
    return BRANCHES[0], "default"


def _one_branch(result, index: int):
    """``result`` (a :class:`redkin.closed_form.ClosedFormSolutions` of every branch) narrowed to one branch."""
    keep = slice(index, index + 1)
    return result._replace(q=result.q[..., keep, :], exists=result.exists[..., keep],
                           within_limits=result.within_limits[..., keep], branches=result.branches[keep])


def _add_every_solution(classified, poses: np.ndarray, value: float, branches: tuple,
                        found: list[list[list[tuple[np.ndarray, bool]]]], others: list[list[int | None]],
                        out: np.ndarray, q0: np.ndarray | None, every: bool, cell) -> None:
    """On an arm whose branch may have several solutions at one value (a nearly S-R-S arm:
    :func:`redkin.srs.branch_solutions` on the pose's certified self-motion, the closed form's first), every solution
    of each branch ``b`` at ``value`` for pose ``k``, each joint shifted by whole turns into its range where it can
    be, nearest ``q0`` where given: all of them into ``found[k][b]`` where ``every``, else the one
    :func:`redkin.arms.branch_choice.preferred` picks (within the limits and clear of the ``cell`` first, then
    nearest ``q0``, else the closed form's), and how many others there are into ``others[k][b]``.  Nothing for a
    pose proven out of reach (``out``)."""
    from redkin.arms.branch_choice import candidates, preferred
    from redkin.collision import clearance

    chain = classified.chain
    rows = np.array([classified.branches.index(str(label)) for label in branches])
    for k, (pose, row) in enumerate(zip(poses, found)):
        if out[k]:
            continue
        for b, solutions in enumerate(classified.implementation.every_solutions(pose, value, rows)):
            if not len(solutions):
                continue
            solutions, inside = candidates(chain, solutions, q0)
            listed = [(q, bool(flag)) for q, flag in zip(solutions, inside)]
            others[k][b] = 0 if every else len(listed) - 1
            if every:
                row[b] = listed
            else:
                clear = None
                if cell is not None:
                    body, scene = cell
                    clear = clearance(chain, body, scene, solutions).distance >= scene.margin
                row[b] = [listed[preferred(solutions, inside, clear, q0)]]


def _run_arm_angles(args: argparse.Namespace) -> int:
    """``redkin arm-angles``: what one pose's redundancy holds on the asked branch (:meth:`redkin.arms.Arm.analyse`),
    whatever the arm's class: the feasible set of that branch and of every branch, the per-joint sets, the joints
    the pose fixes and the singular values where the class has them, and the limit-avoiding values.  Without
    ``--branch`` it shows ``+++`` and, where that set is empty, names the branches that have one."""
    from redkin.srs import parse_branch

    chain = load_robot(args)
    classified = _closed_form_arm(chain, args)
    cell = load_cell(args, chain)
    exact = classified.implementation.one_per_branch
    python_first = cell is None and not exact and _nearly_sets_as_python()
    if cell is not None and exact:  # one pose's collision-free sets: as Python until their kernels are cached
        parameter = classified.parameter.name
        small_work(python_until_compiled(CELL_SETS_KERNELS[parameter], "these collision-free sets",
                                         CELL_SETS_SECTIONS[parameter]))
    else:
        small_work((cell is None and exact) or python_first)
    branch = str(parse_branch("+++" if args.branch is None else args.branch))
    target = None if args.target is None else joint_vector(chain, args.target, args.deg, "--target values")
    pose = target_pose(args)
    analysis = None
    if python_first:
        try:
            with within_seconds(_PYTHON_SECONDS):
                analysis = classified.analyse(pose, branch, target=target, weights=args.weights)
        except OverTime:
            print(f"redkin: note: still running as Python after {_PYTHON_SECONDS:.0f} s (a pose next to a singular "
                  "configuration takes longer): waiting for the compile, then running compiled", file=sys.stderr)
            wait_for_compile()
            small_work(False)
    if analysis is None:
        analysis = classified.analyse(pose, branch, target=target, weights=args.weights)
    report = _arm_angles_report(classified, analysis, args.deg)
    if cell is not None:
        from redkin.collision import collision_free_set

        body, scene = cell
        free = collision_free_set(classified, pose, body, scene)
        row = classified.branches.index(branch)

        def minimiser(arcs) -> float:  # the class's own optimum over the free intervals (Arm.optimal in a cell)
            return classified.implementation.optimal(pose, row, target, None, arcs)[0]

        free_report(report, chain, free, scene, body, args.deg, branch, analysis.branches[0].optimal, minimiser)
    if args.json:
        print_json(report)
        return 0
    _print_arm_angles(report, analysis, args.deg)
    if args.branch is None and not report["feasible"]:
        others = [label for label, arcs in report["branches"].items() if arcs]
        symbol, name = analysis.parameter.set_ascii, analysis.parameter.name
        print(f"branch +++ (the default) has no feasible {name}; {', '.join(others)} "
              f"{'has' if len(others) == 1 else 'have'} a {symbol}: --branch B shows one" if others else
              f"no branch has a feasible {name} at this pose")
    return 0


def _arm_angles_report(classified, analysis, deg: bool) -> dict[str, Any]:
    """The JSON of ``redkin arm-angles`` (angles in degrees where ``deg``): the fields the analysis holds."""
    parameter, shown = analysis.parameter, analysis.branches[0]

    def angle(value: float):
        return None if not np.isfinite(value) else angles_out(value, deg)

    def arcs(bounds: np.ndarray) -> list:
        return [[float(v) for v in angles_out(arc, deg)] for arc in bounds]

    def wraps(bounds: np.ndarray) -> list[bool]:
        return [bool(lo > hi) for lo, hi in bounds]

    report: dict[str, Any] = {
        "robot": classified.chain.name,
        "class": classified.kind,
        "parameter": parameter.name,
        "units": {"angles": f"{angle_unit(deg)} (every {parameter.noun} and joint value below)"},
        "arcs": ("[start, end] read counter-clockwise from start to end; the parallel *_wraps entry is true for an arc "
                 "through +-180 deg (+-pi rad), whose start is larger than its end" if parameter.wraps else
                 f"[start, end] intervals of {parameter.name}, increasing, within its domain"),
        "domain": [float(v) for v in angles_out(np.array(parameter.domain), deg)],
        "branch": shown.branch,
        "feasible": arcs(shown.arcs),
        "feasible_wraps": wraps(shown.arcs),
        "complete": analysis.complete,
        "branches": {label: arcs(bounds) for label, bounds in zip(classified.branches, analysis.sets)},
    }
    if analysis.samples is not None:
        report["samples"] = analysis.samples
    if analysis.remarks:
        report["remarks"] = list(analysis.remarks)
    if shown.fixed:
        report["fixed"] = {str(joint): angle(value) for joint, value in shown.fixed.items()}
    if shown.per_joint is not None:
        report["per_joint"] = {str(joint): arcs(bounds) for joint, bounds in shown.per_joint.items()}
        report["per_joint_wraps"] = {str(joint): wraps(bounds) for joint, bounds in shown.per_joint.items()}
    if shown.singular is not None:
        report["alignment"] = ("a *_nearest angle is the signed angle between the pair's axes' lines: 0 where they "
                               "are parallel or antiparallel")
        report["singular"] = {}
        for name, part in shown.singular.items():
            report["singular"][name] = [float(angles_out(value, deg)) for value in part.values]
            report["singular"][f"{name}_everywhere"] = part.everywhere
            report["singular"][f"{name}_nearest"] = None if part.nearest is None else {
                parameter.name: angle(part.nearest[0]), "angle": angle(part.nearest[1])}
    report["optimal"] = {name: {"unclamped": angle(unclamped), "feasible": angle(feasible)}
                         for name, (unclamped, feasible) in shown.optimal.items()}
    return report


def _print_arm_angles(report: dict[str, Any], analysis, deg: bool) -> None:
    """``redkin arm-angles`` in text: the report's fields, a line each."""
    parameter, unit = analysis.parameter, angle_unit(deg)
    symbol, name = parameter.set_ascii, parameter.name
    print(f"{report['robot']}, branch {report['branch']}; the redundancy parameter is {name}, angles in {unit}")
    for remark in analysis.remarks:
        print(remark)
    for joint, value in report.get("fixed", {}).items():
        print(f"joint {joint}: {fixed(value)} at every {name} (the pose fixes it)")
    for joint, arcs in report.get("per_joint", {}).items():
        print(f"{symbol}_{joint}: {_format_arcs(arcs, deg)}")
    cell = report.get("collision")
    if cell is not None:
        print(f"{symbol} (within the limits): {_format_arcs(report['limits_feasible'], deg)}")
        print(f"{symbol} (collision-free, {plural(len(cell['obstacles']), 'obstacle')} and "
              f"{plural(cell['self_pairs'], 'pair')} of the arm's own capsules at margin {cell['margin']:g} m): "
              f"{_format_arcs(report['feasible'], deg)}")
        undecided = ("next to a singular arm angle, or the clearance grazes the margin" if name == "psi" else
                     "next to a singular configuration or where the branch ends, or the clearance grazes the margin")
        slivers = []
        for stretch in report["blocked"]:
            start, end = stretch["arc"]
            width = end - start if end >= start else end - start + (360.0 if deg else 2.0 * np.pi)  # through +-pi
            if stretch["cause"] not in ("collision", "limit") and width <= cell["resolution"]:
                slivers.append(start)  # where a located end may lie, no wider than the resolution: said together
                continue
            what = (f"{stretch['link']} meets {stretch['obstacle']}" if stretch["cause"] == "collision" else
                    "no solution" if stretch["obstacle"] == "no solution" else
                    f"{stretch['obstacle']} out of range" if stretch["cause"] == "limit" else
                    f"undecided ({undecided})")
            print(f"  removed {_format_arcs([stretch['arc']], deg)}: {what}")
        if slivers:
            print(f"  removed {plural(len(slivers), 'undecided sliver')} of at most {cell['resolution']:g} {unit} at "
                  f"{', '.join(fixed(v) for v in slivers)} ({undecided})")
        for line in cell_note_lines(cell):
            print(f"  {line}")
        if not cell["complete"]:
            print("  (the work budget ran out: undecided stretches wider than the resolution remain; what is shown "
                  "free is free)")
    else:
        print(f"{symbol} (feasible): {_format_arcs(report['feasible'], deg)}")
    if not analysis.complete:
        print("  (certified arcs of the self-motion followed; it could not be followed whole within the work budget, "
              "near a stretched elbow or a straight wrist or shoulder, so the set may miss arcs)")
    print(f"{symbol} ({'collision-free' if cell is not None else 'feasible'}) of every branch:")
    for label, arcs in report["branches"].items():
        print(f"  branch {label}: {_format_arcs(arcs, deg)}")
    singular = report.get("singular")
    if singular is not None:
        print(f"singular shoulder: {_format_list(singular['shoulder'])}  wrist: {_format_list(singular['wrist'])}")
        for part in ("shoulder", "wrist"):
            if singular[f"{part}_everywhere"]:
                print(f"the {part} is singular at every {name} for this pose")
            nearest = singular[f"{part}_nearest"]
            if nearest is None:
                continue
            if abs(nearest["angle"]) <= angles_out(_ALIGNED, deg):
                print(f"nearest {part} alignment: on one line at {name} {fixed(nearest[name])}")
            else:
                print(f"nearest {part} alignment: {abs(nearest['angle']):.3g} {unit} from one line at {name} "
                      f"{fixed(nearest[name])}")
    for part, entry in report["optimal"].items():
        unclamped = "none (no solution on this branch)" if entry["unclamped"] is None else fixed(entry["unclamped"])
        clamped = "none (empty feasible set)" if entry["feasible"] is None else fixed(entry["feasible"])
        free = "" if "collision_free" not in entry else " -> collision-free " + (
            "none (empty free set)" if entry["collision_free"] is None else fixed(entry["collision_free"]))
        print(f"optimal {part}: {unclamped} -> feasible {clamped}{free}")


def _format_arcs(arcs: list, degrees: bool) -> str:
    """Arcs ``[start, end]`` as text; an arc through +-pi (``start > end``, counter-clockwise) says so, in the printed
    unit: ``[-61.589003, -99.990472] (through ±180)``."""
    if not arcs:
        return "empty"
    seam = f"{plus_minus()}{'180' if degrees else 'pi'}"
    return " U ".join(f"[{fixed(lo)}, {fixed(hi)}]" + (f" (through {seam})" if lo > hi else "") for lo, hi in arcs)


def _format_list(values: list) -> str:
    return "[" + ", ".join(fixed(v) for v in values) + "]"
