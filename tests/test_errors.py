"""redkin.errors: each kind of input error is its own class, and every one is still a ValueError."""

import numpy as np
import pytest

import redkin
from redkin._validation import check_count, check_pose
from redkin.errors import (
    MapStoreError,
    NotArmAngleClassError,
    RedkinError,
    RobotDescriptionError,
    SizeLimitError,
    UnreachablePoseError,
)
from redkin.models import franka_panda, get_robot, pa10_7c
from redkin.srs import feasible_pieces, ik, ik_all_branches, srs_geometry


@pytest.mark.parametrize("kind", [MapStoreError, NotArmAngleClassError, RobotDescriptionError, SizeLimitError,
                                  UnreachablePoseError])
def test_every_error_is_a_redkin_error_and_a_value_error(kind):
    assert issubclass(kind, RedkinError) and issubclass(kind, ValueError)
    assert getattr(redkin, kind.__name__) is kind


def test_every_refusal_in_the_source_is_a_redkin_error():
    """docs/errors.md: everything redkin refuses raises a subclass of RedkinError, so that ``except
    redkin.RedkinError`` catches it (a sweep found an unknown robot, a branch label, the velocity controllers and
    most of the virtual arms raising a plain ValueError).  No module raises ValueError itself."""
    import ast
    from pathlib import Path

    source = Path(redkin.__file__).parent
    plain = []
    for file in sorted(source.rglob("*.py")):
        for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) and getattr(
                    node.exc.func, "id", None) == "ValueError":
                plain.append(f"{file.relative_to(source)}:{node.lineno}")
    assert plain == []
    with pytest.raises(RedkinError, match="unknown robot"):
        redkin.arm("no-such-robot")
    with pytest.raises(RedkinError):
        redkin.srs.parse_branch("++")


def test_unreachable_poses_are_caught_by_type_with_their_index():
    chain = pa10_7c()
    poses = chain.fk(np.random.default_rng(2).uniform(-1, 1, (2, 3, 7)))
    poses[1, 2, :3, 3] = [2.5, 0.0, 0.3]
    poses[0, 1, :3, 3] = [0.0, 3.0, 0.3]
    for call in (lambda: ik_all_branches(chain, poses, 0.1), lambda: ik(chain, poses, 0.1, "+-+"),
                 lambda: feasible_pieces(chain, poses, "---")):
        with pytest.raises(UnreachablePoseError) as raised:
            call()
        assert raised.value.index == (0, 1) and raised.value.count == 2
    with pytest.raises(UnreachablePoseError) as raised:
        ik(chain, poses[1, 2], 0.0)
    assert raised.value.index == () and raised.value.count == 1


def test_a_malformed_pose_is_not_an_unreachable_one():
    chain = pa10_7c()
    pose = chain.fk(np.zeros(7))
    pose[0, 0] = np.nan
    with pytest.raises(RedkinError) as raised:
        ik(chain, pose, 0.0)
    assert not isinstance(raised.value, UnreachablePoseError)
    with pytest.raises(RedkinError):
        check_pose(pose)


def test_arms_without_arm_angle_ik_are_caught_by_type_with_the_distance():
    with pytest.raises(NotArmAngleClassError) as raised:
        srs_geometry(franka_panda())
    assert raised.value.chain_name == franka_panda().name
    assert raised.value.distance is not None and raised.value.distance > 0.01  # the Panda's offsets, in metres
    assert f"{raised.value.distance:.3g}" in str(raised.value)


def test_robot_files_name_the_file_and_the_key(tmp_path):
    path = tmp_path / "arm.toml"
    path.write_text('name = "x"\n[[joint]]\na = 0.1\nalpha = 0.0\nd = "long"\n')
    with pytest.raises(RobotDescriptionError) as raised:
        get_robot(path)
    assert raised.value.path == str(path) and raised.value.key == "joint 1 d"
    with pytest.raises(RobotDescriptionError) as raised:
        get_robot(tmp_path / "missing.toml")
    assert raised.value.path == str(tmp_path / "missing.toml")


def test_a_urdf_joint_redkin_cannot_model_is_named(tmp_path):
    path = tmp_path / "slider.urdf"
    path.write_text(
        '<robot name="slider"><link name="a"/><link name="b"/>'
        '<joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>'
        '<limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    with pytest.raises(RobotDescriptionError) as raised:
        get_robot(path)
    assert raised.value.path == str(path) and raised.value.key == "slide"


def test_sizes_beyond_their_limit_are_caught_by_type():
    with pytest.raises(SizeLimitError) as raised:
        check_count(5000, "resolution", 1, 1000)
    assert (raised.value.name, raised.value.value, raised.value.maximum) == ("resolution", 5000, 1000)
    for bad in (0, 2.5, float("nan"), "ten"):
        with pytest.raises(RedkinError) as raised:
            check_count(bad, "resolution", 1, 1000)
        assert not isinstance(raised.value, SizeLimitError)


def test_a_tracking_run_longer_than_the_step_limit_is_a_size_error():
    from redkin.models import barrett_wam
    from redkin.velocity import Pseudoinverse
    from redkin.velocity.tracking import MAX_STEPS, simulate

    chain = barrett_wam()
    with pytest.raises(SizeLimitError) as raised:
        simulate(chain, np.full(7, 0.3), np.zeros(6), duration=1.0, method=Pseudoinverse(), dt=0.5 / MAX_STEPS)
    assert raised.value.maximum == MAX_STEPS and raised.value.value > MAX_STEPS
