"""``redkin robots``, ``redkin fk`` and ``redkin jacobian``."""

from __future__ import annotations

import argparse

import numpy as np

from redkin.cli.common import (
    add_output_flags,
    add_robot_argument,
    angle_unit,
    angles_out,
    format_matrix,
    joint_vector,
    load_robot,
    print_json,
)
from redkin.models import MODELS


def register(subparsers: argparse._SubParsersAction) -> None:
    robots = subparsers.add_parser("robots", help="list the named robot models")
    add_output_flags(robots, degrees=True)
    robots.set_defaults(handler=run_robots)

    fk = subparsers.add_parser("fk", help="end pose of a robot at joint values")
    add_robot_argument(fk)
    fk.add_argument("q", nargs="+", type=float, metavar="Q", help="joint values (radians, or degrees with --deg)")
    add_output_flags(fk)
    fk.set_defaults(handler=run_fk)

    jac = subparsers.add_parser("jacobian", help="geometric Jacobian (6 x n, base frame, linear rows first)")
    add_robot_argument(jac)
    jac.add_argument("q", nargs="+", type=float, metavar="Q", help="joint values (radians, or degrees with --deg)")
    jac.add_argument("--manipulability", action="store_true", help="also print sqrt(det(J J^T))")
    add_output_flags(jac)
    jac.set_defaults(handler=run_jacobian)


def run_robots(args: argparse.Namespace) -> int:
    entries = []
    for name, factory in MODELS.items():
        chain = factory()
        entries.append({
            "name": name,
            "joints": chain.n,
            "convention": chain.convention,
            "source": chain.source,
            "lower": angles_out(chain.lower, args.deg),
            "upper": angles_out(chain.upper, args.deg),
        })
    if args.json:
        print_json({"units": {"lower": angle_unit(args.deg), "upper": angle_unit(args.deg)},
                    "robots": [{**e, "lower": _finite(e["lower"]), "upper": _finite(e["upper"])} for e in entries]})
    else:
        for e in entries:
            print(f"{e['name']:<16} {e['joints']} joints  {e['convention']:<4} {e['source']}")
    return 0


def run_fk(args: argparse.Namespace) -> int:
    chain = load_robot(args)
    q = joint_vector(chain, args.q, args.deg)
    pose = chain.fk(q)
    if args.json:
        print_json({
            "robot": chain.name,
            "units": {"q": angle_unit(args.deg), "position": "m", "pose": "m (translation column)"},
            "q": angles_out(q, args.deg),
            "position": pose[:3, 3],
            "rotation": pose[:3, :3],
            "pose": pose,
            "within_limits": bool(chain.within_limits(q)),
        })
    else:
        print(format_matrix(pose))
        if not chain.within_limits(q):
            print("note: these joint values are outside the robot's limits")
    return 0


def run_jacobian(args: argparse.Namespace) -> int:
    chain = load_robot(args)
    q = joint_vector(chain, args.q, args.deg)
    jac = chain.jacobian(q)
    manip = float(chain.manipulability(q)) if args.manipulability else None
    if args.json:
        units = {"q": angle_unit(args.deg), "jacobian": "per rad of joint motion: m/rad (linear rows), rad/rad (angular rows)",
                 "manipulability": "of J as printed"}
        out = {"robot": chain.name, "units": units, "q": angles_out(q, args.deg), "jacobian": jac}
        if manip is not None:
            out["manipulability"] = manip
        print_json(out)
    else:
        print(format_matrix(jac))
        if manip is not None:
            print(f"manipulability {manip:.6g}")
    return 0


def _finite(values: np.ndarray) -> list:
    return [float(v) if np.isfinite(v) else None for v in values]
