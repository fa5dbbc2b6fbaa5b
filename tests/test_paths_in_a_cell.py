"""Paths in a cell (issue 40): with a body and a scene, every waypoint of a resolved path keeps the margin from every
obstacle (measured here with the clearance of the joint values returned), the path swings the elbow around an
obstacle the plain path runs into, and a waypoint the obstacles block on every branch fails with reason
``"collision"`` and the pair that blocks it."""

from __future__ import annotations

import numpy as np
import pytest

import redkin
from redkin.circle import arc_length
from redkin.collision import Scene, body_of, clearance, primitives
from redkin.errors import RedkinError
from redkin.paths import resolve_path
from tests.support.iiwa_cell import END, START, three_capsules


@pytest.fixture(scope="module")
def setting():
    chain = redkin.get_robot("kuka-iiwa14")
    poses = chain.fk(np.linspace(START, END, 25))
    body = three_capsules(chain)
    return chain, poses, body, resolve_path(chain, poses, 0.15)


def test_the_path_swings_the_elbow_around_what_the_plain_path_hits(setting):
    chain, poses, body, plain = setting
    assert plain.status == "ok"
    elbow = chain.frames(plain.q[12])[3, :3, 3]
    scene = Scene(("ball",), primitives.sphere(elbow, 0.06)[None], 0.01)
    assert clearance(chain, body, scene, plain.q).distance.min() < scene.margin  # the plain path runs into it
    result = resolve_path(chain, poses, 0.15, body=body, scene=scene)
    assert result.status == "ok"
    assert np.all(clearance(chain, body, scene, result.q).distance >= scene.margin - 1e-12)
    assert np.allclose(chain.fk(result.q), poses, atol=1e-9)


def test_a_waypoint_blocked_on_every_branch_names_the_pair(setting):
    chain, poses, body, plain = setting
    hand = chain.frames(plain.q[10])[7, :3, 3]  # the hand does not move with the arm angle: every branch meets it
    scene = Scene(("ball",), primitives.sphere(hand + [0.0, 0.0, 0.0], 0.03)[None], 0.0)
    result = resolve_path(chain, poses, 0.15, body=body, scene=scene)
    assert result.status == "no-path"
    failure = result.failure
    assert failure.reason == "collision" and failure.pair == ("hand", "ball")
    assert failure.waypoint <= 10
    assert "hand meets ball" in failure.message
    assert failure.parameter == "psi" and "no arm angle within the joint limits" in failure.message


def test_a_cell_needs_both_parts_and_a_class_with_free_sets(setting):
    chain, poses, body, _ = setting
    with pytest.raises(RedkinError, match="both"):
        resolve_path(chain, poses, 0.15, body=body)
    sawyer = redkin.get_robot("sawyer.urdf")  # solved numerically: no redundancy parameter, so no sets
    with pytest.raises(RedkinError, match="'sawyer' is a general chain"):
        resolve_path(sawyer, sawyer.fk(np.zeros((3, 7)) + 0.2), 0.15, body=body_of([], sawyer),
                     scene=Scene((), np.empty((0, primitives.WIDTH))))


@pytest.mark.parametrize("centre, radius", [([1.5, 1.5, 1.5], 0.1), ([0.0, 0.0, -0.3], 0.2),
                                            ([0.5, -0.6, 0.3], 0.15), ("elbow", 0.06)])
def test_a_clearance_proved_optimal_in_a_cell_is_not_beaten_at_its_bottleneck(setting, centre, radius):
    """Where a path in a cell is proved optimal (among the certified collision-free sets, complete at its
    bottleneck), no configuration of any branch at the bottleneck waypoint, on 20 000 arm angles, that keeps the
    margin (by 10 um more: a free sliver narrower than the sets' resolution is not claimed) and the limits is
    further from the limits than the path's clearance and the margin of the proof."""
    from redkin.paths import OPTIMALITY_MARGIN

    chain, poses, body, plain = setting
    if centre == "elbow":  # the ball the plain path's elbow meets at waypoint 12 (the first test's)
        centre = chain.frames(plain.q[12])[3, :3, 3]
    scene = Scene(("ball",), primitives.sphere(np.array(centre), radius)[None], 0.01)
    result = resolve_path(chain, poses, 0.5, body=body, scene=scene)
    assert result.status == "ok"
    if not result.optimal:  # only where the elbow's ball decides the clearance: not proved (a sliver may pass it)
        assert radius == 0.06
        return
    arm = redkin.arm(chain)
    psi = np.linspace(-np.pi, np.pi, 20_000, endpoint=False)
    rows = arm.ik(np.broadcast_to(poses[result.bottleneck], (len(psi), 4, 4)), psi)
    q = rows.q[rows.exists & rows.within_limits]
    q = q[clearance(chain, body, scene, q).distance >= scene.margin + 1e-5]
    from_limits = np.minimum(q - chain.lower, chain.upper - q)[:, ~chain.covers_circle].min(axis=1)
    assert from_limits.max(initial=-np.inf) <= result.clearance + OPTIMALITY_MARGIN


def test_a_tolerance_above_the_default_reaches_the_cell():
    """The YuMi's right arm is nearly S-R-S only within a tolerance above the default (axes about 4 cm apart): with
    ``srs_tolerance`` 0.05 the path in a cell, its collision-free pieces and the stretches the cell removes are all
    of that class (the cell's sets were asked of the arm classified at the default, a general chain, and refused),
    and per waypoint and branch the free set and the removed stretches fill the limit-feasible set."""
    from redkin.collision import BodyCapsule, scene_of
    from redkin.paths import feasible_along_path, removed_along_path

    chain = redkin.get_robot("yumi_right.urdf")
    assert redkin.arm(chain).kind == "general chain" and redkin.arm(chain, srs_tolerance=0.05).kind == "nearly S-R-S"
    qs = np.linspace([0.3, -0.6, 0.2, 0.4, 0.4, 0.8, 0.1], [-0.4, -1.2, 0.8, 0.9, -0.6, 0.3, 0.6], 3)
    poses = chain.fk(qs)
    body = body_of([BodyCapsule("hand", 7, (0, 0, 0), (0, 0, 0.02), 0.03)], chain)
    hand = chain.frames(qs[2])[7, :3, 3]  # the hand does not move with the arm angle: every branch meets it
    scene = scene_of({"margin": 0.01, "obstacles": [{"name": "ball", "type": "sphere", "center": hand.tolist(),
                                                      "radius": 0.03}]})
    result = resolve_path(chain, poses, 1.0, srs_tolerance=0.05, body=body, scene=scene)
    assert not result.ok and result.failure.waypoint == 2 and result.failure.pair == ("hand", "ball")
    limits = feasible_along_path(chain, poses, 0.05)
    free = feasible_along_path(chain, poses, 0.05, body, scene)
    removed = removed_along_path(chain, poses, body, scene, srs_tolerance=0.05)
    assert limits.feasible.any(axis=-1).sum() >= 6
    for k in range(len(poses)):
        for b in range(8):
            taken = sum(arc_length(start, end) for start, end, _ in removed[k][b])
            assert free.arc_set((k, b)).length + taken == pytest.approx(limits.arc_set((k, b)).length, abs=1e-3)
            if k == 2:
                assert free.arc_set((k, b)).is_empty and all(cause in ("hand meets ball", "undecided")
                                                               for _, _, cause in removed[k][b])
