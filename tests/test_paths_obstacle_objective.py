"""The objective ``"obstacle-clearance"`` (issue 40): in a cell, the path as far from the obstacles and the arm's own
links as the searched graph allows, then the least motion.

Laws: the path's ``cell_clearance`` is the least distance measured here pair by pair at its waypoints, at least the
default objective's (which ignores the distance) and no more than any waypoint allows (the largest distance over
dense arm angles of every branch within the limits, plus what the sampling can miss); every waypoint and step keeps
the margin; the objective without a cell is refused, in the API and on the command line.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import redkin
from redkin.collision import BodyCapsule, Scene, body_of, clearance, primitives
from redkin.collision.arm_angle_free import moved_pairs
from redkin.collision.clearance import pair_table
from redkin.errors import RedkinError
from redkin.paths import resolve_path
from redkin.paths.arm_family import path_family
from redkin.paths.collision_family import collision_free_family
from tests.support.cli import run
from tests.support.iiwa_cell import CAPSULES, END, START, three_capsules

#: Dense arm angles per branch for the waypoints' largest distance, and what a distance can change between two of
#: them (a body point moves at most about 1 m per radian of arm angle on the iiwa14).
_DENSE = 720
_BETWEEN = 2 * np.pi / _DENSE


@pytest.fixture(scope="module")
def setting():
    chain = redkin.get_robot("kuka-iiwa14")
    body = three_capsules(chain)
    poses = chain.fk(np.linspace(START, END, 12))
    return chain, body, poses, resolve_path(chain, poses, 0.3)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_path_keeps_as_far_from_the_obstacles_as_the_waypoints_allow(setting, seed):
    chain, body, poses, plain = setting
    rng = np.random.default_rng(seed)
    centre = chain.frames(plain.q[rng.integers(len(poses))])[3, :3, 3] + rng.normal(0.0, 0.05, 3)
    scene = Scene(("ball",), primitives.sphere(centre, rng.uniform(0.02, 0.1))[None], 0.01)
    default = resolve_path(chain, poses, 0.3, body=body, scene=scene)
    result = resolve_path(chain, poses, 0.3, body=body, scene=scene, objective="obstacle-clearance")
    assert default.ok and result.ok
    measured = clearance(chain, body, scene, result.q).distance
    assert result.cell_clearance == pytest.approx(float(measured.min()), abs=1e-12)
    assert default.cell_clearance == pytest.approx(float(clearance(chain, body, scene, default.q).distance.min()),
                                                   abs=1e-12)
    assert result.cell_clearance >= default.cell_clearance
    family = collision_free_family(path_family(chain, None), body, scene)
    assert family.moving_distances(result.q).min() >= family.moving_distances(default.q).min()
    assert measured.min() >= scene.margin - 1e-12 and result.steps.certified.all()
    assert np.allclose(chain.fk(result.q), poses, atol=1e-9) and np.all(chain.joints_within_limits(result.q))
    assert np.abs(np.diff(result.q, axis=0)).max() <= 0.3 + 1e-12
    # no waypoint allows more: the largest distance over dense arm angles of every branch within the limits
    solutions = redkin.arm(chain).ik(poses[:, None], np.linspace(-np.pi, np.pi, _DENSE, endpoint=False))
    usable = solutions.exists & solutions.within_limits  # (N, S, 8)
    distance = clearance(chain, body, scene, solutions.q).distance
    ceiling = np.where(usable, distance, -np.inf).max(axis=(1, 2)).min()
    assert result.cell_clearance <= ceiling + _BETWEEN


def test_the_pairs_left_out_keep_their_distance_at_every_arm_angle(setting):
    """moved_pairs: a pair said not to move keeps its distance over 24 arm angles of the branch at the pose (the
    hand and the obstacles, the upper arm and a ball at the wrist centre), and the others do change."""
    chain, _, poses, plain = setting
    body = body_of([*CAPSULES, BodyCapsule("wrist ball", 5, [0, 0, 0], [0, 0, 0], 0.06)], chain)
    scene = Scene(("post", "lamp"), np.stack([primitives.capsule([0.4, 0.3, 0.0], [0.4, 0.3, 1.2], 0.05),
                                              primitives.sphere([0.2, -0.3, 0.8], 0.1)]), 0.0)
    arm = redkin.arm(chain)
    psi = np.linspace(-np.pi, np.pi, 24, endpoint=False)
    for k in (0, 6):
        solutions = arm.ik(np.repeat(poses[k : k + 1], len(psi), axis=0), psi, branches=plain.branch[k])
        q = solutions.q[:, 0][solutions.exists[:, 0]]
        moves = moved_pairs(arm, body, scene, q)
        assert np.all(moves == moves[0])  # a property of the pose, not of the arm angle
        table, pairs = pair_table(chain, body, scene, q)
        spread = np.ptp(table, axis=0)
        still = [pairs.names[i] for i in np.flatnonzero(~moves[0])]
        assert ("hand", "post") in still and ("upper arm", "wrist ball") in still and ("forearm", "post") not in still
        assert np.all(spread[~moves[0]] < 1e-9) and np.all(spread[moves[0]] > 1e-6)


def test_the_objective_needs_a_cell(setting, capsys, tmp_path):
    chain, _, poses, _ = setting
    with pytest.raises(RedkinError, match="obstacle-clearance needs a cell"):
        resolve_path(chain, poses, 0.3, objective="obstacle-clearance")
    file = tmp_path / "poses.npy"
    np.save(file, poses)
    code, _, err = run(capsys, ["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.3", "--objective",
                                "obstacle-clearance"])
    assert code == 2 and "needs the cell: give --scene FILE" in err and len(err.strip().splitlines()) == 1


def test_the_command_line_keeps_the_path_far_from_the_post(setting, capsys, tmp_path):
    chain, _, poses, _ = setting
    file, scene, body = tmp_path / "poses.npy", tmp_path / "cell.yaml", tmp_path / "body.yaml"
    np.save(file, poses)
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.3, 0.35, 0], b: [0.3, 0.35, 1.2], radius: 0.04}\n")
    body.write_text("capsules:\n  link_3: [{a: [0, 0, -0.2], b: [0, 0, 0], radius: 0.05}]\n"
                    "  link_4: [{a: [0, 0, 0], b: [0, 0.2, 0], radius: 0.05}]\n")
    argv = ["path", "kuka-iiwa14", "--poses", str(file), "--max-step", "0.3", "--scene", str(scene), "--body",
            str(body), "--json"]
    reports = {}
    for objective in ("clearance", "obstacle-clearance"):
        code, out, _ = run(capsys, [*argv, "--objective", objective])
        assert code == 0
        reports[objective] = json.loads(out)
    far = reports["obstacle-clearance"]
    assert far["objective"] == "obstacle-clearance"
    assert far["collision"]["least"] >= reports["clearance"]["collision"]["least"]
    post = redkin.collision.read_scene(scene)
    links = redkin.collision.read_body(body, chain, redkin.collision.numbered_link_frames(chain))
    assert far["collision"]["least"] == pytest.approx(
        float(clearance(chain, links, post, np.array(far["q"])).distance.min()), abs=1e-12)
