"""redkin.workspace: the orientation set, the grid, and map entries against direct feasible-set calls."""

import numpy as np
import pytest

pytest.importorskip("dask")
pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")

from redkin.arms import arm  # noqa: E402
from redkin.errors import SizeLimitError  # noqa: E402
from redkin.franka import feasible_q7, franka_geometry  # noqa: E402
from redkin.franka.feasible import q7_domain  # noqa: E402
from redkin.models import get_robot  # noqa: E402
from redkin.reproduce import printed  # noqa: E402
from redkin.srs import BRANCHES, feasible_arm_angles, pose_from, reachable  # noqa: E402
from redkin.workspace import (  # noqa: E402
    feasible_measures,
    reachability_index,
    redundancy_index,
    super_fibonacci_rotations,
    workspace_grid,
    workspace_map,
)
from redkin.workspace.grid import MAX_CHUNKS, MAX_POSES  # noqa: E402

EXTENTS = {"pa10-7c": [-0.9, 0.9, -0.9, 0.9, -0.5, 1.3], "barrett-wam": [-0.8, 0.8, -0.8, 0.8, -0.6, 1.0]}


def test_super_fibonacci_rotations_are_deterministic_proper_and_spread():
    rotations = super_fibonacci_rotations(400)
    assert np.array_equal(rotations, super_fibonacci_rotations(400))
    np.testing.assert_allclose(rotations @ rotations.swapaxes(-1, -2), np.broadcast_to(np.eye(3), (400, 3, 3)),
                               atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(rotations), 1.0, atol=1e-12)
    # the Haar mean of R is 0; every random rotation is near one of the set (covering radius)
    assert np.abs(rotations.mean(axis=0)).max() < 0.01
    samples = super_fibonacci_rotations(1)[0] @ _random_rotations(np.random.default_rng(3), 300)
    cosine = (np.einsum("sij,nij->sn", samples, rotations) - 1.0) / 2.0
    assert np.degrees(np.arccos(np.clip(cosine.max(axis=1), -1, 1))).max() < 35.0


def _random_rotations(rng: np.random.Generator, count: int) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(count, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=-2, axis2=-1))[..., None, :]
    return q * np.linalg.det(q)[:, None, None]


def test_grid_chunks_cover_every_point_once():
    grid = workspace_grid([-1, 1, -2, 2, 0, 1], 7, 10, chunk=3)
    assert grid.chunk_counts == (3, 3, 3)
    seen = np.zeros((7, 7, 7), dtype=int)
    for index in grid.chunk_indices():
        seen[grid.chunk_slices(index)] += 1
        positions = grid.chunk_positions(index)
        assert positions.shape[:3] == seen[grid.chunk_slices(index)].shape
    assert np.all(seen == 1)
    x, y, z = grid.axes
    assert x[0] == -1 and x[-1] == 1 and y[-1] == 2 and z[0] == 0
    assert workspace_grid([-1, 1, -1, 1, -1, 1], 50, 500).chunk == 8  # 8^3 x 500 <= 262144 < 9^3 x 500


@pytest.mark.parametrize("extent, message", [
    ([0, 1, 0, 1, 0], "6 numbers"),
    ([1, 0, 0, 1, 0, 1], "xmin must be below xmax"),
    ([0, 1, 0, np.nan, 0, 1], "finite"),
])
def test_grid_rejects_bad_extents(extent, message):
    with pytest.raises(ValueError, match=message):
        workspace_grid(extent, 4, 10)


def test_grid_rejects_bad_sizes():
    with pytest.raises(ValueError, match=r"resolution must be an integer in 2\.\.1000"):
        workspace_grid([0, 1, 0, 1, 0, 1], 1, 10)
    with pytest.raises(ValueError, match=r"chunk must be an integer in 1\.\.4"):
        workspace_grid([0, 1, 0, 1, 0, 1], 4, 10, chunk=5)
    with pytest.raises(ValueError, match=r"orientations must be an integer in 1\.\.20000"):  # as workspace_map
        workspace_grid([0, 1, 0, 1, 0, 1], 4, 0)


