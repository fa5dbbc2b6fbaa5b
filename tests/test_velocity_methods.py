"""Baselines' documented bounds, the blend, the WAM factorisation and the proposed method (paper 003)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import barrett_wam, kuka_iiwa14, pa10_7c
from redkin.velocity import (
    NumericalFactorisation,
    WamFactorisation,
    adaptive_damped_least_squares,
    adaptive_damping,
    algorithmic_singularity,
    blend_weight,
    check_single_parameter,
    column_minors,
    damped_least_squares,
    fixed_joint_sc,
    make_method,
    pseudoinverse,
    rotation_factor,
    singularity_consistent,
    twist_scale,
)
from tests.support.velocity_wam import EPS, FACTOR, Q0, TWIST, WAM

# root of D_e, paper 003 sec. 3.3
SINGULAR_Q4 = float(np.arctan2(FACTOR.a * (FACTOR.d3 + FACTOR.d5), FACTOR.d3 * FACTOR.d5 - FACTOR.a**2))
seeds = st.integers(0, 2**32 - 1)


def random_q(seed, count=None):
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, (7,) if count is None else (count, 7))


# ------------------------------------------------------------------ baselines
@settings(deadline=None, max_examples=40)
@given(seeds, st.floats(1e-3, 0.5))
def test_velocity_dls_bound_and_pinv_exactness(seed, damping):
    rng = np.random.default_rng(seed)
    jac, twist = rng.normal(size=(6, 7)), rng.normal(size=6)
    jac[:, 0] = jac[:, 1] * rng.uniform(0.99, 1.01)  # nearly singular columns stress the bound
    qdot = damped_least_squares(jac, twist, damping)
    assert np.linalg.norm(qdot) <= np.linalg.norm(twist) / (2 * damping) * (1 + 1e-12)
    assert np.allclose(qdot, jac.T @ np.linalg.solve(jac @ jac.T + damping**2 * np.eye(6), twist))
    exact = pseudoinverse(jac, twist)
    assert np.allclose(jac @ exact, twist, atol=1e-6 * np.linalg.norm(twist) * np.linalg.cond(jac))


@settings(deadline=None, max_examples=30)
@given(seeds)
def test_velocity_adaptive_damping_bound(seed):
    jac = WAM.jacobian(random_q(seed))
    twist = np.random.default_rng(seed).normal(size=6)
    sigma = np.linalg.svd(jac, compute_uv=False)[-1]
    lam = adaptive_damping(jac, 0.1, 0.05)
    qdot = adaptive_damped_least_squares(jac, twist, 0.1, 0.05)
    bound = np.linalg.norm(twist) * min(1 / sigma, np.inf if lam == 0 else 1 / (2 * lam))
    assert np.linalg.norm(qdot) <= bound * (1 + 1e-9)
    if sigma >= 0.1:
        assert lam == 0 and np.allclose(qdot, pseudoinverse(jac, twist))
    manip = adaptive_damping(jac, 0.1, 0.05, measure="manipulability")
    assert 0 <= manip <= 0.05


def test_velocity_pinv_finite_at_exact_singularity_but_dls_bounded():
    q = random_q(3)
    q[3] = SINGULAR_Q4
    jac = WAM.jacobian(q)
    assert np.all(np.isfinite(pseudoinverse(jac, TWIST)))
    assert np.linalg.norm(damped_least_squares(jac, TWIST, 0.05)) <= np.linalg.norm(TWIST) / 0.1


# ------------------------------------------------------------------ blend (derived [003 eq. 21])
@settings(deadline=None, max_examples=50)
@given(st.floats(1e-3, 1.0))
def test_velocity_blend_continuous_at_threshold(eps):
    for edge in (eps, -eps):
        inside, outside = edge * (1 - 1e-12), edge * (1 + 1e-12)
        assert np.isclose(twist_scale(inside, eps), twist_scale(outside, eps), atol=1e-9)
        assert np.isclose(blend_weight(inside, eps), blend_weight(outside, eps), rtol=1e-9)
        assert np.isclose(rotation_factor(inside, eps), rotation_factor(outside, eps), atol=1e-9)
    x = np.linspace(-3 * eps, 3 * eps, 2001)
    g = twist_scale(x, eps)
    assert np.all(np.abs(np.diff(g)) <= 3.0 * (x[1] - x[0]) / (2 * eps) + 1e-12)  # Lipschitz, no jump
    assert np.all(np.sign(g) == np.sign(x))  # changes sign exactly through 0
    assert np.allclose(g[np.abs(x) > eps], np.sign(x[np.abs(x) > eps]))  # commanded twist outside
    assert np.all(g * rotation_factor(x, eps) >= 0)  # rotation keeps its sign
    assert np.isclose(blend_weight(0.0, eps), 3 / (2 * eps))


def test_velocity_blend_rejects_bad_eps():
    with pytest.raises(ValueError, match="eps"):
        twist_scale(0.1, 0.0)


# ------------------------------------------------------------------ factorisation
@settings(deadline=None, max_examples=30)
@given(seeds)
def test_velocity_wam_closed_form_factors(seed):
    q = random_q(seed, 16)
    minors = column_minors(WAM.jacobian(q))
    d_e = FACTOR.index(q)
    assert np.allclose(minors, d_e[:, None] * FACTOR.factors(q), atol=1e-13)
    keep = np.abs(d_e) > 1e-3
    assert np.allclose(FACTOR.factors(q)[keep], minors[keep] / d_e[keep, None], atol=1e-10)


def test_velocity_wam_factors_independent_of_lengths_choice():
    chain = barrett_wam(d3=0.5, d5=0.3, d7=0.1, a=0.06)
    factor = WamFactorisation.from_chain(chain)
    q = random_q(11, 8)
    assert np.allclose(column_minors(chain.jacobian(q)), factor.index(q)[:, None] * factor.factors(q), atol=1e-13)


def test_velocity_numerical_route_matches_closed_form_on_and_off_the_singularity():
    numerical = NumericalFactorisation(WAM, FACTOR.index)
    q = random_q(5, 6)
    q[:3, 3] = SINGULAR_Q4  # on D_e = 0: l'Hopital limit
    assert np.abs(FACTOR.index(q[:3])).max() < 1e-15
    assert np.allclose(numerical.factors(q), FACTOR.factors(q), atol=1e-6)


def test_velocity_single_parameter_check():
    assert check_single_parameter(WAM, FACTOR.index, samples=16).factors
    # S-R-S index fails on the WAM
    assert not check_single_parameter(WAM, lambda q: np.sin(q[..., 3]), samples=16).factors
    assert check_single_parameter(pa10_7c(), lambda q: np.sin(q[..., 3]), samples=16).factors
    assert check_single_parameter(kuka_iiwa14(), lambda q: np.sin(q[..., 3]), samples=16).factors
    # wrist: not a J singularity
    assert not check_single_parameter(pa10_7c(), lambda q: np.sin(q[..., 5]), samples=16).factors
    assert not check_single_parameter(WAM, lambda q: FACTOR.index(q) ** 3, samples=16).factors  # higher-order zero


def test_velocity_wam_pattern_required():
    with pytest.raises(ValueError, match="Barrett WAM DH pattern"):
        WamFactorisation.from_chain(pa10_7c())


# ------------------------------------------------------------------ conventional SC ([003 eqs. 9-11])
def test_velocity_fixed_joint_sc_and_algorithmic_singularity():
    q = Q0.copy()
    jac = WAM.jacobian(q)
    solution = fixed_joint_sc(jac, TWIST, joint=0, eps=1e-3)
    assert np.isclose(solution.joint_velocity[0], 0.0)  # joint 1 fixed
    assert np.allclose(jac @ solution.joint_velocity, solution.target_twist, atol=1e-12)
    # Joint 4 fixed: det J_4 = 0 everywhere on the WAM although det(J J^T) > 0 -- no end-point motion.
    assert algorithmic_singularity(jac, 3)
    assert not algorithmic_singularity(jac, 0)
    stuck = fixed_joint_sc(jac, TWIST, joint=3, eps=1e-3)
    assert np.allclose(stuck.target_twist, 0.0, atol=1e-12)
    # Joint 1 fixed: det J_1 = D_e D_1 vanishes at cos q3 = 0 inside the workspace.
    q_alg = q.copy()
    q_alg[2] = np.pi / 2
    assert algorithmic_singularity(WAM.jacobian(q_alg), 0)


# ------------------------------------------------------------------ proposed method ([003 eqs. 15-22])
@settings(deadline=None, max_examples=30)
@given(seeds, st.sampled_from([1.0, -1.0]))
def test_velocity_sc_realises_its_target_and_equals_pseudoinverse_outside(seed, direction):
    q = random_q(seed)
    jac = WAM.jacobian(q)
    d_e = FACTOR.index(q)
    sol = singularity_consistent(jac, TWIST, d_e, FACTOR.factors(q), eps=0.05, direction=direction)
    assert np.allclose(jac @ sol.joint_velocity, sol.target_twist, atol=1e-12)
    if abs(d_e) > 0.05 and np.sign(d_e) == direction:
        assert np.allclose(sol.target_twist, TWIST, atol=1e-15)
        assert np.allclose(sol.joint_velocity, np.linalg.pinv(jac) @ TWIST, atol=1e-9)  # [003 eqs. 18, 20]
    assert sol.target_twist[4] >= 0.0  # rotation about +y never reverses


def test_velocity_sc_moves_at_the_singularity():
    q = Q0.copy()
    q[3] = SINGULAR_Q4
    jac = WAM.jacobian(q)
    sol = singularity_consistent(jac, TWIST, FACTOR.index(q), FACTOR.factors(q), eps=EPS, direction=-1.0)
    assert np.linalg.norm(sol.joint_velocity) > 0.1  # q_dot != 0 at D_e = 0
    assert np.allclose(sol.target_twist, 0.0, atol=1e-15)
    assert np.allclose(jac @ sol.joint_velocity, 0.0, atol=1e-12)


def test_velocity_sc_batched_equals_looped():
    q = random_q(9, 5)
    jac = WAM.jacobian(q)
    batch = singularity_consistent(jac, TWIST, FACTOR.index(q), FACTOR.factors(q), eps=0.1)
    for k in range(5):
        one = singularity_consistent(jac[k], TWIST, FACTOR.index(q[k]), FACTOR.factors(q[k]), eps=0.1)
        assert np.allclose(batch.joint_velocity[k], one.joint_velocity)


def test_velocity_sc_bad_input():
    jac = WAM.jacobian(np.zeros(7))
    with pytest.raises(ValueError, match="direction"):
        singularity_consistent(jac, TWIST, 0.1, np.ones(7), 0.1, direction=0.5)
    with pytest.raises(ValueError, match="D_s"):
        singularity_consistent(jac, TWIST, 0.1, np.zeros(7), 0.1)
    with pytest.raises(ValueError, match="factors"):
        singularity_consistent(jac, TWIST, 0.1, np.ones(6), 0.1)
    with pytest.raises(ValueError, match="method"):
        make_method("newton")
    with pytest.raises(ValueError, match="damping"):
        make_method("dls", damping=-1.0)
