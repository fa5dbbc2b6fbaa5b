"""``redkin ik --q7`` and ``redkin arm-angles`` on Franka-class arms: the solutions reach the pose, the sets are the
library's, an unreachable pose is an empty answer, and a misplaced option is one line with exit code 2."""

import json
from pathlib import Path

import numpy as np
import pytest

from redkin import franka
from redkin.cli.main import main
from redkin.models import get_robot

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: A configuration of the Panda inside its limits (branch --+: q2 < 0, theta_4 below phi, cos q5 > 0).
Q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.8, 0.5])


def pose_argv(pose: np.ndarray) -> list[str]:
    return ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist())]


def run_json(capsys, argv: list[str]) -> dict:
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("degrees", [False, True])
def test_ik_q7_gives_every_solution_and_the_configuration_itself(capsys, degrees):
    chain = get_robot("franka-panda")
    pose = chain.fk(Q)
    q7 = np.degrees(Q[6]) if degrees else Q[6]
    data = run_json(capsys, ["ik", "franka-panda", *pose_argv(pose), "--q7", repr(float(q7)), "--all"]
                    + (["--deg"] if degrees else []))
    assert data["parameter"] == "q7" and data["units"]["q7"] == ("deg" if degrees else "rad")
    q = np.array([s["q"] for s in data["solutions"]])
    q = np.radians(q) if degrees else q
    assert len(q) + len(data["missing"]) == 8 and len(q) >= 1
    assert np.abs(chain.fk(q) - pose).max() < 1e-9
    mine = [s for s, row in zip(data["solutions"], q) if np.abs(row - Q).max() < 1e-9]
    assert [s["branch"] for s in mine] == ["--+"] and mine[0]["within_limits"]


def test_ik_q7_on_franka_description_with_and_without_the_hand(capsys):
    path = str(EXAMPLES / "fr3.urdf")
    for tip in ("fr3_link8", "fr3_hand_tcp"):
        chain = get_robot(path, tip=tip)
        pose = chain.fk(np.array([0.1, 0.4, -0.3, -1.9, 0.2, 2.0, -0.4]))
        data = run_json(capsys, ["ik", path, "--tip", tip, *pose_argv(pose), "--q7", "-0.4", "--all"])
        q = np.array([s["q"] for s in data["solutions"]])
        assert np.abs(chain.fk(q) - pose).max() < 1e-9


def test_ik_single_branch_and_an_unreachable_pose_is_an_empty_answer(capsys):
    chain = get_robot("franka-fr3")
    pose = chain.fk(Q)
    data = run_json(capsys, ["ik", "franka-fr3", *pose_argv(pose), "--q7", "0.5", "--branch", "--+"])
    assert [s["branch"] for s in data["solutions"]] == ["--+"]
    far = pose.copy()
    far[:3, 3] = [2.0, 0.0, 0.5]
    assert main(["ik", "franka-fr3", *pose_argv(far), "--q7", "0.5", "--all", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["solutions"] == [] and len(data["missing"]) == 8
    assert main(["ik", "franka-fr3", *pose_argv(far), "--q7", "0.5"]) == 1  # no solution: exit 1 on every class
    assert "no solution of branch +++ at q7 = 0.5" in capsys.readouterr().out


def test_arm_angles_prints_the_library_q7_sets_and_optimum(capsys):
    chain = get_robot("franka-panda")
    pose = chain.fk(Q)
    data = run_json(capsys, ["arm-angles", "franka-panda", *pose_argv(pose), "--branch", "--+"])
    sets = franka.feasible_q7(chain, pose)
    assert data["parameter"] == "q7" and data["domain"] == list(sets.domain)
    index = franka.franka_geometry(chain).branch_index("--+")
    np.testing.assert_array_equal(np.array(data["feasible"]).reshape(-1, 2), sets.arcs[index])
    assert any(lo <= Q[6] <= hi for lo, hi in data["feasible"])
    assert set(data["branches"]) == {str(b) for b in franka.BRANCHES}
    assert set(data["optimal"]) == {"overall"} and "singular" not in data and "per_joint" not in data
    optimal = data["optimal"]["overall"]["feasible"]
    assert any(lo <= optimal <= hi for lo, hi in data["feasible"])
    assert main(["arm-angles", "franka-panda", *pose_argv(pose), "--branch", "--+"]) == 0
    assert "the redundancy parameter is q7" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["ik", "franka-panda", "--psi", "0"], "its redundancy parameter is q7 (--q7), not psi"),
        (["ik", "pa10-7c", "--q7", "0"], "its redundancy parameter is arm angle (--psi), not q7"),
        (["ik", str(EXAMPLES / "sawyer.urdf"), "--q7", "0"], "has no closed-form IK"),
        (["ik", "kinova-gen3", "--q7", "0"], "its redundancy parameter is arm angle (--psi), not q7"),
        (["arm-angles", "franka-panda", "--weights", "1", "0"], "weights weigh the shoulder against the wrist"),
        (["ik", "franka-panda", "--q7", "0", "--branch", "+x+"], "branch must be three signs"),
    ],
)
def test_misplaced_options_are_one_line_with_exit_2(capsys, argv, fragment):
    pose = get_robot("franka-panda").fk(Q)
    assert main(argv[:2] + pose_argv(pose) + argv[2:]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and fragment in err[0]
