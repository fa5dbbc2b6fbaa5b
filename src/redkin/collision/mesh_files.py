"""The mesh files a robot description names for its links' collision shapes (issue 40): where they are, and their
triangles.

Where.  A URDF names a mesh as ``package://PKG/path`` (a file of the ROS package ``PKG``), ``file:///path`` or a
path relative to the URDF's folder.  A package is looked up as a ``.xacro``'s ``$(find PKG)`` is
(:mod:`redkin.urdf`): in the caller's package paths first, then in the folders above the URDF (a folder with a
``package.xml`` naming it: a maker's description checked out on its own is found from its own files), then
``ROS_PACKAGE_PATH`` and, under ROS 2, the ament index.

Reading.  STL, OBJ, PLY, DAE (COLLADA) and the other formats ``trimesh`` reads (the ``mesh`` extra: ``trimesh``, and
``pycollada`` for DAE); a file of several meshes (a DAE scene) is read as one, every part placed by the file's own
transforms.  The URDF's ``scale`` multiplies the vertices along each axis of the mesh's frame.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from redkin._extras import missing_extra
from redkin.errors import RedkinError, RobotDescriptionError

#: The sizes a mesh may span once scaled [m]: anything outside is a scale gone wrong (millimetres read as metres a
#: million times over, a factor of 1e-30), and past them the covers' arithmetic loses its digits.
_SMALLEST_SPAN, _LARGEST_SPAN = 1e-6, 1e4


def mesh_path(filename: str, description: Path, places: Sequence[Path] = ()) -> Path:
    """The file a description's mesh ``filename`` names (module docstring).

    Parameters
    ----------
    filename : str
        As written: ``package://PKG/path``, ``file://path`` or a path (relative to the description's folder).
    description : pathlib.Path
        The description's file.
    places : sequence of pathlib.Path
        Folders searched first for ``PKG`` (each a package, or holding packages).

    Raises
    ------
    RobotDescriptionError
        For a package that is not found, or a file that does not exist: one line naming both and where it looked.
    """
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://"):].partition("/")
        found = Path(_package_folder(package, description, places)) / rest
    elif filename.startswith("file://"):
        found = Path(filename[len("file://"):])
    else:
        found = description.parent / filename
    problem = mesh_file_problem(filename, found)
    if problem:
        raise RobotDescriptionError(f"{description}: {problem}", str(description), filename)
    return found


def mesh_file_problem(given: str, found: Path) -> str | None:
    """What keeps the mesh file ``given`` (as written), looked for at ``found``, from being read, in words: not
    found, or a folder; ``None`` for a file."""
    if found.is_dir():
        return f"mesh file {given!r} is a folder ({str(found)!r}), not a file"
    if not found.is_file():
        return f"mesh file {given!r} not found (looked for {str(found)!r})"
    return None


def read_mesh(path: Path, scale: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The vertices (``(V, 3)``, [m] once scaled) and triangles (``(F, 3)`` indices) of a mesh file.

    Raises
    ------
    RobotDescriptionError
        For a file trimesh cannot read, one with no triangles or vertices that are not finite, and a scale that is
        not three finite numbers (or one): one line naming the file.
    RedkinError
        Where the ``mesh`` extra is not installed, with the command that installs it.
    """
    try:
        import trimesh
    except ImportError:
        raise RedkinError(missing_extra(f"reading the mesh {str(path)!r} needs trimesh", "mesh")) from None
    try:
        factors = np.ones(3) if scale is None else np.asarray(scale, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        factors = np.full(2, np.nan)  # refused below, in the same words
    if factors.shape not in ((1,), (3,)) or not np.all(np.isfinite(factors)) or np.any(factors == 0.0):
        raise RobotDescriptionError(f"{path}: mesh scale {scale!r} must be one or three finite numbers, none zero",
                                    str(path))
    try:
        mesh: Any = trimesh.load(str(path), force="mesh", process=False)  # processing drops a NaN's triangle
    except ImportError as exc:  # a format whose reader is missing (DAE: pycollada)
        raise RedkinError(missing_extra(f"reading the mesh {str(path)!r} needs {exc.name or 'a reader'}",
                                        "mesh")) from None
    except Exception as exc:  # trimesh raises what its format readers raise
        raise RobotDescriptionError(f"{path}: not a mesh trimesh can read ({type(exc).__name__}: {exc})",
                                    str(path)) from None
    faces = np.asarray(getattr(mesh, "faces", np.empty((0, 3))), dtype=np.int64)
    if len(faces) == 0:
        raise RobotDescriptionError(f"{path}: the mesh has no triangles", str(path))
    if not np.all(np.isfinite(np.asarray(mesh.vertices, dtype=float)[faces.reshape(-1)])):
        raise RobotDescriptionError(f"{path}: the mesh has vertices that are not finite", str(path))
    mesh.process()  # duplicate vertices merged, degenerate triangles dropped, as trimesh.load does by default
    vertices = np.asarray(mesh.vertices, dtype=float) * factors
    faces = np.asarray(mesh.faces, dtype=np.int64)
    if len(faces) == 0:
        raise RobotDescriptionError(f"{path}: the mesh has no triangles", str(path))
    span = float(np.ptp(vertices[faces.reshape(-1)], axis=0).max())
    if not _SMALLEST_SPAN <= span <= _LARGEST_SPAN:
        raise RobotDescriptionError(f"{path}: the mesh is {span:.3g} m across, scaled; a shape in a cell lies between "
                                    f"{_SMALLEST_SPAN:g} and {_LARGEST_SPAN:g} m (is its scale right?)", str(path))
    return vertices, faces


def _package_folder(package: str, description: Path, places: Sequence[Path]) -> str:
    """The folder of the ROS package ``package`` (module docstring)."""
    from xacrodoc.packages import PackageFinder, PackageNotFoundError

    finder = PackageFinder()
    environment = [place for place in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if place]
    if environment:
        finder.look_in(environment)
    finder.walk_up_from(description)  # each call puts its places first
    if places:
        finder.look_in([str(place) for place in places])
    try:
        return finder.get_path(package)
    except (PackageNotFoundError, ValueError):  # ValueError: a package.xml above with no single name
        searched = "".join(f"{place}, " for place in places)
        raise RobotDescriptionError(f"{description}: ROS package {package!r} of its meshes not found (searched "
                                    f"{searched}the folders above the file and ROS_PACKAGE_PATH); give its folder "
                                    "with --package-path", str(description), package) from None
