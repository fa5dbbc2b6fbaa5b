"""``redkin virtual-arms``: a quick run, JSON content checked against the chain, and bad input exiting with code 2."""

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import planar_arm


def test_virtual_arms_cli_json_run_reaches_goals(capsys, tmp_path):
    out = tmp_path / "run.png"
    code = main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--point", "joint:3=0.3,0.4",
                 "--json", "--out", str(out)])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "converged"
    assert data["steps"] > 0
    q = np.array(data["q"])
    frames = planar_arm().frames(q)
    assert np.linalg.norm(frames[-1, :2, 3] - [0.5, 0.6]) < 1e-4  # end point checked on the chain itself
    assert np.linalg.norm(frames[2, :2, 3] - [0.3, 0.4]) < 1e-4  # joint 3 origin
    assert [p["point"] for p in data["points"]] == ["end", "joint:3"]
    assert all(p["error"] < 1e-4 for p in data["points"])
    assert out.stat().st_size > 0


def test_virtual_arms_cli_clamped_joints_keep_their_start(capsys):
    code = main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--fix", "1,2", "--limits", "--json", "--deg"])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "converged"
    q = np.radians(data["q"])
    assert np.allclose(q[:2], 0.5, atol=1e-12)  # clamped joints 1, 2 stay at the default start ([004 eq. 27])
    assert np.linalg.norm(planar_arm().frames(q)[-1, :2, 3] - [0.5, 0.6]) < 1e-4


def test_virtual_arms_cli_obstacle_run_reports_clearance_and_status(capsys, tmp_path):
    out = tmp_path / "obstacle.png"
    code = main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--obstacle", "0.75,0.9,0.1", "--json",
                 "--out", str(out)])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "reached"
    q = np.array(data["q"])
    frames = planar_arm().frames(q)
    assert np.linalg.norm(frames[-1, :2, 3] - [0.5, 0.6]) == pytest.approx(data["end_error"], abs=1e-12)
    assert data["end_error"] < 1e-3
    assert data["min_clearance"] > 0.0
    # the final posture itself, checked on the chain: every link stays outside the circle
    t = np.linspace(0.0, 1.0, 101)[:, None, None]
    links = frames[:-1, :2, 3] + t * (frames[1:, :2, 3] - frames[:-1, :2, 3])
    assert np.min(np.linalg.norm(links - [0.75, 0.9], axis=-1)) - 0.1 >= data["min_clearance"] - 1e-3
    assert data["obstacles"] == [{"centre": [0.75, 0.9], "radius": 0.1}]
    assert data["periods"] >= 1 and data["steps"] > 0 and data["seconds"] > 0
    assert out.stat().st_size > 0


@pytest.mark.parametrize("argv, words", [
    (["--goal", "0.5"], "--goal needs 2"),
    (["--goal", "0.5", "0.6", "--point", "joint:9=1,2"], "joint number"),
    (["--goal", "0.5", "0.6", "--point", "joint:3"], "--point must look like"),
    (["--goal", "0.5", "0.6", "--weight", "1", "--weight", "2"], "one per point"),
    (["--goal", "0.5", "0.6", "--fix", "0"], "--fix"),
    (["--goal", "0.5", "nan"], "finite"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.2"], "--obstacle must be X,Y,R"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.2,0.3,0.1,0.1"], "--obstacle must be X,Y,R"),
    (["--goal", "0.5", "0.6", "--obstacle", "a,b,c"], "--obstacle must be X,Y,R"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.7,0.9,inf"], "finite"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.7,0.9,-0.1"], "radius must be positive"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.5,0.6,0.1"], "goal [0.5, 0.6] is inside obstacle 0"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.7,0.9,0.1", "--point", "joint:3=0.3,0.4"], "drop --point"),
    (["--goal", "0.5", "0.6", "--obstacle", "0.7,0.9,0.1", "--model", "learned"], "analytic forward models only"),
])
def test_virtual_arms_cli_bad_input_exits_2_with_one_line(capsys, argv, words):
    assert main(["virtual-arms", "planar-5"] + argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1


def test_virtual_arms_cli_unknown_robot_exits_2(capsys):
    assert main(["virtual-arms", "no-such-robot", "--goal", "1", "2", "3"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


@pytest.mark.slow
def test_virtual_arms_cli_gif_out_animates_the_run(capsys, tmp_path):
    from PIL import Image  # matplotlib's own dependency

    out = tmp_path / "run.gif"
    assert main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--out", str(out)]) == 0
    with Image.open(out) as animation:
        assert animation.n_frames > 10
        first = np.asarray(animation.convert("RGB"), dtype=float)
        animation.seek(animation.n_frames - 1)
        last = np.asarray(animation.convert("RGB"), dtype=float)
    assert np.abs(first - last).mean() > 0.1  # the arm moves between the first and the last frame


def test_out_that_cannot_be_written_fails_before_the_run(capsys, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    for target in ("/proc/forbidden/run.png", str(blocker / "run.png"), str(tmp_path / "run.txt")):
        assert main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--out", target]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "--out" in err, err


def test_out_creates_missing_folders(capsys, tmp_path):
    target = tmp_path / "new" / "folder" / "run.png"
    assert main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--out", str(target)]) == 0
    assert target.stat().st_size > 1000


def test_a_goal_that_is_not_met_is_named_with_its_distance_and_why(capsys):
    """The README example: joint 3's goal lies 3.5 cm beyond its reach with joint 1 fixed; the run ends
    'converged' (at rest), and the output says what that means here."""
    argv = ["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--point", "joint:3=0.5,0.6", "--fix", "1"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert out.startswith("planar-5: converged")
    assert "joint:3: error 3.456e-02 m  (goal not met)" in out
    note = out.strip().splitlines()[-1]
    assert note.startswith("converged: the dynamics came to rest") and "goal of joint:3 not met, 3.46 cm away" in note
    assert "out of its reach (joint 1 fixed)" in note
    assert main(argv + ["--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [p["met"] for p in data["points"]] == [True, False] and data["all_goals_met"] is False
    assert data["points"][1]["error_alone"] > 0.03 and data["note"] == note
    assert data["goal_tolerance"] == 1e-3 and data["units"]["error_alone"] == "m"


def test_goals_that_compete_are_told_apart_from_goals_out_of_reach(capsys):
    """Joint 5's goal is 0.72 m from the end point's, one 0.4 m link away: each point reaches its goal alone, not
    both together; the note says the weights decide (the over-constrained run of Fig. 6 ends on its step budget)."""
    assert main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--point", "joint:5=1.1,0.2", "--max-steps",
                 "300", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["all_goals_met"] is False and all(p["error_alone"] < 1e-3 for p in data["points"])
    assert data["note"].startswith(data["status"] + ": ")
    assert "goals of end (" in data["note"] and "each reaches its goal on its own" in data["note"]
    assert "compete for the joints" in data["note"]


def test_a_run_that_meets_its_goals_adds_no_note(capsys):
    assert main(["virtual-arms", "planar-5", "--goal", "0.5", "0.6", "--point", "joint:3=0.3,0.4"]) == 0
    out = capsys.readouterr().out
    assert "not met" not in out and "converged:" not in out
