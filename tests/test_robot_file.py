"""Robot files: the example reproduces the built-in model; malformed files are rejected clearly."""

import json
from pathlib import Path

import numpy as np
import pytest

from redkin.models import get_robot, pa10_7c
from redkin.robot_file import _robot_from_dict, load_robot

EXAMPLE = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "pa10.toml"


def test_example_file_equals_builtin_pa10():
    from_file, builtin = load_robot(EXAMPLE), pa10_7c()
    q = np.random.default_rng(0).uniform(-2, 2, (30, 7))
    np.testing.assert_allclose(from_file.fk(q), builtin.fk(q), atol=1e-15)
    np.testing.assert_allclose(from_file.limits, builtin.limits, atol=1e-15)
    assert get_robot(str(EXAMPLE)).name == "pa10-from-file"


def minimal(**extra):
    data = {"convention": "mdh", "angle_unit": "deg", "length_unit": "mm",
            "joint": [{"a": 0, "alpha": 0, "d": 100, "lower": -90, "upper": 90},
                      {"a": 200, "alpha": 90, "d": 0, "offset": 90, "sign": -1}]}
    data.update(extra)
    return data


def test_units_offsets_signs_and_tool(tmp_path):
    data = minimal(tool={"translation": [0, 0, 50], "xyz_fixed_angles": [90, 0, 0]})
    path = tmp_path / "arm.json"
    path.write_text(json.dumps(data))
    chain = load_robot(path)
    np.testing.assert_allclose(chain.d, [0.1, 0.0])
    np.testing.assert_allclose(chain.a, [0.0, 0.2])
    np.testing.assert_allclose(chain.offset, [0.0, np.pi / 2])
    np.testing.assert_allclose(chain.sign, [1, -1])
    np.testing.assert_allclose(chain.limits[0], np.radians([-90, 90]))
    assert not np.isfinite(chain.upper[1])
    np.testing.assert_allclose(chain.tool[:3, 3], [0, 0, 0.05])
    np.testing.assert_allclose(chain.tool[:3, :3] @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    assert chain.name == "arm"


@pytest.mark.parametrize(
    "data, message",
    [
        (minimal(joint=[]), r"\[\[joint\]\]"),
        (minimal(joint=[{"a": 0, "alpha": 0}]), "missing 'd'"),
        (minimal(joint=[{"a": 0, "alpha": 0, "d": "long"}]), "joint 1 d must be a number"),
        (minimal(joint=[{"a": 0, "alpha": 0, "d": 0, "twist": 1}]), "unknown key 'twist'"),
        (minimal(joint=[{"a": 0, "alpha": 0, "d": 0, "sign": 3}]), "sign"),
        (minimal(joint=[{"a": 0, "alpha": 0, "d": 0, "lower": 10, "upper": -10}]), "exceeds"),
        (minimal(convention="craig"), "convention"),
        (minimal(angle_unit="grad"), "angle_unit"),
        (minimal(tool={"translation": [0, 0]}), "list of 3 numbers"),
        (minimal(robot="x"), "unknown key 'robot'"),
        ([1, 2], "table"),
    ],
)
def test_malformed_content(data, message):
    with pytest.raises(ValueError, match=message):
        _robot_from_dict(data)


def test_unparsable_and_missing_files(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("name = \n[[joint]")
    with pytest.raises(ValueError, match="cannot be parsed"):
        load_robot(bad)
    with pytest.raises(ValueError, match="does not exist"):
        get_robot(str(tmp_path / "none.toml"))
    (tmp_path / "folder.json").mkdir()
    with pytest.raises(ValueError, match="is a folder, not a file"):  # it said "does not exist"
        get_robot(str(tmp_path / "folder.json"))
    with pytest.raises(ValueError, match="unknown robot"):
        get_robot("pa11")
