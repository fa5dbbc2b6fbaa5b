"""Files written whole or not at all, and the Zarr store that writes every file of a map so (imports zarr).

:func:`write_durably` writes into a temporary file beside the target,
flushes it to the disk, renames it over the target (atomic on POSIX) and
flushes the folder's entry: a process killed at any moment, or a power cut,
leaves the target as it was or with all of the new data, never torn.
:class:`DurableStore` is zarr's ``LocalStore`` with every write done so; see
:mod:`redkin.workspace.store` for what that guarantees a map.

The store class lives at module level: Dask tokenizes a Zarr array by
pickling it and loading it back, and cloudpickle would rebuild a class
defined inside a function anew (its methods' globals a copy of this module's).
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import os
import uuid
from pathlib import Path
from typing import Any

from zarr.storage import LocalStore

from redkin._constants import PARTIAL_SUFFIX


def write_durably(path: Path, data: Any) -> None:
    """Write ``data`` (bytes or a buffer) to ``path`` whole or not at all.

    A temporary ``.NAME.<random>.partial`` beside it is written, flushed
    (``fsync``), renamed over ``path`` (``os.replace``) and the folder's entry
    flushed.  A process killed at any moment leaves ``path`` absent, as it
    was, or with all of ``data``, plus at most the temporary file; on an error
    (a full disk) the temporary file is removed before the error is raised.
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


class DurableStore(LocalStore):
    """A local Zarr store whose every write is whole or nothing, and on the disk once it returns."""

    async def set(self, key: str, value: Any) -> None:
        """Write ``value`` (a zarr ``Buffer``) as the file ``key`` through :func:`write_durably`."""
        if self.read_only:
            raise ValueError(f"the store {self.root} is read-only")
        await asyncio.to_thread(write_durably, self.root / key, value.as_buffer_like())
