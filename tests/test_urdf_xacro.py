"""`.xacro` input: expanded with xacrodoc (with its arguments and ROS package paths), then read as the URDF it
expands to; a file that cannot be read says its whole reason in one line."""

import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.models import get_robot

XACRO = """<?xml version="1.0"?>
<robot name="macro_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="upper_arm" value="0.42"/>
  <xacro:macro name="segment" params="k parent z roll axis">
    <link name="link${k}"/>
    <joint name="joint${k}" type="revolute">
      <parent link="${parent}"/><child link="link${k}"/>
      <origin xyz="0 0 ${z}" rpy="${roll} 0 0"/><axis xyz="${axis}"/>
      <limit lower="${-radians(170)}" upper="${radians(170)}" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
  <link name="link0"/>
  <xacro:segment k="1" parent="link0" z="0.36" roll="0" axis="0 0 1"/>
  <xacro:segment k="2" parent="link1" z="0" roll="${pi/2}" axis="0 0 -1"/>
  <xacro:segment k="3" parent="link2" z="0" roll="${-pi/2}" axis="0 0 1"/>
  <xacro:segment k="4" parent="link3" z="${upper_arm}" roll="${pi/2}" axis="0 0 1"/>
</robot>
"""


def _urdf_by_hand() -> str:
    half = repr(np.pi / 2)
    limit = f'<limit lower="{-float(np.radians(170))!r}" upper="{float(np.radians(170))!r}" effort="1" velocity="1"/>'
    rows = [("0.36", "0", "0 0 1"), ("0", half, "0 0 -1"), ("0", f"-{half}", "0 0 1"), ("0.42", half, "0 0 1")]
    joints = "".join(
        f'<link name="link{k}"/><joint name="joint{k}" type="revolute"><parent link="link{k - 1}"/>'
        f'<child link="link{k}"/><origin xyz="0 0 {z}" rpy="{roll} 0 0"/><axis xyz="{axis}"/>{limit}</joint>'
        for k, (z, roll, axis) in enumerate(rows, start=1))
    return f'<robot name="macro_arm"><link name="link0"/>{joints}</robot>'


def test_a_xacro_gives_the_chain_of_the_urdf_it_expands_to(tmp_path: Path):
    (tmp_path / "arm.urdf.xacro").write_text(XACRO)
    (tmp_path / "arm.urdf").write_text(_urdf_by_hand())
    from_xacro, from_urdf = get_robot(tmp_path / "arm.urdf.xacro"), get_robot(tmp_path / "arm.urdf")
    q = np.random.default_rng(0).uniform(-3, 3, (50, 4))
    np.testing.assert_allclose(from_xacro.fk(q), from_urdf.fk(q), atol=1e-12)
    np.testing.assert_allclose(from_xacro.lower, np.radians(np.full(4, -170.0)), atol=1e-12)
    assert from_xacro.joint_names == ("joint1", "joint2", "joint3", "joint4")


