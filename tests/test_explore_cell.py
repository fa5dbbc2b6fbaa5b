"""The explorer in a cell (issue 40): the page's numbers are redkin's, laws over the grid.

The collision-free arcs are those of collision_free_arm_angles; the least distance and its pair at every grid value
are the ones measured here pair by pair at the grid's joint values; the capsules drawn are the body posed there; the
page opens where the body keeps farthest from the obstacles among the free values of every branch; the command line
writes the page and its JSON, and refuses what it cannot draw.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import redkin
from redkin.collision import builtin_body, clearance, collision_free_arm_angles, collision_free_q7, posed, scene_of
from redkin.errors import RedkinError
from redkin.explore import explorer_data, explorer_html
from redkin.reproduce.cell_case import cell
from tests.support.cli import run


@pytest.fixture(scope="module")
def shelf():
    chain, body, scene, poses = cell()
    pose = poses[len(poses) // 2]
    return chain, body, scene, pose, explorer_data(chain, pose, body=body, scene=scene, samples=181)


def test_the_cell_s_numbers_are_redkin_s(shelf):
    chain, body, scene, pose, data = shelf
    assert data.cell is not None and len(data.cell.branches) == len(data.branches) == 8
    free = collision_free_arm_angles(redkin.arm(chain), pose, body, scene, [b.branch for b in data.branches])
    for k, (curves, inside) in enumerate(zip(data.branches, data.cell.branches, strict=True)):
        assert np.array_equal(inside.free, free.free[k].bounds)
        q = curves.q[curves.exists]
        measured = clearance(chain, body, scene, q)
        assert np.allclose(inside.distance[curves.exists], measured.distance, rtol=0, atol=1e-12)
        names = [data.cell.pairs[i] for i in inside.closest[curves.exists]]
        assert names == list(zip(measured.link, measured.against, strict=True))
        shapes = posed(body, chain.frames(q))
        assert np.allclose(inside.capsules[curves.exists][..., 0, :], shapes[..., 2:5], rtol=0, atol=1e-12)
        assert np.isnan(inside.capsules[~curves.exists]).all()
        assert all(" meets " in text or text.startswith("undecided") for _, _, text in inside.blocked)
    assert any(" meets post" in text for inside in data.cell.branches for _, _, text in inside.blocked)


def test_the_page_opens_where_the_arm_keeps_farthest_from_the_obstacles(shelf):
    _, _, scene, _, data = shelf
    best = -np.inf
    for curves, inside in zip(data.branches, data.cell.branches, strict=True):
        values = curves.values
        free = np.zeros(len(values), dtype=bool)
        for lo, hi in inside.free:
            free |= ((values >= lo) & (values <= hi)) if lo <= hi else ((values >= lo) | (values <= hi))
        free &= curves.exists & curves.feasible_at
        best = max(best, np.where(free, inside.distance, -np.inf).max())
    shown = data.branches[data.initial]
    assert data.cell.branches[data.initial].distance[shown.start] == best >= scene.margin
    assert data.opening.startswith("Opened where the arm keeps farthest from the obstacles")


def test_the_page_holds_the_obstacles_and_the_body(shelf):
    _, body, scene, _, data = shelf
    page = explorer_html(data, degrees=True)
    payload = json.loads(re.search(r'<script id="explorer-data" type="application/json">(.*?)</script>', page,
                                   re.S).group(1))
    assert [o["name"] for o in payload["cell"]["obstacles"]] == list(scene.names)
    assert payload["cell"]["links"] == list(body.link) and payload["cell"]["margin"] == scene.margin
    assert {o["kind"] for o in payload["cell"]["obstacles"]} == {"capsule", "box"}
    shown = payload["branches"][payload["initial"]]
    assert len(shown["cell"]["capsules"]) == len(shown["values"]) * len(body) * 6
    assert "removed by an obstacle" in page


def test_a_cell_with_no_pair_to_check_draws_a_page():
    """No obstacle and no self pair: every distance is infinite, written as null (no pair to check)."""
    chain = redkin.get_robot("kuka-iiwa14")
    body = redkin.collision.body_of([redkin.collision.BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.05)],
                                    chain)
    empty = redkin.collision.Scene((), np.empty((0, redkin.collision.WIDTH)), 0.01)
    data = explorer_data(chain, chain.fk(np.zeros(7) + 0.3), body=body, scene=empty, samples=64)
    assert all(np.isinf(b.distance[curves.exists]).all() for b, curves in zip(data.cell.branches, data.branches))
    page = explorer_html(data)
    payload = json.loads(re.search(r'<script id="explorer-data" type="application/json">(.*?)</script>', page,
                                   re.S).group(1))
    assert all(d is None for b in payload["branches"] for d in b["cell"]["distance"])


def test_a_cell_on_another_class_or_half_a_cell_is_refused(shelf):
    chain, body, scene, pose, _ = shelf
    with pytest.raises(RedkinError, match="both"):
        explorer_data(chain, pose, body=body)
    sawyer = redkin.get_robot("sawyer.urdf")  # solved numerically: no redundancy parameter, so no sets
    with pytest.raises(RedkinError, match="sawyer"):
        explorer_data(sawyer, sawyer.fk(np.zeros(7) + 0.2), body=redkin.collision.body_of([], sawyer),
                      scene=scene, samples=64)


def test_the_franka_class_s_cell_holds_its_q7_sets():
    """On the Panda the cell's free intervals are collision_free_q7's, and the distances are measured ones."""
    chain = redkin.get_robot("franka-panda")
    body = builtin_body("franka-panda", chain)
    scene = scene_of({"margin": 0.01, "obstacles": [
        {"name": "post", "type": "capsule", "a": [0.3, 0.3, 0], "b": [0.3, 0.3, 1.0], "radius": 0.04},
        {"name": "table", "type": "box", "center": [0.5, 0, -0.06], "size": [1.0, 1.0, 0.1]}]})
    pose = chain.fk(np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.785]))
    data = explorer_data(chain, pose, body=body, scene=scene, samples=121)
    assert data.parameter.name == "q7" and data.cell is not None
    free = collision_free_q7(redkin.arm(chain), pose, body, scene, [b.branch for b in data.branches])
    for k, (curves, inside) in enumerate(zip(data.branches, data.cell.branches, strict=True)):
        assert np.array_equal(inside.free, free.free[k].bounds)
        measured = clearance(chain, body, scene, curves.q[curves.exists])
        assert np.allclose(inside.distance[curves.exists], measured.distance, rtol=0, atol=1e-12)
    assert any(" meets post" in text for inside in data.cell.branches for _, _, text in inside.blocked)
    shown = data.branches[data.initial]
    assert shown.exists[shown.start] and np.any((free.free[data.initial].bounds[:, 0] <= shown.values[shown.start])
                                                & (shown.values[shown.start] <= free.free[data.initial].bounds[:, 1]))


def test_the_command_line_writes_the_cell_s_page(capsys, tmp_path):
    chain, _, _, poses = cell()
    pose = poses[len(poses) // 2]
    scene, body = tmp_path / "cell.yaml", tmp_path / "body.yaml"
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.33, -0.26, 0], b: [0.33, -0.26, 1.1], radius: 0.04}\n")
    body.write_text("capsules:\n  link_3: [{a: [0, 0, -0.2], b: [0, 0, 0], radius: 0.07}]\n"
                    "  link_4: [{a: [0, 0, 0], b: [0, 0.2, 0], radius: 0.07}]\n")
    out = tmp_path / "page.html"
    argv = ["explore", "kuka-iiwa14", "--position", *map(repr, pose[:3, 3].tolist()), "--rotation",
            *map(repr, pose[:3, :3].ravel().tolist()), "--scene", str(scene), "--body", str(body), "--out", str(out)]
    code, output, _ = run(capsys, [*argv, "--json"])
    assert code == 0 and out.exists()
    report = json.loads(output)
    read_body = redkin.collision.read_body(body, chain, redkin.collision.numbered_link_frames(chain))
    free = collision_free_arm_angles(redkin.arm(chain), pose, read_body, redkin.collision.read_scene(scene))
    for k, label in enumerate(free.branches):
        assert np.allclose(report["collision_free"][label]["feasible"], free.free[k].bounds.reshape(-1, 2),
                           rtol=0, atol=1e-12)
    assert any(stretch["cause"] == "link_3 meets post" for sets in report["collision_free"].values()
               for stretch in sets["blocked"])
    code, _, err = run(capsys, ["explore", "kuka-iiwa14", "--path", str(out), "--scene", str(scene), "--body",
                                str(body), "--out", str(tmp_path / "again.html")])
    assert code == 2 and err.count("\n") == 1 and "cannot read it as JSON" in err  # a page is not a path to play
