"""Files written whole or not at all: a process killed at any moment, or a power cut, leaves the target as it was
or with all of the new data, never torn (the workspace maps' store, a timed trajectory's file)."""

from __future__ import annotations

import contextlib
import errno
import os
import uuid
from pathlib import Path
from typing import Any

from redkin._constants import PARTIAL_SUFFIX


def write_durably(path: Path, data: Any) -> None:
    """Write ``data`` (bytes or a buffer) to ``path`` whole or not at all.

    A temporary ``.NAME.<random>.partial`` beside it is written, flushed
    (``fsync``), renamed over ``path`` (``os.replace``) and the folder's entry
    flushed.  A process killed at any moment leaves ``path`` absent, as it
    was, or with all of ``data``, plus at most the temporary file; on an error
    (a full disk) the temporary file is removed before the error is raised,
    an ``OSError`` that names ``path``.
    The folder is created if needed (zarr makes an array's folder with its
    first file).
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.{uuid.uuid4().hex}{PARTIAL_SUFFIX}")
    try:
        descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        try:
            view = memoryview(data).cast("B")
            while view:
                view = view[os.write(descriptor, view):]
            os.fsync(descriptor)  # the data are on the disk before the name points to them
        finally:
            os.close(descriptor)
        os.replace(temporary, path)
    except OSError as error:  # a write's error names no file: this one names the file being written
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        if error.filename is None:
            raise OSError(error.errno, error.strerror, str(path)) from error
        raise
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    fsync_folder(path.parent)  # the new name is on the disk before anything written after it (the marker)


def fsync_folder(folder: Path) -> None:
    """Flush a folder's entries to the disk (skipped on a file system that cannot, such as some network ones)."""
    descriptor = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    except OSError as exc:
        if exc.errno not in (errno.EINVAL, errno.ENOTSUP, errno.EBADF):
            raise
    finally:
        os.close(descriptor)
