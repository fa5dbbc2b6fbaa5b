"""Collision-free numerical IK (issue 40) on the Sawyer, an arm with no closed form: every solution returned reaches
the pose by our own FK, lies within the limits and keeps the margin by distances measured here pair by pair; the
solutions are the solver's clear candidates in its order; a scene that blocks every candidate returns none and says
how near the best came; a batch is filtered pose by pose."""

from __future__ import annotations

import inspect

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.collision import BodyCapsule, Scene, body_of, clearance, posed, primitives, signed_distance
from redkin.collision import _clearance_kernels as clearance_kernels
from redkin.collision import _free_ik_kernels as free_ik_kernels
from redkin.collision.clearance import checked_pairs, clearance_inputs
from redkin.collision.free_ik import collision_free_ik
from redkin.errors import RedkinError
from redkin.numerical import _kernels as numerical_kernels
from redkin.numerical import ik
from redkin.numerical.solve import start_streams

MARGIN = 0.02


@pytest.fixture(scope="module")
def arm():
    chain = redkin.get_robot("sawyer.urdf")
    # the capsules on the wrist's frames 5 and 7 overlap by 1.4 cm wherever we looked: ignored, as an SRDF would
    body = body_of([BodyCapsule(f"link {k}", k, [0, 0, 0], [0, 0, 0.05], 0.05) for k in range(2, chain.n + 1)],
                   chain, ignore=[("link 5", "link 7")])
    return chain, body


def _pair_distances(chain, body, scene, q) -> float:
    """The least distance over the body's capsules and the obstacles and its self pairs, each pair measured alone."""
    shapes = posed(body, chain.frames(q))
    least = np.inf
    for i in range(len(body.link)):
        for o in range(len(scene.names)):
            least = min(least, float(signed_distance(shapes[i], scene.shapes[o]).distance))
    for i, j in body.pairs.tolist():
        least = min(least, float(signed_distance(shapes[i], shapes[j]).distance))
    return least


def _blocking_scene(chain, q: np.ndarray) -> Scene:
    """A ball on the origin of frame 4 of ``q`` (the elbow): ``q`` itself collides."""
    elbow = chain.frames(q)[4][:3, 3]
    return Scene(("ball",), primitives.sphere(elbow, 0.06)[None], MARGIN)


@settings(max_examples=6)
@given(st.lists(st.floats(0.1, 0.9), min_size=7, max_size=7))
def test_every_solution_reaches_the_pose_within_the_limits_and_keeps_the_margin(arm, fractions):
    chain, body = arm
    q = chain.lower + np.asarray(fractions) * (chain.upper - chain.lower)
    pose = chain.fk(q)
    plain = ik(chain, pose)
    scene = _blocking_scene(chain, plain.q[0])
    result = collision_free_ik(chain, body, scene, pose, count=3)
    assert result.found.shape == (3,) and result.q.shape == (3, 7)
    for k in np.flatnonzero(result.found):
        solution = result.q[k]
        reached = chain.fk(solution)
        assert np.abs(reached[:3, 3] - pose[:3, 3]).max() < 1e-8
        assert np.abs(reached[:3, :3] - pose[:3, :3]).max() < 1e-8
        assert np.all(solution >= chain.lower - 1e-12) and np.all(solution <= chain.upper + 1e-12)
        measured = _pair_distances(chain, body, scene, solution)
        assert measured >= MARGIN and abs(measured - result.clearance[k]) < 1e-12
    assert not np.any(np.all(np.abs(result.q[result.found] - plain.q[0]) < 1e-9, axis=-1))  # it collides
    examined = result.solver.q[result.solver.found]  # the solver's starts and the walks' steps alike: certified
    assert len(examined) == result.candidates
    reached = chain.fk(examined)
    assert np.abs(reached[:, :3, 3] - pose[:3, 3]).max() < 1e-8
    assert np.abs(reached[:, :3, :3] - pose[:3, :3]).max() < 1e-8
    assert np.all(chain.within_limits(examined))
    apart = np.abs(examined[:, None] - examined[None]).max(axis=-1) + np.eye(len(examined))
    assert np.all(apart > 0.1)  # distinct by the solver's separation
    assert 0 <= result.blocked <= result.candidates and result.found.sum() <= result.candidates - result.blocked


