"""``redkin track`` end to end: the summary by default, the time series with --series, and the --plot file."""

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot
from redkin.reproduce import printed

# paper 003 section 4, read with --deg: the angular rates in deg/s
TWIST_DEG = [*printed.SECTION_4_TWIST[:3], *np.degrees(printed.SECTION_4_TWIST[3:])]
SCENARIO = ["track", "barrett-wam", "--q0", *map(str, printed.SECTION_4_Q0_DEG), "--deg",
            "--twist", *map(str, TWIST_DEG), "--duration", "4", "--dt", "0.01"]


def test_velocity_cli_track_json_crosses_once(capsys, tmp_path):
    png = tmp_path / "run.png"
    assert main(SCENARIO + ["--method", "sc", "--json", "--series", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["crossings"] == 1 and png.stat().st_size > 1000
    realised = np.array(out["realised_twist"])
    assert out["units"]["realised_twist"] == "m/s (linear), deg/s (angular)"  # the scenario reads --deg
    assert np.allclose(realised[0], TWIST_DEG, atol=1e-8)
    assert np.allclose(realised[-1], [-TWIST_DEG[0], *TWIST_DEG[1:]], atol=1e-8)


def test_velocity_cli_track_dls_text(capsys):
    assert main(SCENARIO + ["--method", "dls", "--damping", "0.05"]) == 0
    assert "sign changes: 0" in capsys.readouterr().out


def test_velocity_cli_bad_input(capsys):
    assert main(["track", "barrett-wam", "--q0", "0", "0", "--twist", "0", "0", "0", "0", "0", "0",
                 "--duration", "1"]) == 2
    assert "7 joints" in capsys.readouterr().err
    assert main(SCENARIO + ["--method", "dls", "--damping", "-1"]) == 2
    capsys.readouterr()
    assert main(SCENARIO + ["--method", "pinv", "--damping", "0.1"]) == 2  # it was ignored without a word
    assert "--damping is for --method dls or dls-adaptive; pinv has no damping" in capsys.readouterr().err
    assert main(SCENARIO[:-4] + ["--duration", "-1"]) == 2
    assert main(SCENARIO + ["--eps", "0"]) == 2


def test_velocity_cli_track_sc_on_srs_arms_crosses_the_stretched_elbow(capsys):
    """PA10 and iiwa: D_e = sin theta_4 (found automatically); stretching the arm passes q4 = 0 once, translation
    reverses.

    D_e changes sign; which sign it starts with depends on the arm's joint-4 sense (KUKA's A4 turns the other
    way from the PA10's Table 1 joint 4).
    """
    for robot in ("pa10-7c", "kuka-iiwa14"):
        chain = get_robot(robot)
        q0 = np.radians([0.0, 30.0, 0.0, 30.0, 0.0, 30.0, 0.0])
        reach = chain.fk(q0)[:3, 3] - chain.frames(q0)[2, :3, 3]  # shoulder centre -> tool: stretch the arm
        velocity = 0.15 * reach / np.linalg.norm(reach)
        args = ["track", robot, "--q0", *map(str, q0), "--twist", *map(str, velocity), "0", "0", "0",
                "--duration", "4", "--dt", "0.01", "--method", "sc", "--json", "--series"]
        assert main(args) == 0
        out = json.loads(capsys.readouterr().out)
        index = np.array(out["index"])
        assert out["crossings"] == 1 and abs(index[0]) > 0.1 and index[-1] * np.sign(index[0]) < -0.1
        assert np.allclose(np.array(out["realised_twist"])[0], [*velocity, 0, 0, 0], atol=1e-9)
        assert np.allclose(np.array(out["realised_twist"])[-1], [*-velocity, 0, 0, 0], atol=1e-9)


def test_velocity_cli_track_sc_refuses_an_arm_that_does_not_factor(capsys, tmp_path):
    """A WAM with an offset wrist (a5 != 0): neither the WAM closed form nor sin q4 factors its minors."""
    rows = [(0, -90, 0), (0, 90, 0), (0.045, -90, 0.55), (-0.045, 90, 0), (0.03, -90, 0.3), (0, 90, 0), (0, 0, 0.06)]
    robot = {"name": "offset-wrist", "convention": "dh", "angle_unit": "deg",
             "joint": [{"a": a, "alpha": alpha, "d": d} for a, alpha, d in rows]}
    path = tmp_path / "offset_wrist.json"
    path.write_text(json.dumps(robot))
    base = ["track", str(path), "--q0", *["0.3"] * 7, "--twist", "0.1", "0", "0", "0", "0", "0", "--duration", "0.1"]
    assert main(base + ["--method", "sc"]) == 2
    err = capsys.readouterr().err
    assert "do not factor through one parameter" in err and len(err.strip().splitlines()) == 1
    assert main(base + ["--method", "pinv"]) == 0  # the baselines need no index


def test_track_json_says_its_units_and_keeps_them(capsys):
    """With --deg every angle and angular rate is in degrees, and the JSON says so."""
    short = ["--duration", "0.2", "--dt", "0.01", "--method", "sc", "--json", "--series"]
    assert main(SCENARIO[:-4] + short) == 0
    deg = json.loads(capsys.readouterr().out)
    q0 = [str(v) for v in np.radians(printed.SECTION_4_Q0_DEG)]
    assert main(["track", "barrett-wam", "--q0", *q0, "--twist", *map(str, printed.SECTION_4_TWIST), *short]) == 0
    rad = json.loads(capsys.readouterr().out)
    assert deg["units"]["max_joint_speed"] == "deg/s" and rad["units"]["max_joint_speed"] == "rad/s"
    assert deg["units"]["joint_velocity"] == "deg/s" and "deg/s (angular)" in deg["units"]["target_twist"]
    np.testing.assert_allclose(deg["max_joint_speed"], np.max(np.linalg.norm(deg["joint_velocity"], axis=1)))
    np.testing.assert_allclose(deg["max_joint_speed"], np.degrees(rad["max_joint_speed"]), rtol=1e-9)
    np.testing.assert_allclose(np.array(deg["target_twist"])[:, 4], TWIST_DEG[4], rtol=1e-9)
    np.testing.assert_allclose(np.radians(deg["q"]), rad["q"], atol=1e-12)


def test_plot_that_cannot_be_written_fails_before_the_run(capsys, tmp_path):
    for target in ("/proc/forbidden/run.png", str(tmp_path / "run.txt"), str(tmp_path)):
        assert main(SCENARIO + ["--plot", target]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "--plot" in err, err


def test_track_json_is_a_summary_unless_series_is_asked_for(capsys):
    """The default --json is a summary of a few dozen lines (the paper's 4 s run at 1 ms printed 164 072 lines):
    the D_e crossing and its time, the peak joint speed and when, the final error, the units; --series adds
    every step, and its numbers agree with the summary."""
    scenario = [*SCENARIO[:-1], "0.001", "--method", "sc", "--json"]  # the paper's step: 4000 steps
    assert main(scenario) == 0
    text = capsys.readouterr().out
    summary = json.loads(text)
    assert len(text.splitlines()) < 120
    assert summary["steps"] == 4000 and summary["crossings"] == 1 and len(summary["crossing_times"]) == 1
    assert 1.0 < summary["crossing_times"][0] < 3.0
    assert set(summary["units"]) >= {"time", "q", "max_joint_speed", "final_error", "position"}
    units = summary["units"]
    assert units["max_joint_speed"] == "deg/s" and units["final_error"].endswith("deg/s (angular)")
    assert not {"time", "joint_velocity", "index", "realised_twist"} & set(summary)
    # SC reverses the translation past the boundary and keeps the rotation: the final error says so
    assert summary["final_error"]["linear"] == pytest.approx(2 * TWIST_DEG[0], rel=1e-6)
    assert summary["final_error"]["angular"] < 1e-9
    assert main(scenario + ["--series"]) == 0
    series = json.loads(capsys.readouterr().out)
    assert len(series["time"]) == 4001 and {k: series[k] for k in summary if k != "units"} == {
        k: v for k, v in summary.items() if k != "units"}
    assert series["units"].items() >= summary["units"].items()
    speed = np.linalg.norm(series["joint_velocity"], axis=1)
    assert summary["max_joint_speed"] == pytest.approx(speed.max(), rel=1e-12)
    assert summary["max_joint_speed_time"] == series["time"][int(np.argmax(speed))]
    index = np.array(series["index"])
    k = int(np.flatnonzero(np.diff(np.sign(index)))[0])
    assert series["time"][k] <= summary["crossing_times"][0] <= series["time"][k + 1]
    error = np.array(series["realised_twist"])[-1] - np.array(summary["final"]["commanded_twist"])
    assert summary["final_error"]["linear"] == pytest.approx(np.linalg.norm(error[:3]), rel=1e-9)
    assert summary["final"]["q"] == series["q"][-1]


def test_series_without_json_is_refused(capsys):
    assert main(SCENARIO + ["--method", "pinv", "--series"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--json" in err


def test_text_summary_names_the_final_error_and_the_crossing_time(capsys):
    assert main(SCENARIO + ["--method", "sc"]) == 0
    out = capsys.readouterr().out
    assert "final error" in out and "sign changes: 1 (t = " in out and "at t = " in out
    assert "-0.0000" not in out


def test_method_help_says_what_each_method_is(capsys):
    with pytest.raises(SystemExit):
        main(["track", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for phrase in ("sc, singularity-consistent", "pinv, the pseudoinverse", "dls, damped least squares",
                   "dls-adaptive, damping that grows", "--series"):
        assert phrase in text, phrase
