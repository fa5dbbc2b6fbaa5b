"""Workspace maps in a cell (issue 40): reachability inside the cell, from the certified collision-free arm angles
(q7 on the Franka class).

Laws: every entry equals the measure of :func:`redkin.collision.collision_free_arm_angles` (or
:func:`redkin.collision.collision_free_q7`) at that pose and branch, and is at most the limits-only map's; the local
scheduler equals a cluster; a store resumes only the same cell.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("dask")
pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")

import redkin  # noqa: E402
from redkin.collision import (  # noqa: E402
    builtin_body,
    collision_free_arm_angles,
    collision_free_q7,
    collision_free_set,
    scene_of,
)
from redkin.srs import pose_from  # noqa: E402
from redkin.workspace import workspace_map  # noqa: E402
from tests.support.cli import run  # noqa: E402

EXTENT = [-0.2, 0.6, -0.4, 0.4, 0.1, 0.9]
SCENE = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.4, 0.3, 0], "b": [0.4, 0.3, 1.2], "radius": 0.05},
    {"name": "table", "type": "box", "center": [0.6, 0, -0.06], "size": [1.2, 1.0, 0.1]},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.3, 0.7], "radius": 0.12}]}


@pytest.fixture(scope="module")
def cell():
    arm = redkin.get_robot("kuka-iiwa14")
    return arm, builtin_body("kuka-iiwa14", arm), scene_of(SCENE, "cell.yaml")


@pytest.fixture(scope="module")
def maps(cell, tmp_path_factory):
    arm, body, scene = cell
    folder = tmp_path_factory.mktemp("maps")
    free = workspace_map(arm, folder / "free.zarr", EXTENT, 3, 4, body=body, scene=scene)
    plain = workspace_map(arm, folder / "plain.zarr", EXTENT, 3, 4, chunk=free.chunks and 3)
    return free, plain


def test_each_entry_is_the_certified_free_set_and_at_most_the_limits_set(cell, maps):
    arm, body, scene = cell
    free, plain = maps
    with xr.open_zarr(free.path, chunks=None) as dataset, xr.open_zarr(plain.path, chunks=None) as limits:
        measure, bound = dataset["measure"].values, limits["measure"].values
        x, y, z = (dataset[axis].values for axis in "xyz")
        rotations = dataset["rotation"].values
        assert "certified feasible" in dataset.attrs["title"] and "collision-free in the cell" in dataset.attrs["title"]
        assert dataset.attrs["cell"]["scene"]["obstacles"] == ["post", "table", "lamp"]
    assert np.all(measure <= bound + 1e-9)
    assert 0 < (measure.max(axis=-1) > 0).sum() < (bound.max(axis=-1) > 0).sum() + 1
    assert np.any(measure < bound - 1e-3)  # the cell takes some arm angles away
    classified = redkin.arm(arm)
    rng = np.random.default_rng(5)
    for i, j, k, o in np.argwhere(bound.max(axis=-1) > 0)[rng.choice(int((bound.max(axis=-1) > 0).sum()), 6,
                                                                      replace=False)]:
        pose = pose_from(np.array([x[i], y[j], z[k]]), rotations[o])
        expected = collision_free_arm_angles(classified, pose, body, scene)
        for column, arcs in enumerate(expected.free):
            length = float(np.sum(arcs.bounds[:, 1] - arcs.bounds[:, 0] + np.where(arcs.wraps, 2 * np.pi, 0.0)))
            assert measure[i, j, k, o, column] == pytest.approx(length if length > 1e-12 else 0.0, abs=1e-9)


def test_a_store_resumes_only_the_same_cell(cell, maps, tmp_path):
    arm, body, scene = cell
    free, _ = maps
    again = workspace_map(arm, free.path, EXTENT, 3, 4, body=body, scene=scene)
    assert again.computed == 0
    moved = scene_of({**SCENE, "margin": 0.05}, "cell.yaml")
    with pytest.raises(ValueError, match=r"holds a map with other parameters \(another cell \(the body, the scene "
                                         r"or its margin\)\); choose another path"):
        workspace_map(arm, free.path, EXTENT, 3, 4, body=body, scene=moved)
    with pytest.raises(ValueError, match=r"\(another chunk, orientations, resolution\)"):
        workspace_map(arm, free.path, EXTENT, 4, 5, body=body, scene=scene)


def test_a_cell_needs_both_the_body_and_the_scene(cell, tmp_path):
    arm, _, scene = cell
    with pytest.raises(ValueError, match="needs both the arm's body and the scene"):
        workspace_map(arm, tmp_path / "m.zarr", EXTENT, 3, 4, scene=scene)


def test_a_nearly_srs_arm_maps_its_own_certified_sets_in_a_cell(tmp_path):
    """On the Gen3 in a cell each entry is the measure of the real arm's certified collision-free arm angles at that
    pose and branch (not the neighbour's, as its maps without a cell are); the model says so, and a store of that
    model is not resumed by a map without the cell."""
    arm = redkin.get_robot("kinova-gen3")
    body, scene = builtin_body("kinova-gen3", arm), scene_of(SCENE, "cell.yaml")
    free = workspace_map(arm, tmp_path / "free.zarr", EXTENT, 2, 2, body=body, scene=scene)
    assert free.model == "certified, the real arm" and free.model_error == "" and free.chunks == 1
    assert free.reachable_poses > 0
    with xr.open_zarr(free.path, chunks=None) as dataset:
        measure = dataset["measure"].values
        x, y, z = (dataset[axis].values for axis in "xyz")
        rotations = dataset["rotation"].values
        assert dataset.attrs["model"] == "certified, the real arm" and "certified" in dataset.attrs["title"]
    classified = redkin.arm(arm)
    checked = 0
    for i, j, k, o in np.argwhere(measure.max(axis=-1) > 0)[:3]:
        expected = collision_free_set(classified, pose_from(np.array([x[i], y[j], z[k]]), rotations[o]), body, scene)
        for column, arcs in enumerate(expected.free):
            length = float(np.sum(arcs.bounds[:, 1] - arcs.bounds[:, 0] + np.where(arcs.wraps, 2 * np.pi, 0.0)))
            assert measure[i, j, k, o, column] == pytest.approx(length if length > 1e-12 else 0.0, abs=1e-9)
        checked += 1
    assert checked
    with pytest.raises(ValueError, match="holds a map with other parameters"):
        workspace_map(arm, free.path, EXTENT, 2, 2)


def test_the_franka_class_maps_its_certified_q7_sets(tmp_path):
    """On the FR3 each entry is the measure of collision_free_q7's intervals at that pose and branch, at most the
    limits-only map's; the default chunk of the class is small (its poses take a good part of a second)."""
    arm = redkin.get_robot("franka-fr3")
    body, scene = builtin_body("franka-fr3", arm), scene_of(SCENE, "cell.yaml")
    free = workspace_map(arm, tmp_path / "free.zarr", EXTENT, 2, 2, body=body, scene=scene)
    plain = workspace_map(arm, tmp_path / "plain.zarr", EXTENT, 2, 2)
    assert free.chunks == 1 and free.reachable_poses > 0
    with xr.open_zarr(free.path, chunks=None) as dataset, xr.open_zarr(plain.path, chunks=None) as limits:
        measure, bound = dataset["measure"].values, limits["measure"].values
        x, y, z = (dataset[axis].values for axis in "xyz")
        rotations = dataset["rotation"].values
        assert dataset.attrs["parameter"] == "q7"
    assert np.all(measure <= bound + 1e-9)
    classified = redkin.arm(arm)
    for i, j, k, o in np.argwhere(bound.max(axis=-1) > 0)[:3]:
        expected = collision_free_q7(classified, pose_from(np.array([x[i], y[j], z[k]]), rotations[o]), body, scene)
        for column, arcs in enumerate(expected.free):
            length = float(np.sum(arcs.bounds[:, 1] - arcs.bounds[:, 0]))
            assert measure[i, j, k, o, column] == pytest.approx(length if length > 1e-12 else 0.0, abs=1e-9)


@pytest.mark.slow
def test_the_command_maps_a_named_model_in_a_cell_with_its_built_in_body(tmp_path, capsys):
    import yaml

    (tmp_path / "cell.yaml").write_text(yaml.safe_dump(SCENE))
    argv = ["workspace", "kuka-iiwa14", "--out", str(tmp_path / "out"), "--extent", *map(str, EXTENT),
            "--resolution", "3", "--orientations", "4", "--scene", str(tmp_path / "cell.yaml"), "--quiet"]
    code, out, _ = run(capsys, [*argv, "--json"])
    assert code == 0
    summary = json.loads(out)
    assert summary["cell"]["obstacles"] == ["post", "table", "lamp"] and summary["cell"]["capsules"] == 8
    code, _, err = run(capsys, ["workspace", "humanoid-right", "--out", str(tmp_path / "h"), "--extent",
                                *map(str, EXTENT), "--resolution", "3", "--scene", str(tmp_path / "cell.yaml")])
    assert code == 2 and err.count("\n") == 1 and "humanoid" in err


def test_the_cluster_gives_the_local_schedulers_map_in_a_cell(cell, maps, client, tmp_path):
    """The body and the scene travel to the workers with the tasks; the values are the local run's, bit for bit."""
    arm, body, scene = cell
    free, _ = maps
    remote = workspace_map(arm, tmp_path / "remote.zarr", EXTENT, 3, 4, body=body, scene=scene, client=client)
    with xr.open_zarr(free.path, chunks=None) as local, xr.open_zarr(remote.path, chunks=None) as other:
        for name in ("measure", "reachability", "redundancy"):
            np.testing.assert_array_equal(local[name].values, other[name].values, err_msg=name)
