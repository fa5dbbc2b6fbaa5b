"""``redkin path``: exit 0 with a lawful path, 1 with the failing waypoint and joint, 2 with one line for bad input."""

import json

import numpy as np

from redkin.cli.main import main
from redkin.models import get_robot


def _line(count=8, elbow_jump=0.0):
    q = np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]) + np.linspace(-0.2, 0.2, count)[:, None] * np.array(
        [1.0, 0.5, -0.5, 0.0, 0.5, 0.5, 1.0])
    q[count // 2:, 3] += elbow_jump
    return q


def test_a_path_in_json(tmp_path, capsys):
    chain = get_robot("kuka-iiwa14")
    file = tmp_path / "poses.npy"
    np.save(file, chain.fk(_line()))
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    q = np.array(report["q"])
    assert report["status"] == "ok" and q.shape == (8, 7) and len(report["branch"]) == 8
    assert np.abs(chain.fk(q) - np.load(file)).max() <= 1e-9
    assert chain.within_limits(q).all() and np.all(np.abs(np.diff(q, axis=0)) <= 0.2)
    assert report["clearance"] > 0
    assert report["parameter"] == "psi" and len(report["psi"]) == 8
    assert isinstance(report["optimal"], bool) and (report["bottleneck"] is not None) == report["optimal"]
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2", "--json", "--thorough"]) == 0
    thorough = json.loads(capsys.readouterr().out)
    assert thorough["clearance"] >= report["clearance"] and thorough["nodes"] >= report["nodes"]
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2", "--json", "--objective",
                 "motion"]) == 0
    least = json.loads(capsys.readouterr().out)
    assert least["objective"] == "motion" and least["motion"] <= report["motion"] + 1e-9 and not least["optimal"]


def test_degrees_and_speed_with_dt(tmp_path, capsys):
    chain = get_robot("kuka-iiwa14")
    file = tmp_path / "poses.npy"
    np.save(file, chain.fk(_line()))
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--speed", "100", "--dt", "0.1", "--deg",
                 "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["unit"] == "deg" and np.allclose(report["step"], 10.0)
    assert np.all(np.abs(np.diff(report["q"], axis=0)) <= 10.0)


def test_no_path_exits_1_naming_the_waypoint_and_joint(tmp_path, capsys):
    file = tmp_path / "poses.npy"
    np.save(file, get_robot("kuka-iiwa14").fk(_line(elbow_jump=0.3)))
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2", "--json"]) == 1
    failure = json.loads(capsys.readouterr().out)["failure"]
    assert (failure["waypoint"], failure["reason"], failure["joint"]) == (4, "step", 4)
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2"]) == 1
    out = capsys.readouterr().out
    assert out.startswith("no path: waypoint 4") and "joint 4" in out and out.count("\n") == 1


def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    file = tmp_path / "poses.npy"
    np.save(file, np.zeros((3, 3)))
    for argv in (["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.1"],
                 ["path", "kuka-iiwa14", "--poses", str(tmp_path / "none.npy"), "--max-step", "0.1"],
                 ["path", "kuka-iiwa14", "--poses", str(file), "--speed", "1"],
                 ["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "-1"]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith("redkin: error:") and err.count("\n") == 1
    np.save(file, get_robot("kuka-iiwa14").fk(_line()))
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0", "--json"]) == 2
    assert main(["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.1", "--dt", "1"]) == 2


def test_plot_writes_the_figure_and_refuses_to_replace_it_without_force(tmp_path, capsys):
    chain = get_robot("kuka-iiwa14")
    poses, figure = tmp_path / "poses.npy", tmp_path / "plane.png"
    np.save(poses, chain.fk(_line()))
    argv = ["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", "--json", "--plot", str(figure)]
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["status"] == "ok"
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    written = figure.stat().st_mtime_ns, figure.stat().st_size
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "already exists" in captured.err and "--force" in captured.err
    assert captured.err.count("\n") == 1 and (figure.stat().st_mtime_ns, figure.stat().st_size) == written
    assert main([*argv, "--force"]) == 0
    capsys.readouterr()


def test_plot_of_a_path_that_does_not_exist_is_written_and_exits_1(tmp_path, capsys):
    poses, figure = tmp_path / "poses.npy", tmp_path / "plane.svg"
    np.save(poses, get_robot("kuka-iiwa14").fk(_line(elbow_jump=0.3)))
    assert main(["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", "--plot", str(figure)]) == 1
    assert capsys.readouterr().out.startswith("no path: waypoint 4")
    assert "<svg" in figure.read_text()


def test_plot_to_a_bad_place_is_one_line_and_exit_2_before_any_work(tmp_path, capsys):
    poses = tmp_path / "poses.npy"
    np.save(poses, get_robot("kuka-iiwa14").fk(_line()))
    blocker = tmp_path / "file"
    blocker.write_text("")
    for place in (blocker / "plane.png", tmp_path / "plane.txt", tmp_path):
        assert main(["path", "kuka-iiwa14", "--poses", str(tmp_path / "missing.npy"), "--max-step", "0.2",
                     "--plot", str(place)]) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and "--plot" in captured.err and captured.err.count("\n") == 1


def test_the_start_branch_is_said_with_its_reason(tmp_path, capsys):
    """Without --q0 the path names the objective's choice; with --q0 it starts on --q0's own branch, whichever
    branch that is (here one other than the objective's choice where one exists)."""
    from redkin.srs import BRANCHES, arm_angle_of, ik

    chain = get_robot("kuka-iiwa14")
    file = tmp_path / "poses.npy"
    np.save(file, chain.fk(_line()))
    argv = ["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.2"]
    assert main(argv + ["--json"]) == 0
    chosen = json.loads(capsys.readouterr().out)["start"]
    assert chosen["why"] == "objective" and chosen["branch"] in [str(b) for b in BRANCHES]
    assert main(argv) == 0
    assert f"starts on branch {chosen['branch']}: no --q0" in capsys.readouterr().out
    start = _line()[0]
    state = arm_angle_of(chain, start)
    for branch in BRANCHES:  # the first waypoint's solutions on the other branches, at the start's arm angle
        q0 = ik(chain, chain.fk(start), float(state.psi), branch)
        if str(branch) == chosen["branch"] or not chain.within_limits(q0):
            continue
        assert main(argv + ["--q0", *map(str, q0), "--json"]) == 0
        report = json.loads(capsys.readouterr().out)
        assert report["start"] == {"branch": str(branch), "why": "q0", "q0_branch": str(branch)}
        assert report["branch"][0] == str(branch)
        assert main(argv + ["--q0", *map(str, q0)]) == 0
        assert f"starts on branch {branch}, within one step of --q0 (its own branch)" in capsys.readouterr().out
        return
    raise AssertionError("no branch other than the objective's reaches the first waypoint within the limits")
