"""Closed-form IK of Franka-class arms at a given q7 (redkin.franka.ik, [F1]-[F7]).

Laws, on the models and random arms of the class: every row that exists reaches its pose to 1e-9 by our FK; the
joint values a pose came from are among the rows at their own q7, in the row of their own branch (as the module
docstring names branches: the signs of ``q_2``, of ``theta_4 - phi`` and of ``cos q_5``); a batch equals its items
one by one, q7 broadcasts against the poses, ``branch=`` gives that row, ``within_limits`` is the chain's own check of
the row; a row that does not exist is zeros, never NaN; an unreachable pose has no rows and raises nothing; bad
input raises ``ValueError``.  The same FK law holds on purpose at the degenerate configurations: the shoulder at
and near ``q_2 = 0``, the wrist point on the joint-1 axis, the elbow stretched and folded, axes 5 and 7 parallel,
and a q7 at which a branch appears or vanishes.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares

from redkin.chain import SerialChain
from redkin.franka import BRANCHES, PARAMETER, Q7Solutions, franka_geometry, ik
from redkin.models import get_robot
from redkin.srs.branches import Branch
from tests.support.franka_arms import MODELS, branch_index, other_conventions, random_arm, random_pose

ROUND_TRIP = 1e-9
TURN = 2.0 * np.pi


def wrap(angle):
    """``angle`` wrapped to [-pi, pi)."""
    return np.mod(np.asarray(angle) + np.pi, TURN) - np.pi


def check_solutions(chain: SerialChain, solutions: Q7Solutions, poses: np.ndarray) -> float:
    """The laws every result obeys; returns the largest FK error of a row that exists.

    Rows that exist reach their pose to :data:`ROUND_TRIP`; rows that do not are zeros; nothing is NaN;
    ``within_limits`` is the chain's own check of an existing row; the parameter is q7.
    """
    q, exists = solutions.q, solutions.exists
    assert not np.isnan(q).any()
    assert np.all(q[~exists] == 0.0)
    # the chain's own check, but for a slack of 1e-12 rad at the limits (redkin.srs._ik_kernels.MEMBERSHIP_TOLERANCE)
    assert np.all(solutions.within_limits <= exists & chain.within_limits(q, tolerance=1e-12))
    assert np.all(exists & chain.within_limits(q) <= solutions.within_limits)
    assert solutions.parameter == PARAMETER == "q7"
    poses = np.broadcast_to(poses, q.shape[:-2] + (4, 4))
    error = np.abs(chain.fk(q) - poses[..., None, :, :]).max(axis=(-1, -2))
    worst = float(error[exists].max(initial=0.0))
    assert worst < ROUND_TRIP, worst
    return worst


def distance_to_rows(chain: SerialChain, rows: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Largest joint difference (..., B) of ``q`` (..., 7) from each row, modulo 2 pi for a range wider than 2 pi
    or a value out of range (IK returns the representative in range, or one in ``[-pi, pi)``)."""
    difference = rows - q[..., None, :]
    wide = ((chain.upper - chain.lower) > TURN) | ~chain.joints_within_limits(q)[..., None, :]
    return np.abs(np.where(wide, wrap(difference), difference)).max(axis=-1)


def conditioned(chain: SerialChain, q: np.ndarray, tolerance: float) -> np.ndarray:
    """``tolerance``, or where q is nearly singular at fixed q7 the accuracy its conditioning allows:
    ``1e-13 / sigma``, ``sigma`` the least singular value of the Jacobian of joints 1-6 (measured on 10^5 random
    in-limit q of each model and 1.3 x 10^5 of random arms: error x sigma <= 1.4e-14; 1 to 4 in 10^5 of the
    models' q need more than 1e-9, all with sigma < 1e-7)."""
    sigma = np.linalg.svd(chain.jacobian(q)[..., :6], compute_uv=False)[..., -1]
    return np.maximum(tolerance, 1e-13 / np.maximum(sigma, 1e-300))


