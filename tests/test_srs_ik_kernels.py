"""The compiled arm-angle IK (redkin.srs._ik_kernels): batches equal single calls, results do not depend on the
thread count or the chunks, the in-kernel pose check agrees with redkin._validation.check_pose, and the
group rotations equal the definitional DH products of [000 eq. 3]."""

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from redkin import _compiled
from redkin._compiled import PARALLEL_BATCH, set_threads
from redkin._validation import check_pose
from redkin.models import pa10_7c
from redkin.srs import BRANCHES, _ik_kernels, feasible_pieces, ik, ik_all_branches, reachable, srs_geometry
from redkin.srs._rotations import group_rotations
from redkin.srs.coefficients import arm_angle_coefficients
from redkin.srs.ik import theta_at
from tests.support.srs_arms import ARM_KINDS, arm, shoulder_rotation, wrist_rotation

KINDS = st.sampled_from(ARM_KINDS)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), KINDS)
def test_batches_equal_single_calls(seed, kind):
    """A batch above PARALLEL_BATCH runs in chunks on the thread pool, one pose in the calling thread: the same
    numbers."""
    rng = np.random.default_rng(seed)
    chain = arm(kind, rng)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (2, PARALLEL_BATCH // 2 + 3, 7)))
    psi = rng.uniform(-np.pi, np.pi, poses.shape[:2])
    together = ik_all_branches(chain, poses, psi)
    coefficients = arm_angle_coefficients(srs_geometry(chain), poses, -1)
    assert together.shape == poses.shape[:2] + (8, 7)
    for i, j in ((0, 0), (1, 41), (1, poses.shape[1] - 1)):
        np.testing.assert_array_equal(together[i, j], ik_all_branches(chain, poses[i, j], psi[i, j]))
        np.testing.assert_array_equal(together[i, j, 5], ik(chain, poses[i, j], psi[i, j], BRANCHES[5]))
        alone = arm_angle_coefficients(srs_geometry(chain), poses[i, j], -1)
        np.testing.assert_array_equal(coefficients.entries[i, j], alone.entries)
        np.testing.assert_array_equal(coefficients.theta4[i, j], alone.theta4)


def test_results_do_not_depend_on_the_thread_count(monkeypatch):
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    chain = pa10_7c().with_limits(np.full(7, -2.5), np.full(7, 2.5))
    rng = np.random.default_rng(4)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (3000, 7)))
    psi = rng.uniform(-np.pi, np.pi, 3000)
    try:
        results = []
        for count in (1, 2, 3):
            set_threads(count)
            coefficients = arm_angle_coefficients(srs_geometry(chain), poses, 1)
            results.append((ik_all_branches(chain, poses, psi), coefficients.entries,
                            theta_at(coefficients, psi, BRANCHES[1]), feasible_pieces(chain, poses, "+-+").start))
    finally:
        set_threads(None)
    for other in results[1:]:
        for one, same in zip(results[0], other):
            np.testing.assert_array_equal(one, same)


def test_a_chunk_of_a_batch_writes_its_rows_alone_and_counts_its_failures():
    """solve_poses computes poses start .. stop - 1 and returns how many of those failed; the chunks' counts add up
    to the batch's.  Each pose's status is its own, a failed pose's rows are zeros and not within the limits, and
    ``within`` is the chain's own check of the rows."""
    chain = pa10_7c()
    geometry = srs_geometry(chain)
    rng = np.random.default_rng(6)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (100, 7)))
    far = chain.fk(np.zeros(7))
    far[:3, 3] *= 9.0  # out of reach
    poses[[3, 50, 51]] = far
    psi = rng.uniform(-np.pi, np.pi, 100)
    whole, parts = np.empty((100, 8, 7)), np.full((100, 8, 7), np.nan)
    within, status = np.empty((100, 8), bool), np.full(100, -1, np.int64)
    arguments = (poses, psi, geometry.kernel_branches, *geometry.kernel_tables)
    assert _ik_kernels.solve_poses(0, 100, *arguments, whole, within, status) == 3
    counts = [_ik_kernels.solve_poses(start, stop, *arguments, parts, np.empty((100, 8), bool),
                                      np.empty(100, np.int64)) for start, stop in ((0, 4), (4, 4), (4, 51), (51, 100))]
    assert counts == [1, 0, 1, 1]
    ok = np.ones(100, bool)
    ok[[3, 50, 51]] = False
    np.testing.assert_array_equal(status, np.where(ok, _ik_kernels.OK, _ik_kernels.UNREACHABLE))
    np.testing.assert_array_equal(parts, whole)
    assert not whole[~ok].any() and not within[~ok].any()
    np.testing.assert_array_equal(whole[ok], ik_all_branches(chain, poses[ok], psi[ok]))
    np.testing.assert_array_equal(within[ok], chain.within_limits(whole[ok], tolerance=1e-12))


