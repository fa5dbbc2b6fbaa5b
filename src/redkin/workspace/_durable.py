"""The Zarr store that writes every file of a map whole or not at all (imports zarr).

:func:`redkin._files.write_durably` writes into a temporary file beside the
target, flushes it to the disk, renames it over the target (atomic on POSIX)
and flushes the folder's entry: a process killed at any moment, or a power
cut, leaves the target as it was or with all of the new data, never torn.
:class:`DurableStore` is zarr's ``LocalStore`` with every write done so; see
:mod:`redkin.workspace.store` for what that guarantees a map.

The store class lives at module level: Dask tokenizes a Zarr array by
pickling it and loading it back, and cloudpickle would rebuild a class
defined inside a function anew (its methods' globals a copy of this module's).
"""

from __future__ import annotations

import asyncio
from typing import Any

from zarr.storage import LocalStore

from redkin._files import write_durably
from redkin.errors import RedkinError


class DurableStore(LocalStore):
    """A local Zarr store whose every write is whole or nothing, and on the disk once it returns."""

    async def set(self, key: str, value: Any) -> None:
        """Write ``value`` (a zarr ``Buffer``) as the file ``key`` through :func:`write_durably`."""
        if self.read_only:
            raise RedkinError(f"the store {self.root} is read-only")
        await asyncio.to_thread(write_durably, self.root / key, value.as_buffer_like())
