"""Joint speed limits: ``SerialChain.velocity``, read from URDFs, carried by the models, and the step bound they give.

The URDF's velocities are checked against an independent reading of the XML with ``xml.etree`` (not the parser
redkin uses); the models' against the makers' files, whose numbers are written here with where they come from.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.chain import SerialChain
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.models import get_robot, robot_names
from redkin.paths import resolve_path, step_bound
from redkin.paths.bounds import missing_speeds

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
URDFS = sorted(EXAMPLES.glob("*.urdf"))

#: The makers' joint speed limits (rad/s), as their files write them.
MAKERS = {
    # KUKA LBR iiwa 14 R820 data sheet; kroshu/kuka_robot_descriptions 7766e92,
    # kuka_lbr_iiwa_support/urdf/lbr_iiwa14_r820_macro.xacro: velocity="${radians(85)}" ...;
    # lbr-stack/lbr_fri_ros2_stack 218d723, lbr_description/urdf/iiwa14/joint_limits.yaml
    "kuka-iiwa14": np.radians([85, 85, 100, 75, 130, 135, 135]),
    "kuka-iiwa14-table1": np.radians([85, 85, 100, 75, 130, 135, 135]),
    # KUKA LBR iiwa 7 R800 data sheet; lbr-stack/lbr_fri_ros2_stack 218d723,
    # lbr_description/urdf/iiwa7/joint_limits.yaml
    "kuka-iiwa7": np.radians([98, 98, 100, 130, 140, 180, 180]),
    # frankaemika/franka_description b299b39, robots/fer/joint_limits.yaml
    "franka-panda": np.array([2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100]),
    # frankaemika/franka_description b299b39, robots/fr3/joint_limits.yaml
    "franka-fr3": np.array([2.62, 2.62, 2.62, 2.62, 5.26, 4.18, 5.26]),
    # Kinovarobotics/ros2_kortex 1fdbef3, kortex_description/arms/gen3/7dof/urdf/gen3_macro.xacro
    "kinova-gen3": np.array([1.3963, 1.3963, 1.3963, 1.3963, 1.2218, 1.2218, 1.2218]),
    # xArm-Developer/xarm_ros2 3654ba7, xarm_description/urdf/xarm7/xarm7.urdf.xacro
    "ufactory-xarm7": np.full(7, 3.14),
}


def _urdf_speeds(text: str, joint_names) -> np.ndarray:
    """Each named joint's ``<limit velocity>`` straight from the XML; ``inf`` where it is absent or 0."""
    joints = {joint.get("name"): joint for joint in ET.fromstring(text).findall("joint")}
    speeds = []
    for name in joint_names:
        limit = joints[name].find("limit")
        value = 0.0 if limit is None else float(limit.get("velocity", "0"))
        speeds.append(np.inf if value == 0.0 else value)
    return np.array(speeds)


def _two_joint_urdf(first_limit: str, second: str = "continuous", second_limit: str = "") -> str:
    return ('<robot name="two"><link name="a"/><link name="b"/><link name="c"/>'
            f'<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>{first_limit}'
            '</joint>'
            f'<joint name="j2" type="{second}"><parent link="b"/><child link="c"/><origin xyz="0 0 0.3"/>'
            f'<axis xyz="0 1 0"/>{second_limit}</joint></robot>')


# ----------------------------------------------------------------------------- the chain
def test_a_chain_has_no_speed_limits_unless_given():
    chain = SerialChain(a=[0.3, 0.2], alpha=[0.0, 0.0], d=[0.0, 0.0])
    assert np.all(np.isinf(chain.velocity)) and not chain.velocity_known.any()
    assert missing_speeds(chain) == "any joint"


@pytest.mark.parametrize("bad", [[1.0, 0.0], [1.0, -2.0], [np.nan, 1.0], [1.0, -np.inf], [1.0, 2.0, 3.0]])
def test_bad_speed_limits_are_refused(bad):
    with pytest.raises(ValueError, match="velocity"):
        SerialChain(a=[0.3, 0.2], alpha=[0.0, 0.0], d=[0.0, 0.0], velocity=bad)


def test_every_copy_keeps_the_speed_limits():
    chain = get_robot("kuka-iiwa14")
    speeds = chain.velocity
    copies = [chain.with_limits(chain.lower / 2, chain.upper / 2), chain.with_tool(np.eye(4)),
              chain.with_base(np.eye(4)), chain.mirrored(), chain.mirrored(flip_joints=[0, 3]),
              replace(chain, name="other")]
    for copy in copies:
        np.testing.assert_array_equal(copy.velocity, speeds)
        assert not copy.velocity.flags.writeable
    assert np.all(np.isinf(chain.with_velocity(None).velocity))
    np.testing.assert_array_equal(chain.velocity, speeds)  # the original is untouched


