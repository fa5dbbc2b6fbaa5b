"""The clearance of a body at joint values (issue 40): the least signed distance over every checked pair, each pair
measured here on its own with the public signed distance; batched equals looped; nothing to check is ``inf``; each
pair's gradient over the joints equals central differences of its distance."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.collision import BodyCapsule, Scene, body_of, clearance, posed, primitives, signed_distance
from redkin.collision import _clearance_kernels as clearance_kernels
from redkin.collision.clearance import checked_pairs, clearance_inputs
from redkin.errors import RedkinError


@pytest.fixture(scope="module")
def cell():
    chain = redkin.get_robot("franka-panda")  # any class: clearance needs only the chain's frames
    body = body_of([BodyCapsule("link 1", 1, [0, 0, -0.1], [0, 0, 0], 0.07),
                    BodyCapsule("link 3", 3, [0, 0, -0.1], [0, 0, 0.05], 0.06),
                    BodyCapsule("link 5", 5, [0, 0, -0.2], [0, 0, 0], 0.05),
                    BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.1], 0.05)], chain)
    scene = Scene(("shelf", "post", "ball", "floor"), np.stack([
        primitives.box([0.5, 0.0, 0.4], [0.3, 0.6, 0.02]), primitives.capsule([0.3, -0.4, 0], [0.3, -0.4, 1], 0.04),
        primitives.sphere([0.0, 0.4, 0.6], 0.1), primitives.plane([0, 0, -0.05], [0, 0, 1])]), 0.01)
    return chain, body, scene


@settings(max_examples=40)
@given(st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7))
def test_the_least_pair_is_the_clearance(cell, fractions):
    chain, body, scene = cell
    q = chain.lower + np.asarray(fractions) * (chain.upper - chain.lower)
    result = clearance(chain, body, scene, q)
    shapes = posed(body, chain.frames(q))
    measured = {}
    for i, link in enumerate(body.link):
        for o, name in enumerate(scene.names):
            measured[(link, name)] = float(signed_distance(shapes[i], scene.shapes[o]).distance)
    for i, j in body.pairs.tolist():
        measured[(body.link[i], body.link[j])] = float(signed_distance(shapes[i], shapes[j]).distance)
    least = min(measured.values())
    assert float(result.distance) == least
    assert measured[(result.link.item(), result.against.item())] == least


def test_batched_equals_looped_and_empty_is_infinite(cell):
    chain, body, scene = cell
    q = np.random.default_rng(5).uniform(chain.lower, chain.upper, (3, 4, 7))
    batch = clearance(chain, body, scene, q)
    assert batch.distance.shape == (3, 4)
    for index in np.ndindex(3, 4):
        one = clearance(chain, body, scene, q[index])
        assert one.distance == batch.distance[index] and one.link.item() == batch.link[index]
    nothing = clearance(chain, body_of([], chain), Scene((), np.empty((0, primitives.WIDTH))), q)
    assert np.all(nothing.distance == np.inf) and np.all(nothing.link == "")
    with pytest.raises(RedkinError):
        clearance(chain, body, scene, np.zeros(6))


def test_a_scene_without_obstacles_still_checks_the_body_against_itself(cell):
    """An empty scene (only the arm's own links to keep apart) measures the self pairs; it once indexed the empty
    obstacle array and raised."""
    chain, body, _ = cell
    empty = Scene((), np.empty((0, primitives.WIDTH)), 0.0)
    q = np.random.default_rng(9).uniform(chain.lower, chain.upper, (5, 7))
    result = clearance(chain, body, empty, q)
    shapes = posed(body, chain.frames(q))
    for k in range(len(q)):
        measured = {(body.link[i], body.link[j]): float(signed_distance(shapes[k, i], shapes[k, j]).distance)
                    for i, j in body.pairs.tolist()}
        assert float(result.distance[k]) == min(measured.values())
        assert measured[(result.link[k], result.against[k])] == min(measured.values())


def test_the_base_is_kept_apart_from_the_arm_but_not_checked_against_obstacles(cell):
    """A capsule of frame 0 never moves: against the obstacles it would decide every configuration alike (a base
    standing on the table would block them all), so it is not checked there, and base_contacts names the contact;
    against the moving links it is checked."""
    from redkin.collision.clearance import base_contacts, checked_pairs

    chain, body, scene = cell
    base = BodyCapsule("base", 0, [0, 0, -0.2], [0, 0, 0.1], 0.12)
    with_base = body_of([base, *(BodyCapsule(link, int(frame), a, b, float(r)) for link, frame, a, b, r in
                                 zip(body.link, body.frame, body.a, body.b, body.radius))], chain)
    names = checked_pairs(with_base, scene).names
    assert not any(link == "base" and other in scene.names for link, other in names)
    assert any(link == "base" and other == "link 3" for link, other in names)  # two joints apart: checked
    q = np.random.default_rng(2).uniform(chain.lower, chain.upper, (50, 7))
    plain = clearance(chain, body, scene, q)
    found = clearance(chain, with_base, scene, q)
    assert np.all(found.distance <= plain.distance)  # only the base's self pairs are added
    contacts = base_contacts(chain, with_base, scene)
    assert [(link, obstacle) for link, obstacle, _ in contacts] == [("base", "floor")]  # 0.2 m below the base
    assert contacts[0][2] == pytest.approx(-(0.2 + 0.12 - 0.05), abs=1e-12)  # the floor's plane at z = -0.05


@settings(max_examples=40)
@given(st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7))
def test_each_pairs_gradient_is_its_distances_derivative(cell, fractions):
    """``pair_gradient`` (from the witness points and the normal) against central differences of the pair's own
    distance, on every checked pair that is apart (obstacles of each kind and the body's self pairs)."""
    chain, body, scene = cell
    q = chain.lower + np.asarray(fractions) * (chain.upper - chain.lower)
    inputs = clearance_inputs(body, scene, checked_pairs(body, scene))
    kinematics = (chain._links, chain._ends, chain._standard)
    cell_arrays = (*inputs.body, inputs.obstacles, *inputs.pairs)
    work = clearance_kernels.scratch(chain._links, inputs.body[0], inputs.pairs[0], inputs.obstacles)
    gradient, jac, scratch_gradient = np.zeros(7), np.zeros((6, 7)), np.zeros(7)
    step = 1e-6
    for k in range(len(inputs.pairs[0])):
        distance = clearance_kernels.pair_gradient(q, *kinematics, *cell_arrays, k, work, jac, gradient)
        if distance < 1e-3:
            continue  # touching or penetrating: a depth may have kinks
        differences = np.empty(7)
        for j in range(7):
            ahead, behind = q.copy(), q.copy()
            ahead[j] += step
            behind[j] -= step
            differences[j] = (clearance_kernels.pair_gradient(ahead, *kinematics, *cell_arrays, k, work, jac,
                                                              scratch_gradient)
                              - clearance_kernels.pair_gradient(behind, *kinematics, *cell_arrays, k, work, jac,
                                                                scratch_gradient)) / (2 * step)
        assert np.abs(gradient - differences).max() < 1e-6, k
