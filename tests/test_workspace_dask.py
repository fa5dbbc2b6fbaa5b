"""redkin.workspace on Dask: local scheduler and a 2-process LocalCluster agree, runs resume, a killed worker costs
nothing."""

import json
import os
import signal

import numpy as np
import pytest

pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")
distributed = pytest.importorskip("distributed")

from redkin.cli.main import main  # noqa: E402
from redkin.workspace import workspace_map  # noqa: E402
from redkin.workspace.run import match_worker_threads, restore_mmap_threshold  # noqa: E402
from redkin.workspace.store import completed_chunks  # noqa: E402
from tests.support.small_map import EXTENT, SIZES, VARIABLES  # noqa: E402
from tests.support.small_map import arrays as _arrays  # noqa: E402


def _assert_same_map(path, small_map):
    arrays = _arrays(path)
    for name in VARIABLES:
        np.testing.assert_array_equal(arrays[name], small_map[name], err_msg=name)


@pytest.mark.slow
def test_local_cluster_gives_identical_arrays(pa10, small_map, client, tmp_path):
    run = workspace_map(pa10, tmp_path / "map.zarr", EXTENT, client=client, **SIZES)
    assert run.computed == 27
    _assert_same_map(run.path, small_map)


def test_cli_scheduler_option_gives_the_same_map(small_map, client, tmp_path, capsys):
    sizes = [f"--{name}={value}" for name, value in SIZES.items()]
    address = client.scheduler.address
    assert main(["workspace", "pa10-7c", "--out", str(tmp_path), "--extent", *map(str, EXTENT), *sizes,
                 "--scheduler", address, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["scheduler"] == address
    _assert_same_map(tmp_path / "map.zarr", small_map)


def test_relative_store_path_is_written_where_the_caller_means(pa10, client, tmp_path, monkeypatch):
    before = client.run(os.getcwd)
    client.run(os.chdir, "/")  # the workers elsewhere than this process
    try:
        monkeypatch.chdir(tmp_path)
        run = workspace_map(pa10, "relative.zarr", EXTENT, 2, 1, chunk=1, client=client)
    finally:
        for address, folder in before.items():
            client.run(os.chdir, folder, workers=[address])
    assert run.computed == 8 and completed_chunks(tmp_path / "relative.zarr").all()


def test_interrupted_run_resumes_to_the_same_map(pa10, small_map, tmp_path):
    def interrupt(done, total):
        if done == 3:
            raise KeyboardInterrupt

    path = tmp_path / "map.zarr"
    with pytest.raises(KeyboardInterrupt):
        workspace_map(pa10, path, EXTENT, progress=interrupt, **SIZES)
    assert 3 <= completed_chunks(path).sum() < 27
    with xr.open_zarr(path) as dataset:  # chunks not computed read NaN
        assert np.isnan(dataset["reachability"].values).any()
    run = workspace_map(pa10, path, EXTENT, **SIZES)
    assert 0 < run.computed <= 24
    _assert_same_map(path, small_map)
    assert workspace_map(pa10, path, EXTENT, **SIZES).computed == 0


def test_resume_refuses_a_store_of_another_map(pa10, tmp_path):
    path = tmp_path / "map.zarr"
    workspace_map(pa10, path, EXTENT, 2, 1)
    with pytest.raises(ValueError, match="holds a map with other parameters"):
        workspace_map(pa10, path, EXTENT, 3, 1)
    (tmp_path / "other").mkdir()
    with pytest.raises(ValueError, match="is not a workspace map"):
        workspace_map(pa10, tmp_path / "other", EXTENT, 2, 1)


def test_map_completes_when_a_worker_is_killed(pa10, small_map, client, tmp_path):
    pids = client.run(os.getpid)
    killed = []

    def kill_one(done, total):
        if not killed:
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    run = workspace_map(pa10, tmp_path / "map.zarr", EXTENT, client=client, progress=kill_one, **SIZES)
    assert killed and run.computed == 27
    _assert_same_map(run.path, small_map)
    client.wait_for_workers(2, timeout=60)  # the nanny restarts it
    assert killed[0] not in client.run(os.getpid).values()


def test_chunk_tasks_fit_their_worker(client):
    """A task on a single-threaded worker runs its compiled batches on one numba thread and gets glibc's 32 MiB mmap
    threshold back (Dask's MALLOC_TRIM_THRESHOLD_ took it away); outside a worker neither changes anything."""
    import platform

    from redkin._compiled import thread_count

    def in_task():
        return (match_worker_threads(), thread_count(), restore_mmap_threshold(),
                "MALLOC_TRIM_THRESHOLD_" in os.environ)

    threads, pool_threads, restored, trimmed = client.submit(in_task, pure=False).result(timeout=60)
    assert threads == pool_threads == 1 and trimmed
    assert restored is (platform.libc_ver()[0] == "glibc")
    assert match_worker_threads() is None
    if "MALLOC_TRIM_THRESHOLD_" not in os.environ:
        assert restore_mmap_threshold() is False
