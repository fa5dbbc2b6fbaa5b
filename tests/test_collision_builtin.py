"""The named models' built-in bodies (issue 40): capsules fitted to the makers' collision meshes
(tools/builtin_bodies.py), shipped as body files.

The makers' meshes are not in the suite, so the laws here are what the arm's own geometry fixes whatever the fit:
the flange (the tool frame's origin, on the face of the last link's casting) lies inside the last link's capsules and
the base frame's origin (the maker's, where the named model's base frame is elsewhere) inside the base's, at any
joint values; each joint's axis passes through the capsules of the
links it joins (the housing holds its axis); the arm is clear of itself in its ready pose; and the command line
uses the body where a named model is given a scene without one.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.collision import builtin_body, builtin_models, clearance, scene_of
from redkin.collision.body import posed
from redkin.errors import RedkinError
from tests.support.cli import run

MODELS = ["barrett-wam7", "franka-fr3", "franka-panda", "kinova-gen3", "kuka-iiwa14", "kuka-iiwa7", "ufactory-xarm7"]
#: A ready pose of each (the makers' own: Franka's, and the others' elbow bent), clipped into the limits.
READY = {"barrett-wam7": [0, 0.5, 0, 1.5, 0, 0.6, 0],
         "franka-fr3": [0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4],
         "franka-panda": [0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4],
         "kinova-gen3": [0, 0.26, 3.14, -2.27, 0, 0.96, 1.57],
         "kuka-iiwa14": [0, 0.5, 0, -1.2, 0, 0.6, 0], "kuka-iiwa7": [0, 0.5, 0, -1.2, 0, 0.6, 0],
         "ufactory-xarm7": [0, 0, 0, 1.2, 0, 1.2, 0]}

#: How far below the named model's base frame the maker's base link lies [m]: the WAM's named model (Barrett's DH
#: table) has its base frame at the shoulder, barrett_model's base_link is on the floor, the shoulder 0.346 m above
#: it (its base_yaw_joint's origin).
BASE_BELOW = {"barrett-wam7": 0.346}


def _outside(point: np.ndarray, rows: np.ndarray) -> float:
    """How far the point lies outside the nearest of the capsule rows (<= 0: inside one)."""
    gaps = []
    for row in rows:
        a, b, radius = row[2:5], row[5:8], row[1]
        t = np.clip(np.dot(point - a, b - a) / max(np.dot(b - a, b - a), 1e-300), 0.0, 1.0)
        gaps.append(np.linalg.norm(point - (a + t * (b - a))) - radius)
    return min(gaps)


def test_the_models_with_a_body_are_the_shipped_files_and_each_says_where_it_comes_from():
    assert list(builtin_models()) == MODELS
    for model in MODELS:
        chain = redkin.get_robot(model)
        body = builtin_body(model, chain)
        assert set(body.link) == {f"link_{k}" for k in range(chain.n + 1)}  # every link of the arm covered
        assert body.notes[0].startswith(f"built-in body of {model}: capsules fitted by redkin to the collision "
                                        "meshes of") and "reaching up to" in body.notes[0]
        assert body.source.endswith(f"{model}.yaml")


@pytest.mark.parametrize("model", MODELS)
@settings(max_examples=10, deadline=None)
@given(fractions=st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7))
def test_the_flange_and_the_base_lie_inside_their_links_capsules(model, fractions):
    chain = redkin.get_robot(model)
    body = builtin_body(model, chain)
    q = np.maximum(chain.lower, -np.pi) + np.asarray(fractions) * (np.minimum(chain.upper, np.pi)
                                                                  - np.maximum(chain.lower, -np.pi))
    rows = posed(body, chain.frames(q))
    last = rows[[link == f"link_{chain.n}" for link in body.link]]
    base = rows[[link == "link_0" for link in body.link]]
    assert _outside(chain.fk(q)[:3, 3], last) <= 0.0
    base_frame = chain.frames(q)[0]
    assert _outside(base_frame[:3, 3] - BASE_BELOW.get(model, 0.0) * base_frame[:3, 2], base) <= 0.0


@pytest.mark.parametrize("model", MODELS)
def test_each_joint_axis_passes_through_the_capsules_of_the_links_it_joins(model):
    chain = redkin.get_robot(model)
    body = builtin_body(model, chain)
    q = np.random.default_rng(3).uniform(np.maximum(chain.lower, -np.pi), np.minimum(chain.upper, np.pi))
    frames = chain.frames(q)
    rows = posed(body, frames)
    for k in range(1, chain.n + 1):  # joint k turns about frame k - 1's z axis
        joined = rows[[link in (f"link_{k - 1}", f"link_{k}") for link in body.link]]
        line = frames[k - 1][:3, 3] + np.linspace(-0.6, 0.6, 1201)[:, None] * frames[k - 1][:3, 2]
        assert min(_outside(point, joined) for point in line) <= 0.0, f"joint {k}"


@pytest.mark.parametrize("model", MODELS)
def test_the_arm_is_clear_of_itself_in_its_ready_pose(model):
    chain = redkin.get_robot(model)
    q = np.clip(READY[model], chain.lower, chain.upper)
    found = clearance(chain, builtin_body(model, chain), scene_of({"obstacles": []}), q)
    assert float(found.distance) > 0.0, (found.link, found.against)


def test_a_model_without_one_is_refused_naming_those_with_one():
    with pytest.raises(RedkinError, match=r"'pa10-7c' has no built-in body .*barrett-wam7, franka-fr3"):
        builtin_body("pa10-7c", redkin.get_robot("pa10-7c"))


def test_a_scene_on_a_named_model_uses_its_built_in_body(capsys, tmp_path):
    scene = tmp_path / "cell.yaml"
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.2], radius: 0.05}\n"
                     "  - {name: table, type: box, center: [0.6, 0, -0.06], size: [1.2, 1.0, 0.1]}\n")
    arm = redkin.arm("kuka-iiwa14")
    pose = arm.fk(np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1]))
    argv = ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist()),
            "--scene", str(scene)]
    code, out, _ = run(capsys, ["arm-angles", "kuka-iiwa14", *argv, "--json"])
    assert code == 0
    cell = json.loads(out)["collision"]
    body = builtin_body("kuka-iiwa14", arm.chain)
    assert cell["body"] == body.source and cell["capsules"] == len(body) and cell["notes"] == list(body.notes)
    assert cell["self_pairs"] == len(body.pairs)
    # the base's capsule reaches into the table it stands on: named, not checked, and the arm is free above it
    assert [(c["link"], c["obstacle"]) for c in cell["base_contacts"]] == [("link_0", "table")]
    assert json.loads(out)["feasible"]
    code, out, _ = run(capsys, ["arm-angles", "kuka-iiwa14", *argv])
    assert code == 0 and "base: link_0 is" in out and "from table, inside the margin; not checked" in out
    code, _, err = run(capsys, ["arm-angles", "pa10-7c", *argv])
    assert code == 2 and err.count("\n") == 1 and "built-in bodies: barrett-wam7, franka-fr3" in err


def test_the_files_ignore_only_pairs_they_list_and_round_their_radii_outward():
    """Each file's header states how often each pair's meshes meet; a pair is ignored only where they never or
    always do, or where its capsules overlap in every configuration, which the body's notes then say."""
    from pathlib import Path

    import redkin.collision.builtin as builtin

    for model in MODELS:
        text = (Path(builtin.__file__).parent / "bodies" / f"{model}.yaml").read_text()
        data = yaml.safe_load(text)
        for first, second in data["ignore"]:
            line = next(line for line in text.splitlines() if line.startswith(f"#   {first} - {second}:"))
            if "(ignored: the capsules always overlap)" in line:
                assert "capsules 100.00 %" in line
                assert any(note.startswith(f"{first} and {second} are not checked: their capsules overlap in every")
                           for note in data["notes"])
                continue
            assert "(ignored: the meshes never meet)" in line or "(ignored: the meshes always meet)" in line
            assert ("meshes 0.00 %" in line) or ("meshes 100.00 %" in line)
