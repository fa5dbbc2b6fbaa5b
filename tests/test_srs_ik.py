"""Arm-angle IK ([000 eqs. 11-19]): FK(IK(x)) = x on every branch, batched equals looped, inverse arm angle."""

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.chain import SerialChain
from redkin.models import barrett_wam, kuka_iiwa14, pa10_7c, planar_arm, srs_chain
from redkin.so3 import rot_x, rot_z
from redkin.srs import BRANCHES, arm_angle_of, ik, ik_all_branches, pose_from, reachable, srs_geometry
from redkin.srs.coefficients import coefficients_for
from redkin.srs.joints import STRETCHED_TOLERANCE
from tests.support.srs_arms import random_poses

ROUND_TRIP = 1e-9


def stretched_groups(entries):
    """Shoulder and wrist: singular at every psi, i.e. all coefficients of the group's x and y entries vanish."""
    return np.abs(entries.reshape(3, 2, 7)[..., :2]).max(axis=(0, 2)) <= STRETCHED_TOLERANCE


def pose_error(a, b):
    return np.abs(a - b).max()


@pytest.mark.parametrize("factory", [pa10_7c, kuka_iiwa14])
def test_round_trip_10000_poses_all_branches(factory):
    chain = factory()
    rng = np.random.default_rng(1)
    poses = random_poses(chain, 10_000, rng)
    psi = rng.uniform(-np.pi, np.pi, 10_000)
    q = ik_all_branches(chain, poses, psi)
    assert q.shape == (10_000, 8, 7)
    assert pose_error(chain.fk(q), poses[:, None]) < ROUND_TRIP
    # the eight branches are distinct solutions with the signs they claim, of the chain's own q (joint 4 of
    # KUKA's iiwa turns the other way from Table 1)
    theta = q
    signs = np.array(BRANCHES)
    assert np.all((np.sign(theta[..., [1, 3, 5]]) == signs) | (np.abs(theta[..., [1, 3, 5]]) < 1e-9))


def test_round_trip_random_geometries_10000_poses():
    rng = np.random.default_rng(2)
    worst = 0.0
    for _ in range(20):
        d_bs, d_se, d_ew, d_wt = rng.uniform(0.05, 1.0, 4) * np.array([1, 1, 1, rng.choice([-1, 0, 1])])
        chain = srs_chain(d_bs, d_se, d_ew, d_wt)
        poses = random_poses(chain, 500, rng)
        q = ik_all_branches(chain, poses, rng.uniform(-np.pi, np.pi, 500))
        worst = max(worst, pose_error(chain.fk(q), poses[:, None]))
    assert worst < ROUND_TRIP


@settings(max_examples=25, deadline=None)
@given(
    st.tuples(*[st.floats(0.05, 1.0)] * 4),
    st.lists(st.sampled_from([1.0, -1.0]), min_size=7, max_size=7),
    st.lists(st.floats(-3.0, 3.0), min_size=7, max_size=7),
    st.floats(-np.pi, np.pi),
    st.integers(0, 2**31),
)
def test_round_trip_with_base_tool_offsets_and_signs(lengths, sign, offset, psi, seed):
    base = np.eye(4)
    base[:3, :3] = rot_z(0.3) @ rot_x(-0.7)
    base[:3, 3] = [0.1, -0.2, 0.3]
    tool = np.eye(4)
    tool[:3, :3] = rot_x(0.4)
    tool[:3, 3] = [0.0, 0.05, 0.1]
    plain = srs_chain(*lengths)
    chain = SerialChain(a=plain.a, alpha=plain.alpha, d=plain.d, offset=offset, sign=sign, base=base, tool=tool)
    poses = random_poses(chain, 20, np.random.default_rng(seed))
    q = ik_all_branches(chain, poses, psi)
    assert pose_error(chain.fk(q), poses[:, None]) < ROUND_TRIP
    state = arm_angle_of(chain, q[:, 0])
    assert np.allclose(np.cos(state.psi - psi), 1.0, atol=1e-9)


