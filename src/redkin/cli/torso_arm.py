"""``redkin torso-arm ik`` and ``redkin torso-arm map`` (thesis 001 humanoid arm)."""

from __future__ import annotations

import argparse
import sys

import numpy as np
from numpy.typing import ArrayLike

from redkin._constants import TORSO_ARM_MAX_RESOLUTION
from redkin._validation import MAX_LENGTH, check_magnitude
from redkin.circle import wrap_angle
from redkin.cli.common import (
    IMAGE_SUFFIXES,
    Progress,
    UsageError,
    add_force_flag,
    add_output_flags,
    add_rotation_arguments,
    angle_unit,
    angles_in,
    angles_out,
    checked_position,
    fixed,
    given_rotation,
    output_file,
    print_json,
)


def register(subparsers: argparse._SubParsersAction) -> None:
    top = subparsers.add_parser("torso-arm", help="8-DOF humanoid arm of thesis 001: IK and manipulability maps")
    sub = top.add_subparsers(dest="torso_command", metavar="ACTION")

    solve = sub.add_parser("ik",
                           help="every joint solution for a wrist/hand pose at shoulder angle psi, elbow angle phi")
    solve.add_argument("--position", nargs=3, type=float, required=True, metavar=("X", "Y", "Z"),
                       help="wrist position, or the hand's with --tool (metres, torso frame)")
    orient = solve.add_mutually_exclusive_group()
    orient.add_argument("--angles", nargs=3, type=float, metavar=("A", "B", "G"),
                        help="hand orientation as X-Y-Z fixed angles alpha, beta, gamma (radians, or degrees with "
                             "--deg; [001 eq. 4.4]); omit it, --rotation and --quat for the wrist position only")
    add_rotation_arguments(orient, "hand")
    solve.add_argument("--shoulder", type=float, required=True, metavar="PSI",
                       help="shoulder angle psi: turn of the neck-shoulder-wrist plane (radians, or degrees with "
                            "--deg)")
    solve.add_argument("--elbow", type=float, required=True, metavar="PHI",
                       help="elbow angle phi: turn of the shoulder-elbow-wrist plane from --reference (radians, or "
                            "degrees with --deg)")
    solve.add_argument("--reference", default="theta4", help="phi = 0: 'theta4' (thesis), 'vector' (+y) or 'X,Y,Z'")
    solve.add_argument("--arm", choices=("right", "left"), default="right",
                       help="which arm of the humanoid to solve: right (default) or left (its mirror image)")
    solve.add_argument("--tool", type=float, default=0.0, metavar="L4",
                       help="tool length L4 in metres: --position is then the hand's (default 0: the wrist)")
    add_output_flags(solve)
    solve.set_defaults(handler=run_ik)

    chart = sub.add_parser("map", help="manipulability map of the wrist position over a plane")
    chart.add_argument("--plane", required=True, help="e.g. z=0.3 (metres)")
    chart.add_argument("--extent", nargs=4, type=float, metavar=("U0", "U1", "V0", "V1"),
                       help="range of the two in-plane axes (x-y-z order), metres (default: the arm's reach there)")
    chart.add_argument("--resolution", type=int, default=100, metavar="N",
                       help=f"grid points along each axis (default 100, at most {TORSO_ARM_MAX_RESOLUTION})")
    chart.add_argument("--arm", choices=("right", "left", "both"), default="right",
                       help="right (default) or left: one arm's manipulability w [m^3]; both: the two arms together "
                            "in the symmetric posture, the right wrist on the grid [m^6]")
    chart.add_argument("--shoulder", type=float, metavar="PSI",
                       help="fixed shoulder angle psi (radians, or degrees with --deg); omit it and --elbow for the "
                            "best map over the redundancy")
    chart.add_argument("--elbow", type=float, metavar="PHI",
                       help="fixed elbow angle phi (radians, or degrees with --deg)")
    chart.add_argument("--reference", default="vector", help="phi reference for a fixed-(psi, phi) map")
    chart.add_argument("--samples", type=int, nargs=2, default=(24, 24), metavar=("N1", "NPHI"),
                       help="theta_1 x phi samples of the best map")
    chart.add_argument("--threshold", type=float, help="report the region where w >= threshold (SI units)")
    chart.add_argument("--out", metavar="PNG", help="write the heat map to this PNG file")
    add_force_flag(chart)
    add_output_flags(chart)
    chart.set_defaults(handler=_run_map)
    top.set_defaults(handler=lambda args: _missing(top))


def _missing(parser: argparse.ArgumentParser) -> int:
    parser.print_help(sys.stderr)
    return 2


def _reference(text: str):
    if text in ("theta4", "vector"):
        return text
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError as exc:
        raise UsageError(f"--reference must be 'theta4', 'vector' or 'X,Y,Z', got {text!r}") from exc
    if len(values) != 3:
        raise UsageError(f"--reference vector needs 3 numbers, got {text!r}")
    return values