def assert_q_in_its_own_row(chain: SerialChain, q: np.ndarray, tolerance: float = 1e-9) -> Q7Solutions:
    """IK at q's own pose and q7 has q in the row of q's branch (:func:`branch_index`), to ``tolerance``
    (:func:`conditioned`)."""
    poses = chain.fk(q)
    solutions = ik(chain, poses, q[..., 6])
    check_solutions(chain, solutions, poses)
    own = branch_index(franka_geometry(chain), q)
    distance = distance_to_rows(chain, solutions.q, q)
    assert np.all(np.take_along_axis(solutions.exists, own[..., None], -1))
    mine = np.take_along_axis(distance, own[..., None], -1)[..., 0]
    assert np.all(mine < conditioned(chain, q, tolerance)), mine.max()
    return solutions


# ----------------------------------------------------------------------------- the laws on random inputs
@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**31), name=st.sampled_from(MODELS))
def test_every_row_reaches_the_pose_and_q_is_in_its_own_row(seed, name):
    chain = get_robot(name)
    rng = np.random.default_rng(seed)
    q = rng.uniform(chain.lower, chain.upper, (400, 7))
    solutions = assert_q_in_its_own_row(chain, q)
    assert np.all((solutions.q[..., 6] == q[:, 6:7]) | ~solutions.exists)  # q7 as given, even past +-pi (xArm7)
    # the branches as the docstring names them, in the user's own values: sign q_2, theta_4 - phi, sign cos q_5
    geometry = franka_geometry(chain)
    elbow = wrap(geometry.form.offset[3] + q[:, 3] - geometry.kernel_arm[9])
    expected = np.where(np.stack([q[:, 1], elbow, np.cos(q[:, 4])], axis=-1) >= 0.0, 1, -1)
    assert np.array_equal(np.array(BRANCHES)[branch_index(geometry, q)], expected)
    # and some other q7 of the same poses: every row still reaches them
    poses = chain.fk(q[:50])
    q7 = rng.uniform(chain.lower[6], chain.upper[6], 50)
    solutions = ik(chain, poses, q7)
    check_solutions(chain, solutions, poses)
    assert np.all((solutions.q[..., 6] == q7[:, None]) | ~solutions.exists)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31), zero_elbow=st.booleans(), zero_d6=st.booleans())
def test_random_arms_in_random_conventions(seed, zero_elbow, zero_d6):
    rng = np.random.default_rng(seed)
    arm = random_arm(rng, zero_elbow=zero_elbow, zero_d6=zero_d6)
    for chain in (arm, *other_conventions(arm, rng).values()):
        assert_q_in_its_own_row(chain, rng.uniform(-np.pi, np.pi, (60, 7)))
        poses = np.stack([random_pose(rng) for _ in range(20)])  # most unreachable at most q7: no rows, no error
        check_solutions(chain, ik(chain, poses, rng.uniform(-np.pi, np.pi, 20)), poses)


def test_the_eight_rows_are_eight_solutions_where_all_exist():
    """A pose of the Panda with all eight branches at its q7: eight distinct rows, each on its own branch."""
    chain = get_robot("franka-panda")
    q = np.array([0.55, -0.57, -0.63, -0.4, -1.58, 2.33, -2.41])
    solutions = ik(chain, chain.fk(q), q[6])
    assert solutions.exists.all() and solutions.branches == BRANCHES
    assert np.array_equal(branch_index(franka_geometry(chain), solutions.q), np.arange(8))
    gaps = np.abs(solutions.q[:, None] - solutions.q[None]).max(axis=-1)
    assert gaps[~np.eye(8, dtype=bool)].min() > 1e-3
    assert np.all(solutions.q[:, 6] == q[6])


