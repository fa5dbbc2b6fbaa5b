"""Which branch ``redkin ik --psi|--q7`` answers without ``--branch``: ``--q0``'s own (so the user's configuration
comes back), else ``+++`` with a line naming the branches within the limits where ``+++`` is not; JSON says which."""

from __future__ import annotations

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot

#: One arm per class with a closed form: S-R-S, offset elbow, Franka, nearly S-R-S; and configurations within the
#: limits on branches other than +++ (negative q2, q4 or q6 in the chain's own senses).
CASES = {
    "kuka-iiwa14": np.array([0.3, -0.6, 0.2, 1.2, -0.4, -0.9, 0.5]),
    "barrett-wam7": np.array([0.3, -0.6, 0.2, 1.2, -0.4, -0.9, 0.5]),
    "franka-panda": np.array([0.0, 0.3, 0.0, -1.5, 0.0, 1.5, 0.7]),
    "kinova-gen3": np.array([0.3, -0.6, 0.2, 1.2, -0.4, -0.9, 0.5]),
}

#: The cases whose +++ solution is outside the limits while other branches' are inside.
NOTED = {"barrett-wam7", "franka-panda"}


def _argv(robot: str, q: np.ndarray) -> list[str]:
    from redkin.paths.arm_family import path_family

    chain = get_robot(robot)
    pose = chain.fk(q)
    _, value = path_family(chain).parameter_of(q[None])
    parameter = "--q7" if robot == "franka-panda" else "--psi"
    return ["ik", robot, "--position", *map(repr, pose[:3, 3].tolist()), "--rotation",
            *map(repr, pose[:3, :3].ravel().tolist()), parameter, repr(float(value[0]))]


@pytest.mark.parametrize("robot", sorted(CASES))
def test_q0_alone_gives_back_the_configuration(capsys, robot):
    q = CASES[robot]
    argv = _argv(robot, q)
    assert main([*argv, "--q0", *map(repr, q.tolist()), "--json"]) == 0
    answer = json.loads(capsys.readouterr().out)
    assert answer["branch_from"] == "q0" and len(answer["solutions"]) == 1
    assert answer["solutions"][0]["branch"] != "+++"  # the case is chosen off the default branch
    np.testing.assert_allclose(answer["solutions"][0]["q"], q, atol=1e-8)


@pytest.mark.parametrize("robot", sorted(CASES))
def test_the_default_branch_says_which_branches_are_within_the_limits(capsys, robot):
    argv = _argv(robot, CASES[robot])
    assert main([*argv, "--json", "--all"]) == 0
    every = json.loads(capsys.readouterr().out)
    inside = [s["branch"] for s in every["solutions"] if s["within_limits"]]
    assert every["branch_from"] == "all"
    assert main([*argv, "--json"]) == 0
    default = json.loads(capsys.readouterr().out)
    assert default["branch_from"] == "default" and [s["branch"] for s in default["solutions"]] in (["+++"], [])
    assert main(argv) == 0 or not default["solutions"]
    lines = capsys.readouterr().out.splitlines()
    plus_inside = bool(default["solutions"]) and default["solutions"][0]["within_limits"]
    if default["solutions"] and not plus_inside and inside:
        assert lines[-1].startswith("branch +++ is the default: " + ", ".join(inside))
    else:
        assert not any(line.startswith("branch +++ is the default") for line in lines)
    # the cases meet both: +++ outside the limits with others inside (WAM, Panda), +++ inside (iiwa14, Gen3)
    assert any(line.startswith("branch +++ is the default") for line in lines) == (robot in NOTED)


@pytest.mark.parametrize("robot, position, rotation", [
    ("pa10-7c", [0.55, 0.0, 0.767], [0, 0, 1, 0, 1, 0, -1, 0, 0]),      # +++ empty, ++- not
    ("pa10-7c", [0.65, 0.0, 0.5], [-1, 0, 0, 0, 1, 0, 0, 0, -1]),       # +++ feasible
])
def test_arm_angles_names_the_feasible_branches_where_the_default_has_none(capsys, robot, position, rotation):
    from redkin.srs import BRANCHES, feasible_arm_angles, pose_from

    chain = get_robot(robot)
    pose = pose_from(np.array(position, dtype=float), np.reshape(np.array(rotation, dtype=float), (3, 3)))
    have = [str(b) for b in BRANCHES if not feasible_arm_angles(chain, pose, b).feasible.is_empty]
    argv = ["arm-angles", robot, "--position", *map(str, position), "--rotation", *map(str, rotation)]
    assert main(argv) == 0
    last = capsys.readouterr().out.splitlines()[-1]
    if "+++" in have:
        assert not last.startswith("branch +++ (the default)")
    else:
        assert last.startswith(f"branch +++ (the default) has no feasible psi; {', '.join(have)}")
    assert main([*argv, "--branch", "+++"]) == 0  # asked for: no such line
    assert not capsys.readouterr().out.splitlines()[-1].startswith("branch +++ (the default)")


def test_arm_angles_on_a_nearly_srs_arm_names_the_branches_of_its_self_motion(capsys):
    """The ROS-I iiwa (nearly S-R-S) at a pose whose +++ set is empty: the line names exactly the branches whose
    certified sets are not (:func:`redkin.srs.feasible_arm_angles_nearly_all`)."""
    from redkin.srs import feasible_arm_angles_nearly_all, nearly_srs

    chain = get_robot("examples/iiwa14_rosi.urdf")
    q = np.array([-0.0257005, -1.4120415, -0.1028156, -0.1366274, 1.4637855, -0.4008369, -2.6409391])
    pose = chain.fk(q)
    have = [str(s.branch) for s in feasible_arm_angles_nearly_all(nearly_srs(chain), pose) if not s.feasible.is_empty]
    assert have and "+++" not in have
    argv = ["arm-angles", "examples/iiwa14_rosi.urdf", "--position", *map(repr, pose[:3, 3].tolist()),
            "--rotation", *map(repr, pose[:3, :3].ravel().tolist())]
    assert main(argv) == 0
    assert capsys.readouterr().out.splitlines()[-1].startswith(
        f"branch +++ (the default) has no feasible psi; {', '.join(have)} have a Psi")
