"""Laws of the poses of a path from what users have (redkin.paths.waypoints).

``line``: its ends are the given poses bit for bit; consecutive poses are within ``step`` and ``angle_step``; the
positions lie on the segment in order; the rotations lie on the geodesic, at the angle ``s theta`` from the start
(checked with the angle between rotations written from its definition, not with the module's quaternions); and the
degenerate lines (equal ends, a half turn, a turn alone, a move alone) obey the same laws.  ``through``: the lines
joined, each key pose once.  ``read_poses``: what the writers write reads back, in any column order, with ``q`` or
``-q``; a bad file is one line that names it.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from redkin._validation import check_pose
from redkin.paths.waypoints import (
    MAX_POSES,
    QUATERNION_TOLERANCE,
    line,
    read_poses,
    through,
    write_poses_csv,
    write_poses_json,
)
from redkin.so3 import matrix_to_quaternion, quaternion_to_matrix

quaternions = arrays(float, 4, elements=st.floats(-1, 1)).filter(lambda v: np.linalg.norm(v) > 0.1)
positions = arrays(float, 3, elements=st.floats(-1, 1))
unit_vectors = arrays(float, 3, elements=st.floats(-1, 1)).filter(lambda v: np.linalg.norm(v) > 0.1)
steps = st.floats(0.02, 0.5)


def pose(quaternion: np.ndarray, position: np.ndarray) -> np.ndarray:
    """The 4x4 pose of a (not necessarily unit) scalar-first quaternion and a position."""
    out = np.eye(4)
    out[:3, :3] = quaternion_to_matrix(quaternion / np.linalg.norm(quaternion))
    out[:3, 3] = position
    return out


poses = st.builds(pose, quaternions, positions)
key_poses = st.lists(poses, min_size=1, max_size=5).map(np.array)


def turn(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation by ``angle`` about ``axis``, from the quaternion ``(cos(a/2), sin(a/2) u)``."""
    u = axis / np.linalg.norm(axis)
    return quaternion_to_matrix(np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * u]))


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The angle in ``[0, pi]`` of the rotation from ``a`` to ``b`` (batched over leading axes), from its definition:
    ``atan2(sin, cos)`` of ``R = a^T b``, ``2 sin = |vee(R - R^T)|`` and ``2 cos = tr R - 1``, accurate at every
    angle (arccos of the trace alone is not near 0 or pi)."""
    r = np.swapaxes(a[..., :3, :3], -1, -2) @ b[..., :3, :3]
    vee = np.stack([r[..., 2, 1] - r[..., 1, 2], r[..., 0, 2] - r[..., 2, 0], r[..., 1, 0] - r[..., 0, 1]], axis=-1)
    return np.arctan2(np.linalg.norm(vee, axis=-1) / 2, (np.trace(r, axis1=-2, axis2=-1) - 1) / 2)


def expected_count(start: np.ndarray, end: np.ndarray, step: float, angle_step: float) -> int:
    """``N = 1 + max(ceil(d / step), ceil(theta / angle_step), 1)``."""
    distance = float(np.linalg.norm(end[:3, 3] - start[:3, 3]))
    return 1 + max(math.ceil(distance / step), math.ceil(float(angle_between(start, end)) / angle_step), 1)


def assert_line_laws(out: np.ndarray, start: np.ndarray, end: np.ndarray, step: float, angle_step: float) -> None:
    """Every law of a line from ``start`` to ``end``."""
    n = len(out)
    assert out.shape == (n, 4, 4) and n >= 2
    np.testing.assert_array_equal(out[0], start)
    np.testing.assert_array_equal(out[-1], end)
    check_pose(out)
    np.testing.assert_array_equal(out[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)))
    # consecutive poses within the steps
    assert np.linalg.norm(np.diff(out[:, :3, 3], axis=0), axis=1).max() <= step + 1e-12
    assert angle_between(out[:-1], out[1:]).max() <= angle_step + 1e-12
    s = np.arange(n) / (n - 1)
    # positions on the segment, in order, at s
    d = end[:3, 3] - start[:3, 3]
    offsets = out[:, :3, 3] - start[:3, 3]
    np.testing.assert_allclose(offsets, s[:, None] * d, rtol=0, atol=1e-12)
    along = offsets @ d
    assert np.all(np.diff(along) >= 0.0)
    # rotations on the geodesic, at the angle s theta from the start
    theta = float(angle_between(start, end))
    from_start, to_end = angle_between(start, out), angle_between(out, end)
    np.testing.assert_allclose(from_start, s * theta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(from_start + to_end, theta, rtol=0, atol=1e-9)


# ---------------------------------------------------------------------------------------------------- line


@settings(max_examples=60)
@given(start=poses, end=poses, step=steps, angle_step=steps)
def test_a_line_keeps_its_ends_its_steps_the_segment_and_the_geodesic(start, end, step, angle_step):
    out = line(start, end, step, angle_step)
    assert len(out) == expected_count(start, end, step, angle_step)
    assert_line_laws(out, start, end, step, angle_step)


@settings(max_examples=30)
@given(start=poses, axis=unit_vectors, angle=st.floats(np.pi - 1e-6, np.pi + 1e-6), move=positions, angle_step=steps)
def test_a_turn_near_a_half_turn_takes_the_shorter_arc(start, axis, angle, move, angle_step):
    """Within 1e-6 of pi either way round (a turn by pi + g about u is one by pi - g about -u), the line turns by the
    smaller angle: the angles along it add up to the angle between its ends, at most pi."""
    end = start.copy()
    end[:3, :3] = start[:3, :3] @ turn(axis, angle)
    end[:3, 3] += move
    out = line(start, end, 0.1, angle_step)
    assert_line_laws(out, start, end, 0.1, angle_step)
    assert angle_between(out[:-1], out[1:]).sum() == pytest.approx(float(angle_between(start, end)), abs=1e-9)


@pytest.mark.parametrize("rotation", [
    np.diag([-1.0, -1.0, 1.0]),  # exactly pi about z
    np.diag([1.0, -1.0, -1.0]),  # exactly pi about x
    2 * np.outer([1, 2, 3], [1, 2, 3]) / 14 - np.eye(3),  # pi about (1, 2, 3), as close as doubles get
], ids=["z", "x", "oblique"])
def test_a_half_turn_follows_one_geodesic(rotation):
    start, end = np.eye(4), np.eye(4)
    end[:3, :3] = rotation
    out = line(start, end)
    assert len(out) == 1 + math.ceil(np.pi / 0.05)
    assert_line_laws(out, start, end, 0.005, 0.05)
    assert float(angle_between(start, end)) == pytest.approx(np.pi, abs=1e-12)


@settings(max_examples=20)
@given(start=poses, step=steps, angle_step=steps)
def test_equal_ends_give_the_two_poses(start, step, angle_step):
    out = line(start, start.copy(), step, angle_step)
    assert out.shape == (2, 4, 4)
    np.testing.assert_array_equal(out, [start, start])


@settings(max_examples=20)
@given(start=poses, axis=unit_vectors, angle=st.floats(0.01, np.pi), angle_step=steps)
@example(start=np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]),
         axis=np.array([1.0, 1.0, 1.0]), angle=0.0625, angle_step=0.0625)  # a fresh draw: one step, or two by rounding
def test_a_turn_alone_keeps_the_position(start, axis, angle, angle_step):
    end = start.copy()
    end[:3, :3] = start[:3, :3] @ turn(axis, angle)
    out = line(start, end, 0.005, angle_step)
    steps = float(angle_between(start, end)) / angle_step  # at a whole number of steps, rounding of the angle decides
    assert len(out) - 1 in {math.ceil(steps - 1e-12), math.ceil(steps + 1e-12)}
    assert_line_laws(out, start, end, 0.005, angle_step)
    np.testing.assert_array_equal(out[:, :3, 3], np.tile(start[:3, 3], (len(out), 1)))


@settings(max_examples=20)
@given(start=poses, move=positions.filter(lambda v: np.linalg.norm(v) > 1e-3), step=steps)
def test_a_move_alone_keeps_the_rotation(start, move, step):
    end = start.copy()
    end[:3, 3] += move
    out = line(start, end, step, 0.05)
    assert len(out) == 1 + math.ceil(np.linalg.norm(end[:3, 3] - start[:3, 3]) / step)
    assert_line_laws(out, start, end, step, 0.05)
    np.testing.assert_allclose(out[:, :3, :3], np.broadcast_to(start[:3, :3], (len(out), 3, 3)), rtol=0, atol=1e-15)


def test_the_default_steps_are_5_mm_and_0_05_rad():
    end = np.eye(4)
    end[:3, 3] = [0.1, 0.0, 0.0]
    assert len(line(np.eye(4), end)) == 21
    end[:3, :3] = turn(np.array([0.0, 0.0, 1.0]), 1.0)
    assert len(line(np.eye(4), end)) == 21
    end[:3, :3] = turn(np.array([0.0, 0.0, 1.0]), 1.01)
    assert len(line(np.eye(4), end)) == 22


@pytest.mark.parametrize("arguments, fragment", [
    ({"step": 0.0}, "step must be a positive finite number"),
    ({"step": -1.0}, "step must be a positive finite number"),
    ({"step": float("nan")}, "step must be a positive finite number"),
    ({"angle_step": float("inf")}, "angle_step must be a positive finite number"),
    ({"angle_step": "fast"}, "angle_step must be a positive finite number"),
    ({"start": np.eye(3)}, "start must be one pose of shape (4, 4)"),
    ({"end": np.stack([np.eye(4)] * 2)}, "end must be one pose of shape (4, 4)"),
    ({"start": np.full((4, 4), np.nan)}, "start must be finite"),
    ({"end": np.diag([1.0, 1.0, -1.0, 1.0])}, "end rotation block must be a proper rotation"),
    ({"end": np.diag([2.0, 1.0, 1.0, 1.0])}, "end rotation block must be orthonormal"),
    ({"start": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 1]]}, "start must have last row"),
    ({"start": "pose"}, "start must be numeric"),
])
def test_bad_arguments_are_refused_by_name(arguments, fragment):
    call = {"start": np.eye(4), "end": np.eye(4)} | arguments
    with pytest.raises(ValueError) as error:
        line(**call)
    assert fragment in str(error.value) and "\n" not in str(error.value)
    if {"step", "angle_step"} & set(arguments):
        steps = {key: value for key, value in arguments.items() if key in ("step", "angle_step")}
        with pytest.raises(ValueError, match="must be a positive finite number"):
            through(np.eye(4)[None], **steps)  # even with one key pose


def test_a_line_of_too_many_poses_is_refused_before_it_is_built():
    end = np.eye(4)
    end[:3, 3] = [1.0, 0.0, 0.0]
    with pytest.raises(ValueError, match=f"more than {MAX_POSES} poses"):
        line(np.eye(4), end, step=1e-7)
    end[:3, 3] = [5e5, 0.0, 0.0]
    start = np.eye(4)
    start[:3, 3] = [-5e5, 0.0, 0.0]
    with pytest.raises(ValueError, match=f"more than {MAX_POSES} poses"):
        line(start, end)
    end[0, 3] = 1e308  # finite, and refused as a pose before its line's length overflows
    with pytest.raises(ValueError, match=r"end translation must be at most 1e\+06 m"):
        line(start, end)
    keys = np.stack([np.eye(4)] * 4)
    keys[1::2, 0, 3] = 0.5  # three lines of 2**19 segments: each fits, all of them do not
    with pytest.raises(ValueError, match=f"need {3 * 2**19 + 1} poses, more than {MAX_POSES}"):
        through(keys, step=2.0**-20)


# ---------------------------------------------------------------------------------------------------- through


@settings(max_examples=40)
@given(keys=key_poses, step=steps, angle_step=steps)
def test_through_joins_the_lines_with_each_key_pose_once(keys, step, angle_step):
    out = through(keys, step, angle_step)
    if len(keys) == 1:
        assert out.shape == (1, 4, 4)
        np.testing.assert_array_equal(out, keys)
        return
    lines = [line(keys[i], keys[i + 1], step, angle_step) for i in range(len(keys) - 1)]
    assert len(out) == sum(map(len, lines)) - (len(keys) - 2)
    np.testing.assert_array_equal(out, np.concatenate([lines[0]] + [piece[1:] for piece in lines[1:]]))
    at = np.cumsum([0] + [len(piece) - 1 for piece in lines])
    np.testing.assert_array_equal(out[at], keys)


def test_through_names_the_bad_key_pose_and_wants_poses():
    keys = np.stack([np.eye(4)] * 4)
    keys[2, 0, 0] = 1.5
    with pytest.raises(ValueError, match=r"key_poses\[2\] rotation block must be orthonormal"):
        through(keys)
    with pytest.raises(ValueError, match=r"key_poses must have shape \(N, 4, 4\) with N >= 1, got shape \(0, 4, 4\)"):
        through(np.zeros((0, 4, 4)))
    with pytest.raises(ValueError, match=r"got shape \(4, 4\)"):
        through(np.eye(4))


# ---------------------------------------------------------------------------------------------------- files


@settings(max_examples=25)
@given(keys=key_poses)
def test_written_poses_read_back(tmp_path_factory, keys):
    folder = tmp_path_factory.mktemp("round")
    write_poses_csv(folder / "p.csv", keys)
    write_poses_json(folder / "p.json", keys)
    np.save(folder / "p.npy", keys)
    for name in ("p.csv", "p.json"):
        np.testing.assert_allclose(read_poses(folder / name), keys, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(read_poses(str(folder / "p.npy")), keys)
    text = (folder / "p.csv").read_text(encoding="utf-8").splitlines()
    assert text[0] == "x,y,z,qx,qy,qz,qw" and len(text) == len(keys) + 1
    assert json.loads((folder / "p.json").read_text(encoding="utf-8"))["units"]["position"] == "m"


def csv_text(columns: list[str], table: np.ndarray) -> str:
    """A CSV file of a header and rows, every number exact."""
    return ",".join(columns) + "\n" + "\n".join(",".join(map(repr, row)) for row in table.tolist()) + "\n"


@settings(max_examples=25)
@given(keys=key_poses, order=st.permutations(["x", "y", "z", "qx", "qy", "qz", "qw", "t"]),
       flips=st.lists(st.booleans(), min_size=5, max_size=5), case=st.sampled_from([str.upper, str.lower, str.title]))
def test_a_csv_reads_in_any_column_order_with_extra_columns_and_either_quaternion_sign(tmp_path_factory, keys, order,
                                                                                      flips, case):
    """Columns in any order, names in any case with spaces around them, an extra ``t`` column, blank lines; ``q`` and
    ``-q`` are the same pose, bit for bit."""
    q = matrix_to_quaternion(keys[:, :3, :3])  # w x y z
    rows = []
    for k, (p, (w, x, y, z)) in enumerate(zip(keys[:, :3, 3], q)):
        sign = -1.0 if flips[k] else 1.0
        values = {"x": p[0], "y": p[1], "z": p[2], "qx": sign * x, "qy": sign * y, "qz": sign * z, "qw": sign * w,
                  "t": 0.1 * k}
        rows.append(",".join(repr(float(values[name])) for name in order))
    folder = tmp_path_factory.mktemp("order")
    file = folder / "poses.CSV"
    file.write_text(",".join(f" {case(name)} " for name in order) + "\n\n" + "\n".join(rows) + "\n\n", encoding="utf-8")
    np.testing.assert_allclose(read_poses(file), keys, rtol=0, atol=1e-12)
    columns = ["x", "y", "z", "qx", "qy", "qz", "qw"]
    (folder / "plus.csv").write_text(csv_text(columns, np.concatenate([keys[:, :3, 3], q[:, 1:], q[:, :1]], axis=1)))
    (folder / "minus.csv").write_text(csv_text(columns, np.concatenate([keys[:, :3, 3], -q[:, 1:], -q[:, :1]], axis=1)))
    np.testing.assert_array_equal(read_poses(folder / "plus.csv"), read_poses(folder / "minus.csv"))


@settings(max_examples=20)
@given(keys=key_poses, scale=st.floats(1 - QUATERNION_TOLERANCE / 2, 1 + QUATERNION_TOLERANCE / 2))
def test_a_quaternion_near_unit_norm_is_normalised(tmp_path_factory, keys, scale):
    q = matrix_to_quaternion(keys[:, :3, :3])
    table = np.concatenate([keys[:, :3, 3], scale * q[:, 1:], scale * q[:, :1]], axis=1)
    file = tmp_path_factory.mktemp("norm") / "p.csv"
    file.write_text(csv_text(["x", "y", "z", "qx", "qy", "qz", "qw"], table), encoding="utf-8")
    np.testing.assert_allclose(read_poses(file), keys, rtol=0, atol=1e-12)


def ros_pose(p: np.ndarray) -> dict:
    """A geometry_msgs/Pose of a 4x4 pose, as a ROS message converted to JSON has it."""
    w, x, y, z = matrix_to_quaternion(p[:3, :3]).tolist()
    return {"position": dict(zip("xyz", p[:3, 3].tolist())), "orientation": {"x": x, "y": y, "z": z, "w": w}}


@settings(max_examples=15)
@given(keys=key_poses)
def test_a_nav_msgs_path_a_list_and_4x4_lists_read_as_json(tmp_path_factory, keys):
    folder = tmp_path_factory.mktemp("json")
    stamped = [{"header": {"frame_id": "base", "stamp": {"sec": k, "nanosec": 0}}, "pose": ros_pose(p)}
               for k, p in enumerate(keys)]
    documents = {
        "path.json": {"header": {"frame_id": "base"}, "poses": stamped},
        "list.json": [ros_pose(p) for p in keys],
        "mixed.json": [p.tolist() if k % 2 else ros_pose(p) for k, p in enumerate(keys)],
    }
    for name, document in documents.items():
        (folder / name).write_text(json.dumps(document), encoding="utf-8")
        np.testing.assert_allclose(read_poses(folder / name), keys, rtol=0, atol=1e-12)


# ---------------------------------------------------------------------------------------------------- bad files

GOOD_ROW = "0,0,0,0,0,0,1"
HEADER = "x,y,z,qx,qy,qz,qw"
GOOD_POSE = {"position": {"x": 0, "y": 0, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}


def _json(document) -> str:
    return json.dumps(document)


def _with(key: str, field: str, value) -> dict:
    """GOOD_POSE with ``pose[key][field] = value`` (a ``field`` of None drops ``key``; a value of ... drops
    ``field``)."""
    changed = json.loads(json.dumps(GOOD_POSE))
    if field is None:
        del changed[key]
    elif value is ...:
        del changed[key][field]
    else:
        changed[key][field] = value
    return changed


BAD_TEXT = [
    ("empty.csv", "", "is empty"),
    ("blank.csv", "\n  \n\n", "is empty"),
    ("header.csv", HEADER + "\n", "has a header but no poses"),
    ("missing.csv", "x,y,z,qx,qy,qz\n0,0,0,0,0,0\n", "no column qw"),
    ("numbers.csv", GOOD_ROW + "\n", "no column x, y, z, qx, qy, qz, qw"),
    ("twice.csv", "x,y,z,qx,qy,qz,qw,X\n0,0,0,0,0,0,1,0\n", "column 'x' more than once"),
    ("short.csv", f"{HEADER}\n{GOOD_ROW}\n0,0,0,0,0,1\n", "data row 2 (line 3) has 6 fields, the header 7"),
    ("long.csv", f"{HEADER}\n{GOOD_ROW},5\n", "data row 1 (line 2) has 8 fields"),
    ("word.csv", f"{HEADER}\n{GOOD_ROW}\n\n{GOOD_ROW}\n0,0,0,0,abc,0,1\n", "data row 3 (line 5): qy is not a number"),
    ("nan.csv", f"{HEADER}\nnan,0,0,0,0,0,1\n", "data row 1 (line 2): x is not finite (nan)"),
    ("inf.csv", f"{HEADER}\n{GOOD_ROW}\n0,0,0,0,0,0,inf\n", "data row 2 (line 3): qw is not finite (inf)"),
    ("norm.csv", f"{HEADER}\n{GOOD_ROW}\n0,0,0,0,0,0,1.002\n", "data row 2 (line 3): the quaternion (qx, qy, qz, qw) "
                                                              "has norm 1.002, expected 1 within 0.001"),
    ("zero.csv", f"{HEADER}\n0,0,0,0,0,0,0\n", "data row 1 (line 2): the quaternion (qx, qy, qz, qw) has norm 0"),
    ("huge.csv", f"{HEADER}\n0,0,0,0,0,0,\"{'1' * 200_000}\"\n", "line 2: not readable as CSV: field larger"),
    ("text.json", "poses: [1, 2]", "is not valid JSON: Expecting value at line 1 column 1"),
    ("empty.json", "", "is not valid JSON"),
    ("object.json", '{"path": []}', "is an object without the key 'poses'"),
    ("scalar.json", "3", "poses must be a list, got 3"),
    ("string.json", '{"poses": "p.csv"}', "poses must be a list, got the string 'p.csv'"),
    ("none.json", "[]", "holds no poses"),
    ("entry.json", _json([GOOD_POSE, 7]), "pose 1 must be an object with position and orientation"),
    ("noorientation.json", _json([GOOD_POSE, _with("orientation", None, 0)]),
     "pose 1: orientation must be an object with keys x, y, z, w, got nothing"),
    ("now.json", _json([_with("orientation", "w", ...)]), "pose 0: orientation has no key 'w'"),
    ("listposition.json", _json([_with("position", "x", 0) | {"position": [0, 0, 0]}]),
     "pose 0: position must be an object with keys x, y, z, got a list"),
    ("stringx.json", _json([GOOD_POSE, _with("position", "x", "0.5")]),
     "pose 1: position.x must be a number, got the string '0.5'"),
    ("boolean.json", _json([_with("orientation", "w", True)]), "pose 0: orientation.w must be a number, got True"),
    ("nan.json", _json([GOOD_POSE, GOOD_POSE, _with("position", "z", float("nan"))]),
     "pose 2: position.z is not finite (nan)"),
    ("bignum.json", '[{"position": {"x": 1' + "0" * 400 + ', "y": 0, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, '
     '"w": 1}}]', "pose 0: position.x is not finite (inf)"),
    ("norm.json", _json({"poses": [{"pose": _with("orientation", "w", 0.5)}]}),
     "pose 0: orientation has norm 0.5, expected 1 within 0.001"),
    ("matrix.json", _json([GOOD_POSE, np.diag([1.0, 1.0, -1.0, 1.0]).tolist()]),
     "pose 1 rotation block must be a proper rotation"),
    ("shape.json", _json([np.eye(4)[:3].tolist()]), "pose 0 must be a 4x4 list of numbers, got shape (3, 4)"),
    ("ragged.json", _json([[[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], [0, 0, 0, 1]]]), "pose 0 must be a 4x4 list"),
]


@pytest.mark.parametrize("name, content, fragment", BAD_TEXT, ids=[case[0] for case in BAD_TEXT])
def test_a_bad_text_file_is_one_line_naming_the_file_and_the_fault(tmp_path, name, content, fragment):
    file = tmp_path / name
    file.write_text(content, encoding="utf-8")
    assert_refused(file, fragment)


def assert_refused(file, fragment: str) -> None:
    with pytest.raises(ValueError) as error:
        read_poses(file)
    message = str(error.value)
    assert "\n" not in message
    assert message.startswith(f"poses file {str(file)!r}: ")
    assert fragment in message
    assert error.value.__cause__ is None  # no chained traceback from csv, json or numpy
    assert error.value.__context__ is None or error.value.__suppress_context__


def test_a_bad_npy_file_is_one_line_naming_the_file_and_the_fault(tmp_path):
    keys = np.stack([np.eye(4)] * 4)
    keys[2, :3, :3] = np.diag([1.0, 1.0, 1.01])
    cases = {
        "rotation.npy": (keys, "pose 2 rotation block must be orthonormal"),
        "last_row.npy": (np.stack([np.eye(4), np.eye(4) * 2]), "pose 1 must have last row [0, 0, 0, 1]"),
        "shape.npy": (np.eye(4), "holds an array of shape (4, 4), expected (N, 4, 4)"),
        "empty.npy": (np.zeros((0, 4, 4)), "holds no poses"),
        "nan.npy": (np.full((1, 4, 4), np.nan), "pose 0 must be finite"),
        "complex.npy": (np.eye(4)[None] + 0j, "holds values of type complex128, expected numbers"),
        "text.npy": (np.array([["a"] * 4] * 4), "holds values of type <U1, expected numbers"),
        "objects.npy": (np.array([None, 1], dtype=object), "is not a readable .npy array"),
    }
    for name, (array, fragment) in cases.items():
        np.save(tmp_path / name, array, allow_pickle=True)
        assert_refused(tmp_path / name, fragment)
    np.savez(tmp_path / "archive.npz", poses=np.eye(4)[None])
    (tmp_path / "archive.npz").rename(tmp_path / "archive.npy")
    assert_refused(tmp_path / "archive.npy", "is an .npz archive")
    (tmp_path / "plain.npy").write_text(HEADER + "\n" + GOOD_ROW + "\n", encoding="utf-8")
    assert_refused(tmp_path / "plain.npy", "is not a .npy file")
    (tmp_path / "cut.npy").write_bytes((tmp_path / "rotation.npy").read_bytes()[:100])
    assert_refused(tmp_path / "cut.npy", "is not a readable .npy array")
    np.save(tmp_path / "integers.npy", np.eye(4, dtype=int)[None].repeat(3, axis=0))
    assert read_poses(tmp_path / "integers.npy").dtype == float


def test_a_file_that_is_not_there_or_not_a_pose_file_is_one_line(tmp_path):
    assert_refused(tmp_path / "absent.csv", "does not exist")
    assert_refused(tmp_path / "poses.txt", "has the suffix '.txt'; expected one of .csv, .json, .npy")
    assert_refused(tmp_path / "poses", "has no suffix")
    (tmp_path / "folder.json").mkdir()
    assert_refused(tmp_path / "folder.json", "is a directory")
    (tmp_path / "latin.csv").write_bytes(HEADER.encode() + b"\n0,0,0,0,0,0,1 \xe9\n")
    assert_refused(tmp_path / "latin.csv", "is not UTF-8 text")
    odd = tmp_path / "two\nlines.csv"
    odd.write_text("", encoding="utf-8")
    assert_refused(odd, "is empty")


def test_the_writers_refuse_before_writing(tmp_path):
    with pytest.raises(ValueError, match=r"file must end in one of \.csv"):
        write_poses_csv(tmp_path / "p.txt", np.eye(4)[None])
    with pytest.raises(ValueError, match=r"file must end in one of \.json"):
        write_poses_json(tmp_path / "p.csv", np.eye(4)[None])
    bad = np.stack([np.eye(4), np.diag([1.0, 2.0, 1.0, 1.0])])
    with pytest.raises(ValueError, match=r"poses\[1\] rotation block must be orthonormal"):
        write_poses_csv(tmp_path / "p.csv", bad)
    with pytest.raises(ValueError, match=r"poses must have shape \(N, 4, 4\)"):
        write_poses_json(tmp_path / "p.json", np.eye(4))
    assert list(tmp_path.iterdir()) == []
