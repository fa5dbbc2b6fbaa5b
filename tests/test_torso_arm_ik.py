"""Thesis 001 inverse kinematics: round trips for every branch, psi and phi laws, reported failures."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import humanoid_right_arm
from redkin.so3 import matrix_to_xyz_fixed
from redkin.torso_arm import (
    BRANCHES,
    ElbowReference,
    humanoid_arm,
    ik,
    position_ik,
    redundancy_parameters,
    shoulder_angle,
    shoulder_angle_eq31,
    theta1_from_shoulder_angle,
    theta1_from_shoulder_angle_eq31,
)
from redkin.torso_arm.branches import NO_REFERENCE, OK, SHOULDER_UNDEFINED, UNREACHABLE, wrap_angle
from redkin.torso_arm.elbow_angle import elbow_circle, elbow_position, reference_direction
from redkin.torso_arm.geometry import ELBOW_FRAME, SHOULDER_FRAME, WRIST_FRAME
from redkin.torso_arm.position_ik import joints_from_points

REFERENCES = ["theta4", "vector", (0.3, -0.2, 1.0)]


def random_postures(arm, count, seed):
    chain = arm.chain
    lower = np.maximum(chain.lower, -np.pi)
    upper = np.minimum(chain.upper, np.pi)
    return np.random.default_rng(seed).uniform(lower, upper, (count, 8))


def angle_error(a, b):
    return np.abs(wrap_angle(a - b))


@pytest.mark.parametrize("side", ["right", "left"])
@pytest.mark.parametrize("reference", REFERENCES)
def test_torso_arm_full_ik_recovers_every_branch(side, reference):
    arm = humanoid_arm(side, 0.1)
    q = random_postures(arm, 300, seed=1)
    psi, phi, defined = redundancy_parameters(arm, q, reference)
    pose = arm.chain.fk(q[defined])
    solution = ik(arm, pose[:, :3, 3], psi[defined], phi[defined], rotation=pose[:, :3, :3], reference=reference)
    assert np.all(solution.ok)
    # every branch reproduces the hand pose
    np.testing.assert_allclose(arm.chain.fk(solution.q), np.broadcast_to(pose[:, None], (len(pose), 8, 4, 4)),
                               atol=1e-10)
    # the original joints are one of the 8 branches, to 1e-8 rad
    error = angle_error(solution.q, q[defined][:, None]).max(axis=-1)
    assert np.all(error.min(axis=-1) <= 1e-8)
    # every branch flag is exercised by some posture
    hits = np.bincount(np.argmin(error, axis=-1), minlength=len(BRANCHES))
    assert np.all(hits[::2] + hits[1::2] > 0)


@settings(deadline=None, max_examples=40)
@given(st.integers(0, 10**6), st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi))
def test_torso_arm_position_ik_all_branches_round_trip(seed, psi, phi):
    arm = humanoid_arm()
    wrist = arm.chain.frames(random_postures(arm, 1, seed)[0])[WRIST_FRAME, :3, 3]
    sol = position_ik(arm, wrist, psi, phi, reference="vector")
    if not sol.ok:
        assert sol.status in (UNREACHABLE, SHOULDER_UNDEFINED)
        assert np.all(np.isnan(sol.q)) and not sol.within_limits.any()
        return
    q = np.concatenate([sol.q, np.zeros((4, 3))], axis=-1)
    frames = arm.chain.frames(q)
    np.testing.assert_allclose(frames[:, WRIST_FRAME, :3, 3], np.broadcast_to(wrist, (4, 3)), atol=1e-11)
    np.testing.assert_allclose(frames[:, ELBOW_FRAME, :3, 3], np.broadcast_to(sol.elbow, (4, 3)), atol=1e-11)
    assert np.allclose(shoulder_angle(sol.q[:, 0], wrist), psi, atol=1e-9) or np.allclose(
        np.abs(wrap_angle(shoulder_angle(sol.q[:, 0], wrist) - psi)), 0, atol=1e-9)
    np.testing.assert_array_equal(sol.within_limits, arm.chain.within_limits(q))


def test_torso_arm_ik_from_xyz_angles_matches_rotation():
    arm = humanoid_arm("right", 0.08)
    q = random_postures(arm, 50, seed=5)
    psi, phi, ok = redundancy_parameters(arm, q, "vector")
    pose = arm.chain.fk(q[ok])
    a = ik(arm, pose[:, :3, 3], psi[ok], phi[ok], rotation=pose[:, :3, :3], reference="vector")
    b = ik(arm, pose[:, :3, 3], psi[ok], phi[ok], angles=matrix_to_xyz_fixed(pose[:, :3, :3]), reference="vector")
    np.testing.assert_allclose(angle_error(a.q, b.q), 0.0, atol=1e-9)


def test_torso_arm_batched_equals_looped():
    arm = humanoid_arm()
    q = random_postures(arm, 12, seed=9)
    pose = arm.chain.fk(q)
    batch = ik(arm, pose[:, :3, 3], 0.2, -0.4, rotation=pose[:, :3, :3], reference="vector")
    for i in range(len(q)):
        one = ik(arm, pose[i, :3, 3], 0.2, -0.4, rotation=pose[i, :3, :3], reference="vector")
        np.testing.assert_array_equal(one.status, batch.status[i])
        np.testing.assert_allclose(one.q, batch.q[i], equal_nan=True, atol=1e-14)


def test_torso_arm_wrist_singularity_reported():
    arm = humanoid_arm()
    q = np.radians([10, 30, 20, 40, 10, 25, 0, 0])  # theta_7 = 0: axes 6 and 8 aligned
    pose = arm.chain.fk(q)
    psi, phi, _ = redundancy_parameters(arm, q, "vector")
    sol = ik(arm, pose[:3, 3], psi, phi, rotation=pose[:3, :3], reference="vector")
    match = np.argmin(angle_error(sol.q, q).max(axis=-1))
    assert sol.wrist_singular[match] and angle_error(sol.q[match], q).max() <= 1e-8
    # the singularity belongs to the branch: the theta_5 second branch turns frame 5 and is regular here
    assert not sol.wrist_singular.all()
    np.testing.assert_allclose(arm.chain.fk(sol.q), np.broadcast_to(pose, (8, 4, 4)), atol=1e-10)


# ------------------------------------------------------------------ shoulder angle
@pytest.mark.slow
@settings(deadline=None, max_examples=40)
@given(st.floats(-1, 1), st.floats(0.05, 1), st.floats(-1, 1), st.booleans())
def test_torso_arm_psi_monotone_in_theta1_with_exact_inverse(x, y, z, below):
    wrist = np.array([x, -y if below else y, z])
    theta1 = np.linspace(-np.pi, np.pi, 721)[:-1]
    psi = shoulder_angle(theta1, wrist)
    steps = wrap_angle(np.diff(np.append(psi, psi[0])))
    assert np.all(steps > 0) if not below else np.all(steps < 0)  # strictly monotone, one turn
    assert abs(steps.sum()) == pytest.approx(2 * np.pi)
    back, defined = theta1_from_shoulder_angle(psi, wrist)
    assert defined.all()
    assert angle_error(back, theta1).max() <= 1e-9
    assert shoulder_angle(0.0, wrist) == pytest.approx(0.0, abs=1e-12)


def test_torso_arm_psi_undefined_on_shoulder_plane():
    arm = humanoid_arm()
    sol = position_ik(arm, [0.2, 0.0, 0.5], 0.3, 0.0, reference="vector")
    assert sol.status == SHOULDER_UNDEFINED and np.isnan(sol.q).all()


def test_torso_arm_eq31_returns_every_root():
    wrist = np.array([0.45, 0.5, 0.35])
    L0 = humanoid_arm().L0
    theta = np.linspace(-np.pi, np.pi, 20001)
    values = shoulder_angle_eq31(theta, wrist, L0)
    for psi in (0.3, 1.0, 2.0):
        roots = theta1_from_shoulder_angle_eq31(psi, wrist, L0)
        np.testing.assert_allclose(shoulder_angle_eq31(roots, wrist, L0), psi, atol=1e-9)
        crossings = np.count_nonzero(np.diff(np.sign(values - psi)) != 0)
        assert len(roots) == crossings


# ------------------------------------------------------------------ elbow angle
def _circle_setup(seed):
    arm = humanoid_arm()
    q = random_postures(arm, 400, seed)
    frames = arm.chain.frames(q)
    shoulder, wrist = frames[:, SHOULDER_FRAME, :3, 3], frames[:, WRIST_FRAME, :3, 3]
    return arm, q, elbow_circle(arm, shoulder, wrist)


def test_torso_arm_phi_turns_right_handed_about_shoulder_to_wrist():
    arm, _, circle = _circle_setup(2)
    e1, exists = reference_direction(arm, circle, ElbowReference("vector"))
    phi, eps = 0.4, 1e-6
    a = elbow_position(circle, e1, phi)
    b = elbow_position(circle, e1, phi + eps)
    moment = np.sum(np.cross(a - circle.centre, b - a) * circle.axis, axis=-1)
    assert np.all(moment[exists] > 0)


@pytest.mark.slow
def test_torso_arm_theta4_reference_gives_theta4_zero_or_reports_no_reference():
    arm, q, circle = _circle_setup(4)
    e1, exists = reference_direction(arm, circle, ElbowReference("theta4"))
    assert exists.any() and (~exists).any()
    elbow = elbow_position(circle, e1, 0.0)
    joints = joints_from_points(arm, q[:, 0], elbow, circle.wrist)
    np.testing.assert_allclose(joints[exists, 0, 3], 0.0, atol=1e-9)  # principal branch theta_4 = 0
    # where none is reported, dense sampling of the circle finds no elbow with principal theta_4 = 0
    missing = np.flatnonzero(~exists)[:20]
    sample = np.linspace(-np.pi, np.pi, 20000, endpoint=False)
    for i in missing:
        sub = type(circle)(*(np.broadcast_to(getattr(circle, f)[i], (sample.size,) + getattr(circle, f)[i].shape)
                             for f in circle.__dataclass_fields__))
        basis = np.broadcast_to(reference_direction(arm, sub, ElbowReference("vector"))[0][0], (sample.size, 3))
        theta4 = joints_from_points(arm, np.full(sample.size, q[i, 0]), elbow_position(sub, basis, sample),
                                    sub.wrist)[:, 0, 3]
        assert np.min(np.abs(theta4)) > 1e-3
    sol = position_ik(arm, circle.wrist[missing], shoulder_angle(q[missing, 0], circle.wrist[missing]), 0.0)
    assert np.all(sol.status == NO_REFERENCE) and np.isnan(sol.q).all()


# ------------------------------------------------------------------ bad input
def test_torso_arm_bad_input_raises_clear_errors():
    arm = humanoid_arm()
    with pytest.raises(ValueError, match="wrist"):
        position_ik(arm, [0.1, 0.2], 0.0, 0.0)
    with pytest.raises(ValueError, match="shoulder_angle"):
        position_ik(arm, [0.1, 0.2, 0.3], np.nan, 0.0)
    with pytest.raises(ValueError, match="orthonormal"):
        ik(arm, [0.1, 0.2, 0.3], 0.0, 0.0, rotation=np.ones((3, 3)))
    with pytest.raises(ValueError, match="exactly one"):
        ik(arm, [0.1, 0.2, 0.3], 0.0, 0.0, rotation=np.eye(3), angles=[0, 0, 0])
    with pytest.raises(ValueError, match="reference"):
        position_ik(arm, [0.1, 0.2, 0.3], 0.0, 0.0, reference="sideways")
    with pytest.raises(ValueError, match="side"):
        humanoid_arm("middle")


def test_torso_arm_unreachable_is_a_status_not_an_error():
    sol = position_ik(humanoid_arm(), [3.0, 2.0, 1.0], 0.0, 0.0)
    assert sol.status == UNREACHABLE and not sol.within_limits.any()
    assert OK != UNREACHABLE


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_torso_arm_wrap_to_limits_shifts_only_into_limits(seed):
    from redkin.torso_arm.branches import wrap_to_limits

    chain = humanoid_right_arm()
    rng = np.random.default_rng(seed)
    q = rng.uniform(-10.0, 10.0, (50, chain.n))
    wrapped = wrap_to_limits(chain, q)
    # the same angle, in (-pi, pi] or shifted by 2 pi from there only when that lands inside the joint's limits
    assert np.allclose(np.cos(wrapped), np.cos(q)) and np.allclose(np.sin(wrapped), np.sin(q))
    principal = np.pi - np.mod(np.pi - q, 2.0 * np.pi)
    inside = (wrapped >= chain.lower) & (wrapped <= chain.upper)
    shifted = ~np.isclose(wrapped, principal)
    assert np.all(inside[shifted])
    for shift in (2.0 * np.pi, -2.0 * np.pi):  # nothing left outside that a shift would bring inside
        moved = principal + shift
        could = (moved >= chain.lower) & (moved <= chain.upper)
        assert not np.any(could & ~inside & ~((principal >= chain.lower) & (principal <= chain.upper)))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-50.0, 50.0), min_size=1, max_size=20))
def test_torso_arm_wrap_angle_is_the_same_angle_in_half_open_range(values):
    angles = np.array(values)
    wrapped = wrap_angle(angles)
    assert np.all((wrapped > -np.pi) & (wrapped <= np.pi))
    assert np.allclose(np.cos(wrapped), np.cos(angles)) and np.allclose(np.sin(wrapped), np.sin(angles))
    inside = (angles > -np.pi) & (angles <= np.pi)
    assert np.array_equal(wrapped[inside], angles[inside])  # already wrapped: unchanged, bit for bit
    assert wrap_angle(np.array([-np.pi]))[0] == np.pi
