"""What ``redkin fk`` prints can be pasted into the commands that take a pose (issue 43, item 1).

The laws: ``fk``'s two pasteable lines hold every number exactly, and pasted into ``ik`` they give the configuration
back; its ``--quat`` line is the same target as its ``--rotation`` line; a matrix off a rotation by rounding (``fk``'s
6-decimal matrix, or a perturbation of about 1e-6) is read as the nearest rotation with one note on stderr, while
one 1e-2 off, a reflection, NaN, a wrong count or a quaternion of the wrong norm is refused with exit code 2 and one
line.  Every command that takes ``--rotation`` takes ``--quat``.
"""

from __future__ import annotations

import argparse
import json

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from redkin.cli.main import _build_parser
from redkin.models import get_robot
from redkin.so3 import axis_angle_to_matrix, matrix_to_quaternion, quaternion_to_matrix
from redkin.srs import arm_angle_of
from tests.support.cli import run

#: Arms with a closed form whose parameter the test can read off a configuration: the arm angle of an S-R-S or
#: offset-elbow arm, q7 of a Franka-class arm.
ARMS = {"pa10-7c": "--psi", "kuka-iiwa14": "--psi", "barrett-wam": "--psi", "franka-panda": "--q7"}
#: The tolerance the docs state for a --rotation read as the nearest rotation (docs/chains.md).
INPUT_TOLERANCE = 1e-3

#: ``capsys`` is read (and so emptied) after each command: sharing it between examples is safe.
CAPSYS = [HealthCheck.function_scoped_fixture]

fractions = st.lists(st.floats(0.05, 0.95), min_size=7, max_size=7)


def configuration(robot: str, fraction: list[float]) -> np.ndarray:
    """A configuration inside the arm's limits, each joint at ``fraction`` of its range (of one turn where the joint
    has no limits)."""
    chain = get_robot(robot)
    lower = np.where(np.isfinite(chain.lower), chain.lower, -np.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper, np.pi)
    return lower + np.array(fraction) * (upper - lower)


def fk_text(capsys, robot: str, q: np.ndarray) -> list[str]:
    """The lines of ``redkin fk ROBOT Q`` (every joint value written exactly)."""
    code, out, err = run(capsys, ["fk", robot, *map(repr, q.tolist())])
    assert code == 0 and err == ""
    return out.splitlines()


def parameter(robot: str, q: np.ndarray) -> str:
    """The value of the arm's redundancy parameter at ``q``, exactly."""
    value = q[6] if ARMS[robot] == "--q7" else arm_angle_of(get_robot(robot), q).psi
    return repr(float(value))


def ik_all(capsys, robot: str, pasted: list[str], value: str) -> tuple[np.ndarray, str]:
    """The solutions of every branch of ``redkin ik ROBOT PASTED --psi/--q7 VALUE --all --json``, and stderr."""
    code, out, err = run(capsys, ["ik", robot, *pasted, ARMS[robot], value, "--all", "--json"])
    assert code == 0, err
    return np.array([s["q"] for s in json.loads(out)["solutions"]]), err


def angle_gap(a: np.ndarray, b: np.ndarray) -> float:
    """The largest difference between joint angles, modulo a whole turn (a solution at pi may print as -pi)."""
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max()) if np.size(a) else 0.0


def perturbed(rotation: np.ndarray, stretch: list[float]) -> np.ndarray:
    """``R (I + S)`` with ``S`` symmetric of eigenvalues ``stretch`` along the axes of ``R``'s frame: a matrix off
    orthonormal by about ``2 max |stretch|``, whose nearest rotation is ``R`` itself (the polar factor)."""
    return rotation @ (np.eye(3) + np.diag(stretch))


def argv_of(pose: np.ndarray, rotation: np.ndarray | None = None) -> list[str]:
    rotation = pose[:3, :3] if rotation is None else rotation
    return ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, rotation.ravel().tolist())]


# ------------------------------------------------------------------------------------------- fk's output pasted