def test_without_the_walk_the_solutions_are_the_solvers_clear_candidates_in_its_order(arm):
    """With ``walk=0`` the candidates examined are the solver's first ones from the same stream, in its order (with a
    seed, sorted by the distance to it), and the search stops once ``count`` of them are clear."""
    chain, body = arm
    q = np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1])
    pose = chain.fk(q)
    scene = _blocking_scene(chain, q)
    for seed in (None, q + 0.3):
        result = collision_free_ik(chain, body, scene, pose, q0=seed, count=2, candidates=4, walk=0)
        examined = int(result.candidates)
        candidates = ik(chain, pose, q0=seed, count=examined)
        assert candidates.found.all()  # the solver finds them all again
        found = candidates.q[candidates.found]
        clear = found[clearance(chain, body, scene, found).distance >= MARGIN]
        assert result.blocked == len(found) - len(clear)
        assert np.array_equal(result.q[result.found], clear[:2])
        assert len(clear) == 2 and result.found.all()  # it stopped at the second clear one
        if seed is None:  # in the order found, the last examined is the one that made two
            assert clearance(chain, body, scene, found[-1]).distance >= MARGIN


def test_a_far_scene_changes_nothing(arm):
    chain, _ = arm
    pose = chain.fk(np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1]))
    far = Scene(("far",), primitives.sphere([10.0, 0.0, 0.0], 0.1)[None], MARGIN)
    hand = body_of([BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.05], 0.05)], chain)  # no self pair to block
    result = collision_free_ik(chain, hand, far, pose, count=2, candidates=2)
    plain = ik(chain, pose, count=2)
    ids = np.flatnonzero(result.found)
    assert len(ids) == plain.found.sum() and np.array_equal(result.q[ids], plain.q[plain.found])
    assert result.blocked == 0 and result.blocked_clearance == -np.inf and result.blocked_link == ""


def test_a_scene_that_blocks_every_candidate_returns_none_and_the_clearest(arm):
    chain, body = arm
    pose = chain.fk(np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1]))
    walls = Scene(("ball",), primitives.sphere(pose[:3, 3], 0.05)[None], MARGIN)  # around the tool point
    result = collision_free_ik(chain, body, walls, pose, restarts=40)
    assert not result.found.any() and result.candidates > 0 and result.blocked == result.candidates
    solver = result.solver
    candidates = solver.q[solver.found]
    measured = clearance(chain, body, walls, candidates)
    assert result.blocked_clearance == measured.distance.max() < MARGIN
    best = int(np.argmax(measured.distance))
    assert (result.blocked_link, result.blocked_against) == (measured.link[best], measured.against[best])
    assert np.all(result.q == 0.0) and np.all(result.clearance == 0.0)


def test_a_batch_is_filtered_pose_by_pose_and_out_of_reach_is_not_searched(arm):
    """Pose ``i`` of a batch starts from the solver's stream ``i`` (redkin.numerical.ik), so a batch is not its poses
    solved alone; without the walk each pose's solutions are still its own clear candidates in the solver's order,
    from the round that last asked it (only the poses short of clear solutions go on to the next round)."""
    chain, body = arm
    poses = chain.fk(np.array([[0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1], [-0.4, 0.2, 0.5, 0.9, -0.3, 1.1, 0.6]]))
    far = poses[1].copy()
    far[:3, 3] = [5.0, 0.0, 0.0]
    batch = np.stack([poses[0], poses[1], far])
    scene = _blocking_scene(chain, np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1]))
    together = collision_free_ik(chain, body, scene, batch, count=2, walk=0)
    streams = start_streams(None, 3)
    for k in range(2):
        candidates = ik(chain, batch[k : k + 1], count=int(together.candidates[k]), rng=streams[k : k + 1])
        assert candidates.found.all()
        found = candidates.q[0]
        clear = found[clearance(chain, body, scene, found).distance >= MARGIN]
        assert np.array_equal(together.q[k][together.found[k]], clear[:2])
        assert together.blocked[k] == len(found) - len(clear)
    assert together.solver.reach.out.tolist() == [False, False, True]
    assert not together.found[2].any() and together.candidates[2] == 0
    assert together.found[:2].all()


