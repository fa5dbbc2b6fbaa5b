"""The limit-avoiding value inside the collision-free sets (issue 40, item 5: ``Arm.optimal(..., body=, scene=)``).

Laws, on the iiwa14 (arm angle) and the Panda (q7) with their built-in bodies in a cell:

* the value lies in the branch's certified collision-free set, and is ``nan`` exactly where that set is empty;
* on the arm angle it is the free set's point nearest the unclamped optimum ([000]'s clamping); on q7 no sampled
  value of the free intervals has a smaller [F10] objective;
* ``unclamped`` is the one without a cell (to the q7 search's tolerance); many poses at once equal one by one;
* ``redkin arm-angles --scene --json`` says the same value; half a cell and an arm without free sets are refused.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import redkin
from redkin.circle import ArcSet
from redkin.collision import builtin_body, collision_free_set, scene_of
from redkin.errors import RedkinError
from tests.support.cli import run

CELL = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.3, 0.3, 0.0], "b": [0.3, 0.3, 1.0], "radius": 0.04},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.35, 0.8], "radius": 0.1}]}
#: Configurations whose poses the laws are checked at (inside both arms' limits).
CONFIGURATIONS = np.array([[0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.785], [0.4, 0.5, -0.3, -1.6, 0.5, 1.4, -0.6]])
#: Samples of q7 per free interval for the minimiser law.
SAMPLES = 400


def _objective(chain, pose, branch, q7):
    """[F10]'s objective at ``q7`` (the middle of each range as the target), ``inf`` where the branch has none."""
    solutions = redkin.arm(chain).ik(np.broadcast_to(pose, (len(q7), 4, 4)), q7, branches=branch)
    half = np.where(chain.limited, (chain.upper - chain.lower) / 2.0, 1.0)
    middle = np.where(chain.limited, (chain.upper + chain.lower) / 2.0, 0.0)
    cost = np.sum(((solutions.q[:, 0] - middle) / half) ** 2, axis=-1)
    return np.where(solutions.exists[:, 0], cost, np.inf)


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "franka-panda"])
def test_the_value_is_the_class_s_optimum_inside_the_free_set(robot):
    arm = redkin.arm(robot)
    body, scene = builtin_body(robot, arm.chain), scene_of(CELL)
    poses = arm.fk(CONFIGURATIONS)
    inside = arm.optimal(poses, body=body, scene=scene)
    plain = arm.optimal(poses)
    assert inside.value.shape == plain.value.shape == (2, 8) and inside.branches == arm.branches
    # the same search (on q7 the better of the whole range's and the free intervals' minimisers, to Brent's 1e-8)
    np.testing.assert_allclose(inside.unclamped, plain.unclamped, rtol=0, atol=1e-7)
    seen = 0
    for p, pose in enumerate(poses):
        free = collision_free_set(arm, pose, body, scene)
        for b, label in enumerate(arm.branches):
            arcs, value = free.free[b], inside.value[p, b]
            if not len(arcs.bounds):
                assert np.isnan(value)
                continue
            seen += 1
            if arm.parameter.name == "psi":
                assert value == pytest.approx(ArcSet(arcs.bounds.tolist()).nearest(inside.unclamped[p, b]), abs=1e-12)
                continue
            assert np.any((arcs.bounds[:, 0] <= value) & (value <= arcs.bounds[:, 1]))
            sampled = np.concatenate([np.linspace(lo, hi, SAMPLES) for lo, hi in arcs.bounds])
            best = _objective(arm.chain, pose, label, np.array([value]))[0]
            assert best <= _objective(arm.chain, pose, label, sampled).min() + 1e-9
    assert seen >= 2
    one = arm.optimal(poses[1], "+-+", body=body, scene=scene)
    np.testing.assert_array_equal(one.value, inside.value[1, [arm.branches.index("+-+")]])


def test_the_command_line_says_the_api_s_value(capsys, tmp_path):
    arm = redkin.arm("franka-panda")
    body, scene = builtin_body("franka-panda", arm.chain), scene_of(CELL)
    pose = arm.fk(CONFIGURATIONS[0])
    expected = arm.optimal(pose, "+-+", body=body, scene=scene).value[0]
    cell = tmp_path / "cell.yaml"
    cell.write_text(json.dumps(CELL))
    code, out, _ = run(capsys, ["arm-angles", "franka-panda", "--position", *map(repr, pose[:3, 3].tolist()),
                                "--rotation", *map(repr, pose[:3, :3].ravel().tolist()), "--scene", str(cell),
                                "--branch=+-+", "--json"])
    assert code == 0
    found = json.loads(out)["optimal"]["overall"]["collision_free"]
    assert (found is None and np.isnan(expected)) or found == pytest.approx(expected, abs=1e-12)


def test_half_a_cell_and_an_arm_without_free_sets_are_refused():
    arm = redkin.arm("kuka-iiwa14")
    with pytest.raises(RedkinError, match="both"):
        arm.optimal(arm.fk(CONFIGURATIONS[0]), scene=scene_of(CELL))
    sawyer = redkin.arm("sawyer.urdf")  # solved numerically: no redundancy parameter, so no sets
    with pytest.raises(RedkinError, match="need a redundancy parameter: 'sawyer' has none"):
        sawyer.optimal(sawyer.fk(np.zeros(7) + 0.3), body=redkin.collision.body_of([], sawyer.chain),
                       scene=scene_of(CELL))
