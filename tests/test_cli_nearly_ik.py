"""``redkin ik --psi/--q7``: one printer for every class with a closed form (exact S-R-S, nearly S-R-S, Franka).

The chosen behaviour for "the pose has no solution at this value of the redundancy parameter", the same on every
class and as the numerical path's for a pose without a solution found: the answer is printed (text: ``no solution
of ... at psi = ...``; JSON: ``solutions`` empty, every asked branch under ``missing``) and the exit code is 1.
A batch (``--poses``) exits 1 when one of its poses has none, after printing every entry.  Bad input stays exit
code 2 with one line.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot
from redkin.srs import pose_from

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


@pytest.mark.parametrize("robot", sorted(CLASSES))
def test_a_pose_out_of_reach_is_an_answer_with_exit_1(capsys, robot):
    option, _ = CLASSES[robot]
    assert main(["ik", robot, *FAR, option, "0.5"]) == 1
    captured = capsys.readouterr()
    name = option.lstrip("-")
    assert captured.out.strip() == f"no solution of branch +++ at {name} = 0.500000 rad" and captured.err == ""
    assert main(["ik", robot, *FAR, option, "0.5", "--all", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["parameter"] == name and data["solutions"] == [] and len(data["missing"]) == 8


@pytest.mark.parametrize("robot", sorted(CLASSES))
def test_a_reachable_pose_prints_the_same_form_on_every_class(capsys, robot):
    option, _ = CLASSES[robot]
    argv, value = _reachable(robot)
    assert main(["ik", robot, *argv, option, value, "--all", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"robot", "parameter", "units", data["parameter"], "solutions", "missing"}
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
    assert main(["ik", robot, "--poses", str(file), option, value]) == 1
    assert capsys.readouterr().out.splitlines()[-1].startswith("pose 1: no solution of branch +++ at")
    np.save(file, np.stack([chain.fk(np.array(q))] * 2))
    assert main(["ik", robot, "--poses", str(file), option, value, "--all", "--json"]) == 0
