"""``redkin ik`` without ``--psi``/``--q7``: numerical on any arm, certified, one JSON entry per pose of a
``--poses`` file, exit 1 where a pose has no solution, and one line with exit code 2 for every mistake."""

import json
from pathlib import Path

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot
from redkin.urdf import load_urdf

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
Q = np.array([0.3, 0.5, -0.2, -1.1, 0.4, 0.9, -0.3])


def pose_argv(pose: np.ndarray) -> list[str]:
    return ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist())]


def refused(capsys, argv: list[str]) -> str:
    """The one line on stderr of a refused command (exit code 2, from argparse or from the command)."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    return err


def run(capsys, argv: list[str]) -> tuple[int, str, str]:
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.parametrize("robot", ["kinova-gen3", "kuka-iiwa14", str(EXAMPLES / "sawyer.urdf")])
@pytest.mark.parametrize("degrees", [False, True])
def test_a_pose_is_solved_numerically_on_any_arm_and_the_output_says_so(capsys, robot, degrees):
    chain = load_urdf(robot) if robot.endswith(".urdf") else get_robot(robot)
    pose = chain.fk(Q)
    seed = np.degrees(Q + 1e-3) if degrees else Q + 1e-3
    code, out, _ = run(capsys, ["ik", robot, *pose_argv(pose), "--q0", *map(repr, seed.tolist()), "--json"]
                       + (["--deg"] if degrees else []))
    data = json.loads(out)
    assert code == 0 and data["method"] == "numerical" and data["status"] == "found"
    q = np.array(data["solutions"])
    q = np.radians(q) if degrees else q
    assert np.abs(chain.fk(q[0]) - pose).max() < 1e-9 and np.abs(q[0] - Q).max() < 1e-2  # the seed's solution
    assert np.all(chain.within_limits(q))
    assert data["units"]["q"] == ("deg" if degrees else "rad") and data["tolerance"]["position"] == 1e-9
    code, out, _ = run(capsys, ["ik", robot, *pose_argv(pose)])
    assert code == 0 and out.startswith("numerical IK, certified to 1e-09 m and 1e-09 rad")


def test_every_pose_of_a_file_gets_an_entry_and_an_unreachable_one_exits_1(capsys, tmp_path):
    chain = get_robot("kinova-gen3")
    poses = chain.fk(np.array([Q, 0.5 * Q, -Q]))
    far = poses[1].copy()
    far[:3, 3] = [3.0, 0.0, 0.0]  # 3 m away: out of reach
    poses = np.concatenate([poses, far[None]])
    file = tmp_path / "poses.npy"
    np.save(file, poses)
    code, out, _ = run(capsys, ["ik", "kinova-gen3", "--poses", str(file), "--count", "2", "--restarts", "40",
                                "--json"])
    data = json.loads(out)
    assert code == 1
    assert [entry["index"] for entry in data["poses"]] == [0, 1, 2, 3]
    assert [entry["status"] for entry in data["poses"]] == ["found"] * 3 + ["not-found"]
    for entry, pose in zip(data["poses"][:3], poses[:3]):
        q = np.array(entry["solutions"])
        assert len(q) == 2 and np.abs(q[0] - q[1]).max() > 0.1
        assert np.abs(chain.fk(q) - pose).max() < 1e-9
    lost = data["poses"][3]
    assert lost["solutions"] == [] and lost["error"]["position"] > 1.0
    assert np.all(chain.within_limits(np.array(lost["closest"])))
    assert lost["starts"] == 1 and lost["reason"] == "out-of-reach"  # proven before any search
    assert [entry["reason"] for entry in data["poses"][:3]] == [None] * 3
    assert all("reach" not in entry for entry in data["poses"][:3])
    centre, radius = chain.reach_bound
    distance = float(np.linalg.norm(far[:3, 3] - centre))
    assert lost["reach"] == {"measure": "the tool point's distance from (0, 0, 0.28481) m on joint 1's axis",
                             "distance": distance, "min": 0.0, "max": radius, "miss": distance - radius}
    code, out, _ = run(capsys, ["ik", "kinova-gen3", "--poses", str(file), "--restarts", "40"])
    assert code == 1 and out.splitlines()[-1] == (
        f"pose 3: no solution: the pose is out of reach (the tool point's distance from (0, 0, 0.28481) m on joint "
        f"1's axis is {distance:.6g} m, beyond the reach of {radius:.6g} m by {distance - radius:.6g} m); not searched")


def test_a_pose_within_reach_without_a_solution_is_searched_and_its_line_is_well_formed(capsys):
    chain = get_robot("planar-5")
    pose = chain.fk(np.full(5, 0.3))
    pose[2, 3] = 0.1  # out of the arm's plane, yet within the links' reach: only a search can tell
    code, out, _ = run(capsys, ["ik", "planar-5", *pose_argv(pose), "--restarts", "7", "--json"])
    data = json.loads(out)
    assert code == 1 and data["status"] == "not-found" and data["starts"] == 7 and data["reason"] is None
    code, out, _ = run(capsys, ["ik", "planar-5", *pose_argv(pose), "--restarts", "7"])
    line = out.splitlines()[-1]
    values = " ".join(f"{v: .6f}" for v in data["closest"]).lstrip()  # a sign slot per value, as solutions print
    assert code == 1 and line == (f"no solution found in 7 starts; the closest joint values miss by "
                                  f"{data['error']['position']:.3g} m and {data['error']['rotation']:.3g} rad: "
                                  f"{values} [rad]")


def test_a_poses_file_with_an_arm_angle_gives_the_closed_form_of_every_pose(capsys, tmp_path):
    chain = get_robot("kuka-iiwa14")
    poses = chain.fk(np.array([Q, 0.5 * Q]))
    file = tmp_path / "poses.npy"
    np.save(file, poses)
    code, out, _ = run(capsys, ["ik", "kuka-iiwa14", "--poses", str(file), "--psi", "0.3", "--all", "--json"])
    data = json.loads(out)
    assert code == 0 and data["parameter"] == "psi" and len(data["poses"]) == 2
    for entry, pose in zip(data["poses"], poses):
        q = np.array([s["q"] for s in entry["solutions"]])
        assert len(q) + len(entry["missing"]) == 8
        assert np.abs(chain.fk(q) - pose).max() < 1e-9


def test_numerical_on_request_on_an_arm_with_a_closed_form(capsys):
    chain = get_robot("franka-fr3")
    pose = chain.fk(np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.8, 0.5]))
    code, out, _ = run(capsys, ["ik", "franka-fr3", *pose_argv(pose), "--numerical", "--json"])
    data = json.loads(out)
    assert code == 0 and "has a closed form in q7; solved numerically as asked" in data["why"]
    assert np.abs(chain.fk(np.array(data["solutions"][0])) - pose).max() < 1e-9


@pytest.mark.parametrize("extra, fragment", [
    (["--poses", "{file}"], "give --poses or --position and --rotation, not both"),
    (["--numerical", "--psi", "0.1"], "--numerical solves without a redundancy parameter"),
    (["--tolerance", "1e-9", "1e-9", "1e-9"], "--tolerance takes one or two numbers, got 3"),
    (["--tolerance", "0"], "tolerance must be a positive finite number"),
    (["--q0", "0", "0"], "kinova-gen3 has 7 joints, got 2 --q0 values"),
    (["--q0", "0", "0", "0", "nan", "0", "0", "0"], "--q0 values must be finite numbers"),
    (["--count", "0"], "count must be an integer in 1..1000, got 0"),
    (["--restarts", "-3"], "restarts must be an integer in 1..100000, got -3"),
    (["--seed", "-1"], "--seed must be an integer >= 0, got -1"),
])
def test_mistakes_are_one_line_and_exit_2(capsys, tmp_path, extra, fragment):
    file = tmp_path / "poses.npy"
    np.save(file, np.eye(4)[None])
    argv = ["ik", "kinova-gen3", *pose_argv(get_robot("kinova-gen3").fk(Q))]
    assert fragment in refused(capsys, argv + [value.format(file=file) for value in extra])


@pytest.mark.parametrize("content, fragment", [
    (np.zeros((3, 4)), "holds an array of shape (3, 4), expected (N, 4, 4)"),
    (np.zeros((0, 4, 4)), "holds no poses"),
    (np.full((1, 4, 4), np.nan), "pose 0 must be finite"),
    (np.array(["a"] * 16).reshape(1, 4, 4), "holds values of type <U1, expected numbers"),
    (None, "is not a .npy file"),
])
def test_a_bad_poses_file_is_one_line_and_exit_2(capsys, tmp_path, content, fragment):
    file = tmp_path / "poses.npy"
    if content is None:
        file.write_text("not an array")
    else:
        np.save(file, content)
    assert fragment in refused(capsys, ["ik", "kinova-gen3", "--poses", str(file)])


def test_too_many_values_for_one_call_are_refused():
    from redkin.errors import SizeLimitError
    from redkin.numerical import ik

    with pytest.raises(SizeLimitError, match="at most 1e\\+08 are computed in one call"):
        ik(get_robot("kinova-gen3"), np.broadcast_to(np.eye(4), (20_000, 4, 4)), count=1000)


def test_no_target_is_one_line_and_exit_2(capsys):
    assert "the target needs --position X Y Z and --rotation R11 ... R33 (or --poses FILE)" in \
        refused(capsys, ["ik", "kinova-gen3"])


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "franka-fr3", "kinova-gen3"])
def test_numerical_solutions_carry_their_branch_and_parameter(capsys, robot):
    """Each numerical solution's label names the closed form's row that is that solution: the branch's solution
    at the labelled arm angle (or q7) is the numerical one (a nearly S-R-S branch's, one of its solutions there)."""
    import redkin
    from redkin.srs import BRANCHES

    chain = get_robot(robot)
    pose = chain.fk(Q)
    code, out, _ = run(capsys, ["ik", robot, *pose_argv(pose), "--count", "3", "--json"])
    data = json.loads(out)
    parameter = "q7" if robot == "franka-fr3" else "psi"
    assert code == 0 and len(data["branches"]) == len(data[parameter]) == len(data["solutions"]) >= 1
    for q, branch, value in zip(np.array(data["solutions"]), data["branches"], data[parameter]):
        if robot == "kinova-gen3":  # a branch may have two solutions at one arm angle: the label names the branch
            from redkin.srs import nearly_srs
            from redkin.srs.nearly import arm_angle, branch_of
            arm = nearly_srs(chain)
            assert abs(float(arm_angle(arm, q)) - value) < 1e-9
            assert str(BRANCHES[int(branch_of(arm, q))]) == branch
            continue
        closed = redkin.ik(chain, pose, **{parameter: value}, branch=branch)
        assert closed.exists[..., 0].all()
        turns = np.angle(np.exp(1j * (closed.q[..., 0, :] - q)))
        assert np.abs(turns).max() < 1e-6
    code, out, _ = run(capsys, ["ik", robot, *pose_argv(pose)])
    assert code == 0 and f"  branch {data['branches'][0]}, {parameter} " in out


def test_a_general_chain_has_no_branch_labels(capsys):
    chain = load_urdf(str(EXAMPLES / "sawyer.urdf"))
    code, out, _ = run(capsys, ["ik", str(EXAMPLES / "sawyer.urdf"), *pose_argv(chain.fk(Q)), "--json"])
    assert code == 0 and "branches" not in json.loads(out)
