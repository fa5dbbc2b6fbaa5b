"""``redkin arm-angles --scene`` (issue 40): the collision-free sets on the command line agree with the API, the body
comes from a body file or a URDF's collision elements, and a mistake is one line with exit 2."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

import redkin
from redkin.circle import ArcSet
from redkin.collision import collision_free_arm_angles, numbered_link_frames, read_body, read_scene, urdf_link_frames
from redkin.examples import resolve
from tests.support.cli import run

Q = [0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1]
SCENE = """margin: 0.01
obstacles:
  - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.2], radius: 0.05}
  - {name: table, type: box, center: [0.6, 0, -0.06], size: [1.2, 1.0, 0.1]}
"""
BODY = """capsules:
  link_3: [{a: [0, 0, -0.2], b: [0, 0, 0], radius: 0.06}]
  link_4: [{a: [0, 0, 0], b: [0, 0.2, 0], radius: 0.06}]
spheres:
  link_7: [{center: [0, 0, 0.05], radius: 0.06}]
"""


def _pose_arguments(chain) -> list[str]:
    pose = chain.fk(np.array(Q))
    return ["--position", *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist())]


@pytest.fixture
def cell(tmp_path: Path) -> tuple[Path, Path]:
    scene, body = tmp_path / "cell.yaml", tmp_path / "body.yaml"
    scene.write_text(SCENE)
    body.write_text(BODY)
    return scene, body


def test_the_json_sets_are_the_api_sets(capsys, cell):
    scene_file, body_file = cell
    arm = redkin.arm("kuka-iiwa14")
    code, out, _ = run(capsys, ["arm-angles", "kuka-iiwa14", *_pose_arguments(arm.chain), "--scene", str(scene_file),
                                "--body", str(body_file), "--branch", "++-", "--json"])
    assert code == 0
    report = json.loads(out)
    body = read_body(body_file, arm.chain, numbered_link_frames(arm.chain))
    expected = collision_free_arm_angles(arm, arm.fk(np.array(Q)), body, read_scene(scene_file))
    b = expected.branches.index("++-")
    assert np.allclose(report["feasible"], expected.free[b].bounds.reshape(-1, 2), atol=1e-12)
    assert np.allclose(report["branches"]["+++"], expected.free[0].bounds.reshape(-1, 2), atol=1e-12)
    free, limits = ArcSet(report["feasible"]), ArcSet(report["limits_feasible"])
    assert limits.union(free).isclose(limits)
    causes = {(stretch["cause"], stretch["link"], stretch["obstacle"]) for stretch in report["blocked"]}
    assert ("collision", "link_4", "post") in causes or ("collision", "link_3", "post") in causes
    assert report["collision"]["obstacles"] == ["post", "table"] and report["collision"]["capsules"] == 3
    for entry in report["optimal"].values():
        assert entry["collision_free"] is None or free.contains(entry["collision_free"], 1e-9)


def test_a_urdf_body_comes_from_its_collision_elements(capsys, cell, tmp_path):
    scene_file, _ = cell
    text = resolve("iiwa14.urdf").read_text()
    for link in ("lbr_iiwa_link_3", "lbr_iiwa_link_4"):  # a cylinder on each, along the link's z
        text = text.replace(f'<link name="{link}"/>', f'<link name="{link}"><collision><geometry>'
                            '<cylinder radius="0.06" length="0.2"/></geometry></collision></link>')
    urdf = tmp_path / "iiwa.urdf"
    urdf.write_text(text)
    chain = redkin.get_robot(str(urdf))
    code, out, _ = run(capsys, ["arm-angles", str(urdf), *_pose_arguments(chain), "--scene", str(scene_file),
                                "--json"])
    assert code == 0
    report = json.loads(out)
    assert report["collision"]["capsules"] == 2 and report["collision"]["self_pairs"] == 0
    assert any("cylinder" in note for note in report["collision"]["notes"])
    code, out, _ = run(capsys, ["arm-angles", str(urdf), *_pose_arguments(chain), "--scene", str(scene_file)])
    assert code == 0 and "collision-free" in out and "meets" in out


@pytest.mark.parametrize(("extra", "words"), [
    (["--body", "{body}"], "--body applies with --scene"),
    (["--scene", "{scene}", "--body", "{body}", "--margin", "-1"], "--margin must be"),
    (["--scene", "missing.yaml", "--body", "{body}"], "cannot read it"),
    (["--scene", "{scene}", "--body", "{body}", "--srdf", "{body}"], "--srdf names URDF links"),
])
def test_mistakes_are_one_line(capsys, cell, extra, words):
    scene_file, body_file = cell
    chain = redkin.get_robot("kuka-iiwa14")
    argv = ["arm-angles", "kuka-iiwa14", *_pose_arguments(chain),
            *[part.format(scene=scene_file, body=body_file) for part in extra]]
    code, out, err = run(capsys, argv)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and words in err


def test_a_chain_without_a_parameter_is_refused_in_words(capsys, cell):
    scene_file, body_file = cell
    chain = redkin.get_robot("sawyer.urdf")
    code, _, err = run(capsys, ["arm-angles", "sawyer.urdf", *_pose_arguments(chain), "--scene", str(scene_file),
                                "--body", str(body_file)])
    assert code == 2 and err.count("\n") == 1 and "sawyer" in err


@pytest.mark.parametrize("psi", [-2.0, 0.2, 1.0])
def test_ik_marks_each_solution_with_its_clearance(capsys, cell, psi):
    scene_file, body_file = cell
    arm = redkin.arm("kuka-iiwa14")
    code, out, _ = run(capsys, ["ik", "kuka-iiwa14", *_pose_arguments(arm.chain), "--psi", str(psi), "--all",
                                "--scene", str(scene_file), "--body", str(body_file), "--json"])
    assert code == 0
    body = read_body(body_file, arm.chain, numbered_link_frames(arm.chain))
    scene = read_scene(scene_file)
    solutions = json.loads(out)["solutions"]
    assert len(solutions) == 8
    for entry in solutions:
        expected = redkin.collision.clearance(arm.chain, body, scene, np.array(entry["q"]))
        assert entry["clearance"] == pytest.approx(float(expected.distance), abs=1e-12)
        assert entry["closest"] == [expected.link.item(), expected.against.item()]
        assert entry["collision_free"] == (float(expected.distance) >= scene.margin)


SAWYER_BODY = """spheres:
  right_l1: [{center: [0, 0, 0], radius: 0.07}]
  right_l2: [{center: [0, 0, 0], radius: 0.06}]
  right_l3: [{center: [0, 0, 0], radius: 0.06}]
  right_l4: [{center: [0, 0, 0], radius: 0.06}]
  right_l5: [{center: [0, 0, 0], radius: 0.05}]
  right_l6: [{center: [0, 0, 0], radius: 0.05}]
