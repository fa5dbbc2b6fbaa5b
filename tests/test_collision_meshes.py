"""Meshes in the arm's body (issue 40): capsules that cover a mesh, the bound on how far they reach beyond it, and a
URDF whose links' collision shapes are mesh files.

The laws hold for every mesh: every point of the surface (and of the solid, for a closed mesh) lies in some capsule,
and no point of a capsule lies farther from the convex hull of what it covers than the stated reach.  The distance to
a hull is computed here independently of the module: as the least-squares point of the hull (non-negative weights of
the vertices summing to one, by ``scipy.optimize.nnls``).  The URDF's meshes are placed by the product of its
``<origin>`` transforms (:func:`tests.support.urdf_reference.reference_fk`), not by redkin.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import nnls
from scipy.spatial import ConvexHull

from redkin._disk_cache import cache_folder
from redkin.collision import urdf_body
from redkin.collision.body import posed
from redkin.collision.mesh_cover import covering_capsules
from redkin.errors import RobotDescriptionError
from tests.support.urdf_reference import reference_fk

trimesh = pytest.importorskip("trimesh", reason="the mesh extra (trimesh) is not installed")


def _distance_to_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    along = b - a
    t = np.clip((points - a) @ along / max(along @ along, 1e-300), 0.0, 1.0)
    return np.linalg.norm(points - (a + t[:, None] * along), axis=1)


def _covered(points: np.ndarray, capsules) -> np.ndarray:
    """Per point, how far it lies outside the nearest capsule (<= 0: inside one)."""
    return np.min([_distance_to_segment(points, c.a, c.b) - c.radius for c in capsules], axis=0)


def _distance_to_hull(point: np.ndarray, vertices: np.ndarray) -> float:
    """The distance from ``point`` to the convex hull of ``vertices``: weights >= 0 summing to one (a heavy row)."""
    heavy = 1e4
    matrix = np.vstack([vertices.T, heavy * np.ones(len(vertices))])
    weights, _ = nnls(matrix, np.append(point, heavy), maxiter=50 * len(vertices))
    return float(np.linalg.norm(vertices.T @ weights - point))


def _surface_points(mesh, rng: np.random.Generator, count: int) -> np.ndarray:
    """Random points on the mesh's triangles (and their corners)."""
    triangles = mesh.vertices[mesh.faces]
    chosen = triangles[rng.integers(0, len(triangles), count)]
    weights = rng.dirichlet(np.ones(3), count)
    return np.concatenate([np.einsum("nk,nkj->nj", weights, chosen), mesh.vertices])


def _bent_link(rng: np.random.Generator):
    """Two boxes meeting at an angle (an L or a V), each closed: an arm link's casting, roughly."""
    first = trimesh.creation.box(extents=[0.1, 0.1, rng.uniform(0.2, 0.5)])
    first.apply_translation([0, 0, first.extents[2] / 2])
    second = trimesh.creation.box(extents=[0.1, 0.1, rng.uniform(0.1, 0.4)])
    second.apply_translation([0, 0, second.extents[2] / 2])
    turn = trimesh.transformations.rotation_matrix(rng.uniform(0.5, 2.0), [1, 0, 0])
    second.apply_transform(turn)
    second.apply_translation([0, 0, first.extents[2]])
    return trimesh.util.concatenate([first, second]), [first, second]


MESHES = {
    "cylinder": lambda rng: trimesh.creation.cylinder(radius=rng.uniform(0.02, 0.1), height=rng.uniform(0.0, 0.4),
                                                      sections=48),
    "box": lambda rng: trimesh.creation.box(extents=rng.uniform(0.01, 0.4, 3)),
    "ball": lambda rng: trimesh.creation.icosphere(subdivisions=2, radius=rng.uniform(0.02, 0.2)),
    "blob": lambda rng: trimesh.convex.convex_hull(rng.normal(size=(40, 3)) * rng.uniform(0.01, 0.2, 3)),
}


def _placed(mesh, rng: np.random.Generator):
    """The mesh at a random pose (a casting is rarely aligned with its link's frame)."""
    pose = trimesh.transformations.random_rotation_matrix(rng.uniform(size=3))
    pose[:3, 3] = rng.uniform(-0.3, 0.3, 3)
    return mesh.copy().apply_transform(pose)


# ----------------------------------------------------------------------------- the capsules contain the mesh
@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(sorted(MESHES)), most=st.integers(1, 3),
       least=st.integers(1, 3))
