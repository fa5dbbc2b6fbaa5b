"""The compiled kernels of redkin.torso_arm equal definitional numpy references; batches equal loops;
a batch computed in chunks (any split, any thread count) equals it computed in one call, bit for bit.

The references below are the slow, literal forms of thesis 001's equations
(products of vectors as arrays, the stacked 6 x 9 Jacobian's determinant,
Jacobians from the chain): they live here only, as what the kernels must equal.
"""

import numpy as np
import pytest

from redkin import _compiled
from redkin._compiled import PARALLEL_BATCH, run_batch, set_threads
from redkin.torso_arm import humanoid_arm, position_ik_from_theta1, shoulder_angle, theta1_from_shoulder_angle
from redkin.torso_arm.branches import POSITION_BRANCHES, wrap_angle, wrap_to_limits
from redkin.torso_arm.elbow_angle import ElbowReference, elbow_circle, elbow_position, reference_direction
from redkin.torso_arm.geometry import ELBOW_FRAME, SHOULDER_FRAME, WRIST_FRAME, TorsoArm
from redkin.torso_arm.manipulability import (
    _wrist_jacobian_from_joints,
    _wrist_manipulability,
    gram_manipulability,
    stacked_dual_manipulability,
)
from redkin.torso_arm.maps import (
    _best_points,
    _lengths,
    _limits,
    _torso_mirror,
    best_over_redundancy,
    states,
)
from redkin.torso_arm.position_ik import joints_from_points

ARM = humanoid_arm()