def test_grid_refuses_more_poses_or_chunks_than_its_limits():
    """Each size within its own range, the product beyond what can be computed: refused before anything is made (a
    1000^3 grid at 20 000 orientations made 1.25e8 chunk indices, and ran out of memory in silence)."""
    box = [0, 1, 0, 1, 0, 1]
    turns = MAX_POSES // 1000**3  # 1000^3 grid points at this many orientations: the limit exactly
    assert workspace_grid(box, 1000, turns).resolution == 1000
    with pytest.raises(SizeLimitError, match=r"more than 1e\+10 .*lower the resolution or the orientations"):
        workspace_grid(box, 1000, turns + 1)
    with pytest.raises(SizeLimitError, match="poses"):
        workspace_grid(box, 1000, 20_000)
    side = round(MAX_CHUNKS ** (1 / 3))
    assert workspace_grid(box, side, 1, chunk=1).chunk_counts == (side, side, side)
    with pytest.raises(SizeLimitError, match="give a larger chunk"):
        workspace_grid(box, side + 1, 1, chunk=1)


def test_map_refuses_an_arm_without_a_redundancy_parameter(tmp_path):
    with pytest.raises(ValueError, match=r"needs a redundancy parameter.*'sawyer' is not S-R-S"):
        workspace_map(get_robot("sawyer.urdf"), tmp_path / "map.zarr", EXTENTS["pa10-7c"], 3, 2)
    assert not (tmp_path / "map.zarr").exists()


@pytest.mark.parametrize("robot", ["fr3.urdf", "xarm7.urdf"])
def test_a_franka_class_map_measures_the_exact_q7_sets(robot, tmp_path):
    """The FR3 and the xArm7 (joint 7 over +-2 pi) are mapped with their exact q7 sets [F8]-[F9]: each entry is
    the length of franka.feasible_q7's arcs, the redundancy index divided by joint 7's range, and the store names
    the parameter."""
    chain = get_robot(robot)
    extent = [0.2, 0.5, -0.2, 0.2, 0.2, 0.6]
    run = workspace_map(chain, tmp_path / "map.zarr", extent, 3, 4)
    domain = q7_domain(franka_geometry(chain))
    with xr.open_zarr(run.path, chunks=None) as dataset:
        measure = dataset["measure"].values
        x, y, z = (dataset[axis].values for axis in "xyz")
        rotations = dataset["rotation"].values
        assert dataset.attrs["parameter"] == "q7" and dataset.attrs["parameter_range"] == list(domain)
        assert "q7" in dataset["measure"].attrs["long_name"]
        np.testing.assert_allclose(dataset["redundancy"].values, redundancy_index(measure, domain[1] - domain[0]))
    assert 0.0 < run.reachable_poses <= run.reachable_positions <= 1.0
    assert 0.0 < np.count_nonzero(measure) < measure.size
    for i, j, k, o in list(np.ndindex(3, 3, 3, 4))[::7]:
        pose = pose_from(np.array([x[i], y[j], z[k]]), rotations[o])
        sets = feasible_q7(chain, pose)
        for column, arcs in enumerate(sets.arcs):
            expected = float(np.sum(arcs[:, 1] - arcs[:, 0])) if len(arcs) else 0.0
            assert measure[i, j, k, o, column] == pytest.approx(expected, abs=1e-9)
    assert measure.max() <= domain[1] - domain[0]