@pytest.mark.parametrize("name", MODELS)
def test_a_batch_equals_its_items_and_q7_broadcasts(name):
    chain = get_robot(name)
    rng = np.random.default_rng(11)
    q = rng.uniform(chain.lower, chain.upper, (6, 7))
    poses = chain.fk(q)
    q7 = rng.uniform(chain.lower[6], chain.upper[6], (3, 1))
    batch = ik(chain, poses, q7)  # (3, 1) against (6,): (3, 6)
    assert batch.q.shape == (3, 6, 8, 7) and batch.exists.shape == batch.within_limits.shape == (3, 6, 8)
    check_solutions(chain, batch, poses)
    for m in range(3):
        for n in range(6):
            one = ik(chain, poses[n], q7[m, 0])
            assert one.q.shape == (8, 7)
            assert np.array_equal(one.q, batch.q[m, n]) and np.array_equal(one.exists, batch.exists[m, n])
            assert np.array_equal(one.within_limits, batch.within_limits[m, n])
    scalar = ik(chain, poses, float(q7[0, 0]))  # one q7 for every pose
    assert np.array_equal(scalar.q, batch.q[0])
    many = ik(chain, poses[2], q7[:, 0])  # one pose at many q7
    assert np.array_equal(many.q, batch.q[:, 2])
    nested = ik(chain, poses.reshape(2, 3, 4, 4), q[:, 6].reshape(2, 3))
    assert np.array_equal(nested.q.reshape(6, 8, 7), ik(chain, poses, q[:, 6]).q)


def test_one_pose_answers_alike_however_its_pose_and_q7_are_given():
    """One pose takes a float64 array and a float q7 as they are, and converts anything else first: a list, a
    read-only or strided array, an integer, a numpy scalar or a 0-d array give the same rows."""
    chain = get_robot("franka-panda")
    pose = chain.fk(np.array([0.1, 0.3, 0.2, -1.5, 0.1, 1.5, 1.0]))
    expected = ik(chain, pose, 1.0)
    frozen = pose.copy()
    frozen.flags.writeable = False
    strided = np.asfortranarray(pose)
    for target, q7 in ((pose.tolist(), 1.0), (frozen, 1.0), (strided, 1.0), (pose, 1), (pose, np.float64(1.0)),
                      (pose, np.array(1.0)), (pose, np.float32(1.0)), (pose, True)):
        one = ik(chain, target, q7)
        assert np.array_equal(one.q, expected.q) and np.array_equal(one.exists, expected.exists)
        assert np.array_equal(one.within_limits, expected.within_limits)


@pytest.mark.parametrize("name", MODELS)
def test_a_branch_gives_its_row(name):
    chain = get_robot(name)
    rng = np.random.default_rng(12)
    q = rng.uniform(chain.lower, chain.upper, (40, 7))
    poses = chain.fk(q)
    every = ik(chain, poses, q[:, 6])
    for index, branch in enumerate(BRANCHES):
        text = "".join("+" if s > 0 else "-" for s in branch)
        for given_as in (text, branch, tuple(branch), Branch(*branch)):
            one = ik(chain, poses, q[:, 6], branch=given_as)
            assert one.branches == (branch,) and one.q.shape == (40, 1, 7)
            assert np.array_equal(one.q[:, 0], every.q[:, index])
            assert np.array_equal(one.exists[:, 0], every.exists[:, index])
            assert np.array_equal(one.within_limits[:, 0], every.within_limits[:, index])


def test_an_unreachable_pose_has_no_rows_and_raises_nothing():
    chain = get_robot("franka-panda")
    far = np.eye(4)
    far[:3, 3] = [2.0, 0.0, 0.3]  # 2 m away: the Panda reaches about 1 m
    poses = np.stack([far, chain.fk(np.array([0.1, 0.3, 0.0, -1.5, 0.0, 1.5, 0.3]))])
    solutions = ik(chain, poses, 0.3)
    check_solutions(chain, solutions, poses)
    assert not solutions.exists[0].any() and not solutions.within_limits[0].any()
    assert np.all(solutions.q[0] == 0.0) and solutions.exists[1].any()
    assert not ik(chain, far, np.linspace(-3.0, 3.0, 50)).exists.any()
    empty = ik(chain, np.zeros((0, 4, 4)), 0.0)
    assert empty.q.shape == (0, 8, 7) and empty.exists.shape == (0, 8)


def _bad_rotation() -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] *= 1.01
    return pose


def _with_nan() -> np.ndarray:
    pose = np.eye(4)
    pose[0, 3] = np.nan
    return pose


