"""A cell's obstacles (issue 40): :class:`Scene`, and :func:`read_scene` for a scene file.

A scene file is YAML (JSON is YAML too), in the arm's base frame, metres::

    margin: 0.01                      # the clearance every link must keep from every obstacle (default 0)
    obstacles:
      - {name: table, type: box, center: [0.6, 0, -0.05], size: [1.2, 1.0, 0.1]}   # optional rotation: 3x3 rows
      - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.0], radius: 0.04}
      - {name: lamp, type: sphere, center: [0.3, -0.4, 0.9], radius: 0.1}
      - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1]}            # solid below
      - {name: fixture, type: mesh, file: fixture.stl, pose: [[1,0,0,0.5],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}

Each obstacle becomes one row of :mod:`redkin.collision.primitives`.  A box's ``rotation`` is given by rows, as a
matrix is written; its columns are the box's axes.  Names must be unique (an unnamed obstacle is called by its
type and place in the list, ``box 1``).  A file that cannot be used is one line naming the file, the entry and the
field.

A mesh obstacle is a mesh file (STL, OBJ, PLY, DAE: :func:`redkin.collision.mesh_files.read_mesh`, the ``mesh``
extra; a relative ``file`` is read from the scene file's folder), placed by ``pose`` (a 4x4 given by rows; default
the identity) after its optional ``scale`` (one number or three).  It becomes one to three oriented boxes that
contain it (:func:`redkin.collision.mesh_cover.covering_boxes`), named ``fixture`` where one box covers it and
``fixture [1/2]``, ``fixture [2/2]`` where more do; :attr:`Scene.notes` says how far the boxes reach beyond the mesh.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from redkin._validation import as_float_array, check_rotation
from redkin._yaml_files import read_yaml
from redkin.collision import primitives
from redkin.errors import RedkinError, RobotDescriptionError

#: Per obstacle type, its fields beside ``name`` and ``type`` (all required but a box's rotation).
_FIELDS = {
    "box": ("center", "size", "rotation"),
    "capsule": ("a", "b", "radius"),
    "sphere": ("center", "radius"),
    "plane": ("point", "normal"),
    "mesh": ("file", "pose", "scale"),
}
_OPTIONAL = {"rotation", "pose", "scale"}
#: Per obstacle type, the primitive that makes its row from those fields.
_MAKERS: dict[str, Callable[..., np.ndarray]] = {"box": primitives.box, "capsule": primitives.capsule,
                                                 "sphere": primitives.sphere, "plane": primitives.plane}


@dataclass(frozen=True, eq=False)
class Scene:
    """Obstacles in the arm's base frame and the clearance to keep from them.

    Attributes
    ----------
    names : tuple of str
        One per obstacle, unique.
    shapes : numpy.ndarray, shape (N, WIDTH)
        The obstacles as rows of :mod:`redkin.collision.primitives` (read-only).
    margin : float
        The clearance [m] >= 0 every link keeps from every obstacle.
    source : str
        Where the scene comes from (its file), for messages.
    notes : tuple of str
        What the shapes over-approximate (a mesh obstacle's boxes) and by how much, one line each.
    """

    names: tuple[str, ...]
    shapes: np.ndarray
    margin: float = 0.0
    source: str = ""
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        shapes = as_float_array(self.shapes, "shapes")
        if shapes.size == 0:
            shapes = shapes.reshape(0, primitives.WIDTH)
        if shapes.ndim != 2 or shapes.shape[1] != primitives.WIDTH:
            raise RedkinError(f"shapes must have shape (N, {primitives.WIDTH}), got {shapes.shape}")
        shapes = shapes.copy()
        if not np.isfinite(shapes).all() or not np.isin(shapes[:, 0], list(primitives.KIND_NAMES)).all():
            raise RedkinError("shapes must be finite rows of redkin.collision.primitives with a known kind")
        names = tuple(str(name) for name in self.names)
        if len(names) != len(shapes):
            raise RedkinError(f"names must have one entry per shape ({len(shapes)}), got {len(names)}")
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise RedkinError(f"obstacle names must be unique: {', '.join(map(repr, repeated))} repeated")
        margin = _number(self.margin, "margin")
        object.__setattr__(self, "notes", tuple(str(note) for note in self.notes))
        shapes.flags.writeable = False
        object.__setattr__(self, "names", names)
        object.__setattr__(self, "shapes", shapes)
        object.__setattr__(self, "margin", margin)

    def __len__(self) -> int:
        return len(self.names)

    def shape(self, name: str) -> np.ndarray:
        """The row of the obstacle called ``name``."""
        if name not in self.names:
            raise RedkinError(f"no obstacle {name!r} in the scene (it has {', '.join(self.names) or 'none'})")
        return self.shapes[self.names.index(name)]


def read_scene(file: str | os.PathLike) -> Scene:
    """The scene of a YAML or JSON file (module docstring).

    Raises
    ------
    RobotDescriptionError
        For a missing or unreadable file, one that is not YAML or JSON, an unknown key, an obstacle of an unknown
        type, a missing, unknown or malformed field, or repeated names: one line naming the file, the obstacle and
        the field.
    """
    source = str(file)
    data = read_yaml(file, "scene file")
    return scene_of(data, source)


def scene_of(data: Any, source: str = "") -> Scene:
    """The scene of the data of a scene file (a mapping with ``obstacles`` and an optional ``margin``), as
    :func:`read_scene` reads it; ``source`` names it in errors."""
    where = f"scene file {source!r}" if source else "scene"
    if not isinstance(data, dict):
        raise RobotDescriptionError(f"{where}: expected a mapping with obstacles (and an optional margin)", source)
    unknown = sorted(set(map(str, data)) - {"obstacles", "margin"})
    if unknown:
        raise RobotDescriptionError(f"{where}: unknown key {unknown[0]!r} (a scene has obstacles and margin)",
                                    source, unknown[0])
    entries = data.get("obstacles", [])
    if not isinstance(entries, list):
        raise RobotDescriptionError(f"{where}: obstacles must be a list of obstacles", source, "obstacles")
    try:
        margin = _number(data.get("margin", 0.0), "margin")
    except RedkinError as exc:
        raise RobotDescriptionError(f"{where}: {exc}", source, "margin") from None
    names: list[str] = []
    rows: list[np.ndarray] = []
    notes: list[str] = []
    for index, entry in enumerate(entries, start=1):
        shapes, note = _obstacle(entry, index, where, source)
        names.extend(name for name, _ in shapes)
        rows.extend(row for _, row in shapes)
        if note:
            notes.append(note)
    try:
        return Scene(tuple(names), np.array(rows).reshape(-1, primitives.WIDTH), margin, source, tuple(notes))
    except RedkinError as exc:
        raise RobotDescriptionError(f"{where}: {exc}", source) from None


def _obstacle(entry: Any, index: int, where: str, source: str) -> tuple[list[tuple[str, np.ndarray]], str]:
    """The names and rows of the ``index``-th obstacle of a scene file (one, or a mesh's boxes), and a note on
    what they over-approximate ('' for a primitive, which its row is)."""
    if not isinstance(entry, dict):
        raise RobotDescriptionError(f"{where}: obstacle {index} must be a mapping with a type and its fields",
                                    source, str(index))
    kind = entry.get("type")
    label = f"obstacle {index}" + (f" ({entry['name']!r})" if "name" in entry else "")
    if kind not in _FIELDS:
        raise RobotDescriptionError(f"{where}: {label}: type must be one of {', '.join(_FIELDS)}, got {kind!r}",
                                    source, "type")
    fields = _FIELDS[kind]
    unknown = sorted(set(map(str, entry)) - set(fields) - {"name", "type"})
    if unknown:
        raise RobotDescriptionError(f"{where}: {label}: unknown field {unknown[0]!r} (a {kind} has "
                                    f"{', '.join(fields)})", source, unknown[0])
    missing = [field for field in fields if field not in entry and field not in _OPTIONAL]
    if missing:
        raise RobotDescriptionError(f"{where}: {label}: missing field {missing[0]!r}", source, missing[0])
    if not isinstance(entry.get("name", ""), str | int | float) or isinstance(entry.get("name"), bool):
        raise RobotDescriptionError(f"{where}: {label}: name must be text, got {entry['name']!r}", source, "name")
    name = str(entry.get("name", f"{kind} {index}"))
    if kind == "mesh":
        return _mesh_obstacle(entry, name, f"{where}: {label}", source)
    try:
        row = _MAKERS[kind](**{field: entry[field] for field in fields if field in entry})
    except (RedkinError, TypeError) as exc:
        raise RobotDescriptionError(f"{where}: {label}: {exc}", source, str(index)) from None
    return [(name, row)], ""


def _mesh_obstacle(entry: dict, name: str, label: str, source: str) -> tuple[list[tuple[str, np.ndarray]], str]:
    """The boxes of a mesh obstacle (module docstring), named, and the note on how far they reach beyond it."""
    from pathlib import Path

    from redkin.collision.mesh_cache import covered_boxes
    from redkin.collision.mesh_files import mesh_file_problem

    given = entry["file"]
    if not isinstance(given, str) or not given:
        raise RobotDescriptionError(f"{label}: file must be a mesh file's path, got {given!r}", source, "file")
    file = Path(given) if Path(given).is_absolute() or not source else Path(source).parent / given
    problem = mesh_file_problem(given, file)
    if problem:
        raise RobotDescriptionError(f"{label}: {problem}", source, "file")
    try:
        pose = np.eye(4) if "pose" not in entry else as_float_array(entry["pose"], "pose")
        if pose.shape != (4, 4) or not np.array_equal(pose[3], [0.0, 0.0, 0.0, 1.0]):
            raise RedkinError(f"pose must be a 4x4 transform given by rows, last row 0 0 0 1, got shape {pose.shape}")
        if not np.all(np.isfinite(pose)):
            raise RedkinError("pose must be finite")
        rotation = check_rotation(pose[:3, :3], "pose rotation")
        boxes = covered_boxes(file, entry.get("scale"))  # in the mesh's frame, then placed by the pose
    except RobotDescriptionError as exc:  # the mesh file's own: it names the file
        raise RobotDescriptionError(f"{label}: {exc}", source, "scale" if "scale" in str(exc) else "file") from None
    except (RedkinError, ValueError) as exc:
        raise RobotDescriptionError(f"{label}: {exc}", source, "pose" if "pose" in str(exc) else "file") from None
    names = [name] if len(boxes) == 1 else [f"{name} [{k}/{len(boxes)}]" for k in range(1, len(boxes) + 1)]
    rows = [(part, primitives.box(rotation @ box.center + pose[:3, 3], box.size, rotation @ box.rotation))
            for part, box in zip(names, boxes)]
    reach = max(box.reach for box in boxes)
    beyond = "its convex hull" if len(boxes) == 1 else "the convex hull of the part each covers"
    return rows, (f"obstacle {name!r}: mesh {given!r} covered by {len(boxes)} box{'es' if len(boxes) > 1 else ''} "
                  f"reaching up to {reach:.3g} m beyond {beyond}")


def _number(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0:
        raise RedkinError(f"{name} must be a finite number >= 0 (metres), got {value!r}")
    return float(value)
