"""``redkin torso-arm``: exit codes and output."""

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.torso_arm import humanoid_arm


def test_torso_arm_cli_ik_json_round_trips(capsys):
    arm = humanoid_arm("right", 0.0)
    q = np.radians([10, 40, 30, 50, 20, 30, 40, 50])
    pose = arm.chain.fk(q)
    from redkin.torso_arm import redundancy_parameters

    psi, phi, _ = redundancy_parameters(arm, q, "vector")
    code = main(["torso-arm", "ik", "--position", *map(str, pose[:3, 3]), "--rotation", *map(str, pose[:3, :3].ravel()),
                 "--shoulder", str(psi), "--elbow", str(phi), "--reference", "vector", "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "ok" and len(out["solutions"]) == 8
    solutions = np.array([s["q"] for s in out["solutions"]])
    np.testing.assert_allclose(arm.chain.fk(solutions), np.broadcast_to(pose, (8, 4, 4)), atol=1e-10)


def test_torso_arm_cli_ik_degrees_and_status(capsys):
    assert main(["torso-arm", "ik", "--position", "3", "2", "1", "--shoulder", "0", "--elbow", "0", "--deg"]) == 0
    assert "unreachable" in capsys.readouterr().out


def test_torso_arm_cli_map_writes_png_and_json(tmp_path, capsys):
    out = tmp_path / "map.png"
    code = main(["torso-arm", "map", "--plane", "z=0.3", "--extent", "0", "1", "-0.4", "0.8", "--resolution", "12",
                 "--shoulder", "0.2", "--elbow", "0", "--out", str(out), "--threshold", "0.05", "--json"])
    assert code == 0 and out.exists()
    data = json.loads(capsys.readouterr().out)
    assert len(data["values"]) == 12 and data["threshold"]["area_m2"] >= 0
    assert main(["torso-arm", "map", "--plane", "y=0.3", "--extent", "0", "1", "-0.4", "0.8", "--resolution", "6",
                 "--arm", "both", "--samples", "4", "4"]) == 0


def test_torso_arm_cli_bad_input_exit_2(capsys):
    assert main(["torso-arm", "map", "--plane", "q=1", "--extent", "0", "1", "0", "1"]) == 2
    assert main(["torso-arm", "map", "--plane", "z=0", "--extent", "0", "1", "0", "1", "--shoulder", "1"]) == 2
    assert main(["torso-arm", "ik", "--position", "1", "2", "3", "--rotation", *["1"] * 9, "--shoulder", "0",
                 "--elbow", "0"]) == 2
    err = capsys.readouterr().err
    assert "plane" in err and "orthonormal" in err
    assert main(["torso-arm", "ik", "--position", "0.3", "-0.3", "0.1", "--rotation", "1", "0", "0", "0", "1", "0",
                 "0", "0", "1", "--shoulder", "0", "--elbow", "0", "--tool", "-1"]) == 2  # a length: it was accepted
    assert "tool_length must be a finite number >= 0, got -1" in capsys.readouterr().err


@pytest.mark.slow
def test_map_without_extent_covers_the_reach_in_that_plane(capsys):
    """The default extent is the box of the arm's reach there: every valid point lies inside, none on its edge."""
    code = main(["torso-arm", "map", "--plane", "z=0.3", "--resolution", "40", "--shoulder", "0.2", "--elbow", "0.3",
                 "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    values = np.array([[np.nan if v is None else v for v in row] for row in out["values"]])
    valid = np.isfinite(values)
    assert valid.any() and not (valid[0].any() or valid[-1].any() or valid[:, 0].any() or valid[:, -1].any())
    assert out["units"]["u"] == "m" and out["units"]["values"] == out["unit"]


def test_map_sizes_beyond_their_limits_exit_2_naming_the_limit(capsys):
    for argv, limit in ((["--resolution", "100000"], "2..1000"), (["--samples", "1", "5000"], "1..3600"),
                        (["--resolution", "200", "--samples", "1000", "90"], "at most 100000000")):
        assert main(["torso-arm", "map", "--plane", "z=0.3", *argv]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and limit in err, err


def test_plane_outside_the_reach_needs_an_extent(capsys):
    assert main(["torso-arm", "map", "--plane", "y=0.9", "--resolution", "10"]) == 2
    assert "outside the arm's reach" in capsys.readouterr().err


def test_map_prints_readable_lines_and_no_blank_line(capsys):
    """The README's fixed-(psi, phi) map at resolution 200 drew no bar yet printed a bar's closing newline: the
    output began with a blank line (stderr) and showed `units:` and `threshold:` as Python dicts."""
    assert main(["torso-arm", "map", "--plane", "z=0.3", "--resolution", "200", "--shoulder", "0.2", "--elbow", "0.3",
                 "--threshold", "0.01"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    lines = captured.out.splitlines()
    assert lines[0] == "plane: z = 0.3 m" and all(line.strip() for line in lines)
    assert not any("{" in line or "'" in line for line in lines), lines
    assert any(line.startswith("max: ") and line.endswith(" m^3") for line in lines)
    assert any(line.startswith("w >= 0.01 m^3: ") and "m^2" in line for line in lines)


def test_ik_help_states_units_and_what_arm_means(capsys):
    for argv, phrases in ((["torso-arm", "ik", "--help"], ["shoulder angle psi", "elbow angle phi",
                                                              "X-Y-Z fixed angles", "which arm"]),
                          (["torso-arm", "map", "--help"], ["both: the two arms together", "fixed shoulder angle"])):
        with pytest.raises(SystemExit):
            main(argv)
        text = " ".join(capsys.readouterr().out.split())
        for phrase in phrases:
            assert phrase in text, (argv, phrase)
        assert text.count("radians, or degrees with --deg") >= 2


def test_ik_text_counts_the_solutions_within_the_limits(capsys):
    assert main(["torso-arm", "ik", "--position", "0.6", "0.4", "0.3", "--angles", "0", "90", "0", "--shoulder", "10",
                 "--elbow", "20", "--deg"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0] == "status: ok, 2 of 8 solutions within the limits"
    assert "-0.000000" not in out


def test_map_progress_off_a_terminal_is_plain_lines(monkeypatch, capsys):
    """--arm both into a log or a file (issue 22): one plain line per tenth, never the '\\r' of a bar."""
    import redkin.torso_arm.maps as maps

    real = maps.best_dual_arm_map

    def reporting(grid, samples, progress=None, **kwargs):
        for k in range(1, 21):
            if progress is not None:
                progress(k / 20)
        return real(maps.plane_grid("y=0.3", (0.0, 1.0, -0.4, 0.8), 4), samples, **kwargs)  # small: fast

    monkeypatch.setattr(maps, "best_dual_arm_map", reporting)
    monkeypatch.setattr("sys.stderr.isatty", lambda: False)
    assert main(["torso-arm", "map", "--plane", "y=0.3", "--extent", "0", "1", "-0.4", "0.8", "--resolution", "400",
                 "--arm", "both", "--samples", "4", "4"]) == 0  # 400^2 x 16 evaluations: a large map, progress
    err = capsys.readouterr().err
    assert "\r" not in err
    assert [line for line in err.splitlines() if line.startswith("progress:")] == [
        f"progress: {10 * k:.1f}%" for k in range(1, 11)]