def test_the_capsules_contain_every_point_of_a_convex_mesh_and_its_solid(seed, kind, most, least):
    rng = np.random.default_rng(seed)
    mesh = _placed(MESHES[kind](rng), rng)
    least = min(least, most)
    capsules = covering_capsules(mesh.vertices, mesh.faces, most=most, least=least)
    assert least <= len(capsules) <= most  # every mesh here can be cut in three
    assert np.all(_covered(_surface_points(mesh, rng, 2000), capsules) <= 1e-12)
    inside = rng.dirichlet(np.ones(len(mesh.vertices)) * 0.2, 500) @ mesh.vertices  # points of the solid
    assert np.all(_covered(inside, capsules) <= 1e-12)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), most=st.integers(1, 3), least=st.integers(1, 3))
def test_the_capsules_contain_a_bent_link_and_its_solid(seed, most, least):
    """Cut into slabs, the capsules still hold the surface and the solid (points inside either box), the corner
    where the cut passes included; also where more pieces are asked for than the volume calls for."""
    rng = np.random.default_rng(seed)
    mesh, parts = _bent_link(rng)
    least = min(least, most)
    capsules = covering_capsules(mesh.vertices, mesh.faces, most=most, least=least)
    assert least <= len(capsules) <= most
    assert np.all(_covered(_surface_points(mesh, rng, 3000), capsules) <= 1e-12)
    for part in parts:
        inside = rng.dirichlet(np.ones(8) * 0.3, 1000) @ part.vertices
        assert np.all(_covered(inside, capsules) <= 1e-12)


def test_a_bent_link_takes_more_than_one_capsule_and_they_hold_less_room():
    rng = np.random.default_rng(7)
    mesh, _ = _bent_link(rng)
    one = covering_capsules(mesh.vertices, mesh.faces, most=1)
    more = covering_capsules(mesh.vertices, mesh.faces, most=3)
    volume = [sum(np.pi * c.radius ** 2 * np.linalg.norm(c.b - c.a) + 4 / 3 * np.pi * c.radius ** 3 for c in caps)
              for caps in (one, more)]
    assert len(more) > 1 and volume[1] <= 0.75 * volume[0]


