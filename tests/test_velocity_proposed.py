"""The lean SC step (one pseudoinverse) equals the exact adjugate path ([003 eqs. 17-22])."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.velocity import (
    SingularityConsistent,
    lean_singularity_consistent,
    singularity_consistent,
)
from tests.support.velocity_wam import EPS, FACTOR, Q4_ZERO, WAM, assert_same, configurations, twists, well_conditioned


def both(q, twist, direction=1.0, self_motion=0.0, modify_rotation=True):
    jac = WAM.jacobian(q)
    index = FACTOR.index(q)
    exact = singularity_consistent(jac, twist, index, FACTOR.factors(q), EPS, direction, self_motion, modify_rotation)
    lean = lean_singularity_consistent(
        jac, twist, index, lambda: FACTOR.factors(q), EPS, direction, self_motion, modify_rotation
    )
    return exact, lean


@pytest.mark.slow
@settings(deadline=None, max_examples=60)
@given(configurations, twists, st.sampled_from([1.0, -1.0]), st.booleans())
def test_lean_equals_exact_on_random_configurations(q, twist, direction, modify_rotation):
    if not well_conditioned(q):
        return
    exact, lean = both(q, twist, direction, modify_rotation=modify_rotation)
    assert_same(exact, lean)


@settings(deadline=None, max_examples=60)
@given(configurations, twists, st.floats(-3.0, 0.0), st.sampled_from([1.0, -1.0]))
def test_lean_equals_exact_near_the_boundary(q, twist, log_distance, sign):
    """|D_e| from ~1e-4 (inside the singular region and the fallback band) to ~1 (outside the region)."""
    if not well_conditioned(q):
        return
    q[3] = Q4_ZERO + sign * 10.0**log_distance
    exact, lean = both(q, twist)
    assert_same(exact, lean)


@pytest.mark.parametrize("offset", [0.0, 1e-12, -1e-9, 1e-6, 5e-3, -5e-3, 0.05])
def test_lean_equals_exact_at_and_around_de_zero(offset):
    rng = np.random.default_rng(3)
    for _ in range(10):
        q = rng.uniform(0.3, 1.2, 7)
        q[3] = Q4_ZERO + offset
        exact, lean = both(q, rng.normal(size=6), direction=-1.0)
        assert_same(exact, lean)
        assert np.linalg.norm(lean.joint_velocity) > 0.0  # keeps moving through D_e = 0


def test_inside_and_outside_the_singular_region_both_paths_are_used_consistently():
    rng = np.random.default_rng(4)
    q = rng.uniform(0.3, 1.2, (40, 7))
    q[:, 3] = Q4_ZERO + np.linspace(-0.8, 0.8, 40)
    q[5, 3] = Q4_ZERO  # exactly on D_e = 0 inside a batch: mixed lean/exact
    twist = rng.normal(size=6)
    exact, lean = both(q, twist)
    assert np.any(np.abs(FACTOR.index(q)) > EPS) and np.any(np.abs(FACTOR.index(q)) < EPS)
    assert_same(exact, lean)


def test_self_motion_term_is_added_the_same_way():
    q = np.array([0.3, 0.8, 0.2, 1.0, 0.4, 0.9, 0.1])
    exact, lean = both(q, np.array([0.1, 0.0, 0.05, 0.0, 0.2, 0.0]), self_motion=0.7)
    assert_same(exact, lean)


def test_method_lean_flag_gives_the_same_step():
    q = np.array([0.3, 0.8, 0.2, 1.0, 0.4, 0.9, 0.1])
    twist = np.array([0.1, -0.2, 0.05, 0.3, 0.0, -0.1])
    fast = SingularityConsistent(eps=EPS).bind(WAM, q)
    slow = SingularityConsistent(eps=EPS, lean=False).bind(WAM, q)
    jac = WAM.jacobian(q)
    assert_same(slow(q, jac, twist), fast(q, jac, twist))


def test_bad_inputs_are_value_errors():
    q = np.zeros(7)
    jac = WAM.jacobian(q)
    with pytest.raises(ValueError, match="index"):
        lean_singularity_consistent(jac, np.zeros(6), np.nan, lambda: FACTOR.factors(q), EPS)
    with pytest.raises(ValueError, match="near_zero"):
        lean_singularity_consistent(jac, np.zeros(6), 0.5, lambda: FACTOR.factors(q), EPS, near_zero=-1.0)
    with pytest.raises(ValueError, match="twist"):
        lean_singularity_consistent(jac, np.zeros(5), 0.5, lambda: FACTOR.factors(q), EPS)
