"""Laws of the rotation helpers."""

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from redkin._validation import check_rotation
from redkin.so3 import (
    axis_angle_to_matrix,
    matrix_to_axis_angle,
    matrix_to_quaternion,
    matrix_to_xyz_fixed,
    nearest_rotation,
    quaternion_to_matrix,
    rot_x,
    rot_y,
    rot_z,
    skew,
    xyz_fixed_to_matrix,
)

finite = st.floats(-10, 10, allow_nan=False)
vectors = arrays(float, 3, elements=finite)


@given(vectors, vectors)
def test_skew_is_cross_product(u, w):
    np.testing.assert_allclose(skew(u) @ w, np.cross(u, w), atol=1e-12)
    np.testing.assert_allclose(skew(u), -skew(u).T)


@given(vectors.filter(lambda v: np.linalg.norm(v) > 1e-3), st.floats(-np.pi, np.pi))
def test_rodrigues_matches_closed_form_and_inverts(axis, angle):
    u = axis / np.linalg.norm(axis)
    expected = np.eye(3) + np.sin(angle) * skew(u) + (1 - np.cos(angle)) * skew(u) @ skew(u)
    r = axis_angle_to_matrix(axis, angle)
    np.testing.assert_allclose(r, expected, atol=1e-12)
    back_axis, back_angle = matrix_to_axis_angle(r)
    np.testing.assert_allclose(axis_angle_to_matrix(back_axis, back_angle), r, atol=1e-9)
    assert 0 <= back_angle <= np.pi + 1e-12


def test_elementary_rotations_are_right_handed():
    a = 0.3
    np.testing.assert_allclose(rot_z(a) @ [1, 0, 0], [np.cos(a), np.sin(a), 0])
    np.testing.assert_allclose(rot_x(a) @ [0, 1, 0], [0, np.cos(a), np.sin(a)])
    np.testing.assert_allclose(rot_y(a) @ [0, 0, 1], [np.sin(a), 0, np.cos(a)])
    for r in (rot_x, rot_y, rot_z):
        np.testing.assert_allclose(r(a), axis_angle_to_matrix(np.eye(3)[[rot_x, rot_y, rot_z].index(r)], a), atol=1e-15)


@given(st.floats(-np.pi, np.pi), st.floats(-np.pi / 2 + 1e-3, np.pi / 2 - 1e-3), st.floats(-np.pi, np.pi))
def test_xyz_fixed_round_trip(alpha, beta, gamma):
    r = xyz_fixed_to_matrix([alpha, beta, gamma])
    # [001 eq. 4.4]: Rz(alpha) Ry(beta) Rx(gamma)
    np.testing.assert_allclose(r, rot_z(alpha) @ rot_y(beta) @ rot_x(gamma), atol=1e-14)
    np.testing.assert_allclose(xyz_fixed_to_matrix(matrix_to_xyz_fixed(r)), r, atol=1e-9)


@pytest.mark.parametrize("beta", [np.pi / 2, -np.pi / 2])
def test_xyz_fixed_gimbal_lock_still_reconstructs(beta):
    r = xyz_fixed_to_matrix([0.7, beta, -0.4])
    angles = matrix_to_xyz_fixed(r)
    assert angles[0] == 0.0
    np.testing.assert_allclose(xyz_fixed_to_matrix(angles), r, atol=1e-9)


def test_batched_equals_looped():
    rng = np.random.default_rng(3)
    angles = rng.uniform(-1.5, 1.5, (4, 5, 3))
    batch = xyz_fixed_to_matrix(angles)
    assert batch.shape == (4, 5, 3, 3)
    for i in range(4):
        for j in range(5):
            np.testing.assert_allclose(batch[i, j], xyz_fixed_to_matrix(angles[i, j]))
    np.testing.assert_allclose(matrix_to_xyz_fixed(batch), angles, atol=1e-12)


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.eye(3) * 2, "orthonormal"),
        (np.diag([1.0, 1.0, -1.0]), "proper rotation"),
        (np.full((3, 3), np.nan), "finite"),
        (np.eye(4), "shape"),
        ("abc", "numeric"),
    ],
)
def test_bad_rotations_are_rejected(bad, message):
    with pytest.raises(ValueError, match=message):
        check_rotation(bad)
    with pytest.raises(ValueError):
        matrix_to_xyz_fixed(bad)


def test_zero_axis_is_rejected():
    with pytest.raises(ValueError, match="non-zero"):
        axis_angle_to_matrix([0, 0, 0], 1.0)


# ------------------------------------------------------------------------------ quaternions, the nearest rotation

quaternions = arrays(float, 4, elements=st.floats(-1, 1)).filter(lambda v: np.linalg.norm(v) > 0.1)


