"""The fewest reconfiguration stops (redkin.paths.stops): equal to a brute force over sampled configurations of
every branch, each segment continuous and within the limits, the stops named, and the timed trajectory at rest
through each reconfiguration."""

from __future__ import annotations

import json

import numpy as np
import pytest

import redkin
from redkin.cli.main import main
from redkin.models import kuka_iiwa14
from redkin.paths import resolve_path

#: An iiwa14 whose joint 1 turns +-1.8 rad only, so that a tool swept about the base must flip the shoulder (an
#: acceleration limit of 10 rad/s^2 assumed for timing: KUKA publishes none).
_BASE = kuka_iiwa14().with_motion_limits(acceleration=[10.0] * 7)
NARROW = _BASE.with_limits(np.r_[-1.8, _BASE.lower[1:]], np.r_[1.8, _BASE.upper[1:]])
STEP = 0.25


def _sweep(end: float, count: int) -> np.ndarray:
    """Poses of the unrestricted arm turning joint 1 from -1.6 rad to ``end``, the rest of the arm fixed."""
    q = np.tile(np.array([0.0, 0.6, 0.0, -1.2, 0.0, 0.8, 0.0]), (count, 1))
    q[:, 0] = np.linspace(-1.6, end, count)
    return _BASE.fk(q)


def _brute_force_stops(chain, poses: np.ndarray, step: float, samples: int = 180) -> int:
    """The fewest stops over sampled configurations: every branch at ``samples`` arm angles per waypoint (the
    closed form of redkin.arm), consecutive nodes joined where no joint moves more than ``step``, and a stop joining
    any two nodes of one waypoint."""
    arm = redkin.arm(chain)
    psi = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    solutions = arm.ik(poses[:, None], psi)  # q (N, S, 8, 7)
    usable = solutions.exists & solutions.within_limits
    nodes = [solutions.q[k][usable[k]] for k in range(len(poses))]
    if not all(len(n) for n in nodes):
        return -1
    cost = np.zeros(len(nodes[0]))  # the fewest stops to arrive at each node
    for k in range(1, len(poses)):
        depart = np.minimum(cost, cost.min() + 1)  # a stop at waypoint k - 1 leaves from any of its nodes
        arrive = np.full(len(nodes[k]), np.inf)
        for chunk in range(0, len(nodes[k]), 256):
            within = np.abs(nodes[k][chunk : chunk + 256, None, :] - nodes[k - 1][None]).max(axis=-1) <= step
            arrive[chunk : chunk + 256] = np.where(within, depart[None], np.inf).min(axis=1, initial=np.inf)
        cost = arrive
    return int(cost.min()) if len(cost) and np.isfinite(cost.min()) else -1


@pytest.mark.parametrize(("end", "count", "expected"), [(1.5, 14, 0), (3.0, 22, 1), (7.5, 46, 2), (9.0, 56, 3)])
def test_the_fewest_stops_equal_a_brute_force_over_sampled_configurations(end, count, expected):
    poses = _sweep(end, count)
    result = resolve_path(NARROW, poses, STEP, allow_stops=True)
    assert result.ok and len(result.stops) == expected == _brute_force_stops(NARROW, poses, STEP)
    np.testing.assert_allclose(NARROW.fk(result.q), poses, atol=1e-9)
    assert NARROW.within_limits(result.q).all()
    stops = {stop.waypoint for stop in result.stops}
    for k in range(1, len(poses)):  # continuous between stops: from the departure configuration at a stop
        before = next(s.path[-1] for s in result.stops if s.waypoint == k - 1) if k - 1 in stops else result.q[k - 1]
        assert np.abs(result.q[k] - before).max() <= STEP + 1e-12
    for stop in result.stops:
        np.testing.assert_allclose(NARROW.fk(stop.path[-1]), poses[stop.waypoint], atol=1e-9)
        assert stop.path[0].tolist() == result.q[stop.waypoint].tolist()
        assert stop.reason in ("branch", "jump") and f"stop at waypoint {stop.waypoint}" in stop.message
        if stop.motion == "self-motion":  # the tool stays at the pose along the whole reconfiguration
            np.testing.assert_allclose(NARROW.fk(stop.path), poses[stop.waypoint][None].repeat(len(stop.path), 0),
                                       atol=1e-9)


def test_without_stops_the_same_path_fails_where_the_first_stop_is_needed():
    poses = _sweep(3.0, 22)
    plain = resolve_path(NARROW, poses, STEP)
    stopped = resolve_path(NARROW, poses, STEP, allow_stops=True)
    assert not plain.ok and plain.failure.reason == "step"
    assert stopped.stops[0].waypoint == plain.failure.waypoint - 1


