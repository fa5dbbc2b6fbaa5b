"""``redkin robots`` (the models, or one chain with ``--show``), ``redkin fk`` and ``redkin jacobian``."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

import numpy as np

from redkin.cli.cell import body_links
from redkin.cli.common import (
    add_base_tip_arguments,
    add_output_flags,
    add_robot_argument,
    add_srs_tolerance_argument,
    add_xacro_arguments,
    angle_unit,
    angles_out,
    format_exact,
    format_matrix,
    format_values,
    joint_vector,
    load_chain,
    load_robot,
    plural,
    print_json,
    xacro_options,
)
from redkin.errors import RedkinError

if TYPE_CHECKING:  # the parsers are built without the chain, the models or the kernels; each handler imports its own
    from redkin.chain import SerialChain


def register(subparsers: argparse._SubParsersAction) -> None:
    robots = subparsers.add_parser("robots",
                                   help="list the named robot models and their arm-angle class, or --show one")
    robots.add_argument("--show", metavar="ROBOT",
                        help="print one chain (a model, robot file, URDF or MJCF file): joints, limits, frames, "
                             "arm-angle class")
    add_base_tip_arguments(robots, "with --show")
    add_xacro_arguments(robots)
    add_srs_tolerance_argument(robots)
    add_output_flags(robots, degrees=True)
    robots.set_defaults(handler=_run_robots, in_python=True)

    fk = subparsers.add_parser(
        "fk", help="end pose of a robot at joint values: the 4x4 pose rounded for reading, then two lines to paste "
                   "into ik, arm-angles or explore, every number exact: --position and --rotation (row by row), "
                   "--position and --quat (unit quaternion w x y z, w >= 0)"
    )
    add_robot_argument(fk)
    fk.add_argument("q", nargs="+", type=float, metavar="Q", help="joint values (radians, or degrees with --deg)")
    add_output_flags(fk)
    fk.set_defaults(handler=_run_fk, in_python=True)

    jac = subparsers.add_parser("jacobian", help="geometric Jacobian (6 x n, base frame, linear rows first)")
    add_robot_argument(jac)
    jac.add_argument("q", nargs="+", type=float, metavar="Q", help="joint values (radians, or degrees with --deg)")
    jac.add_argument("--manipulability", action="store_true", help="also print sqrt(det(J J^T))")
    add_output_flags(jac)
    jac.set_defaults(handler=_run_jacobian, in_python=True)


def _run_robots(args: argparse.Namespace) -> int:
    from redkin.arms.classify import arm_angle_class
    from redkin.models import MODELS

    if args.show is not None:
        return _show_robot(load_chain(args.show, args.base, args.tip, **xacro_options(args)), args)
    if args.base is not None or args.tip is not None or args.xacro_args or args.package_paths:
        raise RedkinError("--base and --tip go with --show ROBOT, as do --xacro-arg and --package-path")
    entries: list[dict[str, Any]] = []
    for name, factory in MODELS.items():
        chain = factory()
        kind, reason = arm_angle_class(chain, args.srs_tolerance)
        entries.append({
            "name": name,
            "joints": chain.n,
            "convention": chain.convention,
            "class": kind,
            "class_reason": reason,
            "source": chain.source,
            "lower": _finite(angles_out(chain.lower, args.deg)),
            "upper": _finite(angles_out(chain.upper, args.deg)),
        })
    from redkin import examples

    files = examples.names()
    if args.json:
        print_json({"units": {"lower": angle_unit(args.deg), "upper": angle_unit(args.deg)}, "robots": entries,
                    "example_files": files})
    else:
        width = max(len(e["name"]) for e in entries)
        for e in entries:
            print(f"{e['name']:<{width}}  {plural(e['joints'], 'joint')}  {e['class']:<19}  {e['source']}")
        print(f"example files, read from any folder as NAME or examples/NAME: {', '.join(files)}")
    return 0


def _show_robot(chain: SerialChain, args: argparse.Namespace) -> int:
    """``redkin robots --show ROBOT``: joint names, limits, joint frames at q = 0, base, tool and class."""
    from redkin.arms.classify import arm_angle_class
    from redkin.collision import builtin_models

    kind, reason = arm_angle_class(chain, args.srs_tolerance)
    links = {name: place.frame for name, place in body_links(args, args.show, chain).items()}
    builtin = args.show.lower() in builtin_models()
    directions, points = chain.joint_axes(np.zeros(chain.n))
    directions = directions * chain.sign[:, None]  # the sense in which q turns
    lower, upper = angles_out(chain.lower, args.deg), angles_out(chain.upper, args.deg)
    if args.json:
        print_json({
            "name": chain.name, "source": chain.source, "convention": chain.convention, "class": kind,
            "class_reason": reason,
            "units": {"lower": angle_unit(args.deg), "upper": angle_unit(args.deg), "point": "m", "base": "m",
                      "tool": "m"},
            "joints": [{"name": name, "lower": low, "upper": high, "point": point, "axis": axis, **motion}
                       for name, low, high, point, axis, motion in zip(chain.joint_names, _finite(lower),
                                                                        _finite(upper), points, directions,
                                                                        _motion_limits(chain, args.deg))],
            "base": chain.base, "tool": chain.tool, "body_links": links, "builtin_body": builtin,
        })
        return 0
    unit = angle_unit(args.deg)
    print(f"{chain.name}: {plural(chain.n, 'joint')} ({chain.convention}), {chain.source}")
    print(f"class: {kind} ({reason})")
    print(f"joints at q = 0 (point on the axis in m, axis turning with +q, limits in {unit}):")
    width = max(len(name) for name in chain.joint_names)
    for k, name in enumerate(chain.joint_names):
        limits = f"[{lower[k]:.6g}, {upper[k]:.6g}]" if chain.limited[k] else "unlimited"
        point = format_values(points[k], 4)
        axis = format_values(directions[k], 4)
        print(f"  {k + 1}  {name:<{width}}  point {point}  axis {axis}  {limits}")
    known = [key for key in chain.motion_limits if np.isfinite(chain.motion_limits[key]).any()]
    if known:
        print(f"limits of motion ({unit}/s, {unit}/s^2, {unit}/s^3; - where unknown):")
        for k, name in enumerate(chain.joint_names):
            values = _motion_limits(chain, args.deg)[k]
            print(f"  {k + 1}  {name:<{width}}  " + "  ".join(
                f"{key} {'-' if values[key] is None else f'{values[key]:.6g}'}" for key in known))
    else:
        print("limits of motion: none known (a limits file gives them: redkin path --limits)")
    by_frame: dict[int, list[str]] = {}
    for name, frame in links.items():
        by_frame.setdefault(frame, []).append(name)
    print("links a body file names (--body), by the chain frame they move with (frame k turns with joint k):")
    for frame in sorted(by_frame):
        print(f"  frame {frame}: {', '.join(by_frame[frame])}")
    if builtin:
        print("built-in body: capsules fitted to the maker's collision meshes, used by --scene without --body "
              "(docs/collisions.md, 'Built-in bodies of the named models')")
    print("base:")
    print(format_matrix(chain.base))
    print("tool:")
    print(format_matrix(chain.tool))
    return 0


def _motion_limits(chain: SerialChain, degrees: bool) -> list[dict]:
    """Per joint, its velocity, acceleration and jerk limits in the command's angle unit (``None`` where
    unknown)."""
    limits = {key: _finite(angles_out(values, degrees)) for key, values in chain.motion_limits.items()}
    return [{key: limits[key][k] for key in limits} for k in range(chain.n)]


def _run_fk(args: argparse.Namespace) -> int:
    from redkin.so3 import matrix_to_quaternion

    chain = load_robot(args)
    q = joint_vector(chain, args.q, args.deg)
    pose = chain.fk(q)
    within = bool(chain.within_limits(q))
    quaternion = matrix_to_quaternion(pose[:3, :3])
    if args.json:
        print_json({
            "robot": chain.name,
            "units": {"q": angle_unit(args.deg), "position": "m", "pose": "m (translation column)",
                      "quaternion": "w x y z (scalar first), norm 1"},
            "q": angles_out(q, args.deg),
            "position": pose[:3, 3],
            "rotation": pose[:3, :3],
            "quaternion": quaternion,
            "pose": pose,
            "within_limits": within,
        })
    else:
        position = f"--position {format_exact(pose[:3, 3])}"
        if not within:
            print("note: these joint values are outside the robot's limits")
        print("pose (rounded to 6 decimals; the two lines below are exact, the quaternion is w x y z):")
        print(format_matrix(pose))
        print(f"{position} --rotation {format_exact(pose[:3, :3])}")
        print(f"{position} --quat {format_exact(quaternion)}")
    return 0


def _run_jacobian(args: argparse.Namespace) -> int:
    chain = load_robot(args)
    q = joint_vector(chain, args.q, args.deg)
    jac = chain.jacobian(q)
    manip = float(chain.manipulability(q)) if args.manipulability else None
    if args.json:
        units = {"q": angle_unit(args.deg),
                 "jacobian": "per rad of joint motion: m/rad (linear rows), rad/rad (angular rows)",
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