# ----------------------------------------------------------------------------- what the capsules add
@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(sorted(MESHES)))
def test_no_point_of_a_capsule_lies_farther_from_the_mesh_hull_than_its_reach(seed, kind):
    rng = np.random.default_rng(seed)
    mesh = _placed(MESHES[kind](rng), rng)
    (capsule,) = covering_capsules(mesh.vertices, mesh.faces, most=1)
    hull = mesh.vertices[ConvexHull(mesh.vertices).vertices]
    directions = rng.normal(size=(60, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    ends = np.where(rng.uniform(size=(60, 1)) < 0.5, capsule.a, capsule.b)
    points = ends + capsule.radius * directions  # on the end spheres, where the distance is greatest
    farthest = max(_distance_to_hull(point, hull) for point in points)
    assert farthest <= capsule.reach + 1e-9
    # and not loose: no capsule point lies farther than r beyond its segment's ends, and the bound is within 1 mm of
    # the greatest distance (mesh_cover's tolerance)
    ends_out = max(_distance_to_hull(capsule.a, hull), _distance_to_hull(capsule.b, hull))
    assert capsule.reach <= ends_out + capsule.radius + 1e-3 + 1e-9


def test_a_cylinder_is_covered_by_the_capsule_round_its_axis():
    """The smallest capsule containing a cylinder (radius r, length L) along z: radius r (the rim), and a segment
    along the axis reaching no farther than the two flat ends."""
    mesh = trimesh.creation.cylinder(radius=0.05, height=0.3, sections=64)
    (capsule,) = covering_capsules(mesh.vertices, mesh.faces)
    assert capsule.radius == pytest.approx(0.05, abs=1e-9)
    axis = (capsule.b - capsule.a) / np.linalg.norm(capsule.b - capsule.a)
    assert abs(axis[2]) == pytest.approx(1.0, abs=1e-6)
    assert np.linalg.norm(capsule.b - capsule.a) == pytest.approx(0.3, abs=1e-6)
    assert 0.05 - 1e-9 <= capsule.reach <= 0.05 + 1e-3 + 1e-9  # the end caps stand r out of the flat ends


def test_a_ball_mesh_is_covered_by_one_ball_reaching_hardly_beyond_it():
    mesh = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    (capsule,) = covering_capsules(mesh.vertices, mesh.faces)
    assert np.linalg.norm(capsule.b - capsule.a) <= 1e-6 and capsule.radius == pytest.approx(0.1, rel=1e-9)
    assert capsule.reach <= 0.1 * 0.01 + 1e-3  # the icosphere's sag (under 1 %) and the bound's tolerance only


@pytest.mark.parametrize(("vertices", "faces", "fragment"), [
    (np.zeros((3, 2)), [[0, 1, 2]], "finite \\(V, 3\\)"),
    ([[0, 0, 0], [1, 0, 0], [np.nan, 0, 0]], [[0, 1, 2]], "finite"),
    (np.eye(3), [[0, 1, 3]], "vertex indices"),
    (np.eye(3), np.zeros((0, 3), dtype=int), "non-empty"),
])
def test_a_malformed_mesh_is_refused(vertices, faces, fragment):
    from redkin.errors import RedkinError

    with pytest.raises(RedkinError, match=fragment):
        covering_capsules(vertices, faces)


def test_least_outside_one_to_most_is_refused():
    from redkin.errors import RedkinError

    mesh = trimesh.creation.box(extents=[0.1, 0.2, 0.3])
    for most, least in ((2, 3), (3, 0)):
        with pytest.raises(RedkinError, match="least must be 1 to most"):
            covering_capsules(mesh.vertices, mesh.faces, most=most, least=least)


# ----------------------------------------------------------------------------- a URDF with mesh files
def _arm_package(folder: Path, scale: str = "1 1 1", extension: str = "stl") -> tuple[Path, str, dict]:
    """A ROS package ``arm`` with a three-joint URDF whose links' collisions are mesh files (one by a relative path,
    one by ``package://``, one scaled), and the meshes written in its ``meshes`` folder."""
    rng = np.random.default_rng(3)
    package = folder / "arm"
    (package / "meshes").mkdir(parents=True)
    (package / "urdf").mkdir()
    (package / "package.xml").write_text("<package format='2'><name>arm</name><version>0.0.0</version></package>")
    meshes = {"l1": _placed(MESHES["blob"](rng), rng), "l2": _bent_link(rng)[0], "l3": _placed(MESHES["box"](rng), rng)}
    for name, mesh in meshes.items():
        mesh.export(package / "meshes" / f"{name}.{extension}")
        # as stored (STL keeps float32)
        meshes[name] = trimesh.load(package / "meshes" / f"{name}.{extension}", force="mesh")
    names = {"l1": f"../meshes/l1.{extension}", "l2": f"package://arm/meshes/l2.{extension}",
             "l3": f"package://arm/meshes/l3.{extension}"}
    links = "".join(
        f'<link name="{name}"><collision><origin xyz="0.01 0.02 0.03" rpy="0.1 0.2 0.3"/><geometry>'
        f'<mesh filename="{names[name]}"{f" scale={chr(34)}{scale}{chr(34)}" if name == "l3" else ""}/>'
        "</geometry></collision></link>" for name in meshes)
    joints = "".join(
        f'<joint name="j{k}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="0 0.1 0.3" rpy="0.4 0 0.2"/><axis xyz="0 0 1"/>'
        '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
        for k, (parent, child) in enumerate([("base", "l1"), ("l1", "l2"), ("l2", "l3")], start=1))
    text = f'<robot name="meshy"><link name="base"/>{links}{joints}</robot>'
    path = package / "urdf" / "arm.urdf"
    path.write_text(text)
    return path, text, meshes


def _origin_pose() -> np.ndarray:
    pose = trimesh.transformations.euler_matrix(0.1, 0.2, 0.3, "sxyz")
    pose[:3, 3] = [0.01, 0.02, 0.03]
    return pose


@pytest.mark.parametrize("extension", ["stl", "dae"])
def test_a_urdf_with_mesh_files_gives_capsules_holding_each_mesh_where_the_urdf_puts_it(tmp_path, extension):
    path, text, meshes = _arm_package(tmp_path, scale="2 1 0.5", extension=extension)
    chain, body = urdf_body(path, "base", "l3")
    assert set(body.link) == {"l1", "l2", "l3"}
    assert any("l2" in note and "capsules" in note for note in body.notes)  # the bent link takes more than one
    rng = np.random.default_rng(0)
    for q in rng.uniform(-2, 2, (4, chain.n)):
        rows = posed(body, chain.frames(q))
        for name, mesh in meshes.items():
            vertices = mesh.vertices * (np.array([2.0, 1.0, 0.5]) if name == "l3" else 1.0)
            place = reference_fk(text, q, name) @ _origin_pose()
            world = vertices @ place[:3, :3].T + place[:3, 3]
            mine = [row for row, link in zip(rows, body.link) if link == name]
            gap = np.min([_distance_to_segment(world, row[2:5], row[5:8]) - row[1] for row in mine], axis=0)
            assert np.all(gap <= 1e-9), name
    notes = [note for note in body.notes if "mesh" in note]
    assert len(notes) == 3 and all("reaching up to" in note and "beyond" in note for note in notes)


def test_pieces_asks_a_link_for_more_capsules_that_still_hold_its_mesh(tmp_path):
    """``pieces``: a link's mesh covered by at least that many capsules, which still hold it where the URDF puts it;
    an unknown link or a count outside 1-3 is one line naming it."""
    path, text, meshes = _arm_package(tmp_path)
    chain, plain = urdf_body(path, "base", "l3")
    _, finer = urdf_body(path, "base", "l3", pieces={"l1": 3, "l3": 2})
    for name, least in (("l1", 3), ("l3", 2)):
        assert list(finer.link).count(name) >= max(least, list(plain.link).count(name))
    assert list(finer.link).count("l2") == list(plain.link).count("l2")
    q = np.random.default_rng(1).uniform(-2, 2, chain.n)
    rows = posed(finer, chain.frames(q))
    for name, mesh in meshes.items():
        place = reference_fk(text, q, name) @ _origin_pose()
        world = mesh.vertices @ place[:3, :3].T + place[:3, 3]
        mine = [row for row, link in zip(rows, finer.link) if link == name]
        assert np.all(np.min([_distance_to_segment(world, row[2:5], row[5:8]) - row[1] for row in mine], axis=0)
                      <= 1e-9), name
    for pieces, fragment in (({"nowhere": 2}, "'nowhere'"), ({"l1": 4}, "4 capsules on link 'l1'")):
        with pytest.raises(RobotDescriptionError, match=fragment) as caught:
            urdf_body(path, "base", "l3", pieces=pieces)
        assert "\n" not in str(caught.value)


def test_a_missing_mesh_or_package_is_one_line_naming_it(tmp_path):
    path, text, _ = _arm_package(tmp_path)
    (tmp_path / "arm" / "meshes" / "l3.stl").unlink()
    with pytest.raises(RobotDescriptionError, match=r"mesh file 'package://arm/meshes/l3\.stl' not found") as caught:
        urdf_body(path, "base", "l3")
    assert "\n" not in str(caught.value)
    other = path.parent / "alone.urdf"
    other.write_text(text.replace("package://arm/", "package://missing_pkg/"))
    with pytest.raises(RobotDescriptionError, match=r"package 'missing_pkg' of its meshes not found.*--package-path"):
        urdf_body(other, "base", "l3")


def test_a_package_path_finds_the_meshes_of_a_urdf_kept_elsewhere(tmp_path):
    path, text, _ = _arm_package(tmp_path / "packages")
    elsewhere = tmp_path / "copy.urdf"
    elsewhere.write_text(text.replace("../meshes/l1.stl", "package://arm/meshes/l1.stl"))
    with pytest.raises(RobotDescriptionError, match="ROS package 'arm'"):
        urdf_body(elsewhere, "base", "l3")
    _, found = urdf_body(elsewhere, "base", "l3", package_paths=[tmp_path / "packages"])
    _, original = urdf_body(path, "base", "l3")
    np.testing.assert_array_equal(found.radius, original.radius)


def test_a_file_that_is_not_a_mesh_is_one_line(tmp_path):
    """The line names the description and the link as well as the mesh file."""
    path, _, _ = _arm_package(tmp_path)
    (tmp_path / "arm" / "meshes" / "l2.stl").write_text("solid nothing\nthis is not a mesh\n")
    with pytest.raises(RobotDescriptionError, match=r"l2\.stl") as caught:
        urdf_body(path, "base", "l3")
    assert "\n" not in str(caught.value) and str(caught.value).startswith(f"{path}: link 'l2'")


def test_a_bad_scale_and_a_missing_mesh_extra_are_one_line(tmp_path, monkeypatch):
    from redkin.errors import RedkinError

    path, text, _ = _arm_package(tmp_path, scale="1 0 1")
    with pytest.raises(RobotDescriptionError, match=r"mesh scale \[1\.0, 0\.0, 1\.0\] must be one or three"):
        urdf_body(path, "base", "l3")
    path.write_text(text.replace('scale="1 0 1"', 'scale="1 2"'))
    with pytest.raises(RobotDescriptionError, match="Invalid vector length"):  # the URDF parser's own word
        urdf_body(path, "base", "l3")
    path.write_text(text.replace('scale="1 0 1"', 'scale="2 2 2"'))
    monkeypatch.setitem(__import__("sys").modules, "trimesh", None)
    with pytest.raises(RedkinError, match=r'needs trimesh, in the mesh extra: pip install "redkin\[mesh\]"'):
        urdf_body(path, "base", "l3")


def test_arm_angles_in_a_cell_reads_a_urdf_whose_links_are_meshes(capsys, tmp_path):
    """The iiwa14 with its links 3 and 4 as mesh files of a package kept apart from the URDF: ``--package-path``
    finds them, the JSON sets are the API's with the same body, and without it the one line names the package."""
    import json

    import redkin
    from redkin.collision import collision_free_arm_angles, read_scene
    from redkin.examples import resolve
    from tests.support.cli import run

    package = tmp_path / "packages" / "iiwa_meshes"
    (package / "meshes").mkdir(parents=True)
    (package / "package.xml").write_text("<package format='2'><name>iiwa_meshes</name></package>")
    rng = np.random.default_rng(11)
    text = resolve("iiwa14.urdf").read_text()
    for link in ("lbr_iiwa_link_3", "lbr_iiwa_link_4"):
        _bent_link(rng)[0].apply_scale(0.5).export(package / "meshes" / f"{link}.stl")
        text = text.replace(f'<link name="{link}"/>', f'<link name="{link}"><collision><geometry><mesh filename='
                            f'"package://iiwa_meshes/meshes/{link}.stl"/></geometry></collision></link>')
    urdf = tmp_path / "iiwa.urdf"
    urdf.write_text(text)
    scene = tmp_path / "cell.yaml"
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.2], radius: 0.05}\n")
    arm = redkin.arm(str(urdf))
    pose = arm.fk(np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1]))
    argv = ["arm-angles", str(urdf), "--position", *map(repr, pose[:3, 3].tolist()),
            "--rotation", *map(repr, pose[:3, :3].ravel().tolist()), "--scene", str(scene), "--json"]
    code, out, err = run(capsys, argv)
    assert code == 2 and out == "" and err.count("\n") == 1 and "'iiwa_meshes'" in err and "--package-path" in err
    code, out, _ = run(capsys, [*argv, "--package-path", str(tmp_path / "packages")])
    assert code == 0
    report = json.loads(out)
    _, body = urdf_body(urdf, package_paths=[tmp_path / "packages"])
    assert report["collision"]["capsules"] == len(body) >= 2
    assert sum("mesh" in note and "reaching up to" in note for note in report["collision"]["notes"]) == 2
    expected = collision_free_arm_angles(arm, pose, body, read_scene(scene))
    assert np.allclose(report["branches"]["+++"], expected.free[0].bounds.reshape(-1, 2), atol=1e-12)


