"""How redkin compiles its kernels and runs their batches: numba ``njit`` with an on-disk cache, one thread pool.

Every compiled kernel of redkin is made by :func:`kernel`, i.e.
``numba.njit(cache=True, nogil=True, no_cfunc_wrapper=True)``: serial machine code that runs
without Python's global interpreter lock.  The first call in a fresh install
compiles it and writes the machine code to numba's cache; later processes
load it from there in milliseconds.  numba looks for a writable cache
directory in this order:

1. ``NUMBA_CACHE_DIR``, if set (and writable), in one subfolder per source
   folder (``$NUMBA_CACHE_DIR/srs_<digest of the folder's path>``);
2. ``__pycache__`` beside the source file (an editable install: ``src/redkin/__pycache__``);
3. the user's cache directory (``~/.cache/numba`` on Linux), for a read-only
   install, in one subfolder per source folder as under 1.

Where none is writable (a read-only install and a read-only home), numba
refuses to cache; :func:`kernel` then compiles without a cache, so redkin
still works and recompiles in every process.  What redkin says about the
cache (:func:`cache_directory`) is read from where numba put each kernel,
never from the environment: a ``NUMBA_CACHE_DIR`` numba cannot write to is
passed over by numba, and by redkin's word too.

numba checks a cached function against its own source file only, so a
kernel whose callee in another module changed would load stale machine code
(numba documents this).  :func:`kernel` therefore keeps one stamp per cache
directory, a digest of every redkin module that defines kernels, and empties
that directory's numba files when the digest differs (after an edit or an
upgrade): the compiled core is cached as a whole.

Compiling is the one slow thing a new install does (a few minutes for
every kernel on a 2-core machine, tens of seconds for the first run of one
command, which compiles only the kernels it calls), so it is said as it
happens, on stderr.  The first time a process compiles a redkin kernel, one
line says so (:data:`COMPILE_NOTICE`, naming the cache directory); then a
progress line (:data:`COMPILE_PROGRESS`) counts the redkin kernels compiled
so far (a kernel's callees are kernels too, compiled inside it) and the
seconds since the first began, and names the kernel compiling now.  Each
kernel the program calls is announced with its wait (:data:`COMPILE_PLAN`:
the kernels it reaches that are not compiled yet, at
:data:`SECONDS_PER_KERNEL`), after the notice or on a line of its own, and
the progress line says about how long is left of it:

* each time the outermost compile (a kernel the program called, with every
  callee it compiles) ends, its line is said with the count so far, so the
  last line of a process gives the count of every kernel it compiled;
* while one compiles, the line is said again every
  :data:`PROGRESS_SECONDS` by a helper thread started at the first compile
  (a large kernel takes 20 s with its callees, and several seconds in LLVM's
  passes after its last callee), so no wait is longer than about 3 s
  without a word;
* on a terminal the line is redrawn in place (a carriage return, and
  cleared to its end) as each kernel starts and ends, and ended by a new
  line when the outermost compile ends; anywhere else (a log, a pipe) each
  line is a whole line, without control characters.

A process that finds every kernel in the cache says nothing and starts no
thread: numba reports compiles through its event API
(``numba.core.event``, ``"numba:compile"``), and loading from the cache is
not a compile.  Every kernel compile also calls the listeners registered
with :func:`on_compile` (``redkin compile`` counts on them).
:func:`set_compile_notice` or ``REDKIN_COMPILE_NOTICE=0`` in the
environment turns the notice and the progress off (the tests do, for the
processes they start too); ``redkin compile``
(:func:`redkin.warm_up.warm_up`) compiles everything ahead, for a Docker
image or a cluster's workers.

Lazy kernels
------------
numba itself is loaded only when a kernel first runs compiled: importing
it (and the scipy BLAS it loads with the first compiled function) takes
about 0.4 s, most of a warm ``redkin fk``.  Until then :func:`kernel`
returns a :class:`Kernel`, which holds the Python function.  Its first call
loads numba for all of them at once: every kernel made so far gets its
numba dispatcher, and the dispatcher replaces the :class:`Kernel` in the
globals of every loaded redkin module, so that numba finds compiled callees
when it compiles a caller, and so that calls from then on go straight to
numba (a :class:`Kernel` kept elsewhere, in a test's namespace, passes its
calls on).  Kernels made after that are dispatchers from the start.

Within :func:`interpreted`, kernels not compiled yet run as their Python
functions, callees included, and numba is not loaded: one implementation
of each equation, run by the interpreter.  Each runs as its twin
(:func:`_python_twin`), whose globals hold its callees' twins, so that a
call between kernels does not pass through the :class:`Kernel` wrapper.  The command line does so for
small work, where loading numba (and compiling, on a fresh install) costs
more than the arithmetic: ``redkin robots``, ``fk`` and ``jacobian``,
``ik`` and ``arm-angles`` on one pose of an exact closed form, ``path`` on
a short path of an S-R-S arm, and ``path`` on a short path of the Franka
class and ``explore`` at a pose while their kernels are not in numba's
cache (:func:`kernels_cached`).  A command that finds
its work large after all (a batch, a nearly S-R-S arm's self-motion, the
numerical solver, a cell) calls :func:`use_compiled`, and every kernel
runs compiled from there.  A batch within :func:`interpreted` runs in the
calling thread (the pool's threads are not inside the caller's context).
Both ways give the same numbers, bit for bit: the kernels do plain float
arithmetic and ``math`` functions, which numba compiles to the same
operations in the same order (``tests/test_interpreted.py`` holds them
equal on five arms of three classes, degenerate configurations included).
numpy's own functions on a scalar are not libm's everywhere: on a machine
with AVX-512, ``np.arctan2`` and ``np.exp`` differ from libm in the last bit
on a few per cent of arguments, so kernels call ``math``'s.

One compile per argument type
-----------------------------
numba compiles a kernel once for each tuple of argument types it is called
with, callees included.  Two kinds of type come apart without need:

* a constant written in a kernel's call to another kernel is a *literal*
  type (``f(x, 0)`` compiles ``f`` for ``Literal[int](0)``, ``f(x, 4)`` once
  more, and a counter started at ``0`` and passed on compiles it for the
  literal first and again for ``int64``): kernels pass ``np.int64(0)``,
  ``np.bool_(True)`` and start counters at ``np.int64(0)`` instead;
* a read-only array is another type than a writeable one: arrays reach a
  kernel through :func:`kernel_array`.

``tests/test_cli_compile.py`` checks both over every kernel.  The float and
complex versions of the Franka class's kernels are two argument types on
purpose (one implementation of each equation, evaluated on both).

Batches
-------
A batch kernel takes the half-open range of items it computes as its first
two arguments, ``kernel(start, stop, *arrays)``, and loops
``for n in range(start, stop)`` over the whole arrays it is given, writing
rows ``start .. stop - 1`` of its outputs and nothing else (with its own
scratch arrays, allocated per call).  One compiled kernel thus serves one
item, a whole batch (``start, stop = 0, N``) and any chunk of it; the
arrays are passed unchanged to every chunk (no per-chunk slicing of a dozen
arguments in Python, and an output row has its input row's index).

:func:`run_batch` runs ``[0, count)`` in one call in the calling thread
below :data:`PARALLEL_BATCH` items (unless the kernel's measured items are
long enough to fill :data:`POOL_SECONDS` in chunks of fewer than
:data:`MIN_CHUNK`), with one thread, or where the kernel's last measured
time per item says the batch takes less than :data:`POOL_SECONDS` (waking
a helper and being woken by it cost tens of microseconds).  A batch run in
one call is timed where it has :data:`PARALLEL_BATCH` items or took
:data:`POOL_SECONDS` in all, so that the call's own cost (microseconds) is
small beside what it measures.  Otherwise it splits the batch into up to
:data:`CHUNKS_PER_THREAD` chunks per thread of at least :data:`MIN_CHUNK`
items, which the calling thread and ``threads - 1`` helpers take one after
another until none is left.  The helpers are the threads of one pool shared
by the whole process (``concurrent.futures.ThreadPoolExecutor``, created on
first use).  The calling thread works rather than waits: a batch starts at
once, needs one wake-up per helper, and where the helpers' cores are busy
with other work the calling thread simply takes more chunks (and waits only
for chunks still running elsewhere).  ``threads`` is the number of cores
this process may run on (``os.sched_getaffinity``), capped by
``NUMBA_NUM_THREADS`` when set; :func:`set_threads` changes it from Python
(``set_threads(1)`` runs every batch in the calling thread).

Why the pool is safe, and why results do not depend on it:

* no shared writes -- the chunks of a batch write disjoint rows of the
  outputs, read inputs nobody writes, and keep their scratch to themselves;
  each item is computed alone, by the same machine code, whatever the chunk
  or thread, so a batch equals its items one by one, bit for bit, on any
  number of threads and any chunking (and whatever the timings decide);
* no GIL, no Python objects -- a kernel is compiled ``nogil=True`` and
  touches only the arrays it is given, so chunks run at once on all cores
  and the interpreter is free meanwhile;
* no launch lock -- numba's own thread pools (``prange``, OpenMP, TBB) are
  not used: two Python threads (a web server, a Dask worker with several
  threads) run batches at the same time, each in its own thread with the
  helpers it gets from the one pool; a kernel never calls back into Python,
  so a helper never waits on the pool;
* fork -- threads do not survive ``fork``; a child (``multiprocessing``'s
  ``fork`` context) sees that its process id is not the pool's and starts a
  pool of its own on its first batch.
"""