@given(vectors.filter(lambda v: np.linalg.norm(v) > 1e-3), st.floats(-np.pi, np.pi))
@example(axis=np.array([1.0, 1.0, 1.0]), angle=np.pi)  # a fresh draw: w = cos(pi/2) is rounding, 6e-17 or 2e-16
@example(axis=np.array([1.0, 1.0, 1.0]), angle=-np.pi)
@example(axis=np.array([0.0, -1.0, 0.0]), angle=np.pi)
def test_quaternion_of_a_turn_is_half_angle_cosine_and_sine(axis, angle):
    """``(cos(a/2), sin(a/2) u)`` is the turn by ``a`` about ``u`` (Hamilton), and matrix_to_quaternion gives it back
    up to the sign, with its first entry beyond rounding positive: at a half turn ``w`` is rounding, whose sign does
    not choose."""
    u = axis / np.linalg.norm(axis)
    q = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * u])
    np.testing.assert_allclose(quaternion_to_matrix(q), axis_angle_to_matrix(axis, angle), atol=1e-12)
    back = matrix_to_quaternion(axis_angle_to_matrix(axis, angle))
    np.testing.assert_allclose(back, q if q[np.flatnonzero(np.abs(q) > 1e-14)[0]] > 0 else -q, atol=1e-12)


@given(quaternions)
@example(quaternion=np.array([1.12591493e-57, 0.0, -1.0, -1.0]))  # a half turn: w's sign is rounding's
def test_quaternion_round_trip_and_both_signs(quaternion):
    q = quaternion / np.linalg.norm(quaternion)
    r = quaternion_to_matrix(q)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
    assert abs(np.linalg.det(r) - 1) < 1e-14
    np.testing.assert_allclose(quaternion_to_matrix(-q), r, atol=1e-15)
    back = matrix_to_quaternion(r)
    assert back[np.flatnonzero(np.abs(back) > 1e-14)[0]] > 0 and abs(np.linalg.norm(back) - 1) < 1e-15
    np.testing.assert_allclose(back, q * np.sign(q @ back), atol=1e-12)


def test_quaternions_batched_and_at_half_turns():
    angles = np.random.default_rng(4).uniform(-np.pi, np.pi, (3, 5, 3))
    r = xyz_fixed_to_matrix(angles)
    q = matrix_to_quaternion(r)
    assert q.shape == (3, 5, 4)
    np.testing.assert_allclose(quaternion_to_matrix(q), r, atol=1e-14)
    np.testing.assert_allclose(q[1, 2], matrix_to_quaternion(r[1, 2]))
    half_turns = np.array([rot_x(np.pi), rot_y(np.pi), rot_z(np.pi), rot_z(np.pi) @ rot_x(np.pi / 2)])
    np.testing.assert_allclose(matrix_to_quaternion(np.round(half_turns, 15)),
                               [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0.5**0.5, 0.5**0.5]], atol=1e-15)


@pytest.mark.parametrize("bad, message", [
    ([1.1, 0, 0, 0], "norm 1"), ([0, 0, 0, 0], "norm 1"), ([np.nan, 0, 0, 1], "finite"), ([1, 0, 0], "shape"),
])
def test_bad_quaternions_are_rejected(bad, message):
    with pytest.raises(ValueError, match=message):
        quaternion_to_matrix(bad)


@given(quaternions, arrays(float, (3, 3), elements=st.floats(-1e-3, 1e-3)))
def test_nearest_rotation_is_the_polar_factor(quaternion, noise):
    """``Q = nearest_rotation(M)`` is a proper rotation with ``Q^T M`` symmetric and positive semi-definite (the
    polar decomposition ``M = Q P``), so no rotation is nearer in the Frobenius norm; a rotation is its own."""
    rotation = quaternion_to_matrix(quaternion / np.linalg.norm(quaternion))
    matrix = rotation + noise
    q = nearest_rotation(matrix)
    np.testing.assert_allclose(q @ q.T, np.eye(3), atol=1e-14)
    assert abs(np.linalg.det(q) - 1) < 1e-14
    p = q.T @ matrix
    np.testing.assert_allclose(p, p.T, atol=1e-14)
    assert np.linalg.eigvalsh((p + p.T) / 2).min() > 0
    np.testing.assert_allclose(nearest_rotation(rotation), rotation, atol=1e-14)
    assert np.abs(q - matrix).max() <= 4 * np.abs(noise).max() + 1e-14


def test_nearest_rotation_is_proper_and_batched():
    reflection = np.diag([1.0, 1.0, -1.0]) @ rot_z(0.3)
    assert abs(np.linalg.det(nearest_rotation(reflection)) - 1) < 1e-14
    batch = np.stack([rot_x(0.2) * 1.0001, reflection])[None]
    np.testing.assert_allclose(nearest_rotation(batch)[0, 0], rot_x(0.2), atol=1e-14)
    with pytest.raises(ValueError, match="finite"):
        nearest_rotation(np.full((3, 3), np.inf))
