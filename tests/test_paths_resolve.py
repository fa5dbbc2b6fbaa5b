"""Path resolution (redkin.paths): every returned path reaches its poses, keeps the limits and the step bound;
failures name the right waypoint, reason and joint; the sampled baselines fail where it does not."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.errors import RedkinError
from redkin.models import get_robot
from redkin.paths import FK_TOLERANCE, OPTIMALITY_MARGIN, resolve_path, resolve_paths, step_bound
from redkin.paths.baselines import clamped_optimum_path, fixed_psi_path, greedy_path, sampled_path
from redkin.srs import arm_angle_of, ik, ik_all_branches

ROBOTS = ["kuka-iiwa14", "pa10-7c", "barrett-wam7"]


def _joint_line(chain, rng, count):
    """Poses along a straight joint-space line between two configurations inside the limits (margin 0.2 rad)."""
    lower = np.where(np.isfinite(chain.lower), chain.lower + 0.2, -np.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper - 0.2, np.pi)
    a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
    q = a + (b - a) * np.linspace(0.0, 1.0, count)[:, None]
    return q, chain.fk(q)


def _assert_lawful(chain, poses, result):
    """The laws of a returned path: FK, limits, bound, and the reported branch and arm angle."""
    assert result.ok and result.q.shape == (len(poses), 7)
    assert np.abs(chain.fk(result.q) - poses).max() <= FK_TOLERANCE
    assert chain.within_limits(result.q).all()
    moves = np.abs(np.diff(result.q, axis=0))
    assert np.all(moves <= result.step)
    for k in range(len(poses)):
        again = ik(chain, poses[k], result.psi[k], result.branch[k])
        turned = np.mod(again - result.q[k] + np.pi, 2 * np.pi) - np.pi
        assert np.abs(turned).max() < 1e-9
    clearance = np.minimum(result.q - chain.lower, chain.upper - result.q)[:, ~chain.covers_circle]
    expected = clearance.min() if clearance.size else np.inf
    assert result.clearance == pytest.approx(expected, abs=1e-12)


@settings(max_examples=5, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(ROBOTS))
def test_a_path_that_exists_is_found_and_keeps_every_law(seed, robot):
    chain = get_robot(robot)
    q, poses = _joint_line(chain, np.random.default_rng(seed), 8)
    step = 2.0 * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3  # the joint line itself is a path
    result = resolve_path(chain, poses, step)
    _assert_lawful(chain, poses, result)
    reference = np.minimum(q - chain.lower, chain.upper - q)[:, ~chain.covers_circle]
    if reference.size:  # at least as far from the limits as the path the poses came from
        assert result.clearance >= reference.min() - 1e-6


def test_the_start_and_end_conditions_hold():
    chain = get_robot("kuka-iiwa14")
    q, poses = _joint_line(chain, np.random.default_rng(3), 10)
    step = 2.0 * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3
    end_branch = str(arm_angle_of(chain, q[-1]).branch_strings())
    result = resolve_path(chain, poses, step, q0=q[0], q_end=q[-1], end_branch=end_branch)
    _assert_lawful(chain, poses, result)
    assert np.all(np.abs(result.q[0] - q[0]) <= step)
    assert np.all(np.abs(result.q[-1] - q[-1]) <= step)
    assert result.branch[-1] == end_branch


def test_many_paths_at_once_equal_one_by_one():
    chain = get_robot("pa10-7c")
    rng = np.random.default_rng(5)
    lines = [_joint_line(chain, rng, 8) for _ in range(3)]
    step = max(2.0 * np.abs(np.diff(q, axis=0)).max() for q, _ in lines) + 1e-3
    together = resolve_paths(chain, np.stack([poses for _, poses in lines]), step)
    for (_, poses), result in zip(lines, together):
        alone = resolve_path(chain, poses, step)
        assert alone.status == result.status
        np.testing.assert_array_equal(alone.q, result.q)


@pytest.mark.parametrize("fractions", [(1.0, 0.5), (10.0,), (0.9,)])
def test_the_floors_of_the_first_sweep_change_no_answer(fractions, monkeypatch):
    """The first sweep keeps only the nodes at or above a floor (:func:`redkin.paths.resolve._floored`): the paths
    found, their clearance and motion, and the failures, are those of the sweep without one, whether the floor
    holds (the best path lies above it), lies above every path (10 x the ceiling: lowered in turn) or anywhere."""
    import redkin.paths.resolve as resolve

    chain = get_robot("kuka-iiwa14")
    rng = np.random.default_rng(8)
    lines = [_joint_line(chain, rng, 12) for _ in range(4)]
    step = max(1.5 * np.abs(np.diff(q, axis=0)).max() for q, _ in lines)
    poses = np.stack([p for _, p in lines])
    poses[2, 6, :3, 3] *= 10.0  # out of reach: no path
    q_end = np.stack([q[-1] for q, _ in lines])
    q_end[3] += 3.0 * step  # an end no path meets
    cases = [dict(), dict(q0=np.stack([q[0] for q, _ in lines]), q_end=q_end), dict(objective="motion")]
    monkeypatch.setattr(resolve, "_FLOOR_FRACTIONS", ())
    plain = [resolve_paths(chain, poses, step, **case) for case in cases]
    monkeypatch.setattr(resolve, "_FLOOR_FRACTIONS", fractions)
    for case, expected in zip(cases, plain):
        for result, alone in zip(resolve_paths(chain, poses, step, **case), expected):
            assert result.status == alone.status and result.failure == alone.failure
            np.testing.assert_array_equal(result.q, alone.q)
            assert result.clearance == alone.clearance or (np.isnan(result.clearance) and np.isnan(alone.clearance))
    assert [r.status for r in plain[0]] == ["ok", "ok", "no-path", "ok"]
    assert plain[1][3].status == "no-path"


def test_speed_and_dt_give_the_step():
    chain = get_robot("kuka-iiwa14")
    np.testing.assert_allclose(step_bound(chain, speed=[1.0] * 7, dt=0.01), 0.01)
    with pytest.raises(RedkinError, match="one of them"):
        step_bound(chain, max_step=0.1, speed=1.0)
    with pytest.raises(RedkinError, match="needs dt"):
        step_bound(chain, speed=1.0)
    with pytest.raises(RedkinError, match="> 0"):
        step_bound(chain, max_step=[0.1] * 6 + [0.0])
    with pytest.raises(RedkinError, match="one number or 7"):
        step_bound(chain, max_step=[0.1] * 3)


def test_bad_input_is_refused():
    chain = get_robot("kuka-iiwa14")
    poses = chain.fk(np.zeros((3, 7)) + 0.3)
    with pytest.raises(RedkinError, match=r"shape \(N, 4, 4\)"):
        resolve_path(chain, poses[0], 0.1)
    with pytest.raises(ValueError):
        resolve_path(chain, poses * 2.0, 0.1)
    with pytest.raises(RedkinError, match="q0"):
        resolve_path(chain, poses, 0.1, q0=[0.0] * 6)
    with pytest.raises(ValueError, match="branch"):
        resolve_path(chain, poses, 0.1, end_branch="+x+")


# ------------------------------------------------------------------ failures, exact and on the graph
def _line_through(chain, q_middle, count=9):
    """Poses along a gentle joint-space path through ``q_middle`` at its middle waypoint."""
    offsets = np.linspace(-0.2, 0.2, count)[:, None] * np.array([1.0, 0.5, -0.5, 0.0, 0.5, 0.5, 1.0])
    return q_middle + offsets


def test_an_elbow_beyond_its_limit_is_reported_at_its_waypoint_and_joint():
    chain = get_robot("kuka-iiwa14")
    q = _line_through(chain, np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]))
    q[6:, 3] = -2.2  # the elbow beyond -120 deg from waypoint 6 on: no arm angle helps
    result = resolve_path(chain, chain.fk(q), 1.0)
    assert result.status == "no-path" and result.q.shape == (0, 7)
    failure = result.failure
    assert (failure.waypoint, failure.reason, failure.joint, failure.exact) == (6, "empty", 4, True)
    assert set(failure.per_branch.values()) == {4}
    assert "waypoint 6" in failure.message and "joint 4" in failure.message
    assert "no arm angle satisfies every joint limit" in failure.message


def test_a_pose_out_of_reach_is_reported():
    chain = get_robot("kuka-iiwa14")
    poses = chain.fk(_line_through(chain, np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0])))
    poses[5, :3, 3] *= 10.0
    failure = resolve_path(chain, poses, 1.0).failure
    assert (failure.waypoint, failure.reason, failure.joint, failure.exact) == (5, "out-of-reach", None, True)


def test_a_jump_between_waypoints_is_a_step_failure_naming_the_joint():
    chain = get_robot("kuka-iiwa14")
    q = _line_through(chain, np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]))
    q[5:, 3] += 0.3  # the elbow (the same at every arm angle) jumps by 0.3 rad into waypoint 5
    result = resolve_path(chain, chain.fk(q), 0.2)
    failure = result.failure
    # proved: the poses fix the elbow, whatever the arm angle, so the graph is not searched again finer
    assert (failure.waypoint, failure.reason, failure.joint, failure.exact) == (5, "step", 4, True)
    assert failure.needed == pytest.approx(0.3, abs=1e-9)
    q[5:, 3] -= 0.3 - 0.15  # a jump within the bound: nothing proved by the elbow
    assert resolve_path(chain, chain.fk(q), 0.2).ok


@settings(max_examples=25, deadline=None)
@given(st.sampled_from(ROBOTS), st.integers(0, 2**32 - 1))
def test_the_elbow_the_poses_fix_bounds_every_step_between_them(robot, seed):
    """:func:`redkin.paths.graph.least_moves` of two poses' fixed joints (the elbow of an S-R-S arm, one value per
    elbow sign) is at most the move of every joint between any configuration of one pose and any of the other,
    on every branch and arm angle, and equal to the least elbow move among them (the elbow does not depend on the
    arm angle); from a start configuration likewise."""
    from redkin.paths.family import ArmAngleFamily
    from redkin.paths.graph import least_moves
    from redkin.srs.geometry import srs_geometry

    chain = get_robot(robot)
    rng = np.random.default_rng(seed)
    lower, upper = np.maximum(chain.lower, -np.pi), np.minimum(chain.upper, np.pi)
    qa = rng.uniform(lower, upper)
    qb = np.clip(qa + rng.normal(0.0, 0.3, 7), lower, upper)
    poses = chain.fk(np.stack([qa, qb]))
    reach, arm = ArmAngleFamily(srs_geometry(chain)).arm(poses, np.full(7, 0.1))
    assert reach.all()
    least = least_moves(arm, arm.pose_fixed(0), arm.pose_fixed(1))
    psi = np.linspace(-np.pi, np.pi, 91)
    found = [ik_all_branches(chain, pose, psi).reshape(-1, 7) for pose in poses]  # NaN where a branch does not exist
    configurations = [q[np.all(np.isfinite(q), axis=-1)] for q in found]
    moves = arm.moves(configurations[0][:, None], configurations[1][None])
    assert np.all(moves.min(axis=(0, 1)) >= least - 1e-9)
    assert moves[..., 3].min() == pytest.approx(least[3], abs=1e-9)
    assert np.all(np.delete(least, 3) == 0.0)
    start = least_moves(arm, qa[None], arm.pose_fixed(1))
    assert np.all(arm.moves(qa, configurations[1]).min(axis=0) >= start - 1e-9)


def test_a_start_too_far_from_the_first_pose_is_a_start_failure():
    chain = get_robot("kuka-iiwa14")
    q = _line_through(chain, np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]))
    start = q[0].copy()
    start[3] += 0.5
    failure = resolve_path(chain, chain.fk(q), 0.2, q0=start).failure
    assert (failure.waypoint, failure.reason, failure.joint) == (0, "start", 4)
    assert failure.needed == pytest.approx(0.5, abs=1e-6)


# ------------------------------------------------------------------ a narrow passage
def _narrow_passage(width=1e-4):
    """An iiwa path of 9 poses whose limits leave, at waypoint 4, one feasible arc ``width`` wide (joints 1 and 3
    close it from both sides; joints 2, 4, 6 keep one branch), and the arm angle inside it."""
    base = get_robot("kuka-iiwa14")
    t = np.linspace(0.0, 1.0, 9)
    u = t - t[4]
    q = np.stack([0.5 + 2 * u**2, 0.7 + 0.2 * t, -0.3 + 2 * u**2, -1.3 + 0.3 * t, 0.2 + 0.3 * t, 0.6 - 0.4 * t,
                  0.1 * t], axis=-1)
    poses = base.fk(q)
    psi = float(arm_angle_of(base, q[4]).psi)
    lower, upper = base.lower.copy(), base.upper.copy()
    lower[1], lower[3], upper[3], lower[5] = 0.0, -2.0, 0.0, 0.0  # branch +-+ only
    lower[0], upper[0] = ik(base, poses[4], psi + width / 2, "+-+")[0], 1.5  # joint 1 falls with psi here
    lower[2], upper[2] = ik(base, poses[4], psi - width / 2, "+-+")[2], 0.7  # joint 3 rises with psi here
    return base.with_limits(lower, upper), q, poses, psi


def test_a_passage_a_ten_thousandth_of_a_radian_wide_is_found():
    chain, q, poses, psi = _narrow_passage()
    from redkin.srs import feasible_pieces_all_branches

    pieces = feasible_pieces_all_branches(chain, poses[4])
    widths = np.where(pieces.feasible, pieces.end - pieces.start, 0.0)
    assert widths.sum() == pytest.approx(1e-4, rel=1e-3)  # the whole feasible set of waypoint 4
    step = 2.0 * np.abs(np.diff(q, axis=0)).max(axis=0)
    result = resolve_path(chain, poses, step)
    _assert_lawful(chain, poses, result)
    assert abs(result.psi[4] - psi) <= 0.5e-4 + 1e-12
    coarse = sampled_path(chain, poses, step, np.radians(0.1))  # the literature's grid misses it
    assert coarse.failure.waypoint == 4 and coarse.failure.reason == "empty" and not coarse.failure.exact


# ------------------------------------------------------------------ optimality: the proof and the two stages
def _densest_clearance(chain, pose, samples=20_000):
    """The largest clearance of any in-limit solution of ``pose`` on a dense arm-angle grid of all branches,
    from the closed form alone (no feasible set): an independent lower estimate of the best possible."""
    psi = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    q = ik_all_branches(chain, np.broadcast_to(pose, (samples, 4, 4)), psi).reshape(-1, 7)
    q = q[np.all(np.isfinite(q), axis=-1)]
    limited = ~chain.covers_circle
    inside = np.minimum(q - chain.lower, chain.upper - q)[:, limited].min(axis=-1)
    return inside.max(initial=-np.inf)


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(ROBOTS), st.floats(1.2, 3.0))
def test_a_clearance_said_optimal_is_not_beaten_at_its_bottleneck(seed, robot, slack):
    chain = get_robot(robot)
    q, poses = _joint_line(chain, np.random.default_rng(seed), 12)
    step = slack * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3
    result = resolve_path(chain, poses, step)
    _assert_lawful(chain, poses, result)
    if not result.optimal:
        assert result.bottleneck is None
        return
    k = result.bottleneck
    own = np.minimum(result.q[k] - chain.lower, chain.upper - result.q[k])[~chain.covers_circle].min()
    assert own <= result.clearance + OPTIMALITY_MARGIN  # the path is at its smallest clearance there
    assert _densest_clearance(chain, poses[k]) <= result.clearance + OPTIMALITY_MARGIN


def test_the_line_of_the_docs_is_proved_optimal_and_a_binding_bound_is_not():
    chain = get_robot("kuka-iiwa14")
    q0 = np.array([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1])
    q1 = np.array([-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9])
    result = resolve_path(chain, chain.fk(q0 + (q1 - q0) * np.linspace(0.0, 1.0, 20)[:, None]), 0.1)
    assert result.optimal and result.bottleneck is not None
    rng = np.random.default_rng(1)
    lower, upper = chain.lower + 0.2, chain.upper - 0.2
    for _ in range(5):  # the fifth of these lines: each waypoint alone could keep more than any path can
        a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
    q = a + (b - a) * np.linspace(0.0, 1.0, 30)[:, None]
    step = 1.5 * np.abs(np.diff(q, axis=0)).max()
    bound = resolve_path(chain, chain.fk(q), step)
    assert bound.ok and not bound.optimal and bound.bottleneck is None
    best_alone = min(_densest_clearance(chain, pose, 4000) for pose in chain.fk(q))
    assert best_alone > bound.clearance + 1e-3
    from redkin.paths.baselines import sampled_path  # the linear programs reach past the literature's grid

    assert bound.clearance >= sampled_path(chain, chain.fk(q), step, np.radians(0.5)).clearance - 1e-12


def _peaked_arc():
    """An iiwa14 line of 5 waypoints with joints 4, 5 and 7 narrowed around it (bench_paths's constructed case 105):
    at waypoint 0 the clearance on branch +-- is bimodal, 2.1e-4 near the right end of its arc and 3.3e-4 within
    1e-3 rad of its left end (joint 7 nears a limit in the middle, joint 5 meets one at either end)."""
    chain = get_robot("kuka-iiwa14")
    first = np.array([0.744302704422052, 0.9897379938004682, -1.0105715712168124, -1.8287150761338702,
                      1.5560649997011637, -1.2496296587395301, 1.4372540861353622])
    last = np.array([0.10127360924758655, 0.48562393428177264, -1.2322346153855608, -1.7334571596602122,
                     1.5903018485277065, -1.360020306667608, 0.928273409191801])
    q = first + (last - first) * np.linspace(0.0, 1.0, 5)[:, None]
    lower, upper = chain.lower.copy(), chain.upper.copy()
    lower[[3, 4, 6]] = -1.8309920229031489, 1.5548774920155162, 0.9280863524572623
    upper[[3, 4, 6]] = -1.7311802128909335, 1.591489356213354, 1.4374411428699008
    arm = chain.with_limits(lower, upper)
    return arm, arm.fk(q), 1.5 * np.abs(np.diff(q, axis=0)).max()


def test_a_clearance_that_peaks_near_an_arc_end_is_found_and_proved(monkeypatch):
    """The samples and the refinement around the first path found stay near the lower peak; the search inside
    limits moved inwards (:func:`redkin.paths.resolve._leveled`) finds the higher one, at least the dense sampled
    search's clearance on a 0.01 deg grid, and proves it optimal."""
    import redkin.paths.resolve as resolve

    arm, poses, step = _peaked_arc()
    result = resolve_path(arm, poses, step)
    _assert_lawful(arm, poses, result)
    dense = sampled_path(arm, poses, step, np.radians(0.01))
    assert result.optimal and result.clearance >= dense.clearance > 3.3e-4
    monkeypatch.setattr(resolve, "_LEVEL_ROUNDS", 0)
    assert resolve_path(arm, poses, step).clearance < 2.2e-4  # without the levels: the lower peak


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 2**31))
def test_the_levels_never_lower_a_clearance_nor_break_a_law(seed):
    """On lines whose limits are narrowed around them (narrow arcs, peaked clearances), the search inside moved
    limits keeps every law and never returns less than the search without it."""
    import redkin.paths.resolve as resolve

    chain = get_robot("kuka-iiwa14")
    rng = np.random.default_rng(seed)
    q, _ = _joint_line(chain, rng, 6)
    q = q[0] + 0.2 * (q - q[0])
    lower, upper = chain.lower.copy(), chain.upper.copy()
    for joint in rng.choice(7, 3, replace=False):
        margin = 10.0 ** rng.uniform(-4.0, -2.0)
        lower[joint] = max(lower[joint], q[:, joint].min() - margin)
        upper[joint] = min(upper[joint], q[:, joint].max() + margin)
    arm = chain.with_limits(lower, upper)
    poses, step = arm.fk(q), 1.5 * np.abs(np.diff(q, axis=0)).max()
    result = resolve_path(arm, poses, step)
    _assert_lawful(arm, poses, result)
    rounds = resolve._LEVEL_ROUNDS
    try:
        resolve._LEVEL_ROUNDS = 0
        plain = resolve_path(arm, poses, step)
    finally:
        resolve._LEVEL_ROUNDS = rounds
    assert result.clearance >= plain.clearance
    assert result.optimal or not plain.optimal


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(ROBOTS))
def test_the_thorough_search_is_never_worse_and_cannot_beat_a_proved_clearance(seed, robot):
    chain = get_robot(robot)
    q, poses = _joint_line(chain, np.random.default_rng(seed), 10)
    step = step_bound(chain, 1.5 * np.abs(np.diff(q, axis=0)).max())
    ours, thorough = resolve_path(chain, poses, step), resolve_path(chain, poses, step, thorough=True)
    assert ours.status == thorough.status
    if not ours.ok:
        return
    _assert_lawful(chain, poses, thorough)
    assert (thorough.clearance, -thorough.motion) >= (ours.clearance, -ours.motion)  # the better of both graphs
    assert thorough.nodes >= ours.nodes
    if ours.optimal:  # proved: the subdivided graph keeps no more (its motion may be less)
        assert thorough.clearance <= ours.clearance + OPTIMALITY_MARGIN


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(ROBOTS + ["franka-fr3"]), st.floats(1.05, 1.6))
def test_the_linear_programs_never_lower_a_clearance_nor_break_a_law(seed, robot, slack):
    from redkin.paths import graph as graphs
    from redkin.paths.arm_family import path_family
    from redkin.paths.resolve import DEFAULT_CONNECT, DEFAULT_REFINEMENTS, DEFAULT_SPACING, search_paths

    chain = get_robot(robot)
    lower = np.where(np.isfinite(chain.lower), np.maximum(chain.lower + 0.2, -3.0), -np.pi)
    upper = np.where(np.isfinite(chain.upper), np.minimum(chain.upper - 0.2, 3.0), np.pi)
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
    q = a + (b - a) * np.linspace(0.0, 1.0, 12)[:, None]
    poses = chain.fk(q)
    step = step_bound(chain, slack * np.abs(np.diff(q, axis=0)).max())  # tight: the bound binds
    runs = [search_paths(path_family(chain), poses[None], step, None, None, None,
                         lambda pieces: graphs.piece_samples(pieces, DEFAULT_SPACING), DEFAULT_CONNECT,
                         DEFAULT_REFINEMENTS, polish=polish)[0] for polish in (False, True)]
    assert runs[0].status == runs[1].status
    if runs[1].ok:  # a polished first stage may be proved and end the search, within the proof's margin
        assert runs[1].clearance >= runs[0].clearance - (OPTIMALITY_MARGIN if runs[1].optimal else 0.0)
        assert np.abs(chain.fk(runs[1].q) - poses).max() <= FK_TOLERANCE
        assert chain.within_limits(runs[1].q).all() and np.all(np.abs(np.diff(runs[1].q, axis=0)) <= step)


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "franka-fr3"])
def test_the_motion_objective_moves_least_and_keeps_every_law(robot):
    chain = get_robot(robot)
    for seed in range(4):
        lower = np.maximum(chain.lower + 0.2, -3.0)
        upper = np.minimum(chain.upper - 0.2, 3.0)
        rng = np.random.default_rng(seed)
        a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
        q = a + (b - a) * np.linspace(0.0, 1.0, 10)[:, None]
        poses = chain.fk(q)
        step = 2.0 * np.abs(np.diff(q, axis=0)).max() + 1e-3
        clearance, motion = resolve_path(chain, poses, step), resolve_path(chain, poses, step, objective="motion")
        assert motion.ok and not motion.optimal and motion.bottleneck is None
        assert np.abs(chain.fk(motion.q) - poses).max() <= FK_TOLERANCE and chain.within_limits(motion.q).all()
        assert np.all(np.abs(np.diff(motion.q, axis=0)) <= step)
        assert motion.motion == pytest.approx(np.abs(np.diff(motion.q, axis=0)).sum(), abs=1e-12)
        assert motion.motion <= clearance.motion + 1e-9 and clearance.clearance >= motion.clearance - 1e-9
        assert motion.motion <= 1.01 * np.abs(np.diff(q, axis=0)).sum()  # about the line the poses came from
    with pytest.raises(RedkinError, match="objective"):
        resolve_path(chain, poses, step, objective="speed")


