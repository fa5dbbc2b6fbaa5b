"""Laws behind the fast S-R-S paths (paper 000): one formula evaluated two ways agrees, batched equals looped.

The compiled kernels (redkin.srs._ik_kernels) evaluate [000 eqs. 12, 16] as
coefficient matrices and read the joints from 14 of their entries; all eight
branches share one frame per elbow sign; the limit equations of all joints
come from one cached matrix.  These tests check each against its definition,
written here: DH rotation products, the entry layout, one branch at a time.
"""

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from redkin._validation import check_pose
from redkin.models import pa10_7c
from redkin.so3 import rot_x
from redkin.srs import (
    BRANCHES,
    _feasible_kernels,
    arm_angle_of,
    feasible_arm_angles,
    feasible_arm_angles_batch,
    feasible_pieces,
    ik,
    ik_all_branches,
    pose_from,
    srs_geometry,
)
from redkin.srs._ik_kernels import ENTRY_LAYOUT
from redkin.srs.coefficients import arm_angle_coefficients
from redkin.srs.feasible import limit_tables
from redkin.srs.joints import _IS_COSINE, PSI_JOINTS
from tests.support.feasible_sampling import random_limits
from tests.support.srs_arms import ARM_KINDS, arm, shoulder_rotation, wrist_rotation


def random_chain(rng, model, crossing=False):
    """A model or random S-R-S arm with random limits (optionally crossing +-pi), and a joint vector."""
    chain = arm(model, rng)
    q = rng.uniform(-np.pi, np.pi, 7)
    return chain.with_limits(*random_limits(rng, q, crossing)), q


def degenerate_q(kind):
    """Joint vectors with theta_2 = 0, theta_6 = 0, theta_4 = 0 or the wrist on the joint-1 axis."""
    return {
        "shoulder": [0.3, 0.0, 0.5, 0.9, 0.2, 0.4, 0.1],
        "wrist": [0.3, 0.7, 0.5, 0.9, 0.2, 0.0, 0.1],
        "elbow": [0.3, 0.7, 0.5, 0.0, 0.2, 0.4, 0.1],
        "axis": [0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 0.2],
        "folded_axis": [0.4, 0.0, -0.4, 0.0, 0.0, 0.0, 0.0],
    }[kind]


MODELS = st.sampled_from(ARM_KINDS)


def entries_of(shoulder, wrist):
    """The signed entries of ENTRY_LAYOUT, read one by one from 0R3 and 4R7 stacks (..., 3, 3) -> (..., 14)."""
    matrices = (shoulder, wrist)
    return np.stack([factor * matrices[int(m)][..., int(r), int(c)] for m, r, c, factor in ENTRY_LAYOUT], axis=-1)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**31), MODELS, st.sampled_from([1, -1]))
def test_coefficients_at_psi_equal_the_rotations_of_the_ik_joint_values(seed, model, elbow):
    """A sin psi + B cos psi + C ([000 eqs. 12, 16]) == 0R3, 4R7 of the IK joint values (DH products, [000 eq. 3]),
    and the entry rows equal those entries of the coefficient matrices."""
    rng = np.random.default_rng(seed)
    chain, _q = random_chain(rng, model)
    geometry = srs_geometry(chain)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (5, 7)))
    psi = rng.uniform(-np.pi, np.pi, 5)
    coefficients = arm_angle_coefficients(geometry, poses, elbow)
    weights = np.stack([np.sin(psi), np.cos(psi), np.ones(5)], axis=-1)
    shoulder = np.einsum("nk,nkij->nij", weights, coefficients.shoulder)
    wrist = np.einsum("nk,nkij->nij", weights, coefficients.wrist)
    np.testing.assert_allclose(np.einsum("nk,nke->ne", weights, coefficients.entries), entries_of(shoulder, wrist),
                               atol=1e-13)
    branch = geometry.table1_branch(f"+{'+' if elbow > 0 else '-'}+")  # named in the chain's joint senses
    theta = geometry.theta_of_q(ik(geometry, poses, psi, branch))
    np.testing.assert_allclose(shoulder, shoulder_rotation(theta), atol=1e-10)
    np.testing.assert_allclose(wrist, wrist_rotation(theta), atol=1e-10)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31), MODELS)
def test_all_branches_equal_each_branch_alone(seed, model):
    """ik_all_branches (one evaluation per elbow sign, signs applied after) == ik branch by branch."""
    rng = np.random.default_rng(seed)
    chain, _ = random_chain(rng, model)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (6, 7)))
    psi = rng.uniform(-np.pi, np.pi, 6)
    together = ik_all_branches(chain, poses, psi)
    for k, branch in enumerate(BRANCHES):
        np.testing.assert_array_equal(together[:, k], ik(chain, poses, psi, branch))
        assert np.abs(chain.fk(together[:, k]) - poses).max() < 1e-9


