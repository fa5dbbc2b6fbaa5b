"""URDF import: the serial chain between two links of a URDF, as exact DH rows.

The file is read with ROS's own pure-Python parser, ``urdfdom-py``
(``urdf_parser_py``; the optional extra ``redkin[urdf]``).  It needs only
lxml and PyYAML, where ``yourdfpy`` also pulls trimesh and its mesh stack,
none of which a kinematic chain uses.  A ``.xacro`` file is expanded first
with ``xacrodoc`` (ROS's xacro without a ROS install; the extra
``redkin[xacro]``).

Conversion.  Joint ``k`` of the chain turns the rest of the chain about a
line: at ``q = 0`` that line passes through the origin of the joint's frame
with the direction of its ``<axis>``, both mapped to the base link by the
product of the ``<origin>`` transforms before it (fixed joints fold into
that product).  Standard DH rows reproduce any chain of such lines exactly:
frame ``k - 1`` has its z axis on line ``k`` and its x axis on the common
normal of lines ``k - 1`` and ``k``; with ``theta_k = offset_k + q_k`` turning
about the same line by the same angle as the URDF joint, every downstream
body moves the same way, so ``base @ A_1 ... A_n @ tool`` equals the URDF's
tip pose for every ``q``.  Parallel axes take the common normal through the
previous frame's origin (``d = 0``), intersecting axes their intersection
(``a = 0``), and collinear axes repeat the previous frame.  The last row is a
pure turn (``a = d = alpha = 0``), the tool maps it to the tip link, and the
base maps the base link to frame 0.  Axes are taken as written (``0 0 -1``
or oblique), so every sign is +1 and the joint values are the URDF's own.

Joint frames of the chain (:meth:`SerialChain.frames`) are the DH frames, not
the URDF's link frames; the end pose is the tip link's.  Exactness has one
numerical limit, that of DH rows themselves: axes a tiny tilt ``t`` off
parallel (``rpy="1.5708 0 0"`` for pi/2 gives ``t ~ 4e-6``) have a common
normal ``offset / t`` away, and rounding then costs ``eps * offset / t``
(1e-11 m there; at most about 1e-8 m, near ``t ~ 1e-8``, see
:data:`redkin._joint_lines.PARALLEL_TOLERANCE`).
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import numpy as np

from redkin._joint_lines import dh_rows_from_lines
from redkin.chain import SerialChain
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.so3 import xyz_fixed_to_matrix

_UNSUPPORTED = {"prismatic", "floating", "planar"}


def load_urdf(path: str | Path, base: str | None = None, tip: str | None = None) -> SerialChain:
    """The chain from link ``base`` to link ``tip`` of the URDF at ``path``.

    Parameters
    ----------
    path : str or Path
        A ``.urdf`` file, or a ``.xacro`` file that expands to one.
    base, tip : str, optional
        Link names.  ``base`` defaults to the root link; ``tip`` to the one
        leaf below ``base`` (a tree with several leaves must name it).

    Returns
    -------
    SerialChain
        Standard DH rows (see the module docstring), named after the robot,
        with the URDF's limits (continuous joints unlimited).

    Raises
    ------
    RobotDescriptionError
        For a missing or malformed file, an unknown link, a tree without a
        single tip, links not on one path, and prismatic, floating, planar or
        mimic joints (named); its ``path`` and ``key`` (the joint or link) say where.
    RedkinError
        When the ``urdf`` (or, for ``.xacro``, the ``xacro``) extra is not installed.
    """
    robot = _parse(Path(path))
    links = {link.name for link in robot.links}
    if not links:
        raise RobotDescriptionError(f"{path}: the URDF has no links", path=str(path))
    parent_of = {joint.child: joint for joint in robot.joints}
    roots = sorted(links - set(parent_of))
    base = base if base is not None else (roots[0] if len(roots) == 1 else None)
    if base is None:
        raise RobotDescriptionError(f"{path}: the URDF has {len(roots)} root links ({', '.join(roots)}); "
                                    "name one with --base", path=str(path))
    for name, role in ((base, "base"), (tip, "tip")):
        if name is not None and name not in links:
            raise RobotDescriptionError(f"{path}: no link named {name!r} for the {role} "
                                        f"(links: {', '.join(sorted(links))})", path=str(path), key=str(name))
    if tip is None:
        tip = _only_leaf(robot, base, path)
    joints = []
    link = tip
    while link != base:
        if link not in parent_of:
            raise RobotDescriptionError(f"{path}: link {tip!r} is not below link {base!r}", path=str(path),
                                        key=str(tip))
        joint = parent_of[link]
        joints.append(joint)
        link = joint.parent
    joints.reverse()
    return _chain(robot.name or Path(path).stem, joints, str(path), base, tip)


def _parse(path: Path):
    try:
        from urdf_parser_py.urdf import URDF
    except ImportError:
        raise RedkinError("reading a URDF needs the urdf extra: pip install 'redkin[urdf]'") from None
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RobotDescriptionError(f"cannot read robot file {str(path)!r}: {exc.strerror or exc}",
                                    path=str(path)) from None
    if path.suffix.lower() == ".xacro":
        text = _expand_xacro(path)
    noise = io.StringIO()
    try:
        with contextlib.redirect_stderr(noise):  # the parser prints warnings of its own
            return URDF.from_xml_string(text)
    except Exception as exc:  # lxml and the parser raise many kinds; all mean a malformed file
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise RobotDescriptionError(f"{path}: malformed URDF: {reason}", path=str(path)) from None


def _expand_xacro(path: Path) -> str:
    """The URDF text a ``.xacro`` file expands to (macros, properties, includes relative to the file)."""
    try:
        from xacrodoc import XacroDoc
    except ImportError:
        raise RedkinError("reading a .xacro file needs the xacro extra: pip install 'redkin[xacro]'") from None
    noise = io.StringIO()
    try:
        with contextlib.redirect_stderr(noise), contextlib.redirect_stdout(noise):  # xacro prints warnings
            return XacroDoc.from_file(str(path)).to_urdf_string()
    except Exception as exc:  # xacro raises its own exceptions and lxml's; all mean a malformed file
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise RobotDescriptionError(f"{path}: malformed xacro: {reason}", path=str(path)) from None


def _only_leaf(robot, base: str, path) -> str:
    children: dict[str, list[str]] = {}
    for joint in robot.joints:
        children.setdefault(joint.parent, []).append(joint.child)
    leaves, stack = [], [base]
    while stack:
        link = stack.pop()
        below = children.get(link, [])
        if not below:
            leaves.append(link)
        stack.extend(below)
    if len(leaves) != 1:
        raise RobotDescriptionError(f"{path}: the tree below {base!r} has {len(leaves)} tips "
                                    f"({', '.join(sorted(leaves))}); name one with --tip", path=str(path), key=base)
    return leaves[0]


def _origin(joint) -> np.ndarray:
    """The joint's ``<origin>`` as a 4x4 transform (roll-pitch-yaw about fixed x, y, z)."""
    pose = np.eye(4)
    if joint.origin is not None:
        xyz = np.zeros(3) if joint.origin.xyz is None else np.asarray(joint.origin.xyz, dtype=float)
        rpy = np.zeros(3) if joint.origin.rpy is None else np.asarray(joint.origin.rpy, dtype=float)
        pose[:3, :3] = xyz_fixed_to_matrix(rpy[::-1])  # URDF rpy: Rz(yaw) Ry(pitch) Rx(roll)
        pose[:3, 3] = xyz
    return pose