@settings(max_examples=50, deadline=None)
@given(st.lists(st.one_of(st.floats(1e-6, 1e3), st.just(np.inf)), min_size=7, max_size=7))
def test_with_velocity_reads_back_and_names_the_unknown_joints(values):
    chain = get_robot("kuka-iiwa14").with_velocity(values)
    np.testing.assert_array_equal(chain.velocity, values)
    np.testing.assert_array_equal(chain.velocity_known, np.isfinite(values))
    unknown = [k + 1 for k, v in enumerate(values) if not np.isfinite(v)]
    text = missing_speeds(chain)
    if not unknown:
        assert text == ""
    elif len(unknown) == 7:
        assert text == "any joint"
    else:
        assert text.split(" ", 1)[1] == ", ".join(str(k) for k in unknown)


# ----------------------------------------------------------------------------- URDF
@pytest.mark.parametrize("path", URDFS, ids=[p.name for p in URDFS])
def test_urdf_speeds_are_the_files_own(path):
    chain = get_robot(path)
    np.testing.assert_array_equal(chain.velocity, _urdf_speeds(path.read_text(), chain.joint_names))


def test_missing_and_zero_urdf_speeds_are_unknown(tmp_path):
    file = tmp_path / "two.urdf"
    cases = {
        "absent, continuous without limit": (_two_joint_urdf('<limit lower="-1" upper="1" effort="1"/>'),
                                             [np.inf, np.inf]),
        "zero, continuous with one": (_two_joint_urdf('<limit lower="-1" upper="1" effort="1" velocity="0"/>',
                                                      second_limit='<limit effort="1" velocity="2.5"/>'),
                                      [np.inf, 2.5]),
        "given, revolute without": (_two_joint_urdf('<limit lower="-1" upper="1" effort="1" velocity="0.7"/>',
                                                    "revolute", '<limit lower="-2" upper="2" effort="1"/>'),
                                    [0.7, np.inf]),
    }
    for name, (text, expected) in cases.items():
        file.write_text(text)
        chain = get_robot(file)
        np.testing.assert_array_equal(chain.velocity, expected, err_msg=name)
        np.testing.assert_array_equal(chain.velocity, _urdf_speeds(text, chain.joint_names), err_msg=name)


def test_a_urdf_without_speeds_is_the_same_chain_otherwise(tmp_path):
    """Writing the missing velocities in before parsing changes nothing else the chain reads."""
    text = (EXAMPLES / "iiwa14.urdf").read_text()
    stripped = re.sub(r'velocity="[0-9.]+"', "", text)
    assert stripped.count("velocity=") == 0 and stripped != text
    file = tmp_path / "iiwa14_no_speeds.urdf"
    file.write_text(stripped)
    with_speeds, without = get_robot(EXAMPLES / "iiwa14.urdf"), get_robot(file)
    assert not without.velocity_known.any() and with_speeds.velocity_known.all()
    for key in ("a", "alpha", "d", "offset", "sign", "lower", "upper", "base", "tool"):
        np.testing.assert_array_equal(getattr(without, key), getattr(with_speeds, key), err_msg=key)
    assert without.joint_names == with_speeds.joint_names


@pytest.mark.parametrize("value", ["-1", "nan"])
def test_a_negative_urdf_speed_is_refused_naming_the_joint(tmp_path, value):
    file = tmp_path / "two.urdf"
    file.write_text(_two_joint_urdf(f'<limit lower="-1" upper="1" effort="1" velocity="{value}"/>'))
    with pytest.raises(RobotDescriptionError, match=r"'j1'.*velocity") as caught:
        get_robot(file)
    assert caught.value.key == "j1"


# ----------------------------------------------------------------------------- models
@pytest.mark.parametrize("name", robot_names())
def test_models_carry_their_makers_speeds_or_none(name):
    chain = get_robot(name)
    if name in MAKERS:
        np.testing.assert_allclose(chain.velocity, MAKERS[name], rtol=0, atol=1e-15)
    else:
        assert not chain.velocity_known.any()


@pytest.mark.parametrize("name, file, atol", [
    ("franka-fr3", "fr3.urdf", 0.0), ("kinova-gen3", "gen3.urdf", 0.0), ("ufactory-xarm7", "xarm7.urdf", 0.0),
    # ROS-Industrial's iiwa 14 (kuka_experimental) writes the data sheet's speeds in radians to 4 decimals
    ("kuka-iiwa14", "iiwa14_rosi.urdf", 5e-4),
])
def test_models_speeds_equal_the_example_urdfs(name, file, atol):
    text = (EXAMPLES / file).read_text()
    speeds = [float(limit.get("velocity")) for limit in ET.fromstring(text).iter("limit")]
    np.testing.assert_allclose(get_robot(name).velocity, speeds, rtol=0, atol=atol)