def test_batched_equals_looped_and_single_branch_equals_all_branches():
    chain = pa10_7c()
    rng = np.random.default_rng(3)
    poses = random_poses(chain, 50, rng).reshape(5, 10, 4, 4)
    psi = rng.uniform(-np.pi, np.pi, (5, 10))
    every = ik_all_branches(chain, poses, psi)
    for k, branch in enumerate(BRANCHES):
        one = ik(chain, poses, psi, str(branch))
        assert one.shape == (5, 10, 7)
        assert np.allclose(np.cos(one - every[..., k, :]), 1.0, atol=1e-12)
        looped = np.array([[ik(chain, poses[i, j], psi[i, j], branch) for j in range(10)] for i in range(5)])
        assert np.allclose(np.cos(looped - one), 1.0, atol=1e-12)



@settings(max_examples=20, deadline=None)
@given(shape=st.sampled_from([(), (1,), (7,), (3, 4)]), seed=st.integers(0, 2**32 - 1), broadcast_psi=st.booleans())
def test_ik_all_branches_into_out_equals_a_fresh_result_and_is_out(shape, seed, broadcast_psi):
    """Written into a reused buffer (the stale values of the previous call in it) the joint values are those of a
    fresh call, bit for bit, and the array returned is the buffer."""
    chain = kuka_iiwa14()
    rng = np.random.default_rng(seed)
    count = int(np.prod(shape))
    poses = random_poses(chain, count, rng).reshape(shape + (4, 4))
    psi = rng.uniform(-np.pi, np.pi, () if broadcast_psi else shape)
    buffer = np.full(shape + (8, 7), np.nan)
    for _ in range(2):
        fresh = ik_all_branches(chain, poses, psi)
        written = ik_all_branches(chain, poses, psi, out=buffer)
        assert written is buffer
        assert np.array_equal(buffer, fresh)
        psi = psi + 0.5  # the second call overwrites the first's values


@pytest.mark.parametrize("out, words", [
    (np.empty((4, 8, 6)), "of shape (4, 8, 7)"),
    (np.empty((3, 8, 7)), "of shape (4, 8, 7)"),
    (np.empty((4, 8, 7), dtype=np.float32), "float64"),
    (np.empty((4, 7, 8)).transpose(0, 2, 1), "C-contiguous"),
    (np.broadcast_to(np.empty((8, 7)), (4, 8, 7)), "writeable"),
    ([[0.0] * 7] * 8, "numpy array"),
])
def test_ik_all_branches_refuses_an_out_it_cannot_write_into(out, words):
    chain = kuka_iiwa14()
    poses = random_poses(chain, 4, np.random.default_rng(0))
    with pytest.raises(ValueError, match=re.escape(words)):
        ik_all_branches(chain, poses, 0.3, out=out)

def test_arm_angle_of_inverts_ik_on_every_branch():
    chain = kuka_iiwa14()
    rng = np.random.default_rng(4)
    poses = random_poses(chain, 200, rng)
    psi = rng.uniform(-np.pi, np.pi, 200)
    q = ik_all_branches(chain, poses, psi)
    state = arm_angle_of(chain, q)
    assert np.allclose(np.cos(state.psi - psi[:, None]), 1.0, atol=1e-9)
    assert np.array_equal(state.branch, np.broadcast_to(np.array(BRANCHES), (200, 8, 3)))
    assert state.branch_strings()[0, 5] == str(BRANCHES[5])


def test_paper_section_6_1_joint_vectors():
    """Paper 000 section 6.1: theta at psi = 0 for x = (0.65, 0, 0.5), R = diag(-1, 1, -1), branch +++."""
    chain = pa10_7c()
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    theta = np.degrees(ik(chain, pose, 0.0, "+++"))
    assert np.allclose(theta, [0, 25.666, 0, 82.872, 0, 71.463, 0], atol=5e-4)


