"""``redkin ik`` and ``redkin arm-angles``: JSON shape, paper numbers, one-line errors with exit code 2."""

import json

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import pa10_7c
from redkin.reproduce import printed

POSE = ["--position", "0.65", "0", "0.5", "--rotation", "-1", "0", "0", "0", "1", "0", "0", "0", "-1"]


def run_json(capsys, argv):
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_ik_all_branches_json_round_trips(capsys):
    data = run_json(capsys, ["ik", "pa10-7c", *POSE, "--psi", "0.3", "--all"])
    assert [s["branch"] for s in data["solutions"]] == ["+++", "++-", "+-+", "+--", "-++", "-+-", "--+", "---"]
    chain = pa10_7c()
    for s in data["solutions"]:
        pose = chain.fk(np.array(s["q"]))
        assert np.allclose(pose[:3, 3], [0.65, 0, 0.5], atol=1e-9)


def test_ik_degrees_single_branch(capsys):
    data = run_json(capsys, ["ik", "pa10-7c", *POSE, "--psi", "0", "--deg", "--branch", "+++"])
    assert np.allclose(data["solutions"][0]["q"], printed.SECTION_6_1_THETA_AT_ZERO, atol=5e-4)


def test_arm_angles_json_keys_and_paper_numbers(capsys):
    data = run_json(capsys, ["arm-angles", "pa10-7c", *POSE, "--deg"])
    assert set(data) >= {"fixed", "per_joint", "feasible", "singular", "optimal", "branches"}
    assert data["fixed"]["4"] == pytest.approx(printed.SECTION_6_1_THETA_AT_ZERO[3], abs=5e-4)
    bound, sixth = printed.SECTION_6_1_PSI_BOUND, printed.SECTION_6_1_JOINT_BOUNDS[6]
    assert np.allclose(data["feasible"], [[-bound, bound]], atol=5e-4)
    assert np.allclose(data["per_joint"]["6"], [[-sixth, sixth]], atol=5e-4)
    assert set(data["singular"]) >= {"shoulder", "wrist"}
    assert set(data["optimal"]["overall"]) == {"unclamped", "feasible"}


def test_arm_angles_empty_set_gives_null_feasible_optimum(capsys):
    data = run_json(capsys, ["arm-angles", "pa10-7c", *POSE, "--branch", "+-+"])
    assert data["feasible"] == [] and data["optimal"]["overall"]["feasible"] is None


def test_arm_angles_text_output(capsys):
    assert main(["arm-angles", "pa10-7c", *POSE, "--target", "0", "90", "0", "0", "0", "90", "0", "--deg",
                 "--weights", "1", "1"]) == 0
    assert "Psi (feasible)" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["ik", "pa10-7c", *POSE[:4], "--rotation", *["1"] * 9, "--psi", "0"], "orthonormal"),
        (["ik", "pa10-7c", *POSE, "--psi", "0", "--branch", "+x+"], "branch"),
        (["ik", "planar-5", *POSE, "--psi", "0"], "7 joints"),
        (["arm-angles", "pa10-7c", *POSE, "--target", "0", "0", "0", "0", "0", "0", "0", "--weights", "0", "0"],
         "weights"),
        (["ik", "pa10-7c", *POSE[:3], "--psi", "0"], "position"),
    ],
)
def test_user_mistakes_exit_2_with_one_line(capsys, argv, message):
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse errors
        code = exit_.code
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err



@pytest.mark.parametrize("written", ["separate", "equals"])
@pytest.mark.parametrize("command", ["ik", "arm-angles"])
def test_every_branch_string_is_read_as_a_branch(capsys, command, written):
    """``-++``, ``--+`` and ``---`` start with a dash, as options do: each of the eight is still a branch."""
    from redkin.srs import BRANCHES, ik, pose_from

    chain = pa10_7c()
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    for branch in BRANCHES:
        option = [f"--branch={branch}"] if written == "equals" else ["--branch", str(branch)]
        if command == "ik":
            data = run_json(capsys, ["ik", "pa10-7c", *POSE, "--psi", "0.2", *option])
            assert data["solutions"][0]["branch"] == str(branch)
            assert np.allclose(data["solutions"][0]["q"], ik(chain, pose, 0.2, branch), atol=1e-12)
        else:
            assert run_json(capsys, ["arm-angles", "pa10-7c", *POSE, *option])["branch"] == str(branch)


