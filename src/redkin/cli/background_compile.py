"""Compiling in the background: a command that ran as Python because its kernels were not in numba's cache yet
starts ``redkin compile --background --section ...`` in a process of its own, so that later runs are compiled.

A first run on a fresh install answers as Python where that is quicker than compiling (one pose of a closed form,
a short Franka path, an explorer page: :func:`redkin.cli.common.python_until_compiled`).  Without more, every later
run would do the same until the user ran ``redkin compile``.  Instead the run starts the sections of
:mod:`redkin.warm_up` that call its kernels in a new session (it outlives the command, at a low priority, its
output discarded), and says so on stderr.  The command does not wait for it.

Only one such compile runs per numba cache: ``redkin compile`` holds an advisory lock (``fcntl.flock``) on a file
of the cache (:func:`_lock_path`: in ``NUMBA_CACHE_DIR``, else in the temporary folder) while it compiles, and a
background compile is neither started nor run while another holds it.  ``REDKIN_BACKGROUND_COMPILE=0`` in the
environment turns this off (the test suite does, for the processes it starts too); where the platform has no
``flock`` or ``posix_spawn`` it is off.

Work that is usually quick as Python but may not be (a nearly S-R-S arm's sets: 10-15 s on most poses, half a
minute and more next to a singular configuration) runs as Python within a time limit while the compile runs
(:func:`within_seconds`); past it the command waits for the compile to end (:func:`wait_for_compile`) and runs
compiled, which costs little more than compiling in the foreground from the start.

Work that runs compiled from its first call because Python would take longer than compiling (a nearly S-R-S arm's
path: its sets of every waypoint) uses the same process to compile in two at once: the background compile takes the
sections of one part of its kernels while the command compiles the other part, then waits for it to end
(:func:`wait_for_process`; :func:`redkin.cli.common.compiled_beside`).
"""

from __future__ import annotations

import hashlib
import os
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: no background compile
    fcntl = None  # type: ignore[assignment]

#: The environment variable that turns background compiles off where it is ``0``.
_ENVIRONMENT = "REDKIN_BACKGROUND_COMPILE"
#: How much lower than the command's a background compile's scheduling priority is (``os.nice``).
NICENESS = 10


def background_compiles() -> bool:
    """Whether a command that ran as Python starts a background compile: not where ``REDKIN_BACKGROUND_COMPILE``
    is ``0``, nor where the platform lacks ``fcntl.flock`` or ``os.posix_spawn``."""
    return os.environ.get(_ENVIRONMENT, "1").strip() != "0" and fcntl is not None and hasattr(os, "posix_spawn")


def _lock_path() -> Path:
    """The lock file of the numba cache this process compiles into: ``redkin-compile.lock`` in ``NUMBA_CACHE_DIR``
    where set (made if missing); else, numba caching beside the sources or in the user's cache, a file in the
    temporary folder named after redkin's own folder and the user."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        folder = Path(os.environ["NUMBA_CACHE_DIR"])
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:  # the lock file cannot be opened then: no lock (compile_lock, _compile_running)
            pass
        return folder / "redkin-compile.lock"
    source = str(Path(__file__).resolve().parents[1])
    name = hashlib.sha256(f"{os.getuid() if hasattr(os, 'getuid') else 0}:{source}".encode()).hexdigest()[:16]
    return Path(tempfile.gettempdir()) / f"redkin-compile-{name}.lock"


@contextmanager
def _tried_lock() -> Iterator[bool | None]:
    """Try the cache's compile lock once, without waiting: yields ``True`` (held by this process for the block),
    ``False`` (another process holds it) or ``None`` (the lock file cannot be opened, or there is no ``flock``)."""
    if fcntl is None:  # pragma: no cover - not POSIX
        yield None
        return
    try:
        handle = open(_lock_path(), "a")
    except OSError:
        yield None
        return
    with handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            yield False
            return
        try:
            yield True
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


@contextmanager
def compile_lock() -> Iterator[bool]:
    """Hold the cache's compile lock for the block if no other process holds it; yields whether this one does
    (``False`` also where the lock file cannot be made or locked: the compile goes on without it)."""
    with _tried_lock() as held:
        yield held is True


def _compile_running() -> bool:
    """Whether another process holds the cache's compile lock (a ``redkin compile`` of this cache is running);
    ``False`` where the lock file cannot be opened (nor can a compile hold it then)."""
    with _tried_lock() as held:
        return held is False


def start(sections: Sequence[str]) -> int | None:
    """Start ``redkin compile --background`` of ``sections`` (names of :data:`redkin.warm_up.SECTION_NAMES`) in a new
    session, its input and output ``/dev/null``; return its process id, or ``None`` where background compiles are
    off (:func:`background_compiles`) or one is running already (:func:`_compile_running`).

    Raises
    ------
    OSError
        Where the process cannot be started (the caller says so and goes on).
    """
    if not background_compiles() or _compile_running():
        return None
    argv = [sys.executable, "-m", "redkin.cli.main", "compile", "--background"]
    for section in sections:
        argv += ["--section", section]
    null = os.devnull
    actions = [(os.POSIX_SPAWN_OPEN, 0, null, os.O_RDONLY, 0), (os.POSIX_SPAWN_OPEN, 1, null, os.O_WRONLY, 0),
               (os.POSIX_SPAWN_OPEN, 2, null, os.O_WRONLY, 0)]
    return os.posix_spawn(sys.executable, argv, dict(os.environ), file_actions=actions, setsid=True)


class OverTime(BaseException):
    """Raised in the main thread when the time of :func:`within_seconds` is up; a ``BaseException``, as
    ``KeyboardInterrupt`` is, so that no ``except Exception`` on the way turns it into an answer or an error."""


def time_limit_available() -> bool:
    """Whether :func:`within_seconds` can stop work in this thread (the main thread, with ``SIGALRM``)."""
    return hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()


@contextmanager
def within_seconds(seconds: float) -> Iterator[None]:
    """Raise :class:`OverTime` in the block once ``seconds`` have passed (a real-time timer's ``SIGALRM``; the
    previous handler and timer are put back after).  Work run as Python stops at its next bytecode.

    Raises
    ------
    RuntimeError
        Outside the main thread or where the platform has no ``setitimer`` (:func:`time_limit_available`).
    """
    if not time_limit_available():
        raise RuntimeError("a time limit needs the main thread and setitimer")

    def over(signum: int, frame: object) -> None:
        raise OverTime

    previous = signal.signal(signal.SIGALRM, over)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def wait_for_compile(poll: float = 0.5) -> None:
    """Return once no ``redkin compile`` of this cache holds its lock (:func:`_compile_running`)."""
    while _compile_running():
        time.sleep(poll)


def wait_for_process(pid: int) -> None:
    """Return once the process ``pid`` this one started (:func:`start`) has ended, and reap it."""
    try:
        os.waitpid(pid, 0)
    except ChildProcessError:  # reaped already, or not this process's child
        pass
