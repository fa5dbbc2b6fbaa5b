"""``redkin explore``: the interactive explorer of an arm's redundancy parameter at a pose (the arm angle of S-R-S,
offset-elbow and nearly S-R-S arms, q7 of Franka-class arms), as one offline HTML page."""

from __future__ import annotations

import argparse

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
    parser.add_argument("--out", required=True, metavar="FILE.html", help="the page to write")
    add_force_flag(parser)
    add_srs_tolerance_argument(parser)
    add_output_flags(parser)
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from redkin.explore import explorer_data, explorer_html

    out = output_file(args.out, "--out", {".html", ".htm"}, args.force)
    chain = load_robot(args)
    q = None if args.q is None else joint_vector(chain, args.q, args.deg, "--q values")
    if args.position is not None or args.rotation is not None or args.quat is not None:
        pose = target_pose(args)
    elif q is not None:
        pose = chain.fk(q)
    else:
        raise UsageError("give the pose (--position and --rotation or --quat), or a configuration --q to explore "
                         "at its pose")
    data = explorer_data(chain, pose, args.branch, srs_tolerance=args.srs_tolerance, q=q)
    out.write_text(explorer_html(data, degrees=args.deg), encoding="utf-8")
    parameter = data.parameter
    shown = data.branches[data.initial]
    opens = float(angles_out(shown.values[shown.start], args.deg))
    feasible = {b.branch: [angles_out(arc, args.deg).tolist() for arc in b.arcs] for b in data.branches}
    if args.json:
        wraps = {b.branch: [bool(lo > hi) for lo, hi in b.arcs] for b in data.branches}
        print_json({"robot": chain.name, "out": str(out), "parameter": parameter.name,
                    "domain": angles_out(parameter.domain, args.deg).tolist(),
                    "units": {"feasible": angle_unit(args.deg), "domain": angle_unit(args.deg)},
                    "grid_points": {b.branch: len(b.values) for b in data.branches}, "feasible": feasible,
                    "feasible_wraps": wraps, "opens": {"branch": shown.branch, parameter.name: opens,
                                                       "why": data.opening}})
    else:
        reachable = sum(bool(arcs) for arcs in feasible.values())
        print(f"wrote {out}: {chain.name}, feasible {parameter.plural} on {reachable} of {len(feasible)} branches; "
              "open it in a browser")
        print(f"{data.opening} ({parameter.name} = {opens:.6f} {angle_unit(args.deg)})")
    return 0
