"""URDF import: the serial chain between two links of a URDF, as exact DH rows.

The file is read with ROS's own pure-Python parser, ``urdfdom-py``
(``urdf_parser_py``, a dependency of redkin).  It needs only lxml and PyYAML,
where ``yourdfpy`` also pulls trimesh and its mesh stack, none of which a
kinematic chain uses.  A ``.xacro`` file is expanded first with ``xacrodoc``
(ROS's xacro without a ROS install, also a dependency), with the caller's
xacro arguments, includes relative to the file, and ``$(find PKG)`` looked
up in the caller's package paths, the folders above the file,
``ROS_PACKAGE_PATH`` and (under ROS 2) the ament index.  A ``.xacro`` is
code: it can read files and environment variables and evaluate Python
expressions (``${...}``, ``$(eval ...)``; xacro restricts them, which is no
sandbox), so it is trusted input.

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
import os
import re
import threading
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from redkin._joint_lines import dh_rows_from_lines
from redkin.chain import SerialChain
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.examples import resolve
from redkin.so3 import xyz_fixed_to_matrix

_UNSUPPORTED = {"prismatic", "floating", "planar"}


def load_urdf(path: str | Path, base: str | None = None, tip: str | None = None, *,
              xacro_args: Mapping[str, str | int | float | bool] | None = None,
              package_paths: str | os.PathLike | Iterable[str | os.PathLike] = ()) -> SerialChain:
    """The chain from link ``base`` to link ``tip`` of the URDF at ``path``.

    Parameters
    ----------
    path : str or Path
        A ``.urdf`` file, or a ``.xacro`` file that expands to one; a path
        that does not exist may name a shipped example
        (:func:`redkin.examples.resolve`: ``examples/iiwa14.urdf``).
    base, tip : str, optional
        Link names.  ``base`` defaults to the root link; ``tip`` to the one
        leaf below ``base`` (a tree with several leaves must name it).
    xacro_args : mapping of str to str, optional
        For a ``.xacro``: the values of its ``<xacro:arg>`` arguments, as
        ``NAME:=VALUE`` on xacro's command line (numbers and booleans are
        written as text, ``True`` as ``true``).  An argument the file neither
        declares nor reads is ignored, as by xacro, with a ``UserWarning``.
    package_paths : path or iterable of paths, optional
        Folders searched first for the ROS packages of a ``.xacro``'s
        ``$(find PKG)`` (a folder that is a package, or holds packages, each
        a folder with a ``package.xml`` naming it).  Then come the folders
        above the file, ``ROS_PACKAGE_PATH`` and, under ROS 2, the ament index.
        The chain reads no ``package://`` mesh file; the body of the
        collision elements does (:func:`redkin.collision.urdf_body`), from the
        same places, so a plain URDF takes them too.

    Returns
    -------
    SerialChain
        Standard DH rows (see the module docstring), named after the robot,
        with the URDF's limits (continuous joints unlimited).

    Raises
    ------
    RobotDescriptionError
        For a missing or malformed file (the whole reason, in one line), a
        missing ROS package (named), an unknown link, a tree without a single
        tip, links not on one path, and prismatic, floating, planar or mimic
        joints (named); its ``path`` and ``key`` (the joint or link) say where.
        Also for xacro arguments given with a plain URDF, and a package path
        that is not a folder.
    RedkinError
        When ``xacro_args`` is not a mapping of names to values.

    Notes
    -----
    A ``.xacro`` is code: it can read any file and environment variable the
    process can, and evaluate Python expressions.  Load only files you trust.
    """
    file = resolve(path)
    arguments = _xacro_arguments(xacro_args)
    places = _package_places(package_paths, file)
    if file.suffix.lower() != ".xacro":
        if arguments:
            raise RobotDescriptionError(f"{path}: xacro arguments apply to .xacro files only; a URDF is read as it "
                                        "is written", path=str(path))
    robot = _parse(file, arguments, places)
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
    return _chain(robot.name or file.stem, joints, str(path), base, tip, arguments)


def _xacro_arguments(xacro_args: Mapping[str, str | int | float | bool] | None) -> dict[str, str]:
    """The xacro arguments as text, checked: a mapping of non-empty names to strings, numbers or booleans."""
    if xacro_args is None:
        return {}
    if not isinstance(xacro_args, Mapping):
        raise RedkinError(f"xacro_args must be a mapping of NAME -> VALUE, got {type(xacro_args).__name__}")
    arguments = {}
    for name, value in xacro_args.items():
        if not isinstance(name, str) or not name.strip() or ":=" in name:
            raise RedkinError(f"xacro_args: an argument name must be a non-empty string without ':=', got {name!r}")
        if isinstance(value, bool):
            value = "true" if value else "false"
        elif isinstance(value, (int, float)):
            value = repr(value)
        elif not isinstance(value, str):
            raise RedkinError(f"xacro_args[{name!r}] must be a string, number or boolean, got "
                              f"{type(value).__name__}")
        arguments[name] = value
    return arguments


def _package_places(package_paths: str | os.PathLike | Iterable[str | os.PathLike], file: Path) -> list[Path]:
    """The package paths as folders that exist (one path alone is taken as a list of one)."""
    paths = [package_paths] if isinstance(package_paths, (str, os.PathLike)) else list(package_paths)
    for place in paths:
        if not Path(place).is_dir():
            raise RobotDescriptionError(f"package path {str(place)!r} is not a folder", path=str(file),
                                        key=str(place))
    return [Path(place) for place in paths]


def _parse(path: Path, arguments: dict[str, str], places: list[Path]):
    from urdf_parser_py.urdf import URDF
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RobotDescriptionError(f"cannot read robot file {str(path)!r}: {exc.strerror or exc}",
                                    path=str(path)) from None
    if path.suffix.lower() == ".xacro":
        text = _expand_xacro(path, arguments, places)
        root = re.search(r"<\s*([A-Za-z_][\w:.-]*)[\s>/]", re.sub(r"<\?.*?\?>|<!--.*?-->", "", text, flags=re.S))
        if root is not None and root[1] != "robot":
            raise RobotDescriptionError(f"{path}: it expands to no robot (its root element is <{root[1]}>, not "
                                        "<robot>): a file of macros only; load the .xacro that calls them",
                                        path=str(path))
    noise = io.StringIO()
    try:
        with contextlib.redirect_stderr(noise):  # the parser prints warnings of its own
            return URDF.from_xml_string(_speeds_written(text))
    except Exception as exc:  # lxml and the parser raise many kinds; all mean a malformed file
        raise RobotDescriptionError(f"{path}: malformed URDF{_urdf_reason(exc)}", path=str(path)) from None


def _speeds_written(text: str) -> str:
    """The URDF text with ``velocity="0"`` (unknown, as the importer reads it) in each joint's ``<limit>`` that has
    no velocity: the URDF format requires the attribute, and ``urdf_parser_py`` refuses a file without it, but many
    kinematics-only files leave it out.  Text with a velocity in every limit is returned as it is."""
    from lxml import etree  # type: ignore[import-untyped]  # urdf_parser_py's own XML library

    root = etree.fromstring(text)
    missing = [limit for limit in root.iterfind("joint/limit") if "velocity" not in limit.attrib]
    if not missing:
        return text
    for limit in missing:
        limit.set("velocity", "0")
    return etree.tostring(root, encoding="unicode")


def _one_line(text: str) -> str:
    """A message of several lines as one: its lines joined by single spaces."""
    return " ".join(text.split())


def _urdf_reason(exc: Exception) -> str:
    """The parser's reason in one line, after ``malformed URDF``: ``" at /robot/joint[@name='j']: could not
    convert ..."`` for urdf_parser_py's ``ParseError in <where>:\n<why>``, ``": <why>"`` otherwise (lxml's
    ``(<string>, line N)`` dropped: the line is already in the reason)."""
    text = _one_line(str(exc)) or type(exc).__name__
    text = re.sub(r" \(<string>, line \d+\)$", "", text)
    located = re.match(r"ParseError in (\S+?):\s*(.*)$", text)
    return f" at {located[1]}: {located[2]}" if located else f": {text}"


#: xacro and xacrodoc keep their state in module globals (the file stack, the package finder): one expansion at a
#: time in this process.
_XACRO_LOCK = threading.Lock()


class _SeenArguments(dict):
    """The xacro arguments, noting each name xacro looks up: ``in`` where the file declares one (``<xacro:arg>``),
    ``[]`` where it reads one (``$(arg NAME)``)."""

    def __init__(self, arguments: dict[str, str]) -> None:
        super().__init__(arguments)
        self.seen: set[str] = set()

    def __contains__(self, name: object) -> bool:
        self.seen.add(str(name))
        return super().__contains__(name)

    def __getitem__(self, name: str) -> str:
        self.seen.add(name)
        return super().__getitem__(name)


def _expand_xacro(path: Path, arguments: dict[str, str], places: list[Path]) -> str:
    """The URDF text a ``.xacro`` file expands to (macros, properties, arguments, includes relative to the file).

    ``package://`` file names (meshes) are left as written: the chain reads none.  Each expansion starts from a
    fresh package finder, so that no package found for an earlier file, nor a place searched for it, leaks into
    this one: the places, first searched first, are ``places``, the folders above the file, ``ROS_PACKAGE_PATH``,
    and xacrodoc's default (the ament index under ROS 2, else ``ROS_PACKAGE_PATH`` again).
    """
    import xacro  # type: ignore[import-untyped]
    from xacrodoc import XacroDoc, packages

    given = _SeenArguments(arguments)
    environment = [place for place in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if place]
    noise = io.StringIO()
    with _XACRO_LOCK:
        packages.reset()
        try:
            if environment:
                packages.look_in(environment)
            packages.walk_up_from(path)  # each call puts its places first
            if places:
                packages.look_in([str(place) for place in places])
            xacro.init_stacks(str(path.resolve()))  # includes relative to this file, not the working directory
            with contextlib.redirect_stderr(noise), contextlib.redirect_stdout(noise):  # xacro prints warnings
                text = XacroDoc.from_file(str(path), walk_up=False, subargs=given,
                                          resolve_packages=False).to_urdf_string()
        except Exception as exc:  # xacro raises its own exceptions and lxml's; all mean a file we cannot expand
            raise RobotDescriptionError(_xacro_failure(path, exc, places), path=str(path)) from None
        finally:
            packages.reset()
            xacro.init_stacks(None)
    for name in arguments:
        if name not in given.seen:
            known = sorted(given.seen | set(given) - set(arguments))
            warnings.warn(f"{path} neither declares nor reads the xacro argument {name!r}: ignored (its arguments: "
                          f"{', '.join(known) or 'none'})", UserWarning, stacklevel=4)
    return text


def _xacro_failure(path: Path, exc: BaseException, places: list[Path]) -> str:
    """The message of a failed expansion in one line: the package missing, or xacro's whole reason."""
    from xacro.substitution_args import ArgException  # type: ignore[import-untyped]
    from xacrodoc.packages import PackageNotFoundError

    causes = [exc]
    while len(causes) < 20:  # xacro wraps the original in ``exc``; Python chains it as the cause or context
        last = causes[-1]
        inner = getattr(last, "exc", None) or last.__cause__ or last.__context__
        if not isinstance(inner, BaseException) or inner in causes:
            break
        causes.append(inner)
    missing = next((cause for cause in causes if isinstance(cause, PackageNotFoundError)), None)
    if missing is not None:
        package = " ".join(str(arg) for arg in missing.args)
        searched = "".join(f"{place}, " for place in places)
        environment = "" if os.environ.get("ROS_PACKAGE_PATH") else " (unset)"
        return (f"{path}: ROS package {package!r} not found (searched {searched}the folders above the file and "
                f"ROS_PACKAGE_PATH{environment}): give the folder that holds it with --package-path DIR "
                "(package_paths in Python) or add it to ROS_PACKAGE_PATH")
    undefined = next((cause for cause in causes if isinstance(cause, ArgException)), None)
    if undefined is not None:
        name = " ".join(str(arg) for arg in undefined.args)
        return (f"{path}: the xacro argument {name!r} has no value and no default: give it with --xacro-arg "
                f"{name}:=VALUE (xacro_args in Python)")
    inner = getattr(exc, "exc", None)
    text = str(exc)
    if isinstance(inner, BaseException) and exc.args and exc.args[0] == f"{type(inner)}: {inner}":
        text = f"{type(inner).__name__}: {inner}"  # xacro's wrapper repeats the reason after the class's repr
    elif isinstance(inner, OSError) and exc.args:
        text = str(exc.args[0])  # "No such file or directory: <file>", without errno's repeat of it
    return f"{path}: malformed xacro: {_one_line(text) or type(exc).__name__}"


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


