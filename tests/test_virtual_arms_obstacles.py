"""Obstacle avoidance with virtual arms (paper 004 Fig. 8): goal reached, whole arm clear, clamps, limits, bad input."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import pa10_7c, planar_arm
from redkin.reproduce import printed
from redkin.virtual_arms import (
    AnalyticModel,
    Obstacle,
    OutputFunction,
    VirtualPoint,
    arm_clearance,
    avoid_obstacles,
    generate_trajectory,
)
from redkin.virtual_arms.clearance import _segment_clearance, densify
from redkin.virtual_arms.obstacles import _end_step, repulsion

ARM = planar_arm()
Q0 = np.radians([30.0] * 5)
GOAL = np.array([0.5, 0.6])
BLOCK = [Obstacle(np.array([0.75, 0.9]), 0.1)]  # across the unobstructed path of the end point


def _limits(deg):
    upper = np.radians(np.full(5, float(deg)))
    return OutputFunction.sine(-upper, upper), -upper, upper


def _independent_clearance(chain, theta, obstacles, axes=(0, 1), samples=201):
    """Smallest distance of densely sampled link points to the obstacle surfaces (no segment formula)."""
    points = chain.frames(theta)[..., :3, 3][..., list(axes)]  # (K, n + 2, l)
    t = np.linspace(0.0, 1.0, samples)[:, None]
    along = points[:, :-1, None, :] + t * (points[:, 1:, None, :] - points[:, :-1, None, :])
    return min(float((np.linalg.norm(along - ob.centre, axis=-1) - ob.radius).min()) for ob in obstacles)


DENSE_STEP = np.radians(0.25)


def _dense(theta, step=DENSE_STEP):
    return densify(theta, step)[0]


@pytest.fixture(scope="module")
def free_run():
    output, _, _ = _limits(printed.FIG_6_JOINT_RANGE_DEG)
    return avoid_obstacles(ARM, Q0, GOAL, BLOCK, output=output)


@pytest.fixture(scope="module")
def clamped_run():
    output, lower, upper = _limits(150.0)
    return avoid_obstacles(ARM, Q0, GOAL, BLOCK, output=output, fixed=[0]), lower, upper


def test_virtual_arms_obstacles_matter_for_the_plain_run():
    plain = generate_trajectory(AnalyticModel(ARM, [VirtualPoint.end()]), Q0, [GOAL],
                                output=_limits(printed.FIG_6_JOINT_RANGE_DEG)[0])
    assert plain.converged
    assert arm_clearance(ARM, plain.theta, BLOCK, (0, 1)).min() < -0.05  # the arm would cut through the obstacle


def test_virtual_arms_obstacles_reach_goal_with_the_whole_arm_clear(free_run):
    run = free_run
    assert run.status == "reached" and run.reached
    assert run.end_error < 1e-3
    assert np.linalg.norm(ARM.fk(run.final_theta)[:2, 3] - GOAL) == pytest.approx(run.end_error, abs=1e-12)
    # every link point, sampled densely along the links and between the recorded postures, stays outside
    independent = _independent_clearance(ARM, _dense(run.theta), BLOCK)
    assert independent > 0.0
    assert run.min_clearance > 0.0
    assert run.min_clearance == pytest.approx(independent, abs=2e-3)
    assert run.clearance.shape == (len(run.theta),)
    assert np.all(run.clearance >= run.min_clearance - 1e-12)
    assert run.periods > 1 and run.steps > run.periods and run.seconds > 0.0
    assert run.positions.shape == (len(run.theta), 1 + len(run.points), 2)
    assert np.allclose(run.positions[:, 0], ARM.frames(run.theta)[:, -1, :2, 3], atol=1e-12)


def test_virtual_arms_obstacles_clamped_joint_is_bit_exact_and_limits_hold(clamped_run):
    run, lower, upper = clamped_run
    assert run.status == "reached" and run.end_error < 1e-3
    assert np.all(run.theta[:, 0] == Q0[0])  # [004 eq. 27]: not a single bit of motion
    assert run.fixed.tolist() == [True, False, False, False, False]
    assert np.all((run.theta >= lower) & (run.theta <= upper))  # [004 eq. 25] keeps the ranges by construction
    assert _independent_clearance(ARM, _dense(run.theta), BLOCK) > 0.0


def test_virtual_arms_obstacles_without_obstacles_is_the_plain_run():
    output, _, _ = _limits(printed.FIG_6_JOINT_RANGE_DEG)
    run = avoid_obstacles(ARM, Q0, GOAL, [], output=output)
    plain = generate_trajectory(AnalyticModel(ARM, [VirtualPoint.end()]), Q0, [GOAL], output=output)
    assert run.status == "reached" and run.periods == 1
    assert run.theta.shape == plain.theta.shape  # the same integrator steps ...
    assert np.allclose(run.theta, plain.theta, rtol=0.0, atol=1e-12)  # ... up to rounding (zero-weight points summed)
    assert run.min_clearance == np.inf


def test_virtual_arms_obstacles_report_blocked_when_the_goal_is_out_of_reach():
    # joints 1-4 clamped: the end point can only turn on a circle round joint 5, which misses the goal
    run = avoid_obstacles(ARM, Q0, GOAL, BLOCK, fixed=[0, 1, 2, 3], patience=3, max_periods=50)
    assert run.status == "blocked" and not run.reached
    assert "no progress" in run.message
    assert run.end_error > 0.1
    assert np.all(run.theta[:, :4] == Q0[:4])
    assert run.min_clearance > 0.0


def test_virtual_arms_obstacles_pa10_elbow_kept_clear_of_a_sphere():
    arm = pa10_7c()
    q0 = np.radians([0.0, 30.0, 0.0, 60.0, 0.0, 30.0, 0.0])
    goal = np.array([0.5, 0.4, 0.3])
    sphere = [Obstacle(np.array([0.25, 0.12, 0.68]), 0.06)]  # where the elbow would go without it
    output = OutputFunction.sine(arm.lower, arm.upper)
    plain = generate_trajectory(AnalyticModel(arm, [VirtualPoint.end()]), q0, [goal], output=output)
    assert arm_clearance(arm, plain.theta, sphere, (0, 1, 2)).min() < 0.0
    run = avoid_obstacles(arm, q0, goal, sphere, points=[VirtualPoint.joint(4)], output=output)
    assert run.status == "reached" and run.end_error < 1e-3
    assert _independent_clearance(arm, _dense(run.theta), sphere, axes=(0, 1, 2)) > 0.0
    elbow = arm.frames(run.theta)[:, 3, :3, 3]
    assert np.all(np.linalg.norm(elbow - sphere[0].centre, axis=-1) > sphere[0].radius)
    assert np.all((run.theta >= arm.lower) & (run.theta <= arm.upper))


@pytest.mark.parametrize("kwargs, words", [
    ({"obstacles": [(0.75, 0.9, -0.1)]}, "obstacle radius"),
    ({"obstacles": [(0.75, 0.9, 0.0)]}, "obstacle radius"),
    ({"obstacles": [(0.75, 0.9, np.nan)]}, "obstacle radius"),
    ({"obstacles": [(0.75, 0.9, 0.2, 0.1)]}, "obstacle 0 must be 2 centre coordinates"),
    ({"obstacles": [Obstacle(np.array([0.7, 0.9, 0.0]), 0.1)]}, "3-D but the task space is 2-D"),
    ({"obstacles": [(0.5, 0.62, 0.05)]}, "goal [0.5, 0.6] is inside obstacle 0"),
    ({"obstacles": [(0.35, 0.2, 0.05)]}, "theta0 puts the arm within margin"),
    ({"goal": [0.5, np.nan]}, "goal"),
    ({"fixed": [7]}, "fixed joints"),
    ({"step": -0.1}, "step"),
    ({"margin": 0.0}, "margin"),
    ({"period_steps": 0}, "period_steps"),
    ({"max_periods": 10**9, "patience": 10**9}, "period_steps x max_periods = 2e+10 integrator steps, more than"),
])
def test_virtual_arms_obstacles_bad_input_is_a_clear_value_error(kwargs, words):
    arguments = {"goal": GOAL, "obstacles": BLOCK} | kwargs
    with pytest.raises(ValueError) as info:
        avoid_obstacles(ARM, Q0, arguments.pop("goal"), arguments.pop("obstacles"), **arguments)
    assert words in str(info.value)


def test_virtual_arms_obstacles_model_must_match_the_points():
    model = AnalyticModel(ARM, [VirtualPoint.end()])
    with pytest.raises(ValueError, match="model must serve the end point"):
        avoid_obstacles(ARM, Q0, GOAL, BLOCK, points=[VirtualPoint.joint(3)], model=model)


coordinate = st.floats(-1.0, 1.0, allow_nan=False)


@settings(deadline=None, max_examples=60)
@given(st.lists(coordinate, min_size=9, max_size=9), st.floats(0.01, 0.5), st.sampled_from([2, 3]))
def test_virtual_arms_segment_clearance_equals_dense_sampling(values, radius, dims):
    start, end, centre = (np.array(values[3 * k: 3 * k + dims]) for k in range(3))
    obstacle = Obstacle(centre, radius)
    t = np.linspace(0.0, 1.0, 20001)[:, None]
    sampled = obstacle.clearance(start + t * (end - start)).min()
    exact = float(_segment_clearance(start, end, obstacle))
    assert exact <= sampled + 1e-12
    assert sampled - exact <= np.linalg.norm(end - start) / 20000 + 1e-12


def test_virtual_arms_segment_clearance_of_a_zero_length_segment_is_the_point_clearance():
    obstacle = Obstacle(np.array([1.0, 0.0]), 0.25)
    point = np.array([0.2, 0.3])
    assert float(_segment_clearance(point, point, obstacle)) == pytest.approx(float(obstacle.clearance(point)))


@settings(deadline=None, max_examples=30)
@given(st.integers(2, 6), st.integers(0, 2**31 - 1), st.floats(0.01, 0.5))
def test_virtual_arms_densify_keeps_records_and_bounds_the_joint_step(count, seed, max_step):
    theta = np.random.default_rng(seed).uniform(-2.0, 2.0, size=(count, 3))
    dense, record = densify(theta, max_step)
    assert np.max(np.abs(np.diff(dense, axis=0))) <= max_step + 1e-12
    ends = np.flatnonzero(np.diff(np.append(record, count)) != 0)  # last dense vector of every record's interval
    assert np.allclose(dense[ends], theta)
    assert record[0] == 0 and np.all(np.diff(record) >= 0) and record[-1] == count - 1


def test_virtual_arms_repulsion_pushes_outward_only_within_influence():
    obstacle = [Obstacle(np.array([0.0, 0.0]), 0.1)]
    points = np.array([[0.15, 0.0], [0.0, -0.12], [0.5, 0.5]])
    push = repulsion(points, obstacle, influence=0.1, gain=0.03)
    assert push[0] == pytest.approx([0.03 * 0.5, 0.0])
    assert push[1] == pytest.approx([0.0, -0.03 * 0.8])
    assert np.all(push[2] == 0.0)


def test_virtual_arms_end_step_slides_round_an_obstacle_in_its_way():
    obstacle = [Obstacle(np.array([0.0, 0.0]), 0.1)]
    position, goal = np.array([0.0, 0.15]), np.array([0.05, -1.0])
    d = _end_step(position, goal, obstacle, step=0.05, influence=0.1)
    assert np.linalg.norm(d) == pytest.approx(0.05)
    assert d @ position == pytest.approx(0.0, abs=1e-12)  # tangent: no part heading into the obstacle
    assert d[0] > 0.0  # on the goal's side
    far = _end_step(np.array([0.0, 1.0]), np.array([0.0, 2.0]), obstacle, step=0.05, influence=0.1)
    assert far == pytest.approx([0.0, 0.05])


def test_absurd_goals_and_obstacles_are_refused_by_name():
    """A finite but absurd goal or obstacle (1e308 m) overflowed into 'theta must be finite'; now the input is
    named, in the library as in the CLI."""
    from redkin.models import planar_arm
    from redkin.virtual_arms import AnalyticModel, VirtualPoint, avoid_obstacles, generate_trajectory

    model = AnalyticModel(planar_arm(), [VirtualPoint.end()])
    with pytest.raises(ValueError, match="goals must be at most 1e\\+06 m"):
        generate_trajectory(model, np.radians([30.0] * 5), [[1e308, 1.2]])
    with pytest.raises(ValueError, match="goal must be at most 1e\\+06 m"):
        avoid_obstacles(planar_arm(), np.radians([30.0] * 5), [1e308, 0.6], [])
    with pytest.raises(ValueError, match="obstacle 0 must be at most 1e\\+06 m"):
        avoid_obstacles(planar_arm(), np.radians([30.0] * 5), [0.5, 0.6], [[0.75, 0.9, 1e308]])