def test_a_jump_no_stop_can_pass_fails_as_without_stops():
    """The elbow (joint 4 of an S-R-S arm is fixed by the pose) jumps between two waypoints: no reconfiguration at
    either waypoint helps."""
    q = np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]) + np.linspace(-0.2, 0.2, 10)[:, None] * np.array(
        [1.0, 0.5, -0.5, 0.0, 0.5, 0.5, 1.0])
    q[5:, 3] += 0.3
    poses = _BASE.fk(q)
    plain, stopped = resolve_path(_BASE, poses, 0.2), resolve_path(_BASE, poses, 0.2, allow_stops=True)
    assert not stopped.ok and stopped.failure == plain.failure


def test_the_timed_trajectory_rests_through_each_reconfiguration():
    pytest.importorskip("toppra")
    poses = _sweep(3.0, 22)
    result = resolve_path(NARROW, poses, STEP, allow_stops=True, timing=1000.0)
    trajectory, (stop,) = result.trajectory, result.stops
    assert np.all(np.abs(trajectory.qd) <= NARROW.velocity) and np.all(np.abs(trajectory.qdd) <= NARROW.acceleration)
    assert NARROW.within_limits(trajectory.q).all()
    q, _, _ = trajectory.at(trajectory.waypoint_times)
    np.testing.assert_allclose(q, result.q, atol=1e-12)
    arrive = trajectory.waypoint_times[stop.waypoint]
    rest = int(np.ceil(arrive * 1000.0 - 1e-9))  # the first sample on the grid after arriving: at rest there
    np.testing.assert_allclose(trajectory.q[rest], stop.path[0], atol=1e-12)
    np.testing.assert_array_equal(trajectory.qd[rest], 0.0)
    departs = trajectory.waypoint_times[stop.waypoint + 1]
    moving = (trajectory.t > arrive) & (trajectory.t < departs)
    reconfigured = np.isclose(trajectory.q, stop.path[-1], atol=1e-12).all(axis=1) & moving
    assert reconfigured.any()  # the arm reaches the departure configuration before going on
    np.testing.assert_allclose(np.diff(trajectory.t)[:-1], 1e-3, rtol=1e-9)  # one grid through the stop


def test_a_trajectory_at_rest_at_every_waypoint_runs_along_the_straight_steps():
    """The last resort of a path in a cell whose spline cannot be proved clear (``timed(..., at_rest=True)``): the
    arm rests at every row, so every sample lies on the straight joint-space step between the two rows around it,
    at rest at each waypoint, through a stop's reconfiguration too, within the limits of motion."""
    pytest.importorskip("toppra")
    from dataclasses import replace

    from redkin.paths.stops import timed

    result = resolve_path(NARROW, _sweep(3.0, 22), STEP, allow_stops=True)
    trajectory = timed(NARROW, replace(result, trajectory=None), 500.0, at_rest=True).trajectory
    assert np.all(np.abs(trajectory.qd) <= NARROW.velocity) and np.all(np.abs(trajectory.qdd) <= NARROW.acceleration)
    q, qd, _ = trajectory.at(trajectory.waypoint_times)
    np.testing.assert_allclose(q, result.q, atol=1e-12)
    np.testing.assert_allclose(qd, 0.0, atol=1e-9)
    rows = np.concatenate([result.q[: result.stops[0].waypoint + 1], result.stops[0].path[1:],
                           result.q[result.stops[0].waypoint + 1:]])  # the joint path, the reconfiguration inside
    for sample in trajectory.q:  # on some straight step: its distance from the nearest step's line is rounding
        first, line = rows[:-1], np.diff(rows, axis=0)
        length = np.maximum(np.einsum("ij,ij->i", line, line), 1e-300)
        along = np.clip(np.einsum("ij,ij->i", sample - first, line) / length, 0.0, 1.0)
        assert np.linalg.norm(first + along[:, None] * line - sample, axis=1).min() <= 1e-9