def _chain(name: str, joints: list, path: str, base_link: str, tip_link: str,
           arguments: dict[str, str]) -> SerialChain:
    """Exact DH rows for the joints from the base link to the tip link (see the module docstring); the source
    names the file, the xacro ``arguments`` it was expanded with, and the links."""
    pose = np.eye(4)  # base link -> current frame at q = 0
    points, directions, lower, upper, speeds, names = [], [], [], [], [], []
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
        speeds.append(_speed(joint, path))
    if not points:
        raise RobotDescriptionError(f"no revolute joint between links {base_link!r} and {tip_link!r}", path=path)
    rows, base, last = dh_rows_from_lines(np.array(points), np.array(directions))
    given = " (xacro " + " ".join(f"{key}:={value}" for key, value in arguments.items()) + ")" if arguments else ""
    return SerialChain(
        a=rows[:, 0], alpha=rows[:, 1], d=rows[:, 2], offset=rows[:, 3], convention="dh",
        lower=lower, upper=upper, base=base, tool=np.linalg.inv(last) @ pose,
        name=name, source=f"URDF {path}{given}, links {base_link} -> {tip_link}", joint_names=names, velocity=speeds,
    )


def _speed(joint, path: str) -> float:
    """The joint's ``<limit velocity=...>`` in rad/s, ``inf`` (unknown) where the file gives none or 0."""
    speed = np.inf if joint.limit is None else float(joint.limit.velocity)
    if np.isnan(speed) or speed < 0.0:
        raise RobotDescriptionError(f"joint {joint.name!r}: <limit velocity> must be >= 0 rad/s (0 where unknown), "
                                    f"got {speed:g}", path=path, key=joint.name)
    return np.inf if speed == 0.0 else speed
