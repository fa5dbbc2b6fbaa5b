"""How kernels are compiled (cached where numba finds a cache directory, uncached and still working where not;
serial and nogil) and how run_batch hands a batch out in chunks."""

import ast
import hashlib
import os
import threading
from itertools import pairwise
from pathlib import Path

import numba
import numpy as np
import pytest
from numba.core import config

from redkin import _compiled
from redkin._compiled import default_threads, kernel, run_batch, set_threads, thread_count


def twice(x):
    return 2.0 * x


def test_kernel_caches_where_a_cache_directory_is_writable():
    compiled = kernel(twice)
    assert compiled(1.5) == 3.0
    assert type(compiled._cache).__name__ != "NullCache"
    assert compiled.targetoptions["nogil"] and not compiled.targetoptions.get("parallel", False)


def test_kernels_are_compiled_without_a_c_callable_wrapper():
    """numba's ``cfunc`` wrapper (one more function per kernel to build and optimise) is not made; the wrapper
    Python calls a kernel through is."""
    compiled = kernel(twice)
    assert compiled(1.5) == 3.0 and compiled.targetoptions["no_cfunc_wrapper"]
    fresh = numba.njit(**_compiled._NJIT_OPTIONS)(lambda x: 2.0 * x)  # not cached: its LLVM IR is at hand
    assert fresh(1.5) == 3.0
    result = fresh.overloads[fresh.signatures[0]]
    ir = result.library.get_llvm_str()
    assert result.fndesc.llvm_cpython_wrapper_name in ir and result.fndesc.llvm_cfunc_wrapper_name not in ir


def test_kernel_compiles_without_a_cache_where_none_is_writable(monkeypatch):
    """IPython's locator alone finds nothing for a file: what numba sees with a read-only install and home."""
    monkeypatch.setattr(config, "CACHE_LOCATOR_CLASSES", "IPythonCacheLocator")
    with pytest.raises(RuntimeError, match="no locator available"):
        numba.njit(cache=True)(twice)
    compiled = kernel(twice)
    assert compiled(1.5) == 3.0
    assert type(compiled._cache).__name__ == "NullCache"


def _kernel_module(folder: Path):
    """A module with one function, ``triple``, loaded from ``folder/kernel_module.py``."""
    import importlib.util

    source = folder / "kernel_module.py"
    source.write_text("def triple(x):\n    return 3.0 * x\n")
    spec = importlib.util.spec_from_file_location("kernel_module", source)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(params=["beside the source", "NUMBA_CACHE_DIR"])
def cache_setting(request, tmp_path, monkeypatch):
    """numba's cache folder as a process starting with ``NUMBA_CACHE_DIR`` unset or set sees it (numba reads it
    when it loads; its locator reads ``config.CACHE_DIR`` when a function is decorated): the folder that should
    hold the kernels of a module in ``tmp_path/source``, and the folder the notice should name."""
    source = tmp_path / "source"
    source.mkdir()
    monkeypatch.setattr(_compiled, "_checked", set())  # as a new process would
    if request.param == "NUMBA_CACHE_DIR":
        root = tmp_path / "numba cache"
        monkeypatch.setenv("NUMBA_CACHE_DIR", str(root))
        monkeypatch.setattr(config, "CACHE_DIR", str(root))
        return source, root / f"source_{hashlib.sha1(str(source).encode()).hexdigest()}", root  # numba's subfolder
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(config, "CACHE_DIR", "")
    return source, source / "__pycache__", source / "__pycache__"


