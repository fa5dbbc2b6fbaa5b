"""``redkin ik`` on a pose out of reach, on every solver path: one line that says so and by how much (exit 1, as any
pose without a solution), ``"reason": "out-of-reach"`` with the distances in JSON; the help of ``--base``/``--tip``
on every command; the digits of a class reason's angle.
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import numpy as np
import pytest

from redkin.cli.main import _build_parser, main
from redkin.models import get_robot

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: The issue's pose: 10 m out along x, the tool pointing down.
FAR = ["--position", "10", "0", "0", "--rotation", "-1", "0", "0", "0", "1", "0", "0", "0", "-1"]
#: One line: the verdict, the measure, the distance, the reach and the miss, in metres.
LINE = re.compile(r"the pose is out of reach \((?P<measure>.+) is (?P<distance>[\d.e+-]+) m, "
                  r"(?P<side>beyond the reach|inside the shortest reach) of (?P<reach>[\d.e+-]+) m by "
                  r"(?P<miss>[\d.e+-]+) m\)")


def _urdf(name: str) -> str:
    return str(EXAMPLES / name)


def _run(capsys, argv: list[str]) -> tuple[int, str, str]:
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _checked_line(line: str, side: str = "beyond the reach") -> re.Match:
    """The reason in ``line``, its numbers consistent: the miss is the distance beyond (or short of) the reach."""
    match = LINE.search(line)
    assert match is not None, line
    distance, reach, miss = (float(match[key]) for key in ("distance", "reach", "miss"))
    assert match["side"] == side and miss > 0.0
    assert miss == pytest.approx(distance - reach if side == "beyond the reach" else reach - distance, rel=1e-5)
    return match


# ------------------------------------------------------------------------------------------------ every class


@pytest.mark.parametrize("robot, extra, measure", [
    ("pa10-7c", ["--psi", "0"], "the shoulder-wrist distance"),
    ("franka-panda", ["--q7", "0.5"], "the shoulder-wrist distance at the most favourable q7"),
    ("pa10-7c", [], "the tool point's distance from (0, 0, 0.317) m on joint 1's axis"),
])
def test_the_issues_pose_says_out_of_reach_in_one_line_on_every_path(capsys, robot, extra, measure):
    code, out, err = _run(capsys, ["ik", robot, *FAR, *extra])
    lines = out.splitlines()
    assert code == 1 and err == ""
    if extra:  # the closed forms: one line
        assert len(lines) == 1 and lines[0].startswith(f"no solution of branch +++ at {extra[0][2:]} = ")
    else:  # numerical: the heading, then one line, and no search
        assert len(lines) == 2 and lines[1].startswith("no solution: ") and lines[1].endswith("; not searched")
        assert "closest" not in out
    match = _checked_line(lines[-1])
    assert match["measure"] == measure and float(match["distance"]) > 9.0


def test_the_pa10_at_psi_measures_what_paper_000_solves(capsys):
    """The distances of the JSON are the closed form's: |x_sw| of the pose, and |d_se -+ d_ew| (in metres)."""
    wrist = np.array([10.0, 0.0, 0.0]) + 0.07 * np.array([0.0, 0.0, 1.0])  # the tool points down: wrist above it
    expected = float(np.linalg.norm(wrist - [0.0, 0.0, 0.317]))
    code, out, _ = _run(capsys, ["ik", "pa10-7c", *FAR, "--psi", "0", "--all", "--json"])
    data = json.loads(out)
    assert code == 1 and data["solutions"] == [] and len(data["missing"]) == 8 and data["units"]["reach"] == "m"
    assert data["reason"] == "out-of-reach" and data["reach"]["measure"] == "the shoulder-wrist distance"
    assert data["reach"]["distance"] == pytest.approx(expected, abs=1e-12)
    assert data["reach"]["min"] == pytest.approx(0.03, abs=1e-12) and data["reach"]["max"] == pytest.approx(0.93)
    assert data["reach"]["miss"] == pytest.approx(expected - 0.93, abs=1e-12)


def test_a_pose_inside_the_pa10s_shortest_reach_says_so(capsys):
    """The wrist 1 cm from the shoulder: |d_se - d_ew| = 3 cm is the shortest shoulder-wrist distance."""
    argv = ["ik", "pa10-7c", "--position", "0.01", "0", "0.247", "--rotation", "-1", "0", "0", "0", "1", "0", "0",
            "0", "-1", "--psi", "0", "--all"]
    code, out, _ = _run(capsys, argv)
    assert code == 1 and out.startswith("no solution of any of the 8 branches at psi = 0.000000 rad: ")
    match = _checked_line(out, "inside the shortest reach")
    assert float(match["distance"]) == pytest.approx(0.01) and float(match["reach"]) == pytest.approx(0.03)
    code, out, _ = _run(capsys, [*argv, "--json"])
    data = json.loads(out)
    assert data["reason"] == "out-of-reach" and data["reach"]["distance"] < data["reach"]["min"]
    assert data["reach"]["miss"] == pytest.approx(0.02)


def test_a_franka_class_urdf_at_q7(capsys):
    path = _urdf("panda.urdf")
    code, out, _ = _run(capsys, ["ik", path, "--tip", "panda_link8", *FAR, "--q7", "0.5", "--json"])
    data = json.loads(out)
    assert code == 1 and data["parameter"] == "q7" and data["solutions"] == []
    assert data["reason"] == "out-of-reach" and data["units"]["reach"] == "m"
    reach = data["reach"]
    assert reach["measure"] == "the shoulder-wrist distance at the most favourable q7"
    assert 0.0 < reach["min"] < reach["max"] < 1.0 and reach["distance"] > 9.0
    assert reach["miss"] == pytest.approx(reach["distance"] - reach["max"], abs=1e-12)
    code, out, _ = _run(capsys, ["ik", path, "--tip", "panda_link8", *FAR, "--q7", "0.5"])
    assert code == 1 and _checked_line(out)["measure"] == reach["measure"]