def _postures(count, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(ARM.chain.lower[:5], ARM.chain.upper[:5], (count, 5))
    q = np.concatenate([q, np.zeros((count, 3))], axis=-1)
    frames = ARM.chain.frames(q)
    return q, frames[:, SHOULDER_FRAME, :3, 3], frames[:, ELBOW_FRAME, :3, 3], frames[:, WRIST_FRAME, :3, 3]


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# ------------------------------------------------------------ section 3.2: psi
def _psi_basis(wrist):
    """n, e1 (+x orthogonal to n), e2 = n x e1."""
    n = _unit(wrist)
    e1 = _unit(np.array([1.0, 0.0, 0.0]) - n[..., :1] * n)
    return n, e1, np.cross(n, e1)


def test_shoulder_angle_is_the_turn_of_the_shoulder_about_the_neck_wrist_axis():
    _, _, _, wrist = _postures(300, 0)
    theta1 = np.random.default_rng(1).uniform(-1.5, 1.5, 300)
    _n, e1, e2 = _psi_basis(wrist)
    s = ARM.shoulder(theta1)
    reference = np.arctan2(np.sum(s * e2, axis=-1), np.sum(s * e1, axis=-1))
    np.testing.assert_allclose(shoulder_angle(theta1, wrist, ARM.L0), reference, rtol=0, atol=1e-13)
    back, defined = theta1_from_shoulder_angle(reference, wrist)
    assert defined.all()
    np.testing.assert_allclose(back, theta1, rtol=0, atol=1e-12)
    undefined, ok = theta1_from_shoulder_angle([0.3], [[0.4, 0.0, 0.2]])  # W_y = 0
    assert not ok[0] and np.isnan(undefined[0])


# ------------------------------------------------------- section 3.3: the elbow
def test_elbow_circle_reference_and_position_equal_their_definitions():
    q, shoulder, elbow, wrist = _postures(400, 2)
    circle = elbow_circle(ARM, shoulder, wrist)
    length = np.linalg.norm(wrist - shoulder, axis=-1)
    cos_s = (ARM.L1**2 + length**2 - ARM.forearm**2) / (2 * ARM.L1 * length)  # law of cosines in SEW
    n = (wrist - shoulder) / length[:, None]
    np.testing.assert_allclose(circle.length, length, rtol=0, atol=1e-15)
    np.testing.assert_allclose(circle.centre, shoulder + n * (ARM.L1 * cos_s)[:, None], rtol=0, atol=1e-14)
    np.testing.assert_allclose(circle.radius, ARM.L1 * np.sqrt(1 - cos_s**2), rtol=0, atol=1e-12)
    assert circle.reachable.all()
    # the true elbow lies on the circle at some phi from a vector reference
    e1, exists = reference_direction(ARM, circle, ElbowReference("vector", (0.2, 1.0, -0.3)))
    v = np.array([0.2, 1.0, -0.3])
    expected = _unit(v - np.sum(v * n, axis=-1, keepdims=True) * n)
    np.testing.assert_allclose(e1, expected, rtol=0, atol=1e-13)
    radial = elbow - circle.centre
    phi = np.arctan2(np.sum(np.cross(e1, radial) * n, axis=-1), np.sum(e1 * radial, axis=-1))
    e2 = np.cross(n, e1)
    literal = circle.centre + circle.radius[:, None] * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    np.testing.assert_allclose(elbow_position(circle, e1, phi), literal, rtol=0, atol=1e-14)
    np.testing.assert_allclose(elbow_position(circle, e1, phi), elbow, rtol=0, atol=1e-12)
    # theta4 reference: where it exists, the principal branch there has theta_4 = 0
    e1, exists = reference_direction(ARM, circle, ElbowReference("theta4"))
    joints = joints_from_points(ARM, q[:, 0], elbow_position(circle, e1, 0.0), wrist)
    assert exists.mean() > 0.5
    np.testing.assert_allclose(joints[exists, 0, 3], 0.0, atol=1e-9)


# --------------------------------------------------- sections 3.4.2-3.4.5: joints
def test_joints_from_points_give_back_the_posture_on_its_branch():
    q, _, elbow, wrist = _postures(400, 3)
    joints = joints_from_points(ARM, q[:, 0], elbow, wrist)
    assert joints.shape == (400, len(POSITION_BRANCHES), 5)
    padded = np.concatenate([joints, np.zeros(joints.shape[:-1] + (3,))], axis=-1)
    frames = ARM.chain.frames(padded)
    np.testing.assert_allclose(frames[..., ELBOW_FRAME, :3, 3], np.broadcast_to(elbow[:, None], (400, 4, 3)),
                               atol=1e-12)
    np.testing.assert_allclose(frames[..., WRIST_FRAME, :3, 3], np.broadcast_to(wrist[:, None], (400, 4, 3)),
                               atol=1e-12)
    # the posture's own joints are one of the four branches
    distance = np.abs(wrap_angle(wrap_to_limits(ARM.chain, joints, slice(0, 5)) - q[:, None, :5])).max(axis=-1)
    assert np.all(distance.min(axis=-1) < 1e-9)


# ------------------------------------------------------------ chapter 5: w
def test_wrist_jacobian_and_w_equal_the_chain_and_the_determinant():
    q, *_ = _postures(300, 4)
    jacobian = _wrist_jacobian_from_joints(ARM, q[:, :5])
    chain = ARM.chain.jacobian(q, frame=WRIST_FRAME)[:, :3, :5]
    np.testing.assert_allclose(np.abs(jacobian), np.abs(chain), rtol=0, atol=1e-12)
    literal = np.sqrt(np.maximum(np.linalg.det(jacobian @ np.swapaxes(jacobian, -1, -2)), 0.0))
    np.testing.assert_allclose(gram_manipulability(jacobian), literal, rtol=1e-10, atol=1e-15)
    np.testing.assert_allclose(gram_manipulability(jacobian), _wrist_manipulability(ARM, q), rtol=1e-10, atol=1e-15)


def test_dual_measure_equals_the_determinant_of_the_stacked_jacobian():
    rng = np.random.default_rng(5)
    right, left = rng.normal(size=(200, 3, 5)), rng.normal(size=(200, 3, 5))
    left[:20, :, 1:] = left[:20, :, 1:2]  # singular joint 2-5 blocks: the adjugate form holds there too
    stacked = np.zeros((200, 6, 9))
    stacked[:, :3, 0], stacked[:, 3:, 0] = right[:, :, 0], left[:, :, 0]
    stacked[:, :3, 1:5], stacked[:, 3:, 5:] = right[:, :, 1:], left[:, :, 1:]
    # w^2; 0 = rounding on the singular ones
    literal = np.maximum(np.linalg.det(stacked @ np.swapaxes(stacked, -1, -2)), 0.0)
    squared = stacked_dual_manipulability(right, left) ** 2
    np.testing.assert_allclose(squared, literal, rtol=1e-9, atol=1e-10 * literal.max())
    assert np.all(squared[:20] < 1e-10 * literal.max())


# --------------------------------------------------------- the maps' kernel
def _best_reference(arm, point, samples, within, dual=False):
    """Best w at one wrist by the public IK (theta_1, phi from +y) and the chain's Jacobian: the definition."""
    lower, upper = max(arm.chain.lower[0], -np.pi), min(arm.chain.upper[0], np.pi)
    thetas = np.linspace(lower, upper, samples[0])
    phis = np.linspace(-np.pi, np.pi, samples[1], endpoint=False)
    best, reached = -np.inf, False
    for theta1 in thetas:
        for phi in phis:
            sol = position_ik_from_theta1(arm, point, theta1, phi, reference="vector")
            ok = bool(sol.ok)
            usable = bool(sol.within_limits.any()) if within else ok
            if dual and ok:
                left = TorsoArm(arm.right_chain, "left")
                other = position_ik_from_theta1(left, _torso_mirror(theta1, point), theta1, phi, reference="vector")
                ok = bool(other.ok)
                usable = usable and (bool(other.within_limits.any()) if within else ok)
            reached = reached or ok
            if not usable:
                continue
            q = np.concatenate([sol.q[0], np.zeros(3)])
            jr = ARM.chain.jacobian(q, frame=WRIST_FRAME)[:3, :5]
            if dual:
                ql = np.concatenate([other.q[0], np.zeros(3)])
                jl = left.chain.jacobian(ql, frame=WRIST_FRAME)[:3, :5]
                stacked = np.zeros((6, 9))
                stacked[:3, 0], stacked[3:, 0], stacked[:3, 1:5], stacked[3:, 5:] = (
                    jr[:, 0], jl[:, 0], jr[:, 1:], jl[:, 1:]
                )
                w = np.sqrt(max(np.linalg.det(stacked @ stacked.T), 0.0))
            else:
                w = np.sqrt(max(np.linalg.det(jr @ jr.T), 0.0))
            best = max(best, w)
    return (best if np.isfinite(best) else np.nan), reached


@pytest.mark.parametrize("side,dual,within", [("right", False, True), ("left", False, True), ("right", False, False),
                                              ("right", True, True)])
def test_best_over_redundancy_equals_the_max_over_the_samples_by_the_public_ik(side, dual, within):
    arm = humanoid_arm(side)
    rng = np.random.default_rng(6)
    x = 1.0 if side == "right" else -1.0
    points = np.stack([x * rng.uniform(0.1, 0.8, 6), rng.uniform(-0.6, 0.6, 6), rng.uniform(-0.5, 0.5, 6)], axis=-1)
    samples = (5, 7)
    best, reached = best_over_redundancy(arm, points, samples, within_limits=within, dual=dual)
    for i, point in enumerate(points):
        expected, hit = _best_reference(arm, point, samples, within, dual)
        assert reached[i] == hit
        np.testing.assert_allclose(best[i], expected, rtol=1e-10, atol=1e-14, equal_nan=True)
    assert np.isfinite(best).any()


def test_best_over_redundancy_batched_equals_looped():
    points = np.random.default_rng(7).uniform([-0.2, -0.7, -0.6], [1.0, 0.7, 0.6], (40, 3))
    for dual in (False, True):
        best, reached = best_over_redundancy(ARM, points.reshape(8, 5, 3), (4, 6), dual=dual)
        for i, point in enumerate(points):
            one, hit = best_over_redundancy(ARM, point, (4, 6), dual=dual)
            assert one.shape == () and hit == reached.reshape(-1)[i]
            np.testing.assert_array_equal(one, best.reshape(-1)[i])


def _one_call(kernel, count, *args):
    kernel(0, count, *args)


def _odd_chunks(kernel, count, *args):
    for start, stop in ((0, 1), (1, 38), (38, 38), (38, count - 1), (count - 1, count)):
        kernel(start, stop, *args)


def _three_threads(kernel, count, *args):
    try:
        set_threads(3)
        run_batch(kernel, count, *args)
    finally:
        set_threads(None)


#: A batch kernel run in one call, in odd chunks in this thread, and in chunks on three threads.
_SPLITS = (_one_call, _odd_chunks, _three_threads)


def _kernel_arguments(count):
    points = np.random.default_rng(8).uniform([-0.2, -0.7, -0.6], [1.0, 0.7, 0.6], (count, 3))
    left = TorsoArm(ARM.right_chain, "left")
    limits = np.ascontiguousarray(np.stack([_limits(ARM), _limits(left)]))
    return points, np.linspace(-1.5, 1.5, 4), np.linspace(-np.pi, np.pi, 5, endpoint=False), limits


@pytest.mark.slow
@pytest.mark.parametrize("dual", [False, True])
def test_best_kernel_in_chunks_equals_one_call_bit_for_bit(dual, monkeypatch):
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    count = 2 * PARALLEL_BATCH + 3
    points, thetas, phis, limits = _kernel_arguments(count)
    results = []
    for run in _SPLITS:
        best, reached = np.empty(count), np.empty(count, dtype=bool)
        run(_best_points, count, points, thetas, phis, _lengths(ARM), np.array([1.0, -1.0]), limits, True, dual, best,
            reached)
        results.append((best, reached))
    for best, reached in results[1:]:
        np.testing.assert_array_equal(results[0][0], best)
        np.testing.assert_array_equal(results[0][1], reached)
    assert np.isfinite(results[0][0]).sum() > count // 4


@pytest.mark.slow
def test_state_kernel_in_chunks_equals_one_call_bit_for_bit(monkeypatch):
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    count = 2 * PARALLEL_BATCH + 3
    points, *_ , limits = _kernel_arguments(count)
    rng = np.random.default_rng(9)
    theta1, phi = rng.uniform(-1.5, 1.5, count), rng.uniform(-np.pi, np.pi, count)
    defined = rng.uniform(size=count) > 0.1
    results = []
    for run in _SPLITS:
        jacobian, status, feasible = np.empty((count, 3, 5)), np.empty(count, dtype=np.int64), np.empty(count, bool)
        run(states, count, points, theta1, defined, phi, _lengths(ARM), 1.0, limits[0], 1, np.zeros(3), jacobian,
            status, feasible)
        results.append((jacobian, status, feasible))
    for other in results[1:]:
        for a, b in zip(results[0], other):
            np.testing.assert_array_equal(a, b)
    assert set(np.unique(results[0][1])) >= {0, 1, 3}


def test_equation_wrappers_batched_equal_looped():
    q, shoulder, elbow, wrist = _postures(20, 10)
    joints = joints_from_points(ARM, q[:, 0], elbow, wrist)
    jacobian = _wrist_jacobian_from_joints(ARM, q[:, :5])
    circle = elbow_circle(ARM, shoulder, wrist)
    for i in range(20):
        np.testing.assert_array_equal(joints_from_points(ARM, q[i, 0], elbow[i], wrist[i]), joints[i])
        np.testing.assert_array_equal(_wrist_jacobian_from_joints(ARM, q[i, :5]), jacobian[i])
        one = elbow_circle(ARM, shoulder[i], wrist[i])
        np.testing.assert_array_equal(one.centre, circle.centre[i])
        np.testing.assert_array_equal(shoulder_angle(q[i, 0], wrist[i]), shoulder_angle(q[:, 0], wrist)[i])


def test_best_over_redundancy_refuses_bad_input():
    with pytest.raises(ValueError, match="points"):
        best_over_redundancy(ARM, [0.1, 0.2])
    with pytest.raises(ValueError, match="samples"):
        best_over_redundancy(ARM, [0.5, 0.2, 0.1], (0, 3))
    with pytest.raises(ValueError, match="right arm"):
        best_over_redundancy(humanoid_arm("left"), [0.5, 0.2, 0.1], dual=True)


def test_measures_refuse_jacobians_of_the_wrong_shape():
    with pytest.raises(ValueError, match="jacobian"):
        gram_manipulability(np.ones((4, 2, 5)))
    with pytest.raises(ValueError, match="jacobians"):
        stacked_dual_manipulability(np.ones((3, 5)), np.ones((3, 4)))
