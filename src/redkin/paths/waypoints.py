"""The poses of a path from what users have: a straight line between two poses, key poses joined in turn, a file.

* :func:`line` -- the straight line from one 4x4 pose to another: positions on the segment, rotations on the
  geodesic of SO(3) (slerp), both at the same fraction ``s`` in ``[0, 1]``, consecutive poses at most ``step`` metres
  and ``angle_step`` radians apart, both ends included exactly.
* :func:`through` -- key poses joined by :func:`line` in turn, each key pose once.
* :func:`read_poses` -- the poses of a ``.npy``, ``.csv`` or ``.json`` file; :func:`write_poses_csv` and
  :func:`write_poses_json` write the last two.

The line
--------
With ``d`` the distance between the positions and ``theta`` in ``[0, pi]`` the angle of the rotation from one
orientation to the other, the line has ``N`` poses with ``N - 1 = max(ceil(d / step), ceil(theta / angle_step), 1)``
at ``s_k = k / (N - 1)``: the position ``p0 + s (p1 - p0)`` and the rotation ``slerp(q0, q1, s)`` of the unit
quaternions of the ends, the one of ``q1`` and ``-q1`` nearer ``q0`` (the shorter of the two arcs; at ``theta = pi``
both are geodesics and either is taken).  The angle from the start is ``s theta``.  Where the two poses are equal the
line is those two poses (``N = 2``).  No line holds more than :data:`MAX_POSES` poses.

Files
-----
``read_poses`` chooses the format by the suffix (any case) and returns ``(N, 4, 4)`` with ``N >= 1``; a file without
poses is refused.  Positions are in metres.

``.npy``
    One ``(N, 4, 4)`` array of numbers (``numpy.save``), read without pickle.  Every pose must pass
    :func:`redkin._validation.check_pose` (rotation block orthonormal with determinant +1 within 1e-6, last row
    ``[0, 0, 0, 1]``); the message names the index of the first one that does not.
``.csv``
    A header row naming the columns, then one pose per row.  The columns ``x, y, z, qx, qy, qz, qw`` must be
    there, in any order, their names in any case and with spaces around them ignored; other columns (``t``,
    ``time``, ...) are ignored.  The quaternion is the one the names say, which is ROS's order (``x y z w``,
    ``geometry_msgs/Quaternion``), not redkin's scalar-first ``(w, x, y, z)`` of :mod:`redkin.so3`.  Blank rows
    are skipped; rows are counted from 1 after the header, and messages give the file's line too.
    :func:`write_poses_csv` writes the header ``x,y,z,qx,qy,qz,qw``.
``.json``
    A list of poses, or an object whose key ``"poses"`` holds that list (other keys are ignored).  A pose is shaped
    like ROS's ``geometry_msgs/Pose``::

        {"position": {"x": 0.5, "y": 0.0, "z": 0.4}, "orientation": {"x": 0.0, "y": 1.0, "z": 0.0, "w": 0.0}}

    or like a ``PoseStamped``, with that object under ``"pose"`` (so a ``nav_msgs/Path`` dumped to JSON reads as
    it is), or a 4x4 nested list (checked as the ``.npy`` poses are).  Poses are counted from 0.
    :func:`write_poses_json` writes ``{"units": ..., "poses": [...]}``, one pose per line.

A quaternion read from a ``.csv`` or ``.json`` file whose norm is within :data:`QUATERNION_TOLERANCE` (1e-3) of 1
is normalised (values printed with 3 decimals read); one farther, zero, NaN or infinite is refused.  ``q`` and
``-q`` are the same rotation.  Every refusal is one :class:`~redkin.errors.RedkinError` (a ``ValueError``) of one
line that names the file and what is wrong in it: the row or pose and the field where there is one.  The writers
write every number as Python's ``repr``, which reads back bit for bit.
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from redkin._files import write_durably
from redkin._validation import as_float_array, check_output_file, check_pose
from redkin.errors import RedkinError, SizeLimitError
from redkin.so3 import matrix_to_quaternion, quaternion_to_matrix

#: How far from 1 the norm of a quaternion read from a file may be; it is then normalised.
QUATERNION_TOLERANCE = 1e-3
#: The most poses a line (or the lines of :func:`through`) may hold: 128 MB of 4x4 matrices.
MAX_POSES = 1_000_000
#: The columns a CSV file must name, in the order :func:`write_poses_csv` writes them.
_CSV_COLUMNS = ("x", "y", "z", "qx", "qy", "qz", "qw")
_JSON_FIELDS = ("position.x", "position.y", "position.z", "orientation.x", "orientation.y", "orientation.z",
                "orientation.w")
_JSON_UNITS = {"position": "m", "orientation": "unit quaternion x, y, z, w (as ROS geometry_msgs/Pose)"}
_NPY_MAGIC = b"\x93NUMPY"
#: What :func:`line` plans before it builds: the ends' quaternions, half the rotation angle, the segment count.
_Plan = tuple[np.ndarray, np.ndarray, float, int]


# ---------------------------------------------------------------------------------------------------- checks


def _positive(value: float, name: str) -> float:
    """``value`` as a float, refused unless finite and > 0."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise RedkinError(f"{name} must be a positive finite number, got {value!r}") from None
    if not math.isfinite(number) or number <= 0.0:
        raise RedkinError(f"{name} must be a positive finite number, got {value!r}")
    return number


