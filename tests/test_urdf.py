"""URDF import: the DH chain equals an independent product of the file's origins and axis rotations.

The reference below reads the XML with ``xml.etree`` (not the parser redkin uses) and multiplies the
joints' ``<origin>`` transforms and Rodrigues rotations about their ``<axis>``, as the URDF
specification defines the tip pose.  Every URDF here, the two in ``examples/`` and the synthetic ones
written in every frame convention, must match it to 1e-12 for any joint values.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.cli.main import main
from redkin.models import get_robot, kuka_iiwa14
from redkin.urdf import load_urdf
from tests.support.urdf_reference import reference_axes, reference_fk, urdf

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
HALF_PI = repr(np.pi / 2)  # written in full: 1.5707963 would make exactly parallel axes nearly parallel (see below)


SYNTHETIC = {
    # frames turned about their own joint axes, axes written as -z, a fixed joint in between
    "turned frames, -z axes, fixed joint": urdf([
        ("revolute", "0 0 0.3", "0 0 0.7", "0 0 -1"), ("revolute", "0 0.1 0.2", f"{HALF_PI} 0 0.4", "0 0 1"),
        ("fixed", "0.05 0 0.1", "0.3 -0.2 0.1", ""), ("continuous", "0 0 0.4", "0 0 -1.1", "0 0 -1"),
        ("revolute", "0.1 0 0", f"-{HALF_PI} 0 0", "0 -1 0"), ("fixed", "0 0 0.05", "0 0 0", "")]),
    # oblique axes and offsets in every direction: skew lines
    "oblique axes": urdf([
        ("revolute", "0.1 -0.2 0.3", "0.2 0.3 0.4", "0.3 0.5 0.8"),
        ("revolute", "0.2 0.1 0.05", "-0.7 0.1 1.2", "1 1 0"),
        ("continuous", "-0.1 0.3 0.2", "0.5 0.5 -0.5", "0.2 -0.9 0.1"),
        ("revolute", "0 0 0.25", "1 2 3", "-1 0.5 0.5")]),
    # parallel axes (a planar arm), the first not along the base z
    "parallel axes": urdf([
        ("revolute", "0 0 0.1", f"{HALF_PI} 0 0", "0 0 1"), ("revolute", "0.4 0 0", "0 0 0.3", "0 0 1"),
        ("revolute", "0.3 0.1 0", "0 0 0", "0 0 -1"), ("revolute", "0.2 0 0.05", "0 0 0", "0 0 1")]),
    # intersecting axes (a spherical wrist) and two collinear axes in a row
    "intersecting and collinear axes": urdf([
        ("revolute", "0 0 0.2", "0 0 0", "0 0 1"), ("revolute", "0 0 0.3", "0 0 0", "0 0 1"),
        ("revolute", "0 0 0.1", "0 0 0", "0 1 0"), ("revolute", "0 0 0", "0 0 0", "1 0 0"),
        ("revolute", "0 0 0", "0.4 0 0", "0 0 1"), ("fixed", "0 0 0.1", "0 0 0", "")]),
}
FILES = {"iiwa14 (examples)": (EXAMPLES / "iiwa14.urdf").read_text(),
         "panda (examples)": (EXAMPLES / "panda.urdf").read_text(), **SYNTHETIC}


def _load(tmp_path: Path, text: str, **links):
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    return load_urdf(path, **links)


def _tip(text: str) -> str:
    root = ET.fromstring(text)
    parents = {j.find("parent").get("link") for j in root.findall("joint")}
    return next(link.get("name") for link in root.findall("link") if link.get("name") not in parents)


@pytest.mark.parametrize("name", FILES)
def test_chain_equals_the_product_of_the_urdf_transforms(tmp_path_factory, name):
    text = FILES[name]
    chain = _load(tmp_path_factory.mktemp("urdf"), text)
    rng = np.random.default_rng(7)
    q = rng.uniform(-np.pi, np.pi, (50, chain.n))
    expected = np.array([reference_fk(text, row, _tip(text)) for row in q])
    np.testing.assert_allclose(chain.fk(q), expected, atol=1e-12)
    np.testing.assert_allclose(chain.fk(np.zeros(chain.n)), reference_fk(text, np.zeros(chain.n), _tip(text)),
                               atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(origins=st.lists(st.tuples(st.lists(st.floats(-0.5, 0.5), min_size=3, max_size=3),
                                  st.lists(st.floats(-3.2, 3.2), min_size=3, max_size=3),
                                  st.sampled_from(["0 0 1", "0 0 -1", "1 0 0", "0 -1 0", "0.3 -0.4 0.87", "1 1 1"]),
                                  st.sampled_from(["revolute", "continuous", "fixed"])), min_size=1, max_size=8),
       q_seed=st.integers(0, 2**16))
def test_any_chain_of_origins_and_axes_matches(tmp_path_factory, origins, q_seed):
    """Random origins, rotations, axes and fixed joints: FK equals the URDF's own product, for any q."""
    joints = [(kind, " ".join(map(repr, xyz)), " ".join(map(repr, rpy)), axis) for xyz, rpy, axis, kind in origins]
    if all(kind == "fixed" for kind, *_ in joints):
        joints[0] = ("revolute",) + joints[0][1:]
    text = urdf(joints)
    chain = _load(tmp_path_factory.mktemp("urdf"), text)
    q = np.random.default_rng(q_seed).uniform(-np.pi, np.pi, (5, chain.n))
    expected = np.array([reference_fk(text, row, f"l{len(joints)}") for row in q])
    np.testing.assert_allclose(chain.fk(q), expected, atol=_stated_accuracy(chain, text, f"l{len(joints)}"))


