"""Laws of serial-chain kinematics for every model."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from redkin.chain import SerialChain, yoshikawa
from redkin.models import HUMANOID_LENGTHS, MODELS, humanoid_left_arm, humanoid_right_arm, pa10_7c
from redkin.so3 import rot_x, rot_z

MODEL_NAMES = list(MODELS)


def transform(rotation=None, translation=(0.0, 0.0, 0.0)):
    out = np.eye(4)
    if rotation is not None:
        out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def explicit_fk(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """Product of 4x4 matrices written from the DH definitions, one joint at a time."""
    pose = chain.base.copy()
    for i in range(chain.n):
        theta = chain.offset[i] + chain.sign[i] * q[i]
        rz, tz = transform(rot_z(theta)), transform(translation=(0, 0, chain.d[i]))
        tx, rx = transform(translation=(chain.a[i], 0, 0)), transform(rot_x(chain.alpha[i]))
        pose = pose @ (rz @ tz @ tx @ rx if chain.convention == "dh" else rx @ tx @ rz @ tz)
    return pose @ chain.tool


def numeric_jacobian(chain: SerialChain, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Central differences of the end position and of the orientation (omega from dR R^T)."""
    jac = np.zeros((6, chain.n))
    rotation = chain.fk(q)[:3, :3]
    for i in range(chain.n):
        step = np.zeros(chain.n)
        step[i] = h
        plus, minus = chain.fk(q + step), chain.fk(q - step)
        jac[:3, i] = (plus[:3, 3] - minus[:3, 3]) / (2 * h)
        omega = (plus[:3, :3] - minus[:3, :3]) / (2 * h) @ rotation.T
        jac[3:, i] = [omega[2, 1], omega[0, 2], omega[1, 0]]
    return jac


def random_q(chain: SerialChain, rng: np.random.Generator, shape=()) -> np.ndarray:
    return rng.uniform(-np.pi, np.pi, shape + (chain.n,))


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_fk_equals_explicit_product_of_transforms(name):
    chain = MODELS[name]()
    rng = np.random.default_rng(1)
    for q in random_q(chain, rng, (20,)):
        np.testing.assert_allclose(chain.fk(q), explicit_fk(chain, q), atol=1e-12)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_jacobian_equals_finite_differences(name):
    chain = MODELS[name]()
    rng = np.random.default_rng(2)
    for q in random_q(chain, rng, (10,)):
        np.testing.assert_allclose(chain.jacobian(q), numeric_jacobian(chain, q), atol=1e-7)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_frame_and_point_jacobians_equal_finite_differences(name):
    chain = MODELS[name]()
    rng = np.random.default_rng(3)
    q = random_q(chain, rng)
    offset = np.array([0.05, -0.02, 0.1])
    h = 1e-6
    for k in range(chain.n + 1):
        jac = chain.jacobian(q, frame=k, offset=offset)[:3]
        numeric = np.zeros((3, chain.n))
        for i in range(chain.n):
            step = np.zeros(chain.n)
            step[i] = h
            point = [f[k, :3, :3] @ offset + f[k, :3, 3] for f in (chain.frames(q + step), chain.frames(q - step))]
            numeric[:, i] = (point[0] - point[1]) / (2 * h)
        np.testing.assert_allclose(jac, numeric, atol=1e-7)
        assert np.all(chain.jacobian(q, frame=k)[:, k:] == 0.0)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_manipulability_is_sqrt_det_and_product_of_singular_values(name):
    chain = MODELS[name]()
    rng = np.random.default_rng(4)
    for q in random_q(chain, rng, (5,)):
        jac = chain.jacobian(q)
        position = jac[:3, : min(5, chain.n)]
        w = chain.manipulability(q, rows=[0, 1, 2], columns=range(min(5, chain.n)))
        np.testing.assert_allclose(w, np.sqrt(max(np.linalg.det(position @ position.T), 0.0)), rtol=1e-8, atol=1e-12)
        np.testing.assert_allclose(w, np.prod(np.linalg.svd(position, compute_uv=False)), rtol=1e-12)
        if chain.n >= 6:
            np.testing.assert_allclose(chain.manipulability(q), np.sqrt(np.linalg.det(jac @ jac.T)), rtol=1e-6)