def run_ik(args: argparse.Namespace) -> int:
    from redkin.torso_arm import BRANCHES, STATUS_NAMES, humanoid_arm, ik, position_ik

    arm = humanoid_arm(args.arm, args.tool)
    psi, phi = angles_in([args.shoulder, args.elbow], args.deg)
    reference = _reference(args.reference)
    branches: list[tuple[int, ...]]
    target = checked_position(args.position)
    rotation = given_rotation(args)
    if args.angles is None and rotation is None:
        position = position_ik(arm, target, psi, phi, reference)
        q, limits, branches, singular = position.q, position.within_limits, [b[:2] for b in BRANCHES[::2]], [False] * 4
        code = position.status
    else:
        kwargs = {"angles": angles_in(args.angles, args.deg)} if args.angles else {"rotation": rotation}
        sol = ik(arm, target, psi, phi, reference=reference, **kwargs)
        q, limits, branches, singular = sol.q, sol.within_limits, list(BRANCHES), sol.wrist_singular.tolist()
        code = sol.status
    status = STATUS_NAMES[int(code)]
    rows = [
        {"branch": list(b), "q": angles_out(q[i], args.deg), "within_limits": bool(limits[i]),
         "wrist_singular": bool(singular[i])}
        for i, b in enumerate(branches)
    ] if status == "ok" else []
    if args.json:
        print_json({"arm": args.arm, "units": {"q": angle_unit(args.deg)}, "status": status, "solutions": rows,
                    "degrees": bool(args.deg)})
    else:
        inside = sum(row["within_limits"] for row in rows)
        print(f"status: {status}" + (f", {inside} of {len(rows)} solutions within the limits" if rows else ""))
        unit = "deg" if args.deg else "rad"
        for row in rows:
            flags = "within limits" if row["within_limits"] else "outside limits"
            if row["wrist_singular"]:
                flags += ", wrist singular"
            print(f"branch {row['branch']}: " + " ".join(fixed(v, 6, " ") for v in row["q"]) + f"  [{unit}] {flags}")
    return 0


def _run_map(args: argparse.Namespace) -> int:
    from redkin.torso_arm import humanoid_arm
    from redkin.torso_arm.maps import (
        best_dual_arm_map,
        best_manipulability_map,
        dual_arm_map,
        manipulability_map,
        plane_grid,
        reach_extent,
        region_above,
    )

    if args.out:
        output_file(args.out, "--out", IMAGE_SUFFIXES, args.force)
    extent = (reach_extent(humanoid_arm("right"), args.plane) if args.extent is None
              else check_magnitude(args.extent, "--extent", MAX_LENGTH, "m"))
    grid = plane_grid(args.plane, extent, args.resolution)
    fixed_angles = args.shoulder is not None or args.elbow is not None
    if fixed_angles and (args.shoulder is None or args.elbow is None):
        raise UsageError("give both --shoulder and --elbow for a fixed-(psi, phi) map, or neither for the best map")

    progress = Progress()

    large = args.resolution * args.resolution * args.samples[0] * args.samples[1] > 2e6
    if fixed_angles:  # turns of planes: wrapped to [-pi, pi), as the map's description prints them
        angles = angles_in([args.shoulder, args.elbow], args.deg)
        if not np.all(np.isfinite(angles)):
            raise UsageError(f"--shoulder and --elbow must be finite numbers, got {args.shoulder} and {args.elbow}")
        psi, phi = np.asarray(wrap_angle(angles)).tolist()
        reference = _reference(args.reference)
        if args.arm == "both":
            result = dual_arm_map(grid, psi, phi, reference)
        else:
            result = manipulability_map(humanoid_arm(args.arm), grid, psi, phi, reference)
    elif args.arm == "both":
        result = best_dual_arm_map(grid, tuple(args.samples), progress=progress if large else None)
    else:
        result = best_manipulability_map(humanoid_arm(args.arm), grid, tuple(args.samples),
                                         progress=progress if large else None)
    progress.close()  # ends the bar's line; a map that drew none prints nothing here
    unit = "m^6" if args.arm == "both" else "m^3"
    summary = {
        "plane": grid.label, "description": result.description, "unit": unit,
        "units": {"u": "m", "v": "m", "values": unit, "max": unit, "threshold": f"{unit} (value), m^2 (area_m2)"},
        "valid_fraction": float(result.valid.mean()),
        "max": float(np.nanmax(result.values)) if result.valid.any() else None,
    }
    if args.threshold is not None:
        region = region_above(result, args.threshold)
        summary["threshold"] = {"value": region.threshold, "area_m2": region.area,
                                "fraction_of_valid": float(region.fraction)}
    if args.out:
        _save(result, args.out, unit, args.arm)
        summary["out"] = args.out
    if args.json:
        print_json({**summary, "u": grid.u, "v": grid.v,
                    "values": [[None if not np.isfinite(x) else x for x in row] for row in result.values]})
    else:
        _print_map_summary(summary, unit)
    return 0


def _print_map_summary(summary: dict, unit: str) -> None:
    """The map's summary as lines a person reads (the JSON keeps the keys)."""
    print(f"plane: {summary['plane']}")
    print(f"map: {summary['description']}")
    print(f"valid points: {100 * summary['valid_fraction']:.1f}% of the grid (reachable within the limits)")
    print("max: " + ("none (no valid point)" if summary["max"] is None else f"{summary['max']:.4g} {unit}"))
    if "threshold" in summary:
        region = summary["threshold"]
        print(f"w >= {region['value']:.4g} {unit}: {region['area_m2']:.4g} m^2, "
              f"{100 * region['fraction_of_valid']:.1f}% of the valid points")
    if "out" in summary:
        print(f"wrote {summary['out']}")


def _save(result, path: str, unit: str, arm: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from redkin.plot.torso_arm import draw_manipulability_map
    from redkin.torso_arm import humanoid_arm

    right = humanoid_arm("right")
    landmarks: dict[str, ArrayLike] = {
        "neck": [0.0, 0.0, 0.0], "R shoulder": right.shoulder(0.0), "L shoulder": -right.shoulder(0.0),
    }
    fig, ax = plt.subplots(figsize=(6, 5))
    draw_manipulability_map(ax, result, landmarks, unit=unit)
    try:
        fig.savefig(path, dpi=120)
    finally:
        plt.close(fig)

