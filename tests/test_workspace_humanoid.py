"""The thesis 001 humanoid's 3-D map: a plane of it is the 2-D map, local = a 2-process LocalCluster, runs resume,
and `redkin workspace humanoid-right` writes the map, its slices and its summary."""

import json
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")
distributed = pytest.importorskip("distributed")

from redkin.cli.main import main  # noqa: E402
from redkin.models import get_robot  # noqa: E402
from redkin.torso_arm import humanoid_arm  # noqa: E402
from redkin.torso_arm.maps import best_dual_arm_map, best_manipulability_map, plane_grid  # noqa: E402
from redkin.workspace.humanoid import VARIABLES, humanoid_map, humanoid_of  # noqa: E402
from redkin.workspace.store import completed_chunks  # noqa: E402
from tests.conftest import default_dask_scheduler  # noqa: E402

EXTENT = [-0.3, 1.0, -0.7, 0.7, -0.6, 0.6]
SIZES = {"resolution": 5, "samples": (5, 6), "chunk": 2}  # 27 chunks, 125 positions
NAMES = (*VARIABLES, "x", "y", "z", "theta1", "phi", "chunk_complete")
#: Seconds a map on the cluster may take before the test fails instead of hanging.
TIMEOUT = 300


def _within(seconds, function, *args, **kwargs):
    """``function(*args, **kwargs)``, failing the test if it takes longer than ``seconds``."""
    with ThreadPoolExecutor(1) as pool:
        return pool.submit(function, *args, **kwargs).result(timeout=seconds)


def _arrays(path):
    with xr.open_zarr(path, chunks=None) as dataset:
        return {name: dataset[name].values for name in NAMES}


@pytest.fixture(scope="module")
def chain():
    return get_robot("humanoid-right")


@pytest.fixture(scope="module")
def reference(chain, tmp_path_factory):
    """The map on the local scheduler, in one uninterrupted run."""
    run = humanoid_map(chain, tmp_path_factory.mktemp("reference") / "map.zarr", EXTENT, **SIZES)
    assert run.computed == run.chunks == 27
    return _arrays(run.path)


def _plane(arrays, axis, k):
    """The 3-D arrays on the plane ``axis = axis[k]`` as (v, u) images, the 2-D maps' layout, and its plane_grid."""
    fixed = "xyz".index(axis)
    u, v = (a for a in "xyz" if a != axis)
    grid = plane_grid(f"{axis}={float(arrays[axis][k])!r}",
                      (arrays[u][0], arrays[u][-1], arrays[v][0], arrays[v][-1]), len(arrays[u]))
    return {name: np.take(arrays[name], k, axis=fixed).T for name in VARIABLES}, grid


@pytest.mark.parametrize("axis,k", [("z", 2), ("y", 1), ("x", 3)])
def test_a_plane_of_the_3d_map_is_the_2d_map(reference, axis, k):
    plane, grid = _plane(reference, axis, k)
    single = best_manipulability_map(humanoid_arm("right"), grid, SIZES["samples"])
    dual = best_dual_arm_map(grid, SIZES["samples"])
    np.testing.assert_array_equal(plane["best_manipulability"], single.values)
    np.testing.assert_array_equal(plane["best_dual_manipulability"], dual.values)
    np.testing.assert_array_equal(plane["reachable"], single.status == 0)
    assert np.isfinite(single.values).any() and (~np.isfinite(single.values)).any()


def test_the_left_arm_map_is_the_mirror_image_of_the_right(reference, tmp_path):
    """The left arm at (x, y, z) is the right arm at (-x, y, z): the same numbers, the x axis reversed."""
    mirrored = [-EXTENT[1], -EXTENT[0], *EXTENT[2:]]
    run = humanoid_map(get_robot("humanoid-left"), tmp_path / "left.zarr", mirrored, **SIZES)
    left = _arrays(run.path)
    plane, grid = _plane(left, "z", 2)
    np.testing.assert_array_equal(plane["best_manipulability"],
                                  best_manipulability_map(humanoid_arm("left"), grid, SIZES["samples"]).values)
    for name in VARIABLES:
        np.testing.assert_allclose(left[name][::-1].astype(float), reference[name].astype(float), rtol=1e-12,
                                   atol=1e-15, err_msg=name)


@pytest.mark.slow
def test_local_cluster_gives_identical_arrays(chain, reference, client, tmp_path):
    """On the session's cluster, whose client is not Dask's default (``set_as_default=False``)."""
    assert default_dask_scheduler() == []
    run = _within(TIMEOUT, humanoid_map, chain, tmp_path / "map.zarr", EXTENT, client=client, **SIZES)
    assert run.computed == 27
    arrays = _arrays(run.path)
    for name in NAMES:
        np.testing.assert_array_equal(arrays[name], reference[name], err_msg=name)
    assert default_dask_scheduler() == []


