"""Timed trajectories (redkin.paths.timing): every sample within the velocity and acceleration limits, the
waypoints passed exactly, at rest at both ends, consistent derivatives, and no faster than the limits allow."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.errors import RedkinError
from redkin.models import franka_panda, kuka_iiwa14
from redkin.paths import resolve_path, time_path

pytest.importorskip("toppra")

PANDA = franka_panda()
#: An iiwa14 with an acceleration limit (KUKA publishes none) of 10 rad/s^2 on every joint.
IIWA = kuka_iiwa14().with_motion_limits(acceleration=[10.0] * 7)


def _joint_line(chain, start_fraction: np.ndarray, move: np.ndarray, count: int) -> np.ndarray:
    """``count`` joint vectors along a straight joint-space line inside ``chain``'s limits (with a bend: a sine
    on top), from the point at ``start_fraction`` of each range."""
    low, high = chain.lower + 0.2, chain.upper - 0.2
    start = low + start_fraction * (high - low)
    s = np.linspace(0.0, 1.0, count)[:, None]
    return np.clip(start + s * move + 0.05 * np.sin(6.0 * s) * np.roll(move, 1), low, high)


def _check_laws(chain, q: np.ndarray, trajectory) -> None:
    t, v, a = trajectory.t, trajectory.velocity, trajectory.acceleration
    assert t[0] == 0.0 and t[-1] == trajectory.duration and np.all(np.diff(t) > 0.0)
    np.testing.assert_allclose(np.diff(t)[:-1], 1.0 / trajectory.rate, rtol=1e-9)
    assert np.all(np.abs(trajectory.qd) <= v) and np.all(np.abs(trajectory.qdd) <= a)
    assert np.all(trajectory.q >= chain.lower) and np.all(trajectory.q <= chain.upper)
    np.testing.assert_array_equal(trajectory.qd[[0, -1]], 0.0)  # at rest at both ends
    at, _, _ = trajectory.at(trajectory.waypoint_times)
    np.testing.assert_allclose(at, q, atol=1e-12)
    assert np.all(np.diff(trajectory.waypoint_times) >= 0.0)
    # the samples' derivatives are those of the samples: with the speed's slope within +-a, a step's mean speed is
    # the mean of its ends' speeds to within a dt / 4
    step = np.diff(t)[:-1, None]
    mean_speed = np.diff(trajectory.q, axis=0)[:-1] / step
    np.testing.assert_array_less(np.abs(mean_speed - 0.5 * (trajectory.qd[1:-1] + trajectory.qd[:-2])),
                                 a * step / 4.0 + 1e-9)
    # no faster than each joint could cover its distance at full speed
    assert trajectory.duration >= (np.abs(np.diff(q, axis=0)).sum(axis=0) / v).max() - 1e-12


@settings(max_examples=12)
@given(st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7), st.lists(st.floats(-0.8, 0.8), min_size=7,
                                                                         max_size=7),
       st.integers(2, 40), st.sampled_from([100.0, 1000.0]))
def test_every_sample_keeps_the_limits_and_the_waypoints_are_passed_exactly(start, move, count, rate):
    q = _joint_line(PANDA, np.array(start), np.array(move), count)
    trajectory = time_path(PANDA, q, rate=rate)
    _check_laws(PANDA, q, trajectory)


def test_a_resolved_path_is_timed_within_the_limits_and_reaches_its_poses_at_the_waypoint_times():
    q = _joint_line(IIWA, np.full(7, 0.4), np.array([0.8, -0.3, 0.5, 0.6, -0.4, 0.3, 1.0]), 200)
    poses = IIWA.fk(q)
    result = resolve_path(IIWA, poses, 0.05, timing=500.0)
    assert result.ok and result.trajectory is not None and result.trajectory.rate == 500.0
    _check_laws(IIWA, result.q, result.trajectory)
    at, _, _ = result.trajectory.at(result.trajectory.waypoint_times)
    np.testing.assert_allclose(IIWA.fk(at), poses, atol=1e-9)


def test_the_time_objective_is_never_slower_than_either_other_objective():
    q = _joint_line(PANDA, np.full(7, 0.5), np.array([0.5, 0.3, -0.2, 0.4, 0.3, -0.3, 0.2]), 120)
    poses = PANDA.fk(q)
    durations = {objective: resolve_path(PANDA, poses, 0.05, objective=objective, timing=1000.0).trajectory.duration
                 for objective in ("clearance", "motion", "time")}
    assert durations["time"] == min(durations["clearance"], durations["motion"])
    assert resolve_path(PANDA, poses, 0.05, objective="time").trajectory.rate == 1000.0  # timed by default


def test_waypoints_at_a_limit_are_joined_without_leaving_the_range():
    """Waypoints that touch a limit (the motion objective's paths do) would make the cubic spline bend past it;
    the trajectory then follows the shape-keeping interpolant, and says so."""
    q = _joint_line(PANDA, np.full(7, 0.5), np.array([0.4, 0.3, -0.2, 0.3, 0.3, -0.3, 0.2]), 30)
    q[10:20, 1] = PANDA.upper[1]  # joint 2 rests at its upper limit for ten waypoints
    q[9, 1] = q[20, 1] = PANDA.upper[1] - 0.02
    trajectory = time_path(PANDA, q)
    assert trajectory.interpolation == "pchip"
    _check_laws(PANDA, q, trajectory)


def test_repeated_waypoints_are_passed_once_and_one_configuration_rests():
    q = _joint_line(PANDA, np.full(7, 0.5), np.full(7, 0.3), 5)
    doubled = np.repeat(q, 2, axis=0)
    trajectory = time_path(PANDA, doubled)
    np.testing.assert_array_equal(trajectory.waypoint_times[0::2], trajectory.waypoint_times[1::2])
    assert trajectory.duration == time_path(PANDA, q).duration
    resting = time_path(PANDA, q[:1].repeat(3, axis=0))
    assert resting.duration == 0.0 and resting.interpolation == "rest" and resting.t.tolist() == [0.0]
    np.testing.assert_array_equal(resting.q, q[:1])


def test_the_message_form_is_a_joint_trajectory():
    q = _joint_line(PANDA, np.full(7, 0.5), np.full(7, 0.3), 5)
    trajectory = time_path(PANDA, q, rate=100.0)
    message = json.loads(json.dumps(trajectory.joint_trajectory()))
    assert message["joint_names"] == list(PANDA.joint_names)
    assert len(message["points"]) == len(trajectory.t)
    last = message["points"][-1]
    assert last["time_from_start"]["sec"] + last["time_from_start"]["nanosec"] * 1e-9 == pytest.approx(
        trajectory.duration, abs=1e-9)
    np.testing.assert_array_equal(last["positions"], trajectory.q[-1])
    assert set(last) == {"positions", "velocities", "accelerations", "time_from_start"}


def test_bad_input_is_refused_in_one_line():
    q = _joint_line(PANDA, np.full(7, 0.5), np.full(7, 0.3), 5)
    cases = {
        "no acceleration limit on joints 1 (": lambda: time_path(kuka_iiwa14(), _joint_line(IIWA, np.full(7, 0.5),
                                                                                        np.full(7, 0.3), 5)),
        "rate must be a positive": lambda: time_path(PANDA, q, rate=0.0),
        "q must have shape (N, 7)": lambda: time_path(PANDA, q[:, :6]),
        "q must be finite": lambda: time_path(PANDA, np.where(q == q[0, 0], np.nan, q)),
        "waypoint 0: joint 4": lambda: time_path(PANDA, np.where(np.arange(7) == 3, 0.5, q)),
        "velocity limits must be > 0": lambda: time_path(PANDA, q, velocity=-1.0),
        "no acceleration limit": lambda: resolve_path(kuka_iiwa14(), PANDA.fk(q), 0.05, objective="time"),
        "rate must be": lambda: resolve_path(PANDA, PANDA.fk(q), 0.05, timing=-1.0),
    }
    for expected, call in cases.items():
        with pytest.raises(RedkinError) as raised:
            call()
        assert expected in str(raised.value) and "\n" not in str(raised.value), expected


@settings(max_examples=20)
@given(st.integers(0, 2**32 - 1))
def test_stretches_along_a_limit_are_timed_inside_the_range(seed):
    """A path that runs along a joint limit for many waypoints (as the motion objective's do, each value on the
    limit or a rounding inside it): the PCHIP samples there compute the limit to within rounding, and every sample
    is inside the range (none a unit past it; before the clip, 15 of 40 such paths were refused)."""
    rng = np.random.default_rng(seed)
    q = _joint_line(PANDA, rng.uniform(0.2, 0.8, 7), rng.uniform(-0.5, 0.5, 7), 60)
    joint = int(rng.integers(7))
    q[:, joint] = np.clip(q[:, joint] + rng.uniform(-0.2, 0.2) + 0.3 * np.sin(np.linspace(0, 3, 60)),
                          PANDA.lower[joint] + 0.2, PANDA.upper[joint] - 0.2)
    up = rng.random() < 0.5
    side = PANDA.upper[joint] if up else PANDA.lower[joint]
    q[15:45, joint] = side - (1.0 if up else -1.0) * rng.choice([0.0, 1e-15, 3e-14, 1e-13], 30)
    trajectory = time_path(PANDA, q)
    _check_laws(PANDA, q, trajectory)
