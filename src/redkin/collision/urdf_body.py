"""An arm's body from a URDF's ``<collision>`` elements (issue 40), and the link pairs an SRDF disables.

Each ``<collision>`` of a link :func:`redkin.collision.link_frames.urdf_link_frames` maps (the chain's path and what
is fixed below it) becomes one capsule, placed by its ``<origin>`` in the link's frame and carried into the chain
frame the link is fixed in:

* a sphere: exactly, a capsule of length 0;
* a cylinder (centred on its frame's origin, its axis the frame's z): the capsule of the same radius around its axis
  segment, of the cylinder's length, which reaches up to ``radius`` beyond each flat end;
* a box: the capsule around the segment through its centre along its longest edge, as long as that edge, whose radius
  is half the diagonal of the other two edges: it contains the box, and reaches up to that radius beyond it (past the
  two end faces; less elsewhere);
* a mesh: read from its file (:mod:`redkin.collision.mesh_files`: ``package://`` names found from the caller's
  package paths, the folders above the URDF and ``ROS_PACKAGE_PATH``; the ``mesh`` extra reads the file), scaled by
  its ``scale``, and covered by one to three capsules that contain it (:mod:`redkin.collision.mesh_cover`; kept on
  disk per file by :mod:`redkin.collision.mesh_cache`, so a file is covered once); ``pieces`` asks for at least two
  or three on a link whose meshes one capsule covers too coarsely.

Link pairs whose capsules overlap at every one of 1000 random configurations within the limits (a wrist's two
housings, covered by capsules larger than the castings) are not checked against each other, and a note names them:
checked, they would remove every configuration, as MoveIt's setup assistant finds such pairs "always in collision"
and disables them.

The body's notes say, one line each, which cylinder, box and mesh were made larger and by how much (for a mesh: how
far its capsules reach beyond the convex hull of what each covers), and which links with ``<collision>`` elements
are not fixed in the chain's frames (a gripper's fingers) and so left out.

An SRDF (MoveIt's semantic description) names link pairs that never need checking against each other,
``<disable_collisions link1="..." link2="..." reason="..."/>``; they become the body's ignored pairs
(:func:`srdf_ignored_pairs`).
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from redkin.chain import SerialChain
from redkin.collision.body import Body, BodyCapsule, body_of
from redkin.collision.link_frames import _urdf_links
from redkin.collision.mesh_cache import covered_capsules
from redkin.collision.mesh_files import mesh_path
from redkin.collision.primitives import WIDTH, _radius
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.examples import resolve
from redkin.urdf import _origin, _package_places

#: How many link names the note on the links left out lists.
_NAMES_SHOWN = 6
#: Random configurations within the limits over which a link pair must always overlap to be left unchecked.
_SAMPLES = 1000


def urdf_body(path: str | Path, base: str | None = None, tip: str | None = None, *,
              srdf: str | os.PathLike | None = None, xacro_args: Mapping[str, str | int | float | bool] | None = None,
              package_paths: str | os.PathLike | Iterable[str | os.PathLike] = (),
              pieces: Mapping[str, int] | None = None) -> tuple[SerialChain, Body]:
    """The chain from link ``base`` to link ``tip`` of a URDF, and the body of its ``<collision>`` elements (module
    docstring).

    Parameters
    ----------
    path, base, tip, xacro_args, package_paths
        As :func:`redkin.urdf.load_urdf` takes them, with the same defaults; the package paths are searched for the
        packages of ``package://`` mesh files too.
    srdf : str or path, optional
        An SRDF whose ``<disable_collisions>`` link pairs the body never checks against each other.
    pieces : mapping of str to int, optional
        Per URDF link name, the fewest capsules (1 to 3) each of its meshes is covered by where the mesh can be cut
        so (:func:`redkin.collision.covering_capsules`' ``least``); by default a second or third capsule only where
        it saves a quarter of the volume.

    Returns
    -------
    chain : SerialChain
        :func:`redkin.urdf.load_urdf`'s chain.
    body : Body
        On that chain, with notes on what its capsules over-approximate or leave out.

    Raises
    ------
    RobotDescriptionError
        As :func:`redkin.urdf.load_urdf` raises it; for a collision's sizes that are not finite lengths >= 0; for a
        mesh file that is not found or not read; for an SRDF that cannot be read, or whose ``<disable_collisions>``
        lacks a link or names one the URDF does not have: one line naming the file, and the link or entry; for
        ``pieces`` naming a link the URDF does not have, or a count that is not 1 to 3.
    RedkinError
        For a mesh where the ``mesh`` extra (trimesh) is not installed, with the command that installs it.
    """
    chain, robot, links = _urdf_links(path, base, tip, xacro_args, package_paths)
    least = dict(pieces or {})
    for name, count in least.items():
        if name not in {link.name for link in robot.links} or count not in (1, 2, 3):
            raise RobotDescriptionError(f"{path}: pieces asks for {count!r} capsules on link {name!r}; give a link of "
                                        "the URDF and 1, 2 or 3", str(path), name)
    file = resolve(path)
    places = _package_places(package_paths, file)
    ignore = [] if srdf is None else srdf_ignored_pairs(srdf)
    known = {link.name for link in robot.links}
    for pair in ignore:
        for name in pair:
            if name not in known:
                raise RobotDescriptionError(f"SRDF {str(srdf)!r}: <disable_collisions> names link {name!r}, which the "
                                            f"URDF {str(path)!r} does not have", str(srdf), name)
    capsules, notes = [], []
    for link in robot.links:
        if link.name not in links:
            continue
        frame, pose = links[link.name]
        for index, collision in enumerate(link.collisions, start=1):
            label = f"link {link.name!r} collision {index}"
            try:
                covering, note = _covering(collision.geometry, label, file, places, least.get(link.name, 1))
            except RobotDescriptionError:
                raise
            except RedkinError as exc:  # a size refused by _radius, or the mesh extra missing
                raise RobotDescriptionError(f"{path}: {exc}", str(path), link.name) from None
            place = pose @ _origin(collision)
            for ends, radius in covering:
                a, b = (place[:3, :3] @ end + place[:3, 3] for end in ends)
                capsules.append(BodyCapsule(link.name, frame, a, b, radius))
            if note:
                notes.append(note)
    left_out = [link.name for link in robot.links if link.collisions and link.name not in links]
    if left_out:
        shown = ", ".join(left_out[:_NAMES_SHOWN]) + (f" and {len(left_out) - _NAMES_SHOWN} more"
                                                      if len(left_out) > _NAMES_SHOWN else "")
        notes.append(f"link{'s' if len(left_out) > 1 else ''} {shown} not covered: not fixed in the chain's frames "
                     "(above its base, or below a joint off the chain)")
    source = str(path) + (f" (SRDF {srdf})" if srdf is not None else "")
    try:
        body = body_of(capsules, chain, ignore, notes=notes, source=source)
    except RedkinError as exc:  # a collision <origin> that is not finite
        raise RobotDescriptionError(f"{path}: {exc}", str(path)) from None
    always = _always_overlapping(chain, body)
    if not always:
        return chain, body
    notes.append(f"link pair{'s' if len(always) > 1 else ''} {', '.join(f'{a} - {b}' for a, b in always)}: the "
                 f"capsules overlap in every one of {_SAMPLES} random configurations within the limits, so "
                 f"{'they are' if len(always) > 1 else 'it is'} not checked (as MoveIt's setup assistant disables "
                 "pairs always in collision; an SRDF or a body file decides otherwise)")
    return chain, body_of(capsules, chain, ignore + always, notes=notes, source=source)


def _always_overlapping(chain: SerialChain, body: Body) -> list[tuple[str, str]]:
    """The link pairs whose capsules overlap at every one of :data:`_SAMPLES` random configurations within the limits
    (a joint without limits: within a turn; a fixed seed): checked, they would remove every configuration."""
    from redkin.collision.clearance import pair_table
    from redkin.collision.scene import Scene

    if not len(body.pairs):
        return []
    rng = np.random.default_rng(0)
    q = rng.uniform(np.maximum(chain.lower, -np.pi), np.minimum(chain.upper, np.pi), (_SAMPLES, chain.n))
    apart, pairs = pair_table(chain, body, Scene((), np.empty((0, WIDTH))), q)
    found = set()
    for k in np.flatnonzero(np.all(apart < 0.0, axis=0)):
        first, second = sorted(pairs.names[k])
        found.add((first, second))
    return sorted(found)


def srdf_ignored_pairs(path: str | os.PathLike) -> list[tuple[str, str]]:
    """The link pairs of an SRDF's ``<disable_collisions link1="..." link2="..."/>`` elements, in the file's order.

    Raises
    ------
    RobotDescriptionError
        For a missing or unreadable file, one that is not XML or whose root element is not ``<robot>``, and a
        ``<disable_collisions>`` without both links: one line naming the file (and the entry).
    """
    where = f"SRDF {str(path)!r}"
    try:
        root = ET.parse(path).getroot()
    except OSError as exc:
        raise RobotDescriptionError(f"{where}: cannot read it ({exc.strerror or exc})", str(path)) from None
    except ET.ParseError as exc:
        raise RobotDescriptionError(f"{where}: not XML (line {exc.position[0]})", str(path)) from None
    if root.tag != "robot":
        raise RobotDescriptionError(f"{where}: its root element is <{root.tag}>, not <robot>", str(path))
    pairs = []
    for index, element in enumerate(root.findall("disable_collisions"), start=1):
        first, second = element.get("link1"), element.get("link2")
        if not first or not second:
            raise RobotDescriptionError(f"{where}: <disable_collisions> {index} needs both link1 and link2",
                                        str(path), "disable_collisions")
        pairs.append((first, second))
    return pairs


def _covering(geometry: Any, label: str, file: Path, places: list[Path],
              least: int = 1) -> tuple[list[tuple[tuple[np.ndarray, np.ndarray], float]], str]:
    """The capsules covering a sphere, cylinder, box or mesh of ``urdf_parser_py`` in its own frame (each its
    segment's ends and its radius; a mesh by at least ``least`` where it can be cut so), and the note on what they
    add ('' for a sphere, which one equals)."""
    from urdf_parser_py.urdf import Cylinder, Mesh, Sphere

    if isinstance(geometry, Sphere):
        return [((np.zeros(3), np.zeros(3)), _radius(geometry.radius, f"{label}: sphere radius"))], ""
    if isinstance(geometry, Cylinder):
        radius = _radius(geometry.radius, f"{label}: cylinder radius")
        half = np.array([0.0, 0.0, _radius(geometry.length, f"{label}: cylinder length") / 2.0])
        return [((-half, half), radius)], (f"{label}: cylinder covered by a capsule reaching up to {radius:.4g} m "
                                           "beyond each flat end")
    if isinstance(geometry, Mesh):
        mesh = mesh_path(geometry.filename, file, places)  # its errors name the description
        try:
            covering = covered_capsules(mesh, geometry.scale, least)
        except RobotDescriptionError as exc:  # the mesh file's own words: say which description and link
            raise RobotDescriptionError(f"{file}: {label}: {exc}", str(file)) from None
        reach = max(capsule.reach for capsule in covering)
        parts = ("its convex hull" if len(covering) == 1
                 else f"the convex hull of the part each covers (cut in {len(covering)} by planes)")
        return ([((capsule.a, capsule.b), capsule.radius) for capsule in covering],
                f"{label}: mesh {geometry.filename!r} covered by {len(covering)} capsule"
                f"{'s' if len(covering) > 1 else ''} reaching up to {reach:.3g} m beyond {parts}")
    sizes = np.array([_radius(size, f"{label}: box size") for size in geometry.size])  # a Box
    longest = int(np.argmax(sizes))
    radius = float(np.hypot(*np.delete(sizes, longest))) / 2.0
    half = np.zeros(3)
    half[longest] = sizes[longest] / 2.0
    return [((-half, half), radius)], (f"{label}: box {' x '.join(f'{size:.4g}' for size in sizes)} m covered by a "
                                       f"capsule along its longest edge, reaching up to {radius:.4g} m beyond the box")
