"""``redkin path`` with what users have and what a controller needs: waypoints from CSV, JSON and key poses, a
limits file, and a timed trajectory written as a JointTrajectory or CSV."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot
from redkin.paths import through, write_poses_csv, write_poses_json

pytest.importorskip("toppra")

PANDA = get_robot("franka-panda")
Q = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5]) + np.linspace(0.0, 1.0, 40)[:, None] * np.array(
    [0.5, 0.3, -0.2, 0.4, 0.3, -0.3, 0.2])


def _refused(capsys, argv: list[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("redkin: error: ") and err.count("\n") == 1
    return err


def test_a_csv_seam_gives_a_timed_joint_trajectory_within_the_limits(tmp_path, capsys):
    poses = PANDA.fk(Q)
    seam = tmp_path / "seam.csv"
    write_poses_csv(seam, poses)
    out = tmp_path / "trajectory.json"
    assert main(["path", "franka-panda", "--poses", str(seam), "--max-step", "0.1", "--trajectory", str(out),
                 "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    timing = report["trajectory"]
    assert timing["file"] == str(out) and timing["joint_trajectory"] is None and timing["rate"] == 1000.0
    jerk = np.diff([p["accelerations"] for p in json.loads(out.read_text())["points"]], axis=0) / np.diff(
        [p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"] for p in
         json.loads(out.read_text())["points"]])[:, None]
    assert timing["jerk_ratio"] == pytest.approx(np.abs(jerk / PANDA.jerk).max(), rel=1e-6)
    message = json.loads(out.read_text())
    assert message["joint_names"] == list(PANDA.joint_names)
    points = message["points"]
    assert len(points) == timing["samples"]
    q = np.array([point["positions"] for point in points])
    qd = np.array([point["velocities"] for point in points])
    qdd = np.array([point["accelerations"] for point in points])
    t = np.array([p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"] for p in points])
    assert t[-1] == pytest.approx(timing["duration"], abs=1e-9)
    assert np.all(np.abs(qd) <= PANDA.velocity) and np.all(np.abs(qdd) <= PANDA.acceleration)
    assert PANDA.within_limits(q).all()
    # the samples at the waypoint times are the path's own configurations: each reaches its pose
    resolved = np.array(report["q"])
    np.testing.assert_allclose(PANDA.fk(resolved), poses, atol=1e-9)
    nearest = np.searchsorted(t, timing["waypoint_times"])
    exact = np.isclose(t[np.minimum(nearest, len(t) - 1)], timing["waypoint_times"], rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(q[nearest[exact]], resolved[exact], atol=1e-9)


def test_key_poses_in_json_joined_at_a_step_and_a_csv_trajectory(tmp_path, capsys):
    keys = PANDA.fk(Q[[0, 20, 39]])
    key_file = tmp_path / "keys.json"
    write_poses_json(key_file, keys)
    out = tmp_path / "trajectory.csv"
    argv = ["path", "franka-panda", "--through", str(key_file), "--step", "0.01", "--max-step", "0.1",
            "--trajectory", str(out), "--rate", "250"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    expected = through(keys, step=0.01)
    assert f"path of {len(expected)} waypoints" in text and "timed: " in text and str(out) in text
    assert "jerk not limited: the largest between samples is" in text
    with out.open() as handle:
        rows = list(csv.reader(handle))
    assert rows[0][:2] == ["t", "q_" + PANDA.joint_names[0].replace(" ", "_")] and len(rows[0]) == 1 + 3 * 7
    table = np.array(rows[1:], dtype=float)
    np.testing.assert_allclose(np.diff(table[:-1, 0]), 1 / 250, rtol=1e-9)
    assert np.all(np.abs(table[:, 8:15]) <= PANDA.velocity)
    assert _refused(capsys, argv).endswith("already exists: add --force to replace it, or choose another name\n")


def test_a_limits_file_sets_the_speeds_the_trajectory_keeps(tmp_path, capsys):
    poses = tmp_path / "poses.npy"
    np.save(poses, PANDA.fk(Q))
    limits = tmp_path / "limits.yaml"
    limits.write_text("velocity: 30\nacceleration: 100\n")
    assert main(["path", "franka-panda", "--poses", str(poses), "--max-step", "6", "--limits", str(limits),
                 "--deg", "--timed", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    message = report["trajectory"]["joint_trajectory"]
    qd = np.array([point["velocities"] for point in message["points"]])
    assert np.abs(qd).max() <= np.radians(30.0) and np.abs(qd).max() > 0.9 * np.radians(30.0)
    assert report["trajectory"]["limits_source"] == f"--limits {limits}"


def test_the_time_objective_in_words_and_in_json(tmp_path, capsys):
    poses = tmp_path / "poses.npy"
    np.save(poses, PANDA.fk(Q))
    argv = ["path", "franka-panda", "--poses", str(poses), "--max-step", "0.1", "--objective", "time"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "by the shorter timed trajectory of the paths of those two objectives" in text and "timed: " in text
    assert main(argv + ["--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    durations = []
    for objective in ("clearance", "motion"):
        assert main(argv[:-1] + [objective, "--timed", "--json"]) == 0
        durations.append(json.loads(capsys.readouterr().out)["trajectory"]["duration"])
    assert report["objective"] == "time" and report["trajectory"]["duration"] == min(durations)


def test_mistakes_are_one_line_and_exit_2(tmp_path, capsys):
    poses = tmp_path / "poses.npy"
    np.save(poses, PANDA.fk(Q))
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y,z,qx,qy,qz\n0,0,0,0,0,0\n")
    limits = tmp_path / "limits.yaml"
    limits.write_text("velocity: [1, 2]\n")
    base = ["path", "franka-panda", "--max-step", "0.1"]
    assert "--poses: poses file" in _refused(capsys, base + ["--poses", str(bad)])
    assert "--through: poses file" in _refused(capsys, base + ["--through", str(bad)])
    assert "--step and --angle-step go with --through" in _refused(capsys, base + ["--poses", str(poses), "--step",
                                                                                   "0.01"])
    assert "velocity has 2 entries" in _refused(capsys, base + ["--poses", str(poses), "--limits", str(limits)])
    assert "no acceleration limit" in _refused(capsys, ["path", "kuka-iiwa14", "--max-step", "0.1", "--poses",
                                                        str(poses), "--timed"])
    assert "rate must be a positive" in _refused(capsys, base + ["--poses", str(poses), "--timed", "--rate", "0"])
    assert "--rate applies to a timed path" in _refused(capsys, base + ["--poses", str(poses), "--rate", "250"])
    assert "--trajectory" in _refused(capsys, base + ["--poses", str(poses), "--trajectory",
                                                      str(tmp_path / "t.txt")])