# ----------------------------------------------------------------------------- mesh obstacles
def _inside_boxes(points: np.ndarray, boxes) -> np.ndarray:
    """Per point, whether some box holds it (in the box's own axes, within rounding)."""
    inside = np.zeros(len(points), dtype=bool)
    for box in boxes:
        local = (points - box.center) @ box.rotation
        inside |= np.all(np.abs(local) <= box.size / 2 + 1e-12, axis=1)
    return inside


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from([*sorted(MESHES), "bent"]), most=st.integers(1, 3))
def test_the_boxes_contain_the_mesh_and_their_reach_is_their_farthest_corner(seed, kind, most):
    from redkin.collision import covering_boxes

    rng = np.random.default_rng(seed)
    mesh = _bent_link(rng)[0] if kind == "bent" else _placed(MESHES[kind](rng), rng)
    boxes = covering_boxes(mesh.vertices, mesh.faces, most=most)
    assert 1 <= len(boxes) <= most
    assert np.all(_inside_boxes(_surface_points(mesh, rng, 2000), boxes))
    if kind != "bent":  # convex: points of the solid
        assert np.all(_inside_boxes(rng.dirichlet(np.ones(len(mesh.vertices)) * 0.2, 500) @ mesh.vertices, boxes))
    if len(boxes) == 1:  # the reach of the one box: the farthest of its corners from the mesh's hull, exactly
        (box,) = boxes
        hull = mesh.vertices[ConvexHull(mesh.vertices).vertices]
        corners = box.center + (np.array(np.meshgrid(*[[-0.5, 0.5]] * 3)).reshape(3, -1).T * box.size) @ box.rotation.T
        assert box.reach == pytest.approx(max(_distance_to_hull(c, hull) for c in corners), abs=1e-7)
        assert np.allclose(box.rotation.T @ box.rotation, np.eye(3)) and np.linalg.det(box.rotation) > 0