@pytest.mark.parametrize("robot", sorted(EXTENTS))
def test_map_entries_equal_direct_feasible_arm_angles(robot, tmp_path):
    arm = get_robot(robot)
    run = workspace_map(arm, tmp_path / "map.zarr", EXTENTS[robot], 5, 12, chunk=3)
    assert (run.chunks, run.computed, run.positions) == (8, 8, 125)
    with xr.open_zarr(run.path, chunks=None) as dataset:
        measure = dataset["measure"].values
        x, y, z = (dataset[axis].values for axis in "xyz")
        rotations = dataset["rotation"].values
        np.testing.assert_array_equal(rotations, super_fibonacci_rotations(12))
        assert dataset["measure"].dims == ("x", "y", "z", "orientation", "branch")
        assert dataset.attrs["branches"] == [str(b) for b in BRANCHES] and dataset["x"].attrs["units"] == "m"
        assert dataset.attrs["arm"]["name"] == arm.name and bool(dataset["chunk_complete"].values.all())
        np.testing.assert_array_equal(dataset["reachability"].values, reachability_index(measure))
        np.testing.assert_array_equal(dataset["redundancy"].values, redundancy_index(measure))
    assert 0.0 < run.reachable_poses < run.reachable_positions < 1.0
    rng = np.random.default_rng(14)
    reached = np.argwhere(measure.max(axis=-1) > 0)
    samples = np.concatenate([reached[rng.choice(len(reached), 12, replace=False)],
                              np.argwhere(measure.max(axis=-1) == 0)[:4]])
    for i, j, k, o in samples:
        pose = pose_from(np.array([x[i], y[j], z[k]]), rotations[o])
        for column, branch in enumerate(BRANCHES):
            expected = 0.0
            if reachable(arm, pose):
                expected = feasible_arm_angles(arm, pose, branch).feasible.length  # arcs may wrap past pi
            assert measure[i, j, k, o, column] == pytest.approx(expected, abs=1e-9)
    # one position's indices from their definitions, over all orientations
    i, j, k = reached[0][:3]
    best = measure[i, j, k].max(axis=-1)
    assert reachability_index(measure)[i, j, k] == np.mean(best > 0)
    assert redundancy_index(measure)[i, j, k] == pytest.approx(best[best > 0].mean() / (2 * np.pi))


def test_indices_of_unreachable_and_free_positions():
    measure = np.zeros((2, 3, 8))
    measure[1, 0, 2] = 2 * np.pi
    measure[1, 1, 5] = np.pi
    np.testing.assert_allclose(reachability_index(measure), [0.0, 2 / 3])
    np.testing.assert_allclose(redundancy_index(measure), [0.0, 0.75])


def test_gamma_experiment_of_paper_000_is_one_line_of_the_map():
    """Paper 000 section 6.2.2: with psi controlled, the tool at x = (0.65, 0, 0.5) m turns by |gamma| < 147.693 deg."""
    gamma = np.radians(np.concatenate([np.arange(-180.0, 180.0, 2.0), [-147.8, -147.6, 147.6, 147.8]]))
    c, s = np.cos(gamma), np.sin(gamma)
    rotations = np.zeros((len(gamma), 3, 3))
    # [000 eq. 41] turned about z
    rotations[:, 0, 0], rotations[:, 0, 1], rotations[:, 1, 0], rotations[:, 1, 1] = -c, -s, -s, c
    rotations[:, 2, 2] = -1.0
    line = feasible_measures(arm("pa10-7c"), np.array([[0.65, 0.0, 0.5]]), rotations)[0, :, 0]
    np.testing.assert_array_equal(line > 0.0, np.abs(np.degrees(gamma)) < printed.SECTION_6_2_2_GAMMA)


def test_chunk_tasks_call_the_function_once_per_index_with_the_shared_values():
    import dask

    from redkin.workspace.run import _chunk_tasks

    shared = (np.arange(3.0), "store")
    tasks = _chunk_tasks(lambda values, name, index: (values.sum(), name, index), shared, [(0, 0, 0), (1, 0, 2)], "t")
    assert len({task.key for task in tasks}) == 2
    assert dask.compute(*tasks, scheduler="sync") == ((3.0, "store", (0, 0, 0)), (3.0, "store", (1, 0, 2)))
