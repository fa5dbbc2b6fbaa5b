"""The makers' arms as a user has them (``examples/gen3.urdf``, ``xarm7.urdf``, ``sawyer.urdf``, ``jaco2.urdf``,
``yumi_right.urdf``) and a parametrised xacro of a user's own: loaded, and solved by the numerical pose IK.

Laws:

- FK of :func:`redkin.urdf.load_urdf` equals the product of the file's own ``<origin>`` transforms and axis
  rotations, read with ``xml.etree`` (:func:`tests.support.urdf_reference.reference_fk`), for random in-limit q;
- certified numerical IK through the front door :func:`redkin.ik` (no ``psi``/``q7``): of 100 targets from FK of
  random in-limit q, at most one is missed, and every joint vector returned reaches its target to 1e-9 m and
  1e-9 rad by the file's own product, within the file's limits;
- ``redkin ik FILE --poses targets.npy --json`` returns the same certified joint vectors (exit 0 when all are
  found);
- a xacro with an argument (``prefix``) that includes a macro through ``$(find PKG)`` loads with ``--xacro-arg``
  and ``--package-path`` as the plain URDF it stands for, and ``redkin ik`` solves it numerically.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import ik
from redkin.cli.main import main
from redkin.urdf import load_urdf
from tests.support.urdf_reference import reference_fk

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: file and its tip link (the default: the file's only leaf)
ARMS = {
    "gen3": (EXAMPLES / "gen3.urdf", "tool_frame"),
    "xarm7": (EXAMPLES / "xarm7.urdf", "link_eef"),
    "sawyer": (EXAMPLES / "sawyer.urdf", "right_hand"),
    "jaco2": (EXAMPLES / "jaco2.urdf", "j2s7s300_end_effector"),
    "yumi_right": (EXAMPLES / "yumi_right.urdf", "yumi_link_7_r"),
}
TARGETS = 100
TOLERANCE = 1e-9


def _in_limits(chain, fractions, unlimited: float) -> np.ndarray:
    """Joint vectors at ``fractions`` (in [0, 1]) of each joint's range; ``+-unlimited`` for a continuous joint.
    (At a fraction of 1, ``lower + (upper - lower)`` may round an ulp past ``upper``: clipped.)"""
    lower = np.where(np.isfinite(chain.lower), chain.lower, -unlimited)
    upper = np.where(np.isfinite(chain.upper), chain.upper, unlimited)
    return np.clip(lower + np.asarray(fractions) * (upper - lower), lower, upper)


def _errors(text: str, tip: str, q: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """``(N, 2)``: position error [m] and rotation angle [rad] of the file's own tip pose at each ``q`` against
    its target; the angle from both the sine and the cosine of ``R_target^T R``, accurate near 0."""
    errors = []
    for row, target in zip(q, targets):
        pose = reference_fk(text, row, tip)
        relative = target[:3, :3].T @ pose[:3, :3]
        sine = np.linalg.norm(relative - relative.T) / (2.0 * np.sqrt(2.0))
        cosine = (np.trace(relative) - 1.0) / 2.0
        errors.append([np.linalg.norm(pose[:3, 3] - target[:3, 3]), np.arctan2(sine, cosine)])
    return np.array(errors)


def _targets(chain) -> np.ndarray:
    """FK of 100 random in-limit joint vectors (continuous joints anywhere in a turn), the same every run."""
    fractions = np.random.default_rng(2025).uniform(0.0, 1.0, (TARGETS, chain.n))
    return chain.fk(_in_limits(chain, fractions, np.pi))


def _within(chain, q: np.ndarray) -> bool:
    return bool(np.all((q >= chain.lower) & (q <= chain.upper)))


def _run(capsys, argv: list[str]) -> tuple[int, str]:
    code = main(argv)
    return code, capsys.readouterr().out


fractions = st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7)


@pytest.mark.parametrize("arm", ARMS)
@settings(max_examples=30, deadline=None)
@given(fractions=fractions)
def test_fk_is_the_product_of_the_files_origins_and_axis_rotations(arm, fractions):
    path, tip = ARMS[arm]
    chain = load_urdf(path)
    q = _in_limits(chain, fractions, 2.0 * np.pi)
    assert chain.within_limits(q)
    np.testing.assert_allclose(chain.fk(q), reference_fk(path.read_text(), q, tip), rtol=0, atol=1e-12)


@pytest.mark.parametrize("arm", ARMS)
def test_numerical_ik_is_certified_within_the_limits_in_python_and_on_the_command_line(arm, tmp_path, capsys):
    path, tip = ARMS[arm]
    chain, text = load_urdf(path), path.read_text()
    targets = _targets(chain)
    result = ik(chain, targets)  # no psi or q7: numerical on every class
    assert result.method == "numerical"
    found = result.found[:, 0]
    assert found.sum() >= TARGETS - 1, f"{arm}: {TARGETS - found.sum()} of {TARGETS} targets missed"
    solutions = result.q[found, 0]
    assert np.all(np.isfinite(result.q)) and np.all(np.isfinite(result.error))
    assert np.all(_errors(text, tip, solutions, targets[found]) <= TOLERANCE)
    assert _within(chain, solutions)
    # a missed target says so with its best residual, never as a solution
    assert np.all(result.error[~found].max(axis=-1) > TOLERANCE)

    file = tmp_path / "targets.npy"
    np.save(file, targets)
    code, out = _run(capsys, ["ik", str(path), "--poses", str(file), "--json"])
    data = json.loads(out)
    assert code == (0 if found.all() else 1)
    assert data["method"] == "numerical" and [entry["index"] for entry in data["poses"]] == list(range(TARGETS))
    assert [entry["status"] == "found" for entry in data["poses"]] == found.tolist()
    cli = np.array([entry["solutions"][0] for entry in data["poses"] if entry["status"] == "found"])
    np.testing.assert_array_equal(cli, solutions)  # the same streams of starts: the same answers
    assert np.all(_errors(text, tip, cli, targets[found]) <= TOLERANCE) and _within(chain, cli)


# ----------------------------------------------------------------------------- a parametrised xacro of a user's own
#: (xyz, rpy, axis) of the seven revolute joints of a small general arm: offsets at the shoulder, the elbow and the
#: wrist, so that no closed form applies
JOINTS = [
    ("0 0 0.2", "0 0 0", "0 0 1"),
    ("0.03 0 0.1", "1.5707963267948966 0 0", "0 0 1"),
    ("0 0.25 0.01", "-1.5707963267948966 0 0", "0 0 1"),
    ("0.04 0 0.05", "1.5707963267948966 0 0.3", "0 0 -1"),
    ("0 0.22 0", "-1.5707963267948966 0 0", "0 0 1"),
    ("0.02 0 0.06", "1.5707963267948966 0 0", "0 1 0"),
    ("0 0.08 0.015", "-1.5707963267948966 0 0", "0 0 1"),
]
TOOL = ("0 0 0.1", "0 0 0.5")  # the fixed flange


def _segments(prefix: str) -> str:
    """The links and joints of the arm with names ``{prefix}link0``...: the URDF that the xacro stands for."""
    links = "".join(f'<link name="{prefix}link{k}"/>' for k in range(len(JOINTS) + 2))
    joints = "".join(
        f'<joint name="{prefix}joint{k + 1}" type="revolute"><parent link="{prefix}link{k}"/>'
        f'<child link="{prefix}link{k + 1}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>'
        f'<limit lower="-2.6" upper="2.6" effort="1" velocity="1"/></joint>'
        for k, (xyz, rpy, axis) in enumerate(JOINTS))
    last = len(JOINTS)
    flange = (f'<joint name="{prefix}flange" type="fixed"><parent link="{prefix}link{last}"/>'
              f'<child link="{prefix}link{last + 1}"/><origin xyz="{TOOL[0]}" rpy="{TOOL[1]}"/></joint>')
    return links + joints + flange


def _user_xacro(tmp_path: Path) -> tuple[Path, Path]:
    """A package ``tiny_arm_description`` (holding the arm as a macro with a ``prefix`` parameter) in a workspace
    ``ws/src``, and a robot xacro elsewhere that takes ``prefix`` as an argument and includes the macro through
    ``$(find tiny_arm_description)``.  Returns (the robot xacro, the workspace's ``src``)."""
    package = tmp_path / "ws" / "src" / "tiny_arm"
    (package / "urdf").mkdir(parents=True)
    (package / "package.xml").write_text(
        '<?xml version="1.0"?><package format="2"><name>tiny_arm_description</name><version>0.1.0</version>'
        '<description>a small arm</description><maintainer email="a@b.c">a</maintainer><license>MIT</license>'
        '</package>')
    (package / "urdf" / "tiny_arm.xacro").write_text(
        '<?xml version="1.0"?><robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        f'<xacro:macro name="tiny_arm" params="prefix">{_segments("${prefix}")}</xacro:macro></robot>')
    robot = tmp_path / "robot" / "tiny_arm.urdf.xacro"
    robot.parent.mkdir()
    robot.write_text(
        '<?xml version="1.0"?><robot name="tiny_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:arg name="prefix" default=""/>'
        '<xacro:include filename="$(find tiny_arm_description)/urdf/tiny_arm.xacro"/>'
        '<xacro:tiny_arm prefix="$(arg prefix)"/></robot>')
    return robot, tmp_path / "ws" / "src"


def test_a_parametrised_xacro_with_a_package_loads_with_its_argument_and_is_solved_numerically(tmp_path, capsys):
    robot, workspace = _user_xacro(tmp_path)
    options = ["--xacro-arg", "prefix:=right_", "--package-path", str(workspace)]
    plain = f'<robot name="tiny_arm">{_segments("right_")}</robot>'
    tip = f"right_link{len(JOINTS) + 1}"

    code, out = _run(capsys, ["robots", "--show", str(robot), *options, "--json"])
    shown = json.loads(out)
    assert code == 0 and shown["class"] == "general chain"
    assert [joint["name"] for joint in shown["joints"]] == [f"right_joint{k}" for k in range(1, 8)]
    assert "prefix:=right_" in shown["source"] and shown["source"].endswith(f"links right_link0 -> {tip}")

    q = np.random.default_rng(5).uniform(-2.6, 2.6, (20, 7))
    file = tmp_path / "targets.npy"
    np.save(file, np.array([reference_fk(plain, row, tip) for row in q]))  # the targets from the plain URDF
    code, out = _run(capsys, ["fk", str(robot), *map(repr, q[0].tolist()), *options, "--json"])
    assert code == 0
    np.testing.assert_allclose(json.loads(out)["pose"], np.load(file)[0], rtol=0, atol=1e-12)

    code, out = _run(capsys, ["ik", str(robot), "--poses", str(file), *options, "--json"])
    data = json.loads(out)
    assert data["method"] == "numerical" and "no closed-form IK" in data["why"]
    found = [entry["status"] == "found" for entry in data["poses"]]
    assert code == (0 if all(found) else 1) and sum(found) >= len(q) - 1
    solutions = np.array([entry["solutions"][0] for entry in data["poses"] if entry["status"] == "found"])
    assert np.all(_errors(plain, tip, solutions, np.load(file)[found]) <= TOLERANCE)
    assert np.all(np.abs(solutions) <= 2.6)

    # without the package path the package is named, and where to give it
    code = main(["fk", str(robot), *["0"] * 7, "--xacro-arg", "prefix:=right_"])
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'tiny_arm_description' not found" in err and "--package-path" in err
