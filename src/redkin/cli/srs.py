"""``redkin ik`` and ``redkin arm-angles``: closed-form IK over the redundancy parameter -- the arm angle psi of
S-R-S and offset-elbow arms (paper 000), q7 of the Franka class (docs/franka.md)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

import numpy as np

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
    fixed,
    format_values,
    joint_vector,
    load_robot,
    out_of_reach,
    plural,
    plus_minus,
    print_json,
    reach_reason,
    read_poses,
    target_pose,
)
from redkin.cli.ik_numerical import add_numerical_arguments, run_numerical

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
    solve.add_argument("--poses", metavar="FILE.npy", help="solve every pose of an (N, 4, 4) array instead of "
                                                          "--position and --rotation or --quat")
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
    add_output_flags(solve)
    solve.set_defaults(handler=run_ik)

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
    add_output_flags(angles)
    angles.set_defaults(handler=_run_arm_angles)


def _arcs(arc_set, degrees: bool) -> list:
    """The arcs as ``[start, end]`` pairs, read counter-clockwise from start to end."""
    return [[float(v) for v in angles_out(arc, degrees)] for arc in arc_set.arcs]


def _wraps(arc_set) -> list[bool]:
    """Per arc of :func:`_arcs`: whether it passes through +-pi (then its start is larger than its end)."""
    return [bool(lo > hi) for lo, hi in arc_set.arcs]


def _closed_form_class(chain, args: argparse.Namespace) -> str:
    """``"psi"`` or ``"q7"``: the redundancy parameter of the chain's class
    (:func:`redkin.closed_form.redundancy_parameter`); a ValueError naming the right option where the command line
    gave the other one."""
    from redkin.closed_form import redundancy_parameter

    parameter = redundancy_parameter(chain, args.srs_tolerance)
    given = "q7" if getattr(args, "q7", None) is not None else "psi" if getattr(args, "psi", None) is not None else None
    if given is not None and given != parameter:
        right = "q7 (--q7)" if parameter == "q7" else "the arm angle (--psi)"
        raise ValueError(f"{chain.name}: its redundancy parameter is {right}, not {given}")
    return parameter


def _ik_poses(args: argparse.Namespace) -> tuple[np.ndarray, bool]:
    """The target of ``redkin ik``: ``--position`` and ``--rotation`` or ``--quat``, or the ``--poses`` file (then
    ``True``)."""
    oriented = args.rotation is not None or args.quat is not None
    if args.poses is not None:
        if args.position is not None or oriented:
            raise UsageError("give --poses or --position and --rotation, not both (--quat stands for --rotation)")
        return read_poses(args.poses), True
    if args.position is None or not oriented:
        raise UsageError("the target needs --position X Y Z and --rotation R11 ... R33 (or --poses FILE.npy); "
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
        return run_numerical(chain, poses, args, batch)
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

    parameter = _closed_form_class(chain, args)
    value = float(angles_in(args.psi if parameter == "psi" else args.q7, args.deg))
    q0 = None if args.q0 is None else joint_vector(chain, args.q0, args.deg, "--q0 values")
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
    others = [[0] * len(result.branches) for _ in found]
    if parameter == "psi" and (args.every_solution or q0 is not None or not batch):
        _add_every_solution(chain, poses.reshape(-1, 4, 4), value, result.branches, found, others, reach.out,
                            args.srs_tolerance, q0, args.every_solution)
    if q0 is not None:  # each solution's joint values nearest q0 modulo whole turns
        found = [[[(chain.nearest_in_range(one, near=q0), inside) for one, inside in row] for row in pose_rows]
                 for pose_rows in found]
    entries: list[dict[str, Any]] = [{
        "index": k,
        "solutions": [{"branch": str(label), "q": angles_out(one, args.deg), "within_limits": inside,
                       "others": others[k][b]}
                      for b, label in enumerate(result.branches) for one, inside in found[k][b]],
        "missing": [str(label) for b, label in enumerate(result.branches) if not found[k][b]],
        **reach_reason(reach, k),
    } for k in range(len(q))]
    code = 0 if all(entry["solutions"] for entry in entries) else 1
    unit = angle_unit(args.deg)
    if args.json:
        head = {"robot": chain.name, "parameter": parameter, "units": {parameter: unit, "q": unit, "reach": "m"},
                parameter: angles_out(value, args.deg), "branch_from": why}
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
            if s["others"]:
                note += (f"  ({plural(s['others'], 'other solution')} of {s['branch']} at this {parameter}: "
                         "--every-solution lists them)")
            print(f"{label}{s['branch']}  {format_values(s['q'])}  [{unit}]{note}")
    if why == "default" and not batch:
        inside = [str(label) for label, flag in zip(every.branches, every.within_limits.reshape(-1)) if flag]
        if entries[0]["solutions"] and not entries[0]["solutions"][0]["within_limits"] and inside:
            print(f"branch {branch} is the default: {', '.join(inside)} {'is' if len(inside) == 1 else 'are'} within "
                  "the limits here (--branch B picks one, --all lists all eight, --q0 Q takes its branch)")
    return code


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


def _add_every_solution(chain, poses: np.ndarray, psi: float, branches: tuple,
                        found: list[list[list[tuple[np.ndarray, bool]]]], others: list[list[int]],
                        out: np.ndarray, tolerance: float | None, q0: np.ndarray | None, every: bool) -> None:
    """On a nearly S-R-S arm, every solution of each branch ``b`` at ``psi`` for pose ``k``
    (:func:`redkin.srs.branch_solutions` on the pose's certified self-motion, the closed form's first, each joint
    shifted by whole turns into its range where it can be, nearest ``q0`` where given): all of them into
    ``found[k][b]`` where ``every``, else the one nearest ``q0`` (without ``q0`` the closed form's), and how many
    others there are into ``others[k][b]``.  Nothing on an exact arm, which has one per branch, nor for a pose
    proven out of reach (``out``)."""
    from redkin.arms.classify import NEARLY_SRS, arm_angle_class
    from redkin.srs import branch_solutions, nearly_srs, self_motions

    if arm_angle_class(chain, tolerance).kind != NEARLY_SRS:
        return
    arm = nearly_srs(chain) if tolerance is None else nearly_srs(chain, tolerance)
    for k, (pose, row) in enumerate(zip(poses, found)):
        if out[k]:
            continue
        curves = self_motions(arm, pose)
        for b, label in enumerate(branches):
            solutions = branch_solutions(arm, pose, psi, label, curves)
            solutions = chain.nearest_in_range(solutions, near=None if q0 is None else np.broadcast_to(
                q0, solutions.shape))
            listed = [(q, bool(chain.within_limits(q, tolerance=1e-9, wrap=True))) for q in solutions]
            if not listed:
                continue
            others[k][b] = 0 if every else len(listed) - 1
            if every:
                row[b] = listed
            else:
                nearest = 0 if q0 is None else int(np.argmin(np.linalg.norm(solutions - q0, axis=-1)))
                row[b] = [listed[nearest]]


def _run_arm_angles(args: argparse.Namespace) -> int:
    """``redkin arm-angles``: the class's renderer; without ``--branch`` it shows ``+++`` and, where that set is
    empty, names the branches that have one (:func:`_name_feasible_branches`)."""
    from redkin.arms.classify import NEARLY_SRS, arm_angle_class

    chain = load_robot(args)
    args.default_branch = args.branch is None
    if args.default_branch:
        args.branch = "+++"
    if _closed_form_class(chain, args) == "q7":
        return _run_franka_arm_angles(chain, args)
    if arm_angle_class(chain, args.srs_tolerance).kind == NEARLY_SRS:
        return _run_nearly_arm_angles(chain, args)
    return _run_exact_arm_angles(chain, args)


def _name_feasible_branches(args: argparse.Namespace, shown_empty: bool, feasible: Callable[[], list[str]],
                            parameter: str) -> None:
    """Where the default branch ``+++`` (no ``--branch``) has no feasible set, one line naming the branches that
    ``feasible()`` says have one (each renderer from the sets it computed: the nearly S-R-S arm's from the same
    self-motion)."""
    if not (args.default_branch and shown_empty):
        return
    others = feasible()
    symbol = "Psi" if parameter == "psi" else "Q7"
    if others:
        print(f"branch +++ (the default) has no feasible {parameter}; {', '.join(others)} "
              f"{'has' if len(others) == 1 else 'have'} a {symbol}: --branch B shows one")
    else:
        print(f"no branch has a feasible {parameter} at this pose")


def _run_exact_arm_angles(chain, args: argparse.Namespace) -> int:
    """``redkin arm-angles`` on an S-R-S or offset-elbow arm: the branch's per-joint, feasible, singular and optimal
    arm angles in closed form [000 eqs. 20-40]."""
    from redkin.srs import (
        BRANCHES,
        feasible_arm_angles,
        optimal_arm_angles,
        parse_branch,
        singular_arm_angles,
        srs_geometry,
    )
    if args.weights is None:
        args.weights = (0.5, 0.5)
    geometry = srs_geometry(chain)
    pose = target_pose(args)
    branch = parse_branch(args.branch)
    target = None if args.target is None else joint_vector(chain, args.target, args.deg, "--target values")
    feasible = feasible_arm_angles(geometry, pose, branch)
    singular = singular_arm_angles(geometry, pose, branch)
    optimal = optimal_arm_angles(geometry, pose, branch, target=target, weights=args.weights,
                                 feasible=feasible.feasible)
    deg = args.deg

    def pair(angle):
        return {"unclamped": angles_out(angle.unclamped, deg), "feasible": angles_out(angle.feasible, deg)}

    result = {
        "robot": chain.name,
        "units": {"angles": f"{angle_unit(deg)} (every arm angle and joint value below)"},
        "arcs": "[start, end] read counter-clockwise from start to end; the parallel *_wraps entry is true for an arc "
                "through +-180 deg (+-pi rad), whose start is larger than its end",
        "branch": str(branch),
        "elbow": angles_out(geometry.q_of_theta(np.r_[np.zeros(3), feasible.theta4, np.zeros(3)])[3], deg),
        "per_joint": {str(j): _arcs(s, deg) for j, s in feasible.per_joint.items()},
        "per_joint_wraps": {str(j): _wraps(s) for j, s in feasible.per_joint.items()},
        "feasible": _arcs(feasible.feasible, deg),
        "feasible_wraps": _wraps(feasible.feasible),
        "singular": {
            "shoulder": [float(angles_out(a, deg)) for a in singular.shoulder],
            "wrist": [float(angles_out(a, deg)) for a in singular.wrist],
            "shoulder_everywhere": singular.shoulder_everywhere,
            "wrist_everywhere": singular.wrist_everywhere,
        },
        "optimal": {"shoulder": pair(optimal.shoulder), "wrist": pair(optimal.wrist), "overall": pair(optimal.overall)},
    }
    if args.json:
        print_json(result)
        return 0
    unit = "deg" if deg else "rad"
    print(f"{chain.name}, branch {branch}; angles in {unit}")
    print(f"elbow (joint 4): {fixed(result['elbow'])}")
    for joint, arcs in result["per_joint"].items():
        print(f"Psi_{joint}: {_format_arcs(arcs, deg)}")
    print(f"Psi (feasible): {_format_arcs(result['feasible'], deg)}")
    singular = result["singular"]
    print(f"singular shoulder: {_format_list(singular['shoulder'])}  wrist: {_format_list(singular['wrist'])}")
    for name in ("shoulder", "wrist", "overall"):
        entry = result["optimal"][name]
        clamped = "none (empty feasible set)" if entry["feasible"] is None else fixed(entry["feasible"])
        print(f"optimal {name}: {fixed(entry['unclamped'])} -> feasible {clamped}")
    _name_feasible_branches(args, feasible.feasible.is_empty, lambda: [
        str(b) for b in BRANCHES if not feasible_arm_angles(geometry, pose, b).feasible.is_empty], "psi")
    return 0


def _format_arcs(arcs: list, degrees: bool) -> str:
    """Arcs ``[start, end]`` (counter-clockwise) as text; an arc through +-pi says so, in the printed unit:
    ``[-61.589003, -99.990472] (through ±180)``."""
    if not arcs:
        return "empty"
    seam = f"{plus_minus()}{'180' if degrees else 'pi'}"
    return " U ".join(f"[{fixed(lo)}, {fixed(hi)}]" + (f" (through {seam})" if lo > hi else "") for lo, hi in arcs)


def _format_list(values: list) -> str:
    return "[" + ", ".join(fixed(v) for v in values) + "]"


def _run_nearly_arm_angles(chain, args: argparse.Namespace) -> int:
    """``redkin arm-angles`` on a nearly S-R-S arm: the branch's feasible, singular and optimal arm angles on the real
    arm (:func:`redkin.srs.feasible_arm_angles_nearly`, :func:`redkin.srs.singular_arm_angles_nearly`,
    :func:`redkin.srs.optimal_arm_angles_nearly`) and what its neighbour drops; no per-joint sets (not computed on
    such arms)."""
    from redkin.srs import (
        BRANCHES,
        NearlyFeasible,
        feasible_arm_angles_nearly,
        nearly_srs,
        optimal_arm_angles_nearly,
        parse_branch,
        singular_arm_angles_nearly,
    )

    arm = nearly_srs(chain) if args.srs_tolerance is None else nearly_srs(chain, args.srs_tolerance)
    pose = target_pose(args)
    branch = parse_branch(args.branch)
    target = None if args.target is None else joint_vector(chain, args.target, args.deg, "--target values")
    result = feasible_arm_angles_nearly(arm, pose, branch)
    singular = singular_arm_angles_nearly(arm, pose, branch)
    optimal = optimal_arm_angles_nearly(arm, pose, branch, target=target,
                                        weights=(0.5, 0.5) if args.weights is None else args.weights,
                                        feasible=result.feasible, curves=result.curves)
    deg = args.deg

    def angle(value):
        return None if value is None or not np.isfinite(value) else angles_out(value, deg)

    def nearest(alignment):
        return None if alignment is None else {"psi": angle(alignment.psi), "angle": angle(alignment.angle)}

    report = {
        "robot": chain.name,
        "class": "nearly S-R-S",
        "neighbour": arm.describe(),
        "units": {"angles": f"{angle_unit(deg)} (every arm angle and angle below)"},
        "arcs": "[start, end] read counter-clockwise from start to end; the parallel *_wraps entry is true for an arc "
                "through +-180 deg (+-pi rad), whose start is larger than its end",
        "alignment": "a *_nearest angle is the signed angle between the pair's axes' lines: 0 where they are parallel "
                     "or antiparallel",
        "branch": str(result.branch),
        "feasible": _arcs(result.feasible, deg),
        "feasible_wraps": _wraps(result.feasible),
        "complete": result.complete,
        "samples": result.samples,
        "singular": {
            "shoulder": [float(angles_out(a, deg)) for a in singular.shoulder],
            "wrist": [float(angles_out(a, deg)) for a in singular.wrist],
            "shoulder_nearest": nearest(singular.shoulder_nearest),
            "wrist_nearest": nearest(singular.wrist_nearest),
        },
        "optimal": {name: {"unclamped": angle(part.unclamped), "feasible": angle(part.feasible)}
                    for name, part in (("shoulder", optimal.shoulder), ("wrist", optimal.wrist),
                                       ("overall", optimal.overall))},
    }
    if args.json:
        print_json(report)
        return 0
    print(f"{chain.name}, branch {result.branch}; angles in {angle_unit(deg)}")
    print(f"nearly S-R-S: {arm.describe()}")
    print(f"Psi (feasible, on the real arm): {_format_arcs(report['feasible'], deg)}")
    if not result.complete:
        print("  (certified arcs of the self-motion followed; it could not be followed whole within the work budget, "
              "near a stretched elbow or a straight wrist or shoulder, so the set may miss arcs)")
    singular_report = report["singular"]
    print(f"singular shoulder: {_format_list(singular_report['shoulder'])}  wrist: "
          f"{_format_list(singular_report['wrist'])}  (axes 1 and 3, 5 and 7 parallel or antiparallel)")
    for part, axes in (("shoulder", "1 and 3"), ("wrist", "5 and 7")):
        entry = singular_report[f"{part}_nearest"]
        if entry is None:
            continue
        if abs(entry["angle"]) <= angles_out(_ALIGNED, deg):
            print(f"nearest {part} alignment: axes {axes} on one line at psi {fixed(entry['psi'])}")
        else:
            print(f"nearest {part} alignment: axes {axes} are {abs(entry['angle']):.3g} {angle_unit(deg)} from one "
                  f"line at psi {fixed(entry['psi'])}")
    for name in ("shoulder", "wrist", "overall"):
        entry = report["optimal"][name]
        unclamped = "none (no solution on this branch)" if entry["unclamped"] is None else fixed(entry["unclamped"])
        clamped = "none (empty feasible set)" if entry["feasible"] is None else fixed(entry["feasible"])
        print(f"optimal {name}: {unclamped} -> feasible {clamped}")
    _name_feasible_branches(args, result.feasible.is_empty, lambda: [  # the same self-motion, every branch
        str(b) for b in BRANCHES if not NearlyFeasible(arm, pose, b, result.curves, result.complete)
        .feasible.is_empty], "psi")
    return 0


def _run_franka_arm_angles(chain, args: argparse.Namespace) -> int:
    """``redkin arm-angles`` on a Franka-class arm: the feasible q7 arcs of the branch (and of every branch), and the
    limit-avoiding q7."""
    from redkin.franka import BRANCHES, feasible_q7, optimal_q7
    from redkin.srs import parse_branch

    if args.weights is not None:
        raise ValueError(f"--weights weighs the shoulder against the wrist in the optimal arm angle of S-R-S arms; "
                         f"{chain.name} is of the Franka class (parameter q7): leave it out")
    pose = target_pose(args)
    branch = parse_branch(args.branch)
    target = None if args.target is None else joint_vector(chain, args.target, args.deg, "--target values")
    sets = feasible_q7(chain, pose)
    index = BRANCHES.index(branch)
    optimal = optimal_q7(chain, pose, branch, target=target, feasible=sets)
    deg = args.deg

    def arcs(pieces) -> list:
        return [[float(v) for v in angles_out(arc, deg)] for arc in pieces]

    result = {
        "robot": chain.name,
        "parameter": "q7",
        "units": {"angles": f"{angle_unit(deg)} (every q7 below)"},
        "arcs": "[start, end] intervals of q7, increasing, within joint 7's range (domain)",
        "branch": str(branch),
        "domain": [float(v) for v in angles_out(sets.domain, deg)],
        "feasible": arcs(sets.arcs[index]),
        "branches": {str(label): arcs(sets.arcs[k]) for k, label in enumerate(BRANCHES)},
        "optimal": {"unclamped": angles_out(optimal.unclamped, deg), "feasible": angles_out(optimal.feasible, deg)},
    }
    if args.json:
        print_json(result)
        return 0
    unit = "deg" if deg else "rad"
    print(f"{chain.name}, branch {branch}; the redundancy parameter is q7, in {unit}")
    print(f"q7 (feasible): {_format_q7_arcs(result['feasible'])}")
    for label, pieces in result["branches"].items():
        print(f"  branch {label}: {_format_q7_arcs(pieces)}")
    entry = result["optimal"]
    unclamped = "none (no solution at any q7)" if entry["unclamped"] is None else fixed(entry["unclamped"])
    clamped = "none (empty feasible set)" if entry["feasible"] is None else fixed(entry["feasible"])
    print(f"optimal q7: {unclamped} -> feasible {clamped}")
    _name_feasible_branches(args, not result["feasible"], lambda: [
        label for label, pieces in result["branches"].items() if pieces], "q7")
    return 0


def _format_q7_arcs(arcs: list) -> str:
    return " U ".join(f"[{fixed(lo)}, {fixed(hi)}]" for lo, hi in arcs) if arcs else "empty"
