"""The compiled velocity steps (redkin.velocity._step_kernels) equal the definitional formulas written here (paper 003).

References: the blend of [003 eqs. 11, 21-22] in numpy; the pseudoinverse and
damped least squares from numpy's SVD; column minors as determinants of the
column-removed Jacobians ([003 eq. 5]); the SC step as the weighted sum of [003 eq. 15]
over the Cramer vectors ``n_i`` of [003 eqs. 6-8] with the weights of [003 eq. 21].
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import _compiled
from redkin._compiled import PARALLEL_BATCH, run_batch, set_threads
from redkin.velocity import (
    SingularityConsistent,
    _step_kernels,
    adaptive_damping,
    blend_weight,
    column_minors,
    damped_least_squares,
    fixed_joint_vectors,
    lean_singularity_consistent,
    pseudoinverse,
    rotation_factor,
    singularity_consistent,
    twist_scale,
    wam_cofactors,
    wam_singularity_index,
)
from redkin.velocity.baselines import PINV_RCOND
from tests.support.velocity_wam import EPS, FACTOR, Q4_ZERO, WAM, assert_same, configurations, twists, well_conditioned

seeds = st.integers(0, 2**32 - 1)


# ----------------------------------------------------------------- references
def reference_pinv(jac, twist):
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    gain = np.where(s > PINV_RCOND * s[0], 1.0 / np.where(s > 0, s, 1.0), 0.0)
    return vt.T @ (gain * (u.T @ twist))


def reference_minors(jac):
    # numpy's det divides by a zero pivot (and warns) when a column-removed Jacobian is exactly singular; it is 0 then
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.array([np.linalg.det(np.delete(jac, i, axis=1)) for i in range(jac.shape[1])])


def reference_sc(jac, twist, index, factors, direction, self_motion=0.0, modify_rotation=True):
    """[003 eqs. 15, 21, 22]: b_i = b_ep w(D_e) D_i / D_s over the Cramer vectors n_i, plus b_sm n_sm ([003 eq. 9])."""
    x = index / EPS
    g = x * EPS * (3.0 - x * x) / (2.0 * EPS) if abs(x) <= 1 else np.sign(x)
    w = (3.0 - x * x) / (2.0 * EPS) if abs(x) <= 1 else 1.0 / abs(index)
    modified = twist.copy()
    if modify_rotation:
        modified[3:] *= direction * np.clip(x, -1.0, 1.0)
    vectors, _ = fixed_joint_vectors(jac, modified)
    weights = direction * w * factors / np.sum(factors**2)
    qdot = weights @ vectors + self_motion * (-1.0) ** np.arange(7) * reference_minors(jac)
    return qdot, direction * g * modified


# ----------------------------------------------------------------------- blend
@settings(deadline=None, max_examples=200)
@given(st.one_of(st.floats(-1.0, 1.0), st.sampled_from([0.0, -0.0, EPS, -EPS, 2 * EPS, -2 * EPS])),
       st.sampled_from([EPS, 0.02, 1.0]))
def test_blend_kernels_equal_the_formulas(x, eps):
    inside = abs(x) <= eps
    # to rounding: the compiled kernel may round (x / eps) ** 2 otherwise (a random x gave 0.9781963084914883 against
    # the formula's 0.9781963084914885)
    rounding = {"rel": 4e-16, "abs": 0.0}
    assert twist_scale(x, eps) == pytest.approx(x * (3.0 - (x / eps) ** 2) / (2.0 * eps) if inside else np.sign(x),
                                                **rounding)
    assert blend_weight(x, eps) == pytest.approx((3.0 - (x / eps) ** 2) / (2.0 * eps) if inside else 1.0 / abs(x),
                                                 **rounding)
    assert rotation_factor(x, eps) == np.clip(x / eps, -1.0, 1.0)


def test_blend_keeps_the_shape_of_its_input():
    x = np.linspace(-0.3, 0.3, 12).reshape(3, 4)
    assert twist_scale(x, EPS).shape == (3, 4) and np.ndim(twist_scale(0.05, EPS)) == 0


# ---------------------------------------------------------- least squares
@settings(deadline=None, max_examples=60)
@given(seeds, st.sampled_from([(6, 7), (3, 7), (6, 6), (2, 3), (7, 6)]), st.integers(0, 2))
def test_least_squares_equals_the_svd_formulas(seed, shape, rank_drop):
    """Random Jacobians, some with exactly dependent rows (rank m - rank_drop) or a zero row."""
    rng = np.random.default_rng(seed)
    jac, twist = rng.normal(size=shape), rng.normal(size=shape[0])
    for k in range(min(rank_drop, shape[0] - 1)):
        jac[k] = jac[-1] * (k + 2.0) if k % 2 == 0 else 0.0
    reference = reference_pinv(jac, twist)
    cond = min(np.linalg.cond(jac), 1e12)
    scale = max(1.0, float(np.abs(reference).max()))
    np.testing.assert_allclose(pseudoinverse(jac, twist), reference, rtol=0, atol=1e-13 * cond * scale)
    dls = jac.T @ np.linalg.solve(jac @ jac.T + 0.05**2 * np.eye(shape[0]), twist)
    np.testing.assert_allclose(damped_least_squares(jac, twist, 0.05), dls, rtol=0,
                               atol=1e-11 * max(1, np.abs(dls).max()))


@settings(deadline=None, max_examples=40)
@given(configurations)
def test_adaptive_damping_equals_the_svd_formula(q):
    jac = WAM.jacobian(q)
    s = np.linalg.svd(jac, compute_uv=False)
    for measure, value in (("sigma", s[-1]), ("manipulability", np.prod(s))):
        ratio = min(value / 0.1, 1.0)
        assert np.isclose(adaptive_damping(jac, 0.1, 0.05, measure), 0.05 * np.sqrt(1.0 - ratio**2), rtol=0, atol=1e-12)


def test_pinv_on_singular_configurations_drops_the_singular_directions():
    for q in (np.zeros(7), np.array([0.3, 0.0, 0.1, Q4_ZERO, 0.2, 0.0, 0.4])):
        jac = WAM.jacobian(q)
        twist = np.array([0.1, -0.2, 0.3, 0.0, 0.5, 0.1])
        np.testing.assert_allclose(pseudoinverse(jac, twist), reference_pinv(jac, twist), atol=1e-12)


# ------------------------------------------------------------- column minors
@settings(deadline=None, max_examples=40)
@given(configurations)
def test_column_minors_equal_determinants_and_the_wam_closed_form(q):
    jac = WAM.jacobian(q)
    minors = column_minors(jac)
    np.testing.assert_allclose(minors, reference_minors(jac), rtol=0, atol=1e-14)
    np.testing.assert_allclose(minors, wam_singularity_index(q, FACTOR.a, FACTOR.d3, FACTOR.d5)
                               * wam_cofactors(q, FACTOR.a, FACTOR.d3, FACTOR.d5), rtol=0, atol=1e-14)


# --------------------------------------------------------------------- SC step
@settings(deadline=None, max_examples=60)
@given(configurations, twists, st.sampled_from([None, 0.0, 1e-12, -1e-6, 1e-3, -0.05, 0.3]),
       st.sampled_from([1.0, -1.0]), st.booleans(), st.sampled_from([0.0, 0.7]))
def test_sc_step_equals_the_weighted_cramer_sum(q, twist, distance, direction, modify_rotation, self_motion):
    """Both paths (adjugate everywhere; pseudoinverse off D_e = 0) equal [003 eq. 15] with [003 eq. 21]'s weights,
    also on D_e = 0."""
    if distance is not None:
        q[3] = Q4_ZERO + distance
    if not well_conditioned(q):
        return
    jac, index, factors = WAM.jacobian(q), float(FACTOR.index(q)), FACTOR.factors(q)
    qdot, target = reference_sc(jac, twist, index, factors, direction, self_motion, modify_rotation)
    reference = type(singularity_consistent(jac, twist, index, factors, EPS))(qdot, target)
    exact = singularity_consistent(jac, twist, index, factors, EPS, direction, self_motion, modify_rotation)
    lean = lean_singularity_consistent(jac, twist, index, lambda: factors, EPS, direction, self_motion, modify_rotation)
    assert_same(reference, exact)
    assert_same(reference, lean)


def test_sc_step_with_every_factor_zero_is_a_value_error():
    jac = WAM.jacobian(np.full(7, 0.5))
    with pytest.raises(ValueError, match="D_s"):
        singularity_consistent(jac, np.ones(6), 0.0, np.zeros(7), EPS)
    assert np.all(np.isfinite(lean_singularity_consistent(jac, np.ones(6), 0.5, lambda: np.zeros(7),
                                                          EPS).joint_velocity))


# ---------------------------------------------------------- batches and threads
def random_batch(count, seed=0):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (count, 7))
    q[::7, 3] = Q4_ZERO + rng.choice([0.0, 1e-9, -1e-4, 0.05], size=q[::7].shape[0])
    return q, rng.normal(size=(count, 6))


def test_batched_steps_equal_looped_steps_bit_for_bit():
    q, twist = random_batch(40)
    jac, index, factors = WAM.jacobian(q), FACTOR.index(q), FACTOR.factors(q)
    pinv = pseudoinverse(jac, twist)
    exact = singularity_consistent(jac, twist, index, factors, EPS, -1.0, 0.3)
    lean = lean_singularity_consistent(jac, twist, index, lambda: factors, EPS, -1.0, 0.3)
    for k in range(len(q)):
        np.testing.assert_array_equal(pinv[k], pseudoinverse(jac[k], twist[k]))
        one = singularity_consistent(jac[k], twist[k], index[k], factors[k], EPS, -1.0, 0.3)
        np.testing.assert_array_equal(exact.joint_velocity[k], one.joint_velocity)
        one = lean_singularity_consistent(jac[k], twist[k], index[k], lambda k=k: factors[k], EPS, -1.0, 0.3)
        np.testing.assert_array_equal(lean.joint_velocity[k], one.joint_velocity)
        np.testing.assert_array_equal(lean.target_twist[k], one.target_twist)


@pytest.mark.slow
def test_batches_in_chunks_equal_one_call_bit_for_bit(monkeypatch):
    """Each batch kernel run in one call, in odd chunks (items start .. stop - 1 each) and on three threads."""
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    count = 2 * PARALLEL_BATCH + 3
    q, twist = random_batch(count, seed=1)
    jac, index, factors = WAM.jacobian(q), FACTOR.index(q), FACTOR.factors(q)

    def one_call(kernel, *args):
        kernel(0, count, *args)

    def odd_chunks(kernel, *args):
        for start, stop in ((0, 1), (1, 38), (38, 38), (38, count - 1), (count - 1, count)):
            kernel(start, stop, *args)

    def three_threads(kernel, *args):
        try:
            set_threads(3)
            run_batch(kernel, count, *args)
        finally:
            set_threads(None)

    outputs = []
    for run in (one_call, odd_chunks, three_threads):
        qdot, target, ok = np.empty((count, 7)), np.empty((count, 6)), np.empty(count, dtype=bool)
        run(_step_kernels.sc, jac, twist, index, factors, EPS, 1.0, 0.2, True, 1e-3, qdot, target, ok)
        out, lam = np.empty((count, 7)), np.empty(count)
        run(_step_kernels.least_squares, jac, twist, 0.05, 0.1, _step_kernels.SIGMA, PINV_RCOND, out, lam)
        minors = np.empty((count, 7))
        run(_step_kernels.column_minors, jac, minors)
        outputs.append((qdot, target, ok, out, lam, minors))
    for other in outputs[1:]:
        for one, same in zip(outputs[0], other):
            np.testing.assert_array_equal(one, same)


@pytest.mark.parametrize("lean", [True, False])
def test_bound_sc_method_takes_batches(lean):
    """SingularityConsistent.bind once stopped with a LAPACK error on a batch; it equals its single steps."""
    q, twist = random_batch(12, seed=2)
    step = SingularityConsistent(eps=EPS, lean=lean).bind(WAM, q[0])
    batched = step(q, WAM.jacobian(q), twist)
    for k in range(len(q)):
        one = step(q[k], WAM.jacobian(q[k]), twist[k])
        np.testing.assert_array_equal(batched.joint_velocity[k], one.joint_velocity)
        np.testing.assert_array_equal(batched.target_twist[k], one.target_twist)