def test_a_cache_filled_by_other_kernels_is_emptied(cache_setting):
    """numba checks a cached kernel against its own file only; redkin's stamp covers every kernel module, in the
    folder where numba caches (NUMBA_CACHE_DIR set or not)."""
    source, cache, _ = cache_setting
    module = _kernel_module(source)
    first = kernel(module.triple)
    assert first(2.0) == 6.0
    assert Path(_compiled._cache_path(first)) == cache
    assert (cache / _compiled._STAMP_NAME).read_text() == _compiled._core_digest()
    assert list(cache.glob("*.nbi")) and list(cache.glob("*.nbc"))
    kernel(module.triple)  # the same version in the same process: nothing is dropped
    assert list(cache.glob("*.nbi"))
    (cache / _compiled._STAMP_NAME).write_text("another version of the kernels")
    _compiled._checked.clear()  # as a new process would
    again = kernel(module.triple)
    assert not list(cache.glob("*.nbi")) and not list(cache.glob("*.nbc"))
    assert (cache / _compiled._STAMP_NAME).read_text() == _compiled._core_digest()
    assert again(2.0) == 6.0


def test_the_cache_named_is_where_numba_caches(cache_setting, tmp_path, monkeypatch):
    """NUMBA_CACHE_DIR itself (not numba's subfolder of it), or the __pycache__ folder; and a NUMBA_CACHE_DIR numba
    cannot write to, which numba passes over, is not named."""
    source, _, named = cache_setting
    assert _compiled.cache_directory() == "no cache"
    kernel(_kernel_module(source).triple)
    assert _compiled.cache_directory() == str(named)
    blocked = tmp_path / "a file, not a folder"
    blocked.write_text("")
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(blocked))
    monkeypatch.setattr(config, "CACHE_DIR", str(blocked))
    _compiled._checked.clear()
    assert Path(_compiled._cache_path(kernel(_kernel_module(source).triple))) == source / "__pycache__"
    assert _compiled.cache_directory() == str(source / "__pycache__")


def recorder():
    """A batch "kernel" in Python that records the chunks it is given and the thread that ran each."""
    calls = []

    def chunk(start, stop, out):
        calls.append((start, stop, threading.current_thread().name))
        out[start:stop] = np.arange(start, stop)
        return stop - start if start % 2 else 0
    return chunk, calls


@pytest.mark.parametrize("threads", [2, 3, 5])
@pytest.mark.parametrize("count", [_compiled.PARALLEL_BATCH, 1001, 40_000])
def test_chunks_cover_the_batch_once_on_the_calling_thread_and_the_pool(threads, count):
    chunk, calls = recorder()
    out = np.full(count, -1.0)
    try:
        set_threads(threads)
        total = run_batch(chunk, count, out)
    finally:
        set_threads(None)
    bounds = sorted((start, stop) for start, stop, _ in calls)
    assert bounds[0][0] == 0 and bounds[-1][1] == count
    assert all(a[1] == b[0] for a, b in pairwise(bounds))  # adjacent, disjoint, no gaps
    assert 2 <= len(bounds) <= _compiled.CHUNKS_PER_THREAD * threads
    assert all(stop - start >= _compiled.MIN_CHUNK for start, stop in bounds)
    helpers = {name for _, _, name in calls} - {threading.current_thread().name}
    assert all(name.startswith("redkin-batch") for name in helpers) and len(helpers) <= threads - 1
    assert total == sum(stop - start for start, stop in bounds if start % 2)  # the chunks' returns add up
    np.testing.assert_array_equal(out, np.arange(count))


def test_small_batches_and_one_thread_run_in_the_calling_thread(monkeypatch):
    for threads, count in ((None, _compiled.PARALLEL_BATCH - 1), (1, 100_000)):
        chunk, calls = recorder()
        try:
            set_threads(threads)
            run_batch(chunk, count, np.empty(count))
        finally:
            set_threads(None)
        assert calls == [(0, count, threading.current_thread().name)]

    def asked() -> int:
        raise AssertionError("a batch too small for the pool asked for the cores (a system call, 2.4 us)")

    monkeypatch.setattr(_compiled, "thread_count", asked)
    chunk, calls = recorder()
    run_batch(chunk, _compiled.PARALLEL_BATCH - 1, np.empty(_compiled.PARALLEL_BATCH - 1))
    assert len(calls) == 1