@pytest.mark.parametrize("pose, q7, branch, message", [
    (np.eye(3), 0.0, None, "pose"),
    (np.zeros((2, 4, 3)), 0.0, None, "pose"),
    (_with_nan(), 0.0, None, "pose"),
    (_bad_rotation(), 0.0, None, "pose"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), 0.0, None, "pose"),  # a reflection, not a rotation
    (np.eye(4), np.nan, None, "q7"),
    (np.eye(4), np.inf, None, "q7"),
    (np.eye(4), [0.0, np.nan], None, "q7"),
    (np.eye(4), "a", None, "q7"),
    (np.eye(4), [[0.0], [0.0, 1.0]], None, "q7 must be numeric"),  # ragged: one pose, converted first
    (np.stack([np.eye(4)] * 2), np.zeros(3), None, "broadcast"),  # shapes that do not broadcast
    (np.eye(4), 0.0, "++", "branch"),
    (np.eye(4), 0.0, "+x+", "branch"),
    (np.eye(4), 0.0, (1, 0, 1), "branch"),
    (np.eye(4), 0.0, 5, "branch"),
])
def test_bad_input_is_a_value_error(pose, q7, branch, message):
    chain = get_robot("franka-fr3")
    with pytest.raises(ValueError, match=message):
        ik(chain, pose, q7, branch)


# ----------------------------------------------------------------------------- degenerate configurations
@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("q2", [0.0, 1e-6, -1e-6, 1e-9, -1e-9, 1e-12])
def test_the_shoulder_at_and_near_q2_zero(name, q2):
    chain = get_robot(name)
    rng = np.random.default_rng(13)
    q = rng.uniform(chain.lower, chain.upper, (200, 7))
    q[:, 1] = q2
    poses = chain.fk(q)
    solutions = ik(chain, poses, q[:, 6])
    check_solutions(chain, solutions, poses)
    # both shoulder branches exist (sin theta_2 = 0 has both signs) and one row of each has |q_2| <= |q2| + 1e-9
    own = branch_index(franka_geometry(chain), q)
    for shoulder_flip in (0, 4):
        index = own ^ shoulder_flip  # BRANCHES: index 4 shoulder + 2 elbow + wrist, bit set for a minus
        assert np.all(np.take_along_axis(solutions.exists, index[:, None], -1))
        rows = np.take_along_axis(solutions.q, index[:, None, None], 1)[:, 0]
        assert np.abs(np.abs(rows[:, 1]) - abs(q2)).max() < 1e-9
    if abs(q2) >= 1e-6:  # away from the singularity q itself comes back (its error grows as eps / |q_2|)
        assert_q_in_its_own_row(chain, q, tolerance=1e-8)


def _wrist_point(geometry, q: np.ndarray) -> np.ndarray:
    """W, where axes 5 and 6 meet: frame 5's origin of the standard DH form (``a_5 = 0``), in the world."""
    return geometry.form.frames(q)[..., 5, :3, 3]