@pytest.mark.parametrize("robot", ARMS)
@settings(max_examples=12, deadline=None, suppress_health_check=CAPSYS)
@given(fraction=fractions)
def test_fk_lines_pasted_into_ik_give_the_configuration_back(capsys, robot, fraction):
    q = configuration(robot, fraction)
    assume(min(abs(q[1]), abs(q[3]), abs(q[5])) > 0.05)  # away from the shoulder, elbow and wrist singularities
    pose = get_robot(robot).fk(q)
    header, *rows, by_matrix, by_quaternion = fk_text(capsys, robot, q)
    assert "w x y z" in header and len(rows) == 4
    words = by_matrix.split()
    assert words[0] == "--position" and words[4] == "--rotation" and len(words) == 14
    numbers = np.array([float(w) for w in words[1:4] + words[5:]])
    assert np.array_equal(numbers[:3], pose[:3, 3]) and np.array_equal(numbers[3:], pose[:3, :3].ravel())  # exact
    assert by_quaternion.split()[:4] == words[:4] and by_quaternion.split()[4] == "--quat"

    value = parameter(robot, q)
    solutions, err = ik_all(capsys, robot, by_matrix.split(), value)
    assert err == ""
    assert np.abs(get_robot(robot).fk(solutions) - pose).max() < 1e-9
    assert np.abs(solutions - q).max(axis=1).min() < 1e-9  # the configuration is one of them
    from_quaternion, err = ik_all(capsys, robot, by_quaternion.split(), value)
    assert err == "" and from_quaternion.shape == solutions.shape
    assert angle_gap(from_quaternion, solutions) < 1e-9


@pytest.mark.parametrize("robot", ["pa10-7c", "franka-panda"])
@settings(max_examples=12, deadline=None, suppress_health_check=CAPSYS)
@given(fraction=fractions)
def test_fks_rounded_matrix_pasted_is_read_as_the_nearest_rotation(capsys, robot, fraction):
    """The 4x4 matrix that ``fk`` prints for reading (6 decimals, what it printed before) is accepted too: as the
    nearest rotation, with one note where it is more than 1e-6 off."""
    q = configuration(robot, fraction)
    pose = get_robot(robot).fk(q)
    rows = np.array([[float(v) for v in row.split()] for row in fk_text(capsys, robot, q)[1:5]])
    assert np.abs(rows - pose).max() <= 5e-7
    code, out, err = run(capsys, ["arm-angles", robot, *argv_of(rows), "--json"])
    assert code == 0 and json.loads(out)
    deviation = np.abs(rows[:3, :3] @ rows[:3, :3].T - np.eye(3)).max()
    noted = deviation > 1e-6 or abs(np.linalg.det(rows[:3, :3]) - 1.0) > 1e-6
    lines = err.splitlines()
    assert len(lines) == int(noted) and all(line.startswith("redkin: note: --rotation is ") for line in lines)
    solutions, _ = ik_all(capsys, robot, argv_of(rows), parameter(robot, q))
    assert len(solutions) and np.abs(get_robot(robot).fk(solutions) - pose).max() < 1e-5


def test_fk_json_carries_the_quaternion_of_its_text(capsys):
    q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.8, 0.5])
    text = fk_text(capsys, "franka-panda", q)[-1].split()
    code, out, _ = run(capsys, ["fk", "franka-panda", *map(repr, q.tolist()), "--json"])
    data = json.loads(out)
    assert code == 0 and data["units"]["quaternion"].startswith("w x y z")
    assert data["quaternion"] == [float(v) for v in text[5:]]
    np.testing.assert_allclose(quaternion_to_matrix(data["quaternion"]), data["rotation"], atol=1e-15)


# ----------------------------------------------------------------------------------------- near a rotation, or far


