"""Forward models of paper 004: analytic Jacobians, the numpy MLP's back-propagation, learned accuracy,
classification."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import pa10_7c, planar_arm
from redkin.virtual_arms import (
    AnalyticModel,
    VirtualPoint,
    classify,
    joints_and_midpoints,
    learn_forward_model,
    parse_point,
)
from redkin.virtual_arms.mlp import MLP

ARM = planar_arm()
PA10 = pa10_7c()


@settings(deadline=None, max_examples=20)
@given(st.lists(st.floats(-3.0, 3.0), min_size=7, max_size=7), st.floats(0.0, 1.0))
def test_virtual_arms_analytic_jacobian_equals_finite_differences(q, fraction):
    q = np.array(q)
    model = AnalyticModel(PA10, [VirtualPoint.end(), VirtualPoint.joint(4), VirtualPoint.on_link(5, fraction)])
    _, jac = model.evaluate(q)
    h = 1e-6
    numeric = np.stack([(model.evaluate(q + h * e)[0] - model.evaluate(q - h * e)[0]) / (2 * h) for e in np.eye(7)],
                       axis=-1)
    assert np.allclose(jac, numeric, atol=1e-7)


def test_virtual_arms_analytic_matches_chain_and_batches():
    rng = np.random.default_rng(1)
    q = rng.uniform(-2, 2, (4, 7))
    model = AnalyticModel(PA10, [VirtualPoint.end(), VirtualPoint.joint(4)])
    x, jac = model.evaluate(q)
    assert np.allclose(x[:, 0], PA10.fk(q)[:, :3, 3])
    assert np.allclose(jac[:, 0], PA10.jacobian(q)[:, :3])
    assert np.allclose(jac[:, 1], PA10.jacobian(q, frame=3)[:, :3])
    looped = np.stack([model.evaluate(qi)[0] for qi in q])
    assert np.allclose(x, looped)
    planar = AnalyticModel(ARM, [VirtualPoint.on_link(2, 0.25)])
    assert planar.dims == 2
    assert np.allclose(planar.evaluate(np.zeros(5))[0], [[0.5, 0.0]])


def test_virtual_arms_classification_fig2():
    end = VirtualPoint.end()
    assert classify(AnalyticModel(ARM, [end])).kind == "redundant"
    assert classify(AnalyticModel(ARM, [end, VirtualPoint.joint(3)])).kind == "redundant"  # Fig. 6 (b)
    assert classify(AnalyticModel(ARM, [end] + joints_and_midpoints(ARM))).kind == "over-constrained"  # Fig. 6 (c)
    singular = classify(AnalyticModel(ARM, [end, VirtualPoint.on_link(5, 0.5)]))  # one joint between the points
    assert singular.kind == "singular" and singular.rank == 3


def test_virtual_arms_mlp_backprop_and_input_jacobian_equal_finite_differences():
    rng = np.random.default_rng(0)
    for activation in ("sigmoid", "sine"):
        net = MLP.initial(3, 5, 2, activation, rng)
        x, target = rng.normal(size=(7, 3)), rng.normal(size=(7, 2))
        _, grad = net.loss_and_gradient(x, target)
        flat, h = net.parameters(), 1e-6
        numeric = [(net.with_parameters(flat + h * e).loss_and_gradient(x, target)[0]
                    - net.with_parameters(flat - h * e).loss_and_gradient(x, target)[0]) / (2 * h)
                   for e in np.eye(flat.size)]
        assert np.allclose(grad, numeric, atol=1e-7)
        jac = net.input_jacobian(x[0])
        numeric_j = np.stack([(net(x[0] + h * e) - net(x[0] - h * e)) / (2 * h) for e in np.eye(3)], axis=-1)
        assert np.allclose(jac, numeric_j, atol=1e-8)


def test_virtual_arms_learned_model_reaches_stated_accuracy():
    # stated accuracy: held-out RMS end-point error below 5 mm for joints in [-1.5, 1.5] rad (sine hidden units)
    model, report = learn_forward_model(ARM, [VirtualPoint.end()], samples=800, held_out=300, hidden=12,
                                        iterations=400, lower=[-1.5] * 5, upper=[1.5] * 5, seed=0)
    assert report.held_out_rms[0] < 5e-3
    assert report.train_rms[0] < 5e-3
    q = np.full(5, 0.3)
    assert model.evaluate(q)[1].shape == (1, 2, 5)


def test_virtual_arms_points_parse_and_reject():
    assert parse_point("joint:3") == VirtualPoint.joint(3)
    assert parse_point("link:2@0.25") == VirtualPoint.on_link(2, 0.25)
    assert parse_point("end") == VirtualPoint.end()
    for bad in ("elbow", "joint:x", "link:2@"):
        with pytest.raises(ValueError, match="point"):
            parse_point(bad)
    with pytest.raises(ValueError, match="joint number"):
        AnalyticModel(ARM, [VirtualPoint.joint(9)])
    with pytest.raises(ValueError, match="fraction"):
        AnalyticModel(ARM, [VirtualPoint.on_link(2, 1.5)])