def test_the_gen3_urdf_as_nearly_srs_at_psi(capsys):
    path = _urdf("gen3.urdf")
    argv = ["ik", path, "--base", "base_link", "--tip", "end_effector_link", *FAR, "--psi", "0.5"]
    code, out, _ = _run(capsys, argv)
    assert code == 1 and out.startswith("no solution of branch +++ at psi = 0.500000 rad: ")
    chain = get_robot(path, "base_link", "end_effector_link")
    centre, radius = chain.reach_bound
    match = _checked_line(out)
    assert float(match["reach"]) == pytest.approx(radius, rel=1e-5)  # six digits printed
    assert float(match["distance"]) == pytest.approx(np.linalg.norm([10.0, 0.0, 0.0] - centre), rel=1e-5)
    code, out, _ = _run(capsys, [*argv, "--json"])
    assert code == 1 and json.loads(out)["reason"] == "out-of-reach"


def test_a_general_chain_numerically(capsys):
    path = _urdf("sawyer.urdf")
    code, out, _ = _run(capsys, ["ik", path, *FAR, "--json"])
    data = json.loads(out)
    assert code == 1 and data["method"] == "numerical" and "no closed-form IK" in data["why"]
    assert data["status"] == "not-found" and data["starts"] == 1 and data["reason"] == "out-of-reach"
    chain = get_robot(path)
    centre, radius = chain.reach_bound
    distance = float(np.linalg.norm(np.array([10.0, 0.0, 0.0]) - centre))
    assert np.allclose(centre, [0.0, 0.0, 0.08 + 0.237])  # joint 1 turns the shoulder's offset about the axis
    assert data["reach"] == {"measure": "the tool point's distance from (0, 0, 0.317) m on joint 1's axis",
                             "distance": distance, "min": 0.0, "max": radius, "miss": distance - radius}
    code, out, _ = _run(capsys, ["ik", path, *FAR])
    assert code == 1 and _checked_line(out.splitlines()[-1])["measure"] == data["reach"]["measure"]


def test_a_batch_says_which_poses_are_out_of_reach_and_solves_the_others(capsys, tmp_path):
    chain = get_robot("kuka-iiwa14")
    poses = chain.fk(np.array([[0.3, 0.5, -0.2, -1.1, 0.4, 0.9, -0.3]] * 3))
    poses[1, :3, 3] = [10.0, 0.0, 0.0]
    file = tmp_path / "poses.npy"
    np.save(file, poses)
    for extra in ([], ["--psi", "0.3"]):
        code, out, _ = _run(capsys, ["ik", "kuka-iiwa14", "--poses", str(file), *extra, "--json"])
        entries = json.loads(out)["poses"]
        assert code == 1 and [entry["reason"] for entry in entries] == [None, "out-of-reach", None]
        assert bool(entries[0]["solutions"]) and not entries[1]["solutions"] and bool(entries[2]["solutions"])
        code, out, _ = _run(capsys, ["ik", "kuka-iiwa14", "--poses", str(file), *extra])
        reasons = [line for line in out.splitlines() if "out of reach" in line]
        assert code == 1 and len(reasons) == 1 and reasons[0].startswith("pose 1: no solution")
        _checked_line(reasons[0])


# ---------------------------------------------------------------------------------------------------- help texts


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = _build_parser()
    actions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(actions[0].choices)


def test_every_command_that_takes_a_tip_describes_urdf_links_and_mjcf_bodies_and_sites():
    described = []
    for name, command in _subcommands().items():
        options = {option: action for action in command._actions for option in action.option_strings}
        if "--tip" not in options:
            continue
        described.append(name)
        assert "--base" in options, name
        tip, base = options["--tip"].help, options["--base"].help
        assert "URDF link" in tip and "MJCF body or site" in tip, (name, tip)
        assert "URDF link" in base and "MJCF body" in base, (name, base)
    assert {"robots", "fk", "jacobian", "ik", "arm-angles", "path", "explore", "track"} <= set(described)


# ------------------------------------------------------------------------------------------- a reason's digits


def test_the_sawyers_class_reason_prints_an_angle_off_90_as_off_90(capsys, tmp_path):
    """The Sawyer with axis 7 turned 6.4e-7 rad (as rounded numbers leave it): 89.99996 deg apart, not "90"."""
    text = Path(_urdf("sawyer.urdf")).read_text(encoding="utf-8")
    exact = 'rpy="-1.57079632679 -0.17453 3.1416"'
    assert exact in text
    path = tmp_path / "sawyer.urdf"
    path.write_text(text.replace(exact, 'rpy="-1.57079568624 -0.17453 3.1416"'), encoding="utf-8")
    code, out, _ = _run(capsys, ["robots", "--show", str(path), "--json"])
    reason = json.loads(out)["class_reason"] if code == 0 else ""
    assert "axes 6 and 7 are 89.99996 deg apart, not 90" in reason


@pytest.mark.parametrize("angle", [89.9, 90.1, 89.9999633, 90.0000367, 89.99999994, 45.0, 0.0])
def test_degrees_apart_prints_an_angle_unlike_the_expected_one(angle):
    from redkin.srs.conventions import degrees_apart

    text = degrees_apart(angle)
    decimals = len(text.split(".")[1]) if "." in text else 0
    assert text != f"{90.0:.{decimals}f}" and abs(float(text) - angle) <= 0.5 * 10.0 ** -decimals
    assert decimals == 0 or f"{angle:.{decimals - 1}f}" == f"{90.0:.{decimals - 1}f}"  # no more digits than needed