@pytest.mark.parametrize("kind", ["shoulder", "wrist", "elbow", "axis", "folded_axis"])
def test_all_branches_equal_each_branch_alone_on_degenerate_poses(kind):
    chain = pa10_7c().with_limits(np.full(7, -4.0), np.full(7, 4.0))
    pose = chain.fk(np.array(degenerate_q(kind)))
    psi = np.array([0.0, 0.7, -np.pi, np.pi / 2])
    together = ik_all_branches(chain, np.broadcast_to(pose, (4, 4, 4)), psi)
    for k, branch in enumerate(BRANCHES):
        np.testing.assert_array_equal(together[:, k], ik(chain, pose, psi, branch))
        assert np.abs(chain.fk(together[:, k]) - pose).max() < 1e-9


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31), MODELS, st.sampled_from([str(b) for b in BRANCHES]), st.booleans())
def test_batched_feasible_sets_equal_looped(seed, model, branch, crossing):
    """feasible_pieces / feasible_arm_angles on a batch == one pose at a time (random limits, crossing +-pi)."""
    rng = np.random.default_rng(seed)
    chain, q = random_chain(rng, model, crossing)
    poses = chain.fk(q + rng.normal(0.0, 0.3, (5, 7)))
    pieces = feasible_pieces(chain, poses, branch)
    batch = feasible_arm_angles_batch(chain, poses, branch)
    for i in range(5):
        alone = feasible_pieces(chain, poses[i], branch)
        np.testing.assert_array_equal(alone.feasible, pieces.feasible[i])
        np.testing.assert_array_equal(alone.start, pieces.start[i])
        single = feasible_arm_angles(chain, poses[i], branch)
        assert single.feasible == batch[i].feasible == pieces.arc_set((i,))
        assert all(single.per_joint[j] == batch[i].per_joint[j] for j in range(1, 8))


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31), MODELS, st.sampled_from([str(b) for b in BRANCHES]), st.booleans())
def test_cut_points_are_where_a_joint_meets_a_limit(seed, model, branch, crossing):
    """Every root of the cached limit-equation matrix puts its joint on the limit ([000 eqs. 21, 22])."""
    rng = np.random.default_rng(seed)
    chain, q = random_chain(rng, model, crossing)
    geometry = srs_geometry(chain)
    pose = chain.fk(q)
    coefficients = arm_angle_coefficients(geometry, pose, geometry.table1_branch(branch).elbow)
    equations, cuts = np.empty((3, 12)), np.empty(24)
    _feasible_kernels.limit_equations(coefficients.entries, limit_tables(geometry).equations, equations)
    _feasible_kernels.cut_points(equations, cuts)
    cuts = cuts.reshape(6, 4)
    for k, joint in enumerate(PSI_JOINTS):
        limits = np.repeat([geometry.theta_lower[joint - 1], geometry.theta_upper[joint - 1]], 2)
        found = ~np.isnan(cuts[k])
        if not geometry.theta_limited[joint - 1]:
            assert not found.any()
            continue
        if not found.any():
            continue
        theta = geometry.theta_of_q(ik(geometry, pose, cuts[k][found], branch))[:, joint - 1]
        if _IS_COSINE[k]:  # theta = +-L
            residual = np.cos(theta) - np.cos(limits[found])
        else:  # theta = L or L + pi, or the joint is singular there
            residual = np.sin(theta - limits[found])
        assert np.abs(residual).max() < 1e-7


def test_feasible_set_finds_a_tight_arc_around_a_known_solution():
    """+-0.001 rad limits around a known solution: the one-pose fast path still finds its arc."""
    chain = pa10_7c()
    q = np.array([0.4, 0.8, -0.3, 1.1, 0.6, -0.7, 0.2])
    tight = chain.with_limits(q - 1e-3, q + 1e-3)
    state = arm_angle_of(tight, q)
    result = feasible_arm_angles(tight, chain.fk(q), str(state.branch_strings()))
    assert not result.is_empty and result.feasible.contains(float(state.psi), tolerance=1e-12)
    pieces = feasible_pieces(tight, chain.fk(q), str(state.branch_strings()))
    assert pieces.arc_set() == result.feasible


def test_limit_tables_are_built_once_per_geometry():
    geometry = srs_geometry(pa10_7c())
    assert geometry.psi_joint_limits is geometry.psi_joint_limits
    assert not geometry.psi_joint_limits.weights.flags.writeable


