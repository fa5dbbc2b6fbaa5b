"""Feasible arm angles ([000 eqs. 21-30]) equal dense sampling with an FK check, and never miss a narrow arc."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import kuka_iiwa14, pa10_7c
from redkin.reproduce import printed
from redkin.srs import BRANCHES, feasible_arm_angles, feasible_arm_angles_batch, feasible_pieces, ik, pose_from
from tests.support.feasible_sampling import assert_set_matches_sampling, random_limits
from tests.support.srs_arms import ARM_KINDS, arm


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from([str(b) for b in BRANCHES]), st.booleans(), st.sampled_from(ARM_KINDS))
def test_feasible_sets_equal_dense_sampling(seed, branch, crossing, model):
    rng = np.random.default_rng(seed)
    chain = arm(model, rng)
    q = rng.uniform(-np.pi, np.pi, 7)
    lower, upper = random_limits(rng, q, crossing)
    chain = chain.with_limits(lower, upper)
    pose = chain.fk(q)
    result = feasible_arm_angles(chain, pose, branch)
    assert_set_matches_sampling(chain, pose, branch, result)


@pytest.mark.parametrize("branch", [str(b) for b in BRANCHES])
@pytest.mark.parametrize("model", ["pa10", "wam"])
def test_narrow_limits_around_a_known_solution_are_found(branch, model):
    rng = np.random.default_rng(7)
    base = arm(model, rng)
    for _ in range(10):
        pose = base.fk(rng.uniform(-np.pi, np.pi, 7))
        psi_star = rng.uniform(-np.pi, np.pi)
        q_star = ik(base, pose, psi_star, branch)
        chain = base.with_limits(q_star - 0.001, q_star + 0.001)
        result = feasible_arm_angles(chain, pose, branch)
        assert not result.is_empty
        assert result.feasible.contains(psi_star, tolerance=1e-12)
        assert result.feasible.length < 0.05
        assert_set_matches_sampling(chain, pose, branch, result, margin=1e-9)


def test_limits_crossing_pi_and_unlimited_joints():
    base = kuka_iiwa14()
    rng = np.random.default_rng(8)
    pose = base.fk(rng.uniform(-np.pi, np.pi, 7))
    q = ik(base, pose, 2.0, "+-+")
    # every limit straddles +-pi in the chain's own q convention
    lower = np.full(7, np.pi - 1.5)
    upper = np.full(7, np.pi + 1.5)
    chain = base.with_limits(lower, upper)
    result = feasible_arm_angles(chain, pose, "+-+")
    assert_set_matches_sampling(chain, pose, "+-+", result)
    unlimited = base.with_limits(np.full(7, -4.0), np.full(7, 4.0))
    free = feasible_arm_angles(unlimited, pose, "+-+")
    assert free.feasible.is_full and all(s.is_full for s in free.per_joint.values())
    del q


STRETCHED = {  # singular at every arm angle: [000 eq. 15] (19) is 0/0 for every psi, the third joint still turns
    "shoulder (home pose)": [0.0] * 7,
    "shoulder, rounding in x_sw": [0.3, 0.0, 0.2, 0.0, 0.1, 0.4, 0.2],
    "wrist": [0.3, 0.5, 0.2, 0.0, 0.1, 0.0, 0.2],
    "both": [0.3, 0.0, 0.2, 0.0, 0.1, 0.0, 0.2],
}


@pytest.mark.parametrize("q", STRETCHED.values(), ids=STRETCHED.keys())
@pytest.mark.parametrize("model", ["pa10", "iiwa", "wam"])
def test_stretched_arm_feasible_sets_equal_dense_sampling(model, q):
    """The home pose and its kin: the third joint's limits still cut the arm-angle circle (all branches, own and
    random limits).

    On the WAM too: at theta_4 = 0 its offsets cancel and the upper arm, forearm and shoulder-wrist line are parallel.
    """
    base = arm(model, np.random.default_rng(0))
    rng = np.random.default_rng(11)
    pose = base.fk(np.array(q))
    for chain in (base, base.with_limits(*random_limits(rng, np.array(q), False))):
        for branch in BRANCHES:
            result = feasible_arm_angles(chain, pose, branch)
            assert_set_matches_sampling(chain, pose, branch, result)


def test_elbow_outside_limits_empties_every_branch_of_that_sign():
    chain = pa10_7c()  # theta_4 in [0, 135] deg: the elbow-negative branches are never feasible
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    for branch in BRANCHES:
        result = feasible_arm_angles(chain, pose, branch)
        if branch.elbow < 0:
            assert result.is_empty and result.per_joint[4].is_empty


def test_batched_pieces_equal_single_pose_sets():
    chain = pa10_7c()
    rng = np.random.default_rng(9)
    q = rng.uniform(-1.0, 1.0, (30, 7)) * [1.5, 0.7, 2.0, 1.0, 1.5, 1.5, 2.0] + [0, 0, 0, 1.2, 0, 0, 0]
    poses = chain.fk(q)
    pieces = feasible_pieces(chain, poses, "+++")
    batch = feasible_arm_angles_batch(chain, poses, "+++")
    assert batch.shape == (30,)
    for i in range(30):
        single = feasible_arm_angles(chain, poses[i], "+++")
        assert single.feasible.isclose(batch[i].feasible, 1e-12)
        assert single.feasible.isclose(pieces.arc_set((i,)), 1e-12)
        assert bool(pieces.nonempty[i]) == (not single.is_empty)


def test_paper_section_6_1_feasible_sets():
    """Paper 000 section 6.1, branch +++: Psi_i and Psi to the printed 3 decimals (degrees)."""
    chain = pa10_7c()
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    result = feasible_arm_angles(chain, pose, "+++")
    for joint, bound in printed.SECTION_6_1_JOINT_BOUNDS.items():
        arcs = np.degrees(result.per_joint[joint].arcs)
        if bound is None:
            assert result.per_joint[joint].is_full
        else:
            assert np.allclose(arcs, [[-bound, bound]], atol=5e-4)
    bound = printed.SECTION_6_1_PSI_BOUND
    assert np.allclose(np.degrees(result.feasible.arcs), [[-bound, bound]], atol=5e-4)
    # the bounds are where theta_2 reaches its 45 deg limit (paper Fig. 6)
    for psi in result.feasible.arcs[0]:
        assert np.degrees(ik(chain, pose, psi, "+++"))[1] == pytest.approx(45.0, abs=1e-9)


@pytest.mark.parametrize("limits", ["maker's", "random", "narrow"])
def test_urdf_arm_feasible_sets_equal_dense_sampling_in_its_own_joint_values(limits):
    """KUKA's URDF (joint 4 the other way from Table 1, other zero frames): sets in KUKA's q and limits."""
    from pathlib import Path

    from redkin.models import get_robot

    arm = get_robot(Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / "iiwa14.urdf")
    rng = np.random.default_rng(21)
    for _ in range(3):
        q = rng.uniform(arm.lower, arm.upper) * 0.8
        chain = arm
        if limits == "random":
            chain = arm.with_limits(*random_limits(rng, q, crossing=False))
        elif limits == "narrow":  # +-0.001 rad around a solution: the arc is tiny and must still be found
            chain = arm.with_limits(q - 1e-3, q + 1e-3)
        pose = chain.fk(q)
        for branch in BRANCHES:
            assert_set_matches_sampling(chain, pose, branch, feasible_arm_angles(chain, pose, branch))
        if limits == "narrow":
            from redkin.srs import arm_angle_of

            state = arm_angle_of(chain, q)
            found = feasible_arm_angles(chain, pose, str(state.branch_strings()))
            assert found.feasible.contains(np.array([float(state.psi)]))[0]


def test_feasible_arm_angles_takes_one_pose_and_the_batch_function_a_batch():
    """One return type per function: a FeasibleArmAngles for one pose, an object array for a batch."""
    chain = pa10_7c()
    poses = chain.fk(np.random.default_rng(5).uniform(-1, 1, (2, 3, 7)))
    with pytest.raises(ValueError, match="feasible_arm_angles_batch"):
        feasible_arm_angles(chain, poses, "+++")
    batch = feasible_arm_angles_batch(chain, poses, "+++")
    assert batch.shape == (2, 3) and batch.dtype == object
    assert batch[1, 2].feasible == feasible_arm_angles(chain, poses[1, 2], "+++").feasible
    one = feasible_arm_angles_batch(chain, poses[0, 0], "+++")
    assert one.shape == () and one[()].feasible == batch[0, 0].feasible


def test_the_result_builds_its_arc_sets_on_access_and_compares_by_content():
    """feasible_arm_angles keeps the kernel's pieces and makes the ArcSets when asked (issue 23): the sets equal
    those of feasible_pieces and of the batch call, and two results of one pose compare equal."""
    chain = kuka_iiwa14()
    pose = chain.fk(np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.9, 0.8]))
    result = feasible_arm_angles(chain, pose, "+-+")
    assert "feasible" not in vars(result) and "per_joint" not in vars(result)  # nothing built yet
    assert result.feasible == feasible_pieces(chain, pose, "+-+").arc_set()
    assert result == feasible_arm_angles_batch(chain, pose[None], "+-+")[0]
    assert set(result.per_joint) == set(range(1, 8)) and result.per_joint[4].is_full
    assert result != feasible_arm_angles(chain, pose, "+++")
