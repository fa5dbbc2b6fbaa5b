"""Workspace maps survive any crash: each fault leaves a store whose marked chunks are right and whole, and a resume
gives the map of a clean run bit for bit.

The faults are real: processes killed with SIGKILL (a subprocess started by the test with ``python -c`` code that
patches the store's own calls, or a Dask worker), two runs started at once, and a full disk (a small tmpfs where
mounting is permitted, and writes that raise ENOSPC everywhere).  Library code has no test hook.
"""

from __future__ import annotations

import errno
import json
import os
import pickle
import shutil
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("zarr")
xr = pytest.importorskip("xarray")
pytest.importorskip("distributed")

from redkin.cli.main import main  # noqa: E402
from redkin.errors import MapStoreError  # noqa: E402
from redkin.models import get_robot  # noqa: E402
from redkin.workspace import _durable as durable  # noqa: E402
from redkin.workspace import store, workspace_map  # noqa: E402
from redkin.workspace.humanoid import humanoid_map  # noqa: E402
from redkin.workspace.store import completed_chunks  # noqa: E402
from tests.support.small_map import CHUNKS, EXTENT, SIZES, VALUES, VARIABLES  # noqa: E402
from tests.support.small_map import arrays as _arrays  # noqa: E402

#: Seconds a subprocess may take before the test fails instead of hanging.
TIMEOUT = 120

#: The start of every subprocess: the map's arguments.  ``SLOW`` seconds of sleep before each chunk's write keep
#: a run of 27 chunks going long enough to be hit while it runs (the values written are the same).
PRELUDE = """
import os, signal, sys, threading, time, types
import redkin._files as files
import redkin.workspace.run as run
from redkin.models import get_robot
from redkin.workspace import workspace_map
ARM, EXTENT, SIZES, SLOW = get_robot("pa10-7c"), {extent!r}, {sizes!r}, {slow!r}
if SLOW:
    _write_chunk = run.write_chunk
    def slow_write_chunk(*args):
        time.sleep(SLOW)
        _write_chunk(*args)
    run.write_chunk = slow_write_chunk
"""

#: Kills the process (SIGKILL, itself) in the middle of the store's own writing of a chunk: its ``NTH`` chunk file in
#: ``FOLDER`` half written (``MODE`` "write"), or whole but not yet renamed into place ("rename").  The store's calls
#: of ``os`` are patched (``redkin._files.os``, where the store's durable writes live), nothing else; the path hit is
#: printed first.
KILL_IN_WRITE = """
FOLDER, MODE, NTH = {folder!r}, {mode!r}, {nth!r}
real, opened, seen, lock = os, {{}}, [0], threading.Lock()
def hit(path):  # a chunk's file in FOLDER (not the metadata: .zarray, .zattrs)
    if "/" + FOLDER + "/" not in str(path) or not os.path.basename(path).lstrip(".")[:1].isdigit():
        return False
    with lock:
        seen[0] += 1
        return seen[0] == NTH
def kill(path):
    print(path, flush=True)
    real.kill(real.getpid(), signal.SIGKILL)
def patched_open(path, flags, mode=0o777):
    descriptor = real.open(path, flags, mode)
    opened[descriptor] = str(path)
    return descriptor
def patched_write(descriptor, data):
    path = opened.get(descriptor, "")
    if MODE == "write" and path.endswith(".partial") and hit(path):
        real.write(descriptor, bytes(data)[:len(data) // 2])
        kill(path)
    return real.write(descriptor, data)
def patched_replace(source, target):
    if MODE == "rename" and hit(target):
        kill(target)
    return real.replace(source, target)
files.os = types.ModuleType("os")
files.os.__dict__.update(vars(real), open=patched_open, write=patched_write, replace=patched_replace)
"""


@pytest.fixture
def spawn():
    """``spawn(code, *args)``: a ``python -c`` subprocess in its own session (killed with its group at the end)."""
    started: list[subprocess.Popen] = []

    def start(code: str, *args: str) -> subprocess.Popen:
        process = subprocess.Popen([sys.executable, "-c", code, *args], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True, start_new_session=True)
        started.append(process)
        return process

    yield start
    for process in started:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
        process.communicate()