WIDTHS = st.one_of(st.floats(1e-3, 7.0), st.sampled_from([np.pi, np.pi / 2, 2 * np.pi - 1e-6, 2 * np.pi]))


@settings(max_examples=150, deadline=None)
@given(st.integers(0, 2**31), st.lists(st.floats(-2 * np.pi, 2 * np.pi), min_size=7, max_size=7),
       st.lists(WIDTHS, min_size=7, max_size=7))
@example(0, [2 * np.pi - 1e-15] + [0.0] * 6, [np.pi] + [1.0] * 6)  # limits pi apart: their zeros differ by rounding
def test_limit_equation_signs_decide_joint_membership(seed, lower, width):
    """Off its cut points a joint's limit membership is read from the signs of its two limit equations.

    Law: for DH angles theta on any branch and any box limits (narrow, wider
    than pi, exactly pi, crossing +-pi, unlimited), the membership table
    looked up with the signs of the limit equations evaluated at the entries
    of ``0R3(theta)`` and ``4R7(theta)`` equals the chain's own limit check.
    """
    lower = np.array(lower)
    chain = pa10_7c().with_limits(lower, lower + np.array(width))
    geometry = srs_geometry(chain)
    limits = geometry.psi_joint_limits
    theta = np.random.default_rng(seed).uniform(-np.pi, np.pi, (400, 7))
    entries = entries_of(shoulder_rotation(theta), wrist_rotation(theta))
    values = (entries @ limits.weights + limits.offset[2]).reshape(-1, 6, 2)
    expected = chain.joints_within_limits(theta, wrap=True)[:, [j - 1 for j in PSI_JOINTS]]
    away = np.all(np.abs(values) > 1e-9, axis=(1, 2))  # not on a cut point
    positive = values > 0
    for sigma_2 in (1, -1):
        for sigma_6 in (1, -1):
            rows = away & (np.sign(theta[:, 1]) == sigma_2) & (np.sign(theta[:, 5]) == sigma_6)
            table = limits.membership[int(sigma_2 < 0), int(sigma_6 < 0)].reshape(6, 4)
            looked_up = table[np.arange(6), 2 * positive[rows, :, 0] + positive[rows, :, 1]]
            np.testing.assert_array_equal(looked_up, expected[rows])


@pytest.mark.parametrize(
    "mutate",
    [
        lambda p: p[:3],  # wrong shape
        lambda p: np.where(np.arange(16).reshape(4, 4) == 5, np.nan, p),  # NaN
        lambda p: p + np.diag([0, 0, 0, 0.1]),  # last row
        lambda p: p @ np.diag([1.0, 1.0, 1.1, 1.0]),  # not orthonormal
        lambda p: p @ np.diag([1.0, 1.0, -1.0, 1.0]),  # reflection (det -1)
    ],
)
def test_pose_errors_match_the_shared_validator(mutate):
    """The lean pose check of the srs entry points raises what redkin._validation.check_pose raises."""
    chain = pa10_7c()
    bad = mutate(chain.fk(np.full(7, 0.3)))
    with pytest.raises(ValueError) as expected:
        check_pose(bad, "pose")
    for call in (lambda: feasible_pieces(chain, bad), lambda: ik(chain, bad, 0.0),
                 lambda: ik_all_branches(chain, bad, 0.0)):
        with pytest.raises(ValueError) as raised:
            call()
        assert str(raised.value) == str(expected.value)


def test_base_tool_offsets_and_signs_take_the_same_fast_path():
    """A chain with base, tool, joint offsets and flipped signs: all-branch IK equals per-branch IK and FK closes."""
    base = pose_from(np.array([0.1, -0.2, 0.3]), rot_x(0.4))
    chain = pa10_7c().with_base(base).with_tool(pose_from(np.array([0.0, 0.0, 0.12]), np.eye(3)))
    rng = np.random.default_rng(3)
    poses = chain.fk(rng.uniform(-2, 2, (20, 7)))
    together = ik_all_branches(chain, poses, 0.25)
    for k, branch in enumerate(BRANCHES):
        np.testing.assert_array_equal(together[:, k], ik(chain, poses, 0.25, branch))
    assert np.abs(chain.fk(together) - poses[:, None]).max() < 1e-9


def test_empty_batches_give_empty_results():
    chain = pa10_7c()
    none = np.zeros((0, 4, 4))
    pieces = feasible_pieces(chain, none, "+-+")
    assert pieces.start.shape[0] == 0 and pieces.feasible.shape[0] == 0
    assert ik_all_branches(chain, none, 0.3).shape == (0, 8, 7)
    assert ik(chain, none, 0.3, "+++").shape == (0, 7)