def _stated_accuracy(chain, text: str, tip: str) -> float:
    """1e-12, unless two consecutive axes of the URDF are nearly parallel (docs/urdf.md, "Accuracy"): a tilt
    ``t`` below :data:`~redkin._joint_lines.PARALLEL_TOLERANCE` counts as parallel and costs ``t`` times the
    lengths; above it the common normal lies ``offset / t`` away and rounding costs about ``eps * d^2``."""
    from redkin._joint_lines import PARALLEL_TOLERANCE

    directions = reference_axes(text, tip)
    tilts = np.linalg.norm(np.cross(directions[:-1], directions[1:]), axis=-1)
    near = tilts[(tilts > 0) & (tilts < 1e-3)]
    if near.size == 0:
        return 1e-12
    scale = max(1.0, float(np.max(np.abs(chain.d))), float(np.max(np.abs(chain.a))))
    length = 3.0 * chain.n  # the synthetic chains' origins are at most 0.5 m apart in each coordinate
    return 1e-12 + 10 * np.finfo(float).eps * scale**2 + float(np.sum(near[near < PARALLEL_TOLERANCE])) * length


@pytest.mark.parametrize("digits", [4, 7, 10, 13])
def test_nearly_parallel_axes_cost_digits_as_stated(tmp_path, digits):
    """``rpy="1.5708 0 0"`` tilts an axis off parallel.  DH rows need the common normal, which then lies far
    away (``d ~ offset / tilt``): the chain stays exact up to rounding of about ``eps * d^2``.  Below
    :data:`~redkin._joint_lines.PARALLEL_TOLERANCE` (2e-6) the axes count as parallel, at a cost of the tilt
    times the lengths.  The two costs meet near that tolerance: a few micrometres per metre at worst, and
    tilts from the usual 4 printed digits cost about 1e-11 m."""
    from redkin._joint_lines import PARALLEL_TOLERANCE

    tilt_text = f"{np.pi / 2:.{digits}f}"
    tilt = abs(float(tilt_text) - np.pi / 2)
    text = urdf([("revolute", "0 0 0.3", "0 0 0", "0 0 1"), ("revolute", "0 0.1 0.2", f"{tilt_text} 0 0", "0 1 0"),
                 ("revolute", "0.1 0 0.2", "0 0 0", "0 -1 0")])
    chain = _load(tmp_path, text)
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (50, 3))
    error = np.max(np.abs(chain.fk(q) - np.array([reference_fk(text, row, "l3") for row in q])))
    scale = max(1.0, float(np.max(np.abs(chain.d))), float(np.max(np.abs(chain.a))))
    bound = 1e-12 + 10 * np.finfo(float).eps * scale**2 + (tilt if tilt < PARALLEL_TOLERANCE else 0.0)
    assert error <= bound and error < 2 * PARALLEL_TOLERANCE, (tilt, scale, error)


def test_jacobian_of_a_urdf_chain_equals_finite_differences_of_the_reference(tmp_path):
    text = SYNTHETIC["oblique axes"]
    chain = _load(tmp_path, text)
    q = np.array([0.3, -0.7, 1.1, 0.4])
    jac = chain.jacobian(q)
    step = 1e-6
    for k in range(chain.n):
        dq = np.zeros(chain.n)
        dq[k] = step
        plus, minus = reference_fk(text, q + dq, "l4"), reference_fk(text, q - dq, "l4")
        np.testing.assert_allclose(jac[:3, k], (plus[:3, 3] - minus[:3, 3]) / (2 * step), atol=1e-8)
        spin = (plus[:3, :3] - minus[:3, :3]) / (2 * step) @ reference_fk(text, q, "l4")[:3, :3].T
        np.testing.assert_allclose(jac[3:, k], [spin[2, 1], spin[0, 2], spin[1, 0]], atol=1e-8)