def _fixture(folder: Path) -> tuple[Path, object]:
    """A bent fixture's STL beside a scene file."""
    mesh = _bent_link(np.random.default_rng(4))[0]
    mesh.export(folder / "fixture.stl")
    return folder / "fixture.stl", trimesh.load(folder / "fixture.stl", force="mesh")


def test_a_mesh_obstacle_becomes_boxes_holding_it_where_the_pose_puts_it(tmp_path):
    from redkin.collision import read_scene

    _, mesh = _fixture(tmp_path)
    turn = trimesh.transformations.rotation_matrix(0.7, [0.3, -0.2, 0.9])
    turn[:3, 3] = [0.5, -0.1, 0.2]
    rows = "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in turn) + "]"
    (tmp_path / "cell.yaml").write_text(
        "margin: 0.02\nobstacles:\n"
        f"  - {{name: fixture, type: mesh, file: fixture.stl, pose: {rows}, scale: [2, 1, 1]}}\n"
        "  - {name: post, type: capsule, a: [0, 0, 0], b: [0, 0, 1], radius: 0.05}\n")
    scene = read_scene(tmp_path / "cell.yaml")
    parts = [name for name in scene.names if name.startswith("fixture")]
    assert scene.names[-1] == "post" and (parts == ["fixture"] or parts == [f"fixture [{k}/{len(parts)}]"
                                                                            for k in range(1, len(parts) + 1)])
    placed = (mesh.vertices * [2, 1, 1]) @ turn[:3, :3].T + turn[:3, 3]
    from redkin.collision import signed_distance
    from redkin.collision.primitives import sphere

    points = np.stack([sphere(point, 0.0) for point in placed])
    depth = np.min([signed_distance(points, np.broadcast_to(scene.shape(name), points.shape)).distance
                    for name in parts], axis=0)
    assert np.all(depth <= 1e-9)  # every vertex of the placed, scaled mesh is in some box
    assert len(scene.notes) == 1 and "'fixture'" in scene.notes[0] and "reaching up to" in scene.notes[0]


