"""MJCF import: the DH chain equals an independent product of the file's frames and hinge rotations.

The reference below reads the XML with ``xml.etree`` (neither MuJoCo nor redkin) and multiplies, as
MJCF defines them, each body's ``pos`` and orientation (``quat``, ``axisangle``, ``euler`` in the
compiler's ``eulerseq``, ``xyaxes`` or ``zaxis``, in the compiler's ``angle`` unit) with the rotations
of its hinges by ``qpos - ref`` about their ``axis`` through their ``pos``; ``<default>`` classes,
nested classes and ``childclass`` supply what an element leaves out.  The files are a Menagerie-style
iiwa14 (the shipped ``examples/iiwa14.xml``) and Panda written from the makers' numbers (the frames of
``examples/iiwa14.urdf``, ``examples/panda.urdf`` and ``examples/fr3.urdf``), the iiwa14 again in degrees
with every frame form, and random chains (hypothesis).  The chains must equal the reference, MuJoCo's own
kinematics at the same ``qpos``, and our URDF models where the frames agree, to 1e-12.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

pytest.importorskip("mujoco", reason="the mjcf extra (mujoco) is not installed")

import mujoco

from redkin.errors import RedkinError, RobotDescriptionError
from redkin.mjcf import load_mjcf
from redkin.models import franka_panda, get_robot, kuka_iiwa14

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"

# ----------------------------------------------------------------------------- the files
#: The iiwa14 as MuJoCo Menagerie writes it (kuka_iiwa_14/iiwa14.xml: its classes, frames and numbers), without
#: meshes, geoms and actuators; the attachment site is the flange, 0.045 m beyond link 7 (KUKA's data sheet).
#: Shipped as the example ``examples/iiwa14.xml``, which the README reads.
IIWA14 = (EXAMPLES / "iiwa14.xml").read_text(encoding="utf-8")

#: The same arm in degrees, each frame in another form (euler in the sequence z, y', x'', axisangle, quat,
#: xyaxes, zaxis), the ranges in degrees (KUKA's data sheet) and the joint axes from the class.
IIWA14_DEGREES = """
<mujoco model="iiwa14-degrees">
  <compiler angle="degree" eulerseq="zyx"/>
  <default>
    <joint axis="0 0 1"/>
    <default class="a1"><joint range="-170 170"/></default>
    <default class="a2"><joint range="-120 120"/></default>
    <default class="a7"><joint range="-175 175"/></default>
  </default>
  <worldbody>
    <body name="base">
      <inertial mass="5" pos="0 0 0.07" diaginertia="0.05 0.06 0.03"/>
      <body name="link1" pos="0 0 0.1575">
        <inertial mass="1" pos="0 0 0.1" diaginertia="0.01 0.01 0.01"/>
        <joint name="A1" class="a1"/>
        <body name="link2" pos="0 0 0.2025" euler="180 0 90">
          <inertial mass="1" pos="0 0.1 0" diaginertia="0.01 0.01 0.01"/>
          <joint name="A2" class="a2"/>
          <body name="link3" pos="0 0.2045 0" axisangle="0 1 1 180">
            <inertial mass="1" pos="0 0 0.1" diaginertia="0.01 0.01 0.01"/>
            <joint name="A3" class="a1"/>
            <body name="link4" pos="0 0 0.2155" quat="1 1 0 0">
              <inertial mass="1" pos="0 0.1 0" diaginertia="0.01 0.01 0.01"/>
              <joint name="A4" class="a2"/>
              <body name="link5" pos="0 0.1845 0" xyaxes="-1 0 0 0 0 1">
                <inertial mass="1" pos="0 0 0.1" diaginertia="0.01 0.01 0.01"/>
                <joint name="A5" class="a1"/>
                <body name="link6" pos="0 0 0.2155" zaxis="0 -1 0">
                  <inertial mass="1" pos="0 0 0" diaginertia="0.01 0.01 0.01"/>
                  <joint name="A6" class="a2"/>
                  <body name="link7" pos="0 0.081 0" euler="180 0 90">
                    <inertial mass="1" pos="0 0 0.02" diaginertia="0.001 0.001 0.001"/>
                    <joint name="A7" class="a7"/>
                    <site name="flange" pos="0 0 0.045"/>
                  </body>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

