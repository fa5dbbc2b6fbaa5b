"""Steps between configurations (issue 40): a certified step keeps the margin at every point of the linear
interpolation (sampled densely here), its proved least clearance is no more than the least sampled, a blocked step
has a configuration that does not keep it, and the motion bound the proof rests on holds."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.collision import BodyCapsule, Scene, body_of, clearance, posed, primitives
from redkin.collision.steps import _reach, step_clearance
from redkin.errors import RedkinError


@pytest.fixture(scope="module")
def cell():
    chain = redkin.get_robot("kuka-iiwa14")
    body = body_of([BodyCapsule("link 2", 2, [0, 0, 0], [0, 0, 0.05], 0.07),
                    BodyCapsule("upper arm", 3, [0, 0, -0.2], [0, 0, 0], 0.06),
                    BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.06),
                    BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.1], 0.05)], chain)
    scene = Scene(("post", "table", "lamp"), np.stack([
        primitives.capsule([0.4, 0.3, 0.0], [0.4, 0.3, 1.2], 0.05), primitives.box([0.6, 0.0, -0.06], [1.2, 1, 0.1]),
        primitives.sphere([0.2, -0.3, 0.8], 0.1)]), 0.01)
    return chain, body, scene


def _sampled(chain, body, scene, qa, qb, count=2049):
    s = np.linspace(0.0, 1.0, count)[:, None]
    return clearance(chain, body, scene, qa + s * (qb - qa)).distance


@settings(max_examples=25)
@given(st.lists(st.floats(-0.9, 0.9), min_size=7, max_size=7), st.lists(st.floats(-0.4, 0.4), min_size=7, max_size=7))
def test_certified_steps_are_clear_and_blocked_ones_are_not(cell, start, move):
    chain, body, scene = cell
    qa = np.asarray(start) * chain.upper
    qb = qa + np.asarray(move)
    result = step_clearance(chain, body, scene, np.stack([qa, qb]))
    sampled = _sampled(chain, body, scene, qa, qb)
    if result.certified[0]:
        assert sampled.min() >= scene.margin - 1e-12
        assert result.least[0] <= sampled.min() + 1e-12
    if result.blocked[0]:
        assert result.least[0] < scene.margin
    assert not (result.certified[0] and result.blocked[0])


@settings(max_examples=25)
@given(st.lists(st.floats(-2.0, 2.0), min_size=7, max_size=7), st.lists(st.floats(-0.5, 0.5), min_size=7, max_size=7))
def test_no_point_moves_farther_than_the_bound(cell, start, move):
    chain, body, _ = cell
    qa, dq = np.asarray(start), np.asarray(move)
    s = np.linspace(0.0, 1.0, 257)[:, None]
    shapes = posed(body, chain.frames(qa + s * dq))
    moved = np.maximum(np.linalg.norm(shapes[:, :, 2:5] - shapes[0, :, 2:5], axis=-1),
                       np.linalg.norm(shapes[:, :, 5:8] - shapes[0, :, 5:8], axis=-1)).max(axis=0)
    assert np.all(moved <= np.abs(dq) @ _reach(chain, body) + 1e-12)


def test_a_step_through_an_obstacle_is_blocked(cell):
    chain, body, _ = cell
    qa, qb = np.array([-1.2, 0.5, 0.0, -1.0, 0.0, 0.5, 0.0]), np.array([1.2, 0.5, 0.0, -1.0, 0.0, 0.5, 0.0])
    middle = chain.frames((qa + qb) / 2)[4, :3, 3]  # the elbow halfway: a ball there, clear of both ends
    ball = Scene(("ball",), primitives.sphere(middle, 0.02)[None], 0.0)
    assert np.all(clearance(chain, body, ball, np.stack([qa, qb])).distance > 0.0)
    result = step_clearance(chain, body, ball, np.stack([qa, qb]))
    assert result.blocked.tolist() == [True] and not result.certified[0]
    fine = step_clearance(chain, body, ball, np.stack([qa, qa, qa]))
    assert fine.certified.tolist() == [True, True]
    with pytest.raises(RedkinError):
        step_clearance(chain, body, ball, qa)