@pytest.mark.parametrize(("field", "fragment"), [
    ("file: missing.stl", "mesh file 'missing.stl' not found"),
    ("file: fixture.stl, pose: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "pose must be a 4x4"),
    ("file: fixture.stl, pose: [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]", "pose rotation"),
    ("file: fixture.stl, scale: [1, 1]", "mesh scale"),
    ("file: fixture.stl, pose: [[1, 0, 0, .nan], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]", "pose must be finite"),
    ("file: 3", "file must be a mesh file's path"),
    ("file: meshes", "mesh file 'meshes' is a folder"),
    ("file: nan.stl", "nan.stl: the mesh has vertices that are not finite"),  # not its triangle dropped in silence
])
def test_a_bad_mesh_obstacle_is_one_line_naming_it(tmp_path, field, fragment):
    from redkin.collision import read_scene

    _fixture(tmp_path)
    (tmp_path / "meshes").mkdir()
    good, bad = ["0 0 0", "1 0 1", "0 1 1"], ["nan 0 0", "1 0 0", "0 1 0"]
    (tmp_path / "nan.stl").write_text("solid t\n" + "".join(
        "facet normal 0 0 1\nouter loop\n" + "".join(f"vertex {v}\n" for v in corners) + "endloop\nendfacet\n"
        for corners in (bad, good)) + "endsolid t\n")
    (tmp_path / "cell.yaml").write_text(f"obstacles:\n  - {{name: jig, type: mesh, {field}}}\n")
    with pytest.raises(RobotDescriptionError, match=re.escape(fragment)) as caught:
        read_scene(tmp_path / "cell.yaml")
    assert "\n" not in str(caught.value) and "'jig'" in str(caught.value)


def test_arm_angles_names_the_mesh_obstacle_that_blocks_the_elbow(capsys, tmp_path):
    """A mesh ball round the iiwa14's elbow: the elbow's arm angles are removed by the mesh's box, which the
    text and JSON name, and the scene's note is printed."""
    import json

    import redkin
    from tests.support.cli import run

    arm = redkin.arm("kuka-iiwa14")
    q = np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.8, 0.1])
    elbow = arm.chain.frames(q)[4][:3, 3]
    trimesh.creation.icosphere(subdivisions=2, radius=0.05).apply_translation(elbow).export(tmp_path / "ball.stl")
    (tmp_path / "cell.yaml").write_text("margin: 0.01\nobstacles:\n  - {name: ball, type: mesh, file: ball.stl}\n")
    (tmp_path / "body.yaml").write_text("capsules:\n  link_4: [{a: [0, 0, 0], b: [0, 0, 0], radius: 0.06}]\n")
    pose = arm.fk(q)
    argv = ["arm-angles", "kuka-iiwa14", "--position", *map(repr, pose[:3, 3].tolist()),
            "--rotation", *map(repr, pose[:3, :3].ravel().tolist()), "--scene", str(tmp_path / "cell.yaml"),
            "--body", str(tmp_path / "body.yaml")]
    code, out, _ = run(capsys, [*argv, "--json"])
    assert code == 0
    report = json.loads(out)
    assert any(s["cause"] == "collision" and s["obstacle"] == "ball" for s in report["blocked"])
    assert report["collision"]["scene_notes"][0].startswith("obstacle 'ball': mesh 'ball.stl' covered by 1 box")
    code, out, _ = run(capsys, argv)
    assert code == 0 and "meets ball" in out and "scene: obstacle 'ball'" in out


