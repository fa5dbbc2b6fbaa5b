"""The compiled virtual-arm kernels equal the definitional numpy forms written here ([004 eqs. 1, 9-14, 17, 25]).

References: end points and their Jacobians from the chain's frames and
joint axes (``z_j x (X - o_j)`` for the joints before the point's frame);
the rate function as [004 eqs. 9-14] in numpy over the subsystems' signals.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import _compiled
from redkin._compiled import PARALLEL_BATCH, set_threads
from redkin.models import franka_panda, pa10_7c, planar_arm
from redkin.virtual_arms import AnalyticModel, OutputFunction, VirtualPoint, joints_and_midpoints
from redkin.virtual_arms import _kernels as kernels
from redkin.virtual_arms.dynamics import GAIN_LAWS, Dynamics
from redkin.virtual_arms.subsystems import OneByOne, Together

seeds = st.integers(0, 2**32 - 1)


def reference_points(model, theta):
    """[004 eq. 1] from the frames: X = o_k + R_k local, columns z_j x (X - o_j) for joints j before frame k."""
    chain = model.chain
    frames = chain.frames(theta)
    directions, origins = chain.joint_axes_in(frames)
    positions, jacobians = [], []
    for point in model.points:
        k, local = point.anchor(chain)
        world = frames[k, :3, 3] + frames[k, :3, :3] @ local
        columns = np.cross(directions * chain.sign[:, None], world - origins)
        columns[np.arange(chain.n) >= min(k, chain.n)] = 0.0
        positions.append(world[list(model.axes)])
        jacobians.append(columns.T[list(model.axes)])
    return np.array(positions), np.array(jacobians)


def reference_state(dyn, y):
    """[004 eqs. 9-14, 17] in numpy at one state y = [u_free, log lambda]."""
    u = dyn.u0.copy()
    u[dyn.free] = y[:-1]
    theta = dyn.output.theta(u)
    theta[~dyn.free] = dyn.theta0[~dyn.free]
    positions, jacobians = dyn.evaluator(theta, dyn.active)
    residual = dyn.goals - positions
    weighted = dyn.weights * residual
    delta_k = np.where(dyn.active[:, None], np.einsum("plm,pl->pm", jacobians, np.nan_to_num(weighted)), 0.0)
    error = np.where(dyn.active, 0.5 * np.sum(np.nan_to_num(residual * weighted), axis=-1), 0.0)
    lam = np.exp(y[-1])
    delta = delta_k.sum(axis=0)[dyn.free]
    displacement = (dyn.theta0 - theta)[dyn.free]
    slope = dyn.output.slope(u)[dyn.free]
    slope_g = slope * (lam * delta + displacement)
    numerator = (0.5 * lam**2 * delta @ delta
                 + dyn.law.gain_constant * np.linalg.norm(delta) * np.linalg.norm(displacement))
    bound = 0.0 if dyn.law.a_max is None else numerator / dyn.law.a_max
    with np.errstate(divide="ignore"):
        gain = 0.0 if numerator == 0 else numerator / (slope_g @ slope_g + bound)
    dlam = dyn.eta * dyn.law.lambda_constant * np.linalg.norm(delta) * np.linalg.norm(displacement) / error.sum()
    energy = lam * error.sum() + 0.5 * displacement @ displacement
    return theta, delta_k, error, dyn.eta * gain * slope_g, dlam, energy, np.linalg.norm(slope * delta)


MODELS = [
    AnalyticModel(planar_arm(), [VirtualPoint.end(), VirtualPoint.joint(3), VirtualPoint.on_link(2, 0.3)]),
    AnalyticModel(pa10_7c(),
                  [VirtualPoint.end(), VirtualPoint.joint(4), VirtualPoint.joint(1), VirtualPoint.on_link(7)]),
    AnalyticModel(franka_panda(), joints_and_midpoints(franka_panda())),
]


@settings(deadline=None, max_examples=40)
@given(seeds, st.sampled_from(range(len(MODELS))))
def test_virtual_points_equal_frames_and_axes(seed, which):
    model = MODELS[which]
    theta = np.random.default_rng(seed).uniform(-np.pi, np.pi, model.joints)
    positions, jacobians = model.evaluate(theta)
    ref_positions, ref_jacobians = reference_points(model, theta)
    np.testing.assert_allclose(positions, ref_positions, rtol=0, atol=1e-14)
    np.testing.assert_allclose(jacobians, ref_jacobians, rtol=0, atol=1e-14)


def test_virtual_points_batched_and_in_chunks_equal_single_calls_bit_for_bit(monkeypatch):
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    model = MODELS[1]
    count = 2 * PARALLEL_BATCH + 5
    theta = np.random.default_rng(1).uniform(-2, 2, (count, 7))
    try:
        set_threads(3)
        positions, jacobians = model.evaluate(theta)  # chunks on the thread pool
    finally:
        set_threads(None)
    arguments = (theta, model.chain._links, model.chain._ends, model.chain._standard, model._frames, model._local,
                 model._axes)
    whole = np.empty(positions.shape), np.empty(jacobians.shape)
    kernels.virtual_points(0, count, *arguments, *whole)
    parts = np.empty(positions.shape), np.empty(jacobians.shape)
    for start, stop in ((0, 7), (7, 8), (8, count)):
        kernels.virtual_points(start, stop, *arguments, *parts)
    for computed in (whole, parts):
        np.testing.assert_array_equal(positions, computed[0])
        np.testing.assert_array_equal(jacobians, computed[1])
    for k in (0, 7, len(theta) - 1):
        one = model.evaluate(theta[k])
        np.testing.assert_array_equal(one[0], positions[k])
        np.testing.assert_array_equal(one[1], jacobians[k])


def dynamics(law="bounded", fixed=(), dropped=(), one_by_one=False, limited=True):
    model = MODELS[0]
    theta0 = np.radians([30.0, 30.0, 30.0, 30.0, 30.0])
    goals = np.array([[0.6, 1.2], [0.1, 0.6], [0.2, 0.3]])
    active = np.ones(3, bool)
    active[list(dropped)] = False
    free = np.ones(5, bool)
    free[list(fixed)] = False
    output = OutputFunction.sine(np.full(5, -2.0), np.full(5, 2.5)) if limited else OutputFunction.identity(5)
    evaluator = OneByOne(model.split()) if one_by_one else Together(model)
    return Dynamics(evaluator, goals, np.array([[1.0, 1.0], [2.0, 0.5], [0.3, 1.0]]), active, theta0, output, free,
                    0.7, GAIN_LAWS[law])


@settings(deadline=None, max_examples=60)
@given(seeds, st.sampled_from(["bounded", "consistent", "literal"]), st.sampled_from([(), (0,), (1, 3)]),
       st.sampled_from([(), (1,)]), st.booleans(), st.booleans())
def test_rate_function_equals_the_equations(seed, law, fixed, dropped, one_by_one, limited):
    dyn = dynamics(law, fixed, dropped, one_by_one, limited)
    rng = np.random.default_rng(seed)
    y = np.append(dyn.u0[dyn.free] + rng.normal(0, 0.3, dyn.free.sum()), rng.normal(0, 2))
    state = dyn.state(y)
    theta, delta, error, du, dlam, energy, gradient = reference_state(dyn, y)
    np.testing.assert_allclose(state.theta, theta, rtol=0, atol=1e-15)
    np.testing.assert_allclose(state.delta, delta, rtol=0, atol=1e-13)
    np.testing.assert_allclose(state.error, error, rtol=0, atol=1e-14)
    np.testing.assert_allclose(state.du, du, rtol=1e-12, atol=1e-14)
    assert state.dlam == pytest.approx(dlam, rel=1e-12)
    assert state.energy == pytest.approx(energy, rel=1e-12)
    assert state.free_gradient == pytest.approx(gradient, rel=1e-12, abs=1e-15)
    assert np.array_equal(np.isnan(state.positions), np.isnan(dyn.evaluator(theta, dyn.active)[0]))


def test_literal_gain_is_infinite_where_g_vanishes():
    """[004 eq. 10] as printed divides by |G' g|^2: at g = 0 with delta != 0 the gain is infinite (the stall), not
    an error."""
    dyn = dynamics("literal", limited=False)
    y = np.append(dyn.u0, 0.0)
    scalars = np.empty((1, 5))  # G' = 0 (slope), so G' g = 0 while delta != 0
    kernels.rates(y[None], dyn.theta0[None], np.zeros((1, 5)), np.zeros((1, 3, 2)), np.ones((1, 3, 2, 5)), dyn.goals,
                  dyn.weights, dyn.active, dyn.theta0, dyn.free, 1.0, 0.5, 1.0, np.inf, np.empty((1, 3, 5)),
                  np.empty((1, 3)), np.empty((1, 5)), scalars)
    assert scalars[0, kernels.GAIN] == np.inf


def test_rates_of_a_batch_equal_rates_of_each_state():
    dyn = dynamics(fixed=(2,))
    ys = np.random.default_rng(3).normal(size=(5, 5))  # 4 free joints and log lambda
    batch = dyn.rates(0.0, ys.T)
    for k in range(5):
        np.testing.assert_array_equal(batch[:, k], dyn.rates(0.0, ys[k]))
