"""``redkin ik --psi/--q7``: one printer for every class with a closed form (exact S-R-S, nearly S-R-S, Franka).

The chosen behaviour for "the pose has no solution at this value of the redundancy parameter", the same on every
class and as the numerical path's for a pose without a solution found: the answer is printed (text: ``no solution
of ... at psi = ...``; JSON: ``solutions`` empty, every asked branch under ``missing``) and the exit code is 1.
Where the pose is beyond the arm's reach the line says so and by how much, and the JSON has ``"reason":
"out-of-reach"`` with the distances (``null`` otherwise).  A batch (``--poses``) exits 1 when one of its poses has
none, after printing every entry.  Bad input stays exit code 2 with one line.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot
from redkin.srs import pose_from

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
FAR = ["--position", "3", "0", "0.5", "--rotation", "1", "0", "0", "0", "-1", "0", "0", "0", "-1"]
CLASSES = {  # robot, parameter option, a reachable pose's joint values
    "pa10-7c": ("--psi", [0.3, 0.6, -0.2, 1.1, 0.4, -0.7, 0.3]),
    "kinova-gen3": ("--psi", [0.4, 0.7, -0.3, 1.2, 0.5, -0.9, 0.2]),
    "franka-fr3": ("--q7", [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785]),
}


def _pose_argv(pose: np.ndarray) -> list[str]:
    return ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist())]


def _reachable(robot: str) -> tuple[list[str], str]:
    option, q = CLASSES[robot]
    chain = get_robot(robot)
    value = "0.785" if option == "--q7" else "0.3"
    return _pose_argv(chain.fk(np.array(q))), value


#: What each class measures against its reach (the nearly S-R-S Gen3: the links' bound of any chain).
MEASURES = {"pa10-7c": "the shoulder-wrist distance", "kinova-gen3": "the tool point's distance from (0, 0, 0.28481) m "
            "on joint 1's axis", "franka-fr3": "the shoulder-wrist distance at the most favourable q7"}


@pytest.mark.parametrize("robot", sorted(CLASSES))
def test_a_pose_out_of_reach_is_an_answer_with_exit_1_and_says_by_how_much(capsys, robot):
    option, _ = CLASSES[robot]
    assert main(["ik", robot, *FAR, option, "0.5", "--all", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    name = option.lstrip("-")
    assert data["parameter"] == name and data["solutions"] == [] and len(data["missing"]) == 8
    assert data["reason"] == "out-of-reach" and data["units"]["reach"] == "m"
    reach = data["reach"]
    assert reach["measure"] == MEASURES[robot] and reach["min"] < reach["max"] < 1.0 < reach["distance"]
    assert reach["miss"] == pytest.approx(reach["distance"] - reach["max"], abs=1e-15)
    assert main(["ik", robot, *FAR, option, "0.5"]) == 1
    captured = capsys.readouterr()
    assert captured.err == "" and captured.out.count("\n") == 1
    assert captured.out.strip() == (
        f"no solution of branch +++ at {name} = 0.500000 rad: the pose is out of reach ({reach['measure']} is "
        f"{reach['distance']:.6g} m, beyond the reach of {reach['max']:.6g} m by {reach['miss']:.6g} m)")


@pytest.mark.parametrize("robot", sorted(CLASSES))
def test_a_reachable_pose_prints_the_same_form_on_every_class(capsys, robot):
    option, _ = CLASSES[robot]
    argv, value = _reachable(robot)
    assert main(["ik", robot, *argv, option, value, "--all", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"robot", "parameter", "units", data["parameter"], "solutions", "missing", "reason",
                         "branch_from"}
    assert data["reason"] is None
    assert data["solutions"] and {s["branch"] for s in data["solutions"]}.isdisjoint(data["missing"])
    chain = get_robot(robot)
    q = np.array([s["q"] for s in data["solutions"]])
    assert np.abs(chain.fk(q)[:, :3, 3] - np.array([float(v) for v in argv[1:4]])).max() < 1e-9
    assert main(["ik", robot, *argv, option, value, "--all"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(data["solutions"]) and all(line.split()[0] in {s["branch"] for s in data["solutions"]}
                                                        for line in lines)


@pytest.mark.parametrize("robot", sorted(CLASSES))
def test_a_batch_with_a_pose_out_of_reach_exits_1_after_every_entry(capsys, tmp_path, robot):
    option, q = CLASSES[robot]
    chain = get_robot(robot)
    far = pose_from(np.array([3.0, 0.0, 0.5]), np.diag([1.0, -1.0, -1.0]))
    file = tmp_path / "poses.npy"
    np.save(file, np.stack([chain.fk(np.array(q)), far]))
    value = _reachable(robot)[1]
    assert main(["ik", robot, "--poses", str(file), option, value, "--all", "--json"]) == 1
    entries = json.loads(capsys.readouterr().out)["poses"]
    assert [bool(e["solutions"]) for e in entries] == [True, False] and len(entries[1]["missing"]) == 8
    assert [e["reason"] for e in entries] == [None, "out-of-reach"] and "reach" not in entries[0]
    assert entries[1]["reach"]["distance"] > entries[1]["reach"]["max"]
    assert main(["ik", robot, "--poses", str(file), option, value]) == 1
    last = capsys.readouterr().out.splitlines()[-1]
    assert last.startswith("pose 1: no solution of branch +++ at") and "the pose is out of reach (" in last
    np.save(file, np.stack([chain.fk(np.array(q))] * 2))
    assert main(["ik", robot, "--poses", str(file), option, value, "--all", "--json"]) == 0


def _two_solutions() -> tuple[object, np.ndarray, list[str]]:
    """The Gen3 (examples/gen3.urdf to end_effector_link) whose branch ``-++`` has two solutions at psi 1.5 for the
    pose of ``tests.test_srs_nearly_self_motion.TWO_SOLUTIONS``: its chain, the pose and the ``redkin ik`` argv
    (JSON) of that branch at that arm angle."""
    from redkin.urdf import load_urdf
    from tests.test_srs_nearly_self_motion import TWO_SOLUTIONS

    gen3 = EXAMPLES / "gen3.urdf"
    chain = load_urdf(gen3, base="base_link", tip="end_effector_link")
    pose = chain.fk(np.array(TWO_SOLUTIONS))
    return chain, pose, ["ik", str(gen3), "--base", "base_link", "--tip", "end_effector_link", *_pose_argv(pose),
                         "--psi", "1.5", "--branch", "-++", "--json"]


def test_every_solution_lists_both_solutions_of_a_branch_where_the_arm_angle_turns_back(capsys):
    from redkin._compiled import use_compiled
    from redkin.srs import BRANCHES, nearly_srs, parse_branch
    from redkin.srs.nearly import arm_angle, branch_of

    use_compiled()  # one pose follows the self-motion once it is compiled (tests/test_cli_startup.py: before, not)
    chain, pose, argv = _two_solutions()
    assert main(argv) == 0
    one = json.loads(capsys.readouterr().out)["solutions"]
    assert main([*argv, "--every-solution"]) == 0
    every = json.loads(capsys.readouterr().out)
    assert len(one) == 1 and one[0]["others"] == 1 and every["missing"] == []
    assert np.abs(np.subtract(every["solutions"][0]["q"], one[0]["q"])).max() < 1e-9  # the closed form's first
    q = np.array([s["q"] for s in every["solutions"]])
    assert len(q) == 2 and np.abs(np.angle(np.exp(1j * (q[1] - q[0])))).max() > 0.1  # two solutions, apart
    arm = nearly_srs(chain)
    assert np.abs(chain.fk(q) - pose).max() < 1e-9
    assert np.abs(np.angle(np.exp(1j * (arm_angle(arm, q) - 1.5)))).max() < 1e-9
    assert np.all(branch_of(arm, q) == BRANCHES.index(parse_branch("-++")))
    assert all(s["within_limits"] == bool(chain.within_limits(s["q"], 1e-9, wrap=True)) for s in every["solutions"])
    assert main([*argv[:-1], "--every-solution"]) == 0
    assert [line.split()[0] for line in capsys.readouterr().out.splitlines()] == ["-++", "-++"]


def test_q0_picks_the_branch_solution_nearest_it(capsys):
    """Issue 38, item 4: where a branch has two solutions at the arm angle, ``--q0`` near the second returns it, and
    the output says the branch has another."""
    _, _, argv = _two_solutions()
    assert main([*argv, "--every-solution"]) == 0
    first, second = (np.array(s["q"]) for s in json.loads(capsys.readouterr().out)["solutions"])
    for wanted in (first, second):
        assert main([*argv, "--q0", *map(repr, (wanted + 0.01).tolist())]) == 0
        (picked,) = json.loads(capsys.readouterr().out)["solutions"]
        assert np.abs(np.array(picked["q"]) - wanted).max() < 1e-9 and picked["others"] == 1
    assert main([*argv[:-1], "--q0", *map(repr, second.tolist())]) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith("-++") and "1 other solution of -++ at this psi: --every-solution lists them" in line


def test_q0_shifts_an_exact_arms_solution_by_whole_turns(capsys):
    argv, value = _reachable("pa10-7c")
    assert main(["ik", "pa10-7c", *argv, "--psi", value, "--json"]) == 0
    (plain,) = json.loads(capsys.readouterr().out)["solutions"]
    assert plain["others"] == 0
    near = np.array(plain["q"]) + np.array([0, 0, 0, 0, 0, 0, 2.0 * np.pi])
    assert main(["ik", "pa10-7c", *argv, "--psi", value, "--json", "--q0", *map(repr, near.tolist())]) == 0
    (shifted,) = json.loads(capsys.readouterr().out)["solutions"]
    shifted_q, plain_q = np.array(shifted["q"]), np.array(plain["q"])
    np.testing.assert_allclose(np.angle(np.exp(1j * (shifted_q - plain_q))), 0.0, atol=1e-12)  # the same solution
    assert np.all(np.abs(shifted_q - near) <= np.abs(plain_q - near) + 1e-12)  # turned towards q0


def test_every_solution_on_an_exact_arm_is_its_one_per_branch(capsys):
    argv, value = _reachable("pa10-7c")
    assert main(["ik", "pa10-7c", *argv, "--psi", value, "--all", "--json"]) == 0
    once = capsys.readouterr().out
    assert main(["ik", "pa10-7c", *argv, "--psi", value, "--all", "--json", "--every-solution"]) == 0
    assert capsys.readouterr().out == once


@pytest.mark.parametrize("extra", [[], ["--numerical"], ["--q7", "0.5"]])
def test_every_solution_without_an_arm_angle_exits_2(capsys, extra):
    argv, _ = _reachable("kinova-gen3")
    with pytest.raises(SystemExit) as stop:
        code = main(["ik", "kinova-gen3", *argv, *extra, "--every-solution"])
        raise SystemExit(code)
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--every-solution" in err
