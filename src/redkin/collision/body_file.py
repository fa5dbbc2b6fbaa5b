"""An arm's body from a body file (issue 40): spheres and capsules per link, as cuRobo and PyRoki describe arms.

A body file is YAML (JSON is YAML too), metres, each shape given in the frame of the link it is fixed to::

    spheres:                              # per link, a list of spheres
      iiwa_link_4: [{center: [0, 0.0, 0.1], radius: 0.07}]
    capsules:                             # per link, a list of capsules: the points within radius of segment a-b
      iiwa_link_3: [{a: [0, 0, 0], b: [0, 0, 0.2], radius: 0.06}]
    ignore: [[iiwa_link_5, iiwa_link_7]]  # link pairs never checked against each other, beside the adjacent ones
    notes: ["capsules measured off the arm"]   # what the shapes approximate, for the user to read

All four keys are optional; the notes become the body's (:attr:`redkin.collision.Body.notes`). The links are those a
description names (:mod:`redkin.collision.link_frames`: a URDF's links, or ``link_0 .. link_n`` of a chain without
link names); each shape is carried into the chain frame its link is fixed in, and the body keeps the spheres first,
then the capsules, in the order of the file. A file that cannot be used is one line naming the file, the link and
entry, and the field.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from redkin._yaml_files import read_yaml
from redkin.chain import SerialChain
from redkin.collision.body import Body, BodyCapsule, body_of
from redkin.collision.link_frames import LinkFrame
from redkin.collision.primitives import _point, _radius
from redkin.errors import RedkinError, RobotDescriptionError

#: Per shape list of a body file, the name of one shape and its fields (all required).
_SHAPES = {"spheres": ("sphere", ("center", "radius")), "capsules": ("capsule", ("a", "b", "radius"))}
#: How many known link names a message about an unknown link lists.
_NAMES_SHOWN = 6


def read_body(file: str | os.PathLike, chain: SerialChain, links: Mapping[str, LinkFrame], *,
              ignore: Iterable[Sequence[str]] = ()) -> Body:
    """The body of a YAML or JSON body file (module docstring) on ``chain``.

    Parameters
    ----------
    file : str or path
    chain : SerialChain
    links : mapping of str to LinkFrame
        Where each link the file may name sits in the chain's frames (:mod:`redkin.collision.link_frames`:
        ``urdf_link_frames``, ``numbered_link_frames``).
    ignore : iterable of (str, str)
        More link pairs to skip beside the file's (an SRDF's, :func:`redkin.collision.srdf_ignored_pairs`).

    Returns
    -------
    Body
        Its source is the file.

    Raises
    ------
    RobotDescriptionError
        For a missing or unreadable file, one that is not YAML or JSON, an unknown key, an unknown link, a shape
        with an unknown, missing or malformed field (a point not of three finite numbers, a radius that is not a
        finite number >= 0), or an ``ignore`` entry that is not two known link names: one line naming the file, the
        link and entry, and the field.
    """
    return body_data(read_yaml(file, "body file"), chain, links, str(file), ignore=ignore)


def body_data(data: Any, chain: SerialChain, links: Mapping[str, LinkFrame], source: str = "", *,
              ignore: Iterable[Sequence[str]] = ()) -> Body:
    """The body of the data of a body file (a mapping with ``spheres``, ``capsules``, ``ignore`` and ``notes``, each
    optional),
    as :func:`read_body` reads it, with the pairs ``ignore`` skipped too; ``source`` names it in errors and becomes
    the body's."""
    where = f"body file {source!r}" if source else "body"
    if not isinstance(data, dict):
        raise RobotDescriptionError(f"{where}: expected a mapping with spheres, capsules, ignore or notes", source)
    unknown = sorted(set(map(str, data)) - {*_SHAPES, "ignore", "notes"})
    if unknown:
        raise RobotDescriptionError(f"{where}: unknown key {unknown[0]!r} (a body file has spheres, capsules, "
                                    "ignore and notes)", source, unknown[0])
    notes = data.get("notes", [])
    if not (isinstance(notes, list) and all(isinstance(note, str) for note in notes)):
        raise RobotDescriptionError(f"{where}: notes must be a list of lines of text", source, "notes")
    capsules = [capsule for key in _SHAPES for capsule in _shapes(data.get(key, {}), key, links, where, source)]
    skipped = _ignored(data.get("ignore", []), links, where, source) + [tuple(pair) for pair in ignore]
    try:
        return body_of(capsules, chain, skipped, notes=notes, source=source)
    except RedkinError as exc:  # links whose frames are not the chain's
        raise RobotDescriptionError(f"{where}: {exc}", source) from None