def _chain(name: str, joints: list, path: str, base_link: str, tip_link: str) -> SerialChain:
    """Exact DH rows for the joints from the base link to the tip link (see the module docstring)."""
    pose = np.eye(4)  # base link -> current frame at q = 0
    points, directions, lower, upper, names = [], [], [], [], []
    for joint in joints:
        if joint.type in _UNSUPPORTED:
            raise RobotDescriptionError(f"joint {joint.name!r} is {joint.type}: redkin chains have revolute "
                                        "joints only", path=path, key=joint.name)
        if joint.mimic is not None:
            raise RobotDescriptionError(f"joint {joint.name!r} mimics {joint.mimic.joint!r}: mimic joints are not "
                                        "supported", path=path, key=joint.name)
        pose = pose @ _origin(joint)
        if joint.type == "fixed":
            continue
        if joint.type not in ("revolute", "continuous"):
            raise RobotDescriptionError(f"joint {joint.name!r} has unknown type {joint.type!r}",
                                        path=path, key=joint.name)
        axis = np.array([1.0, 0.0, 0.0] if joint.axis is None else joint.axis, dtype=float)
        if not np.all(np.isfinite(axis)) or np.linalg.norm(axis) < 1e-12:
            raise RobotDescriptionError(f"joint {joint.name!r}: axis must be a non-zero finite vector, "
                                        f"got {axis.tolist()}", path=path, key=joint.name)
        names.append(joint.name)
        points.append(pose[:3, 3].copy())
        directions.append(pose[:3, :3] @ (axis / np.linalg.norm(axis)))
        limit = joint.limit if joint.type == "revolute" else None
        if joint.type == "revolute" and (limit is None or limit.lower is None or limit.upper is None):
            raise RobotDescriptionError(f"revolute joint {joint.name!r} needs <limit lower=... upper=...>",
                                        path=path, key=joint.name)
        lower.append(-np.inf if limit is None else float(limit.lower))
        upper.append(np.inf if limit is None else float(limit.upper))
    if not points:
        raise RobotDescriptionError(f"no revolute joint between links {base_link!r} and {tip_link!r}", path=path)
    rows, base, last = dh_rows_from_lines(np.array(points), np.array(directions))
    return SerialChain(
        a=rows[:, 0], alpha=rows[:, 1], d=rows[:, 2], offset=rows[:, 3], convention="dh",
        lower=lower, upper=upper, base=base, tool=np.linalg.inv(last) @ pose,
        name=name, source=f"URDF {path}, links {base_link} -> {tip_link}", joint_names=names,
    )
