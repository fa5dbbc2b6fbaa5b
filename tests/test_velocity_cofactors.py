"""Laws of the cofactor building blocks and of the weighted-sum method ([003 eqs. 4-8, 12-18], App. A)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import barrett_wam
from redkin.velocity import (
    adjugate,
    adjugate_direction,
    column_minors,
    fixed_joint_vectors,
    minimum_norm_weights,
    pseudoinverse_weights,
    self_motion_vector,
    weighted_sum_direction,
)
from tests.support.velocity_wam import FACTOR, Q0, TWIST

seeds = st.integers(0, 2**32 - 1)


def random_problem(seed, rows=6):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(rows, rows + 1)), rng.normal(size=rows)


@settings(deadline=None, max_examples=40)
@given(seeds)
def test_velocity_cauchy_binet(seed):
    jac, _ = random_problem(seed)
    assert np.isclose(np.linalg.det(jac @ jac.T), np.sum(column_minors(jac) ** 2), rtol=1e-9)


@settings(deadline=None, max_examples=40)
@given(seeds)
def test_velocity_self_motion_in_null_space(seed):
    jac, _ = random_problem(seed)
    n_sm = self_motion_vector(jac)
    assert np.linalg.norm(n_sm) > 1e-8
    assert np.allclose(jac @ n_sm, 0.0, atol=1e-10 * np.linalg.norm(n_sm))
    # It is the null space: parallel to the last right singular vector.
    null = np.linalg.svd(jac)[2][-1]
    assert np.isclose(abs(null @ n_sm) / np.linalg.norm(n_sm), 1.0, atol=1e-9)


@settings(deadline=None, max_examples=40)
@given(seeds)
def test_velocity_fixed_joint_vectors_solve_augmented_system(seed):
    jac, twist = random_problem(seed)
    vectors, minors = fixed_joint_vectors(jac, twist)
    for i in range(7):
        assert vectors[i, i] == 0.0  # [003 eq. 7]
        augmented = np.hstack([jac, -twist[:, None]])  # [003 eq. 2]
        assert np.allclose(augmented @ np.append(vectors[i], minors[i]), 0.0, atol=1e-9)


@settings(deadline=None, max_examples=40)
@given(seeds)
def test_velocity_eq17_is_adjugate_direction_and_eq18_is_pseudoinverse(seed):
    jac, twist = random_problem(seed)
    n17, size17 = weighted_sum_direction(jac, twist, minimum_norm_weights(jac))
    n_pi, size_pi = adjugate_direction(jac, twist)
    assert np.allclose(n17, n_pi, rtol=1e-9, atol=1e-9 * np.abs(n_pi).max())
    assert np.isclose(size17, size_pi, rtol=1e-9)  # [003 eq. 16] vs [003 eq. 13]
    n18, size18 = weighted_sum_direction(jac, twist, pseudoinverse_weights(jac))
    assert np.allclose(n18, np.linalg.pinv(jac) @ twist, rtol=1e-8, atol=1e-10)
    assert np.isclose(size18, 1.0)


@settings(deadline=None, max_examples=40)
@given(seeds)
def test_velocity_appendix_a_orthogonality(seed):
    jac, twist = random_problem(seed)
    n_sum, _ = weighted_sum_direction(jac, twist, minimum_norm_weights(jac))
    n_sm = self_motion_vector(jac)
    assert abs(n_sum @ n_sm) <= 1e-10 * np.linalg.norm(n_sum) * np.linalg.norm(n_sm)
    # ... and a different weighting is not orthogonal in general.
    other, _ = weighted_sum_direction(jac, twist, np.ones(7))
    assert abs(other @ n_sm) > 1e-6 * np.linalg.norm(other) * np.linalg.norm(n_sm)


def test_velocity_adjugate_direction_vanishes_at_singularity():
    chain = barrett_wam()
    q = Q0.copy()
    # elbow stretched, [003 eq. 14]
    q[3] = np.arctan2(FACTOR.a * (FACTOR.d3 + FACTOR.d5), FACTOR.d3 * FACTOR.d5 - FACTOR.a**2)
    direction, size = adjugate_direction(chain.jacobian(q), TWIST)
    assert abs(size) < 1e-12 and np.abs(direction).max() < 1e-12
    # Away from it the direction is not zero.
    q[3] += 0.3
    assert np.abs(adjugate_direction(chain.jacobian(q), TWIST)[0]).max() > 1e-4


@settings(deadline=None, max_examples=30)
@given(seeds)
def test_velocity_adjugate_matches_inverse_and_rank_one_limit(seed):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(5, 5))
    assert np.allclose(adjugate(a), np.linalg.det(a) * np.linalg.inv(a), atol=1e-9)
    singular = a.copy()
    singular[:, 0] = singular[:, 1] + singular[:, 2]
    adj = adjugate(singular)
    assert np.allclose(singular @ adj, 0.0, atol=1e-9)  # A adj(A) = det(A) I = 0


def test_velocity_batched_equals_looped():
    rng = np.random.default_rng(7)
    jac, twist = rng.normal(size=(3, 4, 6, 7)), rng.normal(size=(3, 4, 6))
    vectors, minors = fixed_joint_vectors(jac, twist)
    for a in range(3):
        for b in range(4):
            v1, m1 = fixed_joint_vectors(jac[a, b], twist[a, b])
            assert np.allclose(vectors[a, b], v1) and np.allclose(minors[a, b], m1)
    # A single twist broadcasts over a batch of Jacobians.
    vectors2, _ = fixed_joint_vectors(jac, twist[0, 0])
    assert np.allclose(vectors2[1, 2], fixed_joint_vectors(jac[1, 2], twist[0, 0])[0])


@pytest.mark.parametrize(
    "jac, twist, match",
    [
        (np.zeros((6, 6)), np.zeros(6), "one more column"),
        (np.zeros((6, 7)), np.zeros(5), "twist must have shape"),
        (np.full((6, 7), np.nan), np.zeros(6), "jacobian must be finite"),
        (np.zeros((6, 7)), [0, 0, 0, 0, 0, np.inf], "twist must be finite"),
        (np.zeros((2, 6, 7)), np.zeros((3, 6)), "do not broadcast"),
    ],
)
def test_velocity_cofactor_bad_input(jac, twist, match):
    with pytest.raises(ValueError, match=match):
        fixed_joint_vectors(jac, twist)


def test_fixed_joint_vectors_of_an_exactly_singular_jacobian():
    """Two zero columns leave every J_i singular: all minors are exactly 0 and each n_i stays finite with
    ``J n_i = det(J_i) t = 0``."""
    jac = np.random.default_rng(3).normal(size=(6, 7))
    jac[:, :2] = 0.0
    vectors, minors = fixed_joint_vectors(jac, np.ones(6))
    assert np.all(minors == 0.0) and np.all(np.isfinite(vectors))
    np.testing.assert_allclose(vectors @ jac.T, 0.0, atol=1e-12)