def test_a_client_that_is_not_the_default_runs_the_map_it_is_given(chain, client, tmp_path):
    """Issue 38: a ``Client(set_as_default=False)`` failed with "No clients found"; a small map on it equals the local
    scheduler's bit for bit, summary included."""
    with pytest.raises(ValueError, match="No clients found"):
        distributed.default_client()
    sizes = {"resolution": 3, "samples": (3, 4), "chunk": 1}  # 27 chunks of one position
    local = humanoid_map(chain, tmp_path / "local.zarr", EXTENT, **sizes)
    run = _within(TIMEOUT, humanoid_map, chain, tmp_path / "cluster.zarr", EXTENT, client=client, **sizes)
    assert run.computed == local.computed == 27
    expected, arrays = _arrays(local.path), _arrays(run.path)
    for name in NAMES:
        np.testing.assert_array_equal(arrays[name], expected[name], err_msg=name)
    fields = ("reachable_positions", "feasible_positions", "max_manipulability", "mean_manipulability",
              "max_dual_manipulability")
    assert [getattr(run, f) for f in fields] == [getattr(local, f) for f in fields]
    assert np.isfinite(expected["best_manipulability"]).any()
    assert default_dask_scheduler() == []


def test_interrupted_run_resumes_to_the_same_map(chain, reference, tmp_path):
    def interrupt(done, total):
        if done == 3:
            raise KeyboardInterrupt

    path = tmp_path / "map.zarr"
    with pytest.raises(KeyboardInterrupt):
        humanoid_map(chain, path, EXTENT, progress=interrupt, **SIZES)
    assert 3 <= completed_chunks(path).sum() < 27
    run = humanoid_map(chain, path, EXTENT, **SIZES)
    assert 0 < run.computed <= 24
    arrays = _arrays(path)
    for name in NAMES:
        np.testing.assert_array_equal(arrays[name], reference[name], err_msg=name)
    assert humanoid_map(chain, path, EXTENT, **SIZES).computed == 0
    with pytest.raises(ValueError, match="other parameters"):
        humanoid_map(chain, path, EXTENT, resolution=5, samples=(5, 7), chunk=2)


def test_humanoid_of_knows_both_arms_and_nothing_else():
    assert humanoid_of(get_robot("humanoid-right")).side == "right"
    assert humanoid_of(get_robot("humanoid-left")).side == "left"
    assert humanoid_of(get_robot("pa10-7c")) is None
    with pytest.raises(ValueError, match="not the thesis 001 humanoid"):
        humanoid_map(get_robot("pa10-7c"), "unused.zarr", EXTENT, 3)


def test_cli_writes_the_map_its_slices_and_its_summary(reference, tmp_path, capsys):
    argv = ["workspace", "humanoid-right", "--out", str(tmp_path), "--extent", *map(str, EXTENT),
            "--resolution", "5", "--samples", "5", "6", "--chunk", "2", "--json", "--quiet"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert captured.err == ""  # --quiet: no progress
    summary = json.loads(captured.out)
    assert summary["chunks"] == 27 and summary["positions"] == 125 and summary["samples"] == [5, 6]
    assert 0 < summary["feasible_positions"] <= summary["reachable_positions"] < 1
    best = reference["best_manipulability"]
    assert summary["max_manipulability"] == pytest.approx(np.nanmax(best), rel=1e-12)
    for image in summary["images"]:
        assert open(image, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    arrays = _arrays(tmp_path / "map.zarr")
    for name in NAMES:
        np.testing.assert_array_equal(arrays[name], reference[name], err_msg=name)


@pytest.mark.parametrize("robot,extra,message", [
    ("humanoid-right", ["--orientations", "4"], "--orientations is for arms with arm-angle IK"),
    ("humanoid-right", ["--samples", "0", "4"], "--samples must be an integer in 1..3600"),
    ("pa10-7c", ["--samples", "4", "4"], "--samples is for the thesis 001 humanoid"),
    ("pa10-7c", [], "its map needs --orientations N"),
])
def test_cli_refuses_options_of_the_other_kind_of_map_in_one_line(robot, extra, message, tmp_path, capsys):
    argv = ["workspace", robot, "--out", str(tmp_path / "out"), "--extent", *map(str, EXTENT), "--resolution", "3"]
    assert main(argv + extra) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert not (tmp_path / "out").exists()
