"""Certified collision-free arm angles (issue 40, item 4) on S-R-S arms: laws that hold for every pose.

* every arm angle of a reported free arc is collision-free and within the limits, on a dense sample of the circle,
  and where the computation is complete no free stretch of the sample (clear by a millimetre) is left out;
* the free set, its blocked and undecided stretches and the limit stretches cover the circle without overlap;
* the speed bounds the certificate rests on hold: links 3 and 4 turn rigidly about the shoulder-wrist line at unit
  rate, the joint-rate bounds hold over random intervals, and so does the bound of how fast a pair's distance
  changes as a capsule turns about a line past a still shape of each kind;
* an empty scene leaves the limit sets as they are; each removed stretch names the pair that blocks it;
* bad input is refused in words.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import redkin
from redkin.circle import ArcSet, arc_length
from redkin.collision import _decision_kernels, primitives
from redkin.collision._arm_angle_kernels import interval_rates, joint_rates, turning_bounds
from redkin.collision._distance_kernels import OUT, distances
from redkin.collision.arm_angle_free import (
    COLLISION,
    LIMIT,
    UNDECIDED,
    _turning_reach,
    collision_free_arm_angles,
    free_arm_angles_of,
    settled,
)
from redkin.collision.body import BodyCapsule, body_of, posed
from redkin.collision.distances import signed_distance
from redkin.collision.scene import Scene
from redkin.errors import RedkinError
from redkin.srs.coefficients import coefficient_arrays
from redkin.srs.ik import theta_at

#: Points of the circle the laws sample.
SAMPLES = 8001


@pytest.fixture(scope="module")
def iiwa():
    return redkin.arm("kuka-iiwa14")


def _body(chain):
    """A covering of the iiwa14's links, in its DH frames (not a maker's: enough links for every kind of speed)."""
    capsules = [
        BodyCapsule("base", 0, [0, 0, 0.07], [0, 0, 0.15], 0.06),
        BodyCapsule("link 1", 1, [0, 0, -0.2], [0, 0, 0], 0.06),
        BodyCapsule("link 2", 2, [0, 0, 0], [0, 0, 0.05], 0.07),
        BodyCapsule("link 3", 3, [0, 0, -0.2], [0, 0, 0], 0.06),
        BodyCapsule("link 4", 4, [0, 0, 0], [0, 0.2, 0], 0.06),
        BodyCapsule("link 5", 5, [0, 0, -0.2], [0, 0, 0], 0.05),
        BodyCapsule("link 6", 6, [0, 0, 0], [0, 0.05, 0], 0.05),
        BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.1], 0.05),
    ]
    return body_of(capsules, chain)


def _scene(margin: float = 0.01) -> Scene:
    return Scene(("post", "table", "lamp"), np.stack([
        primitives.capsule([0.4, 0.3, 0.0], [0.4, 0.3, 1.2], 0.05),
        primitives.box([0.6, 0.0, -0.06], [1.2, 1.0, 0.1]),
        primitives.sphere([0.2, -0.3, 0.8], 0.1),
    ]), margin)


def _clearance(arm, body, scene, pose, psi, label):
    """The least clearance (distance minus margin) over every checked pair, and whether the joints are within their
    limits, at each arm angle: computed pair by pair from the posed capsules."""
    solutions = arm.ik(pose, psi, branches=label)
    q = solutions.q[:, 0]
    shapes = posed(body, arm.chain.frames(q))
    apart = [signed_distance(shapes[:, :, None], scene.shapes[None, None]).distance.reshape(len(psi), -1),
             signed_distance(shapes[:, body.pairs[:, 0]], shapes[:, body.pairs[:, 1]]).distance]
    return np.concatenate(apart, axis=1).min(axis=1) - scene.margin, solutions.within_limits[:, 0]


def _inside(arcs, psi):
    inside = np.zeros(psi.shape, dtype=bool)
    for (lo, hi), wraps in zip(arcs.bounds, arcs.wraps, strict=True):
        inside |= ((psi >= lo) | (psi <= hi)) if wraps else ((psi >= lo) & (psi <= hi))
    return inside


@settings(max_examples=5)
@given(st.lists(st.floats(-0.8, 0.8), min_size=7, max_size=7))
def test_free_arcs_are_free_and_nothing_clear_is_missed(iiwa, fractions):
    chain = iiwa.chain
    q = np.where(np.asarray(fractions) >= 0, np.asarray(fractions) * chain.upper, -np.asarray(fractions) * chain.lower)
    pose = chain.fk(q)
    body, scene = _body(chain), _scene()
    result = collision_free_arm_angles(iiwa, pose, body, scene)
    psi = np.linspace(-np.pi, np.pi, SAMPLES)
    for b, label in enumerate(result.branches):
        clearance, within = _clearance(iiwa, body, scene, pose, psi, label)
        inside = _inside(result.free[b], psi)
        assert np.all(clearance[inside] >= -1e-12), label
        assert np.all(within[inside]), label
        if not result.complete:  # a degenerate pose (every arm angle singular): sound, not complete
            continue
        clear = within & (clearance > 1e-3)
        ends = np.concatenate([result.free[b].bounds.ravel(), result.limits[b].bounds.ravel()])
        near_end = np.min(np.abs(psi[:, None] - ends[None, :]), axis=1, initial=np.inf) < 1e-5
        assert not np.any(clear & ~inside & ~near_end), label


@settings(max_examples=5)
@given(st.lists(st.floats(-0.8, 0.8), min_size=7, max_size=7))
def test_free_blocked_and_limit_stretches_cover_the_circle(iiwa, fractions):
    chain = iiwa.chain
    q = np.where(np.asarray(fractions) >= 0, np.asarray(fractions) * chain.upper, -np.asarray(fractions) * chain.lower)
    result = collision_free_arm_angles(iiwa, chain.fk(q), _body(chain), _scene())
    for b in range(len(result.branches)):
        free = ArcSet(result.free[b].bounds.tolist())
        removed = ArcSet([[s.start, s.end] for s in result.blocked[b]])
        assert free.union(removed).is_full
        assert free.intersection(removed).length < 1e-9  # they share ends only
        for stretch in result.blocked[b]:
            assert stretch.cause in (COLLISION, LIMIT, UNDECIDED)
            if stretch.cause == UNDECIDED and result.complete:
                assert arc_length(stretch.start, stretch.end) <= result.resolution
        limits = ArcSet(result.limits[b].bounds.tolist())
        assert limits.union(free).isclose(limits)  # free within the limits


def test_the_elbow_turns_rigidly_about_the_shoulder_wrist_line(iiwa):
    chain = iiwa.chain
    rng = np.random.default_rng(3)
    for _ in range(5):
        pose = chain.fk(rng.uniform(chain.lower * 0.7, chain.upper * 0.7))
        psi, step = rng.uniform(-np.pi, np.pi), 1e-6
        q = iiwa.ik(pose, np.array([psi - step, psi + step]), branches="+++").q[:, 0]
        frames = chain.frames(q)
        _, points = chain.joint_axes_in(frames[0])
        wrist = frames[0][6, :3, 3] if chain.convention == "dh" else frames[0][7, :3, 3]
        point = np.array([0.03, -0.05, 0.12, 1.0])  # a point fixed in link 3, and one in link 4
        for frame in (3, 4):
            a, b = (frames[:, frame] @ point)[:, :3]
            speed = np.linalg.norm(b - a) / (2 * step)
            shoulder = points[1]
            axis = (wrist - shoulder) / np.linalg.norm(wrist - shoulder)
            offset = (a + b) / 2 - shoulder
            radius = np.linalg.norm(offset - (offset @ axis) * axis)
            assert speed == pytest.approx(radius, rel=1e-6, abs=1e-9)


def test_each_capsule_reaches_as_far_as_its_ends_from_what_its_frame_turns_about(iiwa):
    """A capsule of frame 1 or 6 from axis 1 or 7, of frame 2 or 5 from the shoulder or wrist centre, of frame 3 or 4
    from the shoulder-wrist line, of frames 0 and 7 nothing: its ends' largest distance, measured here by cross
    products and by the closest points of two axes solved as least squares."""
    chain = iiwa.chain
    rng = np.random.default_rng(5)
    capsules = [BodyCapsule(f"link_{frame}_{k}", frame, rng.uniform(-0.2, 0.2, 3), rng.uniform(-0.2, 0.2, 3), 0.05)
                for frame in range(8) for k in range(2)]
    body = body_of(capsules, chain)
    q = rng.uniform(chain.lower * 0.9, chain.upper * 0.9, (6, 7))
    frames = chain.frames(q)
    shapes = posed(body, frames)
    reach = _turning_reach(chain, body, frames, shapes)

    def meeting(p1, u1, p2, u2):  # the midpoint of the closest points of two lines
        (s, t), *_ = np.linalg.lstsq(np.stack([u1, -u2], axis=1), p2 - p1, rcond=None)
        return (p1 + s * u1 + p2 + t * u2) / 2

    for n in range(len(q)):
        directions, points = chain.joint_axes_in(frames[n])
        shoulder = meeting(points[0], directions[0], points[1], directions[1])
        wrist = meeting(points[5], directions[5], points[6], directions[6])
        along = (wrist - shoulder) / np.linalg.norm(wrist - shoulder)
        for m, capsule in enumerate(capsules):
            ends = [shapes[n, m, 2:5], shapes[n, m, 5:8]]
            if capsule.frame in (1, 6):
                axis = 0 if capsule.frame == 1 else 6
                far = max(np.linalg.norm(np.cross(end - points[axis], directions[axis])) for end in ends)
            elif capsule.frame in (3, 4):
                far = max(np.linalg.norm(np.cross(end - shoulder, along)) for end in ends)
            elif capsule.frame in (2, 5):
                far = max(np.linalg.norm(end - (shoulder if capsule.frame == 2 else wrist)) for end in ends)
            else:
                far = 0.0
            assert reach[n, m] == pytest.approx(far, rel=1e-9, abs=1e-12), (n, capsule.link)


@settings(max_examples=30)
@given(st.lists(st.floats(-0.9, 0.9), min_size=7, max_size=7), st.floats(-np.pi, np.pi), st.floats(1e-4, 1.0),
       st.sampled_from([1.0, -1.0]))
def test_joint_rate_bounds_hold_over_the_interval(iiwa, fractions, middle, half, elbow):
    chain = iiwa.chain
    q = np.asarray(fractions) * np.where(np.asarray(fractions) >= 0, chain.upper, -chain.lower)
    geometry = iiwa.implementation.geometry
    coefficients, _, _ = coefficient_arrays(geometry, chain.fk(q), elbow)
    rates, pieced = np.empty(4), np.empty(4)
    joint_rates(coefficients.entries, middle, half, rates)
    interval_rates(coefficients.entries, middle, half, pieced, np.empty(4))  # the largest bound over its pieces
    psi = np.linspace(middle - half, middle + half, 401)
    branch = redkin.srs.branches.Branch(1, int(elbow), 1)
    theta = np.unwrap(theta_at(coefficients, psi, branch), axis=0)
    slopes = np.abs(np.diff(theta, axis=0)) / np.diff(psi)[:, None]
    observed = slopes.max(axis=0)[[0, 1, 5, 6]]
    assert np.all(observed <= rates * (1 + 1e-6) + 1e-9)
    assert np.all(observed <= pieced * (1 + 1e-6) + 1e-9) and np.all(pieced <= rates * (1 + 1e-12))


def _still_shape(kind, rng):
    if kind == "sphere":
        return primitives.sphere(rng.uniform(-0.6, 0.6, 3), rng.uniform(0.0, 0.2))
    if kind == "capsule":
        return primitives.capsule(rng.uniform(-0.6, 0.6, 3), rng.uniform(-0.6, 0.6, 3), rng.uniform(0.0, 0.1))
    if kind == "box":
        return primitives.box(rng.uniform(-0.6, 0.6, 3), rng.uniform(0.05, 0.6, 3),
                              Rotation.random(random_state=rng).as_matrix())
    normal = Rotation.random(random_state=rng).as_matrix()[:, 2]
    return primitives.plane(-rng.uniform(0.3, 0.8) * normal, normal)


@settings(max_examples=40)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["sphere", "capsule", "box", "plane"]), st.floats(1e-4, 1.5),
       st.booleans())
def test_the_turning_bound_holds_as_a_capsule_turns_about_a_line(seed, kind, half, flip):
    """:func:`turning_bounds`, the bounds of a pair's distance as a capsule of links 3-4 turns about the shoulder-wrist
    line past a still shape, hold at 401 angles across the interval, whichever of the two the distance was measured
    from: ``|d(delta) - d(0)| <= v |delta|``; and at a margin drawn between the least and the largest distance there,
    the clearance keeps its sign within each side's extent (one-sided quadratic bounds, below and above the middle)
    wherever the samples reach: the turn is positive about the line's direction as delta grows."""
    rng = np.random.default_rng(seed)
    axis = Rotation.random(random_state=rng).as_matrix()[:, 0]
    line = np.concatenate([rng.uniform(-0.3, 0.3, 3), axis])
    ends = rng.uniform(-0.7, 0.7, (2, 3))
    still = _still_shape(kind, rng)
    radius = rng.uniform(0.0, 0.08)
    delta = np.linspace(-half, half, 401)
    turned = Rotation.from_rotvec(delta[:, None] * axis).apply
    rows = np.stack([primitives.capsule(turned(ends[0] - line[:3])[n] + line[:3],
                                        turned(ends[1] - line[:3])[n] + line[:3], radius) for n in range(len(delta))])
    apart = signed_distance(rows, still[None]).distance
    middle = rows[len(delta) // 2]
    witness = np.empty((1, OUT))
    pair = (still[None], middle[None]) if flip else (middle[None], still[None])
    distances(0, 1, *pair, witness)
    margin = rng.uniform(apart.min(), apart.max())
    clearance = apart[len(delta) // 2] - margin
    speed, below, above = turning_bounds(middle, witness[0], flip, still, line, half, clearance)
    if apart[len(delta) // 2] + radius + still[1] <= 1e-6:
        return  # the cores touch or overlap: no direction of their own (inf, the first-order bound stays)
    assert np.isfinite(speed) and (below >= 0.0) == (above >= 0.0) == (clearance > 0.0)
    change = np.abs(apart - apart[len(delta) // 2])
    assert np.all(change <= speed * np.abs(delta) * (1 + 1e-9) + 1e-12)
    within = np.where(delta < 0.0, -delta <= abs(below) * (1 - 1e-9), delta <= abs(above) * (1 - 1e-9))
    assert not np.any((apart[within] - margin) * np.sign(clearance) < -1e-12), (below, above, clearance)


def test_an_empty_scene_keeps_the_limit_sets(iiwa):
    chain = iiwa.chain
    pose = chain.fk(np.array([0.2, 0.5, -0.3, -1.1, 0.6, 0.9, -0.4]))
    empty = body_of([], chain)
    result = collision_free_arm_angles(iiwa, pose, empty, Scene((), np.empty((0, primitives.WIDTH))))
    for b in range(8):
        assert ArcSet(result.free[b].bounds.tolist()).isclose(ArcSet(result.limits[b].bounds.tolist()))
        assert all(stretch.cause == LIMIT for stretch in result.blocked[b])
    assert result.evaluations > 0


def test_an_obstacle_on_the_elbow_circle_is_named(iiwa):
    chain = iiwa.chain
    q = np.array([0.1, 0.7, 0.0, -1.3, 0.0, 0.6, 0.0])
    pose = chain.fk(q)
    elbow = chain.frames(q)[3, :3, 3]
    ball = Scene(("ball",), primitives.sphere(elbow, 0.05)[None], 0.0)
    body = body_of([BodyCapsule("forearm", 4, [0, 0, 0], [0, 0, 0.01], 0.05)], chain)
    label = str(iiwa.branch_of(q))
    psi = float(iiwa.parameter_of(q))
    result = collision_free_arm_angles(iiwa, pose, body, ball, label)
    assert not _inside(result.free[0], np.array([psi]))[0]
    blocking = [s for s in result.blocked[0] if _inside(type(result.free[0])(np.array([[s.start, s.end]]),
                                                                              np.array([s.start > s.end])),
                                                          np.array([psi]))[0]]
    assert [(s.cause, s.link, s.against) for s in blocking] == [(COLLISION, "forearm", "ball")]


def test_bad_input_is_refused_in_words(iiwa):
    chain = iiwa.chain
    pose = chain.fk(np.zeros(7) + 0.3)
    body, scene = _body(chain), _scene()
    with pytest.raises(RedkinError, match="resolution"):
        collision_free_arm_angles(iiwa, pose, body, scene, resolution=0.0)
    with pytest.raises(RedkinError, match="one 4x4"):
        collision_free_arm_angles(iiwa, np.stack([pose, pose]), body, scene)
    with pytest.raises(RedkinError, match="Franka"):
        franka = redkin.arm("franka-panda")
        collision_free_arm_angles(franka, franka.fk(np.zeros(7) + 0.3), body_of([], franka.chain), scene)
    with pytest.raises(ValueError):
        collision_free_arm_angles(iiwa, pose, body, scene, "+?+")
    for budget in (0, -1, 2.5, True):
        with pytest.raises(RedkinError, match="budget must be an integer >= 1"):
            collision_free_arm_angles(iiwa, pose, body, scene, budget=budget)


@pytest.mark.parametrize("name", ["kuka-iiwa14", "franka-panda", "kinova-gen3"])
def test_a_pose_out_of_reach_is_refused_with_its_distance_by_the_one_pose_forms(name):
    """The one-pose sets refuse a pose their class proves out of reach, in one line with the distance and the range
    (as the docstrings say and ``Arm.analyse`` does); a batch answers it with no free set, each branch's whole circle
    removed as "no solution", beside the other poses' sets."""
    from redkin.collision import builtin_body, collision_free_set, free_sets_of, scene_of
    from redkin.errors import UnreachablePoseError

    arm = redkin.arm(name)
    body, scene = builtin_body(name, arm.chain), scene_of({"margin": 0.01, "obstacles": []})
    far = np.eye(4)
    far[:3, 3] = (3.0, 0.0, 0.5)
    with pytest.raises(UnreachablePoseError, match=r"unreachable pose: .* is \d+(\.\d+)? m, outside \["):
        collision_free_set(arm, far, body, scene)
    if name == "kuka-iiwa14":  # the batch form, on a class that decides it quickly
        near = arm.chain.fk(np.array([0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1]))
        sets = free_sets_of(arm, np.stack([far, near]), body, scene)
        assert all(not len(arcs.bounds) for arcs in sets[0].free)
        assert all([tuple(s) for s in stretches] == [(-np.pi, np.pi, LIMIT, "", "no solution")]
                   for stretches in sets[0].blocked)
        assert any(len(arcs.bounds) for arcs in sets[1].free)


def test_the_readme_example_runs(capsys):
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("### Obstacles: the collision-free arm angles"):]
    start = section.index("```python\n") + len("```python\n")
    code = section[start:section.index("```\n", start)]
    exec(compile(code, "README.md", "exec"), {})
    printed = capsys.readouterr().out
    assert "Stretch(" in printed and "[[" in printed


def test_the_arm_answers_the_free_sets_in_its_own_shapes(iiwa):
    chain = iiwa.chain
    rng = np.random.default_rng(11)
    poses = chain.fk(rng.uniform(chain.lower * 0.7, chain.upper * 0.7, (2, 3, 7)))
    body, scene = _body(chain), _scene()
    sets = iiwa.feasible(poses, ["+++", "-+-"], body=body, scene=scene)
    assert sets.shape == (2, 3) and sets.branches == ("+++", "-+-") and not sets.exact
    for index in np.ndindex(2, 3):
        direct = collision_free_arm_angles(iiwa, poses[index], body, scene, ["+++", "-+-"])
        for b, label in enumerate(("+++", "-+-")):
            assert ArcSet(sets.arcs(label, index).bounds.tolist()).isclose(
                ArcSet(direct.free[b].bounds.tolist()), 1e-12)
    with pytest.raises(RedkinError, match="both"):
        iiwa.feasible(poses, body=body)


def test_poses_decided_together_equal_each_pose_alone(iiwa):
    """Batched equals looped: each pose's intervals are halved on their own, whatever the others in the batch."""
    chain = iiwa.chain
    rng = np.random.default_rng(5)
    q = rng.uniform(chain.lower * 0.8, chain.upper * 0.8, (6, 7))
    q[1] = [0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1]
    poses = chain.fk(q)
    body, scene = _body(chain), _scene()
    together = free_arm_angles_of(iiwa, poses, body, scene, ["+++", "--+", "-+-"])
    assert any(any(len(arcs.bounds) for arcs in free.free) for free in together)
    for pose, free in zip(poses, together, strict=True):
        alone = collision_free_arm_angles(iiwa, pose, body, scene, ["+++", "--+", "-+-"])
        assert free.branches == alone.branches and free.blocked == alone.blocked
        assert (free.evaluations, free.complete) == (alone.evaluations, alone.complete)
        for mine, theirs in zip(free.free + free.limits, alone.free + alone.limits, strict=True):
            assert np.array_equal(mine.bounds, theirs.bounds) and np.array_equal(mine.wraps, theirs.wraps)
    with pytest.raises(RedkinError, match=r"\(P, 4, 4\)"):
        free_arm_angles_of(iiwa, poses[0], body, scene)


@pytest.mark.parametrize("width", [1e-4, 1e-5])
def test_a_narrow_gap_between_two_obstacles_on_the_elbow_circle_is_found(iiwa, width):
    """Two balls on the circle the elbow turns on leave free only the arm angles between them, an arc ``width`` wide
    whose ends are known in closed form: the elbow's distance to a ball at arm angle ``psi_k`` is the chord
    ``2 rho sin(|psi - psi_k| / 2)``, ``rho`` the elbow's distance from the shoulder-wrist line."""
    chain = iiwa.chain
    q = np.array([0.2, 0.7, -0.3, -1.4, 0.3, 0.6, 0.1])
    pose, label = chain.fk(q), str(iiwa.branch_of(q))
    psi0 = float(iiwa.parameter_of(q))

    def elbow_at(psi):
        return chain.frames(iiwa.ik(pose, np.atleast_1d(psi), branches=label).q[:, 0])[:, 3, :3, 3]

    frames = chain.frames(q)
    shoulder, wrist = frames[1, :3, 3], frames[5, :3, 3]
    axis = (wrist - shoulder) / np.linalg.norm(wrist - shoulder)
    offset = elbow_at(psi0)[0] - shoulder
    rho = np.linalg.norm(offset - (offset @ axis) * axis)
    ball, margin, ball_radius = 0.03, 0.01, 0.04
    reach = 2.0 * np.arcsin((ball + ball_radius + margin) / (2.0 * rho))
    first, second = psi0 - reach - width / 2, psi0 + reach + width / 2
    centres = elbow_at(np.array([first, second]))
    scene = Scene(("left", "right"), np.stack([primitives.sphere(c, ball_radius) for c in centres]), margin)
    body = body_of([BodyCapsule("elbow", 3, [0, 0, 0], [0, 0, 0], ball)], chain)
    result = collision_free_arm_angles(iiwa, pose, body, scene, label)
    lo, hi = psi0 - width / 2, psi0 + width / 2
    found = [(a, b) for a, b in result.free[0].bounds.tolist() if a <= psi0 <= b]
    assert len(found) == 1
    assert found[0][0] == pytest.approx(lo, abs=result.resolution)
    assert found[0][1] == pytest.approx(hi, abs=result.resolution)


@settings(max_examples=60)
@given(st.integers(1, 6), st.integers(1, 5), st.integers(0, 2**32 - 1), st.sampled_from([0.0, 0.05]))
def test_an_interval_is_decided_by_its_own_clearances(rows, pairs, seed, finest):
    """Each interval's decision (:func:`settled`, the compiled step of every level) follows from its clearances and
    speed bounds: a pair left open has ``c - v h <= 0``; free where none is; blocked only by a pair with
    ``c + v h < 0`` (the pair it names); undecided only when no wider than ``finest``.  Where an open interval is
    cut around its middle, every open pair stays on its side of the margin over the stretch by its speed bound:
    ``c - v r >= 0`` for all where it is free, ``c + v r <= 0`` for the cause where it is blocked; the stretch never
    leaves the interval, and pairs already proved clear do not matter."""
    rng = np.random.default_rng(seed)
    clearance = rng.uniform(-0.2, 0.2, (rows, pairs))
    speed = rng.choice([0.0, 0.5, 3.0, np.inf], (rows, pairs)) * rng.uniform(0.5, 1.5, (rows, pairs))
    given_active = rng.random((rows, pairs)) < 0.7
    clearance[~given_active] = np.inf  # as the measure gives them
    half = rng.uniform(1e-6, 0.2, rows)
    active = given_active.copy()
    kind, pair, radius, up, carved, cause = settled(half, clearance, speed, active, finest, True)
    assert np.array_equal(radius, up)  # a speed bound proves as far on both sides
    with np.errstate(invalid="ignore"):
        low = np.where(given_active, clearance - speed * half[:, None], np.inf)
        high = np.where(given_active, clearance + speed * half[:, None], np.inf)
    assert np.array_equal(active, given_active & ~(low > 0.0))
    assert np.array_equal(kind == _decision_kernels.FREE, ~active.any(axis=1))
    blocked = kind == _decision_kernels.BLOCKED
    assert np.all(high[blocked, pair[blocked]] < 0.0) and np.all(active[blocked, pair[blocked]])
    assert np.all(np.any(high < 0.0, axis=1)[active.any(axis=1)] == blocked[active.any(axis=1)])
    assert np.all(2.0 * half[kind == _decision_kernels.UNDECIDED] <= finest)
    opened = kind == _decision_kernels.OPEN
    assert np.all(2.0 * half[opened] > finest)
    assert np.all((radius >= 0.0) & (radius <= half)) and np.all(radius[~opened] == 0.0)
    with np.errstate(invalid="ignore"):
        reach = np.where(active, clearance - speed * radius[:, None], np.inf)
    for row in np.flatnonzero(radius > 0.0):
        if carved[row] == _decision_kernels.FREE:
            assert np.all(reach[row] >= 0.0)
        else:
            assert active[row, cause[row]] and clearance[row, cause[row]] + speed[row, cause[row]] * radius[row] <= 0.0
    clear = np.all(~active | ((clearance > 0.0) & np.isfinite(speed)), axis=1) & opened
    assert np.all(radius[clear] > 0.0) and np.all(carved[clear] == _decision_kernels.FREE)


@settings(max_examples=80)
@given(st.integers(1, 5), st.integers(0, 2**32 - 1))
def test_a_stretch_is_carved_as_far_as_each_side_is_proved(pairs, seed):
    """Where the measure proves each clearance's sign farther on one side of the middle than on the other (the
    turning bounds), the stretch carved around it reaches, on each side, no farther than every open pair's proof
    there where it is free, and than its cause's where it is blocked; it reaches the interval's end where every
    proof passes it (no sliver left for an evaluation of its own), and is empty where a pair is exactly at the
    margin with nothing proved."""
    rng = np.random.default_rng(seed)
    half = rng.uniform(1e-6, 0.5)
    clearance = rng.uniform(-0.2, 0.2, pairs) * rng.choice([0.0, 1.0], pairs, p=[0.1, 0.9])
    speed = rng.uniform(1.0, 5.0, pairs)  # open: |c| <= v h for every pair
    clearance = np.clip(clearance, -speed * half * 0.999, speed * half * 0.999)
    sign = np.sign(clearance)
    below = sign * rng.uniform(0.0, 2.0, pairs) * half
    above = sign * rng.uniform(0.0, 2.0, pairs) * half
    active = np.ones(pairs, dtype=bool)
    kind, _, down, up, carved, cause = _decision_kernels.decided_one(half, clearance, speed, below, above, active,
                                                                    0.0, True)
    assert kind == _decision_kernels.OPEN and 0.0 <= down <= half and 0.0 <= up <= half
    if np.all(clearance > 0.0):
        assert carved == _decision_kernels.FREE
        assert down <= below.min() and up <= above.min()
        assert (down == half) == (below.min() * _decision_kernels.CARVE_SHRINK >= half)
        assert (up == half) == (above.min() * _decision_kernels.CARVE_SHRINK >= half)
    elif np.any(clearance < 0.0):
        assert carved == _decision_kernels.BLOCKED and clearance[cause] < 0.0
        assert down <= -below[cause] and up <= -above[cause]
        assert below[cause] + above[cause] == (below + above)[clearance < 0.0].min()
    else:
        assert down == up == 0.0


@settings(max_examples=200)
@given(st.floats(0.0, 1e3, allow_subnormal=False), st.floats(-1e3, 1e3, allow_subnormal=False),
       st.one_of(st.just(0.0), st.floats(1e-12, 1e3)))
def test_the_quadratic_root_is_where_the_bound_first_reaches_the_clearance(a, b, k):
    """``_quadratic_root(a, b, k)``: ``a t^2 + b t`` stays below ``k`` before the root and reaches it there (a slope of
    either sign); ``inf`` only where it never does; 0 for ``k = 0`` and for a bound that is not finite."""
    from redkin.collision._arm_angle_kernels import _quadratic_root

    root = _quadratic_root(a, b, k)
    if k == 0.0:
        assert root == 0.0
    elif root == np.inf:
        assert a == 0.0 and b <= 0.0
    else:
        size = a * root * root + abs(b) * root + k  # the terms' size: their sum cancels where b < 0
        assert abs(a * root * root + b * root - k) <= 1e-9 * size
        t = np.linspace(0.0, root, 50)[:-1]
        assert np.all(a * t * t + b * t - k < 1e-9 * size)
    assert _quadratic_root(np.inf, b, 1.0) == _quadratic_root(1.0, np.nan, 1.0) == 0.0


def test_the_linear_extent_divides_as_numpy_and_run_as_python_warns_of_nothing():
    """``linear_extent`` is numpy's ``clearance / speed`` (speed >= 0) with what it makes NaN read as 0, compiled
    and run as Python alike, and as Python it warns of nothing (a Franka arm's sets in a cell, run as Python on a
    fresh install, printed "invalid value encountered in scalar divide" from an ``inf / inf``)."""
    import warnings

    clearances = [0.0, -0.0, 1.5, -2.0, 1e-300, np.inf, -np.inf, np.nan]
    for clearance in clearances:
        for speed in [0.0, 1.5, 1e-300, np.inf, np.nan]:  # a bound of a rate: not negative
            with np.errstate(divide="ignore", invalid="ignore"):
                expected = np.divide(np.float64(clearance), np.float64(speed))
            expected = 0.0 if np.isnan(expected) else float(expected)
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                as_python = _decision_kernels.linear_extent.py_func(np.float64(clearance), np.float64(speed))
            assert as_python == expected and _decision_kernels.linear_extent(clearance, speed) == expected


@pytest.mark.parametrize(("a", "b", "k"), [(0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (2.0, 0.0, 0.5), (0.0, 3.0, 0.3),
                                           (1e-12, 0.4, 1e-9), (5.0, 1e-9, 2.0)])
def test_the_quadratic_root_reaches_k_and_keeps_no_sign_at_zero(a, b, k):
    """``_quadratic_root``, the extent of a clearance under a bound ``a t^2 + b t``: the bound reaches ``k`` at the
    root (``inf`` where it never rises); a clearance of exactly 0 has extent 0, so that it carves nothing (it was
    ``inf``, which carved a whole interval as colliding)."""
    from redkin.collision._arm_angle_kernels import _quadratic_root
    root = _quadratic_root(a, b, k)
    if k == 0.0:
        assert root == 0.0
    elif a == 0.0 and b == 0.0:
        assert root == np.inf
    else:
        assert a * root * root + b * root == pytest.approx(k, rel=1e-12)


def test_a_stretch_around_the_whole_circle_is_written_whole():
    """On an S-R-S arm whose joints are not limited every branch's limit set is the whole circle; with a ball at the
    hand the cell takes all of it: one stretch per branch, ``(-pi, pi)``, named by the pair (its ends wrapped were
    one point, ``(-pi, -pi)``, which the picture drew as nothing and the JSON as an empty arc); the path's failure
    and the removed stretches say the same."""
    import dataclasses

    from redkin.paths import removed_along_path

    chain = dataclasses.replace(redkin.get_robot("kuka-iiwa14"), lower=np.full(7, -np.inf),
                                upper=np.full(7, np.inf))
    q = np.array([0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1])
    body = body_of([BodyCapsule("hand", 7, (0, 0, 0), (0, 0, 0.02), 0.03)], chain)
    scene = Scene(("ball",), primitives.sphere(chain.frames(q)[7, :3, 3], 0.03)[None], 0.01)
    sets = collision_free_arm_angles(redkin.arm(chain), chain.fk(q), body, scene)
    for limits, free, blocked in zip(sets.limits, sets.free, sets.blocked, strict=True):
        assert ArcSet(limits.bounds.tolist()).is_full and not len(free.bounds)
        assert [tuple(stretch) for stretch in blocked] == [(-np.pi, np.pi, COLLISION, "hand", "ball")]
    removed = removed_along_path(chain, chain.fk(q)[None], body, scene)
    assert all(row == [(-np.pi, np.pi, "hand meets ball")] for row in removed[0])


def test_a_branch_without_a_feasible_arm_angle_is_named_at_the_middle_of_the_circle():
    """A branch with no arm angle inside the limits has one removed stretch, the whole circle, named (as every
    stretch) by the joints out of range at its middle, arm angle 0, not at its start -pi (the middle of ``(-pi,
    pi)`` was read as ``-pi + ((pi - -pi) mod 2 pi) / 2``). Joint 4 is out everywhere here, joint 3 only away from
    0."""
    import dataclasses

    iiwa = redkin.get_robot("kuka-iiwa14")
    q = np.array([0.3, 0.6, 0.1, -1.2, 0.2, 0.8, 0.1])
    pose = iiwa.fk(q)
    at = {psi: redkin.arm(iiwa).ik(pose, psi).q for psi in (0.0, -np.pi)}  # (8, 7): the eight branches' rows
    lower, upper = iiwa.lower.copy(), iiwa.upper.copy()
    lower[2], upper[2] = at[0.0][0, 2] - 0.05, at[0.0][0, 2] + 0.05  # branch 0's joint 3 at arm angle 0, +-0.05
    lower[3], upper[3] = 0.5, 0.6  # joint 4 is -1.2 or 1.2 at every arm angle of this pose
    chain = dataclasses.replace(iiwa, lower=lower, upper=upper)
    assert not lower[2] <= at[-np.pi][0, 2] <= upper[2]  # so the name at -pi differs
    body = body_of([BodyCapsule("hand", 7, (0, 0, 0), (0, 0, 0.02), 0.03)], chain)
    scene = Scene(("ball",), primitives.sphere(np.array([5.0, 0.0, 0.0]), 0.1)[None], 0.01)
    sets = collision_free_arm_angles(redkin.arm(chain), pose, body, scene)
    assert not len(sets.limits[0].bounds)
    assert [tuple(stretch) for stretch in sets.blocked[0]] == [(-np.pi, np.pi, LIMIT, "", "joint 4")]