# ------------------------------------------------------------------ against the baselines
def test_agrees_with_a_dense_sampled_search_on_small_paths():
    chain = get_robot("kuka-iiwa14")
    rng = np.random.default_rng(11)
    for _ in range(2):
        q, _ = _joint_line(chain, rng, 5)
        q = q[0] + 0.2 * (q - q[0])  # a short stretch: small steps keep the dense search's windows small
        poses = chain.fk(q)
        step = 1.5 * np.abs(np.diff(q, axis=0)).max()
        ours = resolve_path(chain, poses, step)
        dense = sampled_path(chain, poses, step, np.radians(0.25))
        assert ours.status == dense.status == "ok"
        # where the step bound binds on every edge (here joint 3's) the refinement alone stopped 1.5e-5 rad short
        # of the dense grid's optimum; the linear programs between the samples reach past it
        assert ours.clearance >= dense.clearance - 1e-12
    q = _line_through(chain, np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]), 4)
    q[2:, 3] += 0.3
    ours, dense = resolve_path(chain, chain.fk(q), 0.2), sampled_path(chain, chain.fk(q), 0.2, np.radians(0.25))
    assert ours.status == dense.status == "no-path"
    assert ours.failure.waypoint == dense.failure.waypoint == 2


def test_per_pose_baselines_fail_where_the_global_path_succeeds():
    chain = get_robot("kuka-iiwa14")
    q0 = np.array([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1])
    q1 = np.array([-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9])
    poses = chain.fk(q0 + (q1 - q0) * np.linspace(0.0, 1.0, 20)[:, None])
    result = resolve_path(chain, poses, 0.1)
    _assert_lawful(chain, poses, result)
    greedy = greedy_path(chain, poses, 0.1)
    fixed = fixed_psi_path(chain, poses, 0.1, 0.0, "+-+")
    clamped = clamped_optimum_path(chain, poses, 0.1, "+-+")
    for baseline in (greedy, fixed, clamped):
        assert not baseline.ok
        assert baseline.first_failure is not None
    assert greedy.jump.max() > 1.0  # greedy jumps: a step over the bound


