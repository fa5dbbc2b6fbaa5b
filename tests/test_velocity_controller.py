"""The control-loop controllers equal the array API ([003 eqs. 17-22]): fast path == general path."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import kuka_iiwa14, planar_arm
from redkin.velocity import (
    ElbowSine,
    NumericalFactorisation,
    PseudoinverseController,
    SingularityConsistent,
    SingularityConsistentController,
    WamFactorisation,
    lean_singularity_consistent,
    pseudoinverse,
    singularity_consistent,
    singularity_factorisation,
)
from tests.support.velocity_wam import (
    EPS,
    FACTOR,
    Q0,
    Q4_ZERO,
    WAM,
    assert_same,
    configurations,
    twists,
    well_conditioned,
)


def exact_step(q, twist, direction, self_motion=0.0, modify_rotation=True):
    return singularity_consistent(
        WAM.jacobian(q), twist, FACTOR.index(q), FACTOR.factors(q), EPS, direction, self_motion, modify_rotation
    )


@settings(deadline=None, max_examples=60)
@given(configurations, twists, st.sampled_from([1.0, -1.0]), st.booleans())
def test_sc_controller_equals_exact_path_on_random_configurations(q, twist, direction, modify_rotation):
    if not well_conditioned(q):
        return
    controller = SingularityConsistentController(WAM, Q0, EPS, direction=direction, modify_rotation=modify_rotation)
    assert_same(exact_step(q, twist, direction, modify_rotation=modify_rotation), controller(q, twist))


@settings(deadline=None, max_examples=60)
@given(configurations, twists, st.floats(-14.0, 0.0), st.sampled_from([1.0, -1.0]))
def test_sc_controller_equals_exact_path_near_de_zero(q, twist, log_distance, sign):
    """|D_e| from ~1e-15 (exact fallback) through the singular region to outside it."""
    if not well_conditioned(q):
        return
    q[3] = Q4_ZERO + sign * 10.0**log_distance
    controller = SingularityConsistentController(WAM, Q0, EPS)
    assert_same(exact_step(q, twist, -1.0), controller(q, twist))


@pytest.mark.parametrize("offset", [0.0, 1e-3 / 0.47, -2e-3, 0.05, -0.3])
def test_sc_controller_at_and_around_de_zero_keeps_moving(offset):
    rng = np.random.default_rng(5)
    controller = SingularityConsistentController(WAM, Q0, EPS)
    for _ in range(10):
        q = rng.uniform(0.3, 1.2, 7)
        q[3] = Q4_ZERO + offset
        twist = rng.normal(size=6)
        fast = controller(q, twist)
        assert_same(exact_step(q, twist, -1.0), fast)
        assert np.linalg.norm(fast.joint_velocity) > 0.0
        np.testing.assert_allclose(WAM.jacobian(q) @ fast.joint_velocity, fast.target_twist, atol=1e-10)


def test_sc_controller_self_motion_and_default_direction():
    q = np.array([0.3, 0.8, 0.2, 1.0, 0.4, 0.9, 0.1])
    twist = np.array([0.1, 0.0, 0.05, 0.0, 0.2, 0.0])
    assert SingularityConsistentController(WAM, Q0).direction == -1.0  # D_e(q0) < 0
    q_positive = Q0.copy()
    q_positive[3] = Q4_ZERO + 0.5
    assert SingularityConsistentController(WAM, q_positive).direction == 1.0
    controller = SingularityConsistentController(WAM, Q0, EPS, self_motion=0.7)
    assert_same(exact_step(q, twist, -1.0, self_motion=0.7), controller(q, twist))


def test_sc_controller_equals_bound_method_as_used_by_tracking():
    rng = np.random.default_rng(6)
    method = SingularityConsistent(eps=EPS).bind(WAM, Q0)
    controller = SingularityConsistentController(WAM, Q0, EPS)
    for _ in range(20):
        q, twist = rng.uniform(-2, 2, 7), rng.normal(size=6)
        assert_same(method(q, WAM.jacobian(q), twist), controller(q, twist))


def test_sc_controller_with_a_numerical_factorisation_on_an_srs_arm():
    """The iiwa's singularity factors through sin q4 (found automatically); the controller equals the bound method.

    In KUKA's conventions A4 turns the other way from Table 1's joint 4: D_e = sin(theta_4) = sin(-q4).
    """
    iiwa = kuka_iiwa14()
    numeric = singularity_factorisation(iiwa)
    assert isinstance(numeric, NumericalFactorisation) and numeric.index_function == ElbowSine(0.0, -1.0)
    q0 = np.array([0.2, 0.5, -0.3, 0.8, 0.1, 0.6, 0.0])
    method = SingularityConsistent(eps=EPS).bind(iiwa, q0)
    controller = SingularityConsistentController(iiwa, q0, EPS)
    rng = np.random.default_rng(7)
    for q4 in (0.0, 1e-4, -0.05, 0.4, -1.5):
        q, twist = rng.uniform(-1.5, 1.5, 7), rng.normal(size=6)
        q[3] = q4
        assert_same(method(q, iiwa.jacobian(q), twist), controller(q, twist))


@settings(deadline=None, max_examples=60)
@given(configurations, twists)
def test_pinv_controller_equals_pseudoinverse(q, twist):
    fast = PseudoinverseController(WAM)(q, twist)
    reference = pseudoinverse(WAM.jacobian(q), twist)
    scale = max(1.0, float(np.max(np.abs(reference))))
    cond = min(np.linalg.cond(WAM.jacobian(q)), 1e12)  # inf on an exact singularity, where both drop sigma_min
    np.testing.assert_allclose(fast.joint_velocity, reference, rtol=0, atol=1e-13 * cond * scale)
    np.testing.assert_array_equal(fast.target_twist, twist)


def test_pinv_controller_on_an_exact_singularity_drops_the_singular_direction():
    q = np.zeros(7)  # arm straight up: shoulder, elbow and wrist singular together
    twist = np.array([0.1, -0.2, 0.3, 0.0, 0.5, 0.1])
    fast = PseudoinverseController(WAM)(q, twist).joint_velocity
    np.testing.assert_allclose(fast, pseudoinverse(WAM.jacobian(q), twist), atol=1e-12)
    assert np.all(np.isfinite(fast))


def test_batched_lean_equals_looped_controller_on_a_mixed_batch():
    rng = np.random.default_rng(8)
    q = rng.uniform(0.3, 1.2, (30, 7))
    q[:, 3] = Q4_ZERO + np.concatenate([np.linspace(-0.6, 0.6, 27), [0.0, 1e-9, -1e-4]])
    twist = rng.normal(size=(30, 6))
    batched = lean_singularity_consistent(WAM.jacobian(q), twist, FACTOR.index(q), lambda: FACTOR.factors(q), EPS, -1.0)
    controller = SingularityConsistentController(WAM, Q0, EPS)
    for k in range(len(q)):
        assert_same(controller(q[k], twist[k]), type(batched)(batched.joint_velocity[k], batched.target_twist[k]))


def test_batched_lean_rejects_an_index_of_the_wrong_shape():
    q = np.full((4, 7), 0.5)
    with pytest.raises(ValueError, match="index must have shape"):
        lean_singularity_consistent(WAM.jacobian(q), np.zeros(6), np.zeros(3), lambda: FACTOR.factors(q), EPS)


@pytest.mark.parametrize(
    ("q", "twist", "message"),
    [
        (np.zeros(6), np.zeros(6), r"q must have shape \(7,\), got shape \(6,\)"),
        (np.zeros((2, 7)), np.zeros(6), r"q must have shape \(7,\)"),
        (np.full(7, np.nan), np.zeros(6), "q must be finite"),
        (["a"] * 7, np.zeros(6), "q must be numeric"),
        (np.zeros(7), np.zeros(5), r"twist must have shape \(6,\)"),
        (np.zeros(7), [0, 0, np.inf, 0, 0, 0], "twist must be finite"),
    ],
)
def test_bad_step_inputs_are_value_errors(q, twist, message):
    for controller in (SingularityConsistentController(WAM, Q0), PseudoinverseController(WAM)):
        with pytest.raises(ValueError, match=message):
            controller(q, twist)


def test_bad_construction_is_a_value_error():
    with pytest.raises(ValueError, match="7 joints"):
        PseudoinverseController(planar_arm())
    with pytest.raises(ValueError, match="SerialChain"):
        PseudoinverseController("barrett-wam")
    offset_wrist = replace(WAM, a=[0.0, 0.0, 0.045, -0.045, 0.03, 0.0, 0.0])
    with pytest.raises(ValueError, match="do not factor through one parameter"):
        SingularityConsistentController(offset_wrist, Q0)
    with pytest.raises(ValueError, match="eps"):
        SingularityConsistentController(WAM, Q0, eps=0.0)
    with pytest.raises(ValueError, match="direction"):
        SingularityConsistentController(WAM, Q0, direction=0.0)
    with pytest.raises(ValueError, match="near_zero"):
        SingularityConsistentController(WAM, Q0, near_zero=-1.0)
    with pytest.raises(ValueError, match="q0"):
        SingularityConsistentController(WAM, np.zeros(3))
    with pytest.raises(ValueError, match="q0 must be finite"):
        SingularityConsistentController(WAM, np.full(7, np.nan))
    with pytest.raises(ValueError, match="factorisation"):
        SingularityConsistentController(WAM, Q0, factorisation=lambda q: q[..., 3])
    with pytest.raises(ValueError, match="self_motion"):
        SingularityConsistentController(WAM, Q0, self_motion=np.nan)


def test_singularity_factorisation_picks_the_closed_form_or_the_elbow_sine():
    assert isinstance(singularity_factorisation(WAM), WamFactorisation)
    flipped = replace(kuka_iiwa14(), offset=[0, 0, 0, 0.4, 0, 0, 0], sign=[1, 1, 1, -1, 1, 1, 1])
    found = singularity_factorisation(flipped)
    assert found.index_function == ElbowSine(0.4, -1.0)
    q = np.random.default_rng(9).uniform(-2, 2, (5, 7))
    np.testing.assert_allclose(found.index(q), np.sin(0.4 - q[:, 3]))
    with pytest.raises(ValueError, match="7 joints"):
        singularity_factorisation(planar_arm())
