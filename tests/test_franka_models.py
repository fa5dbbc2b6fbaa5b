"""The Franka models (``franka-panda``, the FER; ``franka-fr3``) and ``examples/fr3.urdf`` against Franka's files.

The reference is Franka's description with its numbers copied here, from frankaemika/franka_description (2025):
``robots/{fer,fr3}/kinematics.yaml`` (joint origins), ``robots/{fer,fr3}/joint_limits.yaml`` (position, velocity
and effort limits), ``robots/common/franka_arm.xacro`` (every axis ``0 0 1``, ``joint8`` the fixed flange, the
mounting link ``base``), and for the hand ``end_effectors/common/franka_hand.xacro`` with
``end_effectors/franka_hand/franka_hand_arguments.xacro`` (the hand on the flange turned by ``-pi/4`` about z, its
TCP ``0 0 0.1034`` on the hand).  :func:`maker_urdf` writes these numbers out as the kinematic part of the URDF
that Franka's xacro expands to, and :func:`tests.support.urdf_reference.reference_fk` multiplies its origins and
Rodrigues turns (``xml.etree``, no redkin).  The FER's numbers are also those of frankaemika/franka_ros
(``franka_description/robots/panda_arm.xacro``, ``robots/panda/joint_limits.yaml``).
"""

from __future__ import annotations

import functools
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from redkin.models import MODELS, franka_fr3, franka_panda, get_robot
from tests.support.urdf_reference import reference_fk

FR3_URDF = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "fr3.urdf"

#: robots/{fer,fr3}/kinematics.yaml (identical for the two arms): joint -> (xyz, rpy), as printed.
KINEMATICS = {
    "joint1": ((0, 0, 0.333), (0, 0, 0)),
    "joint2": ((0, 0, 0), (-1.570796326794897, 0, 0)),
    "joint3": ((0, -0.316, 0), (1.570796326794897, 0, 0)),
    "joint4": ((0.0825, 0, 0), (1.570796326794897, 0, 0)),
    "joint5": ((-0.0825, 0.384, 0), (-1.570796326794897, 0, 0)),
    "joint6": ((0, 0, 0), (1.570796326794897, 0, 0)),
    "joint7": ((0.088, 0, 0), (1.570796326794897, 0, 0)),
    "joint8": ((0, 0, 0.107), (0, 0, 0)),
}
#: The Franka Hand: franka_hand_arguments.xacro's rpy_ee "0 0 ${-pi/4}" and tcp_xyz "0 0 0.1034".
HAND = ((0, 0, 0), (0, 0, -np.pi / 4))
HAND_TCP = ((0, 0, 0.1034), (0, 0, 0))

#: robots/<arm>/joint_limits.yaml: per joint (lower, upper, velocity, effort).
LIMITS = {
    "fr3": [(-2.7437, 2.7437, 2.62, 87.0), (-1.7837, 1.7837, 2.62, 87.0), (-2.9007, 2.9007, 2.62, 87.0),
            (-3.0421, -0.1518, 2.62, 87.0), (-2.8065, 2.8065, 5.26, 12.0), (0.5445, 4.5169, 4.18, 12.0),
            (-3.0159, 3.0159, 5.26, 12.0)],
    "fer": [(-2.8973, 2.8973, 2.1750, 87.0), (-1.7628, 1.7628, 2.1750, 87.0), (-2.8973, 2.8973, 2.1750, 87.0),
            (-3.0718, -0.0698, 2.1750, 87.0), (-2.8973, 2.8973, 2.6100, 12.0), (-0.0175, 3.7525, 2.6100, 12.0),
            (-2.8973, 2.8973, 2.6100, 12.0)],
}
FACTORIES = {"fr3": ("franka-fr3", franka_fr3), "fer": ("franka-panda", franka_panda)}
UNIT = arrays(np.float64, 7, elements=st.floats(0.0, 1.0))


def _numbers(values) -> str:
    return " ".join(repr(float(v)) for v in values)


def maker_urdf(arm: str) -> str:
    """The kinematic part of Franka's URDF for ``arm`` ("fr3" or "fer") with the Franka Hand, in Franka's names."""
    joints = [("base_joint", "fixed", "base", "link0", ((0, 0, 0), (0, 0, 0)), None)]
    for k in range(1, 9):
        kind = "revolute" if k < 8 else "fixed"
        joints.append((f"joint{k}", kind, f"{arm}_link{k - 1}", f"link{k}", KINEMATICS[f"joint{k}"],
                       LIMITS[arm][k - 1] if k < 8 else None))
    joints += [("hand_joint", "fixed", f"{arm}_link8", "hand", HAND, None),
               ("hand_tcp_joint", "fixed", f"{arm}_hand", "hand_tcp", HAND_TCP, None)]
    body = ['<link name="base"/>']
    for name, kind, parent, child, (xyz, rpy), limit in joints:
        body.append(f'<link name="{arm}_{child}"/>')
        tags = f'<parent link="{parent}"/><child link="{arm}_{child}"/>'
        tags += f'<origin xyz="{_numbers(xyz)}" rpy="{_numbers(rpy)}"/>'
        if limit is not None:
            lower, upper, velocity, effort = limit
            tags += '<axis xyz="0 0 1"/>'
            tags += f'<limit lower="{lower}" upper="{upper}" effort="{effort}" velocity="{velocity}"/>'
        body.append(f'<joint name="{arm}_{name}" type="{kind}">{tags}</joint>')
    return f'<robot name="{arm}">{"".join(body)}</robot>'


