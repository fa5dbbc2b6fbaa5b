"""Laws of the virtual-arm trajectory generation (paper 004): goals, minimum-norm and least-squares limits,
limits, clamps, one-by-one evaluation, the literal [004 eq. 10] stall and the [004 eq. 16] identity."""

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares, minimize

from redkin.models import pa10_7c, planar_arm
from redkin.reproduce import printed
from redkin.virtual_arms import AnalyticModel, OutputFunction, VirtualPoint, generate_trajectory, joints_and_midpoints
from redkin.virtual_arms.dynamics import GAIN_LAWS, Dynamics
from redkin.virtual_arms.generate import _settled
from redkin.virtual_arms.subsystems import Together

ARM = planar_arm()
Q0 = np.radians([30.0, 30.0, 30.0, 30.0, 30.0])
GOAL = np.array([0.6, 1.2])
_HALF_RANGE = np.full(5, np.radians(printed.FIG_6_JOINT_RANGE_DEG))
FULL_RANGE = OutputFunction.sine(-_HALF_RANGE, _HALF_RANGE)  # Fig. 6's joint ranges ([004 section 4])


def min_norm_posture(model, theta0, goals):
    """argmin |theta - theta0| subject to f(theta) = goals: the limit of the penalty path of [004 eq. 14]."""
    constraint = {"type": "eq", "fun": lambda q: (model.evaluate(q)[0] - goals).ravel()}
    result = minimize(lambda q: 0.5 * np.sum((q - theta0) ** 2), theta0, jac=lambda q: q - theta0,
                      constraints=[constraint], method="SLSQP", options={"ftol": 1e-14, "maxiter": 500})
    assert result.success
    return result.x


@pytest.mark.parametrize("output", [None, FULL_RANGE], ids=["identity", "sine"])
def test_virtual_arms_redundant_end_point_reaches_goal_at_min_norm_posture(output):
    model = AnalyticModel(ARM, [VirtualPoint.end()])
    run = generate_trajectory(model, Q0, [GOAL], output=output)
    assert run.converged, run.message
    assert np.linalg.norm(model.evaluate(run.final_theta)[0][0] - GOAL) < 1e-4
    expected = min_norm_posture(model, Q0, GOAL[None])
    assert np.max(np.abs(np.degrees(run.final_theta - expected))) < 0.05


def test_virtual_arms_joint3_and_end_coincide_at_goal():  # Fig. 6 (b)
    model = AnalyticModel(ARM, [VirtualPoint.end(), VirtualPoint.joint(3)])
    goal = np.array([0.5, 0.6])
    run = generate_trajectory(model, Q0, [goal, goal], output=FULL_RANGE)
    assert run.converged, run.message
    positions = model.evaluate(run.final_theta)[0]
    assert np.all(np.linalg.norm(positions - goal, axis=-1) < 1e-4)
    expected = min_norm_posture(model, Q0, np.array([goal, goal]))
    assert np.max(np.abs(np.degrees(run.final_theta - expected))) < 0.05