def test_a_batch_too_short_for_the_pool_runs_in_the_calling_thread(monkeypatch):
    """A kernel's measured time per item decides: a batch it would finish within POOL_SECONDS runs alone."""
    chunk, calls = recorder()
    out = np.empty(1001)
    try:
        set_threads(2)
        run_batch(chunk, 1001, out)  # not timed yet: on the pool, which times the calling thread's chunks
        assert len(calls) > 1 and _compiled._seconds_per_item[chunk] > 0.0
        monkeypatch.setitem(_compiled._seconds_per_item, chunk, 1e-9)  # about its cost; a busy machine measures more
        calls.clear()
        run_batch(chunk, 1001, out)
        assert calls == [(0, 1001, threading.current_thread().name)]
        calls.clear()
        monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)
        run_batch(chunk, 1001, out)
        assert len(calls) > 1
    finally:
        set_threads(None)
    np.testing.assert_array_equal(out, np.arange(1001))


def test_a_small_batch_of_long_items_goes_to_the_pool(monkeypatch):
    """A kernel measured at a millisecond an item hands even ten items out, in chunks as small as one item."""
    chunk, calls = recorder()
    out = np.full(10, -1.0)
    monkeypatch.setitem(_compiled._seconds_per_item, chunk, 1e-3)
    try:
        set_threads(2)
        run_batch(chunk, 10, out)
    finally:
        set_threads(None)
    bounds = sorted((start, stop) for start, stop, _ in calls)
    assert len(bounds) > 1 and bounds[0][0] == 0 and bounds[-1][1] == 10
    assert all(a[1] == b[0] for a, b in pairwise(bounds))
    np.testing.assert_array_equal(out, np.arange(10))


def test_a_small_batch_is_timed_only_where_it_ran_long(monkeypatch):
    """Under PARALLEL_BATCH items the call's own cost would make cheap items look dear: a batch is timed only where
    it took POOL_SECONDS in all (many items of moderate length too: 200 IK poses at 24 us each were never timed,
    so they never went to the pool), and a batch under TIMED_BATCH never is (nor handed out)."""

    def timed(tick: float, count: int):
        """The time per item recorded of a fresh kernel run on ``count`` items, where each clock reading advances
        ``tick`` seconds (whatever the machine's load), or None."""
        kernel, _ = recorder()
        clock = iter(np.arange(0.0, 1.0, tick))
        with monkeypatch.context() as patched:
            patched.setattr(_compiled.time, "perf_counter", lambda: next(clock))
            run_batch(kernel, count, np.empty(count))
        return _compiled._seconds_per_item.pop(kernel, None)

    pool = _compiled.POOL_SECONDS
    assert timed(1e-6, 20) is None  # 20 cheap items: 1 us in all
    assert timed(0.5 * pool, 20) is None  # half of POOL_SECONDS in all
    assert timed(2.0 * pool, 100) == pytest.approx(2.0 * pool / 100)  # 4 us an item, twice POOL_SECONDS in all
    assert timed(2.0 * pool, 20) == pytest.approx(2.0 * pool / 20)
    assert timed(2.0 * pool, _compiled.TIMED_BATCH - 1) is None


def test_a_failing_chunk_raises_after_every_chunk_is_done():
    done = []

    def chunk(start, stop):
        if start == 0:
            raise ZeroDivisionError("first chunk")
        done.append(start)

    try:
        set_threads(2)
        with pytest.raises(ZeroDivisionError, match="first chunk"):
            run_batch(chunk, 10_000)
    finally:
        set_threads(None)
    assert len(done) == 2 * _compiled.CHUNKS_PER_THREAD - 1


def test_thread_count_is_the_cores_capped_by_numba_num_threads(monkeypatch):
    cores = len(os.sched_getaffinity(0))
    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    assert default_threads() == thread_count() == cores
    monkeypatch.setenv("NUMBA_NUM_THREADS", "1")
    assert default_threads() == 1
    monkeypatch.setenv("NUMBA_NUM_THREADS", str(cores + 7))
    assert default_threads() == cores
    try:
        set_threads(cores + 3)
        assert thread_count() == cores + 3
    finally:
        set_threads(None)
    assert thread_count() == cores
    for wrong in (0, -1, 1.5, True, "2", "many"):
        with pytest.raises(ValueError, match="threads must be a positive integer"):
            set_threads(wrong)


