"""Which of a branch's two solutions ``Arm.ik`` and ``redkin ik`` report on a nearly S-R-S arm (issue 40's nearly
fold; issue 38, item 4; redkin.arms.branch_choice).

On the Kinova Gen3 at the pose of ``tests.test_srs_nearly_self_motion.TWO_SOLUTIONS`` the branch ``-++`` has two
solutions at psi = 1.5, 1.7 rad apart in q1.  A ball beside link 4 of the closed form's solution (the first) meets it
and clears the other by more than the margin.

Laws: in a cell a row is one of the branch's solutions at its value, and it is clear within the limits wherever one
of them is; ``q0`` picks the one nearest it; the API and the command line pick the same one.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.arms.branch_choice import candidates, preferred
from redkin.collision import builtin_body, clearance, scene_of
from tests.support.cli import run
from tests.test_srs_nearly_self_motion import TWO_SOLUTIONS

#: The arm angle and the branch with two solutions at the pose.
PSI, BRANCH = 1.5, "-++"
#: A ball that meets link 4 of the branch's first solution and clears the second by 7.8 mm beyond the margin.
BALL = {"margin": 0.01, "obstacles": [
    {"name": "ball", "type": "sphere", "center": [-0.0008, -0.0604, 0.7484], "radius": 0.02}]}


@pytest.fixture(scope="module")
def fold():
    arm = redkin.arm("kinova-gen3")
    pose = arm.fk(np.array(TWO_SOLUTIONS))
    body, scene = builtin_body("kinova-gen3", arm.chain), scene_of(BALL)
    first, second = arm.every_solution(pose, PSI, BRANCH)
    distance = clearance(arm.chain, body, scene, np.stack([first, second])).distance
    assert distance[0] < scene.margin <= distance[1]  # the premise: the closed form's solution collides
    return arm, pose, body, scene, first, second


def _argv(pose: np.ndarray) -> list[str]:
    return ["ik", "kinova-gen3", "--position", *map(repr, pose[:3, 3].tolist()), "--rotation",
            *map(repr, pose[:3, :3].ravel().tolist()), "--psi", repr(PSI), f"--branch={BRANCH}", "--json"]


def test_in_a_cell_the_branch_solution_clear_of_it_is_returned(fold, tmp_path, capsys):
    arm, pose, body, scene, first, second = fold
    np.testing.assert_allclose(arm.ik(pose, PSI, branches=BRANCH).q[0], first, atol=1e-12)  # without the cell
    marked = arm.ik(pose, PSI, branches=BRANCH, body=body, scene=scene)
    np.testing.assert_allclose(marked.q[0], second, atol=1e-12)
    assert marked.collision_free[0] and marked.within_limits[0] and marked.clearance.distance[0] >= scene.margin
    every_row = arm.ik(np.stack([pose, pose]), PSI, body=body, scene=scene)  # a batch of every branch
    np.testing.assert_allclose(every_row.q[:, arm.branches.index(BRANCH)], [second, second], atol=1e-12)
    cell = tmp_path / "ball.json"
    cell.write_text(json.dumps(BALL))
    code, out, _ = run(capsys, [*_argv(pose), "--scene", str(cell)])
    (solution,) = json.loads(out)["solutions"]
    assert code == 0 and solution["collision_free"] and solution["others"] == 1
    np.testing.assert_allclose(solution["q"], second, atol=1e-9)
    code, out, _ = run(capsys, [*_argv(pose), "--scene", str(cell), "--every-solution"])
    listed = json.loads(out)["solutions"]
    assert code == 0 and [s["collision_free"] for s in listed] == [False, True]
    batch = tmp_path / "poses.npy"  # a batch in the cell chooses as one pose does
    np.save(batch, np.stack([pose, pose]))
    code, out, _ = run(capsys, ["ik", "kinova-gen3", "--poses", str(batch), "--psi", repr(PSI), f"--branch={BRANCH}",
                                "--json", "--scene", str(cell)])
    entries = json.loads(out)["poses"]
    assert code == 0 and all(entry["solutions"][0]["collision_free"] for entry in entries)
    np.testing.assert_allclose([entry["solutions"][0]["q"] for entry in entries], [second, second], atol=1e-9)


def test_q0_picks_the_branch_solution_nearest_it_in_the_api_as_on_the_command_line(fold, capsys):
    arm, pose, _, _, first, second = fold
    for wanted in (first, second):
        near = wanted + 0.01
        picked = arm.ik(pose, PSI, branches=BRANCH, q0=near)
        np.testing.assert_allclose(picked.q[0], wanted, atol=1e-12)
        code, out, _ = run(capsys, [*_argv(pose), "--q0", *map(repr, near.tolist())])
        assert code == 0
        np.testing.assert_allclose(json.loads(out)["solutions"][0]["q"], picked.q[0], atol=1e-9)


def test_a_row_already_clear_of_the_cell_is_the_closed_forms(fold):
    arm, pose, body, _, first, _ = fold
    far = scene_of({"margin": 0.01, "obstacles": [{"name": "far", "type": "sphere", "center": [3, 3, 3],
                                                   "radius": 0.1}]})
    clear_anyway = arm.ik(pose, PSI, branches=BRANCH, body=body, scene=far)  # clear: nothing to replace
    np.testing.assert_allclose(clear_anyway.q[0], first, atol=1e-12)
    assert clear_anyway.collision_free[0]


@settings(max_examples=3, deadline=None)
@given(fraction=st.lists(st.floats(0.05, 0.95), min_size=7, max_size=7), psi=st.floats(-3.1, 3.1))
def test_each_row_in_a_cell_is_a_branch_solution_and_clear_wherever_one_is(fold, fraction, psi):
    arm, _, body, _, _, _ = fold
    scene = scene_of({"margin": 0.01, "obstacles": [
        {"name": "post", "type": "capsule", "a": [0.45, 0.25, -0.2], "b": [0.45, 0.25, 1.2], "radius": 0.05},
        {"name": "lamp", "type": "sphere", "center": [0.2, -0.4, 0.8], "radius": 0.12}]})
    low, high = np.maximum(arm.chain.lower, -np.pi), np.minimum(arm.chain.upper, np.pi)
    pose = arm.fk(low + np.asarray(fraction) * (high - low))
    rows = arm.ik(pose, psi, body=body, scene=scene)
    for b, branch in enumerate(arm.branches):
        every = arm.every_solution(pose, psi, branch)
        assert rows.exists[b] == bool(len(every))
        if not len(every):
            continue
        moved, inside = candidates(arm.chain, every, None)
        good = inside & (clearance(arm.chain, body, scene, moved).distance >= scene.margin)
        gap = np.abs(np.angle(np.exp(1j * (moved - rows.q[b])))).max(axis=-1)
        assert gap.min() < 1e-9, branch  # one of the branch's solutions
        assert (rows.collision_free[b] and rows.within_limits[b]) == good.any(), branch


def test_preferred_ranks_clear_and_within_first_then_nearest_q0():
    solutions = np.array([[0.0] * 7, [1.0] * 7, [2.0] * 7])
    within = np.array([True, True, False])
    assert preferred(solutions, within, None, None) == 0
    assert preferred(solutions, within, np.array([False, True, True]), None) == 1  # clear and within first
    assert preferred(solutions, within, np.array([False, False, True]), None) == 2  # then clear
    assert preferred(solutions, within, None, np.full(7, 1.9)) == 1  # nearest q0 among those within
    assert preferred(solutions, ~within, None, np.full(7, 0.2)) == 2