#: HiGHS's default primal and dual feasibility tolerance: how far either program's answer may be off.
_HIGHS_SLACK = 1e-7


class _SmoothArm:
    """A stand-in arm for the polish's linear program: joint ``j`` at waypoint ``i`` is ``base[i, j] + size[i, j] *
    sin(parameter + phase[i, j])``, limits at ``+-1.5`` (joint 7 on the circle); ``step`` is set by the test."""

    def __init__(self, rng: np.random.Generator, count: int) -> None:
        from types import SimpleNamespace

        self.base = np.cumsum(rng.normal(0.0, 0.05, (count, 7)), axis=0)
        self.size = rng.uniform(0.0, 1.0, (count, 7)) * rng.choice([0.3, 3.0], (count, 7))
        self.phase = rng.uniform(-np.pi, np.pi, (count, 7))
        self.chain = SimpleNamespace(lower=np.full(7, -1.5), upper=np.full(7, 1.5))
        self.circle = np.arange(7) == 6
        self.step = np.full(7, 0.3)

    def rows(self, waypoint, branch, parameter):
        q = self.base[waypoint] + self.size[waypoint] * np.sin(parameter[:, None] + self.phase[waypoint])
        return q, np.minimum(q[:, :6] + 1.5, 1.5 - q[:, :6]).min(axis=1)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**31), st.integers(2, 40), st.sampled_from([1e-3, 1e-2, 0.1, 0.4]),
       st.sampled_from([0.0, 1e-3]))
