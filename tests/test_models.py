"""Models of real arms against their makers' URDFs: poses, joint senses and limits.

The reference below is the URDF definition itself, written out here without redkin: each joint's
``<origin>`` (``xyz``, then ``rpy`` as ``Rz(yaw) Ry(pitch) Rx(roll)``) followed by a Rodrigues turn by
``q`` about its ``<axis>``.  The joint data are copied from each maker's description file (named per
model); where a model departs from the file on purpose, the entry says so.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from redkin.models import (
    MODELS,
    barrett_wam7,
    franka_panda,
    kinova_gen3,
    kuka_iiwa7,
    kuka_iiwa14,
    kuka_iiwa14_table1,
    srs_chain,
    ufactory_xarm7,
)
from redkin.srs import ik_all_branches
from tests.support.urdf_reference import axis_angle

PI, HALF = np.pi, np.pi / 2
X, Y, Z, MINUS_Y = (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, -1, 0)
INF = np.inf


def _step(xyz, rotation) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, xyz
    return out


def urdf_pose(joints: list[tuple], q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The tip pose for joint values ``q``, and the unit axis of each moving joint in the base frame.

    ``joints``: ``(xyz, rpy, axis)`` from the base link down; ``axis`` None for a fixed joint.
    """
    pose, axes, k = np.eye(4), [], 0
    for xyz, (roll, pitch, yaw), axis in joints:
        pose = pose @ _step(xyz, axis_angle(Z, yaw) @ axis_angle(Y, pitch) @ axis_angle(X, roll))
        if axis is not None:
            axes.append(pose[:3, :3] @ np.asarray(axis, float) / np.linalg.norm(axis))
            pose, k = pose @ _step((0, 0, 0), axis_angle(axis, q[k])), k + 1
    return pose, np.array(axes)


def right_angles(joints: list[tuple]) -> list[tuple]:
    """The joints with each rpy angle within 1e-4 of a multiple of pi/2 (1.5708, 3.1416, 2.7629e-18) read as it."""

    def snap(value: float) -> float:
        nearest = float(np.round(value / HALF) * HALF)
        return nearest if abs(value - nearest) < 1e-4 else value

    return [(xyz, tuple(snap(v) for v in rpy), axis) for xyz, rpy, axis in joints]