from __future__ import annotations

import hashlib
import importlib
import operator
import os
import sys
import threading
import time
import types
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from redkin.errors import RedkinError

#: Batches of fewer items run in the calling thread (handing out chunks costs more than the cores save), unless the
#: kernel's measured time per item says they are long enough for the pool (an item of a hundred microseconds).
PARALLEL_BATCH = 256
#: A batch is split into at most this many chunks per thread (each taken by whichever thread is free).
CHUNKS_PER_THREAD = 4
#: Items per chunk at least; fewer where the kernel's measured time per item fills :data:`POOL_SECONDS` with fewer.
MIN_CHUNK = 128
#: Batches whose kernel, at its last measured time per item, would take less than this (seconds) run in the
#: calling thread: waking a helper and being woken by it cost tens of microseconds (about 20-30 us each on a
#: 2-core virtual machine), so a batch of FK shorter than this is faster alone.
POOL_SECONDS = 2e-4
#: Batches of fewer items always run in the calling thread, untimed.
TIMED_BATCH = 8

_seconds_per_item: dict = {}  # kernel -> its last measured time per item (a run in one call, or the caller's chunks)


#: The line said on stderr the first time a process compiles a redkin kernel (``{cache}``: where it is cached).
COMPILE_NOTICE = ("redkin: compiling its kernels for this machine, once per install (cached in {cache}; "
                  "'redkin compile' compiles them all ahead)...")
