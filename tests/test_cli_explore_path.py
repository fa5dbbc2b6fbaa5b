"""``redkin explore ROBOT --path RESULT.json``: the playback page of a timed path, from the JointTrajectory file or
the ``redkin path --json`` report (with its stops), and one line for a file it cannot play."""

from __future__ import annotations

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot

pytest.importorskip("toppra")

PANDA = get_robot("franka-panda")
Q = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5]) + np.linspace(0.0, 1.0, 30)[:, None] * np.array(
    [0.5, 0.3, -0.2, 0.4, 0.3, -0.3, 0.2])


def _page_data(file) -> dict:
    text = file.read_text()
    start = text.index('<script id="playback-data" type="application/json">') + len(
        '<script id="playback-data" type="application/json">')
    return json.loads(text[start:text.index("</script>", start)])


def test_the_page_plays_the_trajectory_file_and_the_report(tmp_path, capsys):
    poses = tmp_path / "poses.npy"
    np.save(poses, PANDA.fk(Q))
    trajectory, report = tmp_path / "trajectory.json", tmp_path / "report.json"
    assert main(["path", "franka-panda", "--poses", str(poses), "--max-step", "0.1", "--trajectory",
                 str(trajectory), "--json"]) == 0
    report.write_text(capsys.readouterr().out)
    message = json.loads(trajectory.read_text())
    for source in (trajectory, report):
        out = tmp_path / f"{source.stem}.html"
        assert main(["explore", "franka-panda", "--path", str(source), "--out", str(out)]) == 0
        assert "a trajectory of" in capsys.readouterr().out
        data = _page_data(out)
        duration = message["points"][-1]["time_from_start"]
        assert data["t"][-1] == pytest.approx(duration["sec"] + 1e-9 * duration["nanosec"], abs=1e-5)
        assert data["joints"] == list(PANDA.joint_names) and len(data["q"]) == 7
        q = np.array(data["q"]).T  # the frames shown are samples of the trajectory, rounded to 1e-5 rad
        np.testing.assert_allclose(q[-1], message["points"][-1]["positions"], atol=1e-5)
        np.testing.assert_allclose(np.array(data["origins"])[:, -1], PANDA.fk(q)[:, :3, 3], atol=1e-4)
        assert data["speed"] == pytest.approx(PANDA.velocity.tolist())


def test_a_file_it_cannot_play_is_one_line(tmp_path, capsys):
    untimed = tmp_path / "untimed.json"
    untimed.write_text(json.dumps({"status": "ok", "q": Q.tolist()}))
    garbage = tmp_path / "garbage.json"
    garbage.write_text("{not json")
    wrong = tmp_path / "wrong.json"
    wrong.write_text(json.dumps({"joint_names": ["a", "b"], "points": [{"positions": [0, 0]}]}))
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"joint_names": list(PANDA.joint_names), "points": [{"positions": [0] * 7}]}))
    for file, expected in ((untimed, "no JointTrajectory in it"), (garbage, "cannot read it as JSON"),
                           (wrong, "the trajectory has 2 joints, franka-panda has 7"),
                           (broken, "a point is malformed")):
        assert main(["explore", "franka-panda", "--path", str(file), "--out", str(tmp_path / "p.html"),
                     "--force"]) == 2
        err = capsys.readouterr().err
        assert expected in err and err.count("\n") == 1, err
    assert main(["explore", "franka-panda", "--path", str(untimed), "--q", *["0.1"] * 7, "--out",
                 str(tmp_path / "q.html")]) == 2
    assert "without a pose or --q" in capsys.readouterr().err