def test_reference_plane_is_theta3_zero_and_psi_is_right_handed():
    chain = pa10_7c()
    rng = np.random.default_rng(5)
    poses = random_poses(chain, 100, rng)
    q0 = ik_all_branches(chain, poses, 0.0)
    assert np.allclose(np.sin(q0[..., 2]), 0.0, atol=1e-9)  # theta_3 = 0 (or pi on the sigma_2 = - branches)
    # a small positive psi turns the elbow right-handedly about shoulder -> wrist
    q1 = ik(chain, poses, 1e-4, "+++")
    frames0, frames1 = chain.frames(q0[:, 0]), chain.frames(q1)
    shoulder, wrist = frames0[:, 2, :3, 3], frames0[:, 5, :3, 3]
    axis = (wrist - shoulder) / np.linalg.norm(wrist - shoulder, axis=-1, keepdims=True)
    elbow0, elbow1 = frames0[:, 3, :3, 3] - shoulder, frames1[:, 3, :3, 3] - shoulder
    assert np.all(np.einsum("ij,ij->i", np.cross(elbow0, elbow1), axis) > 0)


def test_wrist_on_joint1_axis_uses_theta1_zero_reference():
    chain = pa10_7c()
    geometry = srs_geometry(chain)
    q = np.array([0.0, 0.0, 0.0, 0.8, 0.3, 0.2, 0.1])
    vx, vy = geometry.d_ew * np.sin(q[3]), -(geometry.d_se + geometry.d_ew * np.cos(q[3]))
    q[1] = np.arctan2(vx, vy)  # with theta_1 = theta_3 = 0 this puts the wrist on the z axis
    pose = chain.fk(q)
    x_sw = pose[:3, 3] - pose[:3, 2] * geometry.d_wt - [0, 0, geometry.d_bs]
    assert np.hypot(x_sw[0], x_sw[1]) < 1e-12
    reference = ik_all_branches(chain, pose, 0.0)
    assert np.allclose(np.sin(reference[:, [0, 2]]), 0.0, atol=1e-12)  # theta_1o = 0 (or pi), theta_3 = 0 (or pi)
    for psi in np.linspace(-np.pi, np.pi, 9):
        solutions = ik_all_branches(chain, pose, psi)
        assert pose_error(chain.fk(solutions), pose) < ROUND_TRIP
        # on the joint-1 axis the arm angle turns joint 1 itself (right-handed about shoulder -> wrist)
        assert np.allclose(np.sin(solutions[:, 0] - np.sign(x_sw[2]) * psi), 0.0, atol=1e-9)


def test_elbow_stretched_and_degenerate_configurations():
    chain = pa10_7c()
    for q in ([0.3, 0.0, 0.5, 0.9, 0.2, 0.4, 0.1], [0.3, 0.7, 0.5, 0.9, 0.2, 0.0, 0.1],
              [0.3, 0.7, 0.5, 0.0, 0.2, 0.4, 0.1]):
        pose = chain.fk(np.array(q))
        for psi in np.linspace(-np.pi, np.pi, 13):
            assert pose_error(chain.fk(ik_all_branches(chain, pose, psi)), pose) < ROUND_TRIP


STRETCHED = {  # singular at every arm angle: q_2 = q_4 = 0 (shoulder), or q_4 = q_6 = 0 (wrist)
    "shoulder (home pose)": [0.0] * 7,
    "shoulder, rounding in x_sw": [0.3, 0.0, 0.2, 0.0, 0.1, 0.4, 0.2],
    "wrist": [0.3, 0.5, 0.2, 0.0, 0.1, 0.0, 0.2],
    "both": [0.3, 0.0, 0.2, 0.0, 0.1, 0.0, 0.2],
}


@pytest.mark.parametrize("q", STRETCHED.values(), ids=STRETCHED.keys())
@pytest.mark.parametrize("factory", [pa10_7c, kuka_iiwa14, barrett_wam])
def test_stretched_group_sets_its_first_joint_to_zero_at_every_psi(factory, q):
    """Where only theta_1 + theta_3 (theta_5 + theta_7) is defined, theta_1 (theta_5) is 0, or pi on sigma = -1.

    A group counts as stretched when its x, y coefficients vanish to rounding.  [000 eq. 11] fixes
    theta_4 only to about sqrt(eps) near 0 (acos), so some stretched poses come out bent by
    ~2e-8 rad; their first joint is then defined and the regular formulas hold (FK still exact).
    """
    chain = factory()
    pose = chain.fk(np.array(q))
    psi = np.linspace(-np.pi, np.pi, 37)
    solutions = ik_all_branches(chain, np.broadcast_to(pose, psi.shape + (4, 4)), psi)  # (37, 8, 7)
    assert pose_error(chain.fk(solutions), pose) < ROUND_TRIP
    for elbow in (1, -1):
        entries = coefficients_for(chain, pose, elbow).entries
        stretched = stretched_groups(entries)
        for group, column in ((0, 0), (1, 4)):
            if not stretched[group]:
                continue
            of_elbow = np.array([b.elbow == elbow for b in BRANCHES])
            first = solutions[:, of_elbow, column]
            flipped = np.array([(b.shoulder if group == 0 else b.wrist) < 0 for b in BRANCHES])[of_elbow]
            assert np.allclose(np.sin(first), 0.0, atol=1e-12)  # no angle left to rounding
            assert np.allclose(np.cos(first), np.where(flipped, -1.0, 1.0), atol=1e-12)