ignore: [[right_l4, right_l6]]
"""


def test_numerical_ik_in_a_cell_returns_collision_free_solutions(capsys, tmp_path):
    """The Sawyer has no closed form: without --psi the numerical solver's solutions are the clear ones, each with
    the clearance the API measures, and a margin nothing meets gives exit 1 and one line saying how near it came."""
    chain = redkin.get_robot("sawyer.urdf")
    pose_arguments = _pose_arguments(chain)
    plain = redkin.numerical.ik(chain, chain.fk(np.array(Q))).q[0]
    elbow = chain.frames(plain)[4][:3, 3]
    scene_file, body_file = tmp_path / "cell.yaml", tmp_path / "body.yaml"
    scene_file.write_text("margin: 0.02\nobstacles:\n  - {name: ball, type: sphere, center: "
                          f"{elbow.tolist()}, radius: 0.05}}\n")
    body_file.write_text(SAWYER_BODY)
    argv = ["ik", "sawyer.urdf", *pose_arguments, "--scene", str(scene_file), "--body", str(body_file)]
    code, out, _ = run(capsys, [*argv, "--count", "3", "--json"])
    assert code == 0
    report = json.loads(out)
    body = read_body(body_file, chain, urdf_link_frames(resolve("sawyer.urdf"))[1])
    scene = read_scene(scene_file)
    assert report["margin"] == 0.02 and len(report["solutions"]) == 3
    assert report["collision"]["candidates"] >= 3 + report["collision"]["blocked"] >= 4  # the plain one collides
    for q, distance, pair in zip(report["solutions"], report["clearance"], report["closest_pairs"]):
        expected = redkin.collision.clearance(chain, body, scene, np.array(q))
        assert distance == pytest.approx(float(expected.distance), abs=1e-12) and distance >= 0.02
        assert pair == [expected.link.item(), expected.against.item()]
        assert np.allclose(chain.fk(np.array(q)), chain.fk(np.array(Q)), atol=1e-9)
        assert not np.allclose(q, plain, atol=1e-9)
    code, out, _ = run(capsys, [*argv, "--margin", "0.5"])
    assert code == 1
    [line] = [text for text in out.splitlines() if "no collision-free solution" in text]
    assert "collide (the clearest of them:" in line


def test_path_in_a_cell_and_its_failure(capsys, cell, tmp_path):
    scene_file, body_file = cell
    chain = redkin.get_robot("kuka-iiwa14")
    qs = np.linspace([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1], [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9], 12)
    poses = tmp_path / "poses.npy"
    np.save(poses, chain.fk(qs))
    code, out, _ = run(capsys, ["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", "--scene",
                                str(scene_file), "--body", str(body_file), "--json"])
    assert code == 0
    report = json.loads(out)
    body = read_body(body_file, chain, numbered_link_frames(chain))
    apart = redkin.collision.clearance(chain, body, read_scene(scene_file), np.array(report["q"]))
    assert report["collision"]["least"] == pytest.approx(float(apart.distance.min()), abs=1e-12)
    assert apart.distance.min() >= 0.01 - 1e-12
    steps = redkin.collision.step_clearance(chain, body, read_scene(scene_file), np.array(report["q"]))
    assert steps.certified.all()  # every step of a path returned is proved clear
    assert report["collision"]["steps"] == {"certified": 11, "of": 11, "least": float(steps.least.min())}
    hand = chain.frames(qs[5])[7, :3, 3]
    blocked = tmp_path / "blocked.yaml"
    blocked.write_text(f"obstacles:\n  - {{name: ball, type: sphere, center: {hand.tolist()}, radius: 0.03}}\n")
    code, out, _ = run(capsys, ["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", "--scene",
                                str(blocked), "--body", str(body_file), "--json"])
    assert code == 1
    failure = json.loads(out)["failure"]
    assert failure["reason"] == "collision" and failure["pair"] == ["link_7", "ball"]
    figure = tmp_path / "why.png"
    code, out, _ = run(capsys, ["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", "--scene",
                                str(blocked), "--body", str(body_file), "--plot", str(figure)])
    assert code == 1 and "link_7 meets ball" in out
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"  # the picture of why (tests/test_plot_paths.py)


def test_a_path_proved_optimal_in_a_cell_says_among_what(capsys, tmp_path):
    """A clearance proved in a cell is proved among the certified collision-free sets, and the line says so (a far
    ball: the elbow joint, which the pose fixes, is the bottleneck); JSON's ``optimal`` is the same proof."""
    chain = redkin.get_robot("kuka-iiwa14")
    poses = tmp_path / "poses.npy"
    np.save(poses, chain.fk(np.linspace([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1], [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9],
                                        12)))
    far = tmp_path / "far.yaml"
    far.write_text("margin: 0.01\nobstacles:\n  - {name: ball, type: sphere, center: [1.5, 1.5, 1.5], radius: 0.1}\n")
    argv = ["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.5", "--scene", str(far)]
    code, out, _ = run(capsys, argv)
    assert code == 0 and "proved the largest any path through the certified collision-free sets keeps" in out
    code, out, _ = run(capsys, [*argv, "--json"])
    assert code == 0 and json.loads(out)["optimal"] is True


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "examples/panda.urdf"])
def test_robots_show_names_the_links_a_body_file_may_use(capsys, robot):
    chain = redkin.get_robot(robot)
    code, out, _ = run(capsys, ["robots", "--show", robot, "--json"])
    assert code == 0
    links = json.loads(out)["body_links"]
    if robot.endswith(".urdf"):
        expected = {name: place.frame for name, place in redkin.collision.urdf_link_frames(robot)[1].items()}
    else:
        expected = {f"link_{k}": k for k in range(chain.n + 1)}
    assert links == expected
    assert json.loads(out)["builtin_body"] == (robot == "kuka-iiwa14")  # a named model with one; a file has none
    code, out, _ = run(capsys, ["robots", "--show", robot])
    assert code == 0 and ("built-in body: capsules fitted to the maker's collision meshes" in out) == (
        robot == "kuka-iiwa14")