#: The wait of a kernel the program called: how many kernels it calls that are neither in the cache nor compiled in
#: this process (:func:`_kernels_called`; a kernel compiled for two argument types counts once, so this is a
#: floor), and the seconds they take at :meth:`_CompileProgress.rate`.  Said after the notice, ``: `` between, when
#: the first compile begins, and as ``redkin: compiling ...`` when a later one begins that takes
#: :data:`PROGRESS_SECONDS` or more.
COMPILE_PLAN = "{kernel} and {callees} kernel{s} it calls, about {wait:.0f} s"
#: The progress line while kernels compile: ``{count}`` kernels compiled so far, ``{seconds}`` since the first began;
#: ``, compiling {kernel}`` is added while one compiles, and ``, about {wait} s left`` while the estimate of the
#: kernel the program called (:data:`COMPILE_PLAN`) is not used up.
COMPILE_PROGRESS = "redkin: {count} kernel{s} compiled in {seconds:.1f} s"
#: Seconds a kernel takes to compile, at least, for the waits said (this process's own mean where it is longer):
#: ``redkin compile`` compiled 234 in 105 s on a 2-core machine (benchmarks/README.md, issue 42).  A kernel's
#: callees compile first and fast, the kernel itself last and slowly, so a mean taken part way is too short.
SECONDS_PER_KERNEL = 0.45
#: While a kernel compiles, its progress line is said again (a new line in a log, redrawn on a terminal) once this
#: many seconds passed since the last line or since the outermost compile began (checked every :data:`_TICK` s).
PROGRESS_SECONDS = 2.0
_TICK = 0.25

_compile_listeners: list[Callable[[str], None]] = []


def on_compile(listener: Callable[[str], None]) -> Callable[[], None]:
    """Call ``listener(name)`` before each redkin kernel compiles (``name``: the kernel's module and function);
    return a function that removes it again."""
    _compile_listeners.append(listener)
    return lambda: _compile_listeners.remove(listener) if listener in _compile_listeners else None


def set_compile_notice(enabled: bool) -> None:
    """Say (``True``, the default) or do not say :data:`COMPILE_NOTICE` and the progress lines when this process
    compiles."""
    _progress.enabled = bool(enabled)


def cache_directory() -> str:
    """Where numba caches the kernels imported so far (see the module docstring): the folder a user names
    (``NUMBA_CACHE_DIR`` or the user's cache directory, whose subfolders numba makes per source folder; or one
    ``__pycache__``), or the folder that holds them all (each source folder's ``__pycache__`` in an editable
    install); ``"no cache"`` where none."""
    roots = {path if os.path.basename(path) == "__pycache__" else os.path.dirname(path) for path in _checked}
    if not roots:
        return "no cache"
    if len(roots) == 1:
        return next(iter(roots))
    return f"the __pycache__ folders under {os.path.commonpath(sorted(roots))}"


