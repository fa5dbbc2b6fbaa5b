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

import os
import threading
from typing import Callable

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
        return numba.njit(cache=True, parallel=parallel)(function)
    except RuntimeError:  # "cannot cache function ...: no locator available for file ..."
        return numba.njit(cache=False, parallel=parallel)(function)


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