@pytest.mark.parametrize("name", MODELS)
def test_the_wrist_point_on_the_joint_1_axis(name):
    chain = get_robot(name)
    geometry = franka_geometry(chain)
    rng = np.random.default_rng(14)
    axis_point, axis = chain.base[:3, 3], geometry.form.base[:3, 2]
    q_all = []
    for _ in range(20):
        q = rng.uniform(chain.lower, chain.upper)

        def off_axis(x, q=q):
            q = q.copy()
            q[1:3] = x
            across = _wrist_point(geometry, q) - axis_point
            return (across - (across @ axis) * axis)[:2] if abs(axis[2]) > 0.5 else np.cross(across, axis)[:2]

        found = least_squares(off_axis, q[1:3], xtol=1e-15, ftol=1e-15, gtol=1e-15)
        q[1:3] = found.x
        across = _wrist_point(geometry, q) - axis_point
        if np.linalg.norm(np.cross(across, axis)) < 1e-13:
            q_all.append(q)
    assert len(q_all) >= 10
    q = np.array(q_all)
    poses = chain.fk(q)
    solutions = ik(chain, poses, q[:, 6])
    check_solutions(chain, solutions, poses)
    distance = np.where(solutions.exists, distance_to_rows(chain, solutions.q, q), np.inf)
    assert np.all(distance.min(axis=-1) < conditioned(chain, q, 1e-9))


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("fold", [0.0, np.pi])
def test_the_elbow_stretched_and_folded(name, fold):
    """q_4 at either end of the elbow's reach: ``theta_4 = phi`` (longest) or ``phi + pi`` (shortest), where the
    two elbow branches meet."""
    chain = get_robot(name)
    geometry = franka_geometry(chain)
    rng = np.random.default_rng(15)
    q = rng.uniform(chain.lower, chain.upper, (100, 7))
    q[:, 3] = wrap(geometry.kernel_arm[9] + fold - geometry.form.offset[3])
    poses = chain.fk(q)
    solutions = ik(chain, poses, q[:, 6])
    check_solutions(chain, solutions, poses)
    own = branch_index(geometry, q)
    for elbow_flip in (0, 2):  # both elbow branches of q's shoulder and wrist exist and hold q_4 (acos at +-1)
        index = own ^ elbow_flip  # BRANCHES: index 4 shoulder + 2 elbow + wrist, bit set for a minus
        assert np.all(np.take_along_axis(solutions.exists, index[:, None], -1))
        rows = np.take_along_axis(solutions.q, index[:, None, None], 1)[:, 0]
        assert np.abs(wrap(rows[:, 3] - q[:, 3])).max() < 1e-6
    reach = np.sqrt(geometry.kernel_arm[7] + np.cos(fold) * geometry.kernel_arm[8])
    assert np.allclose(np.linalg.norm(_wrist_point(geometry, q) - geometry.form.frames(q)[:, 2, :3, 3], axis=-1),
                       reach, atol=1e-12)


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("turn", [0.0, np.pi])
def test_axes_5_and_7_parallel(name, turn):
    """theta_6 = 0 or pi: axes 5 and 7 (both perpendicular to axis 6) parallel."""
    chain = get_robot(name)
    geometry = franka_geometry(chain)
    rng = np.random.default_rng(16)
    q = rng.uniform(chain.lower, chain.upper, (200, 7))
    q[:, 5] = wrap(turn - geometry.form.offset[5])
    directions, _ = chain.joint_axes(q)
    assert np.abs(np.abs(np.einsum("ij,ij->i", directions[:, 4], directions[:, 6])) - 1.0).max() < 1e-12
    poses = chain.fk(q)
    check_solutions(chain, ik(chain, poses, q[:, 6]), poses)
    assert_q_in_its_own_row(chain, q, tolerance=1e-8)


def _existence_changes(chain, pose, low, high, count=4001):
    """``(a, c, b)``: branch ``b`` appears or vanishes between the adjacent floats ``a`` and ``c`` (bisected to the
    rounding) on ``[low, high]``."""
    grid = np.linspace(low, high, count)
    exists = ik(chain, pose, grid).exists
    changes = []
    for k, b in zip(*np.nonzero(exists[1:] != exists[:-1])):
        a, c = grid[k], grid[k + 1]
        state = exists[k, b]
        while True:
            middle = 0.5 * (a + c)
            if middle in (a, c):
                break
            if ik(chain, pose, middle, BRANCHES[b]).exists[0] == state:
                a = middle
            else:
                c = middle
        changes.append((a, c, b))
    return changes


@pytest.mark.parametrize("name", MODELS)
def test_a_q7_at_which_a_branch_appears_or_vanishes(name):
    chain = get_robot(name)
    rng = np.random.default_rng(17)
    found = 0
    for _ in range(30):
        pose = chain.fk(rng.uniform(chain.lower, chain.upper))
        for a, c, b in _existence_changes(chain, pose, -np.pi, np.pi):
            found += 1
            q7 = np.array([a, c, np.nextafter(a, -np.inf), np.nextafter(c, np.inf), a - 1e-12, c + 1e-12,
                           a - 1e-9, c + 1e-9])
            solutions = ik(chain, pose, q7)
            check_solutions(chain, solutions, pose)
            assert solutions.exists[0, b] != solutions.exists[1, b]  # the branch exists on one side only
        if found >= 8:
            break
    assert found >= 8