class _CompileProgress:
    """The notice and the progress lines of this process's redkin kernel compiles on stderr (module docstring).

    numba compiles one function at a time in the whole process (under its compiler lock), a callee inside its
    caller, so the compiles form one stack whatever thread runs them; the helper thread only reads it.
    """

    def __init__(self) -> None:
        self.enabled = os.environ.get("REDKIN_COMPILE_NOTICE", "1") != "0"
        self.compiled = 0  # redkin kernels compiled so far
        self.compiling: list[str] = []  # the redkin kernels compiling now, the outermost first
        self.began: float | None = None  # time.perf_counter() when the first compile began
        self.quiet_since = 0.0  # when the last line was said or the outermost compile began, the later
        self.seconds = 0.0  # seconds spent compiling, outermost compiles ended so far
        self.outer_began = 0.0  # when the outermost compile running now began
        self.expected = 0  # the count of kernels compiled when the outermost compile now running should end
        self.done: set[str] = set()  # the kernels compiled in this process
        self.after_fork()

    def after_fork(self) -> None:
        """A new lock and no helper thread (a forked child has neither): the next compile starts the thread."""
        self.lock = threading.Lock()
        self.busy = threading.Event()  # set while a redkin kernel compiles: the helper thread waits for it
        self.helper_process = 0  # the process id whose helper thread runs; 0: none

    def start(self, name: str, function: Callable | None = None) -> None:
        """The redkin kernel ``name`` (its Python function, if known) begins to compile."""
        with self.lock:
            self.compiling.append(name)
            now = time.perf_counter()
            if len(self.compiling) == 1:
                self.outer_began = now  # kept while the notice is off too: the compile seconds stay right
            if not self.enabled:
                return
            plan, wait = "", 0.0
            if len(self.compiling) == 1:
                callees = 0 if function is None else len(self._to_compile(function)) - 1
                self.expected = self.compiled + 1 + callees
                wait = (callees + 1) * self.rate()
                plan = COMPILE_PLAN.format(kernel=name.rsplit(".", 1)[-1], callees=callees,
                                           s="" if callees == 1 else "s", wait=wait)
            if self.began is None:
                self.began = now
                notice = COMPILE_NOTICE.format(cache=cache_directory())
                self._say(notice.removesuffix("...") + ": " + plan + "..." if plan else notice, whole=True)
            elif plan and wait >= PROGRESS_SECONDS:
                self._say("redkin: compiling " + plan, whole=True)
            if len(self.compiling) == 1:
                self.quiet_since = now
            if _terminal():
                self._say(self._line(now), whole=False)
            self.busy.set()
            if self.helper_process != os.getpid():
                self.helper_process = os.getpid()
                threading.Thread(target=self._tick, name="redkin-compile-progress", daemon=True).start()

    def end(self) -> None:
        """The innermost redkin kernel compiling has compiled (or failed to)."""
        with self.lock:
            self.done.add(self.compiling.pop())
            self.compiled += 1
            if not self.compiling:
                self.busy.clear()
                self.seconds += time.perf_counter() - self.outer_began
            if self.enabled and self.began is not None and (not self.compiling or _terminal()):
                self._say(self._line(time.perf_counter()), whole=not self.compiling)

    def _tick(self) -> None:
        """The helper thread: while a kernel compiles, say the line again every :data:`PROGRESS_SECONDS`."""
        while True:
            self.busy.wait()
            time.sleep(_TICK)
            with self.lock:
                now = time.perf_counter()
                if self.compiling and self.enabled and self.began is not None and \
                        now - self.quiet_since >= PROGRESS_SECONDS:
                    self._say(self._line(now), whole=False)

    def _line(self, now: float) -> str:
        """The progress line at ``now``, naming the kernel compiling now if one is, and the wait left."""
        line = COMPILE_PROGRESS.format(count=self.compiled, s="" if self.compiled == 1 else "s",
                                       seconds=now - (self.began or now))
        if not self.compiling:
            return line
        line += f", compiling {self.compiling[-1].rsplit('.', 1)[-1]}"
        left = (self.expected - self.compiled) * self.rate(now)
        return line + f", about {left:.0f} s left" if left >= 1.0 else line

    def rate(self, now: float | None = None) -> float:
        """Seconds per kernel for the waits said: this process's mean so far (the outermost compile running at
        ``now`` included), or :data:`SECONDS_PER_KERNEL` where that is longer."""
        running = 0.0 if now is None or not self.compiling else now - self.outer_began
        mean = (self.seconds + running) / self.compiled if self.compiled else 0.0
        return max(SECONDS_PER_KERNEL, mean)

    def _to_compile(self, function: Callable) -> list[Callable]:
        """``function`` and the redkin kernels it calls, transitively (:func:`_kernels_called`), less those compiled
        in this process or in numba's cache: what compiling it will compile."""
        return [function] + [callee for callee in _kernels_called(function)[1:]
                             if f"{callee.__module__}.{callee.__name__}" not in self.done
                             and not _in_cache(callee)]

    def _say(self, text: str, whole: bool) -> None:
        """Write ``text`` on stderr: on a terminal over the current line (ending it if ``whole``), else as a line."""
        if _terminal():
            text = "\r" + text + "\x1b[K" + ("\n" if whole else "")
        else:
            text += "\n"
        try:
            sys.stderr.write(text)
            sys.stderr.flush()
        except (AttributeError, OSError, ValueError):  # pragma: no cover - no stderr, or closed: compiling goes on
            pass
        self.quiet_since = time.perf_counter()