@settings(max_examples=30, deadline=None, suppress_health_check=CAPSYS)
@given(fraction=fractions, stretch=st.lists(st.floats(-5e-4, 5e-4), min_size=3, max_size=3))
# found by the explore profile: orthonormal within 1e-3, det 0.9988 was refused as improper
@example(fraction=[0.5] * 7, stretch=[-0.0005, -0.00047971119178984314, -0.00023513230751535545])
def test_a_matrix_a_little_off_is_projected_onto_the_rotation_with_a_note(capsys, fraction, stretch):
    assume(max(map(abs, stretch)) > 1e-6)
    q = configuration("pa10-7c", fraction)
    pose = get_robot("pa10-7c").fk(q)
    value = parameter("pa10-7c", q)
    exact, _ = ik_all(capsys, "pa10-7c", argv_of(pose), value)
    near, err = ik_all(capsys, "pa10-7c", argv_of(pose, perturbed(pose[:3, :3], stretch)), value)
    [line] = err.splitlines()
    assert line.startswith("redkin: note: --rotation is ") and "using the nearest rotation" in line
    assert near.shape == exact.shape and angle_gap(near, exact) < 1e-9


@settings(max_examples=20, deadline=None, suppress_health_check=CAPSYS)
@given(fraction=fractions, axis=st.integers(0, 2), size=st.floats(2 * INPUT_TOLERANCE, 0.5))
def test_a_matrix_far_off_is_refused_with_one_line(capsys, fraction, axis, size):
    pose = get_robot("pa10-7c").fk(configuration("pa10-7c", fraction))
    stretch = [0.0, 0.0, 0.0]
    stretch[axis] = size
    for command in ("ik", "arm-angles"):
        code, out, err = run(capsys, [command, "pa10-7c", *argv_of(pose, perturbed(pose[:3, :3], stretch))])
        assert (code, out) == (2, "") and len(err.splitlines()) == 1
        assert err.startswith("redkin: error: --rotation must be orthonormal (R R^T = I within 0.001)")


def test_explore_refuses_a_matrix_far_off_before_writing(capsys, tmp_path):
    pose = get_robot("pa10-7c").fk(np.full(7, 0.4))
    page = tmp_path / "page.html"
    code, out, err = run(capsys, ["explore", "pa10-7c", *argv_of(pose, perturbed(pose[:3, :3], [0.01, 0, 0])),
                                  "--out", str(page)])
    assert (code, out) == (2, "") and len(err.splitlines()) == 1 and not page.exists()
    assert err.startswith("redkin: error: --rotation must be orthonormal (R R^T = I within 0.001)")


@pytest.mark.parametrize("option, values, fragment", [
    ("--rotation", ["nan", "0", "0", "0", "1", "0", "0", "0", "1"], "--rotation must be finite"),
    ("--rotation", ["-1", "0", "0", "0", "1", "0", "0", "0", "1"], "--rotation must be a proper rotation (det = +1)"),
    ("--rotation", ["1", "0", "0", "0", "1", "0", "0", "0"], "argument --rotation: expected 9 arguments"),
    ("--rotation", ["1e308", "0", "0", "0", "1", "0", "0", "0", "1"], "an entry of magnitude 1e+308"),
    ("--quat", ["inf", "0", "0", "0"], "--quat must be finite"),
    ("--quat", ["1", "0", "0"], "argument --quat: expected 4 arguments"),
    ("--quat", ["1.01", "0", "0", "0"], "--quat must have norm 1 (within 0.001), got norm 1.01"),
    ("--quat", ["0", "0", "0", "0"], "--quat must have norm 1 (within 0.001), got norm 0"),
])
@pytest.mark.parametrize("command", ["ik", "arm-angles"])
def test_bad_orientations_are_refused_with_one_line(capsys, command, option, values, fragment):
    code, out, err = run(capsys, [command, "pa10-7c", "--position", "0.5", "0", "0.5", option, *values,
                                  "--branch", "+++"])
    assert (code, out) == (2, "") and len(err.splitlines()) == 1 and fragment in err, err


def test_rotation_and_quat_together_are_refused(capsys):
    code, _, err = run(capsys, ["ik", "pa10-7c", "--position", "0.5", "0", "0.5", "--rotation", *"100010001",
                                "--quat", "1", "0", "0", "0"])
    assert code == 2 and "argument --quat: not allowed with argument --rotation" in err


