"""``redkin ik`` without ``--psi``/``--q7``: certified numerical pose IK on any chain (:func:`redkin.numerical.ik`),
for one pose or every pose of a ``--poses`` file; exit 1 where a pose has no solution found."""

from __future__ import annotations

import argparse

import numpy as np

from redkin.cli.common import (
    UsageError,
    angle_unit,
    angles_out,
    format_values,
    joint_vector,
    out_of_reach,
    print_json,
    reach_reason,
)


def add_numerical_arguments(parser: argparse.ArgumentParser) -> None:
    """The numerical solver's options of ``redkin ik``."""
    group = parser.add_argument_group("numerical IK (without --psi and --q7)")
    group.add_argument("--q0", nargs="+", type=float, metavar="Q",
                       help="a configuration to be near (one value per joint; radians, or degrees with --deg): the "
                            "numerical solver's seed, whose nearest solution is preferred; with --psi or --q7 each "
                            "branch's solution nearest it (joint values modulo whole turns; on a nearly S-R-S arm the "
                            "nearest of a branch's solutions where it has two)")
    group.add_argument("--count", type=int, default=1, metavar="K", help="distinct solutions wanted per pose "
                                                                          "(default 1)")
    group.add_argument("--tolerance", nargs="+", type=float, metavar="T",
                       help="certificate: largest position error [m] and rotation error [rad], one number for both "
                            "or two (default 1e-9)")
    group.add_argument("--restarts", type=int, default=None, metavar="S",
                       help="starts per pose: the seed, then random joint vectors within the limits (default 200)")
    group.add_argument("--seed", type=int, default=None, metavar="INT",
                       help="random seed of the restarts (default: a fixed stream per pose, so runs repeat)")
    group.add_argument("--numerical", action="store_true",
                       help="solve numerically even where the arm has a closed form (the default without --psi and "
                            "--q7)")


def run_numerical(chain, poses: np.ndarray, args: argparse.Namespace, batch: bool) -> int:
    """Solve ``poses`` ((4, 4), or (N, 4, 4) from ``--poses`` where ``batch``) and print them; 0 when every pose
    has a solution, else 1."""
    from redkin.closed_form import redundancy_parameter
    from redkin.errors import NotArmAngleClassError
    from redkin.numerical import ik
    from redkin.numerical.solve import RESTARTS, TOLERANCE

    options: dict = {"count": args.count, "restarts": RESTARTS if args.restarts is None else args.restarts}
    tolerance = (TOLERANCE, TOLERANCE) if args.tolerance is None else tuple(args.tolerance)
    if len(tolerance) > 2:
        raise UsageError(f"--tolerance takes one or two numbers, got {len(tolerance)}")
    options["tolerance"] = tolerance if len(tolerance) == 2 else tolerance[0]
    position, rotation = (tolerance * 2)[:2]
    if args.q0 is not None:
        options["q0"] = joint_vector(chain, args.q0, args.deg, "--q0 values")
    if args.seed is not None:
        options["rng"] = args.seed
    try:
        parameter: str | None = redundancy_parameter(chain)
        why = (f"{chain.name} has a closed form in {parameter}; solved numerically as asked (--numerical)"
               if args.numerical else f"{chain.name} has a closed form in {parameter}, but no --{parameter} was "
                                      "given: solved numerically")
    except NotArmAngleClassError as error:
        parameter, why = None, str(error)
    result = ik(chain, poses, **options)
    reach = result.reach
    assert reach is not None  # ik always measures the poses' reach
    label = None if parameter is None else _labeller(chain, parameter)
    entries = ([_entry(result, k, args.deg, label) for k in range(len(poses))] if batch
               else [_entry(result, (), args.deg, label)])
    if args.json:
        head = {"robot": chain.name, "method": "numerical", "why": why,
                "units": {"q": angle_unit(args.deg), "position_error": "m", "rotation_error": "rad", "reach": "m"},
                "tolerance": {"position": position, "rotation": rotation}}
        print_json({**head, "poses": entries} if batch else {**head, **entries[0]})
    else:
        unit = angle_unit(args.deg)
        print(f"numerical IK, certified to {position:g} m and {rotation:g} rad: {why}")
        for k, entry in enumerate(entries):
            label = f"pose {k}: " if batch else ""
            if entry["reason"]:
                print(f"{label}no solution: {out_of_reach(reach, k if batch else ())}; not searched")
            elif entry["status"] == "found":
                for j, q in enumerate(entry["solutions"]):
                    where = "" if parameter is None else \
                        f"  branch {entry['branches'][j]}, {parameter} {entry[parameter][j]:.6f} {unit}"
                    print(f"{label}{format_values(q)}  [{unit}]{where}")
                short = "" if len(entry["solutions"]) == args.count else f"; {len(entry['solutions'])} of the " \
                    f"{args.count} distinct solutions asked"
                print(f"{label}error {entry['error']['position']:.2g} m, {entry['error']['rotation']:.2g} rad "
                      f"({entry['starts']} start{'s' if entry['starts'] != 1 else ''}{short})")
            else:
                print(f"{label}no solution found in {entry['starts']} starts; the closest joint values miss by "
                      f"{entry['error']['position']:.3g} m and {entry['error']['rotation']:.3g} rad: "
                      f"{format_values(entry['closest']).lstrip()} [{unit}]")
    return 0 if bool(np.all(result.found[..., 0])) else 1


def _labeller(chain, parameter: str):
    """A function of solutions ``(K, 7)`` [rad] giving each one's branch (three signs) and ``parameter`` value
    [rad], read off the configuration by its class (:meth:`redkin.Arm.branch_of`, :meth:`redkin.Arm.parameter_of`)."""
    from redkin.arms import arm

    classified = arm(chain)

    def label(q: np.ndarray) -> tuple[list[str], np.ndarray]:
        if len(q) == 0:
            return [], np.zeros(0)
        return [str(b) for b in classified.branch_of(q)], classified.parameter_of(q)

    return parameter, label


def _entry(result, index, degrees: bool, labeller=None) -> dict:
    """One pose's JSON entry: status, solutions (with their branch and redundancy parameter where ``labeller``,
    of :func:`_labeller`, is given), the closest joint values and their error, starts used, and the reason where
    the pose is out of reach."""
    found = result.found[index]
    labels: dict = {}
    if labeller is not None:
        parameter, label = labeller
        branches, values = label(result.q[index][found])
        labels = {"branches": branches, parameter: [float(angles_out(v, degrees)) for v in values]}
    entry = {
        "status": "found" if found[0] else "not-found",
        "solutions": [angles_out(q, degrees) for q in result.q[index][found]],
        "closest": angles_out(result.closest[index], degrees),
        "error": {"position": float(result.error[index][0]), "rotation": float(result.error[index][1])},
        "starts": int(result.starts[index]),
        **labels,
        **reach_reason(result.reach, index),
    }
    if isinstance(index, int):
        entry = {"index": index, **entry}
    return entry
