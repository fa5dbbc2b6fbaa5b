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
    assert json.loads(report.read_text())["robot"] == "franka-panda"
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
    other = tmp_path / "other.json"  # another arm's seven joints
    other.write_text(json.dumps({"joint_names": [f"iiwa_joint_{k}" for k in range(1, 8)],
                                 "points": [{"positions": [0] * 7}]}))
    elsewhere = tmp_path / "elsewhere.json"  # a named model's report: its joints are "joint 1" .. "joint 7" too
    elsewhere.write_text(json.dumps({"robot": "kuka-iiwa14", "trajectory": {"joint_trajectory": {
        "joint_names": list(PANDA.joint_names), "points": [{"positions": [0] * 7, "time_from_start": {
            "sec": 0, "nanosec": 0}}]}}}))
    def points(*rows) -> list:
        return [{"positions": list(row), "velocities": [], "time_from_start": {"sec": k, "nanosec": 0}}
                for k, row in enumerate(rows)]

    short = tmp_path / "short.json"  # a point of three joints: it said numpy's "inhomogeneous shape"
    short.write_text(json.dumps({"joint_names": list(PANDA.joint_names), "points": points(Q[0], Q[1, :3])}))
    outside = tmp_path / "outside.json"  # an iiwa's path has the Panda's names too: its values leave the ranges
    outside.write_text(json.dumps({"joint_names": list(PANDA.joint_names),
                                   "points": points(Q[0], np.where(np.arange(7) == 0, 50.0, Q[1]))}))
    for file, expected in ((untimed, "no JointTrajectory in it"), (garbage, "cannot read it as JSON"),
                           (wrong, "the trajectory has 2 joints, franka-panda has 7"),
                           (broken, "a point is malformed"), (other, "(another robot's path?)"),
                           (elsewhere, "the path was made for kuka-iiwa14, not franka-panda"),
                           (short, "point 1 has 3 positions, franka-panda has 7 joints"),
                           (outside, "point 1 puts joint 1 at 50 rad, outside franka-panda's range [-2.8973, "
                                     "2.8973] (another robot's path?)")):
        assert main(["explore", "franka-panda", "--path", str(file), "--out", str(tmp_path / "p.html"),
                     "--force"]) == 2
        err = capsys.readouterr().err
        assert expected in err and err.count("\n") == 1, err
    assert main(["explore", "franka-panda", "--path", str(untimed), "--q", *["0.1"] * 7, "--out",
                 str(tmp_path / "q.html")]) == 2
    assert "without a pose or --q" in capsys.readouterr().err


def test_the_playback_in_a_cell_draws_the_cell_and_the_distance_at_each_frame(tmp_path, capsys):
    """``path --playback --scene`` and ``explore --path --scene``: the page holds the obstacles, the body's capsules
    at each frame where the body's own FK puts them, and the least distance and its pair at each frame, equal to
    ``clearance`` at the frame's joint values."""
    from redkin.collision import builtin_body, clearance, read_scene
    from redkin.collision.body import capsule_ends, posed

    chain = get_robot("kuka-iiwa14")
    qs = np.linspace([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1], [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9], 10)
    poses, scene = tmp_path / "poses.npy", tmp_path / "cell.yaml"
    np.save(poses, chain.fk(qs))
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.2], radius: 0.05}\n"
                     "  - {name: table, type: box, center: [0.6, 0, -0.06], size: [1.2, 1.0, 0.1]}\n")
    page, trajectory, limits = tmp_path / "cell.html", tmp_path / "trajectory.json", tmp_path / "limits.yaml"
    limits.write_text("acceleration: 10\n")  # the iiwa's data sheet gives speeds, not accelerations
    assert main(["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", "--scene", str(scene),
                 "--limits", str(limits), "--playback", str(page), "--trajectory", str(trajectory)]) == 0
    capsys.readouterr()
    again = tmp_path / "again.html"
    assert main(["explore", "kuka-iiwa14", "--path", str(trajectory), "--scene", str(scene), "--out",
                 str(again)]) == 0
    body = builtin_body("kuka-iiwa14", chain)
    from redkin.cli.cell import cell_note_lines, cell_notes

    said = cell_note_lines(cell_notes(chain, (body, read_scene(scene))))
    assert said and capsys.readouterr().out.splitlines()[1:] == said  # the page's line, then the cell's notes
    for file in (page, again):
        data = _page_data(file)
        cell = data["cell"]
        assert [o["name"] for o in cell["obstacles"]] == ["post", "table"] and cell["margin"] == 0.01
        assert cell["links"] == list(body.link)
        q = np.array(data["q"]).T
        expected = clearance(chain, body, read_scene(scene), q)
        np.testing.assert_allclose(cell["distance"], expected.distance, atol=1e-4)  # q rounded to 1e-5 rad
        names = [tuple(cell["pairs"][k]) for k in cell["closest"]]
        assert sum(name == (a, b) for name, a, b in zip(names, expected.link, expected.against)) >= 0.9 * len(names)
        ends = np.array(cell["capsules"]).reshape(len(q), len(body.link), 2, 3)
        # the page's ends are written to 1e-5 m from the unrounded joint values; q is read back rounded to 1e-5 rad,
        # which moves a point up to its levers' sum times 5e-6 (1.01e-5 m seen on a wrist capsule)
        np.testing.assert_allclose(ends, capsule_ends(posed(body, chain.frames(q))), atol=1e-4)