def test_limits_and_joint_counts_come_from_the_urdf(tmp_path):
    chain = _load(tmp_path, SYNTHETIC["turned frames, -z axes, fixed joint"])
    assert chain.n == 4 and chain.joint_names == ("j0", "j1", "j3", "j4")  # two fixed joints folded
    np.testing.assert_array_equal(chain.lower, [-2, -2, -np.inf, -2])  # the continuous joint is unlimited
    np.testing.assert_array_equal(chain.upper, [2.5, 2.5, np.inf, 2.5])
    iiwa = get_robot(EXAMPLES / "iiwa14.urdf")
    np.testing.assert_allclose(np.degrees(iiwa.upper), [170, 120, 170, 120, 170, 120, 175], atol=1e-3)


def test_kuka_urdf_is_our_kuka_iiwa14_model():
    """Guards the example against a typing slip: the URDF and the named model are both in KUKA's joint senses."""
    urdf_chain, model = get_robot(EXAMPLES / "iiwa14.urdf"), kuka_iiwa14()
    q = np.random.default_rng(3).uniform(-2, 2, (20, 7))
    np.testing.assert_allclose(urdf_chain.fk(q), model.fk(q), atol=1e-12)
    np.testing.assert_allclose(urdf_chain.limits, model.limits, rtol=0, atol=1e-15)  # the file prints 17 digits


def test_base_and_tip_pick_a_sub_chain(tmp_path):
    text = FILES["panda (examples)"]
    chain = _load(tmp_path, text, base="panda_link2", tip="panda_link6")
    assert chain.n == 4
    q = np.array([0.1, 0.2, 0.3, -1.0, 0.4, 1.2, 0.5])  # the sub-chain is link 6's pose relative to link 2
    to_link2 = reference_fk(text, q, "panda_link2")
    to_link6 = reference_fk(text, q, "panda_link6")
    np.testing.assert_allclose(chain.fk(q[2:6]), np.linalg.inv(to_link2) @ to_link6, atol=1e-12)


TREE = ('<robot name="tree"><link name="root"/><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="ja" type="revolute"><parent link="root"/><child link="a"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        '<joint name="jb" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/></joint>'
        '<joint name="jc" type="continuous"><parent link="a"/><child link="c"/><axis xyz="1 0 0"/></joint></robot>')


@pytest.mark.parametrize("text, links, message", [
    (TREE, {}, "2 tips (b, c)"),
    (TREE, {"tip": "nowhere"}, "no link named 'nowhere'"),
    (TREE, {"base": "b", "tip": "c"}, "not below link 'b'"),
    (urdf([("prismatic", "0 0 0", "0 0 0", "0 0 1")]), {}, "joint 'j0' is prismatic"),
    (urdf([("revolute", "0 0 0", "0 0 0", "0 0 1"), ("floating", "0 0 0", "0 0 0", "0 0 1")]), {},
     "joint 'j1' is floating"),
    (urdf([("planar", "0 0 0", "0 0 0", "0 0 1")]), {}, "joint 'j0' is planar"),
    (urdf([("fixed", "0 0 0", "0 0 0", "")]), {}, "no revolute joint"),
    (TREE.replace('<joint name="jc" type="continuous">', '<joint name="jc" type="continuous"><mimic joint="jb"/>'),
     {"tip": "c"}, "joint 'jc' mimics 'jb'"),
    ("<robot name='x'><link name='a'/>", {}, "malformed URDF"),
    ("not xml at all", {}, "malformed URDF"),
])
def test_what_redkin_cannot_use_is_named_in_one_line(tmp_path, text, links, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _load(tmp_path, text, **links)


def test_cli_reads_a_urdf_with_base_and_tip(capsys, tmp_path):
    path = tmp_path / "tree.urdf"
    path.write_text(TREE)
    assert main(["fk", str(path), "0.3", "0.2", "--tip", "b", "--json"]) == 0
    pose = np.array(json.loads(capsys.readouterr().out)["pose"])
    np.testing.assert_allclose(pose, reference_fk(TREE, np.array([0.3, 0.2]), "b"), atol=1e-12)
    assert main(["fk", str(path), "0.3", "0.2"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--tip" in err
    assert main(["fk", "pa10-7c", *["0"] * 7, "--tip", "b"]) == 2
    assert "URDF and MJCF files only" in capsys.readouterr().err
    assert main(["fk", str(tmp_path / "missing.urdf"), "0"]) == 2
    assert "cannot read" in capsys.readouterr().err