def test_manipulability_is_zero_for_more_rows_than_columns():
    assert yoshikawa(np.ones((3, 2))) == 0.0


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_batched_equals_looped(name):
    chain = MODELS[name]()
    rng = np.random.default_rng(5)
    q = random_q(chain, rng, (3, 4))
    fk, frames, jac, w = chain.fk(q), chain.frames(q), chain.jacobian(q), chain.manipulability(q, rows=[0, 1, 2])
    assert fk.shape == (3, 4, 4, 4) and frames.shape == (3, 4, chain.n + 2, 4, 4)
    for i in range(3):
        for j in range(4):
            np.testing.assert_allclose(fk[i, j], chain.fk(q[i, j]), atol=1e-15)
            np.testing.assert_allclose(frames[i, j], chain.frames(q[i, j]), atol=1e-15)
            np.testing.assert_allclose(jac[i, j], chain.jacobian(q[i, j]), atol=1e-15)
            np.testing.assert_allclose(w[i, j], chain.manipulability(q[i, j], rows=[0, 1, 2]), atol=1e-15)
    np.testing.assert_allclose(frames[..., -1, :, :], fk, atol=1e-15)


def test_standard_and_modified_dh_describe_the_same_arm():
    """Standard row i (theta, d, a, alpha) = modified rows: Rz Tz in row i, Tx Rx moved to row i+1 (or the tool)."""
    std = pa10_7c()
    tool = transform(rot_x(std.alpha[-1]), (std.a[-1], 0, 0)) @ std.tool
    mdh = SerialChain(
        a=np.concatenate([[0.0], std.a[:-1]]),
        alpha=np.concatenate([[0.0], std.alpha[:-1]]),
        d=std.d,
        convention="mdh",
        offset=std.offset,
        sign=std.sign,
        tool=tool,
    )
    rng = np.random.default_rng(6)
    q = random_q(std, rng, (50,))
    np.testing.assert_allclose(mdh.fk(q), std.fk(q), atol=1e-12)
    np.testing.assert_allclose(mdh.jacobian(q), std.jacobian(q), atol=1e-12)


@given(arrays(float, 7, elements=st.floats(-np.pi, np.pi)))
@settings(max_examples=50, deadline=None)
def test_pa10_shoulder_rotation_entries_of_paper_000(q):
    """Section 3.3 of paper 000 prints entries of 0R3: (1,2) -c1 s2, (2,2) -s1 s2, (3,1) -s2 c3, (3,2) -c2,
    (3,3) s2 s3."""
    r03 = pa10_7c().frames(q)[3, :3, :3]
    c, s = np.cos(q), np.sin(q)
    np.testing.assert_allclose(r03[0, 1], -c[0] * s[1], atol=1e-12)
    np.testing.assert_allclose(r03[1, 1], -s[0] * s[1], atol=1e-12)
    np.testing.assert_allclose(r03[2, 0], -s[1] * c[2], atol=1e-12)
    np.testing.assert_allclose(r03[2, 1], -c[1], atol=1e-12)
    np.testing.assert_allclose(r03[2, 2], s[1] * s[2], atol=1e-12)


def thesis_wrist_position(q):
    """Closed-form wrist position X, Y, Z of thesis 001 section 5.1 (as printed; lengths in metres)."""
    L0, L1, L2, L3 = (HUMANOID_LENGTHS[k] for k in ("L0", "L1", "L2", "L3"))
    c1, c2, c3, c4, c5 = np.cos(q[:5])
    s1, s2, s3, s4, s5 = np.sin(q[:5])
    inner = L1 + L2 * c5 + L3 * s5
    x = c1 * (L0 + c3 * s4 * (L3 * c5 - L2 * s5) + s3 * inner) + (
        c2 * c4 * (L3 * c5 - L2 * s5) + s2 * (s3 * s4 * (-L3 * c5 + L2 * s5) + c3 * inner)
    ) * s1
    y = c4 * s2 * (-L3 * c5 + L2 * s5) + c2 * (s3 * s4 * (-L3 * c5 + L2 * s5) + c3 * inner)
    z = c1 * (c2 * c4 * (L3 * c5 - L2 * s5) + s2 * (s3 * s4 * (-L3 * c5 + L2 * s5) + c3 * inner)) - (
        L0 + c3 * s4 * (L3 * c5 - L2 * s5) + s3 * inner
    ) * s1
    return np.array([x, y, z])


@given(arrays(float, 8, elements=st.floats(-np.pi, np.pi)))
@settings(max_examples=50, deadline=None)
def test_humanoid_wrist_matches_thesis_section_5_1(q):
    wrist = humanoid_right_arm().frames(q)[6, :3, 3]  # joints 6-8 intersect at the origin of frame 6
    np.testing.assert_allclose(wrist, thesis_wrist_position(q), atol=1e-12)


