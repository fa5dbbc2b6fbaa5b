"""Timed trajectories (redkin.paths.timing): every sample within the velocity and acceleration limits, the
waypoints passed exactly, at rest at both ends, consistent derivatives, and no faster than the limits allow."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.errors import RedkinError, SizeLimitError
from redkin.models import franka_panda, kuka_iiwa14
from redkin.paths import resolve_path, time_path
from redkin.paths.timing import MAX_SAMPLES, _least_duration

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
    # no faster than each joint could cover its distance at full speed, or reach its farthest waypoint from rest:
    # the least duration by which a trajectory too long to sample is refused before it is timed
    assert trajectory.duration >= (np.abs(np.diff(q, axis=0)).sum(axis=0) / v).max() - 1e-12
    assert trajectory.duration >= _least_duration(q, {"velocity": v, "acceleration": a})[0] - 1e-12


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


def test_the_time_objective_takes_the_path_that_can_be_timed(monkeypatch):
    """Where the time parametrisation refuses one of the two paths, the time objective returns the other timed
    (it failed whole); where it refuses both, its first refusal."""
    import redkin.paths.resolve as resolve

    q = _joint_line(PANDA, np.full(7, 0.5), np.array([0.5, 0.3, -0.2, 0.4, 0.3, -0.3, 0.2]), 40)
    poses = PANDA.fk(q)
    motion = resolve_path(PANDA, poses, 0.05, objective="motion", timing=1000.0)
    timed = resolve._timed
    calls: list = []

    def refusing(family, result, rate, again=None):  # the first path timed (the clearance path) is refused
        calls.append(result)
        if len(calls) == 1:
            raise RedkinError("the clearance path refused")
        return timed(family, result, rate, again)

    monkeypatch.setattr(resolve, "_timed", refusing)
    chosen = resolve_path(PANDA, poses, 0.05, objective="time")
    assert len(calls) == 2
    np.testing.assert_array_equal(chosen.q, motion.q)
    assert chosen.trajectory.duration == motion.trajectory.duration

    def refusing_all(family, result, rate, again=None):
        raise RedkinError("no profile")

    monkeypatch.setattr(resolve, "_timed", refusing_all)
    with pytest.raises(RedkinError, match="no profile"):
        resolve_path(PANDA, poses, 0.05, objective="time")


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
        "no acceleration limit on joints 1, 2, 3, 4, 5, 6, 7: give": lambda: time_path(
            kuka_iiwa14(), _joint_line(IIWA, np.full(7, 0.5), np.full(7, 0.3), 5)),
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


def test_limits_too_small_to_time_are_refused_in_one_line():
    """A velocity limit whose least duration needs more than MAX_SAMPLES samples is refused before the time
    parametrisation (it overflowed to an infinite sample count); an acceleration limit so small that the
    parametrisation's speeds round to 0 is refused in words (it gave a NaN duration)."""
    q = IIWA.fk(_joint_line(IIWA, np.full(7, 0.3), np.full(7, 0.4), 10))
    q = resolve_path(IIWA, q, 0.1).q
    least = np.abs(np.diff(q, axis=0)).sum(axis=0).max() / 1e-3
    with pytest.raises(SizeLimitError, match=r"joint \d alone needs at least") as raised:
        time_path(IIWA, q, velocity=1e-300)
    assert raised.value.value > MAX_SAMPLES
    rate = 0.5 * MAX_SAMPLES / least  # the least duration fits at this rate, and twice it does not
    time_path(IIWA, q, velocity=1e-3, acceleration=1e3, rate=rate)
    with pytest.raises(SizeLimitError, match="check the limits, or lower the rate"):
        time_path(IIWA, q, velocity=1e-3, acceleration=1e3, rate=4.0 * rate)
    with pytest.raises(RedkinError, match="no profile of finite duration") as raised:
        time_path(IIWA, q, velocity=1.0, acceleration=1e-12, rate=1e-3)
    assert "\n" not in str(raised.value)


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


