"""``redkin ik`` and ``redkin arm-angles``: arm-angle IK of S-R-S arms (paper 000)."""

from __future__ import annotations

import argparse

import numpy as np

from redkin.cli.common import (
    BRANCH_HELP,
    add_output_flags,
    add_robot_argument,
    add_target_arguments,
    angle_unit,
    angles_in,
    angles_out,
    fixed,
    joint_vector,
    load_robot,
    plus_minus,
    print_json,
    target_pose,
)


def register(subparsers: argparse._SubParsersAction) -> None:
    solve = subparsers.add_parser(
        "ik", help="joint values of an S-R-S or offset-elbow arm for a pose and an arm angle (paper 000)"
    )
    add_robot_argument(solve)
    add_target_arguments(solve)
    solve.add_argument("--psi", type=float, required=True, help="arm angle (radians, or degrees with --deg)")
    group = solve.add_mutually_exclusive_group()
    group.add_argument("--branch", default="+++", help=BRANCH_HELP)
    group.add_argument("--all", action="store_true", help="all eight branches")
    add_output_flags(solve)
    solve.set_defaults(handler=run_ik)

    angles = subparsers.add_parser(
        "arm-angles",
        help="feasible, singular and optimal arm angles of an S-R-S or offset-elbow arm for a pose (paper 000)",
    )
    add_robot_argument(angles)
    add_target_arguments(angles)
    angles.add_argument("--branch", default="+++", help=BRANCH_HELP)
    angles.add_argument("--target", nargs=7, type=float, metavar="Q",
                        help="joint values the optimal arm angles stay nearest to (radians, or degrees with --deg; "
                             "default: the middle of each joint's range)")
    angles.add_argument("--weights", nargs=2, type=float, metavar=("RS", "RW"), default=(0.5, 0.5),
                        help="how much the shoulder joints (RS) and the wrist joints (RW) count in the overall "
                             "optimal arm angle, two numbers >= 0, not both 0 (default 0.5 0.5; [000 eq. 40])")
    add_output_flags(angles)
    angles.set_defaults(handler=_run_arm_angles)


def _arcs(arc_set, degrees: bool) -> list:
    """The arcs as ``[start, end]`` pairs, read counter-clockwise from start to end."""
    return [[float(v) for v in angles_out(arc, degrees)] for arc in arc_set.arcs]


def _wraps(arc_set) -> list[bool]:
    """Per arc of :func:`_arcs`: whether it passes through +-pi (then its start is larger than its end)."""
    return [bool(lo > hi) for lo, hi in arc_set.arcs]


def run_ik(args: argparse.Namespace) -> int:
    from redkin.srs import BRANCHES, ik, parse_branch, srs_geometry

    chain = load_robot(args)
    geometry = srs_geometry(chain)
    pose = target_pose(args)
    psi = float(angles_in(args.psi, args.deg))
    branches = list(BRANCHES) if args.all else [parse_branch(args.branch)]
    solutions = []
    for branch in branches:
        q = ik(geometry, pose, psi, branch)
        solutions.append({
            "branch": str(branch),
            "q": angles_out(q, args.deg),
            "within_limits": bool(chain.within_limits(q, tolerance=1e-9, wrap=True)),
        })
    if args.json:
        print_json({"robot": chain.name, "units": {"psi": angle_unit(args.deg), "q": angle_unit(args.deg)},
                    "psi": angles_out(psi, args.deg), "solutions": solutions})
    else:
        unit = "deg" if args.deg else "rad"
        for s in solutions:
            values = "  ".join(fixed(v, 6, " ") for v in s["q"])
            note = "" if s["within_limits"] else "  (outside limits)"
            print(f"{s['branch']}  {values}  [{unit}]{note}")
    return 0


def _run_arm_angles(args: argparse.Namespace) -> int:
    from redkin.srs import feasible_arm_angles, optimal_arm_angles, parse_branch, singular_arm_angles, srs_geometry

    chain = load_robot(args)
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
