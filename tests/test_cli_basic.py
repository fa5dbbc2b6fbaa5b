"""The foundation commands: robots, fk, jacobian; user mistakes exit with code 2 and one line."""

import json
import subprocess
import sys

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.franka import franka_geometry
from redkin.models import MODELS, barrett_wam, pa10_7c
from redkin.reproduce import printed
from redkin.srs import srs_geometry
from redkin.srs.nearly import nearly_srs


def run(capsys, *argv):
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_fk_json_prints_the_pose(capsys):
    code, out, _ = run(capsys, "fk", "pa10-7c", *["0"] * 7, "--json")
    assert code == 0
    data = json.loads(out)
    np.testing.assert_allclose(data["pose"], pa10_7c().fk(np.zeros(7)))
    np.testing.assert_allclose(data["position"], [0, 0, 1.317])
    assert data["within_limits"] is True


def test_fk_degrees(capsys):
    q_deg = printed.SECTION_4_Q0_DEG  # paper 003 section 4's start
    code, out, _ = run(capsys, "fk", "barrett-wam", *map(str, q_deg), "--deg", "--json")
    assert code == 0
    expected = barrett_wam().fk(np.radians(q_deg))
    np.testing.assert_allclose(json.loads(out)["pose"], expected, atol=1e-12)
    np.testing.assert_allclose(json.loads(out)["q"], q_deg)


def test_jacobian_and_manipulability(capsys):
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7])
    _, out, _ = run(capsys, "jacobian", "pa10-7c", *map(str, q), "--manipulability", "--json")
    data = json.loads(out)
    np.testing.assert_allclose(data["jacobian"], pa10_7c().jacobian(q), atol=1e-12)
    np.testing.assert_allclose(data["manipulability"], pa10_7c().manipulability(q))


def test_robots_lists_models_with_their_arm_angle_class(capsys):
    code, out, _ = run(capsys, "robots", "--json")
    robots = {r["name"]: r for r in json.loads(out)["robots"]}
    assert code == 0 and set(robots) == set(MODELS)
    assert robots["pa10-7c"]["class"] == "S-R-S" and robots["barrett-wam"]["class"] == "S-R-S, offset elbow"
    assert robots["planar-5"]["class"] == "general chain" and "7 joints" in robots["planar-5"]["class_reason"]
    assert robots["franka-panda"]["class"] == "Franka (q7)" and "0.088 m" in robots["franka-panda"]["class_reason"]
    assert robots["kinova-gen3"]["class"] == "nearly S-R-S"
    assert "offset along axis 4 by 12.75 mm, axes 1 and 3 miss each other by 11.75 mm" in \
        robots["kinova-gen3"]["class_reason"]
    for name, entry in robots.items():  # each class is the one its closed-form solver acts on
        chain = MODELS[name]()
        try:
            srs_geometry(chain)
        except ValueError as exc:
            try:
                franka_geometry(chain)
            except ValueError as other:
                try:
                    nearly = nearly_srs(chain)
                except ValueError:
                    assert entry["class"] == "general chain" and entry["class_reason"].startswith(str(exc))
                    assert chain.n != 7 or entry["class_reason"].endswith(str(other))
                else:
                    assert entry["class"] == "nearly S-R-S"
                    assert entry["class_reason"] == f"{nearly.describe()}, and solutions are polished on the real arm"
            else:
                assert entry["class"] == "Franka (q7)"
        else:
            assert entry["class"] not in ("general chain", "Franka (q7)")
    from redkin import examples

    assert json.loads(run(capsys, "robots", "--json")[1])["example_files"] == examples.names()
    code, out, _ = run(capsys, "robots")
    lines = out.splitlines()
    assert code == 0 and len(lines) == len(MODELS) + 1  # a line per model, then the example files
    assert lines[-1].startswith("example files") and all(name in lines[-1] for name in examples.names())


def test_robots_show_prints_the_chain_and_why_it_is_of_its_class(capsys):
    code, out, _ = run(capsys, "robots", "--show", "barrett-wam", "--json", "--deg")
    data = json.loads(out)
    wam = barrett_wam()
    directions, points = wam.joint_axes(np.zeros(7))
    assert code == 0 and data["class"] == "S-R-S, offset elbow" and "a_3 0.045 m" in data["class_reason"]
    np.testing.assert_allclose([j["axis"] for j in data["joints"]], directions * wam.sign[:, None], atol=1e-15)
    np.testing.assert_allclose([j["point"] for j in data["joints"]], points, atol=1e-15)
    np.testing.assert_allclose(data["tool"], wam.tool)
    code, out, _ = run(capsys, "robots", "--show", "pa10-7c", "--deg")
    assert code == 0 and "class: S-R-S" in out and "[-90, 90]" in out and "joint 7" in out


