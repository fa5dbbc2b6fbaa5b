"""``--xacro-arg NAME:=VALUE`` and ``--package-path DIR`` on every command that takes a robot, and the one-line
errors of a xacro that cannot be expanded (issue 25, item 4)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pytest

import redkin.models
from redkin.cli.main import _build_parser, main
from tests.test_urdf_xacro import HAND, USES_PACKAGE, _package

POSE = ["--position", "0.5", "0", "0.5", "--rotation", "1", "0", "0", "0", "1", "0", "0", "0", "1"]

#: A cheap, valid command line for every command that takes a robot, ``R`` where the robot goes.
COMMANDS = {
    ("fk",): ["fk", "R", "0"],
    ("jacobian",): ["jacobian", "R", "0"],
    ("robots",): ["robots", "--show", "R"],
    ("ik",): ["ik", "R", *POSE, "--psi", "0"],
    ("arm-angles",): ["arm-angles", "R", *POSE],
    ("path",): ["path", "R", "--poses", "{poses}", "--max-step", "0.1"],
    ("explore",): ["explore", "R", *POSE, "--out", "{out}/page.html"],
    ("track",): ["track", "R", "--q0", "0", "--twist", "0", "0", "0", "0", "0", "0", "--duration", "0.01"],
    ("virtual-arms",): ["virtual-arms", "R", "--goal", "0.5", "0"],
    ("workspace",): ["workspace", "R", "--out", "{out}/map", "--extent", "-1", "1", "-1", "1", "-1", "1",
                     "--resolution", "2"],
}


def _commands_taking_a_robot(parser: argparse.ArgumentParser, words: tuple[str, ...] = ()) -> dict:
    """Every (sub)command of ``parser`` with a robot argument (``ROBOT`` or ``--show ROBOT``): its words -> its
    parser."""
    found = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                found.update(_commands_taking_a_robot(sub, (*words, name)))
        elif action.dest in ("robot", "show"):
            found[words] = parser
    return found


def _capture(capsys) -> tuple[str, list[str]]:
    captured = capsys.readouterr()
    return captured.out, captured.err.strip().splitlines()


def test_every_command_that_takes_a_robot_passes_the_xacro_options_to_the_loader(tmp_path: Path, monkeypatch,
                                                                                 capsys):
    """Found from the parser itself, so that a new command that takes a robot is checked too (it needs a line in
    :data:`COMMANDS`)."""
    found = _commands_taking_a_robot(_build_parser())
    assert set(found) == set(COMMANDS)
    seen: list[tuple] = []

    def spy(name_or_path, base=None, tip=None, *, xacro_args=None, package_paths=()):
        seen.append((str(name_or_path), base, tip, xacro_args, list(package_paths)))
        raise ValueError("the spy stops here")

    monkeypatch.setattr(redkin.models, "get_robot", spy)
    np.save(tmp_path / "poses.npy", np.tile(np.eye(4), (2, 1, 1)))
    (tmp_path / "packages").mkdir()
    for words, template in COMMANDS.items():
        options = {action.dest for action in found[words]._actions}
        assert {"xacro_args", "package_paths", "base", "tip"} <= options, words
        argv = [word.format(poses=tmp_path / "poses.npy", out=tmp_path) for word in template]
        argv = [str(tmp_path / "arm.xacro") if word == "R" else word for word in argv]
        argv += ["--tip", "flange", "--xacro-arg", "hand:=false", "--xacro-arg", "reach:=0.5",
                 "--xacro-arg", "hand:=true", "--package-path", str(tmp_path / "packages"),
                 "--package-path", str(tmp_path)]
        seen.clear()
        assert main(argv) == 2, words
        assert _capture(capsys)[1] == ["redkin: error: the spy stops here"], words
        assert seen == [(str(tmp_path / "arm.xacro"), None, "flange", {"hand": "true", "reach": "0.5"},
                         [str(tmp_path / "packages"), str(tmp_path)])], words


def test_fk_honours_a_xacro_argument(tmp_path: Path, capsys):
    file = tmp_path / "hand.urdf.xacro"
    file.write_text(HAND)
    heights = []
    for extra in ([], ["--xacro-arg", "hand:=false"], ["--xacro-arg", "hand:=false", "--xacro-arg", "reach:=0.5"]):
        assert main(["fk", str(file), "0", "--json", *extra]) == 0
        out, err = _capture(capsys)
        assert err == []
        heights.append(json.loads(out)["pose"][2][3])
    np.testing.assert_allclose(heights, [0.4, 0.3, 0.5], atol=1e-15)
    assert main(["robots", "--show", str(file), "--xacro-arg", "hand:=false", "--json"]) == 0
    shown = json.loads(_capture(capsys)[0])
    assert shown["source"] == f"URDF {file} (xacro hand:=false), links base -> flange"


def test_an_unknown_xacro_argument_is_one_warning_line_after_the_output(tmp_path: Path, capsys):
    file = tmp_path / "hand.xacro"
    file.write_text(HAND)
    assert main(["fk", str(file), "0", "--xacro-arg", "hnd:=false"]) == 0
    out, err = _capture(capsys)
    assert out.splitlines()[0].startswith("pose") and out.splitlines()[-1].startswith("--position")  # fk's whole
    assert err == [f"redkin: warning: {file} neither declares nor reads the xacro argument 'hnd': ignored (its "
                   "arguments: hand, reach)"]


@pytest.mark.parametrize("value", ["hand=false", "hand", ":=false", " :=x", ""])
def test_a_xacro_argument_without_name_and_assignment_is_a_usage_error(tmp_path: Path, capsys, value):
    file = tmp_path / "hand.xacro"
    file.write_text(HAND)
    with pytest.raises(SystemExit) as exit_:
        main(["fk", str(file), "0", "--xacro-arg", value])
    assert exit_.value.code == 2
    assert _capture(capsys)[1] == [f"redkin fk: error: argument --xacro-arg: expected NAME:=VALUE (as on xacro's "
                                   f"command line), got {value!r}"]


def test_an_empty_value_is_a_value(tmp_path: Path, capsys):
    file = tmp_path / "named.xacro"
    file.write_text(HAND.replace('<robot name="hand_arm"', '<robot name="arm$(arg suffix)"')
                    .replace('<xacro:arg name="hand" default="true"/>',
                             '<xacro:arg name="hand" default="true"/><xacro:arg name="suffix" default="_x"/>'))
    assert main(["robots", "--show", str(file), "--xacro-arg", "suffix:=", "--json"]) == 0
    assert json.loads(_capture(capsys)[0])["name"] == "arm"


def test_package_path_and_ros_package_path_find_a_package(tmp_path: Path, monkeypatch, capsys):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    file = tmp_path / "robot" / "packaged.xacro"
    file.parent.mkdir()
    file.write_text(USES_PACKAGE)
    _package(tmp_path / "workspace" / "src")
    assert main(["fk", str(file), "0"]) == 2
    err = _capture(capsys)[1]
    assert len(err) == 1 and "ROS package 'my_pkg' not found" in err[0] and "--package-path DIR" in err[0]
    assert "ROS_PACKAGE_PATH" in err[0]
    assert main(["fk", str(file), "0", "--json", "--package-path", str(tmp_path / "workspace")]) == 0
    out, err = _capture(capsys)
    assert err == [] and json.loads(out)["pose"][2][3] == pytest.approx(0.25, abs=1e-15)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "workspace"))
    assert main(["fk", str(file), "0", "--json"]) == 0
    out, err = _capture(capsys)
    assert err == [] and json.loads(out)["pose"][2][3] == pytest.approx(0.25, abs=1e-15)


@pytest.mark.parametrize("argv, fragment", [
    (["fk", "kuka-iiwa14", *["0"] * 7, "--xacro-arg", "hand:=false"], "apply to .xacro files only"),
    (["fk", "kuka-iiwa14", *["0"] * 7, "--package-path", "."], "apply to .xacro files only"),
    (["fk", "{dir}/arm.urdf", "0", "--xacro-arg", "hand:=false"], "xacro arguments apply to .xacro files only"),
    (["fk", "{dir}/hand.xacro", "0", "--package-path", "{dir}/nowhere"], "nowhere' is not a folder"),
    (["fk", "{dir}/hand.xacro", "0", "--package-path", "{dir}/arm.urdf"], "arm.urdf' is not a folder"),
    (["robots", "--xacro-arg", "hand:=false"], "go with --show ROBOT, as do --xacro-arg and --package-path"),
    (["robots", "--package-path", "."], "go with --show ROBOT, as do --xacro-arg and --package-path"),
])
def test_misplaced_xacro_options_exit_2_with_one_line(tmp_path: Path, capsys, argv, fragment):
    (tmp_path / "hand.xacro").write_text(HAND)
    (tmp_path / "arm.urdf").write_text('<robot name="r"><link name="a"/></robot>')
    assert main([word.format(dir=tmp_path) for word in argv]) == 2
    err = _capture(capsys)[1]
    assert len(err) == 1 and err[0].startswith("redkin: error: ") and fragment in err[0]