def _terminal() -> bool:
    """Whether stderr is a terminal (read at each line: a program or a test may replace ``sys.stderr``)."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # None, or closed
        return False


_progress = _CompileProgress()


def _redkin_kernel(event) -> str | None:
    """The module and name of the redkin function a ``"numba:compile"`` event is about, or ``None`` (numba's own
    functions compile too)."""
    dispatcher = event.data.get("dispatcher") if isinstance(event.data, dict) else None
    function = getattr(dispatcher, "py_func", None)
    module = getattr(function, "__module__", "") or ""
    if function is None or not module.startswith("redkin."):
        return None
    return f"{module}.{function.__name__}"


class Kernel:
    """A redkin kernel before numba is loaded: its Python function, compiled on the first call (module docstring,
    "Lazy kernels").

    Calling it loads numba (:func:`_load_numba`), which turns every kernel into its numba dispatcher and puts the
    dispatcher in place of this object in every redkin module; a call through an object kept elsewhere goes to the
    dispatcher too.  Within :func:`interpreted` (and before numba is loaded) a call runs the Python function itself
    (its twin, :func:`_python_twin`).  Attributes other than ``py_func`` and ``twin`` are the dispatcher's.
    """

    def __init__(self, function: Callable) -> None:
        self.py_func = function
        self.dispatcher: Callable | None = None  # numba's, once it is loaded
        self.twin: Callable | None = None  # its Python function calling its callees' directly (_python_twin)
        self.__name__ = function.__name__
        self.__qualname__ = function.__qualname__
        self.__module__ = function.__module__
        self.__doc__ = function.__doc__
        self.__wrapped__ = function

    def __call__(self, *args):
        dispatcher = self.dispatcher
        if dispatcher is None:
            if _interpreting.depth:
                return (self.twin or _python_twin(self))(*args)
            _load_numba()
            dispatcher = self.dispatcher
            assert dispatcher is not None
        return dispatcher(*args)

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        if self.dispatcher is None:
            _load_numba()
        return getattr(self.dispatcher, name)

    def __repr__(self) -> str:
        return f"<redkin kernel {self.__module__}.{self.__qualname__}, not compiled yet>"


_waiting: list[Kernel] = []  # the kernels made before numba was loaded
_numba_lock = threading.RLock()
_numba_loaded = False


class _Interpreting(threading.local):
    depth = 0


_interpreting = _Interpreting()

_twin_modules: dict[str, types.ModuleType] = {}  # module name -> its twin (_twin_module)


def _python_twin(waiting: Kernel) -> Callable:
    """The Python function of ``waiting`` with the globals of its module's twin (:func:`_twin_module`), made once.

    A kernel run as Python calls other kernels through its module's globals, where each is a :class:`Kernel`
    until numba is loaded, whose ``__call__`` costs about 0.15 us on top of the call: a nearly S-R-S arm's sets
    make 1.8 million such calls.  The twin's globals hold the callees' twins instead, so a kernel run as Python
    calls its callees' Python functions directly: the same code on the same values (numba reads a kernel's
    globals when it compiles it, so a snapshot of them is what a compiled kernel sees too)."""
    with _numba_lock:
        if waiting.twin is None:
            function = waiting.py_func
            names = vars(_twin_module(sys.modules[function.__module__]))
            waiting.twin = types.FunctionType(function.__code__, names, function.__name__, function.__defaults__,
                                              function.__closure__)
        return waiting.twin


def _twin_module(module: types.ModuleType) -> types.ModuleType:
    """A module of the same name holding ``module``'s globals, in which every :class:`Kernel` is its twin
    (:func:`_python_twin`) and every redkin module that defines kernels is its twin too; made once per module and
    registered before it is filled (kernel modules import each other)."""
    twin = _twin_modules.get(module.__name__)
    if twin is not None:
        return twin
    twin = _twin_modules[module.__name__] = types.ModuleType(module.__name__)
    names = vars(twin)
    for key, value in list(vars(module).items()):
        if isinstance(value, Kernel):
            value = _python_twin(value)
        elif isinstance(value, types.ModuleType) and _defines_kernels(value):
            value = _twin_module(value)
        names[key] = value
    return twin


def _defines_kernels(module: types.ModuleType) -> bool:
    """Whether ``module`` is a redkin module that defines a :class:`Kernel`."""
    name = module.__name__
    return (name == "redkin" or name.startswith("redkin.")) and any(
        isinstance(value, Kernel) and value.__module__ == name for value in list(vars(module).values()))


@contextmanager
def interpreted() -> Iterator[None]:
    """Within this context, in this thread, kernels not compiled yet run as Python functions and numba is not
    loaded (module docstring, "Lazy kernels"); once numba is loaded the kernels run compiled whatever the context.
    For a command's one small computation, where loading numba would cost more than the arithmetic."""
    _interpreting.depth += 1
    try:
        yield
    finally:
        _interpreting.depth -= 1


def numba_loaded() -> bool:
    """Whether this process has loaded numba for redkin's kernels (the first compiled call does)."""
    return _numba_loaded


def running_as_python() -> bool:
    """Whether kernels called now, in this thread, run as Python functions (within :func:`interpreted`, numba not
    loaded): then :func:`run_batch` runs every batch in the calling thread."""
    return bool(_interpreting.depth) and not _numba_loaded


def use_compiled() -> None:
    """From now on every kernel runs compiled, within :func:`interpreted` too: numba is loaded here (a computation
    too large to run as Python, inside a context that chose Python for a small one)."""
    _load_numba()