def _one_pose(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as one checked 4x4 pose."""
    array = as_float_array(value, name)
    if array.shape != (4, 4):
        raise RedkinError(f"{name} must be one pose of shape (4, 4), got shape {array.shape}")
    return check_pose(array, name)


def _poses(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as checked poses of shape ``(N, 4, 4)``, ``N >= 1``; a bad pose is named by its index."""
    array = as_float_array(value, name)
    if array.ndim != 3 or array.shape[1:] != (4, 4) or len(array) == 0:
        raise RedkinError(f"{name} must have shape (N, 4, 4) with N >= 1, got shape {array.shape}")
    try:
        return check_pose(array, name)
    except RedkinError:
        for i, pose in enumerate(array):
            check_pose(pose, f"{name}[{i}]")
        raise


# ---------------------------------------------------------------------------------------------------- lines


def _plan(start: np.ndarray, end: np.ndarray, step: float, angle_step: float) -> _Plan:
    """The unit quaternions of the ends (``q1`` on ``q0``'s side), half the rotation angle, and the segment count."""
    q0 = matrix_to_quaternion(start[:3, :3])
    q1 = matrix_to_quaternion(end[:3, :3])
    if float(q0 @ q1) < 0.0:
        q1 = -q1
    # the angle between q0 and q1 in R^4, accurate at every size (arccos of the dot product is not near 0)
    half = 2.0 * math.atan2(float(np.linalg.norm(q1 - q0)), float(np.linalg.norm(q1 + q0)))
    with np.errstate(over="ignore"):
        distance = float(np.linalg.norm(end[:3, 3] - start[:3, 3]))
    ratio = max(distance / step, 2.0 * half / angle_step, 1.0)
    if not ratio <= MAX_POSES - 1:
        raise SizeLimitError(f"a line of {distance:.6g} m and {2.0 * half:.6g} rad at step {step:g} m and angle_step "
                             f"{angle_step:g} rad needs more than {MAX_POSES} poses; take larger steps",
                             name="poses", value=ratio + 1.0, maximum=MAX_POSES)
    return q0, q1, half, math.ceil(ratio)


def _build(start: np.ndarray, end: np.ndarray, q0: np.ndarray, q1: np.ndarray, half: float,
           segments: int) -> np.ndarray:
    """The ``segments + 1`` poses of the line at ``s = k / segments``, its ends ``start`` and ``end`` as given."""
    s = np.linspace(0.0, 1.0, segments + 1)
    if half > 0.0:
        w0, w1 = np.sin((1.0 - s) * half) / math.sin(half), np.sin(s * half) / math.sin(half)
    else:
        w0, w1 = 1.0 - s, s
    q = w0[:, None] * q0 + w1[:, None] * q1
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    out = np.zeros((segments + 1, 4, 4))
    out[:, :3, :3] = quaternion_to_matrix(q)
    out[:, :3, 3] = start[:3, 3] + s[:, None] * (end[:3, 3] - start[:3, 3])
    out[:, 3, 3] = 1.0
    out[0], out[-1] = start, end
    return out


def line(start: ArrayLike, end: ArrayLike, step: float = 0.005, angle_step: float = 0.05) -> np.ndarray:
    """The straight line from ``start`` to ``end``: positions on the segment, rotations on the geodesic (slerp).

    Parameters
    ----------
    start, end : array_like, shape (4, 4)
        The poses at its ends.
    step : float
        The largest distance between consecutive positions, metres (> 0).
    angle_step : float
        The largest rotation angle between consecutive orientations, radians (> 0).

    Returns
    -------
    numpy.ndarray, shape (N, 4, 4)
        ``N - 1 = max(ceil(d / step), ceil(theta / angle_step), 1)`` with ``d`` the distance between the
        positions and ``theta`` in ``[0, pi]`` the angle of the rotation between the orientations.  Pose ``k`` is at
        ``s = k / (N - 1)``: position ``p0 + s (p1 - p0)``, rotation at angle ``s theta`` from the start's on the
        shorter arc (at ``theta = pi`` one of the geodesics).  The first and last poses are ``start`` and ``end``
        bit for bit; two equal poses give ``N = 2``.

    Raises
    ------
    RedkinError
        For a pose of the wrong shape, not finite, or not a rigid transform (:func:`redkin._validation.check_pose`),
        or a step that is not a positive finite number.
    SizeLimitError
        Where the line would hold more than :data:`MAX_POSES` poses.
    """
    a, b = _one_pose(start, "start"), _one_pose(end, "end")
    step, angle_step = _positive(step, "step"), _positive(angle_step, "angle_step")
    return _build(a, b, *_plan(a, b, step, angle_step))


def through(key_poses: ArrayLike, step: float = 0.005, angle_step: float = 0.05) -> np.ndarray:
    """Key poses joined by :func:`line` in turn, each key pose appearing once.

    Parameters
    ----------
    key_poses : array_like, shape (K, 4, 4)
        ``K >= 1`` poses; one alone is returned as it is, with shape ``(1, 4, 4)``.
    step, angle_step : float
        As for :func:`line`, on every segment.

    Returns
    -------
    numpy.ndarray, shape (N, 4, 4)
        The lines from key pose ``i`` to ``i + 1``, each after the first without its first pose (the previous
        line's last): ``N`` is the sum of the lines' counts minus ``K - 2``.  Every key pose is in it bit for bit.

    Raises
    ------
    RedkinError
        As :func:`line`; a bad key pose is named by its index.
    SizeLimitError
        Where the path would hold more than :data:`MAX_POSES` poses.
    """
    keys = _poses(key_poses, "key_poses")
    step, angle_step = _positive(step, "step"), _positive(angle_step, "angle_step")
    plans = [_plan(keys[i], keys[i + 1], step, angle_step) for i in range(len(keys) - 1)]
    count = 1 + sum(plan[3] for plan in plans)
    if count > MAX_POSES:
        raise SizeLimitError(f"the lines through {len(keys)} key poses at step {step:g} m and angle_step "
                             f"{angle_step:g} rad need {count} poses, more than {MAX_POSES}; take larger steps",
                             name="poses", value=count, maximum=MAX_POSES)
    pieces = [keys[:1].copy()]
    pieces += [_build(keys[i], keys[i + 1], *plan)[1:] for i, plan in enumerate(plans)]
    return np.concatenate(pieces)


# ---------------------------------------------------------------------------------------------------- files


def _error(path: Path, what: str) -> RedkinError:
    """The one-line error about the poses file ``path``."""
    return RedkinError(f"poses file {str(path)!r}: {' '.join(str(what).splitlines())}")


def _show(value: Any, width: int = 40) -> str:
    """``repr(value)``, cut to about ``width`` characters."""
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."


def _assemble(path: Path, values: np.ndarray, fields: Sequence[str], quaternion: str,
              where: Callable[[int], str]) -> np.ndarray:
    """Poses from rows ``x, y, z, qx, qy, qz, qw``: every value finite, every quaternion of norm 1 within
    :data:`QUATERNION_TOLERANCE` (then normalised); ``where(i)`` names row ``i`` in a message."""
    bad = ~np.isfinite(values)
    if bad.any():
        row, column = np.argwhere(bad)[0]
        raise _error(path, f"{where(int(row))}: {fields[column]} is not finite ({float(values[row, column])!r})")
    norm = np.linalg.norm(values[:, 3:], axis=1)
    off = np.abs(norm - 1.0) > QUATERNION_TOLERANCE
    if off.any():
        row = int(np.argmax(off))
        raise _error(path, f"{where(row)}: {quaternion} has norm {norm[row]:.6g}, expected 1 within "
                           f"{QUATERNION_TOLERANCE:g}")
    q = values[:, 3:] / norm[:, None]
    out = np.zeros((len(values), 4, 4))
    out[:, :3, :3] = quaternion_to_matrix(q[:, [3, 0, 1, 2]])
    out[:, :3, 3] = values[:, :3]
    out[:, 3, 3] = 1.0
    return out


def _read_csv(path: Path) -> np.ndarray:
    with path.open(newline="", encoding="utf-8-sig") as handle:
        reader = csv.reader(handle)
        try:
            header = next((row for row in reader if any(field.strip() for field in row)), None)
            if header is None:
                raise _error(path, "is empty; expected a header row naming the columns " + ", ".join(_CSV_COLUMNS))
            names = [field.strip().lower() for field in header]
            twice = sorted({name for name in _CSV_COLUMNS if names.count(name) > 1})
            if twice:
                raise _error(path, f"the header names column {twice[0]!r} more than once")
            missing = [name for name in _CSV_COLUMNS if name not in names]
            if missing:
                raise _error(path, f"the header row has no column {', '.join(missing)}: it must name "
                                   f"{', '.join(_CSV_COLUMNS)} (any order), got {_show(header, 80)}")
            columns = [names.index(name) for name in _CSV_COLUMNS]
            rows: list[list[float]] = []
            lines: list[int] = []
            for row in reader:
                if not any(field.strip() for field in row):
                    continue
                lines.append(reader.line_num)
                label = f"data row {len(lines)} (line {reader.line_num})"
                if len(row) != len(header):
                    raise _error(path, f"{label} has {len(row)} fields, the header {len(header)}")
                numbers = []
                for name, column in zip(_CSV_COLUMNS, columns):
                    try:
                        numbers.append(float(row[column]))
                    except ValueError:
                        raise _error(path, f"{label}: {name} is not a number: {_show(row[column])}") from None
                rows.append(numbers)
        except csv.Error as exc:
            raise _error(path, f"line {reader.line_num}: not readable as CSV: {exc}") from None
    if not rows:
        raise _error(path, "has a header but no poses")
    return _assemble(path, np.array(rows), _CSV_COLUMNS, "the quaternion (qx, qy, qz, qw)",
                     lambda i: f"data row {i + 1} (line {lines[i]})")


def _kind(value: Any) -> str:
    """What a JSON value is, in JSON's words."""
    if isinstance(value, dict):
        return "an object"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return f"the string {_show(value)}"
    return "null" if value is None else _show(value)


def _json_numbers(path: Path, i: int, pose: dict, key: str, letters: str) -> list[float]:
    """The numbers of ``pose[key]``'s keys ``letters`` (``position`` x y z or ``orientation`` x y z w)."""
    part = pose.get(key)
    if not isinstance(part, dict):
        got = "nothing" if key not in pose else _kind(part)
        raise _error(path, f"pose {i}: {key} must be an object with keys {', '.join(letters)}, got {got}")
    numbers = []
    for letter in letters:
        if letter not in part:
            raise _error(path, f"pose {i}: {key} has no key {letter!r}")
        value = part[letter]
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise _error(path, f"pose {i}: {key}.{letter} must be a number, got {_kind(value)}")
        try:
            numbers.append(float(value))
        except OverflowError:  # an integer beyond any float
            numbers.append(math.inf)
    return numbers


def _json_matrix(path: Path, i: int, entry: list) -> np.ndarray:
    try:
        matrix = np.array(entry, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise _error(path, f"pose {i} must be a 4x4 list of numbers") from None
    if matrix.shape != (4, 4):
        raise _error(path, f"pose {i} must be a 4x4 list of numbers, got shape {matrix.shape}")
    try:
        return check_pose(matrix, f"pose {i}")
    except RedkinError as exc:
        raise _error(path, str(exc)) from None


def _read_json(path: Path) -> np.ndarray:
    try:
        with path.open(encoding="utf-8-sig") as handle:
            data = json.load(handle)
    except json.JSONDecodeError as exc:
        raise _error(path, f"is not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    except RecursionError:
        raise _error(path, "is not readable as JSON: nested too deeply") from None
    if isinstance(data, dict):
        if "poses" not in data:
            raise _error(path, "is an object without the key 'poses'; expected a list of poses or an object "
                               "with the key 'poses' holding one")
        data = data["poses"]
    if not isinstance(data, list):
        raise _error(path, f"poses must be a list, got {_kind(data)}")
    if not data:
        raise _error(path, "holds no poses")
    out = np.zeros((len(data), 4, 4))
    rows, indices = [], []
    for i, entry in enumerate(data):
        if isinstance(entry, dict) and "pose" in entry and "position" not in entry:
            entry = entry["pose"]  # a PoseStamped
        if isinstance(entry, list):
            out[i] = _json_matrix(path, i, entry)
        elif isinstance(entry, dict):
            rows.append(_json_numbers(path, i, entry, "position", "xyz")
                        + _json_numbers(path, i, entry, "orientation", "xyzw"))
            indices.append(i)
        else:
            raise _error(path, f"pose {i} must be an object with position and orientation (geometry_msgs/Pose), "
                               f"one with them under 'pose', or a 4x4 list, got {_kind(entry)}")
    if rows:
        out[indices] = _assemble(path, np.array(rows), _JSON_FIELDS, "orientation", lambda k: f"pose {indices[k]}")
    return out


def _read_npy(path: Path) -> np.ndarray:
    with path.open("rb") as handle:
        magic = handle.read(len(_NPY_MAGIC))
    if magic.startswith(b"PK"):
        raise _error(path, "is an .npz archive, expected one array saved by numpy.save")
    if magic != _NPY_MAGIC:
        raise _error(path, "is not a .npy file (it does not start with numpy's header)")
    try:
        data = np.load(path, allow_pickle=False)
    except (ValueError, EOFError) as exc:
        raise _error(path, f"is not a readable .npy array ({exc})") from None
    if data.dtype.kind not in "iuf":
        raise _error(path, f"holds values of type {data.dtype}, expected numbers")
    if data.ndim != 3 or data.shape[1:] != (4, 4):
        raise _error(path, f"holds an array of shape {data.shape}, expected (N, 4, 4)")
    if len(data) == 0:
        raise _error(path, "holds no poses")
    poses = data.astype(float)
    try:
        return check_pose(poses, "poses")
    except RedkinError:
        for i, pose in enumerate(poses):
            try:
                check_pose(pose, f"pose {i}")
            except RedkinError as exc:
                raise _error(path, str(exc)) from None
        raise


_READERS: dict[str, Callable[[Path], np.ndarray]] = {".csv": _read_csv, ".json": _read_json, ".npy": _read_npy}


def read_poses(file: str | os.PathLike) -> np.ndarray:
    """The poses of a ``.npy``, ``.csv`` or ``.json`` file (the formats are in this module's docstring).

    Parameters
    ----------
    file : str or os.PathLike
        The file; its suffix (in any case) names the format.

    Returns
    -------
    numpy.ndarray, shape (N, 4, 4)
        ``N >= 1`` poses, in the file's order.

    Raises
    ------
    RedkinError
        With one line naming the file and what is wrong: an unknown suffix, a missing or unreadable file, an empty
        one, a missing column or key, a row of the wrong length, a value that is not a number or not finite, a
        quaternion whose norm is off 1 by more than :data:`QUATERNION_TOLERANCE`, a matrix that is not a rigid
        transform (naming the row, 1-based, of a CSV file, or the index, 0-based, of a pose of the others).
    """
    path = Path(file)
    reader = _READERS.get(path.suffix.lower())
    if reader is None:
        suffix = f"the suffix {path.suffix!r}" if path.suffix else "no suffix"
        raise _error(path, f"has {suffix}; expected one of {', '.join(_READERS)}")
    if not path.exists():
        raise _error(path, "does not exist")
    if path.is_dir():
        raise _error(path, "is a directory, expected a file")
    try:
        return reader(path)
    except UnicodeDecodeError:
        raise _error(path, "is not UTF-8 text") from None
    except OSError as exc:
        raise _error(path, f"cannot be read: {exc.strerror or exc}") from None


def _write(path: Path, text: str) -> None:
    try:
        write_durably(path, text.encode("utf-8"))
    except OSError as exc:
        raise RedkinError(f"cannot write poses file {str(path)!r}: {exc.strerror or exc}") from None


def write_poses_csv(file: str | os.PathLike, poses: ArrayLike) -> None:
    """Write poses as a CSV file that :func:`read_poses` reads back: the header ``x,y,z,qx,qy,qz,qw``, then one row
    per pose, every number as its ``repr`` (the quaternion of :func:`redkin.so3.matrix_to_quaternion`, in ROS's
    order).

    Parameters
    ----------
    file : str or os.PathLike
        A path ending in ``.csv``; its folder is created if needed, and an existing file is replaced.
    poses : array_like, shape (N, 4, 4)
        ``N >= 1`` poses.

    Raises
    ------
    RedkinError
        For poses as :func:`through` refuses them, another suffix, or a file that cannot be written; nothing is
        written then.
    """
    array = _poses(poses, "poses")
    path = check_output_file(file, "file", {".csv"})
    q = matrix_to_quaternion(array[:, :3, :3])
    rows = [",".join(_CSV_COLUMNS)]
    rows += [",".join(map(repr, [*p, x, y, z, w])) for p, (w, x, y, z) in zip(array[:, :3, 3].tolist(), q.tolist())]
    _write(path, "\n".join(rows) + "\n")


def write_poses_json(file: str | os.PathLike, poses: ArrayLike) -> None:
    """Write poses as a JSON file that :func:`read_poses` reads back: ``{"units": ..., "poses": [...]}``, each pose
    a ``geometry_msgs/Pose``-shaped object on a line of its own, every number as its ``repr``.

    Parameters
    ----------
    file : str or os.PathLike
        A path ending in ``.json``; its folder is created if needed, and an existing file is replaced.
    poses : array_like, shape (N, 4, 4)
        ``N >= 1`` poses.

    Raises
    ------
    RedkinError
        As :func:`write_poses_csv`.
    """
    array = _poses(poses, "poses")
    path = check_output_file(file, "file", {".json"})
    q = matrix_to_quaternion(array[:, :3, :3])
    entries = [json.dumps({"position": dict(zip("xyz", p)), "orientation": {"x": x, "y": y, "z": z, "w": w}})
               for p, (w, x, y, z) in zip(array[:, :3, 3].tolist(), q.tolist())]
    _write(path, f'{{"units": {json.dumps(_JSON_UNITS)},\n "poses": [\n' + ",\n".join(entries) + "\n]}\n")
