"""``redkin ik`` without ``--psi``/``--q7``: certified numerical pose IK on any chain (:func:`redkin.numerical.ik`),
for one pose or every pose of a ``--poses`` file; exit 1 where a pose has no solution found."""

from __future__ import annotations

import argparse

import numpy as np

from redkin.cli.cell import cell_note_lines, cell_notes
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
                            "branch's solution nearest it (joint values modulo whole turns; on a nearly S-R-S arm, "
                            "where a branch has two, the nearest of those within the limits)")
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


def run_numerical(chain, poses: np.ndarray, args: argparse.Namespace, batch: bool, cell=None) -> int:
    """Solve ``poses`` ((4, 4), or (N, 4, 4) from ``--poses`` where ``batch``) and print them; 0 when every pose
    has a solution, else 1.  With a ``cell`` (the body and the scene of ``--scene``) the solutions are the
    collision-free ones (:func:`redkin.collision.free_ik.collision_free_ik`), each with its clearance."""
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
        if args.seed < 0:
            raise UsageError(f"--seed must be an integer >= 0, got {args.seed}")
        options["rng"] = args.seed
    try:
        parameter: str | None = redundancy_parameter(chain)
        why = (f"{chain.name} has a closed form in {parameter}; solved numerically as asked (--numerical)"
               if args.numerical else f"{chain.name} has a closed form in {parameter}, but no --{parameter} was "
                                      "given: solved numerically")
    except NotArmAngleClassError as error:
        parameter, why = None, str(error)
    free = None
    if cell is None:
        result = ik(chain, poses, **options)
    else:
        from redkin.collision.free_ik import collision_free_ik

        body, scene = cell
        free = collision_free_ik(chain, body, scene, poses, **options)
        result = free.solver._replace(q=free.q, found=free.found)
    reach = result.reach
    assert reach is not None  # ik always measures the poses' reach
    label = None if parameter is None else _labeller(chain, parameter)
    entries = ([_entry(result, k, args.deg, label, free) for k in range(len(poses))] if batch
               else [_entry(result, (), args.deg, label, free)])
    if args.json:
        head = {"robot": chain.name, "method": "numerical", "why": why,
                **({} if cell is None else {"margin": cell[1].margin, "cell": cell_notes(chain, cell)}),
                "units": {"q": angle_unit(args.deg), "position_error": "m", "rotation_error": "rad", "reach": "m"},
                "tolerance": {"position": position, "rotation": rotation}}
        print_json({**head, "poses": entries} if batch else {**head, **entries[0]})
    else:
        unit = angle_unit(args.deg)
        kept = "" if cell is None else f", collision-free by {cell[1].margin:g} m"
        print(f"numerical IK, certified to {position:g} m and {rotation:g} rad{kept}: {why}")
        for k, entry in enumerate(entries):
            label = f"pose {k}: " if batch else ""
            if entry["reason"]:
                print(f"{label}no solution: {out_of_reach(reach, k if batch else ())}; not searched")
            elif entry["status"] == "found":
                for j, q in enumerate(entry["solutions"]):
                    where = "" if parameter is None else \
                        f"  branch {entry['branches'][j]}, {parameter} {entry[parameter][j]:.6f} {unit}"
                    clear = "" if cell is None else f"  clearance {entry['clearance'][j]:.4g} m " \
                        f"({' / '.join(entry['closest_pairs'][j])})"
                    print(f"{label}{format_values(q)}  [{unit}]{where}{clear}")
                short = "" if len(entry["solutions"]) == args.count else f"; {len(entry['solutions'])} of the " \
                    f"{args.count} distinct solutions asked"
                print(f"{label}error {entry['error']['position']:.2g} m, {entry['error']['rotation']:.2g} rad "
                      f"({entry['starts']} start{'s' if entry['starts'] != 1 else ''}{short})")
                if cell is not None:
                    print(f"{label}{_refused(entry['collision'])}")
            elif cell is not None and entry["collision"]["candidates"]:
                print(f"{label}no collision-free solution: {_refused(entry['collision'])}")
            else:
                print(f"{label}no solution found in {entry['starts']} starts; the closest joint values miss by "
                      f"{entry['error']['position']:.3g} m and {entry['error']['rotation']:.3g} rad: "
                      f"{format_values(entry['closest']).lstrip()} [{unit}]")
        for line in cell_note_lines(None if cell is None else cell_notes(chain, cell)):
            print(line)
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


def _refused(collision: dict) -> str:
    """One line on the candidates a scene refused: how many, and how near the clearest of them came."""
    found, blocked = collision["candidates"], collision["blocked"]
    line = f"{blocked} of the {found} distinct solution{'s' if found != 1 else ''} found collide"
    if blocked:
        clearest = collision["clearest_blocked"]
        line += f" (the clearest of them: {clearest['clearance']:.4g} m, {' / '.join(clearest['pair'])})"
    return line


def _collision_entry(free, index) -> dict:
    """A pose's JSON fields with a scene: each solution's clearance and closest pair, and the candidates refused."""
    found = free.found[index]
    pairs = zip(free.link[index][found], free.against[index][found])
    entry: dict = {"clearance": [float(d) for d in free.clearance[index][found]],
                   "closest_pairs": [[str(a), str(b)] for a, b in pairs],
                   "collision": {"candidates": int(free.candidates[index]), "blocked": int(free.blocked[index])}}
    if free.blocked[index]:
        entry["collision"]["clearest_blocked"] = {
            "clearance": float(free.blocked_clearance[index]),
            "pair": [str(free.blocked_link[index]), str(free.blocked_against[index])]}
    return entry


def _entry(result, index, degrees: bool, labeller=None, free=None) -> dict:
    """One pose's JSON entry: status, solutions (with their branch and redundancy parameter where ``labeller``,
    of :func:`_labeller`, is given), the closest joint values and their error, starts used, and the reason where
    the pose is out of reach; with a scene (``free``, of :func:`redkin.collision.free_ik.collision_free_ik`) each
    solution's clearance and the candidates refused."""
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
        **({} if free is None else _collision_entry(free, index)),
        **reach_reason(result.reach, index),
    }
    if isinstance(index, int):
        entry = {"index": index, **entry}
    return entry