def kernels_cached(*kernels: Callable) -> bool:
    """Whether running ``kernels`` compiled costs a load from numba's cache, not a compile
    (:func:`kernels_on_disk`), told without importing numba; ``True`` once it is loaded (the kernels run compiled
    anyway)."""
    return _numba_loaded or kernels_on_disk(*kernels)


def kernels_on_disk(*kernels: Callable) -> bool:
    """Whether numba's on-disk cache holds each of ``kernels``, and every kernel they call
    (:func:`_kernels_called`), for the current sources, whether or not numba is loaded.

    The folder is the one numba would choose (module docstring, items 1-3: ``NUMBA_CACHE_DIR``'s subfolder for the
    source folder, else a writable ``__pycache__`` beside the source, else the user's cache directory's subfolder),
    the index file numba names after the kernel's module, name, first line and Python version, and the folder's
    stamp must be the current sources' digest (else the first compiled call empties it).  Anything else, or a
    folder numba would find in a way not mirrored here, reads as not cached: the caller then runs the work as
    Python, which costs time but never a wrong answer.
    """
    return all(_in_cache(function) for each in kernels for function in _kernels_called(getattr(each, "py_func", each)))


def _in_cache(function: Callable) -> bool:
    """Whether numba's cache folder for the Python function of a kernel holds its index file and the current
    sources' stamp (:func:`kernels_cached`)."""
    source = Path(function.__code__.co_filename).resolve()
    index = (f"{source.stem}.{function.__qualname__.replace('<', '').replace('>', '')}-"
             f"{function.__code__.co_firstlineno}.py{sys.version_info[0]}{sys.version_info[1]}"
             f"{getattr(sys, 'abiflags', '')}.nbi")
    folder = _numba_cache_folder(source)
    stamp = folder / _STAMP_NAME
    try:
        return (folder / index).is_file() and stamp.is_file() and stamp.read_text() == _core_digest()
    except OSError:
        return False


def _kernels_called(function: Callable) -> list[Callable]:
    """``function`` and the Python functions of every redkin kernel it calls, transitively, first seen first: the
    names its code reads from its module's globals (directly, or as an attribute of a module it imported) that are
    kernels (a :class:`Kernel` or a numba dispatcher of a redkin function)."""
    found: dict[int, Callable] = {}
    waiting = [function]
    while waiting:
        current = waiting.pop(0)
        if id(current) in found:
            continue
        found[id(current)] = current
        names: set[str] = set()
        codes = [current.__code__]
        while codes:
            code = codes.pop()
            names.update(code.co_names)
            codes += [constant for constant in code.co_consts if isinstance(constant, types.CodeType)]
        for name in sorted(names):
            value = current.__globals__.get(name)
            for candidate in ([getattr(value, other, None) for other in sorted(names)]
                              if isinstance(value, types.ModuleType) else [value]):
                callee = getattr(candidate, "py_func", None)
                if callable(callee) and (getattr(callee, "__module__", "") or "").startswith("redkin."):
                    waiting.append(callee)
    return list(found.values())


def _numba_cache_folder(source: Path) -> Path:
    """The folder where numba caches the kernels of the file ``source`` (:func:`kernels_cached`)."""
    subfolder = f"{source.parent.name}_{hashlib.sha1(str(source.parent).encode()).hexdigest()}"
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / subfolder
    in_tree = source.parent / "__pycache__"
    if os.access(in_tree if in_tree.is_dir() else source.parent, os.W_OK):
        return in_tree
    user = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return user / "numba" / subfolder


#: numba's options of every kernel beside the cache: no GIL, and no C-callable wrapper (``numba.cfunc``'s, which
#: nothing in redkin calls: a kernel calls another as a dispatcher, never as a first-class function).  Building
#: those wrappers took 0.80 s of 22.4 s compiling three warm_up sections ('srs ik', 'srs sets', 'collision
#: distances'), before LLVM optimised and emitted them.
_NJIT_OPTIONS: dict[str, Any] = {"nogil": True, "no_cfunc_wrapper": True}


def _njit(function: Callable):
    """``numba.njit(cache=True, **_NJIT_OPTIONS)`` of ``function``, or without the cache where numba finds no
    writable cache directory; a stale cache emptied (:func:`_drop_stale_cache`)."""
    import numba

    try:
        compiled = numba.njit(cache=True, **_NJIT_OPTIONS)(function)
    except RuntimeError:  # "cannot cache function ...: no locator available for file ..."
        return numba.njit(cache=False, **_NJIT_OPTIONS)(function)
    _drop_stale_cache(compiled)
    return compiled