def test_a_mesh_file_is_covered_once_and_read_back_exactly(tmp_path, monkeypatch):
    """The second reading of a URDF takes its covers from the cache: the same capsules, bit for bit, without fitting;
    an edited mesh, a cover file that does not read back, or a folder that cannot be written costs only the time."""
    import redkin.collision.mesh_cache as mesh_cache

    path, _, _ = _arm_package(tmp_path)
    _, first = urdf_body(path, "base", "l3")
    kept = sorted(cache_folder("mesh-covers").glob("*.json"))
    assert len(kept) == 3  # one cover per mesh file

    def refuse(*_args, **_kwargs):
        raise AssertionError("fitted again")

    monkeypatch.setattr(mesh_cache, "covering_capsules", refuse)
    _, again = urdf_body(path, "base", "l3")
    for field in ("a", "b", "radius"):
        np.testing.assert_array_equal(getattr(again, field), getattr(first, field))
    assert again.notes == first.notes
    kept[0].write_text("{not json")  # read back: no; fitted again
    with pytest.raises(AssertionError, match="fitted again"):
        urdf_body(path, "base", "l3")
    monkeypatch.undo()
    monkeypatch.setenv("REDKIN_CACHE_DIR", str(tmp_path / "arm" / "package.xml"))  # a file: no folder there
    _, unwritable = urdf_body(path, "base", "l3")
    np.testing.assert_array_equal(unwritable.radius, first.radius)
    monkeypatch.setenv("REDKIN_CACHE_DIR", str(tmp_path / "cache"))
    urdf_body(path, "base", "l3")  # the three covers kept again, in a folder that can be written
    mesh = trimesh.load(tmp_path / "arm" / "meshes" / "l3.stl", force="mesh")
    mesh.apply_scale(1.5).export(tmp_path / "arm" / "meshes" / "l3.stl")  # an edited mesh: its own cover
    fitted = []
    real = mesh_cache.covering_capsules
    monkeypatch.setattr(mesh_cache, "covering_capsules", lambda *args, **kw: fitted.append(1) or real(*args, **kw))
    urdf_body(path, "base", "l3")
    assert len(fitted) == 1 and len(list(cache_folder("mesh-covers").glob("*.json"))) == 4