@pytest.mark.parametrize("end_weight", [1.0, 30.0])
def test_virtual_arms_over_constrained_matches_weighted_least_squares(end_weight):  # Fig. 6 (c)
    points = [VirtualPoint.end()] + joints_and_midpoints(ARM)
    model = AnalyticModel(ARM, points)
    goals = model.evaluate(Q0)[0].copy()
    goals[0] = [0.25, 1.3]
    weights = np.ones(len(points))
    weights[0] = end_weight
    # the errors cannot vanish, lambda grows only like sqrt(s) ([004 eq. 11]): the run ends when they settle
    run = generate_trajectory(model, Q0, goals, weights)
    assert run.converged and "errors settled" in run.message, run.message
    root_w = np.sqrt(weights)[:, None]
    residual = lambda q: (root_w * (model.evaluate(q)[0] - goals)).ravel()  # noqa: E731
    direct = least_squares(residual, Q0, xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    # the errors are at their least-squares minimum (E* + O(1/lambda^2)) ...
    assert 0.5 * np.sum(residual(run.final_theta) ** 2) == pytest.approx(0.5 * np.sum(residual(direct) ** 2), rel=1e-5)
    # ... and the posture is as far from the limit as the joints moved over the last doubling of lambda (c / lambda)
    earlier = run.theta[np.searchsorted(run.lam, run.lam[-1] / 2, side="right") - 1]
    last_motion = np.linalg.norm(run.final_theta - earlier)
    assert np.linalg.norm(run.final_theta - direct) <= 1.5 * last_motion and last_motion < 5e-3
    # weights trade the goals: a heavier end point lands closer to its goal
    assert run.final_errors[0] > 1e-3


def _fig6c_heavy_end(start):
    """Fig. 6 (c) with w_end = 100 from ``start``: nine points held, the end point sent away."""
    points = [VirtualPoint.end()] + joints_and_midpoints(ARM)
    model = AnalyticModel(ARM, points)
    goals = model.evaluate(Q0)[0].copy()
    goals[0] = [0.5, 0.6]
    weights = np.ones(len(points))
    weights[0] = 100.0
    return generate_trajectory(model, start, goals, weights, output=FULL_RANGE)


@pytest.fixture(scope="module")
def fig6c_heavy_end():
    return _fig6c_heavy_end(Q0)


@pytest.mark.parametrize("seed", range(4))
def test_over_constrained_run_settles_whatever_the_last_bits(fig6c_heavy_end, seed):
    """From theta(0) moved by 1e-12 rad, as another BLAS's rounding would move it, the run still settles.

    Before the errors-settled test and rtol = 1e-6 about one such run in three ended "stalled" (Radau's
    Newton iteration failing on the narrow late path), depending on the rounding alone.
    """
    run = _fig6c_heavy_end(Q0 + np.random.default_rng(seed).normal(size=5) * 1e-12)
    assert run.converged and fig6c_heavy_end.converged, (run.message, fig6c_heavy_end.message)
    # The run stops where the error *sum* changes by at most error_rtol = 1e-6 over a doubling of lambda, so the end
    # point's own error is known to about 1e-5: over 12 such perturbations it lay -5.2e-6..+5.5e-6 (relative) from
    # the unperturbed run's with the numpy chain, and -1.2e-5..-0.8e-6 with the compiled chain (issue 13).
    assert run.final_errors[0] == pytest.approx(fig6c_heavy_end.final_errors[0], rel=3e-5)


def test_virtual_arms_heavier_end_weight_brings_end_closer():
    points = [VirtualPoint.end()] + joints_and_midpoints(ARM)
    model = AnalyticModel(ARM, points)
    goals = model.evaluate(Q0)[0].copy()
    goals[0] = [0.25, 1.3]
    errors = []
    for w in (1.0, 100.0):
        weights = np.ones(len(points))
        weights[0] = w
        errors.append(generate_trajectory(model, Q0, goals, weights).final_errors[0])
    assert errors[0] > 10 * errors[1]


def test_virtual_arms_limits_hold_along_whole_path():  # Fig. 7
    lower = -np.radians(printed.FIG_7_JOINT_LIMITS_DEG)
    model = AnalyticModel(ARM, [VirtualPoint.end()])
    run = generate_trajectory(model, Q0 * np.array([1, 1, 1, 0.5, 0.5]), [GOAL],
                              output=OutputFunction.sine(lower, -lower))
    assert run.converged, run.message
    assert np.all(run.theta >= lower) and np.all(run.theta <= -lower)
    assert np.linalg.norm(model.evaluate(run.final_theta)[0][0] - GOAL) < 1e-4


def test_virtual_arms_clamped_joints_do_not_move():  # [004 eq. 27]
    model = AnalyticModel(ARM, [VirtualPoint.end()])
    run = generate_trajectory(model, Q0, [GOAL], output=FULL_RANGE, fixed=[0, 1])
    assert run.converged, run.message
    assert np.all(run.theta[:, :2] == Q0[:2])
    assert np.linalg.norm(model.evaluate(run.final_theta)[0][0] - GOAL) < 1e-4


def test_virtual_arms_one_by_one_equals_together_and_survives_a_dropped_subsystem():
    model = AnalyticModel(ARM, [VirtualPoint.end(), VirtualPoint.joint(3), VirtualPoint.on_link(4, 0.5)])
    goals = np.array([GOAL, [0.2, 0.7], [0.5, 1.0]])
    together = generate_trajectory(model, Q0, goals, drop={2: 0.3})
    one_by_one = generate_trajectory(model, Q0, goals, drop={2: 0.3}, evaluation="one_by_one")
    assert together.converged and one_by_one.converged
    assert together.steps == one_by_one.steps
    assert np.allclose(together.theta, one_by_one.theta, atol=1e-9)
    assert not together.active[2]
    assert np.all(together.final_errors[:2] < 1e-4)


def test_virtual_arms_literal_eq10_is_reported_stalled_far_from_goal():
    model = AnalyticModel(ARM, [VirtualPoint.end()])
    run = generate_trajectory(model, Q0, [GOAL], gain="literal")
    assert (run.status == "stalled" and "step size" in run.message) or "failed" in run.message
    assert run.final_errors[0] > 1e-2
    assert generate_trajectory(model, Q0, [GOAL], gain="bounded").converged


@pytest.mark.parametrize("law", ["consistent", "literal"])
def test_virtual_arms_energy_rate_eq16_holds_only_with_consistent_constants(law):
    model = AnalyticModel(ARM, [VirtualPoint.end(), VirtualPoint.joint(3)])
    goals = np.array([GOAL, [0.1, 0.6]])
    rng = np.random.default_rng(3)
    dyn = Dynamics(Together(model), goals, np.ones((2, 2)), np.ones(2, bool), Q0, FULL_RANGE, np.ones(5, bool), 1.0,
                   GAIN_LAWS[law])
    for _ in range(5):
        y = np.append(dyn.u0 + rng.normal(0, 0.2, 5), rng.normal(0, 1))
        st = dyn.state(y)
        delta = st.delta.sum(axis=0)
        moved = np.linalg.norm(Q0 - st.theta)
        eq16 = -0.5 * st.lam**2 * delta @ delta
        extra = (GAIN_LAWS[law].lambda_constant - GAIN_LAWS[law].gain_constant) * np.linalg.norm(delta) * moved
        assert dyn.energy_rate(y) == pytest.approx(eq16 + extra, rel=1e-9, abs=1e-12)
        h = 1e-6  # V along the flow, by central differences
        rate = dyn.rates(0.0, y)
        numeric = (dyn.state(y + h * rate).energy - dyn.state(y - h * rate).energy) / (2 * h)
        assert numeric == pytest.approx(dyn.energy_rate(y), rel=1e-4, abs=1e-8)
        if law == "literal":
            assert extra > 0


def test_virtual_arms_spatial_pa10_elbow_and_hand():
    arm = pa10_7c()
    q0 = np.radians([0, 30, 0, 60, 0, 30, 0])
    model = AnalyticModel(arm, [VirtualPoint.end(), VirtualPoint.joint(4)])
    goals = model.evaluate(q0 + np.radians([10, -5, 10, 10, 5, -10, 0]))[0]  # reachable within the limits
    run = generate_trajectory(model, q0, goals, output=OutputFunction.sine(arm.lower, arm.upper))
    assert run.converged, run.message
    assert np.all(run.final_errors < 1e-4)
    assert np.all(arm.within_limits(run.theta))


def test_virtual_arms_bad_input():
    model = AnalyticModel(ARM, [VirtualPoint.end()])
    with pytest.raises(ValueError, match="goals"):
        generate_trajectory(model, Q0, [[1.0, 2.0, 3.0]])
    with pytest.raises(ValueError, match="theta0"):
        generate_trajectory(model, [np.nan] * 5, [GOAL])
    with pytest.raises(ValueError, match="gain"):
        generate_trajectory(model, Q0, [GOAL], gain="huge")
    with pytest.raises(ValueError, match="fixed"):
        generate_trajectory(model, Q0, [GOAL], fixed=[7])
    with pytest.raises(ValueError, match="outside its range"):
        generate_trajectory(model, Q0, [GOAL], output=OutputFunction.sine(np.zeros(5), np.full(5, 0.1)))


@given(st.floats(1.0, 1e6), st.floats(-1.0, 1.0), st.floats(1e-9, 1e-3))
@settings(max_examples=50, deadline=None)
def test_virtual_arms_settled_measures_motion_over_a_doubling_of_lambda(lam_end, c, tol):
    # a penalty path theta = theta* + c / lambda: over a doubling the joints move |c| / lambda_end
    lams = lam_end * 2.0 ** np.linspace(-6.0, 0.0, 25)
    record = [(float(k), SimpleNamespace(lam=lam, theta=np.array([1.0, 2.0]) + np.array([c, 0.0]) / lam))
              for k, lam in enumerate(lams)]
    motion = abs(c) / lam_end
    found = _settled(record, tol)
    if motion <= tol * (1 - 1e-6):
        assert found == pytest.approx(motion, rel=1e-6, abs=1e-14)
    elif motion > tol * (1 + 1e-6):
        assert found is None
    assert _settled(record, 0.0) is None  # off
    assert _settled(record[:1], tol) is None  # no doubling yet