def test_bad_input_is_a_value_error(arm):
    chain, body = arm
    pose = chain.fk(np.zeros(7))
    scene = _blocking_scene(chain, np.zeros(7))
    for options in ({"count": 0}, {"candidates": 1001}, {"count": 1.5}, {"restarts": 0}, {"walk": -1}, {"walk": 101}):
        with pytest.raises(RedkinError):
            collision_free_ik(chain, body, scene, pose, **options)
    with pytest.raises(RedkinError):
        collision_free_ik(chain, body, scene, np.eye(3))


def test_the_arm_answers_the_same_in_its_rows(arm):
    """``redkin.arm(...).ik(pose, body=, scene=)``: on the Sawyer (no branches) the rows are the solutions in order;
    on the iiwa14 each clear solution sits in its branch's row, and every row that exists keeps the margin."""
    chain, body = arm
    q = np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1])
    scene = _blocking_scene(chain, q)
    sawyer = redkin.arm(chain)
    rows = sawyer.ik(chain.fk(q), body=body, scene=scene, count=3)
    direct = collision_free_ik(chain, body, scene, chain.fk(q), count=3)
    assert np.array_equal(rows.q, direct.q) and np.array_equal(rows.exists, direct.found)
    iiwa = redkin.arm("kuka-iiwa14")
    forearm = body_of([BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.06)], iiwa.chain)
    pose = iiwa.fk(np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1]))
    elbow = iiwa.chain.frames(np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1]))[4][:3, 3]
    ball = Scene(("ball",), primitives.sphere(elbow, 0.05)[None], MARGIN)
    solutions = iiwa.ik(pose, body=forearm, scene=ball, count=4)
    assert solutions.exists.any()
    assert np.all(clearance(iiwa.chain, forearm, ball, solutions.q[solutions.exists]).distance >= MARGIN)
    labels = [iiwa.branches[k] for k in np.flatnonzero(solutions.exists)]
    assert iiwa.branch_of(solutions.q[solutions.exists]).tolist() == labels  # each in its own branch's row
    with pytest.raises(RedkinError, match="both"):
        iiwa.ik(pose, body=forearm)
    assert solutions.collision_free is not None and np.array_equal(solutions.collision_free, solutions.exists)


def test_only_the_poses_short_of_clear_solutions_are_asked_again(arm):
    """With ``candidates=1`` the first round examines one candidate of every pose; a pose whose candidate is clear is
    not searched again, one whose candidate collides is searched for four times as many, from its own starts (stream
    ``i``; without the walk, the solver's candidates), and stops at its first clear one."""
    chain, body = arm
    q = np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1])
    blocked_pose = chain.fk(q)
    scene = _blocking_scene(chain, q)
    clear_q = np.array([-0.4, 0.2, 0.5, 0.9, -0.3, 1.1, 0.6])
    batch = np.stack([chain.fk(clear_q), blocked_pose])
    first = ik(chain, batch, count=1)
    first_clear = clearance(chain, body, scene, first.q[:, 0]).distance >= MARGIN
    result = collision_free_ik(chain, body, scene, batch, count=1, candidates=1, walk=0)
    assert first_clear.tolist() == [True, False]  # one pose of each kind: the law below is not empty
    assert result.asked[0] == 1 and result.candidates[0] == 1 and np.array_equal(result.q[0, 0], first.q[0, 0])
    assert result.asked[1] in (4, 16, 64, 256, 1000) and result.found[1, 0]
    examined = int(result.candidates[1])
    again = ik(chain, batch[1:], count=examined, rng=start_streams(None, 2)[1:])
    assert np.array_equal(again.q[0], result.solver.q[1, :examined]) and not result.solver.found[1, examined:].any()
    measured = clearance(chain, body, scene, again.q[0]).distance >= MARGIN
    assert measured.tolist() == [False] * (examined - 1) + [True]  # stopped at the first clear one
    assert np.array_equal(result.q[1, 0], again.q[0, -1])


