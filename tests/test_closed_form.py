"""The front door ``redkin.ik``: the chain's class picks the solver and its parameter, the other parameter is
refused by name, and the answers are the class solvers' own."""

from pathlib import Path

import numpy as np
import pytest

from redkin import franka, get_robot, ik, srs
from redkin.closed_form import redundancy_parameter
from redkin.errors import NotArmAngleClassError


def test_each_class_gets_its_own_parameter_and_solver():
    fr3, iiwa = get_robot("franka-fr3"), get_robot("kuka-iiwa14")
    q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.8, 0.5])
    pose = fr3.fk(q)
    result = ik(fr3, pose, q7=q[6])
    expected = franka.ik(fr3, pose, q[6])
    assert result.parameter == "q7" and redundancy_parameter(fr3) == "q7"
    np.testing.assert_array_equal(result.q, expected.q)
    np.testing.assert_array_equal(result.within_limits, expected.within_limits)
    pose = iiwa.fk(np.array([0.3, 0.5, 0.2, -1.2, 0.4, 0.8, 0.5]))
    result = ik(iiwa, pose, psi=0.7, branch="+-+")
    assert result.parameter == "psi" and result.branches == (srs.parse_branch("+-+"),)
    np.testing.assert_array_equal(result.q[0], srs.ik(iiwa, pose, 0.7, "+-+"))
    assert result.exists.all()


def test_an_srs_pose_out_of_reach_has_no_solution_rather_than_an_error():
    pa10 = get_robot("pa10-7c")
    poses = pa10.fk(np.array([[0.1, 0.5, 0.0, 1.0, 0.0, 0.3, 0.0]] * 3))
    poses[1, :3, 3] = [3.0, 0.0, 0.3]
    result = ik(pa10, poses, psi=np.array([0.0, 0.1, 0.2]))
    assert result.exists.tolist() == [[True] * 8, [False] * 8, [True] * 8]
    assert not result.q[1].any() and not result.within_limits[1].any()
    np.testing.assert_array_equal(result.q[2], srs.ik_all_branches(pa10, poses[2], 0.2))
    assert np.abs(pa10.fk(result.q[result.exists]) - poses[[0, 2]].repeat(8, axis=0)).max() < 1e-9


@pytest.mark.parametrize("robot, arguments, fragment", [
    ("franka-fr3", {"psi": 0.1}, "takes q7 as its redundancy parameter; got psi"),
    ("kuka-iiwa14", {"q7": 0.1}, "takes psi as its redundancy parameter; got q7"),
    ("kuka-iiwa14", {"psi": 0.1, "q0": np.zeros(7)}, "q0: keywords of the numerical solver"),
    ("kinova-gen3", {"branch": "+++"}, "branch applies to the closed forms"),
    ("franka-fr3", {"psi": 0.1, "q7": 0.1}, "got psi and q7"),
])
def test_the_wrong_parameter_is_refused_by_name(robot, arguments, fragment):
    with pytest.raises(ValueError, match=fragment.replace("(", r"\(").replace(")", r"\)")):
        ik(get_robot(robot), np.eye(4), **arguments)


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "kinova-gen3"])
def test_without_a_parameter_the_front_door_solves_numerically_and_says_so(robot):
    chain = get_robot(robot)
    q = np.array([0.3, 0.5, -0.2, -1.1, 0.4, 0.9, -0.3])
    result = ik(chain, chain.fk(q), q0=q + 1e-3)
    assert result.method == "numerical" and result.found[0]
    assert np.abs(chain.fk(result.q[0]) - chain.fk(q)).max() < 1e-9


def test_a_chain_without_a_closed_form_says_why():
    sawyer = get_robot(str(Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "sawyer.urdf"))
    with pytest.raises(NotArmAngleClassError, match=r"has no closed-form IK: .*axes 1 and 3 miss each other by "
                                                    r"0.1925 m"):
        ik(sawyer, np.eye(4), psi=0.0)


def test_a_nearly_srs_arm_takes_the_arm_angle_at_the_front_door():
    gen3 = get_robot("kinova-gen3")
    q = np.array([0.3, 0.5, -0.2, -1.1, 0.4, 0.9, -0.3])
    from redkin.srs.nearly import arm_angle, nearly_srs

    result = ik(gen3, gen3.fk(q), psi=arm_angle(nearly_srs(gen3), q))
    assert result.parameter == "psi" and result.exists.sum() >= 1
    assert np.abs(gen3.fk(result.q[result.exists]) - gen3.fk(q)).max() < 1e-9
    assert np.abs(result.q[result.exists] - q).max(axis=-1).min() < 1e-8  # q itself among them