POSE_DEFECTS = st.sampled_from(["nan", "inf", "last_row", "scale", "uniform", "shear", "reflection", "tiny", "none"])


@settings(max_examples=80, deadline=None)
@given(st.integers(0, 2**32 - 1), POSE_DEFECTS, st.floats(1e-8, 1e-3))
@example(0, "uniform", 9.8e-7)  # R R^T = I within 9.8e-7 (accepted), det R = 1 + 1.47e-6: only its sign counts
def test_in_kernel_pose_check_agrees_with_check_pose(seed, defect, size):
    """pose_defect flags a pose exactly when redkin._validation.check_pose raises (sizes around the tolerance)."""
    rng = np.random.default_rng(seed)
    pose = pa10_7c().fk(rng.uniform(-np.pi, np.pi, 7))
    entry = tuple(rng.integers(0, 3, 2))
    if defect == "nan":
        pose[entry] = np.nan
    elif defect == "inf":
        pose[entry] = np.inf
    elif defect == "last_row":
        pose[3, rng.integers(0, 4)] += size
    elif defect == "scale":
        pose[:3, rng.integers(0, 3)] *= 1.0 + size
    elif defect == "uniform":  # R R^T - I = (2 e + e^2) I: e = size / 2
        pose[:3, :3] *= 1.0 + size / 2.0
    elif defect == "shear":
        pose[entry] += size
    elif defect == "reflection":
        pose[:3, 0] *= -1.0
    elif defect == "tiny":
        pose[entry] += 1e-9
    try:
        check_pose(pose)
        valid = True
    except ValueError:
        valid = False
    assert (_ik_kernels.pose_defect(pose) == _ik_kernels.OK) == valid


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), KINDS)
def test_group_rotations_equal_the_dh_products(seed, kind):
    """0R3 and 4R7 read from the chain's compiled frames == the products Rz Rx of [000 eq. 3] (written in the test)."""
    rng = np.random.default_rng(seed)
    geometry = srs_geometry(arm(kind, rng))
    q = rng.uniform(-np.pi, np.pi, (6, 7))
    shoulder, wrist = group_rotations(geometry, q)
    theta = geometry.theta_of_q(q)
    np.testing.assert_allclose(shoulder, shoulder_rotation(theta), atol=1e-12)
    np.testing.assert_allclose(wrist, wrist_rotation(theta), atol=1e-12)


def test_errors_name_the_first_bad_pose_of_a_batch():
    chain = pa10_7c()
    poses = chain.fk(np.random.default_rng(0).uniform(-1, 1, (5, 7)))
    far = poses.copy()
    far[3, :3, 3] = [3.0, 0.0, 0.5]
    with pytest.raises(ValueError, match=r"unreachable position: .* \(pose \(3,\); 1 unreachable\)"):
        ik_all_branches(chain, far, 0.0)
    assert reachable(chain, far).tolist() == [True, True, True, False, True]
    with pytest.raises(ValueError, match="psi must be finite"):
        ik(chain, poses, np.array([0.0, 0.1, np.nan, 0.3, 0.4]))
    with pytest.raises(ValueError, match="does not broadcast"):
        ik(chain, poses, np.zeros(3))
    scaled = poses.copy()
    scaled[:, :3, :3] *= 1.1
    with pytest.raises(ValueError, match="pose rotation block must be orthonormal"):
        reachable(chain, scaled)


def test_a_chain_derives_its_geometry_once():
    chain = pa10_7c()
    assert srs_geometry(chain) is srs_geometry(chain)
    assert srs_geometry(chain).kernel_branch("+-+") is srs_geometry(chain).kernel_branch("+-+")
    assert not srs_geometry(chain).kernel_arm.flags.writeable