#: The Panda in Menagerie's style (franka_emika_panda/panda.xml: class ranges with per-joint overrides,
#: quat frames, slide-joint fingers), some frames as euler angles in radians, the hand turned -pi/4 about z
#: as an axis-angle written to 16 digits (Menagerie prints its quat to 7), and the hand's TCP as a site.
PANDA = """
<mujoco model="panda">
  <compiler angle="radian" autolimits="true"/>
  <default>
    <default class="panda">
      <joint armature="0.1" damping="1" axis="0 0 1" range="-2.8973 2.8973"/>
      <default class="finger">
        <joint axis="0 1 0" type="slide" range="0 0.04"/>
      </default>
    </default>
  </default>
  <worldbody>
    <body name="link0" childclass="panda">
      <inertial mass="0.63" pos="-0.041 0 0.05" diaginertia="0.003 0.004 0.004"/>
      <body name="link1" pos="0 0 0.333">
        <inertial mass="4.97" pos="0.0039 0.0021 -0.0476" diaginertia="0.7 0.7 0.009"/>
        <joint name="joint1"/>
        <body name="link2" quat="1 -1 0 0">
          <inertial mass="0.65" pos="-0.0031 -0.0287 0.0035" diaginertia="0.008 0.028 0.026"/>
          <joint name="joint2" range="-1.7628 1.7628"/>
          <body name="link3" pos="0 -0.316 0" euler="1.5707963267948966 0 0">
            <joint name="joint3"/>
            <inertial mass="3.23" pos="0.0275 0.0393 -0.0665" diaginertia="0.037 0.036 0.011"/>
            <body name="link4" pos="0.0825 0 0" quat="1 1 0 0">
              <inertial mass="3.59" pos="-0.0532 0.1044 0.0275" diaginertia="0.026 0.02 0.028"/>
              <joint name="joint4" range="-3.0718 -0.0698"/>
              <body name="link5" pos="-0.0825 0.384 0" quat="1 -1 0 0">
                <inertial mass="1.23" pos="-0.012 0.041 -0.038" diaginertia="0.036 0.029 0.009"/>
                <joint name="joint5"/>
                <body name="link6" euler="1.5707963267948966 0 0">
                  <inertial mass="1.67" pos="0.06 -0.014 -0.011" diaginertia="0.002 0.004 0.005"/>
                  <joint name="joint6" range="-0.0175 3.7525"/>
                  <body name="link7" pos="0.088 0 0" quat="1 1 0 0">
                    <inertial mass="0.74" pos="0.0105 -0.0043 0.0616" diaginertia="0.013 0.01 0.005"/>
                    <joint name="joint7"/>
                    <body name="link8" pos="0 0 0.107">
                      <body name="hand" axisangle="0 0 1 -0.7853981633974483">
                        <inertial mass="0.73" pos="-0.01 0 0.03" diaginertia="0.001 0.0025 0.0017"/>
                        <site name="tcp" pos="0 0 0.1034"/>
                        <body name="left_finger" pos="0 0 0.0584">
                          <inertial mass="0.015" pos="0 0 0" diaginertia="2.375e-6 2.375e-6 7.5e-7"/>
                          <joint name="finger_joint1" class="finger"/>
                        </body>
                        <body name="right_finger" pos="0 0 0.0584" quat="0 0 0 1">
                          <inertial mass="0.015" pos="0 0 0" diaginertia="2.375e-6 2.375e-6 7.5e-7"/>
                          <joint name="finger_joint2" class="finger"/>
                        </body>
                      </body>
                    </body>
                  </body>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

FILES = {"iiwa14": (IIWA14, "attachment_site"), "iiwa14 in degrees": (IIWA14_DEGREES, "flange"),
         "panda to the hand's TCP": (PANDA, "tcp")}


def _write(tmp_path: Path, text: str, name: str = "robot.xml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# ----------------------------------------------------------------------------- the reference
def _basic(axis: str, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def _turn(axis, angle: float) -> np.ndarray:
    """Rodrigues: the rotation by ``angle`` about ``axis``."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * skew + (1 - np.cos(angle)) * skew @ skew


def _numbers(text: str) -> np.ndarray:
    return np.array([float(v) for v in text.split()])


