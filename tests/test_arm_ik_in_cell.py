"""``Arm.ik(..., body=, scene=)`` (issue 40, item 5): every row marked with its clearance, its closest pair and
whether it keeps the margin, on the iiwa14 (arm angle) and the Panda (q7) with their built-in bodies.

Laws: at values of the parameter the marks are the pair-by-pair clearance of the rows returned (``nan`` and ``""``
where a row does not exist) and ``collision_free`` is ``exists`` and at least the margin; the rows are those without
a cell; at ``"optimal"`` each row sits at :meth:`redkin.Arm.optimal`'s value in the cell and keeps the margin; without
a cell the marks are ``None``.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.collision import builtin_body, clearance, scene_of

CELL = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.3, 0.3, 0.0], "b": [0.3, 0.3, 1.0], "radius": 0.04},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.35, 0.8], "radius": 0.1}]}
ROBOTS = ["kuka-iiwa14", "franka-panda"]


@pytest.fixture(scope="module", params=ROBOTS)
def setup(request):
    arm = redkin.arm(request.param)
    return arm, builtin_body(request.param, arm.chain), scene_of(CELL)


@settings(max_examples=10, deadline=None)
@given(fraction=st.lists(st.floats(0.05, 0.95), min_size=7, max_size=7), t=st.floats(-2.8, 2.8))
def test_each_row_is_marked_with_its_measured_clearance(setup, fraction, t):
    arm, body, scene = setup
    chain = arm.chain
    low, high = np.maximum(chain.lower, -np.pi), np.minimum(chain.upper, np.pi)
    pose = arm.fk(low + np.asarray(fraction) * (high - low))
    poses = np.stack([pose, pose])
    values = np.array([t, 0.5 * t])
    marked, plain = arm.ik(poses, values, body=body, scene=scene), arm.ik(poses, values)
    assert plain.clearance is None and plain.collision_free is None
    np.testing.assert_array_equal(marked.q, plain.q)
    np.testing.assert_array_equal(marked.exists, plain.exists)
    measured = clearance(chain, body, scene, np.where(plain.exists[..., None], plain.q, 0.0))
    there = plain.exists
    np.testing.assert_array_equal(marked.clearance.distance[there], measured.distance[there])
    np.testing.assert_array_equal(marked.clearance.link[there], measured.link[there])
    np.testing.assert_array_equal(marked.clearance.against[there], measured.against[there])
    assert np.isnan(marked.clearance.distance[~there]).all() and (marked.clearance.link[~there] == "").all()
    np.testing.assert_array_equal(marked.collision_free, there & (measured.distance >= scene.margin))


def test_the_optimal_rows_in_a_cell_keep_the_margin(setup):
    arm, body, scene = setup
    found = 0
    for q in ([0.4, 0.5, -0.3, -1.6, 0.5, 1.4, -0.6], [0.0, -0.3, 0.0, -1.9, 0.0, 2.0, 0.785]):  # inside the limits
        pose = arm.fk(np.array(q))
        rows = arm.ik(pose, "optimal", body=body, scene=scene)
        best = arm.optimal(pose, body=body, scene=scene).value
        found += int(rows.exists.sum())
        np.testing.assert_array_equal(rows.exists, ~np.isnan(best))
        np.testing.assert_array_equal(rows.parameter[rows.exists], best[rows.exists])
        assert np.array_equal(rows.collision_free, rows.exists)
        assert np.all(clearance(arm.chain, body, scene, rows.q[rows.exists]).distance >= scene.margin)
    assert found


def test_a_cell_of_the_wrong_kind_is_refused_in_words(setup, tmp_path):
    """A scene or body given as something else (a file's name, the mistake to expect) is refused by every call that
    takes a cell, naming the function that reads it; one without the other too."""
    arm, body, scene = setup
    pose = arm.fk(np.zeros(7) + 0.3)
    calls = [lambda **cell: arm.ik(pose, 0.3, **cell), lambda **cell: arm.feasible(pose, **cell),
             lambda **cell: arm.optimal(pose, **cell)]
    for call in calls:
        with pytest.raises(ValueError, match=r"scene must be a redkin.collision.Scene \(redkin.collision.read_scene"):
            call(body=body, scene=str(tmp_path / "cell.yaml"))
        with pytest.raises(ValueError, match=r"body must be a redkin.collision.Body \(redkin.collision.read_body"):
            call(body={"spheres": {}}, scene=scene)
        with pytest.raises(ValueError, match="need both the arm's body and the scene"):
            call(scene=scene)