def _in_limits(arm: str, unit: np.ndarray) -> np.ndarray:
    """Joint values inside the maker's limits: ``unit`` in [0, 1] mapped onto each range (ends included)."""
    lower, upper = np.array([entry[:2] for entry in LIMITS[arm]]).T
    return lower + unit * (upper - lower)


@functools.cache
def _chain(case: str):
    """The chain under test: a model by name, or examples/fr3.urdf to a tip link."""
    if case.startswith("franka-"):
        return get_robot(case)
    return get_robot(FR3_URDF, tip=case.split(":")[1]) if ":" in case else get_robot(FR3_URDF)


#: chain under test -> (Franka's arm, the link of Franka's URDF whose pose it must equal).
CASES = {
    "franka-fr3": ("fr3", "fr3_link8"),
    "franka-panda": ("fer", "fer_link8"),
    "fr3.urdf:fr3_link8": ("fr3", "fr3_link8"),
    "fr3.urdf:fr3_hand": ("fr3", "fr3_hand"),
    "fr3.urdf:fr3_hand_tcp": ("fr3", "fr3_hand_tcp"),
    "fr3.urdf (default tip)": ("fr3", "fr3_hand_tcp"),
}


@pytest.mark.parametrize("case", CASES)
@settings(max_examples=40, deadline=None)
@given(unit=UNIT)
def test_pose_equals_the_product_of_frankas_frames(case, unit):
    arm, link = CASES[case]
    q = _in_limits(arm, unit)
    np.testing.assert_allclose(_chain(case).fk(q), reference_fk(maker_urdf(arm), q, link), rtol=0, atol=1e-12)


@pytest.mark.parametrize("case", CASES)
def test_batched_poses_and_the_limit_corners_equal_frankas_frames(case):
    """Above 16 configurations the chain propagates axis columns instead of multiplying matrices."""
    arm, link = CASES[case]
    unit = np.vstack([np.zeros(7), np.ones(7), np.random.default_rng(24).uniform(0, 1, (38, 7))])
    q = _in_limits(arm, unit)
    text = maker_urdf(arm)
    expected = np.array([reference_fk(text, row, link) for row in q])
    np.testing.assert_allclose(_chain(case).fk(q), expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize("arm", FACTORIES)
def test_models_are_named_with_frankas_limits_and_source(arm):
    name, factory = FACTORIES[arm]
    chain = get_robot(name)
    assert MODELS[name] is factory and chain.name == name and chain.n == 7
    assert "franka_description" in chain.source
    lower, upper = np.array([entry[:2] for entry in LIMITS[arm]]).T
    np.testing.assert_array_equal(chain.lower, lower)
    np.testing.assert_array_equal(chain.upper, upper)
    np.testing.assert_array_equal(chain.sign, np.ones(7))  # Franka's own joint senses


@pytest.mark.parametrize("arm", FACTORIES)
def test_docstring_tables_print_frankas_ranges_and_speeds(arm):
    """The table in each model's docstring: joint i, its range [lower, upper] and its speed, as Franka's file."""
    rows = re.findall(r"^\s*(\d)\s.*\[(\S+), (\S+)\]\s+(\S+)\s*$", FACTORIES[arm][1].__doc__, flags=re.M)
    printed = [(float(lo), float(hi), float(speed)) for _, lo, hi, speed in rows]
    assert [int(i) for i, *_ in rows] == list(range(1, 8))
    assert printed == [entry[:3] for entry in LIMITS[arm]]


def test_fr3_urdf_is_frankas_kinematics_joint_for_joint():
    """examples/fr3.urdf has Franka's links, joints, origins, axes and limits (velocity and effort included)."""

    def kinematics(text: str) -> tuple[set, dict]:
        root = ET.fromstring(text)
        joints = {}
        for joint in root.findall("joint"):
            origin, axis, limit = joint.find("origin"), joint.find("axis"), joint.find("limit")
            joints[joint.get("name")] = (
                joint.get("type"), joint.find("parent").get("link"), joint.find("child").get("link"),
                [float(v) for v in origin.get("xyz").split()], [float(v) for v in origin.get("rpy").split()],
                None if axis is None else [float(v) for v in axis.get("xyz").split()],
                None if limit is None else {key: float(value) for key, value in limit.attrib.items()},
            )
        return {link.get("name") for link in root.findall("link")}, joints

    example_links, example = kinematics(FR3_URDF.read_text())
    maker_links, maker = kinematics(maker_urdf("fr3"))
    assert example_links == maker_links and set(example) == set(maker)
    for name, (kind, parent, child, xyz, rpy, axis, limit) in maker.items():
        got = example[name]
        assert got[:3] == (kind, parent, child) and got[5] == axis and got[6] == limit, name
        np.testing.assert_allclose(got[3], xyz, rtol=0, atol=0, err_msg=name)
        np.testing.assert_allclose(got[4], rpy, rtol=0, atol=1e-15, err_msg=name)


def test_fr3_urdf_chains_name_frankas_joints_and_keep_its_limits():
    chain = _chain("fr3.urdf:fr3_link8")
    assert chain.joint_names == tuple(f"fr3_joint{k}" for k in range(1, 8))
    assert chain.source.endswith("base -> fr3_link8") and _chain("fr3.urdf (default tip)").source.endswith(
        "base -> fr3_hand_tcp")
    np.testing.assert_array_equal(chain.limits, franka_fr3().limits)