def _orientation(attrs: dict, unit: float, sequence: str) -> np.ndarray:
    """An MJCF frame's rotation matrix, as the MJCF reference defines each form."""
    if "quat" in attrs:
        w, x, y, z = _numbers(attrs["quat"]) / np.linalg.norm(_numbers(attrs["quat"]))
        return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    if "axisangle" in attrs:
        values = _numbers(attrs["axisangle"])
        return _turn(values[:3], values[3] * unit)
    if "euler" in attrs:  # lower case: about the rotating axes (post-multiplied); upper case: the fixed ones
        rotation = np.eye(3)
        for axis, angle in zip(sequence, _numbers(attrs["euler"]) * unit):
            step = _basic(axis.lower(), angle)
            rotation = rotation @ step if axis.islower() else step @ rotation
        return rotation
    if "xyaxes" in attrs:
        values = _numbers(attrs["xyaxes"])
        x = values[:3] / np.linalg.norm(values[:3])
        y = values[3:] - (values[3:] @ x) * x
        y /= np.linalg.norm(y)
        return np.column_stack([x, y, np.cross(x, y)])
    if "zaxis" in attrs:  # the smallest rotation taking z to the given axis
        z = _numbers(attrs["zaxis"]) / np.linalg.norm(_numbers(attrs["zaxis"]))
        normal = np.cross([0.0, 0.0, 1.0], z)
        if np.linalg.norm(normal) < 1e-15:
            return np.eye(3)
        return _turn(normal, np.arctan2(np.linalg.norm(normal), z[2]))
    return np.eye(3)


def _frame(attrs: dict, unit: float, sequence: str) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = _orientation(attrs, unit, sequence)
    pose[:3, 3] = _numbers(attrs.get("pos", "0 0 0"))
    return pose


def _classes(root: ET.Element) -> dict[str, dict[str, dict]]:
    """Each default class's attributes per element kind, nested classes inheriting from their parent."""
    classes: dict[str, dict[str, dict]] = {}

    def walk(node, name, inherited):
        own = {tag: dict(attrs) for tag, attrs in inherited.items()}
        for child in node:
            if child.tag != "default":
                own.setdefault(child.tag, {}).update(child.attrib)
        classes[name] = own
        for child in node.findall("default"):
            walk(child, child.get("class"), own)

    top = root.find("default")
    walk(top if top is not None else ET.Element("default"), "main", {})
    return classes


class Reference:
    """The poses of an MJCF's bodies and sites at given hinge values, from the MJCF definition alone."""

    def __init__(self, text: str):
        self.root = ET.fromstring(text)
        compiler = self.root.find("compiler")
        compiler = {} if compiler is None else compiler.attrib
        self.unit = np.pi / 180 if compiler.get("angle", "degree") == "degree" else 1.0
        self.sequence = compiler.get("eulerseq", "xyz")
        self.classes = _classes(self.root)

    def attributes(self, element: ET.Element, childclass: str) -> dict:
        return {**self.classes[element.get("class", childclass)].get(element.tag, {}), **element.attrib}

    def joints(self) -> dict[str, tuple[float, float]]:
        """Every joint's range (radians), in document order; ``(-inf, inf)`` without one."""
        ranges = {}
        for joint, attrs, _ in self._walk():
            low, high = _numbers(attrs["range"]) * self.unit if "range" in attrs else (-np.inf, np.inf)
            ranges[joint.get("name")] = (float(low), float(high))
        return ranges

    def _walk(self, body=None, childclass="main"):
        body = self.root.find("worldbody") if body is None else body
        for element in body:
            if element.tag == "joint":
                yield element, self.attributes(element, childclass), body
            elif element.tag == "body":
                yield from self._walk(element, element.get("childclass", childclass))

    def poses(self, qpos: dict[str, float]) -> dict[str, np.ndarray]:
        """World poses of every named body and site with the named hinges at ``qpos`` (others at ``ref``)."""
        found: dict[str, np.ndarray] = {"world": np.eye(4)}
        self._pose_below(self.root.find("worldbody"), np.eye(4), "main", qpos, found)
        return found

    def _pose_below(self, body, pose, childclass, qpos, found):
        for element in body:
            if element.tag != "body":
                continue
            inner = element.get("childclass", childclass)
            here = pose @ _frame(element.attrib, self.unit, self.sequence)
            for joint in element.findall("joint"):
                attrs = self.attributes(joint, inner)
                kind, axis = attrs.get("type", "hinge"), _numbers(attrs.get("axis", "0 0 1"))
                assert kind in ("hinge", "slide"), "the reference moves hinges and slides only"
                ref = float(attrs.get("ref", 0.0)) * (self.unit if kind == "hinge" else 1.0)
                move, step = qpos.get(joint.get("name"), ref) - ref, np.eye(4)
                if kind == "slide":
                    step[:3, 3] = move * axis / np.linalg.norm(axis)
                else:  # a turn about the line through the anchor
                    anchor = _numbers(attrs.get("pos", "0 0 0"))
                    step[:3, :3] = _turn(axis, move)
                    step[:3, 3] = anchor - step[:3, :3] @ anchor
                here = here @ step
            found[element.get("name")] = here
            for site in element.findall("site"):
                found[site.get("name")] = here @ _frame(self.attributes(site, inner), self.unit, self.sequence)
            self._pose_below(element, here, inner, qpos, found)