def test_ik_path_and_explore_say_what_the_cell_says_of_itself(capsys, cell, tmp_path):
    """The body's notes and the base's contacts (not checked: the base never moves) are said by ``ik`` (closed
    form and numerical), ``path`` and ``explore``, as by ``arm-angles``: a line each, and in JSON the fields the API
    gives."""
    from redkin.collision.clearance import base_contacts

    scene_file, _ = cell
    body_file = tmp_path / "based.yaml"
    base = "capsules:\n  link_0: [{a: [0, 0, -0.1], b: [0, 0, 0.1], radius: 0.1}]\n"
    note = "notes: [the base is a capsule round the pedestal's bolts]\n"
    body_file.write_text(BODY.replace("capsules:\n", base) + note)
    chain = redkin.get_robot("kuka-iiwa14")
    body = read_body(body_file, chain, numbered_link_frames(chain))
    scene = read_scene(scene_file)
    expected = {"notes": ["the base is a capsule round the pedestal's bolts"], "scene_notes": [],
                "base_contacts": [{"link": link, "obstacle": obstacle, "distance": distance}
                                  for link, obstacle, distance in base_contacts(chain, body, scene)]}
    assert [c["obstacle"] for c in expected["base_contacts"]] == ["table"]  # 0.1 m below the base, the table top
    cell_arguments = ["--scene", str(scene_file), "--body", str(body_file)]
    qs = np.linspace([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1], [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9], 12)
    poses = tmp_path / "poses.npy"
    np.save(poses, chain.fk(qs))
    commands = {"ik": ["ik", "kuka-iiwa14", *_pose_arguments(chain), "--psi", "0.2", *cell_arguments],
                "numerical": ["ik", "kuka-iiwa14", *_pose_arguments(chain), "--count", "1", *cell_arguments],
                "path": ["path", "kuka-iiwa14", "--poses", str(poses), "--max-step", "0.2", *cell_arguments],
                "explore": ["explore", "kuka-iiwa14", *_pose_arguments(chain), *cell_arguments, "--force", "--out",
                            str(tmp_path / "page.html")]}
    for name, argv in commands.items():
        code, out, _ = run(capsys, [*argv, "--json"])
        said = json.loads(out)["collision" if name == "path" else "cell"]
        assert code == 0 and said | expected == said, name
        code, out, _ = run(capsys, argv)
        lines = out.splitlines()
        assert code == 0, name
        assert "body: the base is a capsule round the pedestal's bolts" in lines, name
        assert any(line.startswith("base: link_0 is ") and "from table, inside the margin; not checked" in line
                   for line in lines), name