def test_a_malformed_xacro_is_one_line_and_exit_2(tmp_path: Path, capsys):
    bad = tmp_path / "bad.xacro"
    bad.write_text('<robot name="x" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:no_such_macro/></robot>')
    with pytest.raises(ValueError, match="malformed xacro: unknown macro name"):
        get_robot(bad)
    assert main(["fk", str(bad), "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "malformed xacro" in err[0]


# --- arguments, package paths and whole reasons (issue 25, item 4) ---

HAND = """<?xml version="1.0"?>
<robot name="hand_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="hand" default="true"/>
  <xacro:arg name="reach" default="0.3"/>
  <link name="base"/><link name="flange"/>
  <joint name="joint1" type="revolute">
    <parent link="base"/><child link="flange"/><origin xyz="0 0 $(arg reach)"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <xacro:if value="$(arg hand)">
    <link name="hand"/>
    <joint name="hand_joint" type="fixed"><parent link="flange"/><child link="hand"/><origin xyz="0 0 0.1"/></joint>
  </xacro:if>
</robot>
"""

#: A xacro whose arm comes from a ROS package: ``$(find my_pkg)`` names it.
USES_PACKAGE = """<?xml version="1.0"?>
<robot name="packaged" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find my_pkg)/urdf/arm.xacro"/>
  <xacro:arm length="0.25"/>
</robot>
"""

PACKAGE_MACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm" params="length">
    <link name="base"/><link name="tip"/>
    <joint name="joint1" type="revolute">
      <parent link="base"/><child link="tip"/><origin xyz="0 0 ${length * SCALE}"/><axis xyz="0 0 1"/>
      <limit lower="-2" upper="2" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
</robot>
"""


def _package(root: Path, name: str = "my_pkg", folder: str = "my_pkg_source", scale: float = 1.0) -> Path:
    """A ROS package ``name`` (its ``package.xml`` names it, whatever the folder's name) under ``root``, holding
    the ``arm`` macro with its length times ``scale``; returns the package's folder."""
    package = root / folder
    (package / "urdf").mkdir(parents=True)
    (package / "package.xml").write_text(
        f'<?xml version="1.0"?><package format="2"><name>{name}</name><version>0.0.0</version>'
        '<description>test</description><maintainer email="a@b.c">a</maintainer><license>MIT</license></package>')
    (package / "urdf" / "arm.xacro").write_text(PACKAGE_MACRO.replace("SCALE", repr(scale)))
    return package


def _height(chain) -> float:
    return float(chain.fk(np.zeros(chain.n))[2, 3])


def test_a_xacro_argument_changes_the_chain(tmp_path: Path):
    file = tmp_path / "hand.urdf.xacro"
    file.write_text(HAND)
    default = get_robot(file)
    assert default.source.endswith("links base -> hand") and _height(default) == pytest.approx(0.4, abs=1e-15)
    without_hand = get_robot(file, xacro_args={"hand": "false"})
    assert without_hand.source == f"URDF {file} (xacro hand:=false), links base -> flange"
    assert _height(without_hand) == pytest.approx(0.3, abs=1e-15)
    # Python values are written as xacro text: False as false, numbers by repr
    assert get_robot(file, xacro_args={"hand": False}).source == without_hand.source
    assert _height(get_robot(file, xacro_args={"hand": False, "reach": 0.55})) == pytest.approx(0.55, abs=1e-15)
    # the tip can still be named: the hand's flange of the default expansion is the same chain
    np.testing.assert_allclose(get_robot(file, tip="flange").fk([0.7]), without_hand.fk([0.7]), atol=1e-15)


def test_an_argument_the_file_does_not_know_is_ignored_with_a_warning(tmp_path: Path):
    file = tmp_path / "hand.xacro"
    file.write_text(HAND)
    with pytest.warns(UserWarning, match=r"neither declares nor reads the xacro argument 'hnd'.*hand, reach"):
        chain = get_robot(file, xacro_args={"hnd": "false"})
    assert chain.source.endswith("links base -> hand")
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)  # arguments the file declares warn of nothing, read or not
        get_robot(file, xacro_args={"hand": "false", "reach": "0.2"})


def test_an_argument_without_value_or_default_says_how_to_give_it(tmp_path: Path):
    file = tmp_path / "needs.xacro"
    file.write_text(HAND.replace('<xacro:arg name="reach" default="0.3"/>', ""))
    with pytest.raises(RobotDescriptionError, match=r"'reach' has no value and no default: give it with "
                                                    r"--xacro-arg reach:=VALUE \(xacro_args in Python\)"):
        get_robot(file)
    assert _height(get_robot(file, xacro_args={"reach": "0.5"})) == pytest.approx(0.6, abs=1e-15)


@pytest.mark.parametrize("xacro_args, fragment", [
    (["hand", "false"], "must be a mapping"),
    ({"": "x"}, "non-empty string"),
    ({"a:=b": "x"}, "without ':='"),
    ({3: "x"}, "non-empty string"),
    ({"hand": None}, "must be a string, number or boolean, got NoneType"),
    ({"hand": [1]}, "got list"),
])
def test_malformed_xacro_arguments_are_refused(tmp_path: Path, xacro_args, fragment):
    file = tmp_path / "hand.xacro"
    file.write_text(HAND)
    with pytest.raises(RedkinError, match=re.escape(fragment)):
        get_robot(file, xacro_args=xacro_args)


def test_xacro_arguments_and_package_paths_are_for_xacro_files_only(tmp_path: Path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_urdf_by_hand())
    with pytest.raises(RobotDescriptionError, match=r"xacro arguments apply to \.xacro files only"):
        get_robot(urdf, xacro_args={"hand": "false"})
    # a plain URDF takes package paths, for its package:// meshes (redkin.collision.urdf_body); its chain is the same
    with_paths, plain = get_robot(urdf, package_paths=[tmp_path]), get_robot(urdf)
    assert all(np.array_equal(getattr(with_paths, k), getattr(plain, k)) for k in ("a", "alpha", "d", "offset", "tool"))
    for robot in ("kuka-iiwa14", tmp_path / "arm.toml"):
        with pytest.raises(ValueError, match=r"apply to \.xacro files only, not to"):
            get_robot(robot, xacro_args={"hand": "false"})
        with pytest.raises(ValueError, match=r"apply to \.xacro files only, not to"):
            get_robot(robot, package_paths=str(tmp_path))
    # empty ones are none at all
    assert get_robot(urdf, xacro_args={}, package_paths=[]).n == 4
    assert get_robot("kuka-iiwa14", xacro_args={}, package_paths=()).n == 7


def test_a_package_path_that_is_not_a_folder_is_refused(tmp_path: Path):
    file = tmp_path / "packaged.xacro"
    file.write_text(USES_PACKAGE)
    with pytest.raises(RobotDescriptionError, match=r"package path .*nowhere' is not a folder"):
        get_robot(file, package_paths=[tmp_path / "nowhere"])


def test_find_is_resolved_in_the_package_paths(tmp_path: Path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    file = tmp_path / "robot" / "packaged.xacro"
    file.parent.mkdir()
    file.write_text(USES_PACKAGE)
    package = _package(tmp_path / "workspace" / "src")
    # a folder that holds packages (at any depth), the package's own folder, or one path alone
    for places in ([tmp_path / "workspace"], [package], str(package), [tmp_path / "empty", package]):
        (tmp_path / "empty").mkdir(exist_ok=True)
        assert _height(get_robot(file, package_paths=places)) == pytest.approx(0.25, abs=1e-15)


def test_find_is_resolved_on_ros_package_path(tmp_path: Path, monkeypatch):
    file = tmp_path / "packaged.xacro"
    file.write_text(USES_PACKAGE)
    _package(tmp_path / "ros" / "share")
    monkeypatch.setenv("ROS_PACKAGE_PATH", os.pathsep.join([str(tmp_path / "nothing"), str(tmp_path / "ros")]))
    assert _height(get_robot(file)) == pytest.approx(0.25, abs=1e-15)
    # the package paths come first: a package of the same name there wins
    _package(tmp_path / "mine", scale=2.0)
    assert _height(get_robot(file, package_paths=[tmp_path / "mine"])) == pytest.approx(0.5, abs=1e-15)


def test_find_is_resolved_by_walking_up_from_the_file(tmp_path: Path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    package = _package(tmp_path)
    file = package / "urdf" / "robot.urdf.xacro"
    file.write_text(USES_PACKAGE)
    assert _height(get_robot(file)) == pytest.approx(0.25, abs=1e-15)


def test_a_package_found_once_is_not_remembered_for_the_next_load(tmp_path: Path, monkeypatch):
    """The result depends on the arguments only: xacrodoc's package finder (a global with a cache) starts afresh
    for every file, so neither a package found nor a place searched for an earlier load leaks into this one."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    file = tmp_path / "packaged.xacro"
    file.write_text(USES_PACKAGE)
    first, second = _package(tmp_path / "a"), _package(tmp_path / "b", scale=3.0)
    assert _height(get_robot(file, package_paths=[first])) == pytest.approx(0.25, abs=1e-15)
    assert _height(get_robot(file, package_paths=[second])) == pytest.approx(0.75, abs=1e-15)
    with pytest.raises(RobotDescriptionError, match="ROS package 'my_pkg' not found"):
        get_robot(file)


def test_a_missing_package_is_named_with_the_ways_to_give_it(tmp_path: Path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    file = tmp_path / "packaged.xacro"
    file.write_text(USES_PACKAGE)
    (tmp_path / "elsewhere").mkdir()
    with pytest.raises(RobotDescriptionError) as caught:
        get_robot(file, package_paths=[tmp_path / "elsewhere"])
    message = str(caught.value)
    assert "\n" not in message and "<class" not in message
    assert message.startswith(f"{file}: ROS package 'my_pkg' not found (searched {tmp_path / 'elsewhere'}, ")
    assert "ROS_PACKAGE_PATH (unset)" in message
    assert "--package-path DIR" in message and "add it to ROS_PACKAGE_PATH" in message
    assert caught.value.path == str(file)


def test_includes_are_relative_to_the_file_not_the_working_directory(tmp_path: Path, monkeypatch):
    (tmp_path / "robot" / "parts").mkdir(parents=True)
    (tmp_path / "robot" / "parts" / "arm.xacro").write_text(PACKAGE_MACRO.replace("SCALE", "1.0"))
    file = tmp_path / "robot" / "top.xacro"
    file.write_text(USES_PACKAGE.replace("$(find my_pkg)/urdf/arm.xacro", "parts/arm.xacro"))
    monkeypatch.chdir(tmp_path)
    assert _height(get_robot(file)) == pytest.approx(0.25, abs=1e-15)
    # and after a failed expansion (which leaves xacro's file stack mid-include), the next one still is
    broken = tmp_path / "robot" / "broken.xacro"
    broken.write_text(USES_PACKAGE.replace("$(find my_pkg)/urdf/arm.xacro", "parts/missing.xacro"))
    with pytest.raises(RobotDescriptionError, match=r"malformed xacro: No such file or directory: .*missing\.xacro$"):
        get_robot(broken)
    assert _height(get_robot(file)) == pytest.approx(0.25, abs=1e-15)


XACRO_HEAD = '<robot name="x" xmlns:xacro="http://www.ros.org/wiki/xacro">'
URDF_JOINT = ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
              '<child link="b"/><axis xyz="0 0 1"/><limit lower="{lower}" upper="1" effort="1" velocity="1"/>'
              '</joint></robot>')


@pytest.mark.parametrize("name, text, reason", [
    ("bad_value.urdf", URDF_JOINT.format(lower="low"),
     "malformed URDF at /robot[@name='r']/joint[@name='j']/limit[@lower]: could not convert string to float: 'low'"),
    ("unclosed.urdf", '<robot name="r"><link name="a">\n<link name="b"/></robot>',
     "malformed URDF: Opening and ending tag mismatch: link line 1 and robot, line 2"),
    ("bad_value.xacro", URDF_JOINT.format(lower="${'low'}").replace('<robot name="r">', XACRO_HEAD),
     "malformed URDF at /robot[@name='x']/joint[@name='j']/limit[@lower]: could not convert string to float: 'low'"),
    ("unclosed.xacro", XACRO_HEAD + '<link name="a"></robot>', "malformed xacro: mismatched tag: line 1"),
    ("expression.xacro", XACRO_HEAD + '<link name="${1/0}"/></robot>',
     "malformed xacro: division by zero when evaluating expression '1/0'"),
    ("eval.xacro", XACRO_HEAD + '<link name="$(eval 1/0)"/></robot>',
     "malformed xacro: ZeroDivisionError: division by zero"),
    ("environment.xacro", XACRO_HEAD + '<link name="$(env REDKIN_TEST_UNSET_VARIABLE)"/></robot>',
     "malformed xacro: SubstitutionException: environment variable 'REDKIN_TEST_UNSET_VARIABLE' is not set"),
])
def test_a_parse_failure_gives_its_whole_reason_in_one_line(tmp_path: Path, monkeypatch, capsys, name, text, reason):
    monkeypatch.delenv("REDKIN_TEST_UNSET_VARIABLE", raising=False)
    file = tmp_path / name
    file.write_text(text)
    with pytest.raises(RobotDescriptionError) as caught:
        get_robot(file)
    message = str(caught.value)
    assert message.startswith(f"{file}: {reason}") and "\n" not in message and "<class" not in message
    assert caught.value.path == str(file)
    assert main(["fk", str(file), "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"redkin: error: {message}"]


def test_a_file_of_macros_only_says_so(tmp_path: Path):
    """Kinova's j2s7s300.xacro defines the arm's macro under a <root> element and calls nothing: the parser's own
    message was "Required attribute not set in XML: name" (a new-user tryout)."""
    path = tmp_path / "macros.xacro"
    path.write_text('<?xml version="1.0"?>\n<!-- macros -->\n<root xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                    '  <xacro:macro name="arm" params="prefix"><link name="${prefix}l"/></xacro:macro>\n</root>\n')
    with pytest.raises(RobotDescriptionError, match=r"it expands to no robot \(its root element is <root>, not "
                                                    r"<robot>\): a file of macros only; load the \.xacro that calls"):
        get_robot(path)