def _load_numba() -> None:
    """Import numba, listen to its compiles, make every waiting kernel's dispatcher and put it in place of the
    :class:`Kernel` in every redkin module (numba reads a kernel's callees from its module's globals when it
    compiles it), once per process."""
    global _numba_loaded
    with _numba_lock:
        if _numba_loaded:
            return
        import numba.core.event

        class _CompileListener(numba.core.event.Listener):
            """numba's ``"numba:compile"`` events of redkin's kernels: the progress, and the listeners."""

            def on_start(self, event) -> None:
                name = _redkin_kernel(event)
                if name is None:
                    return
                _progress.start(name, getattr(event.data.get("dispatcher"), "py_func", None))
                for listener in list(_compile_listeners):
                    listener(name)

            def on_end(self, event) -> None:
                if _redkin_kernel(event) is not None:
                    _progress.end()

        numba.core.event.register("numba:compile", _CompileListener())
        made = {id(waiting): _njit(waiting.py_func) for waiting in _waiting}
        _bind_dispatchers(made)
        for waiting in _waiting:  # only now: a thread that finds its dispatcher set finds its callees bound
            waiting.dispatcher = made[id(waiting)]
        _waiting.clear()
        _numba_loaded = True


def _bind_dispatchers(made: dict[int, Callable]) -> None:
    """Put each kernel's dispatcher (``made``, by the id of its :class:`Kernel`) in place of its :class:`Kernel` in
    the globals of every loaded redkin module and of every module that defines a kernel."""
    namespaces = {id(vars(module)): vars(module) for name, module in list(sys.modules.items())
                  if module is not None and (name == "redkin" or name.startswith("redkin."))}
    namespaces.update({id(waiting.py_func.__globals__): waiting.py_func.__globals__ for waiting in _waiting})
    for names in namespaces.values():
        for key, value in list(names.items()):
            if isinstance(value, Kernel) and id(value) in made:
                names[key] = made[id(value)]


def kernel(function: Callable):
    """A redkin kernel: ``numba.njit(cache=True, nogil=True, no_cfunc_wrapper=True)`` of ``function`` (without the
    cache where numba finds no writable cache directory), made when numba is loaded; before then a :class:`Kernel`
    that loads it on its first call."""
    with _numba_lock:
        if _numba_loaded:
            return _njit(function)
        waiting = Kernel(function)
        _waiting.append(waiting)
        return waiting