def test_the_command_line_says_when_a_trajectory_in_a_cell_rests_at_every_waypoint():
    """``redkin path --timed --scene`` reports a trajectory at rest at every waypoint (the last resort for steps that
    graze the margin) in its line and in JSON, and not a spline that passes through them."""
    pytest.importorskip("toppra")
    from dataclasses import replace

    from redkin.cli.path import _trajectory_in_cell
    from redkin.collision import BodyCapsule, Scene, body_of, primitives
    from redkin.paths.stops import timed

    body = body_of([BodyCapsule("forearm", 4, [0, 0, 0], [0, 0, 0.2], 0.05)], NARROW)
    far = Scene(("ball",), primitives.sphere([3.0, 0.0, 0.0], 0.1)[None], 0.01)
    poses = _sweep(1.5, 14)
    smooth = resolve_path(NARROW, poses, STEP, body=body, scene=far, timing=500.0)
    report, line = _trajectory_in_cell(smooth)
    assert report["clear"] and not report["at_rest_at_waypoints"] and "rest" not in line
    stopping = replace(smooth, trajectory=timed(NARROW, replace(smooth, trajectory=None), 500.0,
                                                at_rest=True).trajectory)
    report, line = _trajectory_in_cell(stopping)
    assert report["at_rest_at_waypoints"] and "comes to rest at every waypoint" in line


def test_the_command_line_names_each_stop(tmp_path, capsys):
    robot = tmp_path / "narrow.toml"
    poses = tmp_path / "sweep.npy"
    np.save(poses, _sweep(3.0, 22))
    _write_narrow_robot(robot)
    q = np.random.default_rng(0).uniform(NARROW.lower, NARROW.upper, (5, 7))
    np.testing.assert_allclose(redkin.get_robot(robot).fk(q), NARROW.fk(q), atol=1e-12)
    argv = ["path", str(robot), "--poses", str(poses), "--max-step", str(STEP), "--allow-stops"]
    assert main(argv + ["--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    (stop,) = report["stops"]
    (expected,) = resolve_path(NARROW, np.load(poses), STEP, allow_stops=True).stops
    assert (stop["waypoint"], stop["reason"], stop["joint"]) == (expected.waypoint, expected.reason, expected.joint)
    assert len(report["q"]) == 22 and stop["message"].startswith(f"stop at waypoint {stop['waypoint']}")
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "1 reconfiguration stop (the fewest" in text and stop["message"] in text
    assert main(argv[:-1]) == 1  # without --allow-stops: no path
    capsys.readouterr()


def _write_narrow_robot(file) -> None:
    """NARROW as a robot file (Table 1 rows of the iiwa14, joint 4 reversed as KUKA turns it)."""
    rows = "".join(
        f"[[joint]]\na = {a!r}\nalpha = {alpha!r}\nd = {d!r}\nsign = {sign!r}\nlower = {lo!r}\nupper = {hi!r}\n\n"
        for a, alpha, d, sign, lo, hi in zip(NARROW.a.tolist(), NARROW.alpha.tolist(), NARROW.d.tolist(),
                                              NARROW.sign.tolist(), NARROW.lower.tolist(), NARROW.upper.tolist()))
    tool = NARROW.tool[:3, 3].tolist()
    file.write_text(f'name = "iiwa14-narrow"\nconvention = "dh"\nangle_unit = "rad"\n\n{rows}'
                    f"[tool]\ntranslation = {tool!r}\n")


def test_a_reconfiguration_inside_one_feasible_piece_is_a_self_motion_that_keeps_the_tool_still():
    from redkin.paths.arm_family import path_family
    from redkin.paths.stops import _self_motion

    family = path_family(_BASE)
    arm = redkin.arm(_BASE)
    q = np.array([0.3, 0.7, -0.2, -1.3, 0.4, 0.9, 0.1])
    pose = _BASE.fk(q)
    branch, psi = arm.branch_of(q), float(arm.parameter_of(q))
    sets = arm.feasible(pose)
    b = sets.index(str(branch))
    lo, hi = next((lo, hi) for lo, hi, keep in zip(sets.start[b], sets.end[b], sets.feasible[b])
                  if keep and lo <= psi <= hi)
    other = lo + 0.8 * (hi - lo) if psi < 0.5 * (lo + hi) else lo + 0.2 * (hi - lo)
    q_other = arm.ik(pose, other, branches=[str(branch)]).q[0]
    path = _self_motion(family, pose, np.full(7, 0.05), str(branch), psi, other, q, q_other)
    assert path is not None and path[0].tolist() == q.tolist() and path[-1].tolist() == q_other.tolist()
    np.testing.assert_allclose(_BASE.fk(path), np.broadcast_to(pose, path.shape[:1] + (4, 4)), atol=1e-9)
    assert np.abs(np.diff(path, axis=0)).max() <= 0.05 and _BASE.within_limits(path).all()
    assert _self_motion(family, pose, np.full(7, 0.05), str(branch), psi, other + 10.0, q,
                        q_other) is None  # a value no feasible piece holds