def test_left_arm_is_the_mirror_image_with_shared_torso():
    rng = np.random.default_rng(7)
    right, left = humanoid_right_arm(0.1), humanoid_left_arm(0.1)
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    for q in rng.uniform(-np.pi, np.pi, (20, 8)):
        flipped = q.copy()
        flipped[0] = -q[0]
        np.testing.assert_allclose(left.fk(q), mirror @ right.fk(flipped) @ mirror, atol=1e-12)
    # the torso joint turns both shoulders the same way about the torso axis (+y)
    q = np.zeros(8)
    q[0] = 0.3
    shoulder_r, shoulder_l = right.frames(q)[2, :3, 3], left.frames(q)[2, :3, 3]
    # at theta1 = 0 the shoulders are at (+-L0, 0, 0); one rotation R about y must carry both
    np.testing.assert_allclose(shoulder_l, -shoulder_r, atol=1e-12)
    assert shoulder_r[2] < 0  # right shoulder moved to -z: a right-handed turn about +y


def test_within_limits_plain_and_wrapped():
    chain = pa10_7c()
    q = np.radians([0, 25, 0, 80, 0, 70, 0])
    assert chain.within_limits(q)
    assert not chain.within_limits(q + np.radians([0, 0, 0, 0, 0, 0, 200]))
    assert chain.within_limits(q + np.array([0, 0, 0, 0, 0, 0, 2 * np.pi]), wrap=True)
    assert not chain.within_limits(q + np.array([0, 0, 0, 0, 0, 0, 2 * np.pi]))
    assert chain.within_limits(np.radians([90.5, 0, 0, 10, 0, 0, 0]), tolerance=np.radians(1))
    crossing = chain.with_limits(np.radians([150, -45, -120, 0, -90, -90, -120]),
                                 np.radians([210, 45, 120, 135, 90, 90, 120]))
    assert crossing.within_limits(np.radians([-170, 0, 0, 10, 0, 0, 0]), wrap=True)
    assert not crossing.within_limits(np.radians([140, 0, 0, 10, 0, 0, 0]), wrap=True)
    wide = chain.with_limits(np.full(7, -4.0), np.full(7, 4.0))  # wider than 2 pi: still a range (issue 22)
    assert np.all(wide.limited) and np.all(wide.covers_circle)
    assert not wide.within_limits(np.full(7, 100.0))
    assert wide.within_limits(np.full(7, 100.0), wrap=True)  # every angle has a representative in range
    unlimited = chain.with_limits(np.full(7, -np.inf), np.full(7, np.inf))
    assert not np.any(unlimited.limited)
    assert unlimited.within_limits(np.full(7, 100.0))


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"a": [0, 0], "alpha": [0], "d": [0, 0]}, "alpha must have 2 entries"),
        ({"a": [0], "alpha": [0], "d": [0], "sign": [2]}, "sign"),
        ({"a": [0], "alpha": [0], "d": [np.nan]}, "finite"),
        ({"a": [0], "alpha": [0], "d": [0], "lower": [1], "upper": [0]}, "exceeds"),
        ({"a": [0], "alpha": [0], "d": [0], "convention": "xyz"}, "convention"),
        ({"a": [0], "alpha": [0], "d": [0], "tool": np.eye(3)}, "shape"),
        ({"a": [], "alpha": [], "d": []}, "at least one joint"),
    ],
)
def test_bad_chain_definitions(kwargs, message):
    with pytest.raises(ValueError, match=message):
        SerialChain(**kwargs)


@pytest.mark.parametrize(
    "q, message",
    [
        (np.zeros(6), r"shape \(\.\.\., 7\)"),
        (np.full(7, np.nan), "finite"),
        ([1, 2, "x", 4, 5, 6, 7], "numeric"),
        (np.zeros((2, 3)), "shape"),
    ],
)
def test_bad_joint_vectors(q, message):
    chain = pa10_7c()
    for function in (chain.fk, chain.frames, chain.jacobian, chain.manipulability, chain.within_limits):
        with pytest.raises(ValueError, match=message):
            function(q)


