"""Where each named link of a robot description sits in the frames of its chain (issue 40), so that a body given
per link (a body file, a URDF's ``<collision>`` elements) is fixed in the frames :class:`redkin.collision.body.Body`
uses.

A link moves with the last movable joint above it, so it is fixed in one frame ``k`` of
:meth:`redkin.chain.SerialChain.frames` (the frame joint ``k`` turns; ``0``: the base, which no joint moves), at a
constant pose ``T`` in that frame, for all joint values ``q``::

    the link's pose in the base link's coordinates  =  chain.frames(q)[k] @ T

For a URDF (:func:`urdf_link_frames`), ``k`` is the number of revolute and continuous joints above the link on the
chain's path, and ``T = inv(chain.frames(0)[k]) @ P``, with ``P`` the link's pose at ``q = 0`` in the base link's
coordinates (the product of the ``<origin>`` transforms from the base link down to it).  The links mapped are those
of the chain's path from its base link to its tip link, and those hanging below one of them (the base and the tip
included) through fixed joints only, such as a hand and its tool-centre point.  A link below a movable joint off the
path (a gripper's finger, the next links past the tip) moves with joint values the chain does not have, and is left
out.

A description without link names (a named model, a robot file) has the links ``link_0 .. link_n``: ``link_k`` is
frame ``k`` itself (:func:`numbered_link_frames`).
"""

from __future__ import annotations

import os
import warnings
from collections import deque
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from redkin.chain import SerialChain
from redkin.examples import resolve
from redkin.urdf import _only_leaf, _origin, _package_places, _parse, _xacro_arguments, load_urdf


class LinkFrame(NamedTuple):
    """Where one link sits in a chain: fixed in chain frame ``frame`` (``0 .. n``) at the constant 4x4 ``pose``, the
    link's own frame expressed in that chain frame (read-only)."""

    frame: int
    pose: np.ndarray


def urdf_link_frames(path: str | Path, base: str | None = None, tip: str | None = None, *,
                     xacro_args: Mapping[str, str | int | float | bool] | None = None,
                     package_paths: str | os.PathLike | Iterable[str | os.PathLike] = (),
                     ) -> tuple[SerialChain, dict[str, LinkFrame]]:
    """The chain from link ``base`` to link ``tip`` of a URDF, and where each of its links sits in the chain's frames.

    Parameters
    ----------
    path, base, tip, xacro_args, package_paths
        As :func:`redkin.urdf.load_urdf` takes them, with the same defaults.

    Returns
    -------
    chain : SerialChain
        :func:`redkin.urdf.load_urdf`'s chain.
    links : dict of str to LinkFrame
        The links of the chain's path and those fixed below them (module docstring), walking down the tree from the
        base link: ``chain.frames(q)[links[name].frame] @ links[name].pose`` is link ``name``'s pose in the base
        link's coordinates at joint values ``q``.

    Raises
    ------
    RobotDescriptionError
        As :func:`redkin.urdf.load_urdf` raises it.
    """
    chain, _, links = _urdf_links(path, base, tip, xacro_args, package_paths)
    return chain, links


def numbered_link_frames(chain: SerialChain) -> dict[str, LinkFrame]:
    """The links of a chain without link names (a named model, a robot file): ``link_k`` is chain frame ``k``
    (``0 .. n``) itself, at the identity."""
    return {f"link_{k}": LinkFrame(k, _constant(np.eye(4))) for k in range(chain.n + 1)}


def _urdf_links(path: str | Path, base: str | None, tip: str | None,
                xacro_args: Mapping[str, str | int | float | bool] | None,
                package_paths: str | os.PathLike | Iterable[str | os.PathLike],
                ) -> tuple[SerialChain, Any, dict[str, LinkFrame]]:
    """:func:`urdf_link_frames`, with the URDF as ``urdf_parser_py`` reads it (its ``Robot``) between the two."""
    chain = load_urdf(path, base, tip, xacro_args=xacro_args, package_paths=package_paths)
    file = resolve(path)  # read once more, for the links: load_urdf has checked all that can fail
    with warnings.catch_warnings():  # load_urdf has already warned of xacro arguments the file does not use
        warnings.filterwarnings("ignore", ".* neither declares nor reads the xacro argument", UserWarning)
        robot = _parse(file, _xacro_arguments(xacro_args), _package_places(package_paths, file))
    parent_of = {joint.child: joint for joint in robot.joints}
    if base is None:
        base = next(link.name for link in robot.links if link.name not in parent_of)  # the one root
    link = _only_leaf(robot, base, path) if tip is None else tip
    path_joints = set()
    while link != base:
        path_joints.add(parent_of[link].name)
        link = parent_of[link].parent
    below: dict[str, list] = {}
    for joint in robot.joints:
        below.setdefault(joint.parent, []).append(joint)
    placed = {base: (0, np.eye(4))}  # link -> (chain frame, pose in the base link's coordinates at q = 0)
    pending = deque([base])  # down the tree from the base link, level by level
    while pending:
        name = pending.popleft()
        frame, pose = placed[name]
        for joint in below.get(name, []):
            if joint.name in path_joints or joint.type == "fixed":
                placed[joint.child] = (frame + int(joint.type != "fixed"), pose @ _origin(joint))
                pending.append(joint.child)
    at_zero = chain.frames(np.zeros(chain.n))
    links = {name: LinkFrame(frame, _constant(np.linalg.inv(at_zero[frame]) @ pose))
             for name, (frame, pose) in placed.items()}
    return chain, robot, links


def _constant(pose: np.ndarray) -> np.ndarray:
    """``pose``, made read-only."""
    pose.flags.writeable = False
    return pose