def test_the_polish_program_keeps_the_whole_programs_optimum(seed, count, trust, margin):
    """The polish's linear program leaves out the rows that cannot bind and the waypoints in no row it keeps
    (:func:`redkin.paths.polish._step`); its answer must be feasible and optimal for the whole program, every
    waypoint's clearance rows and every step's rows, solved here apart."""
    from scipy.optimize import linprog

    from redkin.paths.polish import _step

    rng = np.random.default_rng(seed)
    arm = _SmoothArm(rng, count)
    waypoint, branch = np.arange(count), np.zeros(count, dtype=np.int64)
    parameter = rng.uniform(-1.0, 1.0, count)
    piece = np.stack([parameter - rng.uniform(0.0, 0.5, count), parameter + rng.uniform(0.0, 0.5, count)], axis=1)
    q = arm.rows(waypoint, branch, parameter)[0]
    moves = np.abs(np.diff(q, axis=0))
    moves[:, 6] = np.abs((moves[:, 6] + np.pi) % (2 * np.pi) - np.pi)
    arm.step = moves.max(axis=0, initial=0.0) * rng.uniform(1.0, 1.3) + margin  # the bound binds somewhere
    delta = _step(arm, waypoint, branch, parameter, piece, q, None, None, trust, margin)
    low = np.minimum(np.maximum(piece[:, 0] - parameter, -trust), 0.0)
    high = np.maximum(np.minimum(piece[:, 1] - parameter, trust), 0.0)
    h = 1e-7  # the same central differences as the program's
    below, above = np.clip(parameter - h, piece[:, 0], piece[:, 1]), np.clip(parameter + h, piece[:, 0], piece[:, 1])
    slope = (arm.rows(waypoint, branch, above)[0] - arm.rows(waypoint, branch, below)[0]) / np.where(
        above > below, above - below, 1.0)[:, None]
    # the whole program: x = (delta, t); t <= clearance + slope delta; |step + slope' delta' - slope delta| <= room
    rows, bound = [], []
    for i in range(count):
        for j in range(6):
            for sign, room in ((-1.0, q[i, j] + 1.5), (1.0, 1.5 - q[i, j])):
                row = np.zeros(count + 1)
                row[i], row[count] = sign * slope[i, j], 1.0
                rows.append(row)
                bound.append(room)
    for i in range(count - 1):
        for j in range(7):
            moved = q[i + 1, j] - q[i, j]
            moved = (moved + np.pi) % (2 * np.pi) - np.pi if j == 6 else moved
            for sign in (1.0, -1.0):
                row = np.zeros(count + 1)
                row[i + 1], row[i] = sign * slope[i + 1, j], -sign * slope[i, j]
                rows.append(row)
                bound.append(arm.step[j] - margin - sign * moved)
    cost = np.zeros(count + 1)
    cost[count] = -1.0
    whole = linprog(cost, A_ub=np.array(rows), b_ub=np.array(bound), bounds=list(zip(low, high)) + [(None, None)],
                    method="highs")
    assert (delta is None) == (whole.status != 0)
    if delta is None:
        return
    assert np.all((delta >= low - 1e-12) & (delta <= high + 1e-12))
    x = np.append(delta, 0.0)
    matrix = np.array(rows)
    steps = slice(count * 12, None)
    assert np.all(matrix[steps] @ x <= np.array(bound)[steps] + _HIGHS_SLACK)  # every step's rows kept
    reached = (np.array(bound)[:count * 12] - matrix[:count * 12, :count] @ delta).min()  # the least clearance row
    assert reached >= -whole.fun - _HIGHS_SLACK  # as high as the whole program's optimum