def test_bad_jacobian_frame():
    with pytest.raises(ValueError, match="frame"):
        pa10_7c().jacobian(np.zeros(7), frame=9)
    with pytest.raises(ValueError, match="rows"):
        pa10_7c().manipulability(np.zeros(7), rows=[7])


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_large_batches_equal_single_calls(name):
    """Large batches take the column-propagation path, single calls the 4x4 path: they must agree."""
    chain = MODELS[name]().with_tool(np.array([[0, -1, 0, 0.01], [1, 0, 0, 0.02], [0, 0, 1, 0.03], [0, 0, 0, 1.0]]))
    q = random_q(chain, np.random.default_rng(8), (40,))
    fk, frames, jac = chain.fk(q), chain.frames(q), chain.jacobian(q)
    directions, points = chain.joint_axes(q)
    for k in (0, 17, 39):
        np.testing.assert_allclose(fk[k], chain.fk(q[k]), atol=1e-14)
        np.testing.assert_allclose(frames[k], chain.frames(q[k]), atol=1e-14)
        np.testing.assert_allclose(jac[k], chain.jacobian(q[k]), atol=1e-14)
        np.testing.assert_allclose(directions[k], chain.joint_axes(q[k])[0], atol=1e-14)
        np.testing.assert_allclose(points[k], chain.joint_axes(q[k])[1], atol=1e-14)


@pytest.mark.parametrize("key", ["a", "d", "base", "tool"])
def test_absurd_lengths_are_refused_before_they_overflow(key):
    """A description with a 1e308 m link (finite, so no NaN check catches it) is refused with the limit named."""
    values = {"a": [0.1, 0.2], "alpha": [0.0, 0.0], "d": [0.0, 0.0]}
    if key in ("a", "d"):
        values[key] = [0.1, 1e308]
        arguments = values
    else:
        far = np.eye(4)
        far[0, 3] = 1e308
        arguments = {**values, key: far}
    with pytest.raises(ValueError, match="at most 1e\\+06 m"):
        SerialChain(**arguments)


@settings(max_examples=20, deadline=None)
@given(shape=st.sampled_from([(), (1,), (7,), (3, 4), (40, 30)]), seed=st.integers(0, 2**32 - 1),
       frame=st.sampled_from([None, 0, 3, 7]), offset=st.booleans())
def test_fk_and_jacobian_into_out_equal_a_fresh_result_and_are_out(shape, seed, frame, offset):
    """Written into reused buffers (holding the previous call's values) FK and the Jacobian are those of a fresh
    call, bit for bit, whatever the batch shape (1200 configurations run in chunks on the pool), frame and offset,
    and the arrays returned are the buffers; the front door (redkin.arm) passes them through."""
    import redkin

    arm = redkin.arm("kuka-iiwa14")
    rng = np.random.default_rng(seed)
    point = rng.normal(size=3) if offset else None
    poses, jacobians = np.full(shape + (4, 4), np.nan), np.full(shape + (6, 7), np.nan)
    for _ in range(2):
        q = rng.uniform(-np.pi, np.pi, shape + (7,))
        assert arm.fk(q, out=poses) is poses
        assert np.array_equal(poses, arm.chain.fk(q))
        assert arm.chain.jacobian(q, frame, point, out=jacobians) is jacobians
        assert np.array_equal(jacobians, arm.chain.jacobian(q, frame, point))
        assert arm.jacobian(q, out=jacobians) is jacobians
        assert np.array_equal(jacobians, arm.chain.jacobian(q))


@pytest.mark.parametrize("which", ["fk", "jacobian"])
@pytest.mark.parametrize("out, words", [
    (np.empty((4, 6, 6)), "of shape"),
    (np.empty((3, 4, 4)), "of shape"),
    (np.empty((4, 4, 4), dtype=np.float32), "float64"),
    ([[0.0] * 4] * 4, "numpy array"),
])
def test_fk_and_jacobian_refuse_an_out_they_cannot_write_into(which, out, words):
    """A buffer of the wrong type, shape or dtype is a ValueError in words; so is a strided or read-only one of
    the right shape."""
    chain = pa10_7c()
    q = np.zeros((4, 7))
    with pytest.raises(ValueError, match=words):
        getattr(chain, which)(q, out=out)
    right = (4, 4, 4) if which == "fk" else (4, 6, 7)
    strided = np.empty(right[:1] + right[:0:-1]).transpose(0, 2, 1)
    with pytest.raises(ValueError, match="C-contiguous"):
        getattr(chain, which)(q, out=strided)
    with pytest.raises(ValueError, match="writeable"):
        getattr(chain, which)(q, out=np.broadcast_to(np.empty(right[1:]), right))