def _code(*parts: str, slow: float = 0.0, **values) -> str:
    return "\n".join(textwrap.dedent(part).format(extent=EXTENT, sizes=SIZES, slow=slow, **values) for part in
                     (PRELUDE, *parts))


def _partial_files(path: Path) -> list[Path]:
    return sorted(path.rglob("*.partial"))


def _assert_marked_chunks_are_right(path: Path, small_map: dict) -> int:
    """Every chunk marked complete holds the clean run's values exactly; the store reads whole. Returns how many."""
    complete = completed_chunks(path)
    arrays = _arrays(path)  # a torn file anywhere would fail to decode here
    np.testing.assert_array_equal(arrays["chunk_complete"], complete)
    c = SIZES["chunk"]
    for index in zip(*np.nonzero(complete)):
        where = tuple(slice(c * i, c * (i + 1)) for i in index)
        for name in VALUES:
            np.testing.assert_array_equal(arrays[name][where], small_map[name][where], err_msg=f"{name} {index}")
    return int(complete.sum())


def _assert_resumes_to_the_reference(pa10, path: Path, small_map: dict, marked: int) -> None:
    """A run with nothing in the way computes exactly the unmarked chunks and gives the clean map bit for bit."""
    run = workspace_map(pa10, path, EXTENT, **SIZES)
    assert run.computed == CHUNKS - marked
    arrays = _arrays(path)
    for name in VARIABLES:
        np.testing.assert_array_equal(arrays[name], small_map[name], err_msg=name)
    assert not _partial_files(path), "a resumed run removes what a killed writer left"
    assert not path.with_name(path.name + ".lock").exists()


def _wait_for(condition, process: subprocess.Popen | None = None, seconds: float = TIMEOUT) -> None:
    end = time.monotonic() + seconds
    while not condition():
        if process is not None and process.poll() is not None:
            raise AssertionError(f"the run ended first (exit {process.returncode}): {process.communicate()}")
        assert time.monotonic() < end, "timed out"
        time.sleep(0.01)


def _two_live_workers(client, dead: int | None = None) -> None:
    """Wait until the cluster has its two workers again, none of them the process ``dead``."""
    end = time.monotonic() + 60
    while True:
        pids = client.run(os.getpid, on_error="ignore")  # a worker dead but not yet removed does not answer
        if len(pids) == 2 and dead not in pids.values():
            return
        assert time.monotonic() < end, f"the cluster did not get two live workers back: {pids}"
        time.sleep(0.1)


def _markers(path: Path) -> int:
    folder = path / "chunk_complete"
    return sum(1 for name in os.listdir(folder) if not name.startswith(".")) if folder.is_dir() else 0


# -- a process killed in the middle of writing a chunk ------------------------------------------------------------

@pytest.mark.parametrize("folder, mode, nth", [
    ("measure", "write", 3),          # the values half written
    ("chunk_complete", "rename", 2),  # every value file in place, the marker whole but not yet renamed into place
    ("chunk_complete", "write", 3),   # the marker half written
])
def test_a_process_killed_in_a_chunk_write_keeps_no_unfinished_chunk(pa10, small_map, tmp_path, spawn, folder, mode,
                                                                     nth):
    path = tmp_path / "map.zarr"
    process = spawn(_code(KILL_IN_WRITE, "workspace_map(ARM, sys.argv[1], EXTENT, **SIZES)", folder=folder,
                          mode=mode, nth=nth), str(path))
    out, err = process.communicate(timeout=TIMEOUT)
    assert process.returncode == -signal.SIGKILL, err
    hit = Path(out.strip())  # the file the process died writing
    assert hit.parent == path / folder
    chunk = tuple(int(part) for part in hit.name.lstrip(".").split(".")[:3])
    marked = _assert_marked_chunks_are_right(path, small_map)
    # the map's chunks are written by a pool's threads at once, so how many are marked when the kill comes is not
    # fixed (CI dry run #26: none, the first marker's rename not yet done when another thread's second one was
    # hit): the laws below hold for any number of them short of all
    assert not completed_chunks(path)[chunk] and 0 <= marked < CHUNKS
    if mode == "write":  # killed mid-write: only the temporary file is torn, and nothing reads it
        assert hit.name.endswith(".partial") and hit.exists()
    else:  # killed between the values and the marker: the values are in place, the chunk is still not complete
        keys = {name: ".".join(map(str, chunk + ((0, 0) if name == "measure" else ()))) for name in VALUES}
        assert not hit.exists() and all((path / name / key).exists() for name, key in keys.items())
    _assert_resumes_to_the_reference(pa10, path, small_map, marked)