def _kernel_inputs(chain, body, scene):
    """The chain's and the cell's arrays as the compiled kernels take them."""
    pairs = checked_pairs(body, scene)
    inputs = clearance_inputs(body, scene, pairs)
    return (chain._links, chain._ends, chain._standard), (*inputs.body, inputs.obstacles, *inputs.pairs)


@settings(max_examples=30)
@given(st.lists(st.floats(0.02, 0.98), min_size=7, max_size=7))
def test_a_walk_step_moves_along_the_self_motion_away_from_the_closest_pair(arm, fractions):
    """``escape`` moves a configuration along its self-motion (the tool's Jacobian annihilates the step), within the
    limits, by 2 x the separation to 1 rad in its largest joint, and raises its closest pair's distance to first order
    (the pair's gradient, checked against central differences in tests/test_collision_clearance.py); where it
    refuses, the configuration is unchanged."""
    chain, body = arm
    q = chain.lower + np.asarray(fractions) * (chain.upper - chain.lower)
    scene = _blocking_scene(chain, q)
    kinematics, cell = _kernel_inputs(chain, body, scene)
    work, _ = numerical_kernels.scratch(chain.n)
    spare = clearance_kernels.scratch(kinematics[0], cell[0], cell[5], cell[4])
    distance, pair = clearance_kernels.least_one(q, *kinematics, *cell, spare)
    assert distance < MARGIN  # the ball sits on the elbow
    gradient, jac = np.zeros(chain.n), np.zeros((6, chain.n))
    clearance_kernels.pair_gradient(q, *kinematics, *cell, pair, spare, jac, gradient)
    moved = q.copy()
    separation = 0.1
    if not free_ik_kernels.escape(moved, *kinematics, chain.lower, chain.upper, *cell, pair, MARGIN - distance,
                                  separation, work, spare):
        assert np.array_equal(moved, q)
        return
    step = moved - q
    size = np.abs(step).max()
    assert 2 * separation - 1e-12 <= size <= free_ik_kernels.WALK_STEP + 1e-12
    assert np.all(moved >= chain.lower) and np.all(moved <= chain.upper)
    tool = chain.jacobian(q)
    assert np.linalg.norm(tool @ step) <= 1e-8 * np.linalg.norm(step)
    assert gradient @ step > 0.0


def test_the_walk_takes_a_colliding_solution_clear_along_its_self_motion(arm):
    """On a pose whose first solution meets a ball at its elbow, the candidates after it are the walk's steps: each a
    certified solution within about a step (1 rad in a joint, and the descent's correction) of the one before,
    clearer than it, until one keeps the margin; the solver's own next starts land far away on the self-motion."""
    chain, body = arm
    q = np.array([0.3, -0.5, 0.2, 1.2, 0.4, 0.8, 0.1])
    pose = chain.fk(q)
    first = ik(chain, pose).q[0]
    scene = _blocking_scene(chain, first)
    walked = collision_free_ik(chain, body, scene, pose, count=1)
    plain = collision_free_ik(chain, body, scene, pose, count=1, walk=0)
    steps = walked.solver.q[walked.solver.found]
    walk = inspect.signature(collision_free_ik).parameters["walk"].default
    assert np.array_equal(steps[0], first) and 2 <= len(steps) <= 1 + walk
    measured = clearance(chain, body, scene, steps).distance
    assert np.all(np.diff(measured) > 0.0) and measured[-1] >= MARGIN > measured[-2]
    moves = np.abs(np.diff(steps, axis=0)).max(axis=-1)
    assert np.all(moves > 0.1) and np.all(moves < free_ik_kernels.WALK_STEP + 0.2)
    assert np.array_equal(walked.q[0], steps[-1]) and walked.clearance[0] == measured[-1]
    assert np.abs(chain.fk(walked.q[0]) - pose).max() < 1e-8
    jumps = np.abs(np.diff(plain.solver.q[plain.solver.found], axis=0)).max(axis=-1)
    assert np.all(jumps > free_ik_kernels.WALK_STEP + 0.2)