def _shapes(entries: Any, key: str, links: Mapping[str, LinkFrame], where: str, source: str) -> list[BodyCapsule]:
    """The capsules of one shape list of a body file (``spheres`` or ``capsules``), in their links' chain frames."""
    kind, fields = _SHAPES[key]
    if not isinstance(entries, dict):
        raise RobotDescriptionError(f"{where}: {key} must be a mapping of link names to lists of {key}", source, key)
    capsules = []
    for link, shapes in entries.items():
        if link not in links:
            raise RobotDescriptionError(f"{where}: {key}: {_unknown_link(link, links)}", source, str(link))
        if not isinstance(shapes, list):
            raise RobotDescriptionError(f"{where}: {key}: link {link!r}: expected a list of {key}", source, link)
        frame, pose = links[link]
        for index, shape in enumerate(shapes, start=1):
            label = f"{where}: {key}: link {link!r}: {kind} {index}"
            if not isinstance(shape, dict):
                raise RobotDescriptionError(f"{label} must be a mapping of {', '.join(fields)}", source, link)
            unknown = sorted(set(map(str, shape)) - set(fields))
            if unknown:
                raise RobotDescriptionError(f"{label}: unknown field {unknown[0]!r} (a {kind} has "
                                            f"{', '.join(fields)})", source, unknown[0])
            missing = [field for field in fields if field not in shape]
            if missing:
                raise RobotDescriptionError(f"{label}: missing field {missing[0]!r}", source, missing[0])
            points, radius = {}, 0.0
            for field in fields:
                try:
                    if field == "radius":
                        radius = _radius(shape[field], field)
                    else:
                        points[field] = _point(shape[field], field)
                except RedkinError as exc:
                    raise RobotDescriptionError(f"{label}: {exc}", source, field) from None
            ends = [points["center"]] * 2 if kind == "sphere" else [points["a"], points["b"]]
            a, b = (pose[:3, :3] @ end + pose[:3, 3] for end in ends)
            capsules.append(BodyCapsule(link, frame, a, b, radius))
    return capsules


def _ignored(entries: Any, links: Mapping[str, LinkFrame], where: str, source: str) -> list[tuple[str, str]]:
    """The ``ignore`` pairs of a body file, each two known link names."""
    if not isinstance(entries, list):
        raise RobotDescriptionError(f"{where}: ignore must be a list of link pairs", source, "ignore")
    for index, entry in enumerate(entries, start=1):
        label = f"{where}: ignore: entry {index}"
        if not (isinstance(entry, list) and len(entry) == 2 and all(isinstance(name, str) for name in entry)):
            raise RobotDescriptionError(f"{label} must be two link names, got {entry!r}", source, "ignore")
        for name in entry:
            if name not in links:
                raise RobotDescriptionError(f"{label}: {_unknown_link(name, links)}", source, name)
    return [(entry[0], entry[1]) for entry in entries]


def _unknown_link(name: Any, links: Mapping[str, LinkFrame]) -> str:
    """The words for a link name ``name`` that ``links`` does not have, with a few names it has."""
    shown = ", ".join(list(links)[:_NAMES_SHOWN]) + (", ..." if len(links) > _NAMES_SHOWN else "")
    return f"unknown link {name!r} (links: {shown or 'none'})"