def test_undecided_slivers_no_wider_than_the_resolution_are_said_together(capsys):
    """An undecided stretch no wider than the resolution (where a located end may lie; six decimals may print it as
    ``[x, x]`` or as two neighbouring values) is not printed on a line of its own: the slivers get one line with
    their number, bound and places; wider stretches, one through +-pi included, and every collision or limit
    stretch keep their own line."""
    from types import SimpleNamespace

    from redkin.cli.common import plus_minus
    from redkin.cli.srs import _print_arm_angles

    cell = {"obstacles": ["post"], "self_pairs": 0, "margin": 0.01, "notes": [], "scene_notes": [],
            "base_contacts": [], "complete": True, "resolution": 1e-6}
    report = {
        "robot": "kuka-iiwa14", "branch": "+++", "collision": cell, "limits_feasible": [[-1.0, 2.0]],
        "feasible": [[-1.0, 0.4], [0.6, 1.2000002], [1.2000004, 1.5], [1.5001, 1.7000001], [1.7000003, 1.8000004],
                     [1.8000013, 2.0]],
        "branches": {"+++": [[-1.0, 2.0]]},
        "optimal": {},
        "blocked": [
            {"arc": [0.4, 0.6], "cause": "collision", "link": "link_4", "obstacle": "post"},
            {"arc": [1.2000002, 1.2000004], "cause": "undecided", "link": None, "obstacle": None},
            {"arc": [1.5, 1.5001], "cause": "undecided", "link": None, "obstacle": None},
            {"arc": [1.7000001, 1.7000003], "cause": "undecided", "link": None, "obstacle": None},
            {"arc": [1.8000004, 1.8000013], "cause": "undecided", "link": None, "obstacle": None},
            {"arc": [3.1415, -3.1415], "cause": "undecided", "link": None, "obstacle": None},
        ],
    }
    analysis = SimpleNamespace(parameter=SimpleNamespace(set_ascii="psi", name="psi"), remarks=(), complete=True)
    _print_arm_angles(report, analysis, deg=False)
    seam = plus_minus()  # the stream's own (as the command wrote it)
    removed = [line.strip() for line in capsys.readouterr().out.splitlines() if line.strip().startswith("removed")]
    assert removed == [
        "removed [0.400000, 0.600000]: link_4 meets post",
        "removed [1.500000, 1.500100]: undecided (next to a singular arm angle, or the clearance grazes the margin)",
        f"removed [3.141500, -3.141500] (through {seam}pi): undecided (next to a singular arm angle, or the "
        "clearance grazes the margin)",
        "removed 3 undecided slivers of at most 1e-06 rad at 1.200000, 1.700000, 1.800000 (next to a singular arm "
        "angle, or the clearance grazes the margin)",
    ]


