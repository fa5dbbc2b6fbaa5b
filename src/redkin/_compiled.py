"""How redkin compiles its kernels: numba ``njit`` with an on-disk cache, and safe parallel launches.

Every compiled kernel of redkin is made by :func:`kernel`, i.e.
``numba.njit(cache=True)``: the first call in a fresh install compiles it
(about a second per kernel) and writes the machine code to numba's cache;
later processes load it from there in milliseconds.  numba looks for a
writable cache directory in this order:

1. ``NUMBA_CACHE_DIR``, if set;
2. ``__pycache__`` beside the source file (an editable install: ``src/redkin/__pycache__``);
3. the user's cache directory (``~/.cache/numba`` on Linux), for a read-only install.

Where none is writable (a read-only install and a read-only home), numba
refuses to cache; :func:`kernel` then compiles without a cache, so redkin
still works and recompiles in every process.

numba checks a cached function against its own source file only, so a
kernel whose callee in another module changed would load stale machine code
(numba documents this).  :func:`kernel` therefore keeps one stamp per cache
directory, a digest of every redkin module that defines kernels, and empties
that directory's numba files when the digest differs (after an edit or an
upgrade): the compiled core is cached as a whole.

Batches run over their leading axis with ``prange`` on all cores
(:func:`run_batch`), through whichever threading layer numba picked
(``NUMBA_THREADING_LAYER``; ``NUMBA_NUM_THREADS`` caps the threads).  Two
launches never overlap (numba's ``workqueue`` layer aborts the process on
concurrent launches), and a process forked after its parent launched a
parallel kernel runs its batches serially (GNU OpenMP, numba's ``omp``
layer here, aborts a forked child that launches one).  Each batch item is
computed alone, so results do not depend on the thread count.
"""

from __future__ import annotations

import hashlib
import os
import threading
from collections.abc import Callable
from pathlib import Path

import numba

#: Batches of at least this many items run on all cores (below it, launching threads costs more than it saves).
PARALLEL_BATCH = 256

_LAUNCH = threading.Lock()
_launched_in: int | None = None  # the process that started numba's thread pool


def kernel(function: Callable | None = None, *, parallel: bool = False):
    """``numba.njit(cache=True)``, or without the cache where numba finds no writable cache directory.

    Use as ``@kernel`` or ``@kernel(parallel=True)``.
    """
    if function is None:
        return lambda f: kernel(f, parallel=parallel)
    try:
        compiled = numba.njit(cache=True, parallel=parallel)(function)
    except RuntimeError:  # "cannot cache function ...: no locator available for file ..."
        return numba.njit(cache=False, parallel=parallel)(function)
    _drop_stale_cache(compiled)
    return compiled


_STAMP_NAME = "redkin-kernels.stamp"
_checked: set[str] = set()  # cache directories whose stamp this process has checked


def _core_digest() -> str:
    """A digest of the source of every redkin module that defines kernels (read once per process)."""
    global _digest
    if _digest is None:
        package = Path(__file__).parent
        digest = hashlib.sha256()
        for path in sorted(package.rglob("*.py")):
            text = path.read_bytes()
            if b"@kernel" in text:
                digest.update(str(path.relative_to(package)).encode() + b"\0" + text)
        _digest = digest.hexdigest()
    return _digest


_digest: str | None = None


def _drop_stale_cache(compiled) -> None:
    """Empty the numba cache directory of a cached kernel if another version of the kernels filled it."""
    path = getattr(getattr(compiled, "_cache", None), "_cache_path", None)  # where numba caches this kernel
    if path is None or path in _checked:
        return
    _checked.add(path)
    directory = Path(path)
    stamp = directory / _STAMP_NAME
    digest = _core_digest()
    try:
        if stamp.is_file() and stamp.read_text() == digest:
            return
        for cached in list(directory.glob("*.nbi")) + list(directory.glob("*.nbc")):
            cached.unlink(missing_ok=True)
        stamp.write_text(digest)
    except OSError:  # pragma: no cover - a directory numba may write to but we cannot: leave it to numba
        return


def run_batch(serial: Callable, parallel: Callable, count: int, *args):
    """Call ``parallel(*args)`` for a batch of ``count`` items where it pays and is safe, else ``serial(*args)``;
    return what it returns.

    ``serial`` and ``parallel`` are the same loop over the batch, with
    ``range`` and with ``prange``.
    """
    global _launched_in
    if count < PARALLEL_BATCH or _launched_in not in (None, os.getpid()):
        return serial(*args)
    _launched_in = os.getpid()  # before the lock: a child forked from here on runs serially, never waits on it
    with _LAUNCH:
        return parallel(*args)