def test_exact_home_pose_of_the_iiwa_is_stretched_at_the_shoulder():
    """Guards the test above against being vacuous: the iiwa's home pose has x = y = 0 exactly."""
    chain = kuka_iiwa14()
    entries = coefficients_for(chain, chain.fk(np.zeros(7)), 1).entries
    assert np.all(stretched_groups(entries))


def test_not_srs_chains_name_the_violated_condition():
    with pytest.raises(ValueError, match="7 joints"):
        srs_geometry(planar_arm())
    plain = srs_chain(0.3, 0.4, 0.4, 0.1)
    offset_wrist = SerialChain(a=plain.a, alpha=plain.alpha, d=[0.3, 0, 0.4, 0.0, 0.4, 0.05, 0.1])
    with pytest.raises(ValueError, match=r"joints 5-7 do not meet in one point: axes 5 and 7 miss each other by "
                                         r"0\.05 m"):
        srs_geometry(offset_wrist)
    with pytest.raises(ValueError, match="shoulder and elbow coincide"):
        srs_geometry(SerialChain(a=plain.a, alpha=plain.alpha, d=[0.3, 0, 0.0, 0, 0.4, 0, 0.1]))
    skewed = SerialChain(a=plain.a, alpha=np.r_[plain.alpha[0], np.radians(80.0), plain.alpha[2:]], d=plain.d)
    with pytest.raises(ValueError, match="axes 2 and 3 are not perpendicular"):
        srs_geometry(skewed)


def test_srs_arms_in_other_descriptions_are_solved_in_their_own_joint_values():
    """A last twist, modified DH rows, reversed joints: the same S-R-S geometry, solved in the chain's own q."""
    plain = srs_chain(0.3, 0.4, 0.4, 0.1)
    twisted = SerialChain(a=plain.a, alpha=np.r_[plain.alpha[:6], 0.3], d=plain.d)  # alpha_7 only turns the tool
    reversed_joints = SerialChain(a=plain.a, alpha=plain.alpha, d=plain.d, sign=[1, -1, -1, 1, -1, 1, -1],
                                  offset=[0.2, 0, 3.0, -0.5, 0, 1.0, 0])
    modified = SerialChain(a=[0.0] * 7, alpha=np.r_[0.0, plain.alpha[:6]], d=[0.3, 0, 0.4, 0, 0.4, 0, 0.1],
                           convention="mdh")
    rng = np.random.default_rng(5)
    for chain in (twisted, reversed_joints, modified):
        q = rng.uniform(-1.5, 1.5, (20, 7))
        poses = chain.fk(q)
        for psi in (-2.0, 0.4):
            solutions = ik_all_branches(chain, poses, psi)  # (20, 8, 7), in the chain's own joint values
            assert pose_error(chain.fk(solutions), poses[:, None]) < ROUND_TRIP
        # the arm angle of a configuration, fed back, returns that configuration on its branch
        geometry = srs_geometry(chain)
        for row in q[:5]:
            state = arm_angle_of(geometry, row)
            again = ik(geometry, chain.fk(row), float(state.psi), str(state.branch_strings()))
            assert np.allclose(np.mod(again - row + np.pi, 2 * np.pi) - np.pi, 0, atol=1e-9)