def _random_q(chain, rng: np.random.Generator, count: int) -> np.ndarray:
    low = np.where(np.isfinite(chain.lower), chain.lower, -np.pi)
    high = np.where(np.isfinite(chain.upper), chain.upper, np.pi)
    return rng.uniform(low, high, (count, chain.n))


def _mujoco_pose(path: Path, names, q: np.ndarray, tip: str) -> np.ndarray:
    """MuJoCo's own world pose of ``tip`` (a body, else a site) with the named hinges at ``q``."""
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    for name, value in zip(names, q):
        data.qpos[model.joint(name).qposadr[0]] = value
    mujoco.mj_kinematics(model, data)
    pose = np.eye(4)
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, tip) >= 0:
        pose[:3, :3], pose[:3, 3] = data.body(tip).xmat.reshape(3, 3), data.body(tip).xpos
    else:
        pose[:3, :3], pose[:3, 3] = data.site(tip).xmat.reshape(3, 3), data.site(tip).xpos
    return pose


# ----------------------------------------------------------------------------- the laws
@pytest.mark.parametrize("name", FILES)
def test_chain_equals_the_product_of_the_mjcf_frames_and_mujoco(tmp_path, name):
    text, tip = FILES[name]
    path = _write(tmp_path, text)
    chain = load_mjcf(path, tip=tip)
    reference = Reference(text)
    q = _random_q(chain, np.random.default_rng(11), 30)
    expected = np.array([reference.poses(dict(zip(chain.joint_names, row)))[tip] for row in q])
    np.testing.assert_allclose(chain.fk(q), expected, rtol=0, atol=1e-12)
    for row in q[:5]:
        np.testing.assert_allclose(chain.fk(row), _mujoco_pose(path, chain.joint_names, row, tip), rtol=0, atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(q_seed=st.integers(0, 2**16))
def test_menagerie_style_iiwa14_is_our_urdf_and_model(tmp_path_factory, q_seed):
    """The issue's target: FK of a Menagerie-style iiwa14 equals the named model and the example URDF to 1e-12,
    for random in-limit q: the world is the URDF's root link, the attachment site its flange."""
    folder = tmp_path_factory.mktemp("mjcf")
    model, urdf = kuka_iiwa14(), get_robot(EXAMPLES / "iiwa14.urdf")
    q = _random_q(model, np.random.default_rng(q_seed), 20)
    for text, tip in (FILES["iiwa14"], FILES["iiwa14 in degrees"]):
        chain = load_mjcf(_write(folder, text), tip=tip)
        np.testing.assert_allclose(chain.fk(q), model.fk(q), rtol=0, atol=1e-12)
        np.testing.assert_allclose(chain.fk(q), urdf.fk(q), rtol=0, atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(q_seed=st.integers(0, 2**16))
def test_menagerie_style_panda_is_our_urdf_and_model(tmp_path_factory, q_seed):
    """The same for the Panda: link 8 is the flange of ``franka-panda`` and ``examples/panda.urdf``, the hand
    and its TCP are ``fr3_hand`` and ``fr3_hand_tcp`` of ``examples/fr3.urdf`` (the FR3 has the FER's frames)."""
    path = _write(tmp_path_factory.mktemp("mjcf"), PANDA)
    model = franka_panda()
    q = _random_q(model, np.random.default_rng(q_seed), 20)
    flange = load_mjcf(path, tip="link8")
    np.testing.assert_allclose(flange.fk(q), model.fk(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(flange.fk(q), get_robot(EXAMPLES / "panda.urdf").fk(q), rtol=0, atol=1e-12)
    for tip, link in (("hand", "fr3_hand"), ("tcp", "fr3_hand_tcp")):
        urdf = get_robot(EXAMPLES / "fr3.urdf", tip=link)
        np.testing.assert_allclose(load_mjcf(path, tip=tip).fk(q), urdf.fk(q), rtol=0, atol=1e-12)


_AXES = ["0 0 1", "0 0 -1", "1 0 0", "0 1 0", "0 -1 0", "1 1 0", "0.3 -0.4 0.87", "1 2 -2"]
_ANGLES = st.integers(-24, 24).map(lambda k: 7.5 * k)  # degrees; converted below for radian files


@st.composite
def _random_mjcf(draw):
    """A random chain of bodies (with a side branch), each frame in a random form, with 0-2 hinges per body
    (random anchors, axes, refs, ranges or none), in degrees or radians and a random Euler sequence."""
    degree = draw(st.booleans())
    sequence = draw(st.sampled_from(["xyz", "zyx", "XYZ", "zYx", "yxz"]))
    scale = 1.0 if degree else np.pi / 180

    def angle():
        return repr(draw(_ANGLES) * scale)

    def position():
        return " ".join(repr(draw(st.integers(-10, 10)) / 20) for _ in range(3))

    def orientation():
        form = draw(st.sampled_from(["none", "quat", "axisangle", "euler", "xyaxes", "zaxis"]))
        if form == "quat":
            return f' quat="{" ".join(str(draw(st.integers(-3, 3))) for _ in range(3))} 2"'
        if form == "axisangle":
            return f' axisangle="{draw(st.sampled_from(_AXES))} {angle()}"'
        if form == "euler":
            return f' euler="{angle()} {angle()} {angle()}"'
        if form == "xyaxes":
            return f' xyaxes="{draw(st.sampled_from(["1 0 0 0 1 0", "0 1 0 -1 0 0", "1 1 0 0 1 1", "0 0 1 1 0 0"]))}"'
        if form == "zaxis":
            return f' zaxis="{draw(st.sampled_from(["1 0 0", "0 1 0", "1 1 1", "0.3 -0.4 0.87"]))}"'
        return ""

    inertial = '<inertial mass="1" pos="0 0 0" diaginertia="0.1 0.1 0.1"/>'
    count, hinges = draw(st.integers(1, 6)), 0
    text = ""
    for k in range(count):
        joints = ""
        for j in range(draw(st.integers(0, 2))):
            ref = f' ref="{angle()}"' if draw(st.booleans()) else ""
            limit = f' range="{-abs(float(angle())) - 30 * scale} {abs(float(angle())) + 20 * scale}"' \
                if draw(st.booleans()) else ""
            joints += f'<joint name="j{k}_{j}" axis="{draw(st.sampled_from(_AXES))}" pos="{position()}"{ref}{limit}/>'
            hinges += 1
        side = f'<body name="side{k}" pos="0.1 0 0">{inertial}</body>' if k == 0 and count > 1 else ""
        text += f'<body name="b{k}" pos="{position()}"{orientation()}>{inertial}{joints}{side}'
    if hinges == 0:
        text = text.replace(inertial, inertial + '<joint name="only" axis="0 1 0"/>', 1)
    text += f'<site name="tip" pos="{position()}"{orientation()}/>' + "</body>" * count
    compiler = f'<compiler angle="{"degree" if degree else "radian"}" eulerseq="{sequence}" autolimits="true"/>'
    return f"<mujoco>{compiler}<worldbody>{text}</worldbody></mujoco>"


@settings(max_examples=60, deadline=None)
@given(text=_random_mjcf(), q_seed=st.integers(0, 2**16))
def test_any_chain_of_frames_and_hinges_matches(tmp_path_factory, text, q_seed):
    """Random MJCF chains: FK equals the MJCF's own product and MuJoCo's kinematics at the same qpos."""
    reference = Reference(text)
    path = _write(tmp_path_factory.mktemp("mjcf"), text)
    chain = load_mjcf(path, tip="tip")
    directions = _world_axes(path, chain.joint_names)
    tilts = np.linalg.norm(np.cross(directions[:-1], directions[1:]), axis=-1)
    assume(not np.any((tilts > 1e-9) & (tilts < 1e-3)))  # nearly parallel axes cost digits (docs/urdf.md)
    q = _random_q(chain, np.random.default_rng(q_seed), 5)
    for row in q:
        expected = reference.poses(dict(zip(chain.joint_names, row)))["tip"]
        np.testing.assert_allclose(chain.fk(row), expected, rtol=0, atol=1e-12)
        np.testing.assert_allclose(chain.fk(row), _mujoco_pose(path, chain.joint_names, row, "tip"), rtol=0,
                                   atol=1e-12)
    ranges = reference.joints()
    np.testing.assert_allclose(chain.lower, [ranges[n][0] for n in chain.joint_names], rtol=1e-15, atol=0)
    np.testing.assert_allclose(chain.upper, [ranges[n][1] for n in chain.joint_names], rtol=1e-15, atol=0)


def _world_axes(path: Path, names) -> np.ndarray:
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    return np.array([data.joint(name).xaxis for name in names])


def test_a_hinge_with_ref_takes_mujocos_qpos_and_two_hinges_in_one_body_chain_in_order(tmp_path):
    """``q`` is MuJoCo's ``qpos``: the pose the file writes is ``q = ref``; a body's hinges compose in order."""
    text = """<mujoco><compiler angle="degree"/><worldbody>
      <body name="upper" pos="0 0 0.3" euler="0 30 0"><inertial mass="1" diaginertia="1 1 1" pos="0 0 0"/>
        <joint name="yaw" axis="0 0 1" ref="40" range="-100 120"/>
        <joint name="pitch" axis="0 1 0" pos="0 0 0.1" ref="-25"/>
        <body name="lower" pos="0.4 0 0" quat="1 0.2 0 0"><inertial mass="1" diaginertia="1 1 1" pos="0 0 0"/>
          <joint name="elbow" axis="1 1 0" pos="0.1 0 0" range="-90 90"/>
          <site name="end" pos="0.2 0 0.05" axisangle="1 0 0 90"/>
        </body>
      </body></worldbody></mujoco>"""
    path = _write(tmp_path, text)
    chain = load_mjcf(path, tip="end")
    assert chain.joint_names == ("yaw", "pitch", "elbow")
    reference = Reference(text)
    written = reference.poses({})["end"]  # every hinge at its ref: the pose as written
    np.testing.assert_allclose(chain.fk(np.radians([40, -25, 0])), written, rtol=0, atol=1e-12)
    rng = np.random.default_rng(5)
    for row in _random_q(chain, rng, 10):
        np.testing.assert_allclose(chain.fk(row), reference.poses(dict(zip(chain.joint_names, row)))["end"],
                                   rtol=0, atol=1e-12)
        np.testing.assert_allclose(chain.fk(row), _mujoco_pose(path, chain.joint_names, row, "end"), rtol=0,
                                   atol=1e-12)
    np.testing.assert_allclose(chain.lower, np.radians([-100, -np.inf, -90]), rtol=1e-15)
    np.testing.assert_allclose(chain.upper, np.radians([120, np.inf, 90]), rtol=1e-15)


def test_limits_names_and_source_come_from_the_compiled_model(tmp_path):
    degrees = load_mjcf(_write(tmp_path, IIWA14_DEGREES), tip="flange")
    assert degrees.joint_names == ("A1", "A2", "A3", "A4", "A5", "A6", "A7")
    np.testing.assert_allclose(degrees.limits, kuka_iiwa14().limits, rtol=0, atol=1e-15)  # degrees converted
    panda = load_mjcf(_write(tmp_path, PANDA, "panda.xml"), tip="tcp")
    np.testing.assert_array_equal(panda.limits, franka_panda().limits)  # class range, per-joint overrides
    assert panda.joint_names == tuple(f"joint{k}" for k in range(1, 8))
    assert panda.name == "panda" and panda.source.endswith("body world -> site tcp")
    free = IIWA14.replace('class="joint3"/>', 'class="joint3" limited="false"/>')
    unlimited = load_mjcf(_write(tmp_path, free, "free.xml"))
    np.testing.assert_array_equal(unlimited.limits[6], [-np.inf, np.inf])  # the class's range, but not limited
    np.testing.assert_array_equal(unlimited.limits[:6], kuka_iiwa14().limits[:6])


def test_the_default_tip_is_the_only_leaf_and_base_picks_a_sub_chain(tmp_path):
    path = _write(tmp_path, IIWA14)
    reference = Reference(IIWA14)
    whole = load_mjcf(path)  # world to the only leaf, link 7
    assert whole.n == 7 and whole.source.endswith("body world -> body link7")
    q = _random_q(whole, np.random.default_rng(2), 10)
    sub = load_mjcf(path, base="link3", tip="attachment_site")  # link 3's frame to the site: joints 4 to 7
    assert sub.joint_names == ("joint4", "joint5", "joint6", "joint7")
    for row in q:
        poses = reference.poses(dict(zip(whole.joint_names, row)))
        np.testing.assert_allclose(whole.fk(row), poses["link7"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(sub.fk(row[3:]), np.linalg.inv(poses["link3"]) @ poses["attachment_site"],
                                   rtol=0, atol=1e-12)


def test_a_robot_placed_in_the_world_keeps_its_placement_unless_its_body_is_the_base(tmp_path):
    placed = IIWA14.replace('<body name="base" childclass="iiwa">',
                            '<body name="base" childclass="iiwa" pos="1 -0.5 0.8" euler="0 0 1.2">')
    path = _write(tmp_path, placed)
    q = _random_q(kuka_iiwa14(), np.random.default_rng(4), 10)
    in_world = load_mjcf(path, tip="attachment_site")
    on_base = load_mjcf(path, base="base", tip="attachment_site")
    np.testing.assert_allclose(on_base.fk(q), kuka_iiwa14().fk(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(in_world.fk(q), Reference(placed).poses({})["base"] @ kuka_iiwa14().fk(q), rtol=0,
                               atol=1e-12)


def test_a_kinematics_only_file_without_masses_loads(tmp_path):
    """Bodies and hinges alone (no inertial, no geom) describe a chain: MuJoCo itself refuses such a file as a model
    to simulate, redkin compiles it with a least mass per body and reads the same kinematics."""
    text = "".join(line for line in IIWA14.splitlines(keepends=True) if "<inertial" not in line)
    path = _write(tmp_path, text)
    with pytest.raises(ValueError, match="mass and inertia of moving bodies"):
        mujoco.MjModel.from_xml_path(str(path))
    chain = load_mjcf(path, tip="attachment_site")
    q = _random_q(chain, np.random.default_rng(8), 20)
    np.testing.assert_allclose(chain.fk(q), kuka_iiwa14().fk(q), rtol=0, atol=1e-12)
    reference = Reference(text)
    for row in q[:5]:
        np.testing.assert_allclose(chain.fk(row), reference.poses(dict(zip(chain.joint_names, row)))["attachment_site"],
                                   rtol=0, atol=1e-12)


def test_unnamed_joints_and_an_unnamed_model_get_names(tmp_path):
    text = """<mujoco><worldbody><body name="arm"><inertial mass="1" diaginertia="1 1 1" pos="0 0 0"/>
      <joint axis="0 0 1"/><joint axis="0 1 0"/>
      <body pos="0 0 1"><inertial mass="1" diaginertia="1 1 1" pos="0 0 0"/><joint axis="1 0 0"/></body>
      </body></worldbody></mujoco>"""
    chain = load_mjcf(_write(tmp_path, text, "unnamed.xml"))
    assert chain.joint_names == ("arm joint 1", "arm joint 2", "#2 joint") and chain.name == "unnamed"


# ----------------------------------------------------------------------------- refusals
def _refusal(tmp_path, text: str, **names) -> RobotDescriptionError:
    path = _write(tmp_path, text)
    with pytest.raises(RobotDescriptionError) as caught:
        load_mjcf(path, **names)
    assert "\n" not in str(caught.value) and caught.value.path == str(path)
    return caught.value


def test_slide_ball_and_free_joints_on_the_way_are_refused_by_name(tmp_path):
    error = _refusal(tmp_path, PANDA, tip="left_finger")
    assert error.key == "finger_joint1" and "'finger_joint1' of body 'left_finger' is a slide joint" in str(error)
    ball = IIWA14.replace('<joint name="joint4" class="joint2"/>', '<joint name="joint4" type="ball"/>')
    assert "'joint4' of body 'link4' is a ball joint" in str(_refusal(tmp_path, ball))
    free = IIWA14.replace('<body name="base" childclass="iiwa">',
                          '<body name="base" childclass="iiwa"><freejoint name="floating"/>')
    assert "'floating' of body 'base' is a free joint" in str(_refusal(tmp_path, free))
    chain = load_mjcf(_write(tmp_path, free, "floating.xml"), base="base")  # above the base it does not matter
    assert chain.n == 7


def test_unknown_names_a_tip_not_below_the_base_and_several_leaves_are_refused(tmp_path):
    error = _refusal(tmp_path, IIWA14, tip="flange")
    assert error.key == "flange" and "no body or site named 'flange'" in str(error)
    assert "bodies: base, link1, link2" in str(error) and "sites: attachment_site" in str(error)
    error = _refusal(tmp_path, IIWA14, base="link0")
    assert "no body named 'link0' for the base (bodies: base, link1," in str(error)
    assert "a site: the base must be a body" in str(_refusal(tmp_path, IIWA14, base="attachment_site"))
    error = _refusal(tmp_path, IIWA14, base="link5", tip="link2")
    assert error.key == "link2" and "'link2' is not below body 'link5'" in str(error)
    error = _refusal(tmp_path, PANDA)
    assert "the tree below body 'world' has 2 leaves (left_finger, right_finger); name one with --tip" in str(error)
    error = _refusal(tmp_path, IIWA14, base="link7", tip="attachment_site")
    assert "no hinge joint between body 'link7' and 'attachment_site'" in str(error)


def test_a_reversed_range_is_as_mujoco_reads_it(tmp_path):
    """MuJoCo refuses ``range="1 -1"`` on a joint marked limited; under autolimits the chain is as MuJoCo reads it."""
    error = _refusal(tmp_path, IIWA14.replace('<joint name="joint5" class="joint1"/>',
                                              '<joint name="joint5" range="1 -1" limited="true"/>'))
    assert "malformed MJCF: Error: range[0] should be smaller than range[1] in joint" in str(error)
    assert "joint5" in str(error)  # MuJoCo's wording of where differs between versions
    text = IIWA14.replace('<joint name="joint5" class="joint1"/>', '<joint name="joint5" range="1 -1"/>')
    path = _write(tmp_path, text, "auto.xml")
    try:  # under autolimits MuJoCo 3.0 refuses it too; later versions compile it as unlimited
        mujoco.MjModel.from_xml_path(str(path))
    except ValueError:
        with pytest.raises(RobotDescriptionError, match="malformed MJCF: Error: range"):
            load_mjcf(path)
    else:
        np.testing.assert_array_equal(load_mjcf(path).limits[4], [-np.inf, np.inf])


def test_coupled_joints_are_refused(tmp_path):
    coupled = IIWA14.replace("</worldbody>", '</worldbody><equality><joint joint1="joint6" joint2="joint7"/>'
                             "</equality>")
    error = _refusal(tmp_path, coupled)
    assert error.key == "joint6" and "coupled to joint 'joint7' by an <equality><joint>" in str(error)


def test_a_malformed_or_missing_file_is_one_line_with_mujocos_whole_reason(tmp_path):
    text = IIWA14.replace('<joint name="joint3" class="joint1"/>', '<joint name="joint3" class="joint1" stiff="3"/>')
    line = 1 + text[: text.index("stiff")].count("\n")
    error = _refusal(tmp_path, text)  # the reason and where: MuJoCo's two lines joined
    assert str(error).endswith("malformed MJCF: XML Error: Schema violation: unrecognized attribute: 'stiff'; "
                               f"Element 'joint', line {line}")
    text = IIWA14.replace('class="joint1"/>', 'class="nowhere"/>', 1)
    line = 1 + text[: text.index("nowhere")].count("\n")
    error = _refusal(tmp_path, text)  # MuJoCo 3.0 does not name the class, later versions do
    assert "malformed MJCF: XML Error: unknown default class" in str(error) and f"line {line}" in str(error)
    assert "malformed MJCF" in str(_refusal(tmp_path, "<mujoco><worldbody><body></worldbody></mujoco>"))
    with pytest.raises(RobotDescriptionError, match=r"cannot read robot file .*missing\.xml"):
        load_mjcf(tmp_path / "missing.xml")


def test_without_mujoco_the_extra_is_named(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco then raises ImportError
    with pytest.raises(RedkinError, match=r'mjcf extra: pip install "redkin\[mjcf\]" \(in a checkout of redkin: '
                                          r'pip install -e "\.\[mjcf\]"\)'):
        load_mjcf(_write(tmp_path, IIWA14))
