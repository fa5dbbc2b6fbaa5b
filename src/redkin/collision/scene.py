"""A cell's obstacles (issue 40): :class:`Scene`, and :func:`read_scene` for a scene file.

A scene file is YAML (JSON is YAML too), in the arm's base frame, metres::

    margin: 0.01                      # the clearance every link must keep from every obstacle (default 0)
    obstacles:
      - {name: table, type: box, center: [0.6, 0, -0.05], size: [1.2, 1.0, 0.1]}   # optional rotation: 3x3 rows
      - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.0], radius: 0.04}
      - {name: lamp, type: sphere, center: [0.3, -0.4, 0.9], radius: 0.1}
      - {name: floor, type: plane, point: [0, 0, 0], normal: [0, 0, 1]}            # solid below

Each obstacle becomes one row of :mod:`redkin.collision.primitives`.  A box's ``rotation`` is given by rows, as a
matrix is written; its columns are the box's axes.  Names must be unique (an unnamed obstacle is called by its
type and place in the list, ``box 1``).  A file that cannot be used is one line naming the file, the entry and the
field.  Mesh obstacles (``type: mesh``) are refused in words: reading meshes is a later step of issue 40.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from redkin._validation import as_float_array
from redkin._yaml_files import read_yaml
from redkin.collision import primitives
from redkin.errors import RedkinError, RobotDescriptionError

#: Per obstacle type, its fields beside ``name`` and ``type`` (all required but a box's rotation).
_FIELDS = {
    "box": ("center", "size", "rotation"),
    "capsule": ("a", "b", "radius"),
    "sphere": ("center", "radius"),
    "plane": ("point", "normal"),
}
_OPTIONAL = {"rotation"}
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
    """

    names: tuple[str, ...]
    shapes: np.ndarray
    margin: float = 0.0
    source: str = ""

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
    names, rows = [], []
    for index, entry in enumerate(entries, start=1):
        name, row = _obstacle(entry, index, where, source)
        names.append(name)
        rows.append(row)
    try:
        return Scene(tuple(names), np.array(rows).reshape(-1, primitives.WIDTH), margin, source)
    except RedkinError as exc:
        raise RobotDescriptionError(f"{where}: {exc}", source) from None


def _obstacle(entry: Any, index: int, where: str, source: str) -> tuple[str, np.ndarray]:
    """The name and row of the ``index``-th obstacle of a scene file."""
    if not isinstance(entry, dict):
        raise RobotDescriptionError(f"{where}: obstacle {index} must be a mapping with a type and its fields",
                                    source, str(index))
    kind = entry.get("type")
    label = f"obstacle {index}" + (f" ({entry['name']!r})" if "name" in entry else "")
    if kind == "mesh":
        raise RobotDescriptionError(f"{where}: {label}: mesh obstacles are not read yet (issue 40's meshes, through "
                                    "trimesh and coal); give boxes, capsules, spheres or planes", source, "type")
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
    try:
        row = _MAKERS[kind](**{field: entry[field] for field in fields if field in entry})
    except (RedkinError, TypeError) as exc:
        raise RobotDescriptionError(f"{where}: {label}: {exc}", source, str(index)) from None
    return str(entry.get("name", f"{kind} {index}")), row


def _number(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0:
        raise RedkinError(f"{name} must be a finite number >= 0 (metres), got {value!r}")
    return float(value)