def test_ik_and_arm_angles_on_a_urdf_in_the_makers_joint_values(capsys):
    from pathlib import Path

    from redkin.models import get_robot

    path = str(Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "iiwa14.urdf")
    arm = get_robot(path)
    pose = arm.fk(np.array([0.3, 0.5, -0.2, -1.1, 0.4, 0.9, 0.1]))
    argv = ["--position", *map(str, pose[:3, 3]), "--rotation", *map(str, pose[:3, :3].ravel())]
    data = run_json(capsys, ["ik", path, *argv, "--psi", "0.3", "--all"])
    q = np.array([s["q"] for s in data["solutions"]])
    assert np.abs(arm.fk(q) - pose).max() < 1e-9
    for solution in data["solutions"]:  # each branch names the signs of KUKA's own q2, q4, q6
        assert "".join("+" if v >= 0 else "-" for v in np.array(solution["q"])[[1, 3, 5]]) == solution["branch"]
    assert run_json(capsys, ["arm-angles", path, *argv, "--branch", "+-+"])["feasible"]


def test_ik_refuses_an_arm_without_a_closed_form_and_the_wrong_parameter_in_one_line(capsys):
    from pathlib import Path

    examples = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
    assert main(["ik", str(examples / "sawyer.urdf"), *POSE, "--psi", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "has no closed-form IK" in err[0] and "is not S-R-S" in err[0]
    assert main(["ik", str(examples / "panda.urdf"), *POSE, "--psi", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "redundancy parameter is q7 (--q7), not psi" in err[0]


#: A pose of the PA10 whose feasible arm angles on branch -++ form one arc through +-pi (joint 5 limits it).
WRAPPING_Q = [1.311, -0.723, 0.12, 1.082, -1.375, 0.444, 1.477]


def _wrapping_pose_argv() -> list[str]:
    pose = pa10_7c().fk(np.array(WRAPPING_Q))
    return ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist()),
            "--branch", "-++"]


@pytest.mark.parametrize("degrees", [True, False])
def test_an_arc_through_pi_prints_as_one_arc_that_says_it_wraps(capsys, degrees):
    """[117.16, -141.65] deg read alone looks empty or reversed: the line says the arc passes +-180 (+-pi)."""
    unit = ["--deg"] if degrees else []
    assert main(["arm-angles", "pa10-7c", *_wrapping_pose_argv(), *unit]) == 0
    lines = capsys.readouterr().out.splitlines()
    feasible = next(line for line in lines if line.startswith("Psi (feasible):"))
    seam = "180" if degrees else "pi"
    assert feasible.endswith(f"(through ±{seam})") and " U " not in feasible, feasible
    start, end = (float(v) for v in feasible.split("[")[1].split("]")[0].split(","))
    assert start > end  # one arc, read counter-clockwise through the seam
    ordinary = next(line for line in lines if line.startswith("Psi_2:"))
    assert "through" not in ordinary  # the full circle [-180, 180] does not wrap


def test_an_arc_through_pi_in_json_keeps_its_pair_and_adds_a_wraps_flag(capsys):
    from redkin.srs import feasible_arm_angles

    data = run_json(capsys, ["arm-angles", "pa10-7c", *_wrapping_pose_argv()])
    chain = pa10_7c()
    exact = feasible_arm_angles(chain, chain.fk(np.array(WRAPPING_Q)), "-++")
    assert np.allclose(data["feasible"], exact.feasible.arcs) and data["feasible_wraps"] == [True]
    assert set(data["per_joint_wraps"]) == set(data["per_joint"])
    for joint, arcs in data["per_joint"].items():
        assert data["per_joint_wraps"][joint] == [start > end for start, end in arcs]
    assert data["per_joint_wraps"]["5"] == [True] and data["per_joint_wraps"]["2"] == [False]
    assert "wraps" in data["arcs"]
    ordinary = run_json(capsys, ["arm-angles", "pa10-7c", *POSE])
    assert ordinary["feasible_wraps"] == [False]


def test_printed_numbers_have_no_negative_zero(capsys):
    """The WAM's Jacobian has entries of -1e-17: they print as 0.000000, never -0.000000."""
    assert main(["jacobian", "barrett-wam", "30", "20", "50", "70", "40", "100", "0", "--deg"]) == 0
    out = capsys.readouterr().out
    assert "-0.000000" not in out and " 0.000000" in out
    assert main(["ik", "pa10-7c", *POSE, "--psi", "0", "--all"]) == 0
    assert "-0.000000" not in capsys.readouterr().out


def test_weights_and_target_help_say_what_they_do(capsys):
    with pytest.raises(SystemExit):
        main(["arm-angles", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "shoulder joints (RS) and the wrist joints (RW)" in text and "default 0.5 0.5" in text