#: Each maker's URDF: the factory, the joints (xyz, rpy, axis) from the base link to the tool link, and the
#: joint limits (continuous joints: -inf, inf).
MAKERS = {
    # kroshu/kuka_robot_descriptions kuka_lbr_iiwa_support/urdf/lbr_iiwa14_r820_macro.xacro, base_link -> link_7;
    # then the flange at the data sheet's 0.126 m past the wrist (the file's flange link sits 0.071 past link_7).
    "kuka-iiwa14": (kuka_iiwa14, [
        ((0, 0, 0.1575), (0, 0, 0), Z), ((0, 0, 0.2025), (0, 0, 0), Y), ((0, 0, 0.2045), (0, 0, 0), Z),
        ((0, 0, 0.2155), (0, 0, 0), MINUS_Y), ((0, 0, 0.1845), (0, 0, 0), Z), ((0, 0, 0.2155), (0, 0, 0), Y),
        ((0, 0, 0.081), (0, 0, 0), Z), ((0, 0, 0.045), (0, 0, 0), None)],
        np.radians([170, 120, 170, 120, 170, 120, 175])),
    # kroshu/kuka_robot_descriptions kuka_lbr_iiwa_support/urdf/lbriiwa7_macro.xacro (its limits are 90 % of the
    # data sheet's, which the model keeps: the limits here are the data sheet's), flange as for the iiwa 14.
    "kuka-iiwa7": (kuka_iiwa7, [
        ((0, 0, 0.1375), (0, 0, 0), Z), ((0, 0, 0.2025), (0, 0, 0), Y), ((0, 0, 0.1845), (0, 0, 0), Z),
        ((0, 0, 0.2155), (0, 0, 0), MINUS_Y), ((0, 0, 0.1845), (0, 0, 0), Z), ((0, 0, 0.2155), (0, 0, 0), Y),
        ((0, 0, 0.081), (0, 0, 0), Z), ((0, 0, 0.045), (0, 0, 0), None)],
        np.radians([170, 120, 170, 120, 170, 120, 175])),
    # Barrett's DH frames as URDF joints, as jhu-lcsr/barrett_model models/components.urdf.xacro writes them
    # (its base_yaw_joint origin starts 0.346 m lower, at the mounting face), the tool plate 0.06 m past the wrist;
    # limits of the WAM Arm User's Manual, Table 6.
    "barrett-wam7": (barrett_wam7, [
        ((0, 0, 0), (0, 0, 0), Z), ((0, 0, 0), (-HALF, 0, 0), Z), ((0, 0, 0), (HALF, 0, 0), Z),
        ((0.045, 0, 0.55), (-HALF, 0, 0), Z), ((-0.045, -0.3, 0), (HALF, 0, 0), Z), ((0, 0, 0), (-HALF, 0, 0), Z),
        ((0, 0, 0), (HALF, 0, 0), Z), ((0, 0, 0.06), (0, 0, 0), None)],
        [2.6, 2.0, 2.8, (-0.9, 3.1), (-4.76, 1.24), 1.6, 3.0]),
    # frankaemika/franka_ros franka_description/robots/panda_arm.xacro, panda_link0 -> panda_link8.
    "franka-panda": (franka_panda, [
        ((0, 0, 0.333), (0, 0, 0), Z), ((0, 0, 0), (-HALF, 0, 0), Z), ((0, -0.316, 0), (HALF, 0, 0), Z),
        ((0.0825, 0, 0), (HALF, 0, 0), Z), ((-0.0825, 0.384, 0), (-HALF, 0, 0), Z), ((0, 0, 0), (HALF, 0, 0), Z),
        ((0.088, 0, 0), (HALF, 0, 0), Z), ((0, 0, 0.107), (0, 0, 0), None)],
        [2.8973, 1.7628, 2.8973, (-3.0718, -0.0698), 2.8973, (-0.0175, 3.7525), 2.8973]),
    # Kinovarobotics/ros2_kortex kortex_description/arms/gen3/7dof/urdf/gen3_macro.xacro, base_link ->
    # end_effector_link, numbers as printed.
    "kinova-gen3": (kinova_gen3, [
        ((0, 0, 0.15643), (3.1416, 2.7629E-18, -4.9305E-36), Z),
        ((0, 0.005375, -0.12838), (1.5708, 2.1343E-17, -1.1102E-16), Z),
        ((0, -0.21038, -0.006375), (-1.5708, 1.2326E-32, -2.9122E-16), Z),
        ((0, 0.006375, -0.21038), (1.5708, -6.6954E-17, -1.6653E-16), Z),
        ((0, -0.20843, -0.006375), (-1.5708, 2.2204E-16, -6.373E-17), Z),
        ((0, 0.00017505, -0.10593), (1.5708, 9.2076E-28, -8.2157E-15), Z),
        ((0, -0.10593, -0.00017505), (-1.5708, -5.5511E-17, 9.6396E-17), Z),
        ((0, 0, -0.0615250000000001), (3.14159265358979, 1.09937075168372E-32, 0), None)],
        [INF, 2.24, INF, 2.57, INF, 2.09, INF]),
    # xArm-Developer/xarm_ros2 xarm_description/urdf/xarm7/xarm7.urdf.xacro (default limits), link_base -> link_eef.
    "ufactory-xarm7": (ufactory_xarm7, [
        ((0, 0, 0.267), (0, 0, 0), Z), ((0, 0, 0), (-1.5708, 0, 0), Z), ((0, -0.293, 0), (1.5708, 0, 0), Z),
        ((0.0525, 0, 0), (1.5708, 0, 0), Z), ((0.0775, -0.3425, 0), (1.5708, 0, 0), Z), ((0, 0, 0), (1.5708, 0, 0), Z),
        ((0.076, 0.097, 0), (-1.5708, 0, 0), Z), ((0, 0, 0), (0, 0, 0), None)],
        [2 * PI, (-2.059, 2.0944), 2 * PI, (-0.19198, 3.927), 2 * PI, (-1.69297, PI), 2 * PI]),
}
SRS_MODELS = [kuka_iiwa14, kuka_iiwa7, kuka_iiwa14_table1]
JOINTS = arrays(np.float64, 7, elements=st.floats(-2 * PI, 2 * PI))