def test_bad_inputs_raise_clear_errors():
    chain = pa10_7c()
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    with pytest.raises(ValueError, match="unreachable position"):
        ik(chain, pose_from(np.array([3.0, 0.0, 0.5]), np.eye(3)), 0.0)
    with pytest.raises(ValueError, match="orthonormal"):
        ik(chain, pose_from(np.array([0.65, 0.0, 0.5]), 2 * np.eye(3)), 0.0)
    with pytest.raises(ValueError, match="pose"):
        ik(chain, np.eye(3), 0.0)
    with pytest.raises(ValueError, match="psi"):
        ik(chain, pose, np.nan)
    with pytest.raises(ValueError, match="branch"):
        ik(chain, pose, 0.0, "++")
    with pytest.raises(ValueError, match="branch"):
        ik(chain, pose, 0.0, (1, 0, 1))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_srs_reachable_mask_filters_a_mixed_batch(seed):
    # a batch with wrists in and out of reach: the mask says which, and IK of the kept rows succeeds
    chain = pa10_7c()
    rng = np.random.default_rng(seed)
    poses = chain.fk(rng.uniform(chain.lower, chain.upper, (12, 7)))
    far = rng.random(12) < 0.5
    directions = rng.normal(size=(12, 3))
    poses[far, :3, 3] = 3.0 * (directions / np.linalg.norm(directions, axis=1, keepdims=True))[far]  # > 1.3 m reach
    mask = reachable(chain, poses)
    assert mask.shape == (12,) and mask.dtype == bool
    assert np.array_equal(mask, ~far)
    for pose, ok in zip(poses, mask):  # the mask is what IK itself decides, pose by pose
        try:
            ik(chain, pose, 0.3)
            raised = False
        except ValueError as error:
            raised = "unreachable" in str(error)
        assert raised == (not ok)
    if mask.any():
        q = ik(chain, poses[mask], 0.3)
        assert np.allclose(chain.fk(q), poses[mask], atol=1e-9)


def test_srs_reachable_rejects_bad_poses_and_keeps_batch_shape():
    chain = pa10_7c()
    with pytest.raises(ValueError, match="pose"):
        reachable(chain, np.full((4, 4), np.nan))
    poses = chain.fk(np.zeros((2, 3, 7)))
    assert reachable(chain, poses).shape == (2, 3)


def test_arm_angle_and_branch_do_not_depend_on_the_description():
    """KUKA's iiwa as Table 1 rows with joint 4 reversed, as KUKA's URDF, and with joints 3-5 written the other
    way round (Table 1's own symmetry): the same q has the same psi, and branches name the signs of the chain's
    own q_2, q_4, q_6."""
    from redkin.models import get_robot

    kuka = kuka_iiwa14()
    turned = SerialChain(a=kuka.a, alpha=kuka.alpha, d=kuka.d, offset=[0, 0, np.pi, 0, np.pi, 0, 0],
                         sign=[1, 1, 1, 1, 1, 1, 1], lower=kuka.lower, upper=kuka.upper)  # theta_4 = +q_4
    descriptions = [kuka, get_robot("examples/iiwa14.urdf"), turned]
    q = np.random.default_rng(9).uniform(-2.0, 2.0, (200, 7))
    for chain in descriptions:
        assert np.abs(chain.fk(q) - kuka.fk(q)).max() < 1e-12
    states = [arm_angle_of(chain, q) for chain in descriptions]
    for state in states:
        assert np.allclose(np.cos(state.psi - states[0].psi), 1.0, atol=1e-9)
        assert np.array_equal(state.branch, np.where(q[:, [1, 3, 5]] < 0, -1, 1))
    poses = kuka.fk(q)
    for chain in descriptions:
        solutions = ik_all_branches(chain, poses, 0.7)
        assert pose_error(chain.fk(solutions), poses[:, None]) < ROUND_TRIP
        signs = np.where(solutions[..., [1, 3, 5]] < 0, -1, 1)
        assert np.all((signs == np.array(BRANCHES)) | (np.abs(solutions[..., [1, 3, 5]]) < 1e-9))
        for k in (0, 5):
            np.testing.assert_allclose(solutions[:, k], ik(chain, poses, 0.7, BRANCHES[k]), atol=1e-12)