# ----------------------------------------------------------------------------- the step bound
@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(1e-3, 1e2), min_size=7, max_size=7), st.floats(1e-4, 10.0),
       st.lists(st.floats(1e-3, 1e2), min_size=7, max_size=7))
def test_dt_alone_takes_the_chains_speeds_and_speed_overrides_them(limits, dt, speed):
    chain = get_robot("kuka-iiwa14").with_velocity(limits)
    np.testing.assert_array_equal(step_bound(chain, dt=dt), np.array(limits) * dt)
    np.testing.assert_array_equal(step_bound(chain, speed=speed, dt=dt), np.array(speed) * dt)
    np.testing.assert_array_equal(step_bound(chain.with_velocity(None), speed=speed, dt=dt), np.array(speed) * dt)


def test_dt_alone_is_refused_naming_the_joints_without_a_speed():
    iiwa = get_robot("kuka-iiwa14")
    with pytest.raises(RedkinError, match=r"pa10-7c has no velocity limit on any joint"):
        step_bound(get_robot("pa10-7c"), dt=0.1)
    partial = replace(iiwa, joint_names=[f"A{k + 1}" for k in range(7)]).with_velocity(
        [1.0, np.inf, 1.0, 1.0, np.inf, 1.0, 1.0])
    with pytest.raises(RedkinError, match=r"on joints 2 \(A2\), 5 \(A5\):"):
        step_bound(partial, dt=0.1)
    with pytest.raises(RedkinError, match=r"on joint 7:"):
        step_bound(iiwa.with_velocity([1.0] * 6 + [np.inf]), dt=0.1)
    np.testing.assert_array_equal(step_bound(partial, speed=2.0, dt=0.1), np.full(7, 0.2))  # speed is enough


def test_the_bound_needs_one_of_max_step_and_dt():
    chain = get_robot("kuka-iiwa14")
    with pytest.raises(RedkinError, match="max_step, or as dt"):
        step_bound(chain)
    with pytest.raises(RedkinError, match="one of them"):
        step_bound(chain, max_step=0.1, dt=0.1)
    with pytest.raises(RedkinError, match="needs dt"):
        step_bound(chain, speed=1.0)
    for dt in (0.0, -1.0, np.inf, np.nan):
        with pytest.raises(RedkinError, match="dt"):
            step_bound(chain, dt=dt)


# ----------------------------------------------------------------------------- a path bounded by the speeds
def _line(count=10):
    return np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]) + np.linspace(-0.2, 0.2, count)[:, None] * np.array(
        [1.0, 0.5, -0.5, 0.0, 0.5, 0.5, 1.0])


def test_resolve_path_with_dt_alone_keeps_each_joint_within_its_speed():
    chain = get_robot("kuka-iiwa14")
    poses = chain.fk(_line())
    dt = 0.05  # the line moves joint 1 by 0.044 rad per waypoint; the bound there is 85 deg/s * dt = 0.074 rad
    result = resolve_path(chain, poses, dt=dt)
    assert result.ok, result.failure
    np.testing.assert_array_equal(result.step, chain.velocity * dt)
    assert np.all(np.abs(np.diff(result.q, axis=0)) <= chain.velocity * dt)
    assert np.abs(chain.fk(result.q) - poses).max() <= 1e-9 and chain.within_limits(result.q).all()
    same = resolve_path(chain, poses, speed=chain.velocity, dt=dt)
    np.testing.assert_array_equal(same.q, result.q)
    with pytest.raises(RedkinError, match="no velocity limit"):
        resolve_path(chain.with_velocity(None), poses, dt=dt)


def test_resolve_path_with_dt_alone_on_a_urdf_arm():
    chain = get_robot(EXAMPLES / "iiwa14.urdf")  # KUKA's 85 .. 135 deg/s, as the file writes them
    np.testing.assert_allclose(chain.velocity, get_robot("kuka-iiwa14").velocity, rtol=1e-15)
    result = resolve_path(chain, chain.fk(_line()), dt=0.05)
    assert result.ok and np.all(np.abs(np.diff(result.q, axis=0)) <= chain.velocity * 0.05)
    fr3 = get_robot(EXAMPLES / "fr3.urdf", tip="fr3_link8")  # the Franka form keeps them too
    from redkin.franka import franka_geometry

    np.testing.assert_array_equal(franka_geometry(fr3).form.velocity, fr3.velocity)
