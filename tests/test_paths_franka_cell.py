"""Paths in a cell on the Franka class (issue 40): q7 chosen inside the certified collision-free q7 sets.

Laws, on the Panda with a body of a forearm ball and a hand capsule: every waypoint of a resolved path keeps the
margin (measured here pair by pair at the joint values returned) and reaches its pose; each waypoint's q7 lies in
that pose's collision-free set of its branch (:func:`redkin.collision.collision_free_q7`); the path swings the elbow
around a ball the plain path runs into; a ball at the hand, which the pose holds still, blocks every branch and the
failure names the pair; ``"obstacle-clearance"`` keeps at least as far as the default objective; the pairs said not
to move with q7 keep their distance at every q7 of the pose, and the command line gives the API's path.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import redkin
from redkin.collision import BodyCapsule, Scene, body_of, clearance, collision_free_q7, primitives
from redkin.collision.clearance import pair_table
from redkin.collision.free_sets import redundancy_moves
from redkin.paths import FK_TOLERANCE, resolve_path
from tests.support.cli import run

#: The ends of the joint-space line whose poses are the waypoints (inside the Panda's limits).
START = [0.3, -0.4, -0.2, -2.0, 0.3, 1.8, 0.5]
END = [-0.4, 0.2, 0.3, -1.5, -0.3, 1.5, 1.2]
#: The bound on each joint's step [rad].
STEP = 0.15


@pytest.fixture(scope="module")
def setting():
    chain = redkin.get_robot("franka-panda")
    poses = chain.fk(np.linspace(START, END, 8))
    body = body_of([BodyCapsule("forearm", 4, [0, 0, 0], [0, 0, 0], 0.05),
                    BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.08], 0.04)], chain)
    plain = resolve_path(chain, poses, STEP)
    assert plain.ok
    elbow = chain.frames(plain.q[4])[4, :3, 3]
    scene = Scene(("ball",), primitives.sphere(elbow, 0.06)[None], 0.01)
    return chain, poses, body, plain, scene


def test_the_path_swings_the_elbow_around_what_the_plain_path_hits(setting):
    chain, poses, body, plain, scene = setting
    assert clearance(chain, body, scene, plain.q).distance.min() < scene.margin  # the plain path runs into it
    result = resolve_path(chain, poses, STEP, body=body, scene=scene)
    assert result.ok and result.parameter == "q7"
    assert np.all(clearance(chain, body, scene, result.q).distance >= scene.margin - 1e-12)
    assert np.abs(chain.fk(result.q) - poses).max() <= FK_TOLERANCE
    assert np.all(chain.joints_within_limits(result.q)) and np.abs(np.diff(result.q, axis=0)).max() <= STEP + 1e-12
    np.testing.assert_array_equal(result.psi, result.q[:, 6])
    arm = redkin.arm(chain)
    for k in (0, 4, 7):
        free = collision_free_q7(arm, poses[k], body, scene)
        bounds = free.free[free.branches.index(result.branch[k])].bounds
        assert np.any((bounds[:, 0] <= result.psi[k]) & (result.psi[k] <= bounds[:, 1]))


def test_a_waypoint_blocked_on_every_branch_names_the_pair(setting):
    chain, poses, body, plain, _ = setting
    hand = chain.frames(plain.q[4])[7, :3, 3]  # link 7 does not move with q7: every branch meets it
    scene = Scene(("ball",), primitives.sphere(hand, 0.03)[None], 0.0)
    result = resolve_path(chain, poses, STEP, body=body, scene=scene)
    assert result.status == "no-path"
    assert result.failure.reason == "collision" and result.failure.pair == ("hand", "ball")
    assert result.failure.waypoint <= 4 and "hand meets ball" in result.failure.message
    assert result.failure.parameter == "q7" and "no value of q7 within the joint limits" in result.failure.message


def test_obstacle_clearance_keeps_at_least_as_far_as_the_default(setting):
    chain, poses, body, _, scene = setting
    default = resolve_path(chain, poses, STEP, body=body, scene=scene)
    result = resolve_path(chain, poses, STEP, body=body, scene=scene, objective="obstacle-clearance")
    assert default.ok and result.ok
    measured = clearance(chain, body, scene, result.q).distance
    assert result.cell_clearance == pytest.approx(float(measured.min()), abs=1e-12)
    assert result.cell_clearance >= default.cell_clearance
    assert measured.min() >= scene.margin - 1e-12 and result.steps.certified.all()


def test_the_pairs_left_out_keep_their_distance_at_every_q7(setting):
    """redundancy_moves on the Franka class: a pair said not to move (the hand and an obstacle, the base and the
    hand) keeps its distance over the q7 values of a branch at the pose; the forearm's pairs are said to move and do."""
    chain, poses, _, plain, _ = setting
    body = body_of([BodyCapsule("base", 0, [0, 0, 0], [0, 0, 0.1], 0.08),
                    BodyCapsule("forearm", 4, [0, 0, 0], [0, 0, 0], 0.05),
                    BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.08], 0.04)], chain, ignore=[])
    scene = Scene(("post", "lamp"), np.stack([primitives.capsule([0.4, 0.3, 0.0], [0.4, 0.3, 1.2], 0.05),
                                              primitives.sphere([0.2, -0.3, 0.8], 0.1)]), 0.0)
    arm = redkin.arm(chain)
    q7 = np.linspace(chain.lower[6], chain.upper[6], 40)
    for k in (0, 5):
        solutions = arm.ik(np.repeat(poses[k : k + 1], len(q7), axis=0), q7, branches=plain.branch[k])
        q = solutions.q[:, 0][solutions.exists[:, 0]]
        assert len(q) > 5
        moves = redundancy_moves(arm, body, scene, q)
        table, _ = pair_table(chain, body, scene, q)
        assert np.all(moves == moves[0])
        still = ~moves[0]
        assert still.any() and moves[0].any()
        assert np.ptp(table[:, still], axis=0).max() < 1e-9
        assert np.ptp(table[:, moves[0]], axis=0).min() > 1e-6


def test_the_command_line_resolves_the_same_path(setting, tmp_path, capsys):
    chain, poses, _, plain, _ = setting
    elbow = chain.frames(plain.q[4])[4, :3, 3]
    scene_file, body_file, poses_file = tmp_path / "cell.yaml", tmp_path / "body.yaml", tmp_path / "poses.npy"
    scene_file.write_text("margin: 0.01\nobstacles:\n  - {name: ball, type: sphere, center: "
                          f"{json.dumps(elbow.tolist())}, radius: 0.06}}\n")
    body_file.write_text("capsules:\n  link_4: [{a: [0, 0, 0], b: [0, 0, 0], radius: 0.05}]\n"
                         "  link_7: [{a: [0, 0, 0], b: [0, 0, 0.08], radius: 0.04}]\n")
    np.save(poses_file, poses)
    code, out, err = run(capsys, ["path", "franka-panda", "--poses", str(poses_file), "--max-step", str(STEP),
                                  "--scene", str(scene_file), "--body", str(body_file), "--json"])
    assert code == 0, err
    report = json.loads(out)
    body = body_of([BodyCapsule("link_4", 4, [0, 0, 0], [0, 0, 0], 0.05),
                    BodyCapsule("link_7", 7, [0, 0, 0], [0, 0, 0.08], 0.04)], chain)
    scene = redkin.collision.read_scene(scene_file)
    api = resolve_path(chain, poses, STEP, body=body, scene=scene)
    assert api.ok and np.allclose(np.asarray(report["q"]), api.q, rtol=0, atol=1e-12)
    assert report["collision"]["least"] >= scene.margin - 1e-12
