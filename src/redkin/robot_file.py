"""Robot files: a user's own arm as a TOML or JSON description.

The format (TOML shown; JSON has the same keys)::

    name = "my-arm"
    convention = "dh"          # "dh" (standard) or "mdh" (modified, Craig)
    angle_unit = "deg"         # "deg" or "rad": alpha, offset, limits, base/tool angles
    length_unit = "m"          # "m" or "mm": a, d, base/tool translations
    source = "where the numbers come from"

    [[joint]]                  # one table per joint, base to tip
    a = 0.0
    alpha = -90
    d = 0.317
    offset = 0                 # optional, theta = offset + sign * q
    sign = 1                   # optional, +1 or -1
    lower = -90                # optional limits on q
    upper = 90

    [tool]                     # optional; [base] has the same keys
    translation = [0, 0, 0.1]
    xyz_fixed_angles = [0, 0, 0]   # optional: Rz(alpha) Ry(beta) Rx(gamma)

``examples/pa10.toml`` (shipped with redkin, :mod:`redkin.examples`) is a complete example.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from redkin.chain import SerialChain
from redkin.errors import RobotDescriptionError
from redkin.examples import resolve
from redkin.so3 import xyz_fixed_to_matrix

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

_TOP_KEYS = {"name", "convention", "angle_unit", "length_unit", "source", "joint", "base", "tool"}
_JOINT_KEYS = {"a", "alpha", "d", "offset", "sign", "lower", "upper"}
_TRANSFORM_KEYS = {"translation", "xyz_fixed_angles"}
_ANGLE_SCALE = {"deg": np.pi / 180.0, "rad": 1.0}
_LENGTH_SCALE = {"m": 1.0, "mm": 1e-3}


def load_robot(path: str | Path) -> SerialChain:
    """Read a robot file (``.toml`` or ``.json``) into a :class:`SerialChain`.

    Parameters
    ----------
    path : str or Path
        The file; a path that does not exist may name a shipped example (:func:`redkin.examples.resolve`:
        ``examples/pa10.toml``).

    Raises
    ------
    RobotDescriptionError
        If the file is missing, cannot be parsed, or does not follow the format;
        the message names the file and the offending key (also its ``path`` and ``key``).
    """
    path = resolve(path)
    if path.is_dir():
        raise RobotDescriptionError(f"robot file {str(path)!r} is a folder, not a file", path=str(path))
    if not path.is_file():
        raise RobotDescriptionError(f"robot file {str(path)!r} does not exist", path=str(path))
    text = path.read_text(encoding="utf-8")
    try:
        if path.suffix.lower() == ".json":
            data = json.loads(text)
        else:
            data = tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as exc:
        raise RobotDescriptionError(f"robot file {str(path)!r} cannot be parsed: {exc}", path=str(path)) from exc
    try:
        return _robot_from_dict(data, default_name=path.stem)
    except ValueError as exc:
        raise RobotDescriptionError(f"robot file {str(path)!r}: {exc}", path=str(path),
                                    key=getattr(exc, "key", "")) from exc


def _robot_from_dict(data: Any, default_name: str = "robot") -> SerialChain:
    """Build a chain from the parsed content of a robot file (see module docstring)."""
    if not isinstance(data, dict):
        raise RobotDescriptionError("the top level must be a table of keys")
    _no_unknown(data, _TOP_KEYS, "top level")
    convention = data.get("convention", "dh")
    if convention not in ("dh", "mdh"):
        raise RobotDescriptionError(f"convention must be 'dh' or 'mdh', got {convention!r}", key="convention")
    angle = _unit(data, "angle_unit", _ANGLE_SCALE, "rad")
    length = _unit(data, "length_unit", _LENGTH_SCALE, "m")
    joints = data.get("joint")
    if not isinstance(joints, list) or not joints:
        raise RobotDescriptionError("needs at least one [[joint]] table", key="joint")
    rows: dict[str, list[float]] = {key: [] for key in _JOINT_KEYS}
    for i, joint in enumerate(joints, start=1):
        if not isinstance(joint, dict):
            raise RobotDescriptionError(f"joint {i} must be a table", key=f"joint {i}")
        _no_unknown(joint, _JOINT_KEYS, f"joint {i}")
        for key in ("a", "alpha", "d"):
            if key not in joint:
                raise RobotDescriptionError(f"joint {i} is missing {key!r}", key=f"joint {i} {key}")
        defaults = {"offset": 0.0, "sign": 1.0, "lower": -np.inf, "upper": np.inf}
        for key in _JOINT_KEYS:
            rows[key].append(_number(joint.get(key, defaults.get(key)), f"joint {i} {key}"))
    scale = {"a": length, "d": length, "alpha": angle, "offset": angle, "lower": angle, "upper": angle, "sign": 1.0}
    arrays = {key: np.asarray(values) * scale[key] for key, values in rows.items()}
    name = data.get("name", default_name)
    if not isinstance(name, str):
        raise RobotDescriptionError(f"name must be a string, got {name!r}", key="name")
    return SerialChain(
        convention=convention,
        base=_transform(data.get("base"), "base", angle, length),
        tool=_transform(data.get("tool"), "tool", angle, length),
        name=name,
        source=str(data.get("source", "robot file")),
        a=arrays["a"], alpha=arrays["alpha"], d=arrays["d"], offset=arrays["offset"], sign=arrays["sign"],
        lower=arrays["lower"], upper=arrays["upper"],
    )


def _no_unknown(table: dict, allowed: set[str], where: str) -> None:
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise RobotDescriptionError(f"unknown key {unknown[0]!r} in {where} (allowed: {', '.join(sorted(allowed))})",
                                    key=unknown[0])


def _unit(data: dict, key: str, scales: dict[str, float], default: str) -> float:
    unit = data.get(key, default)
    if unit not in scales:
        raise RobotDescriptionError(f"{key} must be one of {', '.join(scales)}, got {unit!r}", key=key)
    return scales[unit]


def _number(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise RobotDescriptionError(f"{what} must be a number, got {value!r}", key=what)
    return float(value)


def _transform(table: Any, what: str, angle: float, length: float) -> np.ndarray | None:
    if table is None:
        return None
    if not isinstance(table, dict):
        raise RobotDescriptionError(f"[{what}] must be a table", key=what)
    _no_unknown(table, _TRANSFORM_KEYS, f"[{what}]")
    out = np.eye(4)
    for key, scale, target in (("translation", length, "p"), ("xyz_fixed_angles", angle, "R")):
        if key not in table:
            continue
        vector = table[key]
        if not isinstance(vector, list) or len(vector) != 3:
            raise RobotDescriptionError(f"[{what}] {key} must be a list of 3 numbers, got {vector!r}",
                                        key=f"{what} {key}")
        values = np.array([_number(v, f"[{what}] {key}") for v in vector]) * scale
        if target == "p":
            out[:3, 3] = values
        else:
            out[:3, :3] = xyz_fixed_to_matrix(values)
    return out