def kernel_array(array: np.ndarray, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """``array`` (broadcast to ``shape`` if given and different) itself where it is C-contiguous and writeable, else
    a C-contiguous copy (writeable).

    numba compiles a kernel once per argument type, and a read-only array (a
    ``numpy.broadcast_to`` view, a frozen table) is another type than a
    writeable one: per-item inputs passed through here give one type however
    the caller made them (one more compile of a large kernel costs seconds).
    """
    if shape is not None and array.shape != shape:
        array = np.broadcast_to(array, shape)
    if array.flags.c_contiguous and array.flags.writeable:
        return array
    return np.array(array, order="C")


_STAMP_NAME = "redkin-kernels.stamp"
_checked: set[str] = set()  # cache directories whose stamp this process has checked


def _kernel_sources() -> list[Path]:
    """Every redkin source file that defines kernels (``@kernel``), sorted."""
    return [path for path in sorted(Path(__file__).parent.rglob("*.py")) if b"@kernel" in path.read_bytes()]


def prepare_cache() -> None:
    """Import every module that defines kernels and load numba, so that each cache folder's stamp is checked now
    (a stale folder emptied, :func:`_drop_stale_cache`): before several processes compile into one cache, which
    they must not empty under each other."""
    package = Path(__file__).parent
    for path in _kernel_sources():
        parts = path.relative_to(package.parent).with_suffix("").parts
        importlib.import_module(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    _load_numba()


def _core_digest() -> str:
    """A digest of the source of every redkin module that defines kernels (read once per process)."""
    global _digest
    if _digest is None:
        package = Path(__file__).parent
        digest = hashlib.sha256()
        for path in _kernel_sources():
            digest.update(str(path.relative_to(package)).encode() + b"\0" + path.read_bytes())
        _digest = digest.hexdigest()
    return _digest


_digest: str | None = None


def _cache_path(compiled) -> str | None:
    """The folder where numba caches the compiled function ``compiled`` (the stamp is there too), or ``None`` where
    it is not cached."""
    return getattr(getattr(compiled, "_cache", None), "cache_path", None)


def _drop_stale_cache(compiled) -> None:
    """Empty the numba cache directory of a cached kernel if another version of the kernels filled it."""
    path = _cache_path(compiled)
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


# ------------------------------------------------------------ the pool
_lock = threading.Lock()  # guards the three below
_setting: int | None = None  # set_threads' value; None: the default
_pool: ThreadPoolExecutor | None = None
_pool_key: tuple[int, int] = (0, 0)  # (process id, threads) the pool was made for


def default_threads() -> int:
    """The cores this process may run on (``os.sched_getaffinity``, else ``os.cpu_count``), capped by
    ``NUMBA_NUM_THREADS`` where that is set to a positive integer."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        cores = os.cpu_count() or 1
    cap = os.environ.get("NUMBA_NUM_THREADS", "")
    if cap.strip().isdigit() and int(cap) > 0:
        cores = min(cores, int(cap))
    return max(1, cores)


def thread_count() -> int:
    """The threads :func:`run_batch` splits a batch over: :func:`set_threads`' value, else :func:`default_threads`."""
    return _setting if _setting is not None else default_threads()


def set_threads(threads: int | None) -> None:
    """Run batches on ``threads`` threads from now on (``1``: in the calling thread); ``None`` restores the
    default (:func:`default_threads`).  Results do not depend on it.

    Raises
    ------
    ValueError
        For anything but ``None`` or a positive integer.
    """
    global _setting
    count = None
    if threads is not None:
        try:
            count = operator.index(threads)  # an int or a numpy integer, not a float or a string
        except TypeError:
            count = 0
        if isinstance(threads, bool) or count < 1:
            raise RedkinError(f"threads must be a positive integer or None, got {threads!r}")
    with _lock:
        _setting = count


def _executor(threads: int) -> ThreadPoolExecutor:
    """The shared pool of ``threads`` threads of this process, made on first use (and anew in a forked child or
    after :func:`set_threads`; a pool left behind ends its idle threads once the batches using it are done)."""
    global _pool, _pool_key
    key = (os.getpid(), threads)
    pool = _pool
    if pool is not None and _pool_key == key:
        return pool
    with _lock:
        if _pool is None or _pool_key != key:
            _pool, _pool_key = ThreadPoolExecutor(threads, thread_name_prefix="redkin-batch"), key
        return _pool


def _after_fork_in_child() -> None:
    """A forked child has the parent's pool object but none of its threads, and maybe a lock held by a thread
    that does not exist here: start both afresh."""
    global _lock, _pool
    _lock, _pool = threading.Lock(), None
    _progress.after_fork()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def run_batch(kernel: Callable, count: int, *args):
    """Run the batch kernel ``kernel(start, stop, *args)`` over ``[0, count)``, in chunks on the calling thread and
    the shared pool where the batch is large enough, and return the sum of what the chunks return (the kernels that
    return something return a count of failed items), or ``None``.

    When this returns or raises, no chunk is running (a chunk's exception is raised once the others are done).
    """
    per_item = _seconds_per_item.get(kernel)
    if count < TIMED_BATCH or running_as_python():  # a few items, or Python: one thread
        return kernel(0, count, *args)
    smallest = MIN_CHUNK if per_item is None else max(1, min(MIN_CHUNK, int(POOL_SECONDS / max(per_item, 1e-12))))
    known = per_item is not None and smallest < MIN_CHUNK  # a small batch of long items goes to the pool too
    if ((count >= PARALLEL_BATCH or known) and (POOL_SECONDS if per_item is None else per_item) * count >= POOL_SECONDS
            and (threads := thread_count()) > 1):  # the cores asked only of a batch that may go to the pool
        chunks = min(CHUNKS_PER_THREAD * threads, count // smallest)
        if chunks > 1:
            return _run_chunks(kernel, count, chunks, threads, args)
    start = time.perf_counter()
    result = kernel(0, count, *args)
    measured = (time.perf_counter() - start) / count
    if count >= PARALLEL_BATCH or measured * count >= POOL_SECONDS:  # else the call's own cost would weigh
        _seconds_per_item[kernel] = measured
    return result


def _run_chunks(kernel: Callable, count: int, chunks: int, threads: int, args: tuple):
    """:func:`run_batch` in ``chunks`` chunks, taken one after another by the calling thread and ``threads - 1``
    helpers from the pool.  The calling thread waits only for chunks still running elsewhere: a helper that wakes
    after every chunk is taken finds nothing to do and is not waited for."""
    bounds = [count * k // chunks for k in range(chunks + 1)]
    results: list = [None] * chunks
    errors: list[BaseException] = []
    order = iter(range(chunks))  # shared by the runners: next() on it is atomic under the GIL
    finished = threading.Event()
    done = [0]
    lock = threading.Lock()

    def runner() -> int:
        """Take chunks until none is left; return how many items this thread computed."""
        items = 0
        for k in order:
            try:
                results[k] = kernel(bounds[k], bounds[k + 1], *args)
                items += bounds[k + 1] - bounds[k]
            except BaseException as error:  # raised by the calling thread once every chunk is done
                errors.append(error)
            with lock:
                done[0] += 1
                if done[0] == chunks:
                    finished.set()
        return items

    pool = _executor(threads - 1)
    try:
        for _ in range(min(threads, chunks) - 1):
            pool.submit(runner)
    except RuntimeError:  # the interpreter is shutting down and the pool takes no more work: this thread does it
        pass
    start = time.perf_counter()
    items = runner()
    if items:
        _seconds_per_item[kernel] = (time.perf_counter() - start) / items
    finished.wait()
    if not items:  # the helpers took every chunk (a busy caller): time the batch as the threads shared it
        _seconds_per_item[kernel] = (time.perf_counter() - start) * min(threads, chunks) / count
    if errors:
        raise errors[0]
    return None if results[0] is None else sum(results)
