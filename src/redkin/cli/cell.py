"""The cell on the command line (issue 40): ``--scene``, ``--body``, ``--srdf`` and ``--margin``, read into the arm's
body and the scene's obstacles, and the collision-free sets in a command's JSON."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from redkin.cli.common import angles_out, xacro_options
from redkin.errors import RedkinError

if TYPE_CHECKING:  # the chain's module loads the compiled kernels: not before a command runs
    from redkin.chain import SerialChain

#: Robot files whose links are named: the body's links come from them.
_NAMED_LINKS = (".urdf", ".xacro")


#: The kernels of an exact class's collision-free sets (``arm-angles --scene``, and a short path of an S-R-S or
#: offset-elbow arm in a cell), by its parameter: one pose's sets run as Python while these are not cached (0.2-0.7 s;
#: compiling them took 19 s on the iiwa14), compiled once they are, and the :data:`CELL_SETS_SECTIONS` of
#: :mod:`redkin.warm_up` compile them in the background.
CELL_SETS_KERNELS = {
    "psi": ("redkin.collision._arm_angle_kernels.level", "redkin.collision._clearance_kernels.clearances",
            "redkin.collision._body_kernels.posed_rows", "redkin.srs._feasible_kernels.poses_feasible",
            "redkin.srs._feasible_kernels.batch_arc_runs", "redkin.srs._ik_kernels.solve_poses",
            "redkin.collision._decision_kernels.next_level"),
    "q7": ("redkin.franka._kernels.limit_spectra_of", "redkin.franka._kernels.solve_branch_rows",
           "redkin.franka._kernels.levels_crossed", "redkin.franka._kernels.feasible_poses",
           "redkin.collision._clearance_kernels.clearances", "redkin.collision._decision_kernels.decided",
           "redkin.collision._body_kernels.posed_rows", "redkin.collision._decision_kernels.next_level",
           "redkin.collision._joint_motion_kernels.reaches"),
}
CELL_SETS_SECTIONS = {"psi": ("srs ik", "srs sets", "collision"), "q7": ("franka", "collision")}

def add_cell_arguments(parser: argparse.ArgumentParser, effect: str) -> None:
    """``--scene`` (whose help ends with what it does to the command, ``effect``), ``--body``, ``--srdf`` and
    ``--margin``."""
    parser.add_argument("--scene", metavar="FILE", help="a scene file (YAML or JSON: obstacles in the base frame and a "
                                                       f"margin, docs/collisions.md): {effect}")
    parser.add_argument("--body", metavar="FILE", help="with --scene: the arm's capsules and spheres per link (YAML or "
                                                      "JSON, keyed by the URDF's link names; link_0 .. link_n, the "
                                                      "chain's frames, for a named model or another file); default: "
                                                      "a URDF's <collision> elements, or a named model's built-in "
                                                      "body (capsules fitted to its maker's meshes)")
    parser.add_argument("--srdf", metavar="FILE", help="with --scene: an SRDF whose disable_collisions link pairs are "
                                                      "not checked against each other")
    parser.add_argument("--margin", type=float, metavar="M",
                        help="with --scene: the clearance to keep in metres (default: the scene file's)")


def load_cell(args: argparse.Namespace, chain: SerialChain):
    """The body and the scene the arguments name, or ``None`` without ``--scene`` (a ValueError in one line for a
    bad file, a body option without a scene, a robot with no body to read, or a cell that checks no pair: no obstacle
    and no self pair, whose every answer would be "collision-free" of nothing).  Covering a mesh (a maker's link, a
    scene's fixture) runs compiled wherever it is asked (:mod:`redkin.collision.mesh_cover`); whether the rest of
    the command's work in the cell is small enough to run as Python is the command's to say
    (:func:`redkin.cli.common.small_work`: one pose's numerical or closed-form IK is, certified sets and paths are
    not)."""
    if args.scene is None:
        given = [option for option in ("body", "srdf", "margin") if getattr(args, option) is not None]
        if given:
            raise RedkinError(f"--{given[0]} applies with --scene FILE")
        return None
    from redkin.collision.clearance import checked_pairs

    body, scene = _read_cell(args, chain)
    if not len(checked_pairs(body, scene).names):
        moving = int(np.sum(np.asarray(body.frame) > 0))
        raise RedkinError(f"the cell checks no pair (obstacles: {len(scene)}, capsules on moving links: {moving}, "
                          f"self-collision pairs: {len(body.pairs)}): give obstacles in --scene, or a --body with "
                          "capsules on the moving links")
    return body, scene


def _read_cell(args: argparse.Namespace, chain: SerialChain):
    """:func:`load_cell`'s body and scene, read."""
    from dataclasses import replace

    from redkin.collision import read_body, read_scene, srdf_ignored_pairs, urdf_body

    scene = read_scene(args.scene)
    if args.margin is not None:
        if not (np.isfinite(args.margin) and args.margin >= 0.0):
            raise RedkinError(f"--margin must be a finite number >= 0 (metres), got {args.margin}")
        scene = replace(scene, margin=float(args.margin))
    named = _named_links(args.robot)
    options = xacro_options(args)
    if args.body is not None:
        if args.srdf is not None and not named:
            raise RedkinError("--srdf names URDF links: it applies to a URDF or xacro robot")
        ignore = [] if args.srdf is None else srdf_ignored_pairs(args.srdf)
        return read_body(args.body, chain, body_links(args, args.robot, chain), ignore=ignore), scene
    if not named:
        from redkin.collision import builtin_body, builtin_models

        if args.robot.lower() in builtin_models():  # a named model's: a robot file is named with its suffix
            if args.srdf is not None:
                raise RedkinError("--srdf names URDF links: it applies to a URDF or xacro robot")
            return builtin_body(args.robot, chain), scene
        raise RedkinError(f"{args.robot} has no collision elements to read nor a built-in body: give --body FILE (its "
                          f"links are link_0 .. link_{chain.n}, the chain's frames; built-in bodies: "
                          f"{', '.join(builtin_models())})")
    _, body = urdf_body(args.robot, args.base, args.tip, srdf=args.srdf, **options)
    if not len(body):
        raise RedkinError(f"{args.robot}: the chain's links have no <collision> elements: give --body FILE")
    return body, scene


def _named_links(robot: str) -> bool:
    """Whether the robot is a URDF or xacro file, whose links a body file names."""
    from redkin.examples import resolve

    file = resolve(robot)
    return file.suffix.lower() in _NAMED_LINKS and file.is_file()


def body_links(args: argparse.Namespace, robot: str, chain: SerialChain) -> dict:
    """The links a body file may name (:class:`redkin.collision.LinkFrame` by name): a URDF's own, or ``link_0 ..
    link_n`` (the chain's frames) for another robot."""
    from redkin.collision import numbered_link_frames, urdf_link_frames

    if _named_links(robot):
        return urdf_link_frames(robot, args.base, args.tip, **xacro_options(args))[1]
    return numbered_link_frames(chain)


def cell_notes(chain: SerialChain, cell) -> dict[str, Any]:
    """What a cell (its body and scene) says of itself, as a command's JSON fields: ``notes``, the body's (where its
    shapes stand for the links' meshes, and how far beyond them they reach); ``scene_notes``, the scene's (how far a
    mesh obstacle's boxes reach beyond it); ``base_contacts``, the obstacles within the margin of the base (frame
    0), which is not checked since it never moves."""
    from redkin.collision.clearance import base_contacts

    body, scene = cell
    return {"notes": list(body.notes), "scene_notes": list(scene.notes),
            "base_contacts": [{"link": link, "obstacle": obstacle, "distance": distance}
                              for link, obstacle, distance in base_contacts(chain, body, scene)]}


def cell_note_lines(notes: dict[str, Any] | None) -> list[str]:
    """:func:`cell_notes` in words, a line each (none without a cell)."""
    if notes is None:
        return []
    return ([f"body: {note}" for note in notes["notes"]] + [f"scene: {note}" for note in notes["scene_notes"]]
            + [f"base: {contact['link']} is {contact['distance']:.3g} m from {contact['obstacle']}, inside the "
               "margin; not checked: it never moves" for contact in notes["base_contacts"]])


def free_report(report: dict[str, Any], chain: SerialChain, free, scene, body, deg: bool, shown: str,
                optimal: dict[str, tuple[float, float]], minimiser: Callable[[Any], float]) -> None:
    """Put the collision-free sets into a command's JSON ``report``: ``feasible`` becomes the shown branch's free set
    and ``limits_feasible`` the joint-limit set, ``branches`` every branch's free set (``limits_branches`` the limit
    sets), ``blocked`` each removed stretch of the shown branch, each entry of ``optimal`` (its unclamped and
    limit-feasible values, radians) gains ``collision_free``: on the arm angle the free set's value nearest the
    unclamped one ([000]'s clamping, as :meth:`redkin.Arm.optimal` in a cell), on q7 ``minimiser(arcs)`` of the
    shown branch's free intervals ([F10] over them, :meth:`redkin.Arm.optimal` in a cell); ``collision`` says what
    was checked."""
    from redkin.circle import ArcSet

    def arcs(bounds: np.ndarray) -> list:
        return [[float(v) for v in angles_out(arc, deg)] for arc in bounds]

    index = free.branches.index(shown)
    report["limits_feasible"], report["limits_feasible_wraps"] = report["feasible"], report["feasible_wraps"]
    report["feasible"] = arcs(free.free[index].bounds)
    report["feasible_wraps"] = [bool(w) for w in free.free[index].wraps]
    report["limits_branches"] = report["branches"]
    report["branches"] = {label: arcs(free.free[b].bounds) for b, label in enumerate(free.branches)}
    report["blocked"] = [{"arc": [float(v) for v in angles_out(np.array([s.start, s.end]), deg)], "cause": s.cause,
                          "link": s.link or None, "obstacle": s.against or None} for s in free.blocked[index]]
    on_circle = ArcSet(free.free[index].bounds.tolist()) if free.parameter == "psi" else None
    for name, (unclamped, _) in optimal.items():
        value = None
        if np.isfinite(unclamped) and on_circle is not None:
            value = on_circle.nearest(unclamped)
        elif on_circle is None and len(free.free[index].bounds):  # q7: [F10]'s minimiser over the free intervals
            found = minimiser(free.free[index])
            value = found if np.isfinite(found) else None
        report["optimal"][name]["collision_free"] = None if value is None else float(angles_out(value, deg))
    report["collision"] = {
        "scene": scene.source, "obstacles": list(scene.names), "margin": scene.margin, "body": body.source,
        "capsules": len(body), "self_pairs": len(body.pairs), **cell_notes(chain, (body, scene)),
        "resolution": float(angles_out(free.resolution, deg)), "complete": free.complete,
        "evaluations": free.evaluations,
    }


def clearance_entry(chain: SerialChain, cell, q: np.ndarray) -> dict[str, Any]:
    """A solution's JSON fields with a scene (none without): ``clearance`` (the least distance, metres),
    ``closest`` (the link and the obstacle or link that have it) and ``collision_free`` (at least the margin)."""
    if cell is None:
        return {}
    from redkin.collision import clearance

    body, scene = cell
    result = clearance(chain, body, scene, q)
    distance = float(result.distance)
    return {"clearance": distance if np.isfinite(distance) else None,
            "closest": [str(result.link.item()), str(result.against.item())],
            "collision_free": bool(distance >= scene.margin)}