def _limits(entries) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` from entries ``v`` (meaning +-v) or ``(lower, upper)``."""
    pairs = [entry if isinstance(entry, tuple) else (-entry, entry) for entry in entries]
    return np.array([p[0] for p in pairs], float), np.array([p[1] for p in pairs], float)


def test_every_maker_model_is_named_and_checked_here():
    assert set(MAKERS) | {"kuka-iiwa14-table1"} <= set(MODELS)
    assert all(MODELS[name] is factory for name, (factory, _, _) in MAKERS.items())


@pytest.mark.parametrize("name", MAKERS)
@settings(max_examples=30, deadline=None)
@given(q=JOINTS)
def test_model_equals_the_makers_urdf(name, q):
    factory, joints, _ = MAKERS[name]
    chain, reference = factory(), right_angles(joints)
    for values in (q, np.zeros(7)):
        np.testing.assert_allclose(chain.fk(values), urdf_pose(reference, values)[0], rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", MAKERS)
def test_batched_poses_equal_the_makers_urdf(name):
    """Above 16 configurations the chain propagates axis columns instead of multiplying matrices."""
    factory, joints, _ = MAKERS[name]
    chain, reference = factory(), right_angles(joints)
    q = np.random.default_rng(12).uniform(-PI, PI, (40, 7))
    expected = np.array([urdf_pose(reference, row)[0] for row in q])
    np.testing.assert_allclose(chain.fk(q), expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", MAKERS)
def test_each_joint_turns_about_the_makers_axis_in_the_makers_sense(name):
    """At the zero pose the angular Jacobian column of joint k is the URDF's axis of joint k in the base frame."""
    factory, joints, _ = MAKERS[name]
    chain, reference = factory(), right_angles(joints)
    axes = urdf_pose(reference, np.zeros(7))[1]
    np.testing.assert_allclose(chain.jacobian(np.zeros(7))[3:].T, axes, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", MAKERS)
def test_limits_are_the_makers(name):
    factory, _, limits = MAKERS[name]
    chain = factory()
    lower, upper = _limits(limits)
    np.testing.assert_array_equal(chain.lower, lower)
    np.testing.assert_array_equal(chain.upper, upper)


@pytest.mark.parametrize("name", ["kinova-gen3", "ufactory-xarm7"])
def test_right_angles_printed_to_five_digits_cost_what_their_rounding_allows(name):
    """Kinova and UFactory print pi/2 as 1.5708 (and pi as 3.1416); the models take the exact angles.

    Each printed angle is off by at most delta_k, which turns everything after it by delta_k: the end
    rotation moves by at most sum(delta_k) and the end point by at most sum(delta_k) * (the arm's length).
    """
    factory, joints, _ = MAKERS[name]
    chain = factory()
    exact = right_angles(joints)
    rounding = sum(np.abs(np.subtract(rpy, snapped)).sum() for (_, rpy, _), (_, snapped, _) in zip(joints, exact))
    length = sum(np.linalg.norm(xyz) for xyz, _, _ in joints)
    q = np.random.default_rng(13).uniform(-PI, PI, (200, 7))
    literal = np.array([urdf_pose(joints, row)[0] for row in q])
    ours = chain.fk(q)
    rotation_error = np.abs(ours[:, :3, :3] - literal[:, :3, :3]).max()
    position_error = np.linalg.norm(ours[:, :3, 3] - literal[:, :3, 3], axis=-1).max()
    assert 1e-7 < rotation_error <= rounding
    assert 1e-8 < position_error <= rounding * length


@pytest.mark.parametrize("factory", SRS_MODELS)
def test_srs_models_get_exact_ik_in_their_own_joint_values(factory):
    """FK(IK) <= 1e-9 on every branch, with KUKA's joint 4 sense or Table 1's."""
    chain = factory()
    rng = np.random.default_rng(14)
    poses = chain.fk(rng.uniform(chain.lower, chain.upper, (300, 7)))
    psi = rng.uniform(-PI, PI, 300)
    solutions = ik_all_branches(chain, poses, psi)  # (300, 8, 7)
    assert solutions.shape == (300, 8, 7)
    assert np.abs(chain.fk(solutions) - poses[:, None]).max() <= 1e-9


def test_table1_form_is_the_former_model_and_kukas_arm_with_joint_4_reversed():
    table1, kuka = kuka_iiwa14_table1(), kuka_iiwa14()
    former = srs_chain(0.36, 0.42, 0.40, 0.126, lower_deg=[-170, -120, -170, -120, -170, -120, -175],
                       upper_deg=[170, 120, 170, 120, 170, 120, 175])
    for key in ("a", "alpha", "d", "offset", "sign", "lower", "upper", "base", "tool"):
        np.testing.assert_array_equal(getattr(table1, key), getattr(former, key), err_msg=key)
    assert table1.convention == former.convention
    q = np.random.default_rng(15).uniform(-PI, PI, (50, 7))
    np.testing.assert_allclose(kuka.fk(q), table1.fk(q * [1, 1, 1, -1, 1, 1, 1]), rtol=0, atol=1e-12)
    assert np.abs(kuka.fk(q) - table1.fk(q)).max() > 0.1  # and not without the reversal