def _binary_stl(path: Path, triangles: list) -> None:
    """A binary STL of ``triangles`` (each three corners), written here so that nothing tidies them first."""
    import struct

    with path.open("wb") as out:
        out.write(b"\0" * 80 + struct.pack("<I", len(triangles)))
        for corners in triangles:
            out.write(struct.pack("<12fH", 0.0, 0.0, 0.0, *[value for corner in corners for value in corner], 0))


def test_cells_that_are_mistakes_are_one_line(capsys, tmp_path):
    """A cell with no pair to check (no obstacle, and a body without self pairs; or no capsule on a moving link) is
    refused rather than answered "collision-free" of nothing (ik wrote ``clearance inf m ( / )``, or failed on it);
    a number no float holds (it raised OverflowError), and a mesh scaled past any cell, are refused naming the
    field."""
    chain = redkin.get_robot("kuka-iiwa14")
    pose = _pose_arguments(chain)
    files = {"empty.yaml": "obstacles: []\n", "one.yaml": "capsules: {link_3: [{a: [0,0,0], b: [0,0,0.2], radius: "
             "0.06}]}\n", "base.yaml": "capsules: {link_0: [{a: [0,0,0], b: [0,0,0.1], radius: 0.1}]}\n",
             "huge.yaml": "obstacles: [{name: ball, type: sphere, center: [0.5, 0, 0.5], radius: 1" + "0" * 400
             + "}]\n",
             "huge-body.yaml": "spheres: {link_4: [{center: [0, 0, 0], radius: 1" + "0" * 400 + "}]}\n",
             "scaled.yaml": "obstacles: [{name: fixture, type: mesh, file: cube.stl, scale: 1e300}]\n"}
    for name, text in {**files, "cell.yaml": SCENE}.items():
        (tmp_path / name).write_text(text)
    _binary_stl(tmp_path / "cube.stl", [[(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 0, 0), (0, 1, 0), (0, 0, 1)],
                                        [(0, 0, 0), (0, 0, 1), (1, 0, 0)], [(1, 0, 0), (0, 0, 1), (0, 1, 0)]])
    keys = tmp_path / "keys.json"
    first = chain.fk(np.array(Q))
    second = first.copy()
    second[1, 3] -= 0.02
    keys.write_text(json.dumps([first.tolist(), second.tolist()]))
    cases = [
        (["ik", "kuka-iiwa14", *pose, "--psi", "0", "--scene", "empty.yaml", "--body", "one.yaml"], "checks no pair"),
        (["ik", "kuka-iiwa14", *pose, "--scene", "empty.yaml", "--body", "one.yaml", "--json"], "checks no pair"),
        (["path", "kuka-iiwa14", "--through", str(keys), "--step", "0.01", "--scene", "empty.yaml", "--body",
          "one.yaml"], "checks no pair"),
        (["arm-angles", "kuka-iiwa14", *pose, "--scene", "cell.yaml", "--body", "base.yaml"],
         "capsules on moving links: 0"),
        (["arm-angles", "kuka-iiwa14", *pose, "--scene", "huge.yaml"], "radius must be a finite number >= 0, got inf"),
        (["arm-angles", "kuka-iiwa14", *pose, "--scene", "cell.yaml", "--body", "huge-body.yaml"],
         "radius must be a finite number >= 0, got inf"),
    ]
    if importlib.util.find_spec("trimesh") is not None:
        cases.append((["arm-angles", "kuka-iiwa14", *pose, "--scene", "scaled.yaml"], "m across, scaled"))
    for argv, words in cases:
        argv = [str(tmp_path / part) if part.endswith(".yaml") else part for part in argv]
        code, out, err = run(capsys, argv)
        assert (code, out, err.count("\n")) == (2, "", 1), (argv, err)
        assert words in err, (argv, err)