def test_every_batch_kernel_computes_its_chunk_and_nothing_has_a_parallel_twin():
    """Read from the source: no prange, no parallel=True; every kernel handed to run_batch takes ``start, stop``
    first and loops ``range(start, stop)`` (so a chunk writes its rows alone), and so does a Python function of the
    caller's module handed to it (a loop that calls a kernel per item, which runs without the interpreter's lock:
    the nearly S-R-S self-motion's seeds); every run_batch call passes one kernel or such a function, then the
    count."""
    package = Path(_compiled.__file__).parent
    kernels, functions, launched = {}, {}, []
    for path in package.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        assert "prange" not in text or path.name == "_compiled.py", path
        assert "parallel=True" not in text, path
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.FunctionDef):
                found = (path.name, [a.arg for a in node.args.args[:2]], ast.unparse(node))
                if any(isinstance(d, ast.Name) and d.id == "kernel" for d in node.decorator_list):
                    kernels[node.name] = found
                else:
                    functions[path.name, node.name] = found
            elif isinstance(node, ast.Call) and getattr(node.func, "id", None) == "run_batch":
                first = node.args[0]
                launched.append((path.name, first.attr if isinstance(first, ast.Attribute) else first.id))
    assert len(launched) >= 25
    for module, name in launched:
        assert name in kernels or (module, name) in functions, (module, name)
        _, arguments, source = kernels[name] if name in kernels else functions[module, name]
        assert arguments == ["start", "stop"] and "in range(start, stop)" in source, (module, name)


def test_one_compiled_version_however_the_caller_made_its_arrays():
    """A broadcast (read-only) input and a writeable one, one item and a batch, a scalar and an array parameter:
    the public functions hand the kernels the same argument types, so each is compiled once, not once per pattern
    (a second compile of the SC step or the S-R-S IK costs seconds on a cold start)."""
    from redkin.models import barrett_wam, pa10_7c
    from redkin.srs import _ik_kernels, ik_all_branches, reachable
    from redkin.torso_arm import humanoid_arm, position_ik
    from redkin.velocity import _step_kernels, damped_least_squares, singularity_consistent

    rng = np.random.default_rng(0)
    arm, wam = pa10_7c(), barrett_wam()
    q = rng.uniform(-1, 1, (300, 7))
    poses, jac = arm.fk(q), wam.jacobian(q)
    right = humanoid_arm()
    wrists = right.chain.frames(rng.uniform(-0.5, 0.5, (300, 8)))[:, 6, :3, 3]

    def calls(k):  # pattern k of the same calls
        twist = np.full(6, 0.1) if k == 0 else np.full((300, 6), 0.1)
        ik_all_branches(arm, poses if k else poses[0], 0.3 if k < 2 else np.full(300, 0.3))
        reachable(arm, np.broadcast_to(poses[0], (300, 4, 4)) if k == 2 else poses)
        singularity_consistent(jac, twist, np.ones(300), np.ones((300, 7)), 0.1)
        damped_least_squares(jac[0] if k == 0 else jac, twist, 0.1)
        position_ik(right, wrists if k else wrists[0], 0.2 if k < 2 else np.full(300, 0.2), 0.1)

    kernels = [_ik_kernels.solve_pose, _ik_kernels.solve_poses, _ik_kernels.coefficients, _step_kernels.sc,
               _step_kernels.sc_one, _step_kernels.least_squares, _step_kernels.least_squares_one]
    before = [len(kernel.signatures) for kernel in kernels]  # other tests may have compiled some already
    for k in (0, 1, 2):
        calls(k)
    added = [len(kernel.signatures) - count for kernel, count in zip(kernels, before)]
    assert max(added) <= 1, added