#: A straight line of the iiwa14 at arm angle 0 as `redkin path` resolved it (21 waypoints, y from -0.2 to 0.2 m at
#: x = 0.55, z = 0.5, the tool pointing down), whose TOPP-RA grid held a point 1e-16 from a knot.
LINE = np.array([
    [-0.348771003583907, 0.49350497162342993, 0.0, -1.3400151132797797, 0.0, 1.3080725686865837, -0.3487710035839069],
    [-0.3162861279121545, 0.478139993927961, 0.0, -1.3631891526705464, 0.0, 1.3002635069912858, -0.31628612791215455],
    [-0.28309578529949553, 0.46433616145017803, -2.7755575615628914e-17, -1.3838279626742127,
     0.0, 1.2934285294654024, -0.2830957852994955],
    [-0.24925214138521365, 0.45210444405444916, 0.0, -1.401971692919997, 0.0, 1.287516516615347, -0.24925214138521357],
    [-0.2148154004016586, 0.4414590189317212, 0.0, -1.4176507746246056, 0.0, 1.2824828600334666, -0.21481540040165856],
    [-0.17985349979247825, 0.43241563551233786, -2.7755575615628914e-17, -1.4308879564055357,
     0.0, 1.2782890616719198, -0.17985349979247825],
    [-0.14444157837464397, 0.4249901785050696, 0.0, -1.4416999462101443, 0.0, 1.2749025288745792, -0.14444157837464394],
    [-0.10866121584058781, 0.41919742320134734, 0.0, -1.4500987262948963,
     0.0, 1.2722965040935494, -0.10866121584058787],
    [-0.07259945373049459, 0.41504998897179857, -1.3877787807814463e-17, -1.4560925860612046,
     0.0, 1.2704500785567898, -0.0725994537304946],
    [-0.03634762101902064, 0.4125575033849585, 0.0, -1.4596869022125938, 0.0, 1.269348247992241, -0.03634762101902064],
    [0.0, 0.4117259914934796, 0.0, -1.460884685041769, 0.0, 1.2689819770545447, 0.0],
    [0.0363476210190207, 0.4125575033849585, 0.0, -1.4596869022125938, 0.0, 1.269348247992241, 0.0363476210190207],
    [0.07259945373049469, 0.4150499889717986, 0.0, -1.4560925860612046, 0.0, 1.2704500785567898, 0.0725994537304947],
    [0.10866121584058781, 0.41919742320134734, 0.0, -1.4500987262948963, 0.0, 1.2722965040935494, 0.10866121584058787],
    [0.144441578374644, 0.4249901785050696, 0.0, -1.4416999462101443, 0.0, 1.2749025288745792, 0.14444157837464397],
    [0.1798534997924783, 0.4324156355123379, 0.0, -1.4308879564055357, 0.0, 1.2782890616719198, 0.1798534997924783],
    [0.21481540040165867, 0.4414590189317212, 2.7755575615628907e-17, -1.4176507746246056,
     0.0, 1.2824828600334666, 0.21481540040165864],
    [0.2492521413852137, 0.45210444405444916, 5.55111512312578e-17, -1.401971692919997,
     0.0, 1.287516516615347, 0.24925214138521365],
    [0.2830957852994956, 0.46433616145017803, 2.7755575615628914e-17, -1.3838279626742127,
     0.0, 1.2934285294654024, 0.28309578529949553],
    [0.3162861279121545, 0.4781399939279612, 0.0, -1.3631891526705462, 0.0, 1.3002635069912858, 0.31628612791215444],
    [0.348771003583907, 0.49350497162342993, 0.0, -1.3400151132797797, 0.0, 1.3080725686865837, 0.3487710035839069],
])


def test_a_grid_point_a_rounding_away_from_a_knot_is_one_point():
    """TOPP-RA's proposed grid can put a point a rounding (1e-16) away from a knot: the profile's acceleration there
    was rounding divided by almost nothing (3e7 rad/s^2 on a straight line of the iiwa14, which halving never cured:
    "still exceeds a joint's limits ... after 8 refinements"). The straight line at arm angle 0 is timed within its
    limits, and the grid never holds two points closer than its spacing."""
    from redkin.paths.timing import _GRID_SPACING, _grid

    chain, q = kuka_iiwa14(), LINE
    for acceleration in (1.0, 5.0, 20.0):
        trajectory = time_path(chain, q, acceleration=np.full(7, acceleration))
        assert np.all(np.abs(trajectory.acceleration) <= acceleration)
    knots = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(q, axis=0), axis=1))]
    grid = _grid(np.r_[knots[5] + 1e-16, knots[7] - 2e-16, 0.3, 0.3 + 1e-17, np.linspace(0.0, knots[-1], 50)], knots)
    assert np.all(np.isin(knots, grid)) and 0.3 in grid
    assert np.diff(grid).min() > _GRID_SPACING * knots[-1]