def test_a_flat_mesh_in_a_cell_is_covered(capsys, tmp_path, monkeypatch):
    """A fixture whose mesh is one triangle (or its corners on a line) is covered like any other: its hull a hair
    thick (scipy's hull needs four points off a plane; it raised QhullError), with no warning from its mass."""
    pytest.importorskip("trimesh")
    monkeypatch.setenv("REDKIN_CACHE_DIR", str(tmp_path / "cache"))  # covered afresh, not read from a cache
    chain = redkin.get_robot("kuka-iiwa14")
    for corners in ([(0.4, 0.2, 0.3), (0.6, 0.2, 0.3), (0.5, 0.4, 0.3)], [(0.4, 0.2, 0.3), (0.5, 0.2, 0.3),
                                                                           (0.6, 0.2, 0.3)]):
        _binary_stl(tmp_path / "flat.stl", [corners])
        (tmp_path / "flat.yaml").write_text("obstacles: [{name: plate, type: mesh, file: flat.stl}]\n")
        code, out, err = run(capsys, ["arm-angles", "kuka-iiwa14", *_pose_arguments(chain), "--scene",
                                      str(tmp_path / "flat.yaml"), "--json"])
        assert code == 0 and "warning" not in err, err
        assert "covered by 1 box" in " ".join(json.loads(out)["collision"]["scene_notes"])
