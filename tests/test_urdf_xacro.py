"""`.xacro` input: expanded with xacrodoc, then read as the URDF it expands to."""

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("urdf_parser_py", reason="the urdf extra (urdfdom-py) is not installed")
pytest.importorskip("xacrodoc", reason="the xacro extra (xacrodoc) is not installed")

from redkin.cli.main import main
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