@pytest.mark.slow
def test_a_cluster_worker_killed_mid_write_costs_nothing(pa10, small_map, own_client, tmp_path):
    """A worker process dies (SIGKILL) half-way through writing a chunk's values: Dask reruns the task elsewhere,
    the map is the clean one, and the torn temporary file is gone after the next run.

    Both workers are set to die in their third write of values: which worker the scheduler gives how many chunks is
    its choice, but of 27 chunks on two workers one writes at least three, so at least one dies.  On a cluster of the
    test's own, so that no other test meets a worker restarting."""
    client = own_client

    def die_in_third_values_write():
        import os as real
        import signal
        import types

        import redkin._files as worker_files

        seen = [0]

        def write(descriptor, data):
            if "/measure/" in real.readlink(f"/proc/self/fd/{descriptor}"):
                seen[0] += 1
                if seen[0] == 3:
                    real.write(descriptor, bytes(data)[:len(data) // 2])
                    real.kill(real.getpid(), signal.SIGKILL)
            return real.write(descriptor, data)

        worker_files.os = types.ModuleType("os")
        worker_files.os.__dict__.update(vars(real), write=write)
        return real.getpid()

    def heal():
        import os as real

        import redkin._files as worker_files

        worker_files.os = real

    _two_live_workers(client)
    patched = set(client.run(die_in_third_values_write).values())
    path = tmp_path / "map.zarr"
    try:
        run = workspace_map(pa10, path, EXTENT, client=client, **SIZES)
    finally:
        client.run(heal, on_error="ignore")  # a patched worker still alive dies no more
        alive = set(client.run(os.getpid, on_error="ignore").values())
        dead = patched - alive
        _two_live_workers(client)  # the nannies restart the dead, without the patch
    assert dead, "no worker died: the fault was not injected"
    # each death tears the file being written and any other write under way in that worker at the moment (zarr may
    # store several files at once: a CI run found 3 torn files from 2 deaths); none is a file the map reads
    assert run.computed == CHUNKS and len(_partial_files(path)) >= 1
    _assert_resumes_to_the_reference(pa10, path, small_map, CHUNKS)


# -- the scheduler (the process running the map) killed mid-run, then the run restarted ---------------------------

@pytest.mark.slow
@pytest.mark.parametrize("scheduler", ["local", "distributed"])
def test_a_run_killed_at_random_moments_resumes_to_the_same_map(pa10, small_map, tmp_path, spawn, scheduler):
    """The whole process (Dask's local scheduler, or a dask.distributed scheduler with its workers in it) is
    killed twice at a random moment after its first chunks appear; every run after it takes over the store (no stale
    lock), loses none of the chunks marked, and the last one gives the clean map."""
    code = _code("""
        client = None
        if sys.argv[2] == "distributed":
            from distributed import Client, LocalCluster
            client = Client(LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None),
                            set_as_default=False)
        workspace_map(ARM, sys.argv[1], EXTENT, client=client, **SIZES)
    """, slow=0.15)
    path = tmp_path / "map.zarr"
    rng = np.random.default_rng(22)
    marked = 0
    for delay in rng.uniform(0.0, 0.5, 2):
        process = spawn(code, str(path), scheduler)
        _wait_for(lambda before=marked: _markers(path) > before, process)
        time.sleep(delay)
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate(timeout=TIMEOUT)
        now = _assert_marked_chunks_are_right(path, small_map)
        assert marked < now < CHUNKS, f"killed after {delay:.3f} s"
        marked = now
    _assert_resumes_to_the_reference(pa10, path, small_map, marked)


# -- a second run on the same store while one runs -------------------------------------------------------------

@pytest.mark.slow
def test_two_runs_started_at_once_one_runs_the_other_is_refused_in_one_line(pa10, small_map, tmp_path, spawn):
    """The issue's case: two ``redkin workspace`` runs at once on a new ``--out``.  One creates the store and
    completes the map; the other is refused with one line and exit 2, and so is a third call while the first runs.
    Nobody meets "Directory not empty" or "No array found"."""
    out, go = tmp_path / "out", tmp_path / "go"
    argv = ["workspace", "pa10-7c", "--out", str(out), "--extent", *map(str, EXTENT),
            *(f"--{name}={value}" for name, value in SIZES.items()), "--json", "--quiet"]
    code = _code("""
        from pathlib import Path
        from redkin.cli.main import main
        Path(sys.argv[1] + ".ready").touch()
        while not Path(sys.argv[2]).exists():
            time.sleep(0.001)
        sys.exit(main(sys.argv[3:]))
    """, slow=0.1)
    processes = [spawn(code, str(tmp_path / f"run{i}"), str(go), *argv) for i in range(2)]
    _wait_for(lambda: all((tmp_path / f"run{i}.ready").exists() for i in range(2)))
    go.touch()
    _wait_for(lambda: any(p.poll() is not None for p in processes))
    with pytest.raises(MapStoreError, match="is in use by another run") as refused:
        workspace_map(pa10, out / "map.zarr", EXTENT, **SIZES)
    assert refused.value.reason == "in use" and refused.value.path == str(out / "map.zarr")
    results = [(p.wait(TIMEOUT), *p.communicate()) for p in processes]
    assert sorted(code for code, _, _ in results) == [0, 2], results
    (_, _, err), = [result for result in results if result[0] == 2]
    # the holder is named by its pid, or "starting" when it has the lock but has not written its pid yet
    in_use = f"redkin: error: {str(out / 'map.zarr')!r} is in use by another run ("
    assert err.count("\n") == 1 and err.startswith((in_use + "pid ", in_use + "starting)")), err
    (_, summary, err), = [result for result in results if result[0] == 0]
    assert json.loads(summary)["chunks_computed"] == CHUNKS and err == ""
    _assert_resumes_to_the_reference(pa10, out / "map.zarr", small_map, CHUNKS)


def test_the_lock_is_per_store_and_one_holder_at_a_time(tmp_path):
    """Within one process too: a store held is refused to a second holder (either map), another store is not; the
    lock goes with its holder, and of many holders at once one at a time wins."""
    path = tmp_path / "map.zarr"
    with store.hold_store(path):
        with pytest.raises(MapStoreError, match="in use") as refused, store.hold_store(path):
            pass
        copy = pickle.loads(pickle.dumps(refused.value))  # errors cross processes pickled
        assert (str(copy), copy.path, copy.reason) == (str(refused.value), str(path), "in use")
        with store.hold_store(tmp_path / "other.zarr"):
            pass
        with pytest.raises(MapStoreError, match="in use"):  # the humanoid's map shares the machinery
            humanoid_map(get_robot("humanoid-right"), path, [-0.3, 1.0, -0.7, 0.7, -0.6, 0.6], 2)
        assert "pid " in path.with_name("map.zarr.lock").read_text()
    assert not path.with_name("map.zarr.lock").exists()
    errors = []
    threads = [threading.Thread(target=lambda: errors.append(_try_hold(path))) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors.count(None) >= 1 and all(e is None or e.reason == "in use" for e in errors)


def _try_hold(path: Path) -> MapStoreError | None:
    try:
        with store.hold_store(path):
            time.sleep(0.01)
    except MapStoreError as error:
        return error
    return None


# -- a full disk -----------------------------------------------------------------------------------------------

@pytest.fixture
def small_disk(tmp_path):
    """A 256 KiB tmpfs (the map needs about 600 KiB there); ``remount(size)`` gives it more room."""
    folder = tmp_path / "disk"
    folder.mkdir()
    if shutil.which("mount") is None:
        pytest.skip("no mount command to make a small tmpfs")
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(folder)], capture_output=True,
                             text=True)
    if mounted.returncode != 0:
        pytest.skip(f"mounting a small tmpfs is not permitted here (needs root): {mounted.stderr.strip()}")

    def remount(size: str) -> None:
        subprocess.run(["mount", "-o", f"remount,size={size}", str(folder)], check=True)

    try:
        yield folder, remount
    finally:
        subprocess.run(["umount", "-l", str(folder)], check=False)


def test_a_full_disk_stops_the_run_in_one_line_and_the_store_resumes(pa10, small_map, small_disk, capsys):
    disk, remount = small_disk
    argv = ["workspace", "pa10-7c", "--out", str(disk), "--extent", *map(str, EXTENT),
            *(f"--{name}={value}" for name, value in SIZES.items()), "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    path = disk / "map.zarr"
    assert err.count("\n") == 1, err
    assert err.startswith(f"redkin: error: no space left on device writing {str(path)!r}: ")
    marked = _assert_marked_chunks_are_right(path, small_map)
    assert 0 < marked < CHUNKS and f"{marked} of {CHUNKS} chunks are complete and kept" in err
    assert not _partial_files(path)  # a write that failed removed its temporary file
    remount("4m")  # space again
    assert main(argv + ["--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["chunks_computed"] == CHUNKS - marked
    _assert_resumes_to_the_reference(pa10, path, small_map, CHUNKS)


@pytest.mark.parametrize("stage, writes", [("creation", 0), ("chunks", 0), ("chunks", 40)])
def test_writes_failing_with_enospc_keep_the_store_resumable(pa10, small_map, tmp_path, monkeypatch, stage, writes):
    """The same without root: the store's file writes fail with ENOSPC, from the first one (the store being
    created), from the first chunk's first file, or after 40 files of chunks (10 chunks are 40 files)."""
    count, lock, write = [0], threading.Lock(), durable.write_durably

    def full_after(path, data):
        counted = stage == "creation" or (path.parent.name in (*VALUES, "chunk_complete")
                                          and not path.name.startswith("."))
        with lock:
            count[0] += counted
            full = counted and count[0] > writes
        if full:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        write(path, data)

    monkeypatch.setattr(durable, "write_durably", full_after)
    path = tmp_path / "map.zarr"
    with pytest.raises(MapStoreError) as raised:
        workspace_map(pa10, path, EXTENT, **SIZES)
    message = str(raised.value)
    assert raised.value.reason == "no space" and "\n" not in message
    assert message.startswith(f"no space left on device writing {str(path)!r}: ")
    if stage == "creation":  # nothing of a store half created is left
        assert "nothing was written" in message and not path.exists()
        assert not path.with_name("map.zarr.creating").exists()
        marked = 0
    else:
        marked = _assert_marked_chunks_are_right(path, small_map)
        assert f"{marked} of {CHUNKS} chunks are complete and kept" in message
        assert (marked == 0) == (writes == 0) and marked < CHUNKS
    monkeypatch.undo()
    _assert_resumes_to_the_reference(pa10, path, small_map, marked)


@pytest.mark.slow
def test_a_full_disk_under_a_cluster_is_one_line_too(pa10, small_map, client, tmp_path):
    """The workers' ENOSPC reaches the caller as the same one line; the chunks they completed stay."""
    def fill_after(limit):
        import errno as worker_errno
        import os as worker_os
        import threading as worker_threading

        import redkin.workspace._durable as worker_durable

        real = worker_durable.__dict__.setdefault("real_write_durably", worker_durable.write_durably)
        count, lock = [0], worker_threading.Lock()

        def full(path, data):
            if path.parent.name == "measure" and not path.name.startswith("."):
                with lock:
                    count[0] += 1
                    if count[0] > limit:
                        raise OSError(worker_errno.ENOSPC, worker_os.strerror(worker_errno.ENOSPC), str(path))
            real(path, data)

        worker_durable.write_durably = full if limit is not None else real

    path = tmp_path / "map.zarr"
    _two_live_workers(client)
    assert len(client.run(fill_after, 4)) == 2  # each worker writes 4 chunks' values, then its disk is full
    try:
        with pytest.raises(MapStoreError) as raised:
            workspace_map(pa10, path, EXTENT, client=client, **SIZES)
    finally:
        client.run(fill_after, None)
    marked = _assert_marked_chunks_are_right(path, small_map)
    assert raised.value.reason == "no space" and not _partial_files(path)
    assert f"{marked} of {CHUNKS} chunks are complete and kept" in str(raised.value) and 0 < marked <= 8
    _assert_resumes_to_the_reference(pa10, path, small_map, marked)
