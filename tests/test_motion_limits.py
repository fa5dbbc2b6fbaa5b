"""Limits of motion: a chain's velocity, acceleration and jerk limits, the makers' figures on the named models, and
limits files in redkin's form and MoveIt's (redkin.motion_limits)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from redkin import get_robot
from redkin.errors import RobotDescriptionError
from redkin.models import franka_fr3, franka_panda, kuka_iiwa14, pa10_7c
from redkin.motion_limits import read_motion_limits
from redkin.srs.conventions import table1_form

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"


def test_the_franka_models_carry_the_control_interface_limits():
    """The values of Franka's "Limits for Panda" and "Limits for Franka Research 3" tables, written here."""
    panda, fr3 = franka_panda(), franka_fr3()
    np.testing.assert_array_equal(panda.acceleration, [15, 7.5, 10, 12.5, 15, 20, 20])
    np.testing.assert_array_equal(panda.jerk, [7500, 3750, 5000, 6250, 7500, 10000, 10000])
    np.testing.assert_array_equal(fr3.acceleration, np.full(7, 10.0))
    np.testing.assert_array_equal(fr3.jerk, np.full(7, 5000.0))
    assert not np.isfinite(kuka_iiwa14().acceleration).any()  # KUKA publishes none


def test_the_example_panda_urdf_carries_frankas_speeds():
    np.testing.assert_array_equal(get_robot(EXAMPLES / "panda.urdf").velocity, franka_panda().velocity)


def test_every_copy_and_conversion_keeps_the_limits_of_motion():
    chain = franka_panda()
    for copy in (chain.with_tool(np.eye(4)), chain.with_limits(chain.lower, chain.upper),
                 chain.with_motion_limits(velocity=chain.velocity)):
        for key, values in chain.motion_limits.items():
            np.testing.assert_array_equal(getattr(copy, key), values, err_msg=key)
    iiwa = kuka_iiwa14().with_motion_limits(acceleration=np.arange(1.0, 8.0))
    np.testing.assert_array_equal(table1_form(iiwa).acceleration, np.arange(1.0, 8.0))


@pytest.mark.parametrize("bad", [0.0, -1.0, np.nan])
def test_a_limit_not_positive_is_refused(bad):
    with pytest.raises(ValueError, match="acceleration limits must be > 0 rad/s\\^2"):
        pa10_7c().with_motion_limits(acceleration=np.full(7, bad))
    with pytest.raises(ValueError, match="limits of motion are"):
        pa10_7c().with_motion_limits(speed=np.ones(7))


def test_redkins_form_reads_in_radians_or_degrees(tmp_path):
    file = tmp_path / "limits.yaml"
    file.write_text("velocity: [10, 20, 30, 40, 50, 60, 70]\nacceleration: 100\n")
    chain = read_motion_limits(file, pa10_7c(), degrees=True)
    np.testing.assert_allclose(chain.velocity, np.radians([10, 20, 30, 40, 50, 60, 70]))
    np.testing.assert_allclose(chain.acceleration, np.radians(np.full(7, 100.0)))
    assert not np.isfinite(chain.jerk).any()
    file = tmp_path / "limits.json"
    file.write_text(json.dumps({"jerk": [1, 2, 3, 4, 5, 6, 7]}))
    chain = read_motion_limits(file, franka_panda())
    np.testing.assert_array_equal(chain.jerk, np.arange(1.0, 8.0))
    np.testing.assert_array_equal(chain.velocity, franka_panda().velocity)  # left out: the chain's own


def test_moveits_joint_limits_read_by_joint_name(tmp_path):
    chain = get_robot(EXAMPLES / "panda.urdf")
    file = tmp_path / "joint_limits.yaml"
    file.write_text("default_velocity_scaling_factor: 0.1\njoint_limits:\n"
                    "  panda_joint3: {has_velocity_limits: true, max_velocity: 1.25, has_acceleration_limits: true,"
                    " max_acceleration: 2.5}\n"
                    "  panda_joint5: {has_velocity_limits: false, max_velocity: 9.0, has_acceleration_limits: true,"
                    " max_acceleration: 3.75}\n"
                    "  panda_finger_joint1: {has_velocity_limits: true, max_velocity: 0.2}\n")
    limited = read_motion_limits(file, chain, degrees=True)  # MoveIt's form is radians whatever the command's unit
    expected_velocity = chain.velocity.copy()
    expected_velocity[2] = 1.25
    np.testing.assert_array_equal(limited.velocity, expected_velocity)
    np.testing.assert_array_equal(limited.acceleration, [np.inf, np.inf, 2.5, np.inf, 3.75, np.inf, np.inf])


@pytest.mark.parametrize(("text", "expected"), [
    ("velocity: [1, 2]", "velocity has 2 entries; the arm has 7 joints"),
    ("speed: 1", "unknown key 'speed'"),
    ("velocity: [1, 1, 1, -1, 1, 1, 1]", "velocity[3] must be a positive number"),
    ("velocity: [1, 1, 1, x, 1, 1, 1]", "velocity[3] must be a positive number, got 'x'"),
    ("velocity: [1, 2", "not YAML or JSON"),
    ("", "expected a mapping"),
    ("joint_limits: {other_joint: {max_velocity: 1}}", "names none of the arm's joints"),
    ("joint_limits: {panda_joint1: {has_velocity_limits: true, max_velocity: .inf}}",
     "joint_limits.panda_joint1.max_velocity must be a positive number"),
    ("acceleration: 1" + "0" * 400, "acceleration[0] must be a positive number, got inf"),  # no float holds it
    ('joint_limits: {panda_joint1: {has_acceleration_limits: "yes", max_acceleration: 1}}',  # it read as false
     "joint_limits.panda_joint1.has_acceleration_limits must be true or false, got 'yes'"),
])
def test_a_bad_limits_file_is_one_line_naming_the_entry(tmp_path, text, expected):
    file = tmp_path / "limits.yaml"
    file.write_text(text)
    with pytest.raises(RobotDescriptionError) as raised:
        read_motion_limits(file, get_robot(EXAMPLES / "panda.urdf"))
    message = str(raised.value)
    assert expected in message and str(file) in message and "\n" not in message
    with pytest.raises(RobotDescriptionError, match="cannot read it"):
        read_motion_limits(tmp_path / "missing.yaml", pa10_7c())


def test_robots_show_prints_the_limits_of_motion(capsys):
    from redkin.cli.main import main

    assert main(["robots", "--show", "franka-fr3", "--json"]) == 0
    joints = json.loads(capsys.readouterr().out)["joints"]
    assert [(j["velocity"], j["acceleration"], j["jerk"]) for j in joints] == list(
        zip(franka_fr3().velocity.tolist(), franka_fr3().acceleration.tolist(), franka_fr3().jerk.tolist()))
    assert main(["robots", "--show", "kuka-iiwa14", "--deg"]) == 0
    text = capsys.readouterr().out
    assert "limits of motion (deg/s, deg/s^2, deg/s^3" in text and "velocity 85" in text and "acceleration" not in text
    assert main(["robots", "--show", "pa10-7c", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["joints"][0]["acceleration"] is None
    assert main(["robots", "--show", "pa10-7c"]) == 0
    assert "limits of motion: none known" in capsys.readouterr().out
