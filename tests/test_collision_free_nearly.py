"""Certified collision-free arm angles of nearly S-R-S arms (issue 40, item 4; redkin.collision.nearly_free).

Laws, on the Kinova Gen3 with its built-in body in a cell of a post, a table and a lamp:

* every arm angle of a free arc has a solution of the branch within the limits and clear of every pair by the margin;
* nothing clear within the limits is left out beyond the resolution about a reported end or undecided stretch;
* each collision stretch is met by the pair it names;
* the bound the certificate rests on holds: over a step's arc (followed again in fine steps), every point lies within
  the step's joint bounds of its anchor, and every pair's clearance within the displacement bound of the anchor's;
* ``Arm.feasible``, ``Arm.optimal`` and ``redkin arm-angles --scene --json`` give the same sets.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import redkin
from redkin.circle import ArcSet, arc_length
from redkin.collision import (
    BodyCapsule,
    Scene,
    body_of,
    builtin_body,
    clearance,
    collision_free_set,
    primitives,
    scene_of,
)
from redkin.collision.arm_angle_free import COLLISION, UNDECIDED
from redkin.collision.clearance import pair_table
from redkin.collision.nearly_free import _StepMeasure
from redkin.srs.nearly.self_motion import branch_solutions, finer_steps, whole_self_motion
from tests.support.cli import run

#: The cell: a post beside the arm, a table under its reach (clear of its base) and a lamp above it.
CELL = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.45, 0.25, -0.2], "b": [0.45, 0.25, 1.2], "radius": 0.05},
    {"name": "table", "type": "box", "center": [0.6, 0, -0.2], "size": [1.2, 1.0, 0.1]},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.4, 0.8], "radius": 0.12}]}
#: Arm angles the laws sample around the circle.
SAMPLES = 4001
#: How far outside a joint's range the limit sets' own ends may put a joint (their ends are certified to rounding).
ROUNDING = 1e-9
#: Configurations (fractions of each joint's range) whose poses give free, collision and limit stretches, and one
#: near the stretched elbow with limit stretches only.
RICH = ([0.87, 0.13, 0.47, 0.28, 0.08, 0.9, 0.43], [0.13, 0.5, 0.6, 0.03, 0.15, 0.93, 0.07])

fractions = st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7)


@pytest.fixture(scope="module")
def setup():
    arm = redkin.arm("kinova-gen3")
    return arm, builtin_body("kinova-gen3", arm.chain), scene_of(CELL)


def _pose(arm, fraction) -> np.ndarray:
    low, high = np.maximum(arm.chain.lower, -np.pi), np.minimum(arm.chain.upper, np.pi)
    return arm.fk(low + np.asarray(fraction) * (high - low))


def _clear_and_within(arm, body, scene, q: np.ndarray) -> np.ndarray:
    within = arm.chain.joints_within_limits(q, tolerance=ROUNDING, wrap=True).all(axis=-1)
    return within & (clearance(arm.chain, body, scene, q).distance - scene.margin >= -1e-12)


@settings(max_examples=2, deadline=None)
@given(fraction=fractions)
@example(fraction=RICH[0])
@example(fraction=RICH[1])
def test_free_arcs_are_clear_and_nothing_clear_is_left_out(setup, fraction):
    arm, body, scene = setup
    pose = _pose(arm, fraction)
    free = collision_free_set(arm, pose, body, scene)
    assert free.parameter == "psi"
    if not free.complete:
        pytest.skip("the self-motion of this pose was not followed whole")
    curves = None
    psi = np.linspace(-np.pi, np.pi, SAMPLES)
    solutions = arm.ik(pose, psi)
    for b, branch in enumerate(free.branches):
        clear_set, limits = ArcSet(free.free[b].bounds.tolist()), ArcSet(free.limits[b].bounds.tolist())
        assert clear_set.intersection(limits).isclose(clear_set, 1e-12)  # free arcs lie in the limits' set
        inside = np.asarray(clear_set.contains(psi))
        exists = solutions.exists[:, b]
        good = np.zeros(len(psi), dtype=bool)
        good[exists] = _clear_and_within(arm, body, scene, solutions.q[exists, b])
        for k in np.flatnonzero(inside & ~good):  # next to a fold the solver's solution may be the other one
            curves = curves if curves is not None else whole_self_motion(arm.implementation.nearly, pose)[0]
            every = branch_solutions(arm.implementation.nearly, pose, psi[k], branch, curves)
            assert len(every) and _clear_and_within(arm, body, scene, every).any(), (branch, psi[k])
        undecided = ArcSet([(s.start, s.end) for s in free.blocked[b] if s.cause == UNDECIDED])
        left_out = ~inside & good & np.asarray(limits.contains(psi)) & ~np.asarray(undecided.contains(psi))
        edges = np.array([v for s in free.blocked[b] for v in (s.start, s.end)] + free.free[b].bounds.ravel().tolist())
        for value in psi[left_out]:
            assert np.min(np.abs((edges - value + np.pi) % (2 * np.pi) - np.pi)) <= 2.0 * free.resolution, (
                branch, value)


@settings(max_examples=1, deadline=None)
@given(fraction=fractions)
@example(fraction=RICH[0])
def test_each_collision_stretch_is_met_by_the_pair_it_names(setup, fraction):
    arm, body, scene = setup
    pose = _pose(arm, fraction)
    free = collision_free_set(arm, pose, body, scene)
    curves = whole_self_motion(arm.implementation.nearly, pose)[0]
    for b, branch in enumerate(free.branches):
        for stretch in (s for s in free.blocked[b] if s.cause == COLLISION):
            width = arc_length(stretch.start, stretch.end)
            if width < 1e-4:
                continue
            for t in stretch.start + width * np.linspace(0.0, 1.0, 7)[1:-1]:
                every = branch_solutions(arm.implementation.nearly, pose, (t + np.pi) % (2 * np.pi) - np.pi, branch,
                                         curves)
                table, pairs = pair_table(arm.chain, body, scene, every)
                columns = [k for k, names in enumerate(pairs.names) if names == (stretch.link, stretch.against)]
                assert len(every) and np.any(table[:, columns].min(axis=1) - scene.margin <= 1e-12), (branch, t)
                assert not _clear_and_within(arm, body, scene, every).any()


@settings(max_examples=2, deadline=None)
@given(fraction=fractions, pick=st.floats(0.0, 1.0))
@example(fraction=RICH[0], pick=0.3)
@example(fraction=RICH[1], pick=0.7)
def test_the_bound_the_certificate_rests_on_holds(setup, fraction, pick):
    """Over a step's arc, followed again in steps 1/64 as long, every point lies within the step's joint bounds of its
    anchor and every pair's clearance within the displacement bound of the anchor's."""
    arm, body, scene = setup
    pose = _pose(arm, fraction)
    nearly = arm.implementation.nearly
    curves = whole_self_motion(nearly, pose)[0]
    measure = _StepMeasure(arm, body, scene)
    checked = 0
    for curve in curves:
        for k in np.unique((pick * (len(curve.spread) - 1) + np.array([0, 7, 31])) % len(curve.spread)).astype(int):
            piece = finer_steps(nearly, pose, curve, k, curve.tubes[k, 0] / 64.0, most=512)
            if piece is None:
                continue
            anchor = curve.q[curve.anchors[k]]
            delta = curve.tubes[k, 0] * np.abs(curve.tangents[curve.anchors[k]]) + curve.tubes[k, 1]
            other = k + 1 if curve.anchors[k] == k else k
            length = float((curve.q[other] - anchor) @ (curve.tangents[curve.anchors[k]]
                                                        * (1.0 if curve.anchors[k] == k else -1.0)))
            along = (piece.q - anchor) @ (curve.tangents[curve.anchors[k]] * (1.0 if curve.anchors[k] == k else -1.0))
            points = piece.q[along <= length + 1e-12]  # the step's own arc (the piece runs a little past its end)
            assert np.all(np.abs(points - anchor) <= delta + 1e-12)
            low, high = measure.bounds(anchor[None], delta[None], np.ones((1, len(measure.pairs.names)), dtype=bool))
            table, _ = pair_table(arm.chain, body, scene, points)
            assert np.all(table - scene.margin >= low - 1e-12) and np.all(table - scene.margin <= high + 1e-12)
            checked += 1
    assert checked


def test_the_api_and_the_command_line_give_the_same_sets(setup, capsys, tmp_path):
    arm, body, scene = setup
    pose = _pose(arm, RICH[0])
    free = collision_free_set(arm, pose, body, scene)
    sets = arm.feasible(pose, body=body, scene=scene)
    assert sets.parameter == "psi" and not sets.exact
    for b, branch in enumerate(free.branches):
        assert ArcSet(sets.arcs(branch).bounds.tolist()).isclose(ArcSet(free.free[b].bounds.tolist()), 1e-12)
    optimal = arm.optimal(pose, body=body, scene=scene)
    for b in range(len(free.branches)):
        value = optimal.value[b]
        assert (np.isnan(value) and not len(free.free[b].bounds)) or ArcSet(free.free[b].bounds.tolist()).contains(
            value, 1e-9)
    cell = tmp_path / "cell.yaml"
    cell.write_text(json.dumps(CELL))
    argv = ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist()),
            "--scene", str(cell)]
    code, out, _ = run(capsys, ["arm-angles", "kinova-gen3", *argv, "--json"])
    assert code == 0
    report = json.loads(out)
    for b, label in enumerate(free.branches):
        assert np.allclose(np.array(report["branches"][label]).reshape(-1, 2), free.free[b].bounds, atol=1e-12)
    assert report["collision"]["complete"] is True


def test_the_removed_stretches_have_width_and_a_whole_circle_is_named(setup):
    """No removed stretch is a point (the ends where a named stretch meets the limits' or another's were listed as
    undecided stretches of no width), and where a ball at the hand takes every arm angle of branches whose limits
    leave the whole circle, each branch's whole circle is one stretch named by the hand and the ball (it was
    dropped as of no width, so no pair was named)."""
    arm, body, scene = setup
    for fraction in RICH:
        for stretches in collision_free_set(arm, _pose(arm, fraction), body, scene).blocked:
            assert all(arc_length(start, end) > 1e-12 for start, end, *_ in stretches)
    q = np.array([0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1])
    hand = body_of([BodyCapsule("hand", 7, (0, 0, 0), (0, 0, 0.02), 0.03)], arm.chain)
    ball = Scene(("ball",), primitives.sphere(arm.chain.frames(q)[7, :3, 3], 0.03)[None], 0.01)
    sets = collision_free_set(arm, arm.fk(q), hand, ball)
    whole = [b for b, limits in enumerate(sets.limits) if ArcSet(limits.bounds.tolist()).is_full]
    assert len(whole) >= 2
    for b in whole:
        assert not len(sets.free[b].bounds)
        assert [(stretch.cause, stretch.link, stretch.against) for stretch in sets.blocked[b]] == [
            (COLLISION, "hand", "ball")]
        assert ArcSet([(stretch.start, stretch.end) for stretch in sets.blocked[b]]).is_full


@pytest.mark.parametrize("width", [1e-4, 1e-5])
def test_a_narrow_gap_between_two_obstacles_near_the_elbow_is_found(width):
    """Two balls beside the path the Gen3's elbow takes, each placed (by bisection on the branch's own solutions) so
    that the elbow's ball touches it, at the margin, exactly at ``psi0 -+ width / 2``: the free arc through ``psi0``
    is that gap, to the resolution."""
    arm = redkin.arm("kinova-gen3")
    chain = arm.chain
    q = np.array([0.2, 0.7, -0.3, 1.4, 0.3, 0.6, 0.1])
    pose, label = chain.fk(q), str(arm.branch_of(q))
    psi0 = float(arm.parameter_of(q))

    def elbow_at(psi):
        return chain.frames(arm.ik(pose, np.atleast_1d(psi), branches=label).q[:, 0])[:, 4, :3, 3]

    ball, margin, ball_radius = 0.03, 0.01, 0.04
    apart = ball + ball_radius + margin
    speed = np.linalg.norm(elbow_at(psi0 + 1e-6)[0] - elbow_at(psi0 - 1e-6)[0]) / 2e-6  # m per rad of psi
    ends, centres = (psi0 - width / 2, psi0 + width / 2), []
    for side, end in zip((-1.0, 1.0), ends, strict=True):
        touch = elbow_at(end)[0]
        low, high = 0.0, 3.0 * apart / speed  # how far beyond the end the ball's centre lies on the elbow's path
        for _ in range(80):
            middle = (low + high) / 2
            if np.linalg.norm(elbow_at(end + side * middle)[0] - touch) < apart:
                low = middle
            else:
                high = middle
        centres.append(elbow_at(end + side * high)[0])
    scene = Scene(("left", "right"), np.stack([primitives.sphere(c, ball_radius) for c in centres]), margin)
    body = body_of([BodyCapsule("elbow", 4, [0, 0, 0], [0, 0, 0], ball)], chain)
    result = collision_free_set(arm, pose, body, scene, label)
    found = [(a, b) for a, b in result.free[0].bounds.tolist() if a <= psi0 <= b]
    assert len(found) == 1
    assert found[0][0] == pytest.approx(ends[0], abs=result.resolution + 1e-9)
    assert found[0][1] == pytest.approx(ends[1], abs=result.resolution + 1e-9)
