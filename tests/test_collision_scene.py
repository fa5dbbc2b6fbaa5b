"""Scene files (issue 40): what is written is what is read (YAML and JSON, every obstacle type, rotations given by
rows), each shape's row is the primitive's own, and a file a user gets wrong is one line naming the file, the
obstacle and the field."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from redkin.collision import BOX, CAPSULE, PLANE, SPHERE, WIDTH, Scene, read_scene, scene_of
from redkin.errors import RobotDescriptionError

_coordinate = st.floats(-2.0, 2.0, allow_nan=False)
_point = st.lists(_coordinate, min_size=3, max_size=3)
_length = st.floats(0.001, 1.0)


@st.composite
def _obstacle(draw) -> dict:
    kind = draw(st.sampled_from(["box", "capsule", "sphere", "plane"]))
    if kind == "box":
        turn = Rotation.random(random_state=draw(st.integers(0, 2**31))).as_matrix()
        return {"type": kind, "center": draw(_point), "size": draw(st.lists(_length, min_size=3, max_size=3)),
                "rotation": turn.tolist()}
    if kind == "capsule":
        return {"type": kind, "a": draw(_point), "b": draw(_point), "radius": draw(_length)}
    if kind == "sphere":
        return {"type": kind, "center": draw(_point), "radius": draw(_length)}
    normal = draw(_point.filter(lambda v: np.linalg.norm(v) > 0.1))
    return {"type": kind, "point": draw(_point), "normal": normal}


def _expected_row(entry: dict) -> np.ndarray:
    """The row of an obstacle as the primitives module documents it, computed here from the entry."""
    row = np.zeros(WIDTH)
    row[8:17] = np.eye(3).ravel()
    kind = entry["type"]
    if kind == "box":
        row[0], row[2:5], row[5:8] = BOX, entry["center"], np.array(entry["size"]) / 2
        row[8:17] = np.array(entry["rotation"]).ravel()
    elif kind == "capsule":
        row[0], row[1], row[2:5], row[5:8] = CAPSULE, entry["radius"], entry["a"], entry["b"]
    elif kind == "sphere":
        row[0], row[1], row[2:5], row[5:8] = SPHERE, entry["radius"], entry["center"], entry["center"]
    else:
        row[0], row[2:5] = PLANE, entry["point"]
        row[5:8] = np.array(entry["normal"]) / np.linalg.norm(entry["normal"])
    return row


@settings(max_examples=40, deadline=None)
@given(entries=st.lists(_obstacle(), max_size=6), margin=st.floats(0.0, 0.1), as_json=st.booleans())
@example(entries=[], margin=1e-9, as_json=True)  # a fresh draw: json.dumps writes "1e-09", once read as a string
def test_a_written_scene_reads_back(tmp_path_factory, entries, margin, as_json):
    named = [{"name": f"thing {k}", **entry} for k, entry in enumerate(entries)]
    folder = tmp_path_factory.mktemp("scene")
    path = folder / ("cell.json" if as_json else "cell.yaml")
    data = {"margin": margin, "obstacles": named}
    path.write_text(json.dumps(data) if as_json else yaml.safe_dump(data))
    scene = read_scene(path)
    assert scene.names == tuple(entry["name"] for entry in named) and scene.margin == margin
    assert scene.shapes.shape == (len(named), WIDTH) and not scene.shapes.flags.writeable
    for entry, row in zip(named, scene.shapes):
        np.testing.assert_allclose(row, _expected_row(entry), rtol=0, atol=1e-15)
    assert len(scene) == len(named) and str(path) == scene.source


def test_unnamed_obstacles_are_called_by_type_and_place_and_the_margin_defaults_to_zero():
    scene = scene_of({"obstacles": [{"type": "sphere", "center": [0, 0, 1], "radius": 0.1},
                                    {"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]}]})
    assert scene.names == ("sphere 1", "plane 2") and scene.margin == 0.0
    np.testing.assert_array_equal(scene.shape("sphere 1")[2:5], [0, 0, 1])
    assert len(scene_of({"obstacles": []})) == 0 and len(scene_of({"margin": 0.02})) == 0  # free space


@pytest.mark.parametrize("data, fragment", [
    ([], "expected a mapping with obstacles"),
    ({"obstacle": []}, "unknown key 'obstacle'"),
    ({"obstacles": {"type": "box"}}, "obstacles must be a list"),
    ({"margin": -0.1}, "margin must be a finite number >= 0"),
    ({"margin": "1cm"}, "margin must be a finite number >= 0"),
    ({"obstacles": ["box"]}, "obstacle 1 must be a mapping"),
    ({"obstacles": [{"type": "cone"}]}, "obstacle 1: type must be one of box, capsule, sphere, plane"),
    ({"obstacles": [{"name": "lamp", "type": "sphere", "radius": 0.1}]}, "obstacle 1 ('lamp'): missing field 'center'"),
    ({"obstacles": [{"type": "sphere", "centre": [0, 0, 0], "radius": 1}]}, "unknown field 'centre'"),
    ({"obstacles": [{"type": "sphere", "center": [0, 0], "radius": 1}]}, "sphere center must have shape"),
    ({"obstacles": [{"type": "sphere", "center": [0, 0, float("nan")], "radius": 1}]}, "finite"),
    ({"obstacles": [{"type": "capsule", "a": [0, 0, 0], "b": [0, 0, 1], "radius": -1}]}, "capsule radius"),
    ({"obstacles": [{"type": "box", "center": [0, 0, 0], "size": [1, 0, 1]}]}, "box size must be three lengths > 0"),
    ({"obstacles": [{"type": "box", "center": [0, 0, 0], "size": [1, 1, 1],
                     "rotation": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}]}, "box rotation"),  # a reflection
    ({"obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]}]}, "plane normal must be a non-zero"),
    ({"obstacles": [{"type": "mesh", "file": "fixture.stl"}]}, "mesh file 'fixture.stl' not found"),
    ({"obstacles": [{"type": "mesh"}]}, "missing field 'file'"),
    ({"obstacles": [{"name": "a", "type": "sphere", "center": [0, 0, 0], "radius": 1}] * 2}, "'a' repeated"),
    ({"obstacles": [{"type": "sphere", "center": [0, 0, 0], "radius": True}]}, "radius must be a number >= 0"),
    ({"obstacles": [{"type": "sphere", "center": [True, False, True], "radius": 1}]}, "center must be three numbers"),
    ({"obstacles": [{"type": "sphere", "center": [0, 0, 0], "radius": "0.1"}]}, "radius must be a number >= 0"),
    ({"obstacles": [{"type": "sphere", "center": [0, "0.5", 0], "radius": 1}]}, "center must be three numbers"),
    ({"obstacles": [{"name": ["a", "b"], "type": "sphere", "center": [0, 0, 0], "radius": 1}]}, "name must be text"),
])
def test_a_bad_scene_is_one_line_naming_the_file_the_obstacle_and_the_field(data, fragment):
    with pytest.raises(RobotDescriptionError) as caught:
        scene_of(data, "cell.yaml")
    message = str(caught.value)
    assert message.startswith("scene file 'cell.yaml': ") and fragment in message and "\n" not in message


def test_a_file_that_is_missing_or_not_yaml_is_one_line(tmp_path):
    with pytest.raises(RobotDescriptionError, match="cannot read it"):
        read_scene(tmp_path / "missing.yaml")
    broken = tmp_path / "broken.yaml"
    broken.write_text("obstacles: [{type: box,\n")
    with pytest.raises(RobotDescriptionError, match="not YAML or JSON at line"):
        read_scene(broken)


def test_a_scene_built_in_python_checks_its_rows():
    with pytest.raises(ValueError, match="shapes must have shape"):
        Scene(("a",), np.zeros((1, 3)))
    with pytest.raises(ValueError, match="one entry per shape"):
        Scene(("a", "b"), np.zeros((1, WIDTH)))
    bad = np.zeros((1, WIDTH))
    bad[0, 0] = 9
    with pytest.raises(ValueError, match="known kind"):
        Scene(("a",), bad)
    with pytest.raises(ValueError, match="no obstacle 'b'"):
        Scene(("a",), np.zeros((1, WIDTH))).shape("b")