def test_robots_show_names_the_franka_class_of_a_urdf_arm(capsys):
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "panda.urdf"
    code, out, _ = run(capsys, "robots", "--show", str(path), "--json")
    data = json.loads(out)
    assert code == 0 and data["class"] == "Franka (q7)"
    assert "axis 7 offset a_6 0.088 m from axis 6" in data["class_reason"]
    assert [j["name"] for j in data["joints"]] == [f"panda_joint{k}" for k in range(1, 8)]


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["fk", "pa10-7c", "0", "0"], "7 joints, got 2"),
        (["fk", "no-such-robot", "0"], "unknown robot"),
        (["fk", "sawyer", "0"], "unknown robot 'sawyer' (redkin ships the example sawyer.urdf)"),
        (["fk", "pa10-7c", *["nan"] * 7], "finite"),
        (["fk", "pa10-7c", "a", "b"], "invalid float"),
        (["fk", "missing.toml", "0"], "does not exist"),
        (["jacobian"], "required"),
        (["robots", "--show", "no-such-robot"], "unknown robot"),
        (["robots", "--tip", "link7"], "--base and --tip go with --show"),
        (["no-such-command"], "invalid choice"),
    ],
)
def test_user_mistakes_exit_2_with_one_line(capsys, argv, fragment):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse errors
        code = exc.code
    captured = capsys.readouterr()
    assert code == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert fragment in lines[0]
    assert "Traceback" not in captured.err


def test_malformed_robot_file_from_cli(tmp_path, capsys):
    path = tmp_path / "arm.toml"
    path.write_text('[[joint]]\na = 0\nalpha = "x"\nd = 0\n')
    code, _, err = run(capsys, "fk", str(path), "0")
    assert code == 2 and "alpha must be a number" in err


def _commands(parser):
    return sorted(next(a for a in parser._actions if a.dest == "command").choices)


def test_each_command_is_parsed_by_its_own_module_alone():
    """main builds only the module of the command it runs (``redkin fk`` imports no matplotlib): the table is
    complete."""
    from redkin.cli.main import _COMMANDS, _build_parser

    assert _commands(_build_parser()) == sorted(_COMMANDS)
    for command in _COMMANDS:
        assert command in _commands(_build_parser(command))
    assert _commands(_build_parser("no-such-command")) == sorted(_COMMANDS)  # an unknown command lists them all


def test_fk_imports_neither_matplotlib_nor_the_other_commands():
    code = ("import sys; from redkin.cli.main import main; main(['fk', 'pa10-7c'] + ['0'] * 7); "
            "print(sorted(m for m in ('matplotlib', 'redkin.reproduce', 'redkin.velocity') if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip().splitlines()[-1] == "[]"


def test_console_script_runs():
    result = subprocess.run([sys.executable, "-m", "redkin.cli.main", "fk", "pa10-7c", "0"], capture_output=True,
                            text=True)
    assert result.returncode == 2 and "Traceback" not in result.stderr


def test_cli_closed_pipe_ends_quietly():
    # `redkin track ... --json | head`: the reader closes the pipe long before the output ends
    import subprocess
    import sys

    command = [sys.executable, "-m", "redkin.cli.main", "track", "barrett-wam",
               "--q0", *map(str, printed.SECTION_4_Q0_DEG), "--deg", "--twist", str(printed.SECTION_4_LINEAR_SPEED),
               "0", "0", "0", "0", "0", "--duration", "2", "--method", "pinv", "--json", "--series"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert process.stdout.read(10)
    process.stdout.close()
    error = process.stderr.read().decode()
    assert process.wait(timeout=120) == 1
    assert "Traceback" not in error and error == ""


def test_one_joint_is_one_joint(tmp_path, capsys):
    path = tmp_path / "one.toml"
    path.write_text("name = 'one'\nconvention = 'dh'\n[[joint]]\na = 0.5\nalpha = 0\nd = 0\n")
    code, out, _ = run(capsys, "robots", "--show", str(path))
    assert code == 0 and out.startswith("one: 1 joint (dh)")
    code, _, err = run(capsys, "fk", str(path), "0", "0")
    assert code == 2 and "one has 1 joint, got 2 joint values" in err


def test_robots_show_prints_no_negative_zero(capsys):
    """Axis components of -1e-17 printed as -0.0000."""
    for robot in ("kuka-iiwa14", "barrett-wam7", "franka-panda", "humanoid-left"):
        code, out, _ = run(capsys, "robots", "--show", robot)
        assert code == 0 and "-0.0000" not in out, robot


@pytest.mark.parametrize("length", ["1e308", "-1e308", "1e7"])
def test_a_robot_file_with_an_absurd_length_exits_2_naming_the_limit(tmp_path, capsys, length):
    path = tmp_path / "huge.toml"
    path.write_text(f"name = 'huge'\nconvention = 'dh'\n[[joint]]\na = {length}\nalpha = 0\nd = 0\n")
    for argv in (["fk", str(path), "0"], ["robots", "--show", str(path)]):
        code, out, err = run(capsys, *argv)
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert "at most 1e+06 m" in err and "Warning" not in err and out == ""
