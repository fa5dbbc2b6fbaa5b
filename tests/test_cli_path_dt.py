"""``redkin path --dt T``: the description's velocity limits bound the path; the command says which speeds it used."""

import json
from pathlib import Path

import numpy as np

from redkin.cli.main import main
from redkin.models import get_robot

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"


def _poses(tmp_path, count=8):
    q = np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]) + np.linspace(-0.2, 0.2, count)[:, None] * np.array(
        [1.0, 0.5, -0.5, 0.0, 0.5, 0.5, 1.0])
    file = tmp_path / "poses.npy"
    np.save(file, get_robot("kuka-iiwa14").fk(q))
    return file


def test_dt_alone_uses_the_description_speeds(tmp_path, capsys):
    chain = get_robot("kuka-iiwa14")
    file = _poses(tmp_path)
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--dt", "0.05", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["status"] == "ok" and report["speed_source"] == "description" and report["dt"] == 0.05
    assert report["speed_unit"] == "rad/s"
    np.testing.assert_array_equal(report["speed"], chain.velocity)
    np.testing.assert_allclose(report["step"], chain.velocity * 0.05, rtol=1e-15)
    q = np.array(report["q"])
    assert np.all(np.abs(np.diff(q, axis=0)) <= chain.velocity * 0.05)
    assert np.abs(chain.fk(q) - np.load(file)).max() <= 1e-9 and chain.within_limits(q).all()


def test_the_text_output_names_the_speeds_in_the_unit_asked(tmp_path, capsys):
    file = _poses(tmp_path)
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--dt", "0.05", "--deg"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert "the description's velocity limits" in first and "[deg/s]" in first and "0.05 s" in first
    numbers = [float(v) for v in first.rsplit(":", 1)[1].split()]
    assert numbers == [85.0, 85.0, 100.0, 75.0, 130.0, 135.0, 135.0]  # KUKA's data sheet, deg/s


def test_speed_overrides_the_description(tmp_path, capsys):
    file = _poses(tmp_path)
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--dt", "0.1", "--speed", "60", "--deg", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["speed_source"] == "--speed" and report["speed_unit"] == "deg/s"
    np.testing.assert_allclose(report["speed"], 60.0)
    np.testing.assert_allclose(report["step"], 6.0)
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--dt", "0.1", "--speed", "1"]) == 0
    assert "from --speed" in capsys.readouterr().out.splitlines()[0]


def test_max_step_reports_no_speeds(tmp_path, capsys):
    file = _poses(tmp_path)
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["speed"] is None and report["speed_source"] is None and report["dt"] is None


def _one_line_exit_2(argv, capsys) -> str:
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith("redkin: error:") and captured.err.count("\n") == 1
    return captured.err


def test_a_robot_without_speed_limits_is_one_line_and_exit_2(tmp_path, capsys):
    file = _poses(tmp_path)
    err = _one_line_exit_2(["path", "pa10-7c", "--poses", str(file), "--dt", "0.05"], capsys)
    assert "pa10-7c has no velocity limit on any joint" in err and "--speed" in err and "--max-step" in err
    assert main(["path", "pa10-7c", "--poses", str(file), "--dt", "0.05", "--speed", "1"]) in (0, 1)


def test_a_urdf_missing_some_speeds_names_those_joints(tmp_path, capsys):
    text = (EXAMPLES / "iiwa14.urdf").read_text()
    for joint in ("lbr_iiwa_joint_2", "lbr_iiwa_joint_5"):
        start = text.index(f'name="{joint}"')
        at = text.index('velocity="', start)
        end = text.index('"', at + len('velocity="'))
        text = text[:at] + 'velocity="0"' + text[end + 1:]
    robot = tmp_path / "iiwa14.urdf"
    robot.write_text(text)
    err = _one_line_exit_2(["path", str(robot), "--poses", str(_poses(tmp_path)), "--dt", "0.05"], capsys)
    assert "joints 2 (lbr_iiwa_joint_2), 5 (lbr_iiwa_joint_5)" in err


def test_a_urdf_with_speeds_bounds_the_path_by_them(tmp_path, capsys):
    file = _poses(tmp_path)
    assert main(["path", str(EXAMPLES / "iiwa14.urdf"), "--poses", str(file), "--dt", "0.05", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    speeds = np.radians([85, 85, 100, 75, 130, 135, 135])  # KUKA's, as the file writes them in rad/s
    np.testing.assert_allclose(report["speed"], speeds, rtol=1e-15)
    assert np.all(np.abs(np.diff(report["q"], axis=0)) <= speeds * 0.05)


def test_the_bound_options_must_make_one_bound(tmp_path, capsys):
    file = str(_poses(tmp_path))
    assert "--max-step A, or --dt T" in _one_line_exit_2(["path", "kuka-iiwa14", "--poses", file], capsys)
    assert "--speed needs --dt" in _one_line_exit_2(["path", "kuka-iiwa14", "--poses", file, "--speed", "1"], capsys)
    _one_line_exit_2(["path", "kuka-iiwa14", "--poses", file, "--max-step", "0.1", "--dt", "0.1"], capsys)
    for dt in ("0", "-1", "inf", "nan"):
        assert "dt" in _one_line_exit_2(["path", "kuka-iiwa14", "--poses", file, "--dt", dt], capsys)
