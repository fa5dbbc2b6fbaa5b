"""Laws of the rotation helpers."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from redkin._validation import check_rotation
from redkin.so3 import (
    axis_angle_to_matrix,
    matrix_to_axis_angle,
    matrix_to_xyz_fixed,
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