@settings(max_examples=20, deadline=None, suppress_health_check=CAPSYS)
@given(fraction=fractions, scale=st.floats(1 - INPUT_TOLERANCE / 2, 1 + INPUT_TOLERANCE / 2))
def test_a_quaternion_near_unit_norm_is_normalised(capsys, fraction, scale):
    q = configuration("pa10-7c", fraction)
    pose = get_robot("pa10-7c").fk(q)
    quaternion = matrix_to_quaternion(pose[:3, :3]) * scale
    exact, _ = ik_all(capsys, "pa10-7c", argv_of(pose), parameter("pa10-7c", q))
    near, err = ik_all(capsys, "pa10-7c", ["--position", *map(repr, pose[:3, 3].tolist()), "--quat",
                                           *map(repr, quaternion.tolist())], parameter("pa10-7c", q))
    assert near.shape == exact.shape and angle_gap(near, exact) < 1e-9
    expected = ["redkin: note: --quat has norm"] if abs(np.linalg.norm(quaternion) - 1) > 1e-6 else []
    assert [line[:len("redkin: note: --quat has norm")] for line in err.splitlines()] == expected


# ---------------------------------------------------------------------------------------- every command's options


def _commands(parser: argparse.ArgumentParser, prefix: str = "") -> dict[str, argparse.ArgumentParser]:
    """Every command's parser by name (``torso-arm ik`` for a subcommand's own commands)."""
    found = {prefix.strip(): parser} if prefix else {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                found.update(_commands(sub, f"{prefix}{name} "))
    return found


def test_every_command_that_takes_rotation_takes_quat_exclusive_of_it():
    taking = []
    for name, command in _commands(_build_parser()).items():
        options = {option: action for action in command._actions for option in action.option_strings}
        if "--rotation" not in options:
            continue
        taking.append(name)
        assert "--quat" in options and "w x y z" in options["--quat"].help, name
        groups = [g for g in command._mutually_exclusive_groups if options["--rotation"] in g._group_actions]
        assert len(groups) == 1 and options["--quat"] in groups[0]._group_actions, name
    assert {"ik", "arm-angles", "explore", "torso-arm ik"} <= set(taking)


@pytest.mark.parametrize("angle", [0.0, 0.7, np.pi])
def test_torso_arm_ik_reads_quat_as_rotation(capsys, angle):
    rotation = axis_angle_to_matrix([0.2, -0.5, 0.8], angle)
    common = ["torso-arm", "ik", "--position", "0.25", "-0.3", "-0.15", "--shoulder", "0.2", "--elbow", "0.4",
              "--json"]
    code, by_matrix, _ = run(capsys, [*common, "--rotation", *map(repr, rotation.ravel().tolist())])
    assert code == 0
    code, by_quaternion, _ = run(capsys, [*common, "--quat", *map(repr, matrix_to_quaternion(rotation).tolist())])
    assert code == 0
    one, other = json.loads(by_matrix), json.loads(by_quaternion)
    assert one["status"] == other["status"] and len(one["solutions"]) == len(other["solutions"])
    for a, b in zip(one["solutions"], other["solutions"]):
        assert a["branch"] == b["branch"] and np.abs(np.subtract(a["q"], b["q"])).max() < 1e-9


def test_the_last_two_lines_of_fk_paste_even_outside_the_limits(capsys):
    """The note on joint values outside the limits comes before the pose, so fk's last two lines are always the
    ones to paste (the README says so)."""
    code, out, _ = run(capsys, ["fk", "franka-fr3", "0", "30", "0", "60", "0", "45", "0", "--deg"])
    lines = out.splitlines()
    assert code == 0 and lines[0].startswith("note: these joint values are outside")
    assert lines[-2].startswith("--position") and "--rotation" in lines[-2]
    assert lines[-1].startswith("--position") and "--quat" in lines[-1]
